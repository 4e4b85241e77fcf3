"""Benchmark: whole ``spl check`` processes on a synthetic .tsm of 1k and 10k nodes
(docs/performance.md, "Targets").

    .venv/bin/python bench/tsm_scale.py [--sizes 1000 10000] [--runs 3] [--line] [--keep DIR]
                                        [--witnesses K]

Writes, for each size, a product line the way a user would write a large one: two robot
containers (endpoint, namespace) and three cloud containers (group and resources), the
nodes spread over them in pipelines (a node publishes its stage's topic and subscribes
to the previous one), every fifth node providing a service its successor calls, every
node with an implementation and parameters; topics bridged from the robots to the
clouds and service clients bridged to cloud servers; a data-acquisition part (data
types, a transform, a store per cloud, writers and readers on the robots). Beside it a
.fm with one optional feature per twenty nodes and a .rm whose elements require those
nodes, set implementations and parameters and migrate a node now and then.

Times ``--runs`` whole ``spl check FILE.tsm`` processes per size, interleaved, and
prints the wall time and peak memory (min and median) of each and the ratio the issue
judges: the 10k median over the 1k median, at most 10 (size ratio 10), and the 10k
median under 5 s. ``--line`` also times ``spl check`` of the whole product-line folder
(the .rm, .fm and .tsm parsed, then the line checks of docs/commands.md, "spl check"),
and of ``product_lines/mapping3d`` in the same rounds, and judges the line folders by
CPU time (docs/performance.md, "Large product lines"): the 1k folder at most 6x
mapping3d and under 300 MB, the 10k folder at most 12x the 1k one. ``--witnesses K``
instead times, in this process, K witness resolutions of each size's line as its
dataflow check makes them (the products ``Root`` and ``F<i>, Root``, the collector
paused as ``spl check`` pauses it): CPU ms per witness, the part of the folder's check
that grows with the line.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROBOTS = ("Rover", "Arm")
CLOUDS = ("Planning", "Mapping", "Archive")
STAGE = 5  # nodes per pipeline stage: one service server, four clients and subscribers
TARGET_RATIO = 10.0
TARGET_SECONDS = 5.0
LINE_TO_SHIPPED = 6.0  # 1k line folder CPU over mapping3d's
LINE_RATIO = 12.0  # 10k line folder CPU over the 1k one's
LINE_MB = 300.0  # peak of the 1k line folder
SHIPPED = Path(__file__).resolve().parents[1] / "product_lines" / "mapping3d"


def bridged_client(i: int) -> bool:
    """Whether robot node ``i`` declares the unbound client a service bridge binds."""
    stage, role = divmod(i, STAGE)
    return role == 1 and stage % 8 == 1


def container_tsm(name: str, index: int, nodes: int, robot: bool) -> list[str]:
    """One container holding ``nodes`` nodes (a multiple of STAGE) and their topics."""
    prefix = name[0]
    cloud = CLOUDS[index % len(CLOUDS)]
    if robot:
        out = [
            f"robot container {name} {{",
            f'    endpoint robot_id "{name.lower()}_1" url "wss://cloud.example.org:9000/" '
            f'user "{name.lower()}" password env "RCE_PASSWORD"',
            f'    namespace "/{name.lower()}"',
            f"    topic {prefix}Readings : sensor_msgs/Temperature",
            f"    writer {prefix}Writer : Reading to {cloud}.{cloud}Store <- {prefix}Readings",
            f"    topic {prefix}Summaries : std_msgs/String",
            f"    reader {prefix}Reader : Summary from {cloud}.{cloud}Store -> {prefix}Summaries"
            " every 1 s",
        ]
    else:
        out = [
            f'cloud container {name} group "{name.lower()}s" size 2 cpu 4 memory 8192 {{',
            f"    store {name}Store {{",
            "        raw Reading",
            "        refined Summary by Summarize every 10 s",
            "    }",
        ]
    for stage in range(nodes // STAGE):
        out.append(
            f'    topic {prefix}T{stage} : sensor_msgs/PointCloud2 name "/{prefix}/t{stage}"'
        )
    for i in range(nodes):
        stage, role = divmod(i, STAGE)
        out.append(f"    {'optional ' if i % 2 else ''}node {prefix}N{i} {{")
        out.append(f'        implementation pkg_{name.lower()}/node_{i} args "--id {i}"')
        out.append(f"        param rate : double = {1 + i % 7}.5")
        out.append(f'        param frame : string = "{prefix.lower()}_frame_{i}"')
        if role == 0:
            out.append(f"        publishes out -> {prefix}T{stage}")
            out.append(f'        provides lookup : nav_msgs/GetMap name "/{prefix}/lookup{stage}"')
        else:
            out.append("        publishes status : std_msgs/String")
            out.append(f"        calls lookup -> {prefix}N{stage * STAGE}.lookup")
        if robot and bridged_client(i):
            out.append("        calls lookup_remote : nav_msgs/GetMap")
        if stage > 0:
            out.append(f"        subscribes in <- {prefix}T{stage - 1}")
        out.append("    }")
    out.append("}")
    out.append("")
    return out


def resolution_element(j: int, chunk: list[tuple[str, str]]) -> list[str]:
    """Feature ``F<j>``'s element over its twenty nodes: the optional ones required, two
    given an implementation and a rate, and every fourth element a migration."""
    qualified = [f"{container}.{node}" for container, node in chunk]
    statements = [f"require {', '.join(q for q in qualified if int(q[-1]) % 2)}"]
    for name in qualified[:2]:
        statements.append(f"implementation {name} = impl{j}/{name.split('.')[1].lower()}")
        statements.append(f"parameter {name}.rate = {j}.5")
    if j % 4 == 0:
        target = CLOUDS[0] if chunk[0][0] in ROBOTS else ROBOTS[0]
        statements.append(f"migrate {qualified[0]} to {target}")
    return [f"when F{j} selected {{", *(f"    {s}" for s in statements), "}"]


def synthetic_line(folder: Path, nodes: int) -> int:
    """Write ``synthetic.tsm``, ``.fm`` and ``.rm`` of about ``nodes`` nodes into
    ``folder``; the number of lines of the .tsm."""
    names = ROBOTS + CLOUDS
    per_container = max(STAGE, nodes // len(names) // STAGE * STAGE)
    tsm = [
        "// synthetic line of bench/tsm_scale.py",
        "system Synthetic",
        "",
        "data Reading { celsius : double  variance : double }",
        "data Summary { fahrenheit : double }",
        "transform Summarize : Reading -> Summary {",
        "    fahrenheit = celsius * 9.0 / 5.0 + 32.0",
        "}",
        "",
    ]
    for index, name in enumerate(names):
        tsm += container_tsm(name, index, per_container, name in ROBOTS)
    for r, robot in enumerate(ROBOTS):
        for i in range(per_container):
            stage = i // STAGE
            if i % STAGE == 0 and stage % 4 == 0:  # every fourth stage's topic to a cloud
                cloud = CLOUDS[(stage // 4 + r) % len(CLOUDS)]
                tsm.append(f"bridge {robot}.{robot[0]}T{stage} -> {cloud}.{cloud[0]}T{stage}")
            if bridged_client(i):
                cloud = CLOUDS[(stage + r) % len(CLOUDS)]
                tsm.append(
                    f"bridge {robot}.{robot[0]}N{i}.lookup_remote -> "
                    f"{cloud}.{cloud[0]}N{stage * STAGE}.lookup"
                )
    (folder / "synthetic.tsm").write_text("\n".join(tsm) + "\n")

    all_nodes = [(name, f"{name[0]}N{i}") for name in names for i in range(per_container)]
    features = max(1, len(all_nodes) // 20)
    fm = ["feature model Synthetic", "", "root Root {"]
    fm += [f"    optional F{j}" for j in range(features)]
    fm += ["}"]
    (folder / "synthetic.fm").write_text("\n".join(fm) + "\n")

    rm = ["resolution model Synthetic", 'tsm "synthetic.tsm"', 'fm "synthetic.fm"', ""]
    for j in range(features):
        rm += resolution_element(j, all_nodes[j * 20 : (j + 1) * 20])
    (folder / "synthetic.rm").write_text("\n".join(rm) + "\n")
    return len(tsm)


def spl_command() -> list[str]:
    script = Path(sys.executable).with_name("spl")
    return [str(script)] if script.exists() else [sys.executable, "-m", "spl"]


def run(arguments: list[str]) -> tuple[float, float, float]:
    """Wall seconds, CPU seconds (user + system) and peak resident MB of one whole
    process (it must succeed). CPU time is given as well because on a shared, loaded
    machine the wall time also measures waiting for a core."""
    # stderr to a file: a large line's check warns more than a pipe nobody reads holds
    with tempfile.TemporaryFile() as stderr:
        start = time.perf_counter()
        process = subprocess.Popen(arguments, stdout=subprocess.DEVNULL, stderr=stderr)
        _, status, usage = os.wait4(process.pid, 0)
        wall = time.perf_counter() - start
        stderr.seek(0)
        error = stderr.read().decode(errors="replace")
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(arguments)} failed:\n{error}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def witness_times(folder: Path, count: int) -> list[float]:
    """CPU seconds of each of ``count`` witness resolutions of the line in ``folder``
    (the first, which reads the line's per-line facts, not counted)."""
    from spl.core.cyclic_gc import without_cyclic_gc
    from spl.resolver.line_checks.witnesses import witness_warnings
    from spl.resolver.resolution.product_line import load_product_line

    line = load_product_line(folder)
    products = [("Root",)] + [(f"F{i}", "Root") for i in range(1, count)]
    times = []
    with without_cyclic_gc("dropped"):  # as the line checks run (spl.resolver.line_checks)
        witness_warnings(line, products[0])
        for witness in products:
            start = time.process_time()
            witness_warnings(line, witness)
            times.append(time.process_time() - start)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--line", action="store_true", help="also check the whole line folder")
    parser.add_argument("--keep", type=Path, help="write the models here and keep them")
    parser.add_argument("--witnesses", type=int, default=0, help="time K witness resolutions")
    options = parser.parse_args()
    if options.witnesses:
        with tempfile.TemporaryDirectory() as tmp:
            medians = {}
            for size in options.sizes:
                folder = (options.keep or Path(tmp)) / f"n{size}"
                folder.mkdir(parents=True, exist_ok=True)
                synthetic_line(folder, size)
                times = witness_times(folder, options.witnesses)
                medians[size] = statistics.median(times)
                print(
                    f"{size} nodes: {len(times)} witnesses, CPU median "
                    f"{1000 * medians[size]:.1f} ms, min {1000 * min(times):.1f} ms"
                )
        if len(options.sizes) > 1:
            small, large = options.sizes[0], options.sizes[-1]
            print(f"witness CPU median {large}/{small}: {medians[large] / medians[small]:.1f}")
        return
    kinds = ("tsm", "line") if options.line else ("tsm",)
    results: dict[tuple[str, int], list[tuple[float, float, float]]] = {}
    lines: dict[int, int] = {}
    with tempfile.TemporaryDirectory() as tmp:
        root = options.keep or Path(tmp)
        targets: dict[tuple[str, int], Path] = {}
        for size in options.sizes:
            folder = root / f"n{size}"
            folder.mkdir(parents=True, exist_ok=True)
            lines[size] = synthetic_line(folder, size)
            targets["tsm", size] = folder / "synthetic.tsm"
            if options.line:
                targets["line", size] = folder
        if options.line:
            targets["shipped", 0] = SHIPPED
            lines[0] = len((SHIPPED / "mapping.tsm").read_text().splitlines())
        for _ in range(options.runs):  # interleaved, so a load change hits every size alike
            for key, target in targets.items():
                results.setdefault(key, []).append(run([*spl_command(), "check", str(target)]))
    print(
        "| spl check | nodes | .tsm lines | wall min s | wall median s | CPU median s "
        "| peak MB median |"
    )
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    medians: dict[tuple[str, int], float] = {}
    cpus: dict[tuple[str, int], float] = {}
    peaks: dict[tuple[str, int], float] = {}
    for (kind, size), samples in results.items():
        walls = [wall for wall, _, _ in samples]
        medians[kind, size] = statistics.median(walls)
        cpu = cpus[kind, size] = statistics.median(cpu for _, cpu, _ in samples)
        memory = peaks[kind, size] = statistics.median(mb for _, _, mb in samples)
        what = {"tsm": "synthetic.tsm", "line": "line folder", "shipped": "mapping3d"}[kind]
        print(
            f"| {what} | {size or '-'} | {lines[size]} | {min(walls):.2f} "
            f"| {medians[kind, size]:.2f} | {cpu:.2f} | {memory:.0f} |"
        )
    small, large = options.sizes[0], options.sizes[-1]
    print()
    if options.line:
        shipped = cpus["line", small] / cpus["shipped", 0]
        met = shipped <= LINE_TO_SHIPPED and peaks["line", small] < LINE_MB
        print(
            f"line: CPU median {small}-node folder / mapping3d: {shipped:.1f}, peak "
            f"{peaks['line', small]:.0f} MB (target <= {LINE_TO_SHIPPED:.0f} and under "
            f"{LINE_MB:.0f} MB: {'met' if met else 'NOT met'})"
        )
        if large != small:
            ratio = cpus["line", large] / cpus["line", small]
            print(
                f"line: CPU median {large}/{small} folder: {ratio:.1f} (target <= "
                f"{LINE_RATIO:.0f}: {'met' if ratio <= LINE_RATIO else 'NOT met'})"
            )
    if len(options.sizes) < 2:
        return
    for kind in kinds:
        ratio = medians[kind, large] / medians[kind, small]
        print(f"{kind}: median wall ratio {large}/{small}: {ratio:.1f}", end="")
        if kind == "tsm":
            met = ratio <= TARGET_RATIO and medians[kind, large] < TARGET_SECONDS
            print(
                f" (target <= {TARGET_RATIO:.0f} and {large} nodes under "
                f"{TARGET_SECONDS:.0f} s: {'met' if met else 'NOT met'})",
                end="",
            )
        print()


if __name__ == "__main__":
    main()
