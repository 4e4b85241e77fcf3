"""Benchmark: spl's feature-model analysis against flamapy on real feature models.

Both tools answer the same four questions — satisfiable, core, dead and false-optional
features — on the same UVL files; the script checks that the answers agree and prints
markdown tables of the times.

flamapy is not a dependency of spl, so it lives in its own virtualenv; this file is run
by spl's interpreter and re-runs itself inside that venv as a worker for the flamapy side:

    python3 -m venv /tmp/benchvenv
    /tmp/benchvenv/bin/pip install flamapy flamapy-fm flamapy-sat    # flamapy 2.6
    .venv/bin/python bench/fm_analysis.py [--flamapy-python /tmp/benchvenv/bin/python]
        [--repeat 3] [--runs 5] [--json-out tests/models/analysis/flamapy_results.json]
        [--spl-only LARGE.uvl ...] [MODEL.uvl ...]

Two measurements:

* **whole process** (the figure the issue-17 target is judged by): one ``spl analyze
  --json --count-seconds 0 MODEL`` process against one flamapy process that reads the
  same file and runs the same four operations (flamapy-fm UVLReader, FmToPysat,
  PySATSatisfiable, PySATCoreFeatures, PySATDeadFeatures, PySATFalseOptionalFeatures)
  and prints them. Both include interpreter start and imports. ``--runs`` pairs are run
  alternately; the ratio flamapy/spl of each pair is reported as min and median.
  ``--spl-only`` models (the Linux kernel model of the UVL corpus, say: it is not
  vendored; get ``Feature_Models/Operating_Systems/Linux/linux-2.6.33.3.uvl`` from the
  Universal-Variability-Language/uvl-models repository) are timed for spl alone.
* **in process**: "load" is reading the UVL file into each tool's model; "analysis" the
  four operations (spl: one FeatureModelFormula on the model ``spl analyze`` reads).
  Each number is the best of ``--repeat`` runs, each on a freshly loaded model. The last
  column is spl's exact product count and its time (flamapy's BDD count, where it
  finishes, must agree).

``--json-out`` stores flamapy's answers (the test fixtures of tests/resolver/test_analysis_real.py).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "feature-models"
DEFAULT_MODELS = [
    "berkeleydb.uvl",
    "axTLS.uvl",
    "busybox_2010-05-02_14-17-07.uvl",
    "automotive01.uvl",
]


def flamapy_worker(path: str, repeat: int, bdd_max_features: int) -> dict:
    """Runs inside the flamapy venv."""
    from flamapy.metamodels.fm_metamodel.transformations import UVLReader
    from flamapy.metamodels.pysat_metamodel.operations import (
        PySATCoreFeatures,
        PySATDeadFeatures,
        PySATFalseOptionalFeatures,
        PySATSatisfiable,
    )
    from flamapy.metamodels.pysat_metamodel.transformations import FmToPysat

    best_load = best_analysis = float("inf")
    result: dict = {}
    for _ in range(repeat):
        start = time.perf_counter()
        fm = UVLReader(path).transform()
        loaded = time.perf_counter()
        sat_model = FmToPysat(fm).transform()
        satisfiable = PySATSatisfiable().execute(sat_model).get_result()
        core = PySATCoreFeatures().execute(sat_model).get_result()
        dead = PySATDeadFeatures().execute(sat_model).get_result()
        false_optional = PySATFalseOptionalFeatures().execute(sat_model).get_result()
        done = time.perf_counter()
        best_load = min(best_load, loaded - start)
        best_analysis = min(best_analysis, done - loaded)
        result = {
            "features": len(fm.get_features()),
            "satisfiable": bool(satisfiable),
            "core": sorted(str(getattr(f, "name", f)) for f in core),
            "dead": sorted(str(getattr(f, "name", f)) for f in dead),
            "false_optional": sorted(str(getattr(f, "name", f)) for f in false_optional),
        }
    result["load_seconds"] = best_load
    result["analysis_seconds"] = best_analysis
    if bdd_max_features and result["features"] <= bdd_max_features:
        # an independent exact count (flamapy's BDD plugin, CUDD-style BDD from ``dd``)
        from flamapy.metamodels.bdd_metamodel.operations import BDDConfigurationsNumber
        from flamapy.metamodels.bdd_metamodel.transformations import FmToBDD

        bdd = FmToBDD(UVLReader(path).transform()).transform()
        result["products"] = BDDConfigurationsNumber().execute(bdd).get_result()
    return result


def flamapy_process(path: str) -> None:
    """The flamapy side of the whole-process comparison (runs in the flamapy venv)."""
    from flamapy.metamodels.fm_metamodel.transformations import UVLReader
    from flamapy.metamodels.pysat_metamodel.operations import (
        PySATCoreFeatures,
        PySATDeadFeatures,
        PySATFalseOptionalFeatures,
        PySATSatisfiable,
    )
    from flamapy.metamodels.pysat_metamodel.transformations import FmToPysat

    sat_model = FmToPysat(UVLReader(path).transform()).transform()
    names = lambda found: sorted(str(getattr(f, "name", f)) for f in found)  # noqa: E731
    print(
        json.dumps(
            {
                "satisfiable": bool(PySATSatisfiable().execute(sat_model).get_result()),
                "core": names(PySATCoreFeatures().execute(sat_model).get_result()),
                "dead": names(PySATDeadFeatures().execute(sat_model).get_result()),
                "false_optional": names(
                    PySATFalseOptionalFeatures().execute(sat_model).get_result()
                ),
            }
        )
    )


def spl_command() -> list[str]:
    """The ``spl`` console script of this interpreter's environment."""
    script = Path(sys.executable).with_name("spl")
    return [str(script)] if script.exists() else [sys.executable, "-m", "spl"]


def timed(command: list[str]) -> tuple[float, dict]:
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    return time.perf_counter() - start, json.loads(done.stdout)


def whole_process(path: Path, runs: int, flamapy_python: str | None) -> dict:
    """``runs`` alternating pairs of processes; seconds and flamapy/spl ratios per pair."""
    spl_seconds, flamapy_seconds, ratios = [], [], []
    report: dict = {}
    for _ in range(runs):
        seconds, report = timed(
            [*spl_command(), "analyze", "--json", "--count-seconds", "0", str(path)]
        )
        spl_seconds.append(seconds)
        if flamapy_python:
            other, answers = timed([flamapy_python, __file__, "--flamapy-process", str(path)])
            flamapy_seconds.append(other)
            ratios.append(other / seconds)
            problems = compare(path.stem, report, answers)
            if problems:
                raise SystemExit("\n".join(problems))
    return {
        "features": report["features"],
        "spl": spl_seconds,
        "flamapy": flamapy_seconds,
        "ratios": ratios,
    }


def spl_run(path: str, repeat: int, solver: str) -> dict:
    from spl.dsl.interop.formats import load_analysable_model
    from spl.resolver.analysis.formula import FeatureModelFormula

    best_load = best_analysis = float("inf")
    result: dict = {}
    for _ in range(repeat):
        start = time.perf_counter()
        model = load_analysable_model(path)
        loaded = time.perf_counter()
        with FeatureModelFormula(model, solver_name=solver) as formula:
            satisfiable = formula.satisfiable()
            core = formula.core_features()
            dead = formula.dead_features()
            false_optional = formula.false_optional_features()
            features = formula.cnf.num_features
        done = time.perf_counter()
        best_load = min(best_load, loaded - start)
        best_analysis = min(best_analysis, done - loaded)
        result = {
            "features": features,
            "satisfiable": satisfiable,
            "core": core,
            "dead": dead,
            "false_optional": false_optional,
        }
    result["load_seconds"] = best_load
    result["analysis_seconds"] = best_analysis
    return result


def spl_count(path: str, seconds: float) -> tuple[int | None, str, float]:
    from spl.dsl.interop.formats import load_analysable_model
    from spl.resolver.analysis.formula import FeatureModelFormula

    model = load_analysable_model(path)
    start = time.perf_counter()
    with FeatureModelFormula(model) as formula:
        count = formula.count(seconds)
    return count.value, count.note, time.perf_counter() - start


def compare(name: str, spl: dict, flamapy: dict) -> list[str]:
    """Differences between the answers, explained; empty when they agree.

    flamapy's false-optional operation tests ``parent and not feature`` for every
    non-mandatory feature, so it also lists the children of dead parents (the test is
    unsatisfiable because the parent never occurs). spl reports those as dead only, so
    flamapy's list is compared without its dead features.
    """
    flamapy = dict(
        flamapy, false_optional=sorted(set(flamapy["false_optional"]) - set(flamapy["dead"]))
    )
    out = []
    for key in ("satisfiable", "core", "dead", "false_optional"):
        a, b = spl[key], flamapy[key]
        if a == b:
            continue
        if isinstance(a, list):
            extra, missing = sorted(set(a) - set(b)), sorted(set(b) - set(a))
            out.append(f"{name}: {key}: only spl {extra}, only flamapy {missing}")
        else:
            out.append(f"{name}: {key}: spl {a}, flamapy {b}")
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("models", nargs="*")
    parser.add_argument("--flamapy-python", default="/tmp/benchvenv/bin/python")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--solver", default="glucose4", help="python-sat solver name for spl")
    parser.add_argument("--count-seconds", type=float, default=600.0)
    parser.add_argument("--json-out", help="store flamapy's answers here (test fixtures)")
    parser.add_argument(
        "--bdd-max-features",
        type=int,
        default=200,
        help="also count products with flamapy's BDD plugin up to this size "
        "(BusyBox does not finish in 5 minutes)",
    )
    parser.add_argument("--runs", type=int, default=5, help="whole-process pairs per model")
    parser.add_argument(
        "--spl-only",
        nargs="*",
        default=[],
        metavar="MODEL",
        help="also time whole spl analyze processes on these (no flamapy)",
    )
    parser.add_argument("--whole-only", action="store_true", help="skip the in-process table")
    parser.add_argument("--flamapy-worker", help=argparse.SUPPRESS)
    parser.add_argument("--flamapy-process", help=argparse.SUPPRESS)
    args = parser.parse_args()

    if args.flamapy_worker:
        print(json.dumps(flamapy_worker(args.flamapy_worker, args.repeat, args.bdd_max_features)))
        return 0
    if args.flamapy_process:
        flamapy_process(args.flamapy_process)
        return 0

    models = [Path(m) for m in args.models] or [DATA / m for m in DEFAULT_MODELS]
    problems = [] if args.whole_only else in_process(models, args)
    print()
    print(
        f"Whole processes ({args.runs} alternating runs each; `spl analyze --json "
        "--count-seconds 0` against flamapy reading the file and running the same four "
        "operations):"
    )
    print()
    print(
        "| model | features | flamapy s (median) | spl s (min / median) | flamapy/spl min "
        "| flamapy/spl median |"
    )
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for path in models:
        found = whole_process(path, args.runs, args.flamapy_python)
        print(
            f"| {path.stem} | {found['features']} | {statistics.median(found['flamapy']):.2f} "
            f"| {min(found['spl']):.2f} / {statistics.median(found['spl']):.2f} "
            f"| {min(found['ratios']):.1f}x | {statistics.median(found['ratios']):.1f}x |"
        )
    for name in args.spl_only:
        found = whole_process(Path(name), args.runs, None)
        print(
            f"| {Path(name).stem} | {found['features']} | - "
            f"| {min(found['spl']):.2f} / {statistics.median(found['spl']):.2f} | - | - |"
        )
    return 1 if problems else 0


def in_process(models: list[Path], args: argparse.Namespace) -> list[str]:
    """The in-process table (load and analysis apart, answers compared); the problems."""
    rows, problems, fixtures = [], [], {}
    for path in models:
        worker = subprocess.run(
            [
                args.flamapy_python,
                __file__,
                "--flamapy-worker",
                str(path),
                "--repeat",
                str(args.repeat),
                "--bdd-max-features",
                str(args.bdd_max_features),
            ],
            capture_output=True,
            text=True,
            check=True,
        )
        flamapy = json.loads(worker.stdout)
        spl = spl_run(str(path), args.repeat, args.solver)
        products, note, count_seconds = spl_count(str(path), args.count_seconds)
        problems += compare(path.stem, spl, flamapy)
        fixtures[path.name] = {
            k: flamapy[k]
            for k in ("features", "satisfiable", "core", "dead", "false_optional", "products")
            if k in flamapy
        }
        if "products" in flamapy and flamapy["products"] != products:
            problems.append(
                f"{path.stem}: products: spl {products}, flamapy BDD {flamapy['products']}"
            )
        ratio = flamapy["analysis_seconds"] / spl["analysis_seconds"]
        overall = (flamapy["load_seconds"] + flamapy["analysis_seconds"]) / (
            spl["load_seconds"] + spl["analysis_seconds"]
        )
        rows.append(
            f"| {path.stem} | {spl['features']} | {len(spl['core'])}/{len(spl['dead'])}/"
            f"{len(spl['false_optional'])} | {flamapy['load_seconds']:.3f} | "
            f"{flamapy['analysis_seconds']:.3f} | {spl['load_seconds']:.3f} | "
            f"{spl['analysis_seconds']:.3f} | {ratio:.1f}x | {overall:.1f}x | "
            f"{'same' if not compare(path.stem, spl, flamapy) else 'DIFFERENT'} | "
            f"{_count_cell(products, note, count_seconds)} |"
        )
    print(
        "| model | features | core/dead/false-opt | flamapy load s | flamapy analysis s "
        "| spl load s | spl analysis s | speed-up analysis | speed-up load+analysis "
        "| same answers | spl exact count (s) |"
    )
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- |")
    for row in rows:
        print(row)
    for problem in problems:
        print("DIFFERENCE:", problem)
    if args.json_out:
        write_fixtures(fixtures, Path(args.json_out))
    return problems


def write_fixtures(fixtures: dict, path: Path) -> None:
    text = json.dumps(
        {
            "produced_by": "bench/fm_analysis.py --json-out, flamapy 2.6 (flamapy-fm UVLReader, "
            "flamapy-sat FmToPysat + PySATSatisfiable, PySATCoreFeatures, "
            "PySATDeadFeatures, PySATFalseOptionalFeatures; products: flamapy-bdd "
            "BDDConfigurationsNumber, small models only) on the UVL files of "
            "tests/data/feature-models",
            "models": fixtures,
        },
        indent=1,
        sort_keys=True,
    )
    path.write_text(text + "\n", encoding="utf-8")


def _count_cell(products: int | None, note: str, seconds: float) -> str:
    if products is None:
        return f"unknown: {note}"
    text = str(products)
    shown = text if len(text) <= 15 else f"{text[0]}.{text[1:4]}e{len(text) - 1}"
    return f"{shown} ({seconds:.2f})"


if __name__ == "__main__":
    sys.exit(main())
