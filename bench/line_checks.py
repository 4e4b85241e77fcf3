"""Time of the product-line checks (``spl check DIR``'s line part) on synthetic lines.

Each line has G alternative groups of four features; the four elements of a group give
one node four implementations and four parameter values (6 + 6 candidate pairs per
group, all ruled out by the ``xor``). Optional features come in pairs that exclude each
other and give one optional node two implementations (ruled out too), except every
50th pair, which is left unconstrained: a real, reported conflict. One optional node in
ten pairs is required by nobody (an SPL011 warning).

    python bench/line_checks.py [--groups 250 2500]

Prints, per size: features, resolution elements, solver calls (full solves, unit
propagations), findings, load time and check time. The target is roughly linear growth
in the number of elements (the checks never enumerate products; the lines have ~4^G
products) and a handful of full solves: most answers come from kept models and from
unit propagation.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from spl.resolver import line_checks
from spl.resolver.product_line import load_product_line


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
            found = line_checks.never_active_elements(line, solver)
            found += line_checks.unreachable_optional_elements(line, solver)
            found += line_checks.reachable_conflicts(line, solver)
            found += line_checks.features_without_effect(line)
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
    args = parser.parse_args()
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
