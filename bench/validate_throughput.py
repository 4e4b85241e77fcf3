"""Benchmark: how fast ``spl validate`` checks every product of a line.

1. mapping3d: one ``spl validate --all`` process against twelve ``spl resolve``
   processes for the same twelve products (the way a CI job would do it without
   ``validate``). Both run on a copy of the line without ``products/``, so both handle
   exactly the twelve products of the feature model; ``validate`` does strictly more per
   product (it also validates every artifact) but parses the models once and starts
   Python once. One run each (validate also with ``--jobs 2``); the ratio is
   resolve-time / validate-time.
2. A synthetic line generated into a temporary folder: ``--features K`` independent
   optional features, each requiring its own optional node (2**K products, 2048 by
   default). ``spl validate --all`` with ``--jobs 1`` and ``--jobs 2``, products per
   second over the whole process (start-up, parsing and enumeration included).
3. What forking saves: the time to parse each line and build its SAT formula, which a
   worker that does not inherit the parent's models (spawn, or one process per product)
   pays again.

    /tmp/venv/bin/python bench/validate_throughput.py [--features 11] [--spl /tmp/venv/bin/spl]
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def timed(command: list[str]) -> tuple[float, subprocess.CompletedProcess]:
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    return time.perf_counter() - start, done


def checked(seconds_and_done: tuple[float, subprocess.CompletedProcess]) -> float:
    seconds, done = seconds_and_done
    if done.returncode != 0:
        sys.exit(f"{' '.join(done.args)} failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return seconds


def synthetic_line(folder: Path, features: int) -> Path:
    """K optional features, each requiring one optional node fed by a shared topic."""
    line = folder / "synthetic"
    line.mkdir()
    nodes = "\n".join(
        f"    optional node Worker{i} {{\n"
        f"        implementation worker_pkg/worker_{i}\n"
        f"        subscribes input <- Ticks\n"
        f"    }}" for i in range(features))
    (line / "synthetic.tsm").write_text(
        "system Synthetic\n\n"
        "robot container Robot {\n"
        '    endpoint robot_id "robot_1" url "wss://cloud.example.org:9000/" user "bench"\n'
        '             password env "RCE_PASSWORD"\n'
        '    topic Ticks : std_msgs/Header name "/ticks"\n'
        "    node Clock {\n"
        "        implementation clock_pkg/clock\n"
        "        publishes ticks -> Ticks\n"
        "    }\n"
        f"{nodes}\n"
        "}\n", encoding="utf-8")
    options = "\n".join(f"    optional F{i}" for i in range(features))
    (line / "synthetic.fm").write_text(
        f"feature model Synthetic\n\nroot Base {{\n{options}\n}}\n", encoding="utf-8")
    elements = "\n".join(f"when F{i} selected {{\n    require Worker{i}\n}}"
                         for i in range(features))
    (line / "synthetic.rm").write_text(
        'resolution model Synthetic\ntsm "synthetic.tsm"\nfm  "synthetic.fm"\n\n'
        f"{elements}\n", encoding="utf-8")
    return line


def load_seconds(line: Path) -> float:
    from spl.line_validation import load_lines

    start = time.perf_counter()
    load_lines([line])
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--features", type=int, default=11,
                        help="optional features of the synthetic line (2**K products)")
    parser.add_argument("--spl", default=str(Path(sys.executable).with_name("spl")),
                        help="the spl executable")
    args = parser.parse_args()
    spl = args.spl

    with tempfile.TemporaryDirectory() as temp:
        temp_dir = Path(temp)
        mapping = temp_dir / "mapping3d"
        shutil.copytree(ROOT / "product_lines" / "mapping3d", mapping,
                        ignore=shutil.ignore_patterns("products"))
        listing = subprocess.run([spl, "products", str(mapping)], capture_output=True,
                                 text=True, check=True).stdout.split()
        validate = checked(timed([spl, "validate", str(mapping), "--all"]))
        validate2 = checked(timed([spl, "validate", str(mapping), "--all", "--jobs", "2"]))
        resolve = 0.0
        for index, features in enumerate(listing):
            resolve += checked(timed([spl, "resolve", str(mapping), "--features", features,
                                      "-o", str(temp_dir / f"bundle{index}")]))
        print(f"mapping3d, {len(listing)} products:")
        print(f"  spl validate --all (one process, every artifact validated): {validate:.2f} s")
        print(f"  {len(listing)} x spl resolve (one process each):{resolve:>21.2f} s")
        print(f"  spl validate --all --jobs 2:{validate2:>33.2f} s")
        print(f"  ratio: validate is {resolve / validate:.1f}x faster "
              f"({resolve / validate2:.1f}x with --jobs 2)")

        line = synthetic_line(temp_dir, args.features)
        count = 2 ** args.features
        print(f"synthetic line: {args.features} optional features, {count} products")
        for jobs in (1, 2):
            seconds, done = timed([spl, "validate", str(line), "--all", "--jobs", str(jobs)])
            last = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else ""
            if done.returncode != 0 or last != f"{count} passed, 0 failed":
                sys.exit(f"validate --jobs {jobs} failed: {last}\n{done.stderr}")
            print(f"  --jobs {jobs}: {seconds:6.1f} s, {count / seconds:6.1f} products/s")

        print("parse + SAT formula per line (what each non-forked worker would repeat):")
        print(f"  mapping3d: {load_seconds(ROOT / 'product_lines' / 'mapping3d') * 1000:.0f} ms;"
              f" synthetic: {load_seconds(line) * 1000:.0f} ms")


if __name__ == "__main__":
    main()
