"""Benchmark: spl's exact product count against Ganak (pyganak) on real feature models.

Both count the same CNF — spl's encoding of the model (``spl.resolver.analysis.cnf``), projected
on the feature variables (auxiliary variables of cardinality and Tseitin encodings are
existentially quantified: Ganak's sampling set is the features) — and must agree.
pyganak is not a dependency of spl; like flamapy in ``bench/fm_analysis.py`` it lives in
its own virtualenv and this file re-runs itself there as a worker:

    python3 -m venv /tmp/benchvenv && /tmp/benchvenv/bin/pip install pyganak
    .venv/bin/python bench/fm_count.py [--ganak-python /tmp/benchvenv/bin/python]
        [--runs 3] [--timeout 300] [MODEL ...]

Times: "spl" is ``FeatureModelFormula.count(None)`` after the backbone (as ``spl analyze
--count`` runs it; the backbone is not counted), "Ganak" the ``Counter.count()`` call
(preprocessing included, adding the clauses not); each the min and median of ``--runs``.
A Ganak run past ``--timeout`` seconds is stopped and reported as such.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from fm_analysis import DATA, DEFAULT_MODELS  # the same vendored models, run as a script


def ganak_worker(path: str) -> None:
    """Runs in the pyganak venv: count the CNF stored in ``path``."""
    from pyganak import Counter

    problem = json.loads(Path(path).read_text())
    counter = Counter()
    counter.new_vars(problem["num_vars"])
    counter.add_clauses(problem["clauses"])
    counter.set_sampling_set(range(1, problem["num_features"] + 1))
    start = time.perf_counter()
    value = counter.count()
    print(json.dumps({"value": str(value), "seconds": time.perf_counter() - start}))


def spl_count(path: Path) -> tuple[int | None, float, dict]:
    from spl.dsl.interop.formats import load_analysable_model
    from spl.resolver.analysis.formula import FeatureModelFormula

    with FeatureModelFormula(load_analysable_model(path)) as formula:
        formula.backbone()
        start = time.perf_counter()
        count = formula.count(None)
        seconds = time.perf_counter() - start
        cnf = formula.cnf
        problem = {
            "num_vars": cnf.num_vars,
            "num_features": cnf.num_features,
            "clauses": [list(c) for c in cnf.clauses],
        }
    return count.value, seconds, problem


def ganak_count(python: str, problem: dict, timeout: float) -> tuple[int | None, float]:
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as handle:
        json.dump(problem, handle)
    try:
        done = subprocess.run(
            [python, __file__, "--ganak-worker", handle.name],
            capture_output=True,
            text=True,
            check=True,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        return None, timeout
    finally:
        Path(handle.name).unlink()
    found = json.loads(done.stdout.strip().splitlines()[-1])
    return int(found["value"]), found["seconds"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("models", nargs="*")
    parser.add_argument("--ganak-python", default="/tmp/benchvenv/bin/python")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=300.0)
    parser.add_argument("--ganak-worker", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.ganak_worker:
        ganak_worker(args.ganak_worker)
        return 0

    models = [Path(m) for m in args.models] or [DATA / m for m in DEFAULT_MODELS]
    print(
        "| model | features | products | spl s (min / median) | Ganak s (min / median) | faster |"
    )
    print("| --- | ---: | ---: | ---: | ---: | --- |")
    status = 0
    for path in models:
        ours, theirs, value, other, features = [], [], None, None, 0
        for _ in range(args.runs):
            value, seconds, problem = spl_count(path)
            ours.append(seconds)
            features = problem["num_features"]
            other, seconds = ganak_count(args.ganak_python, problem, args.timeout)
            theirs.append(seconds)
        if other is not None and other != value:
            print(f"DIFFERENCE: {path.stem}: spl {value}, Ganak {other}")
            status = 1
        text = str(value)
        shown = text if len(text) <= 15 else f"{text[0]}.{text[1:4]}e{len(text) - 1}"
        ganak = (
            f"{min(theirs):.3f} / {statistics.median(theirs):.3f}"
            if other is not None
            else f"stopped after {args.timeout:g} s"
        )
        faster = (
            "spl"
            if other is None or statistics.median(ours) < statistics.median(theirs)
            else "Ganak"
        )
        print(
            f"| {path.stem} | {features} | {shown} | {min(ours):.3f} / "
            f"{statistics.median(ours):.3f} | {ganak} | {faster} |"
        )
    return status


if __name__ == "__main__":
    sys.exit(main())
