"""Time of the product-line checks (``spl check DIR``'s line part) on synthetic lines.

Each line has G alternative groups of four features; the four elements of a group give
one node four implementations and four parameter values (6 + 6 candidate pairs per
group, all ruled out by the ``xor``). Optional features come in pairs that exclude each
other and give one optional node two implementations (ruled out too), except every
50th pair, which is left unconstrained: a real, reported conflict. One optional node in
ten pairs is required by nobody (an SPL011 warning).

    python bench/line_checks.py [--groups 250 2500] [--runs 5]

Prints first, per shipped line, the CPU time of a whole ``spl check DIR`` process
(budget 0.3 s) and of its dataflow checks (SPL045/046 unfed inputs with witness
products, SPL052 unconsumed outputs; docs/semantics.md F8); then the dataflow checks on
a generated line of 200 features and 1,000 inputs (budget 2 s). Then, per size:
features, resolution elements, solver calls (full solves, unit
propagations), findings, load time and check time. The target is roughly linear growth
in the number of elements (the checks never enumerate products; the lines have ~4^G
products) and a handful of full solves: most answers come from kept models and from
unit propagation.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from spl.resolver import line_checks
from spl.resolver.line_checks.conflicts import reachable_conflicts
from spl.resolver.line_checks.dataflow import unfed_inputs_in_line
from spl.resolver.line_checks.dead_elements import never_active_elements
from spl.resolver.line_checks.no_effect import features_without_effect
from spl.resolver.line_checks.unconsumed import unconsumed_outputs_in_line
from spl.resolver.resolution.product_line import load_product_line

ROOT = Path(__file__).resolve().parents[1]


def synthetic_line(folder: Path, groups: int) -> None:
    pairs = groups
    fm = ["feature model Synthetic", "", "root Root {"]
    for g in range(groups):
        fm.append(f"    mandatory G{g} xor {{ A{g}_0 A{g}_1 A{g}_2 A{g}_3 }}")
    for i in range(2 * pairs):
        fm.append(f"    optional O{i}")
    fm += ["}", "", "constraints {"]
    for j in range(pairs):
        if j % 50:
            fm.append(f"    O{2 * j} excludes O{2 * j + 1}")
    fm.append("}")
    (folder / "synthetic.fm").write_text("\n".join(fm) + "\n")

    tsm = ["system Synthetic", "", "robot container Robot {"]
    tsm.append(
        '    endpoint robot_id "robot_1" url "wss://cloud.example.org:9000/" '
        'user "bench" password env "RCE_PASSWORD"'
    )
    for g in range(groups):
        tsm += [
            f"    node N{g} {{",
            "        implementation base/n",
            "        param p : double = 0.0",
            "    }",
        ]
    for j in range(pairs):
        tsm += [f"    optional node M{j} {{", "        implementation base/m", "    }"]
        if j % 10 == 0:
            tsm += [f"    optional node U{j} {{", "        implementation base/u", "    }"]
    tsm.append("}")
    (folder / "synthetic.tsm").write_text("\n".join(tsm) + "\n")

    rm = ["resolution model Synthetic", 'tsm "synthetic.tsm"', 'fm "synthetic.fm"', ""]
    for g in range(groups):
        for k in range(4):
            rm += [
                f"when A{g}_{k} selected {{",
                f"    implementation N{g} = impl{k}/n{g}",
                f"    parameter N{g}.p = {k}.0",
                "}",
            ]
    for j in range(pairs):
        for side in (0, 1):
            rm += [
                f"when O{2 * j + side} selected {{",
                f"    require M{j}",
                f"    implementation M{j} = side{side}/m{j}",
                "}",
            ]
    (folder / "synthetic.rm").write_text("\n".join(rm) + "\n")


def dataflow_line(folder: Path, features: int = 200, consumers: int = 100, per: int = 10) -> None:
    """A line of ``features`` optional features (F2i+1 requires F2i) and ``consumers`` x
    ``per`` subscribers, half in a robot and half in a cloud bridged to it: topic Tk is
    fed by optional P{k} (kept by Fk) and, but for every tenth topic, by optional Qk
    (kept by ``when Fk not selected``), so every input is a SAT question, 1 in 10 has a
    product leaving it unfed, and those share one witness (no feature selected)."""
    fm = ["feature model Flows", "", "root Root {"]
    fm += [f"    optional F{k}" for k in range(features)]
    fm += ["}", "", "constraints {"]
    fm += [f"    F{2 * i + 1} requires F{2 * i}" for i in range(features // 2)]
    fm.append("}")
    (folder / "flows.fm").write_text("\n".join(fm) + "\n")
    endpoint = (
        '    endpoint robot_id "robot_1" url "wss://cloud.example.org:9000/" user "bench" '
        'password env "RCE_PASSWORD"'
    )
    robot = ["system Flows", "", "robot container Robot {", endpoint]
    cloud = ["cloud container Cloud {"]
    bridges = []
    for k in range(features):
        robot.append(f'    topic T{k} : std_msgs/String name "/t{k}"')
        cloud.append(f'    topic T{k} : std_msgs/String name "/t{k}"')
        bridges.append(f"bridge Robot.T{k} -> Cloud.T{k}")
    for k in range(features):
        for name in [f"P{k}"] + ([f"Q{k}"] if k % 10 else []):
            robot += [f"    optional node {name} {{", "        implementation base/p"]
            robot += [f"        publishes out -> T{k}", "    }"]
    for j in range(consumers):
        block = robot if j % 2 == 0 else cloud
        block += [f"    node C{j} {{", "        implementation base/c"]
        block += [f"        subscribes in{i} <- T{(per * j + i) % features}" for i in range(per)]
        block.append("    }")
    text = "\n".join([*robot, "}", "", *cloud, "}", "", *bridges])
    (folder / "flows.tsm").write_text(text + "\n")
    rm = ["resolution model Flows", 'tsm "flows.tsm"', 'fm "flows.fm"', ""]
    for k in range(features):
        rm += [f"when F{k} selected {{", f"    require P{k}", "}"]
        if k % 10:
            rm += [f"when F{k} not selected {{", f"    require Q{k}", "}"]
    (folder / "flows.rm").write_text("\n".join(rm) + "\n")


def measure_dataflow() -> dict[str, float]:
    """The dataflow checks (SPL045/046 and SPL052) on :func:`dataflow_line`."""
    with tempfile.TemporaryDirectory() as tmp:
        dataflow_line(Path(tmp))
        line = load_product_line(tmp)
        _ = line.formula
        inputs = sum(len(n.interfaces) for c in line.tsm.containers for n in c.nodes
                     if n.name.startswith("C"))  # fmt: skip
        with line_checks.ActivationSolver(line) as solver:
            start = time.perf_counter()
            unfed = unfed_inputs_in_line(line, solver)
            middle = time.perf_counter()
            unconsumed = unconsumed_outputs_in_line(line, solver)
            end = time.perf_counter()
        return {
            "features": line.formula.cnf.num_features,
            "inputs": inputs,
            "unfed": len(unfed),
            "unconsumed": len(unconsumed),
            "unfed s": middle - start,
            "unconsumed s": end - middle,
        }


def measure_shipped(runs: int) -> list[tuple[str, float, float]]:
    """Per shipped line: the median CPU seconds of a whole ``spl check DIR`` process (the
    0.3 s budget, docs/performance.md) and of its dataflow checks in this process."""
    spl = Path(sys.executable).with_name("spl")
    found = []
    for folder in sorted((ROOT / "product_lines").iterdir()):
        cpu = []
        for _ in range(runs):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run([str(spl), "check", str(folder)], capture_output=True, check=True)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
        line = load_product_line(folder)
        _ = line.formula
        flows = []
        for _ in range(runs):
            with line_checks.ActivationSolver(line) as solver:
                start = time.process_time()
                unfed_inputs_in_line(line, solver)
                unconsumed_outputs_in_line(line, solver)
                flows.append(time.process_time() - start)
        found.append((folder.name, statistics.median(cpu), statistics.median(flows)))
    return found


def measure(groups: int) -> dict[str, float]:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        synthetic_line(folder, groups)
        start = time.perf_counter()
        line = load_product_line(folder)
        _ = line.formula
        loaded = time.perf_counter() - start
        with line_checks.ActivationSolver(line) as solver:
            calls = {"solve": 0, "propagate": 0}
            for name in calls:
                original = getattr(solver.solver, name)

                def counted(*args, _name=name, _original=original, **kwargs):
                    calls[_name] += 1
                    return _original(*args, **kwargs)

                setattr(solver.solver, name, counted)
            start = time.perf_counter()
            found = never_active_elements(line, solver)
            found += line_checks.unreachable_optional_elements(line, solver)
            found += reachable_conflicts(line, solver)
            found += features_without_effect(line)
            checked = time.perf_counter() - start
        return {
            "features": line.formula.cnf.num_features,
            "elements": len(line.rm.elements),
            "solve": calls["solve"],
            "propagate": calls["propagate"],
            "conflicts": sum(d.code == "SPL012" for d in found),
            "unreachable": sum(d.code == "SPL011" for d in found),
            "load s": loaded,
            "check s": checked,
        }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--groups", type=int, nargs="+", default=[250, 2500])
    parser.add_argument("--runs", type=int, default=5, help="runs per shipped line (median)")
    args = parser.parse_args()
    for name, cpu, flows in measure_shipped(args.runs):
        verdict = "within" if cpu < 0.3 else "OVER"
        print(
            f"spl check {name}: {cpu:.3f} s CPU ({verdict} the 0.3 s budget), "
            f"dataflow checks {flows * 1000:.1f} ms"
        )
    flow = measure_dataflow()
    print(
        f"dataflow line: {flow['features']} features, {flow['inputs']} inputs, "
        f"{flow['unfed']} unfed found in {flow['unfed s']:.2f} s, "
        f"{flow['unconsumed']} unconsumed in {flow['unconsumed s']:.2f} s "
        f"(budget 2 s: {'met' if flow['unfed s'] + flow['unconsumed s'] < 2 else 'NOT met'})"
    )
    results = []
    for groups in args.groups:
        result = measure(groups)
        results.append(result)
        print(
            f"groups {groups}: {result['features']} features, {result['elements']} elements, "
            f"{result['solve']} solves, {result['propagate']} propagations, "
            f"{result['conflicts']} conflicts, "
            f"{result['unreachable']} unreachable optional nodes; "
            f"load {result['load s']:.2f} s, checks {result['check s']:.2f} s"
        )
    if len(results) > 1:
        first, last = results[0], results[-1]
        print(
            f"elements x{last['elements'] / first['elements']:.1f}: "
            f"check time x{last['check s'] / max(first['check s'], 1e-9):.1f}"
        )


if __name__ == "__main__":
    main()
