"""Resolve time on synthetic product lines of 1k and 10k nodes (docs/performance.md,
"Resolution scaling").

Each line has one robot and four cloud containers. In every container the nodes form
chains over topics; every cloud container mirrors a tenth of the robot's topics (same
ROS names) with bridges from the robot. Half of the nodes are optional. One feature per
twenty nodes requires its slice of optional nodes and sets implementations and
parameters, and every fourth feature migrates nodes between the robot and the cloud.
All features are selected, so every element is active.

    python bench/resolve_scaling.py [--sizes 1000 10000]

Prints parse and resolve time per size and the ratio of resolve times; the target is
linear growth (ratio 10k/1k <= 12).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

CONTAINERS = ["Robot", "Cloud0", "Cloud1", "Cloud2", "Cloud3"]


def synthetic_line(folder: Path, nodes: int) -> list[str]:
    per_container = nodes // len(CONTAINERS)
    tsm = ["system Synthetic", ""]
    node_names: dict[str, list[str]] = {}
    for c, container in enumerate(CONTAINERS):
        if container == "Robot":
            tsm.append("robot container Robot {")
            tsm.append(
                '    endpoint robot_id "robot_1" url "wss://cloud.example.org:9000/" '
                'user "bench" password env "RCE_PASSWORD"'
            )
        else:
            tsm.append(f'cloud container {container} group "g{c}" {{')
        for i in range(per_container):
            if container == "Robot" or i % 10 == 0:
                tsm.append(f'    topic T{i} : std_msgs/String name "/t{i}"')
        names = node_names.setdefault(container, [])
        for i in range(per_container):
            name = f"{container}N{i}"
            names.append(name)
            optional = "optional " if i % 2 else ""
            tsm.append(f"    {optional}node {name} {{")
            tsm.append(f"        implementation pkg{c}/exe{i}")
            tsm.append("        param rate : double = 1.0")
            has_topic = container == "Robot" or i % 10 == 0
            if has_topic:
                tsm.append(f"        publishes out -> T{i}")
            previous = i - 1 if container == "Robot" else i - 10
            if i > 0 and previous >= 0 and (container == "Robot" or has_topic):
                tsm.append(f"        subscribes in <- T{previous}")
            tsm.append("    }")
        tsm.append("}")
        tsm.append("")
    for container in CONTAINERS[1:]:
        for i in range(0, per_container, 10):
            tsm.append(f"bridge Robot.T{i} -> {container}.T{i}")
    (folder / "synthetic.tsm").write_text("\n".join(tsm) + "\n")

    features = nodes // 20
    fm = ["feature model Synthetic", "", "root Root {"]
    fm += [f"    optional F{j}" for j in range(features)]
    fm += ["}"]
    (folder / "synthetic.fm").write_text("\n".join(fm) + "\n")

    rm = ["resolution model Synthetic", 'tsm "synthetic.tsm"', 'fm "synthetic.fm"', ""]
    all_nodes = [(c, n) for c in CONTAINERS for n in node_names[c]]
    for j in range(features):
        chunk = all_nodes[j * 20 : (j + 1) * 20]
        optional = [n for k, (_, n) in enumerate(chunk) if int(n.split("N")[1]) % 2]
        rm.append(f"when F{j} selected {{")
        if optional:
            rm.append(f"    require {', '.join(optional)}")
        for _, name in chunk[:4]:
            rm.append(f"    implementation {name} = impl{j}/{name.lower()}")
            rm.append(f"    parameter {name}.rate = {j}.5")
        if j % 4 == 0:
            container, name = chunk[0]
            target = "Cloud0" if container == "Robot" else "Robot"
            rm.append(f"    migrate {name} to {target}")
        rm.append("}")
    (folder / "synthetic.rm").write_text("\n".join(rm) + "\n")
    return [f"F{j}" for j in range(features)]


def measure(nodes: int) -> tuple[float, float, int]:
    from spl.resolver.resolution.engine import resolve
    from spl.resolver.resolution.product_line import load_product_line
    from spl.resolver.resolution.product_selection import ProductSelection

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        features = synthetic_line(folder, nodes)
        start = time.perf_counter()
        line = load_product_line(folder)
        line.formula  # noqa: B018 - the solver is built once per line, with the parse
        parsed = time.perf_counter()
        resolution = resolve(line, ProductSelection("all", features))
        resolved = time.perf_counter()
    return parsed - start, resolved - parsed, len(resolution.product.migrations)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000])
    sizes = parser.parse_args().sizes
    results = {}
    print("| nodes | parse + SAT encoding (s) | resolve (s) | migrations |")
    print("| ---: | ---: | ---: | ---: |")
    for size in sizes:
        parse, resolve_time, migrations = measure(size)
        results[size] = resolve_time
        print(f"| {size} | {parse:.2f} | {resolve_time:.3f} | {migrations} |")
    if len(sizes) >= 2:
        small, large = sizes[0], sizes[-1]
        ratio = results[large] / results[small]
        print(
            f"\nresolve time ratio {large}/{small}: {ratio:.1f} "
            f"(size ratio {large / small:.0f}; target <= {1.2 * large / small:.0f})"
        )


if __name__ == "__main__":
    main()
