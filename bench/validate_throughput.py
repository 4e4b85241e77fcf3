"""Benchmark: how fast ``spl validate`` checks every product of a line.

1. mapping3d: one ``spl validate --all`` process against twelve ``spl resolve``
   processes for the same twelve products (the way a CI job would do it without
   ``validate``). Both run on a copy of the line without ``products/``, so both handle
   exactly the twelve products of the feature model; ``validate`` does strictly more per
   product (it also validates every artifact) but parses the models once and starts
   Python once. ``--runs`` rounds (5 by default), each timing validate with one job,
   the twelve resolves and validate with ``--jobs 2`` one after the other, so a busy
   spell of the machine hits both sides; the ratio of a round is resolve-time /
   validate-time, reported per round and as min/median/max, and the ratio of each side's
   fastest round (other programs only ever add time, and one validate process is
   more exposed to a busy spell than twelve resolves are). Each side is timed by the
   wall clock and by the CPU time its processes used (user + system, children
   included: resolve's ``dot``): on a shared machine the wall clock also counts the
   time other programs held the CPU, the CPU time does not.
2. A synthetic line generated into a temporary folder: ``--features K`` independent
   optional features, each requiring its own optional node (2**K products, 2048 by
   default). ``spl validate --all`` with ``--jobs 1`` and ``--jobs 2``, products per
   second over the whole process (start-up, parsing and enumeration included).
3. What forking saves: the time to parse each line and build its SAT formula, which a
   worker that does not inherit the parent's models (spawn, or one process per product)
   pays again.

Every ``spl`` process runs as a user's install would: with Python's bytecode cache
(``PYTHONDONTWRITEBYTECODE`` removed from its environment, and one untimed resolve and
validate first, so the ``.pyc`` files exist before anything is timed). Without the cache
each process would compile spl's modules from source (~80 ms), a cost a user does not
pay and that would weigh twelve times on the resolve side.

    /tmp/venv/bin/python bench/validate_throughput.py [--runs 5] [--features 11]
        [--no-synthetic] [--spl /tmp/venv/bin/spl]
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# What a user's shell has: bytecode cached (this environment may switch it off).
USER_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def children_cpu() -> float:
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    return used.ru_utime + used.ru_stime


def timed(command: list[str]) -> tuple[float, subprocess.CompletedProcess]:
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, env=USER_ENV)
    return time.perf_counter() - start, done


def checked(seconds_and_done: tuple[float, subprocess.CompletedProcess]) -> float:
    seconds, done = seconds_and_done
    if done.returncode != 0:
        sys.exit(f"{' '.join(done.args)} failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return seconds


def wall_and_cpu(commands: list[list[str]]) -> tuple[float, float]:
    """Wall-clock and CPU seconds of running the commands one after the other."""
    cpu = children_cpu()
    wall = sum(checked(timed(command)) for command in commands)
    return wall, children_cpu() - cpu


def synthetic_line(folder: Path, features: int) -> Path:
    """K optional features, each requiring one optional node fed by a shared topic."""
    line = folder / "synthetic"
    line.mkdir()
    nodes = "\n".join(
        f"    optional node Worker{i} {{\n"
        f"        implementation worker_pkg/worker_{i}\n"
        f"        subscribes input <- Ticks\n"
        f"    }}"
        for i in range(features)
    )
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
        "}\n",
        encoding="utf-8",
    )
    options = "\n".join(f"    optional F{i}" for i in range(features))
    (line / "synthetic.fm").write_text(
        f"feature model Synthetic\n\nroot Base {{\n{options}\n}}\n", encoding="utf-8"
    )
    elements = "\n".join(
        f"when F{i} selected {{\n    require Worker{i}\n}}" for i in range(features)
    )
    (line / "synthetic.rm").write_text(
        f'resolution model Synthetic\ntsm "synthetic.tsm"\nfm  "synthetic.fm"\n\n{elements}\n',
        encoding="utf-8",
    )
    return line


def load_seconds(line: Path) -> float:
    from spl.validation.line import load_lines

    start = time.perf_counter()
    load_lines([line])
    return time.perf_counter() - start


def mapping_round(spl: str, mapping: Path, listing: list[str], out: Path) -> dict[str, tuple]:
    """One round: validate (one job), the twelve resolves, validate with two jobs; the
    wall-clock and CPU seconds of each."""
    resolves = [
        [spl, "resolve", str(mapping), "--features", features, "-o", str(out / f"b{index}")]
        for index, features in enumerate(listing)
    ]
    times = {
        "validate": wall_and_cpu([[spl, "validate", str(mapping), "--all"]]),
        "resolve": wall_and_cpu(resolves),
        "validate2": wall_and_cpu([[spl, "validate", str(mapping), "--all", "--jobs", "2"]]),
    }
    shutil.rmtree(out)
    return times


def spread(values: list[float]) -> str:
    return f"{min(values):.1f}x/{statistics.median(values):.1f}x/{max(values):.1f}x"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5, help="rounds of the mapping3d comparison")
    parser.add_argument(
        "--features",
        type=int,
        default=11,
        help="optional features of the synthetic line (2**K products)",
    )
    parser.add_argument("--no-synthetic", action="store_true", help="only the mapping3d comparison")
    parser.add_argument(
        "--spl", default=str(Path(sys.executable).with_name("spl")), help="the spl executable"
    )
    args = parser.parse_args()
    spl = args.spl

    with tempfile.TemporaryDirectory() as temp:
        temp_dir = Path(temp)
        mapping = temp_dir / "mapping3d"
        shutil.copytree(
            ROOT / "product_lines" / "mapping3d", mapping, ignore=shutil.ignore_patterns("products")
        )
        listing = subprocess.run(
            [spl, "products", str(mapping)],
            capture_output=True,
            text=True,
            check=True,
            env=USER_ENV,
        ).stdout.split()
        # untimed: writes the bytecode cache of every module either side imports
        checked(
            timed(
                [
                    spl,
                    "resolve",
                    str(mapping),
                    "--features",
                    listing[0],
                    "-o",
                    str(temp_dir / "warm"),
                ]
            )
        )
        checked(timed([spl, "validate", str(mapping), "--all"]))
        print(
            f"mapping3d, {len(listing)} products, {args.runs} rounds "
            "(bytecode cache on, as installed; seconds, wall clock / CPU):"
        )
        print("  round  validate --all   12 x resolve   ratio wall / cpu  --jobs 2  ratio")
        walls, cpus, walls2, fastest = [], [], [], {"validate": [], "resolve": []}
        for round_ in range(1, args.runs + 1):
            times = mapping_round(spl, mapping, listing, temp_dir / "bundles")
            (v_wall, v_cpu), (r_wall, r_cpu) = times["validate"], times["resolve"]
            v2_wall = times["validate2"][0]
            walls.append(r_wall / v_wall)
            fastest["validate"].append(v_wall)
            fastest["resolve"].append(r_wall)
            cpus.append(r_cpu / v_cpu)
            walls2.append(r_wall / v2_wall)
            print(
                f"  {round_:>5}  {v_wall:>5.2f} / {v_cpu:>5.2f}  {r_wall:>5.2f} / {r_cpu:>5.2f}"
                f"  {walls[-1]:>5.1f}x / {cpus[-1]:>4.1f}x  {v2_wall:>8.2f}  {walls2[-1]:>4.1f}x",
                flush=True,
            )
        print(
            f"  validate is {spread(walls)} faster with one job by the wall clock "
            f"(min/median/max), {spread(cpus)} by CPU time; {spread(walls2)} with --jobs 2"
        )
        v_best, r_best = min(fastest["validate"]), min(fastest["resolve"])
        print(
            f"  fastest of each side: validate {v_best:.2f} s, twelve resolves {r_best:.2f} s: "
            f"{r_best / v_best:.1f}x (each side's least disturbed round)"
        )
        if args.no_synthetic:
            return

        line = synthetic_line(temp_dir, args.features)
        count = 2**args.features
        print(f"synthetic line: {args.features} optional features, {count} products")
        for jobs in (1, 2):
            seconds, done = timed([spl, "validate", str(line), "--all", "--jobs", str(jobs)])
            last = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else ""
            if done.returncode != 0 or last != f"{count} passed, 0 failed":
                sys.exit(f"validate --jobs {jobs} failed: {last}\n{done.stderr}")
            print(f"  --jobs {jobs}: {seconds:6.1f} s, {count / seconds:6.1f} products/s")

        print("parse + SAT formula per line (what each non-forked worker would repeat):")
        print(
            f"  mapping3d: {load_seconds(ROOT / 'product_lines' / 'mapping3d') * 1000:.0f} ms;"
            f" synthetic: {load_seconds(line) * 1000:.0f} ms"
        )


if __name__ == "__main__":
    main()
