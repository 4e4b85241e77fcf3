"""Benchmark: ``spl diff --all`` of the mapping line against one edit of itself, next to
``spl validate --all`` of the edited line, with and without ``--changed-from``
(docs/evolution.md, "In CI: re-checking only what changed").

    .venv/bin/python bench/line_diff.py [--runs 5] [--smoke]

The edit is the right camera's device (``/dev/video1`` -> ``/dev/video7`` in
``mapping.tsm``), which changes the stereo products' bundles and no other. Each round
runs, as whole processes (interpreter start and reading included), ``spl validate
EDITED --all``, ``spl diff LINE EDITED --all`` and ``spl validate EDITED --all
--changed-from LINE``; with ``--smoke`` also the two validations with ``--smoke`` (ROS 1
needed; about 6 s a rehearsed product). Printed: the median wall and CPU seconds of
each command and its last line of output.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LINE = ROOT / "product_lines" / "mapping3d"
SPL = Path(sys.executable).with_name("spl")


def timed(command: list[str]) -> tuple[float, float, str]:
    """Wall and CPU seconds of one whole process, and its last line of output."""
    before = os.times()
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    after = os.times()
    cpu = (after.children_user - before.children_user) + (
        after.children_system - before.children_system
    )
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed:\n{result.stdout}{result.stderr}")
    lines = result.stdout.strip().splitlines()
    return wall, cpu, lines[-1] if lines else ""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--smoke", action="store_true", help="also time --smoke runs")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        edited = Path(scratch) / LINE.name
        shutil.copytree(LINE, edited)
        tsm = edited / "mapping.tsm"
        tsm.write_text(
            tsm.read_text(encoding="utf-8").replace('"/dev/video1"', '"/dev/video7"'),
            encoding="utf-8",
        )
        commands = {
            "spl validate --all": [str(SPL), "validate", str(edited), "--all"],
            "spl diff --all": [str(SPL), "diff", str(LINE), str(edited), "--all"],
            "spl validate --all --changed-from": [
                *(str(SPL), "validate", str(edited), "--all"),
                *("--changed-from", str(LINE)),
            ],
        }
        if args.smoke:
            for name in ("spl validate --all", "spl validate --all --changed-from"):
                commands[name.replace("--all", "--all --smoke")] = [*commands[name], "--smoke"]
        for name, command in commands.items():
            runs = [timed(command) for _ in range(args.runs)]
            wall = statistics.median(r[0] for r in runs)
            cpu = statistics.median(r[1] for r in runs)
            print(f"{name:45} wall {wall:6.2f} s  CPU {cpu:6.2f} s  {runs[-1][2]}")


if __name__ == "__main__":
    main()
