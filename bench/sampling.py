"""Benchmark: t-wise samples of the vendored real models, size and time, checked.

    .venv/bin/python bench/sampling.py [--pairs 5000] [--runs 1] [MODEL.uvl:t ...]

Each case runs ``spl products MODEL --sample t=N --json`` as its own process (the time a
user waits: interpreter, imports, reading the model and sampling) and reports the number
of products, the sampler's own seconds (what spl prints), the wall time of the process,
its peak memory and the load average when it ended (the machine is shared: a figure
means little without it). The products are then checked by an oracle that shares
nothing with the sampler but the CNF: a fresh MiniSat (the sampler runs Glucose)
decides that every product satisfies the formula, and ``--pairs`` random combinations
of t literals (seeded; validity decided by the same fresh solver) must each be in some
product.

For t = 2 it also prints a *lower bound* on the size of any pairwise sample, so that a
size can be judged without another tool: if the literals of a set X exclude each other
pairwise (at most one is in a product), and so do those of Y, a product covers at most
one pair of X x Y, and every valid pair of X x Y needs a product of its own. X and Y are
grown greedily from the pairs the sample shows invalid, every exclusion inside them is
confirmed by the solver, and the bound is the largest number of valid pairs (again by
the solver) across two such sets.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import time
from itertools import combinations
from pathlib import Path

import numpy as np
from pysat.solvers import Solver

from spl.dsl.interop.formats import load_analysable_model
from spl.resolver.analysis.formula import FeatureModelFormula

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "tests" / "data" / "feature-models"
CASES = [
    ("berkeleydb.uvl", 2),
    ("axTLS.uvl", 2),
    ("busybox_2010-05-02_14-17-07.uvl", 2),
    ("automotive01.uvl", 2),
    ("berkeleydb.uvl", 3),
    ("axTLS.uvl", 3),
    ("busybox_2010-05-02_14-17-07.uvl", 3),
]
# runs the command in a child and reports the child's own peak memory on its last line
# (VmHWM: getrusage's ru_maxrss would keep the parent's peak across the exec)
CHILD = """
import sys
from spl.cli import main
try:
    main(sys.argv[1:], standalone_mode=False)
finally:
    with open("/proc/self/status") as status:
        peak = next(line.split()[1] for line in status if line.startswith("VmHWM:"))
    print(f"peak_kb {peak}", file=sys.stderr)
"""


def run_case(path: Path, t: int) -> dict:
    started = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", CHILD, "products", str(path), "--sample", f"t={t}", "--json"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    wall = time.perf_counter() - started
    summary, memory = done.stderr.strip().splitlines()[-2:]
    seconds = float(summary.rsplit(" in ", 1)[1].split()[0])
    products = [frozenset(json.loads(line)["features"]) for line in done.stdout.splitlines()]
    return {
        "model": path.name,
        "t": t,
        "products": products,
        "summary": summary,
        "sample_s": seconds,
        "wall_s": wall,
        "peak_mb": int(memory.split()[1]) // 1024,
        "load": os.getloadavg()[0],
    }


def check(formula: FeatureModelFormula, products: list, t: int, count: int) -> str:
    """The oracle: every product is a model of the CNF, and every valid drawn combination
    is in some product. Returns a line for the report; raises when a check fails."""
    cnf = formula.cnf
    rng = random.Random(20260101)
    valid = uncovered = 0
    with Solver(name="minisat22", bootstrap_with=list(cnf.clauses)) as oracle:
        for product in products:
            assignment = [cnf.var[f] if f in product else -cnf.var[f] for f in cnf.names]
            if not oracle.solve(assumptions=assignment):
                raise AssertionError(f"not a product: {sorted(product)}")
        for _ in range(count):
            drawn = [(name, rng.random() < 0.5) for name in rng.sample(cnf.names, t)]
            if not oracle.solve(assumptions=[cnf.var[n] if v else -cnf.var[n] for n, v in drawn]):
                continue
            valid += 1
            if not any(all((n in p) == v for n, v in drawn) for p in products):
                uncovered += 1
    if uncovered:
        raise AssertionError(f"{uncovered} of {valid} drawn valid combinations uncovered")
    return (
        f"{len(products)} products valid; {valid} of {count} drawn combinations valid, all covered"
    )


def lower_bound(formula: FeatureModelFormula, products: list) -> int:
    """A bound no pairwise sample of the model can go below (see the module docstring)."""
    cnf = formula.cnf
    core, dead = formula.backbone()
    free = [name for name in cnf.names if name not in core | dead]
    m = len(free)
    literals = [cnf.var[name] for name in free] + [-cnf.var[name] for name in free]
    seen = np.zeros((2 * m, 2 * m), dtype=bool)
    for product in products:
        inside = np.array([name in product for name in free])
        chosen = np.flatnonzero(np.concatenate([inside, ~inside]))
        seen[np.ix_(chosen, chosen)] = True
    conflict = ~seen
    same = np.arange(2 * m) % m
    conflict[same[:, None] == same[None, :]] = False
    cliques = set()
    for start in range(2 * m):
        clique, candidates = [int(start)], np.flatnonzero(conflict[start])
        while candidates.size:
            inner = conflict[np.ix_(candidates, candidates)].sum(axis=1)
            best = int(candidates[int(np.argmax(inner))])
            clique.append(best)
            candidates = candidates[conflict[best, candidates]]
        cliques.add(tuple(sorted(clique)))
    ranked = sorted(cliques, key=lambda c: (-len(c), c))[:60]
    best = 0
    with Solver(name="minisat22", bootstrap_with=list(cnf.clauses)) as oracle:

        def valid(a: int, b: int) -> bool:
            return bool(oracle.solve(assumptions=[literals[a], literals[b]]))

        confirmed = [c for c in ranked if not any(valid(a, b) for a, b in combinations(c, 2))]
        for x, y in combinations(confirmed, 2):
            if len(x) * len(y) <= best or {i % m for i in x} & {i % m for i in y}:
                continue
            best = max(best, sum(1 for a in x for b in y if valid(a, b)))
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=5000, help="random combinations to check")
    parser.add_argument("cases", nargs="*", help="MODEL.uvl:t (default: the vendored models)")
    args = parser.parse_args()
    cases = [(c.split(":")[0], int(c.split(":")[1])) for c in args.cases] or CASES
    print("| model | t | products | sample s | process s | peak MB | load | lower bound |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    notes = []
    for name, t in cases:
        path = MODELS / name if not Path(name).exists() else Path(name)
        result = run_case(path, t)
        formula = FeatureModelFormula(load_analysable_model(path))
        notes.append(f"{name} t={t}: {result['summary']}; oracle: ")
        notes[-1] += check(formula, result["products"], t, args.pairs)
        bound = lower_bound(formula, result["products"]) if t == 2 else ""
        print(
            f"| {name} | {t} | {len(result['products'])} | {result['sample_s']:.2f} | "
            f"{result['wall_s']:.1f} | {result['peak_mb']} | {result['load']:.1f} | {bound} |",
            flush=True,
        )
    print()
    print("\n".join(notes))


if __name__ == "__main__":
    main()
