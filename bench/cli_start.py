"""Benchmark: how long a short ``spl`` command takes as a whole process.

    .venv/bin/python bench/cli_start.py [--runs 10] [--importtime] [-- spl arguments]

Runs ``spl check product_lines/mapping3d`` (or the arguments after ``--``) ``--runs``
times and prints the wall time and the CPU time (user + system) of each process, min and
median, next to the bare interpreter start and ``import click`` for comparison. CPU time
is printed because on a shared, loaded machine the wall time also measures waiting for
a core; on an idle machine the two nearly agree. The verdict compares the median wall
time with the 0.3 s target of docs/performance.md, "Targets" (``--target S`` for other
commands).
``--importtime`` adds the modules whose import (with what they import) took longest,
from ``python -X importtime``.

The processes run without ``PYTHONDONTWRITEBYTECODE`` (whatever the calling shell has),
so they read cached bytecode as an installed spl does; a first run writes it.
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TARGET_SECONDS = 0.3  # docs/performance.md, "Targets", for the default command


def spl_command() -> list[str]:
    script = Path(sys.executable).with_name("spl")
    return [str(script)] if script.exists() else [sys.executable, "-m", "spl"]


# as a user's install runs: with bytecode (compiling spl from source costs ~80 ms)
ENVIRONMENT = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def measure(command: list[str], runs: int) -> tuple[list[float], list[float]]:
    """Wall and CPU seconds of ``runs`` processes (output discarded, must succeed)."""
    walls, cpus = [], []
    for _ in range(runs):
        start = time.perf_counter()
        process = subprocess.Popen(
            command,
            cwd=ROOT,
            env=ENVIRONMENT,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        _, status, usage = os.wait4(process.pid, 0)
        walls.append(time.perf_counter() - start)
        cpus.append(usage.ru_utime + usage.ru_stime)
        if os.waitstatus_to_exitcode(status) != 0:
            raise SystemExit(f"{' '.join(command)} failed")
    return walls, cpus


def row(label: str, walls: list[float], cpus: list[float]) -> str:
    return (
        f"| {label} | {min(walls):.3f} | {statistics.median(walls):.3f} "
        f"| {min(cpus):.3f} | {statistics.median(cpus):.3f} |"
    )


def slowest_imports(command: list[str], count: int = 15) -> list[str]:
    python = [sys.executable, "-X", "importtime", "-m", "spl", *command[1:]]
    done = subprocess.run(
        python, cwd=ROOT, env=ENVIRONMENT, capture_output=True, text=True, check=True
    )
    found = []
    for line in done.stderr.splitlines():
        match = re.match(r"import time:\s+(\d+) \|\s+(\d+) \|(\s*)(\S+)", line)
        if match:
            found.append((int(match.group(2)), len(match.group(3)), match.group(4)))
    found.sort(reverse=True)
    return [
        f"{us / 1000:8.1f} ms  {'  ' * (depth // 2)}{name}" for us, depth, name in found[:count]
    ]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--importtime", action="store_true")
    parser.add_argument(
        "--target",
        type=float,
        help=f"seconds to compare with (default: {TARGET_SECONDS} for the default command)",
    )
    parser.add_argument("arguments", nargs="*", help="spl arguments (after --)")
    args = parser.parse_args()
    arguments = args.arguments or ["check", "product_lines/mapping3d"]
    command = [*spl_command(), *arguments]
    measure(command, 1)  # writes the bytecode a first run lacks

    load = os.getloadavg()[0]
    print(f"`spl {' '.join(arguments)}`, {args.runs} processes each, load average {load:.1f}:")
    print()
    print("| process | wall min s | wall median s | CPU min s | CPU median s |")
    print("| --- | ---: | ---: | ---: | ---: |")
    print(row("python -c pass", *measure([sys.executable, "-c", "pass"], args.runs)))
    print(
        row("python -c 'import click'", *measure([sys.executable, "-c", "import click"], args.runs))
    )
    walls, cpus = measure(command, args.runs)
    print(row(f"spl {' '.join(arguments)}", walls, cpus))
    print()
    target = args.target if args.target is not None else None if args.arguments else TARGET_SECONDS
    print(
        f"spl {' '.join(arguments)}: median {statistics.median(walls):.3f} s wall, "
        f"{statistics.median(cpus):.3f} s CPU (on a loaded machine the wall time includes "
        "waiting for a core)"
    )
    if target is not None:
        verdict = "meets" if statistics.median(walls) <= target else "misses"
        print(f"{verdict} the {target:g} s target on the median wall time")
    if args.importtime:
        print()
        print("slowest imports (cumulative):")
        for line in slowest_imports(command):
            print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
