"""Benchmark: peak memory and time of ``spl analyze`` on the largest feature models.

Each run is one ``spl analyze --json --count-seconds 0 MODEL`` process (as a user runs
it: interpreter start and imports included); its peak resident memory is the kernel's
``ru_maxrss`` of the finished child (``os.wait4``; kilobytes on Linux), its times the
wall clock of the process and the ``seconds`` the report gives for the analysis. With
``--before SRC`` each run is paired with one of another checkout's ``src`` folder
(``git archive REV src | tar -x``), alternately, so both see the same machine load:

    .venv/bin/python bench/fm_memory.py [--runs 3] [--before /tmp/old/src] [MODEL.uvl ...]

Without models it runs the vendored ones of ``bench/fm_analysis.py``; the 18,616-feature
Automotive02 and the Linux kernel model are not vendored (the
Universal-Variability-Language/uvl-models repository has them:
``Feature_Models/Automotive/Automotive02/automotive2_4.uvl``,
``Feature_Models/Operating_Systems/Linux/linux-2.6.33.3.uvl``). Printed: a markdown
table, per model and checkout, of the peak RSS (max over runs) and the median times.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from fm_analysis import DATA, DEFAULT_MODELS  # the same vendored models, run as a script

SPL = Path(sys.executable).with_name("spl")


def one_run(model: Path, src: str | None) -> tuple[float, float, float]:
    """(peak RSS in MB, process seconds, analysis seconds) of one ``spl analyze``."""
    env = dict(os.environ)
    if src is not None:
        env["PYTHONPATH"] = src  # ahead of the editable install of this checkout
    command = [str(SPL), "analyze", "--json", "--count-seconds", "0", str(model)]
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.PIPE, env=env)
    output = process.stdout.read()  # type: ignore[union-attr]  # stdout is a pipe
    process.stdout.close()  # type: ignore[union-attr]
    _, status, usage = os.wait4(process.pid, 0)  # reaped here, for this child's usage
    wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise SystemExit(f"{model}: spl analyze exited {process.returncode}")
    report = json.loads(output)
    return usage.ru_maxrss / 1024, wall, float(report["seconds"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", type=Path)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--before", help="the src folder of the checkout to compare with")
    args = parser.parse_args()
    models = args.models or [DATA / name for name in DEFAULT_MODELS]
    sides: list[tuple[str, str | None]] = [("this checkout", None)]
    if args.before:
        sides.insert(0, ("before", args.before))
    print(f"load {os.getloadavg()[0]:.1f}, {args.runs} runs each")
    print("| model | checkout | peak RSS MB | process s (median) | analysis s (median) |")
    print("|---|---|---|---|---|")
    for model in models:
        runs: dict[str, list[tuple[float, float, float]]] = {label: [] for label, _ in sides}
        for _ in range(args.runs):
            for label, src in sides:
                runs[label].append(one_run(model, src))
        for label, _ in sides:
            rss = max(r[0] for r in runs[label])
            wall = statistics.median(r[1] for r in runs[label])
            analysis = statistics.median(r[2] for r in runs[label])
            print(f"| {model.name} | {label} | {rss:.0f} | {wall:.2f} | {analysis:.3f} |")


if __name__ == "__main__":
    main()
