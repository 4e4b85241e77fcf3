"""Benchmark: spl's analysis of UVL's Arithmetic and Type levels against flamapy's z3 plugin.

Both tools answer the same questions on the same typed UVL files (by default every model
of the UVL project's parser tests, tests/data/uvl-parser, that spl reads as typed):
satisfiable, core, dead and false-optional features, and, where flamapy can enumerate
them (no typed feature: its configurations are then the products), the number of
products. The script checks that the answers agree, settles every difference on a model
without typed features by brute force (tests/support/fm_typed_semantics.py, docs/fm.md's
semantics, no z3), and prints markdown tables of the times and the differences
(docs/performance.md, "Typed models against flamapy's z3 plugin"). It exits 1 when an
answer of spl's is not brute force's, or a difference cannot be settled; a difference
where flamapy alone is wrong is reported, not a failure.

flamapy is not a dependency of spl, so it lives in its own virtualenv; this file is run
by spl's interpreter and re-runs itself inside that venv as a worker for the flamapy side:

    python3.11 -m venv /tmp/flamavenv
    /tmp/flamavenv/bin/pip install flamapy flamapy-fm flamapy-z3      # flamapy 2.6
    .venv/bin/python bench/fm_typed.py [--flamapy-python /tmp/flamavenv/bin/python]
        [--repeat 3] [--count-limit 5000] [MODEL.uvl ...]

flamapy's operations on a typed model (flamapy-z3 2.6.0, ``FmToZ3`` on flamapy-fm's
``UVLReader``): ``Z3Satisfiable``, ``Z3Backbone`` (core and dead at once, what
``Z3CoreFeatures`` and ``Z3DeadFeatures`` call), ``Z3FalseOptionalFeatures``,
``Z3Configurations``/``Z3ConfigurationsNumber`` (every assignment of features *and*
typed values: endless for an unbounded Integer), ``Z3SatisfiableConfiguration``,
``Z3FeatureBounds``/``Z3AllFeatureBounds`` and ``Z3AttributeOptimization`` (spl has no
counterpart of the last three). "load" is reading the file into each tool's model
(flamapy: ``UVLReader`` and ``FmToZ3``; spl: ``read_uvl_plain`` and ``SmtFormula``),
"analysis" the four operations; each the best of ``--repeat`` runs.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CORPUS = ROOT / "tests" / "data" / "uvl-parser" / "test_models"
QUESTIONS = ("satisfiable", "core", "dead", "false_optional")


def flamapy_worker(path: str, repeat: int, count: bool) -> dict:
    """Runs inside the flamapy venv: the answers, the times, or where flamapy stopped."""
    import logging

    logging.disable(logging.CRITICAL)  # flamapy logs every unsupported attribute
    from flamapy.metamodels.fm_metamodel.transformations import UVLReader
    from flamapy.metamodels.z3_metamodel.operations import (
        Z3Backbone,
        Z3ConfigurationsNumber,
        Z3FalseOptionalFeatures,
        Z3Satisfiable,
    )
    from flamapy.metamodels.z3_metamodel.transformations import FmToZ3

    best_load = best_analysis = float("inf")
    result: dict = {}
    for _ in range(repeat):
        start = time.perf_counter()
        try:
            model = UVLReader(path).transform()
        except Exception as error:  # flamapy's reader raises anything
            return {"error": f"UVLReader: {type(error).__name__}: {error}"[:160]}
        try:
            z3_model = FmToZ3(model).transform()
            loaded = time.perf_counter()
            satisfiable = Z3Satisfiable().execute(z3_model).get_result()
            backbone = Z3Backbone().execute(z3_model).get_result()
            false_optional = Z3FalseOptionalFeatures().execute(z3_model).get_result()
        except Exception as error:  # and so does its z3 plugin
            return {"error": f"FmToZ3: {type(error).__name__}: {error}"[:160]}
        done = time.perf_counter()
        best_load, best_analysis = min(best_load, loaded - start), min(best_analysis, done - loaded)
        result = {
            "satisfiable": bool(satisfiable),
            "core": sorted(map(str, backbone["core"])),
            "dead": sorted(map(str, backbone["dead"])),
            "false_optional": sorted(map(str, false_optional)),
        }
        if count:
            result["products"] = Z3ConfigurationsNumber().execute(z3_model).get_result()
    return {**result, "load_seconds": best_load, "analysis_seconds": best_analysis}


def spl_run(path: Path, repeat: int) -> dict:
    from spl.dsl.interop.interchange import written_names
    from spl.dsl.interop.uvl import read_uvl_plain
    from spl.resolver.analysis.smt import SmtFormula

    best_load = best_analysis = float("inf")
    result: dict = {}
    for _ in range(repeat):
        start = time.perf_counter()
        model = read_uvl_plain(path)
        formula = SmtFormula(model)  # typed: the corpus filter
        loaded = time.perf_counter()
        answers = {
            "satisfiable": formula.satisfiable(),
            "core": formula.core_features(),
            "dead": formula.dead_features(),
            "false_optional": formula.false_optional_features(),
        }
        done = time.perf_counter()
        best_load, best_analysis = min(best_load, loaded - start), min(best_analysis, done - loaded)
        written = written_names(model)
        result = {
            key: value if key == "satisfiable" else sorted(written[n] for n in value)
            for key, value in answers.items()
        }
        result["typed_features"] = len(model.types)
        result["features"] = formula.cnf.num_features
    count = SmtFormula(model).count(None)
    return {**result, "products": count.value, "load_seconds": best_load,
            "analysis_seconds": best_analysis}  # fmt: skip


def as_spl_reads(flamapy: dict) -> dict:
    """flamapy's answers with its false-optional list read as spl defines it. flamapy's
    operation tests ``parent and not feature`` for every non-mandatory feature, so on a
    void model it lists them all and otherwise also the children of dead parents (that
    test is unsatisfiable because the parent never occurs): spl reports those as dead
    only (bench/fm_analysis.py compares the SAT plugin so too)."""
    listed = set(flamapy["false_optional"]) - set(flamapy["dead"]) if flamapy["satisfiable"] else ()
    return {**flamapy, "false_optional": sorted(listed)}


def differences(spl: dict, flamapy: dict) -> list[str]:
    """What the two answer differently (flamapy's answers :func:`as_spl_reads` them)."""
    found = []
    for key in (*QUESTIONS, "products"):
        if key not in flamapy or spl[key] == flamapy[key]:
            continue
        if isinstance(spl[key], list):
            only_spl = sorted(set(spl[key]) - set(flamapy[key]))
            only_flamapy = sorted(set(flamapy[key]) - set(spl[key]))
            found.append(f"{key}: only spl {only_spl}, only flamapy {only_flamapy}")
        else:
            found.append(f"{key}: spl {spl[key]}, flamapy {flamapy[key]}")
    return found


def brute_force(path: Path) -> dict | None:
    """The answers by enumeration (docs/fm.md's semantics, no z3) for a model without
    typed features, whose products are finite; None for one with typed features."""
    sys.path.insert(0, str(ROOT / "tests"))
    from spl.dsl.interop.interchange import written_names
    from spl.dsl.interop.uvl import read_uvl_plain
    from spl.resolver.analysis.smt import SmtFormula

    from support.fm_typed_semantics import expected_analysis

    model = read_uvl_plain(path)
    if model.types:
        return None
    expected = expected_analysis(model, SmtFormula(model))
    written = written_names(model)
    return {
        key: value if not isinstance(value, list) else sorted(written[n] for n in value)
        for key, value in expected.items()
    }


def typed_models() -> list[Path]:
    from spl.core.diagnostics import ModelError
    from spl.dsl.interop.uvl import read_uvl_plain
    from spl.dsl.interop.uvl_typed import TypedFeatureModel

    found = []
    for path in sorted(CORPUS.rglob("*.uvl")):
        try:
            if isinstance(read_uvl_plain(path), TypedFeatureModel):
                found.append(path)
        except ModelError:
            continue  # the faulty models
    return found


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("models", nargs="*")
    parser.add_argument("--flamapy-python", default="/tmp/flamavenv/bin/python")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument(
        "--count-limit",
        type=int,
        default=5000,
        help="let flamapy enumerate the products of a model without typed features when "
        "spl counts at most this many",
    )
    parser.add_argument("--flamapy-worker", help=argparse.SUPPRESS)
    parser.add_argument("--count", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.flamapy_worker:
        print(json.dumps(flamapy_worker(args.flamapy_worker, args.repeat, args.count)))
        return 0

    models = [Path(m) for m in args.models] or typed_models()
    rows, notes, problems = [], [], 0
    totals = {"spl": 0.0, "flamapy": 0.0}
    for path in models:
        name = str(path.relative_to(CORPUS)) if path.is_relative_to(CORPUS) else str(path)
        spl = spl_run(path, args.repeat)
        countable = not spl["typed_features"] and (spl["products"] or 0) <= args.count_limit
        command = [args.flamapy_python, __file__, "--flamapy-worker", str(path)]
        command += ["--repeat", str(args.repeat)] + (["--count"] if countable else [])
        done = subprocess.run(command, capture_output=True, text=True, check=False)
        flamapy = json.loads(done.stdout) if done.returncode == 0 else {"error": done.stderr[-160:]}
        spl_seconds = spl["load_seconds"] + spl["analysis_seconds"]
        answer = f"{'yes' if spl['satisfiable'] else 'no'} {len(spl['core'])}/{len(spl['dead'])}"
        answer += f"/{len(spl['false_optional'])}"
        if "error" in flamapy:
            verdict, flamapy_cell = "flamapy cannot read it", "-"
            notes.append(f"- `{name}`: flamapy stops: {flamapy['error'].strip()}")
        else:
            flamapy = as_spl_reads(flamapy)
            found = differences(spl, flamapy)
            flamapy_seconds = flamapy["load_seconds"] + flamapy["analysis_seconds"]
            totals["spl"] += spl_seconds
            totals["flamapy"] += flamapy_seconds
            flamapy_cell = f"{flamapy['load_seconds']:.4f} / {flamapy['analysis_seconds']:.4f}"
            verdict = "same" if not found else "DIFFERENT"
            if found:
                truth = brute_force(path)
                for difference in found:
                    key = difference.split(":")[0]
                    settled = ""
                    right: list[str] = []
                    if truth is not None:
                        right = [
                            tool
                            for tool, answers in (("spl", spl), ("flamapy", flamapy))
                            if _same(key, answers, truth)
                        ]
                        settled = f"; brute force agrees with {' and '.join(right) or 'neither'}"
                    # a failure is spl wrong, or a difference brute force cannot settle
                    problems += "spl" not in right
                    notes.append(f"- `{name}`: {difference}{settled}")
        products = spl["products"]
        rows.append(
            f"| {name} | {spl['features']} | {spl['typed_features']} | {answer} | "
            f"{products if products is not None else 'unknown'} | "
            f"{spl['load_seconds']:.4f} / {spl['analysis_seconds']:.4f} | {flamapy_cell} | "
            f"{verdict} |"
        )
    print(
        "| model | features | typed | satisfiable, core/dead/false-optional (spl) | products "
        "(spl) | spl load / analysis s | flamapy load / analysis s | answers |"
    )
    print("| --- | ---: | ---: | --- | ---: | ---: | ---: | --- |")
    for row in rows:
        print(row)
    print()
    print(
        f"Totals over the models both read: spl {totals['spl']:.3f} s, flamapy "
        f"{totals['flamapy']:.3f} s (load and analysis)."
    )
    print()
    for note in notes:
        print(note)
    return 1 if problems else 0


def _same(key: str, answers: dict, truth: dict) -> bool:
    """Whether a tool's answer to ``key`` is brute force's."""
    return answers.get(key) == truth["count" if key == "products" else key]


if __name__ == "__main__":
    sys.exit(main())
