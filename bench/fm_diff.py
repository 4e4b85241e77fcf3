"""Benchmark: ``spl diff`` of the largest shared feature model against itself with a small
edit, next to one ``spl analyze`` of it in the same run (docs/evolution.md, the bound:
at most twice the analysis).

    .venv/bin/python bench/fm_diff.py [--runs 5] [MODEL.uvl]

MODEL defaults to the largest community ``.uvl`` model of the shared data folder beside
the repository (the copies in tests/data when that folder is not there): automotive01,
2,513 features (docs/evolution.md). Two edits
of its UVL text, each written to a temporary file:

* *removed*: its first constraint left out;
* *reversed*: its first constraint of the form ``A => B`` written ``B => A``.

Each round runs, as whole processes (interpreter start and reading included), ``spl
analyze MODEL`` and ``spl diff MODEL EDITED`` for each edit, with the default count
bound, then the same with ``--count`` (no bound), in that order; ``--runs`` rounds.
Printed: the median wall and CPU seconds of each command, and each diff's median wall
time over the analysis's of the same round (the ratio of medians), with what each diff
reported (its class and counts).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "feature-models"
COPIES = ROOT / "tests" / "data" / "feature-models"
BOUND = 2.0  # a diff takes at most twice one analysis


def largest_model() -> Path:
    folder = SHARED if SHARED.is_dir() else COPIES
    return max(folder.glob("*.uvl"), key=lambda path: path.stat().st_size)


def edits(text: str) -> dict[str, str]:
    """The model's text with its first constraint removed, and with its first ``A => B``
    constraint reversed."""
    lines = text.splitlines(keepends=True)
    start = next(i for i, line in enumerate(lines) if line.strip() == "constraints") + 1
    constraints = [i for i in range(start, len(lines)) if lines[i].strip()]
    removed = lines[: constraints[0]] + lines[constraints[0] + 1 :]
    out = {"removed": "".join(removed)}
    simple = re.compile(r"^(\s*)(\S+) => (\S+)\s*$")
    for i in constraints:
        match = simple.match(lines[i])
        if match:
            indent, left, right = match.groups()
            out["reversed"] = "".join([*lines[:i], f"{indent}{right} => {left}\n", *lines[i + 1 :]])
            break
    return out


def spl() -> list[str]:
    script = Path(sys.executable).with_name("spl")
    return [str(script)] if script.exists() else [sys.executable, "-m", "spl"]


def timed(command: list[str]) -> tuple[float, float, str]:
    """Wall and CPU seconds of one process, and its output (it must succeed)."""
    start = time.perf_counter()
    process = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE, text=True)
    assert process.stdout is not None
    output = process.stdout.read()
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(command)} failed")
    return wall, usage.ru_utime + usage.ru_stime, output


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("model", nargs="?", type=Path, default=None)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    model = args.model or largest_model()
    with tempfile.TemporaryDirectory(prefix="spl-bench-diff-") as scratch:
        edited = {}
        for name, text in edits(model.read_text(encoding="utf-8")).items():
            edited[name] = Path(scratch) / f"{name}.uvl"
            edited[name].write_text(text, encoding="utf-8")
        commands: dict[str, list[str]] = {}
        for bound, flags in (("default", []), ("--count", ["--count"])):
            commands[f"analyze, {bound}"] = [*spl(), "analyze", "--json", *flags, str(model)]
            for name, path in edited.items():
                commands[f"diff {name}, {bound}"] = [
                    *spl(), "diff", "--json", *flags, str(model), str(path),
                ]  # fmt: skip
        walls: dict[str, list[float]] = {label: [] for label in commands}
        cpus: dict[str, list[float]] = {label: [] for label in commands}
        reports: dict[str, dict] = {}
        for _ in range(args.runs):
            for label, command in commands.items():
                wall, cpu, output = timed(command)
                walls[label].append(wall)
                cpus[label].append(cpu)
                reports[label] = json.loads(output)
    print(f"{model.name}, {args.runs} rounds, load {os.getloadavg()[0]:.1f}")
    print("| command | wall s (median) | CPU s (median) | / analyze | reported |")
    print("| --- | --- | --- | --- | --- |")
    for label in commands:
        wall = statistics.median(walls[label])
        cpu = statistics.median(cpus[label])
        bound = label.split(", ")[1]
        analysis = statistics.median(walls[f"analyze, {bound}"])
        report = reports[label]
        if label.startswith("analyze"):
            said = f"products {_count(report['products'])}"
        else:
            counts = report["counts"]
            said = (
                f"{report['classification']}, removed {_count(counts['old_not_new'])}, "
                f"added {_count(counts['new_not_old'])}"
            )
        ratio = wall / analysis
        verdict = (
            ""
            if label.startswith("analyze")
            else f"{ratio:.2f}x" + ("" if ratio <= BOUND else f" (over {BOUND:g}x)")
        )
        print(f"| `{label}` | {wall:.2f} | {cpu:.2f} | {verdict} | {said} |")


def _count(value: int | None) -> str:
    if value is None:
        return "unknown"
    return f"{value:.2e}" if value >= 10**6 else str(value)


if __name__ == "__main__":
    main()
