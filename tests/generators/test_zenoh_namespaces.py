"""Zenoh carries every product and fleet whose flow table some bridge namespaces give
exactly (docs/deployment.md, "How the bridges' namespaces are chosen"): the written
bridges, matched by key as the bridges match them, deliver every crossing once and
nothing else, and no place routes out through one bridge what another routes in. Where
``zenoh/`` is refused, the reason names the flows and a brute force over the namespaces
finds no exact choice either (tests/support/zenoh_oracle.py).

The offshore line (tests/models/offshore/, written from the manual for these tests) has
a detector on the vessel's edge cloud, shared by a team or by the farm, whose defects go
to the onshore cloud's shared reports: a flow between two shared instances."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import networkx as nx
import pytest
import yaml
from hypothesis import event, given, settings, strategies as st

from spl.dsl.tsm import language as tsm_language
from spl.generators.bundle.paths import Skipped
from spl.generators.kubernetes import manifests as kubernetes
from spl.generators.transport.bridge import transport
from spl.generators.transport.namespaces import Choice
from spl.generators.transport.routes import links, routes
from spl.generators.zenoh import configurations as zenoh
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.wiring import Wiring
from spl.resolver.fleets.deployment import deploy
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file, selection_from_list

from support.cli_outcome import run
from support.hypothesis_budget import examples
from support.random_lines import (
    ROS_TOPICS,
    SERVICE_TYPES,
    Interface,
    LineSpec,
    Node,
    Topic,
    fleet_specs,
    write_line,
)
from support.zenoh_oracle import brute_force, crossings, exact, space, written

ROOT = Path(__file__).resolve().parents[2]
OFFSHORE = ROOT / "tests" / "models" / "offshore"
# the shipped lines', the offshore line's and the other wind-farm test line's
LISTED = [
    *sorted(ROOT.glob("product_lines/*/products/*.yaml")),
    *sorted(OFFSHORE.glob("products/*.yaml")),
    *sorted((ROOT / "tests" / "models" / "windfarm").glob("products/*.yaml")),
]
# the most choices the brute force tries in a property test (a few seconds at most)
AFFORDABLE = 5_000


def searched(products: list[ResolvedProduct]) -> bool:
    """Whether the usual namespaces were not exact (for the statistics only)."""
    wirings = [Wiring(p.flows, Placement(p.system, []), []) for p in products]
    choice = Choice(*links(wirings))
    choice.choose()
    return choice.tries > 0


def carried_exactly_or_none_is(products: list[ResolvedProduct], files: dict) -> str:
    """``carried`` when the bridges written deliver exactly the crossings, ``refused``
    when zenoh/ is left out, no namespaces would do and the reason names the flows,
    ``quiet`` when nothing crosses."""
    table, robots = crossings(products)
    wanted = {c.delivery for c in table}
    skipped = files.get("zenoh/")
    if isinstance(skipped, Skipped):
        assert brute_force(table, robots) is None, skipped.reason
        ends = {
            f"{n.eContainer().eContainer().name}.{n.eContainer().name}.{n.name}"
            for p in products
            for f in p.flows
            for n in (f.source, f.target)
        }
        assert any(end in skipped.reason for end in ends), skipped.reason
        return "refused"
    if list(files) == ["zenoh/README.md"]:
        assert not wanted
        return "quiet"
    assert exact(written(files), wanted)
    return "carried"


@pytest.mark.parametrize("path", LISTED, ids=lambda p: f"{p.parents[1].name}/{p.stem}")
def test_every_listed_product_is_carried_or_no_namespaces_would_do(path):
    line = load_product_line(path.parents[1])
    product = resolve(line, load_selection_file(path)).product
    outcome = carried_exactly_or_none_is([product], zenoh.generate(product))
    # every listed product of the shipped lines and of the offshore line is carried
    # (or nothing of it crosses: the data-acquisition line, orchard's on-board products)
    assert outcome in ("carried", "quiet")


def test_the_vessels_defects_go_ashore_under_the_crawlers_namespace():
    """The crawler's ultrasonic defects and the team's detector both publish
    /blade/defects on the vessel (the log takes them there), and both reach the farm's
    reports onshore. Under no namespace, the detector's flow would leave the vessel
    through a second bridge, which would forward the crawler's defects again: the
    detector's defects go under /crawler_1 instead, through the one bridge that takes
    the crawler's in (a bridge never sends back its own), and the reports onshore get
    each publisher's defects once."""
    line = load_product_line(OFFSHORE)
    selection = load_selection_file(OFFSHORE / "products" / "vessel_wall_defects.yaml")
    product = resolve(line, selection).product
    files = zenoh.generate(product)
    found = {
        (b.place, b.namespace): {k: sorted(v) for k, v in b.lists if v} for b in written(files)
    }
    assert found == {
        ("crawler_1", "/crawler_1"): {
            "publishers": ["/blade/defects", "/blade/frames", "/blade/wall_thickness"]
        },
        ("drone_1", "/drone_1"): {"publishers": ["/blade/frames"]},
        ("VesselEdge_vessel", "/crawler_1"): {
            "publishers": ["/blade/defects"],
            "subscribers": ["/blade/defects", "/blade/frames"],
        },
        ("VesselEdge_vessel", "/drone_1"): {"subscribers": ["/blade/frames"]},
        ("Onshore_crawler_1", "/crawler_1"): {"subscribers": ["/blade/wall_thickness"]},
        ("Onshore_public", "/crawler_1"): {"subscribers": ["/blade/defects"]},
    }
    # the pods run these bridges: two sidecars on the vessel, one onshore
    manifests = kubernetes.generate(product)
    vessel = list(yaml.safe_load_all(manifests["kubernetes/vesseledge-vessel.yaml"]))
    pod = next(d for d in vessel if d["kind"] == "Deployment")["spec"]["template"]["spec"]
    assert [c["name"] for c in pod["containers"][1:]] == ["zenoh-bridge", "zenoh-bridge-2"]
    onshore = manifests["kubernetes/onshore-public.yaml"].decode()
    assert '"namespace": "/crawler_1"' in onshore


def test_products_the_usual_namespaces_carried_keep_them():
    """The paper's product: every bridge talking with robot_1 under /robot_1, as before
    the search existed (the bundle digests of the shipped lines are unchanged)."""
    line = load_product_line(ROOT / "product_lines" / "mapping3d")
    product = resolve(line, selection_from_list("YouBot,Stereo,AdditionalPC,Room")).product
    spaces = {b.namespace for b in written(zenoh.generate(product))}
    assert spaces == {"/robot_1"}


FLEETS = [OFFSHORE / "fleets" / "two_teams.yaml", ROOT / "tests/models/windfarm/fleets/teams.yaml"]


@pytest.mark.parametrize("path", FLEETS, ids=lambda p: p.parents[1].name)
def test_the_test_lines_fleets_of_two_teams_are_carried(tmp_path, path):
    """In the offshore fleet each team's vessel feeds its own repair planner onshore:
    under no namespace the north vessel's defects would reach the south team's planner,
    so one team's flow goes under its crawler's namespace."""
    out = tmp_path / "fleet"
    result = run("fleet", "resolve", path, "-o", out)
    assert result.exit_code == 0, result.output
    assert json.loads((out / "fleet.json").read_text())["skipped"] == {}
    files = {f"zenoh/{p.name}": p.read_bytes() for p in (out / "zenoh").iterdir()}
    products = [entry.product for entry in deploy(check_fleet(load_fleet(path))).robots]
    assert carried_exactly_or_none_is(products, files) == "carried"
    if path.parents[1] == OFFSHORE:
        onshore = ("Onshore_north", "Onshore_south")
        planners = {b.namespace for b in written(files) if b.place in onshore}
        assert planners == {"", "/north_Crawler"}


# zenoh/ of the product of a .tsm file, as a digest (run in a process of its own)
DIGEST = """
import hashlib, sys
from spl.dsl.tsm import language as tsm
from spl.generators.zenoh import configurations as zenoh
from spl.resolver.architecture.product import ResolvedProduct
files = zenoh.generate(ResolvedProduct("p", tsm.parse_file(sys.argv[1]), ()))
print(hashlib.sha256(repr(sorted(files.items())).encode()).hexdigest())
"""


def test_the_same_product_gives_the_same_bytes_whatever_the_hash_seed(tmp_path):
    """The search meets names in sets, whose order follows Python's string hashes: runs
    with other seeds write the same ``zenoh/``, for a fleet of six teams, each its own
    group, where the search places every team's flows, and for a random product whose
    namespaces an earlier search chose differently under seeds 1 and 2."""
    teams = "".join(
        f"  team{i}: {{group: g{i}, features: [DetectionOnVessel, Reporting, "
        f"RepairPlanning, {'Thickness, WallDefects, LogOnVessel' if i < 3 else 'Marking'}]}}\n"
        for i in range(6)
    )
    fleet = tmp_path / "teams.yaml"
    fleet.write_text(f"fleet: teams\nproduct_line: {OFFSHORE}\nrobots:\n{teams}")
    product = ROOT / "tests" / "models" / "zenoh" / "hash_order.tsm"
    seen = []
    for seed in ("1", "2", "3"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        out = tmp_path / f"out{seed}"
        command = [sys.executable, "-m", "spl", "fleet", "resolve", str(fleet), "-o", str(out)]
        done = subprocess.run(command, env=env, cwd=tmp_path, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        digest = [sys.executable, "-c", DIGEST, str(product)]
        alone = subprocess.run(digest, env=env, cwd=tmp_path, capture_output=True, text=True)
        assert alone.returncode == 0, alone.stderr
        files = {p.name: p.read_bytes() for p in (out / "zenoh").iterdir()}
        seen.append((files, alone.stdout))
    assert seen[0] == seen[1] == seen[2]
    assert "VesselEdge_g0.json5" in seen[0][0]


ECHO_TSM = """system Echo

robot container Rover {
    endpoint robot_id "rover_1" url "wss://cloud.example.org:9000/" user "u" password env "P"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Lidar {
        implementation urg_node/urg_node
        publishes scan -> Scan
    }
}

robot container Arm {
    endpoint robot_id "arm_1" url "wss://cloud.example.org:9000/" user "u" password env "P"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Avoider {
        implementation arm/avoider
        subscribes scan <- Scan
    }
}

cloud container Cloud {
    topic In : sensor_msgs/LaserScan name "/scan"
    topic Out : sensor_msgs/LaserScan name "/scan"
    node Filter sharing public {
        implementation laser_filters/scan_to_scan_filter_chain
        subscribes raw <- In
        publishes filtered -> Out
    }
}

bridge Rover.Scan -> Cloud.In
bridge Cloud.Out -> Arm.Scan
"""


def test_a_product_no_namespaces_carry_is_refused_naming_the_flows(tmp_path):
    """The cloud's filter takes the rover's /scan in and publishes its own /scan for the
    arm, two topics of one name: whatever the namespaces, the rover's scans would reach
    the arm (through the cloud's bridges, or straight under one key), which the table
    does not deliver."""
    path = tmp_path / "echo.tsm"
    path.write_text(ECHO_TSM)
    product = ResolvedProduct("echo", tsm_language.parse_file(path), ())
    files = zenoh.generate(product)
    assert carried_exactly_or_none_is([product], files) == "refused"
    reason = files["zenoh/"].reason
    assert reason.startswith("Zenoh cannot carry this product: in Cloud_public, /scan comes in")
    assert "Arm.Avoider.scan would get the data of Rover.Lidar.scan" in reason
    # a search cut short says so, and still names the flows
    placement = Placement(product.system, [])
    found = routes([Wiring(product.flows, placement, [])], limit=1)
    assert found.problems[-1] == "no exact choice of bridge namespaces was found in 1 tries"
    assert "Rover.Lidar.scan" in found.problems[0]


@st.composite
def products_of_random_lines(draw):
    spec = draw(fleet_specs())
    selected = draw(st.sets(st.sampled_from(spec.features()))) if spec.elements else set()
    return spec, selected


@settings(max_examples=examples(80), deadline=None)
@given(products_of_random_lines())
def test_random_products_are_carried_exactly_or_no_namespaces_would_do(case):
    spec, selected = case
    with tempfile.TemporaryDirectory() as scratch:
        line = load_product_line(write_line(spec, Path(scratch) / "line"))
        selection = selection_from_list(",".join(["Root", *sorted(selected)]))
        check_random_product(resolve(line, selection).product)


def check_random_product(product) -> None:
    """zenoh/ carries the product exactly, or the brute force finds no choice that
    would (skipped, and counted, where the brute force would try too many)."""
    if affordable([product]):
        event(carried_exactly_or_none_is([product], zenoh.generate(product)))
        event(f"searched: {searched([product])}")


def affordable(products) -> bool:
    table, robots = crossings(products)
    if space(table, robots) > AFFORDABLE:
        event(f"too many choices for the brute force ({space(table, robots):.0e})")
        return False
    return True


# -- lines and fleets of the offshore shape --------------------------------------------------
@st.composite
def shared_flow_lines(
    draw, robots: int | None = None, modes: tuple[str, ...] = ("private", "protected", "public")
) -> LineSpec:
    """1-2 robots and two clouds with both topics /scan and /pose everywhere; cloud nodes
    of every sharing mode publish and subscribe them, serve and call; bridges join robots
    and clouds and the two clouds, in both directions, never bringing data back where
    it was (docs/resolution.md). Flows between shared instances, and shared instances
    both taking in and giving out one name, are common."""
    count = robots if robots is not None else draw(st.integers(1, 2))
    containers = {f"Robot{i}": "robot" for i in range(count)}
    containers |= {f"Cloud{i}": "cloud" for i in range(count, count + 2)}
    names = {"/scan": "Scan", "/pose": "Pose"}
    topics = [Topic(c, names[ros], ros) for c in containers for ros in names]
    nodes: list[Node] = []
    for container, kind in containers.items():
        for _ in range(draw(st.integers(1, 1 if kind == "robot" else 3))):
            node = Node(f"N{len(nodes)}", container, False)
            if kind == "cloud":
                node.sharing = draw(st.sampled_from(modes))
            # a publisher and a subscriber, then a server, a client or another topic
            more = st.sampled_from(["publishes", "subscribes", "calls", "provides"])
            kinds = ["publishes", "subscribes", *draw(st.lists(more, max_size=2))]
            for k, what in enumerate(kinds):
                if what == "provides" and kind == "robot":
                    continue
                if what in ("publishes", "subscribes"):
                    ros = draw(st.sampled_from(sorted(names)))
                    interface = Interface(what, f"{what[0]}{k}", ROS_TOPICS[ros], names[ros])
                else:
                    interface = Interface(what, f"{what[0]}{k}", SERVICE_TYPES[0])
                node.interfaces.append(interface)
            nodes.append(node)
    bridges: list = []
    graph = nx.DiGraph()
    for a in containers:
        for b in containers:
            if a == b or containers[a] == containers[b] == "robot":
                continue
            for name in names.values():
                if draw(st.booleans()):
                    graph.add_edge((a, name), (b, name))
                    if any(
                        other[0] == topic[0]
                        for topic in graph
                        for other in nx.descendants(graph, topic)
                    ):
                        graph.remove_edge((a, name), (b, name))
                    else:
                        bridges.append(((a, name), (b, name)))
    servers = [
        (n.container, n.name, i.name) for n in nodes for i in n.interfaces if i.kind == "provides"
    ]
    service_bridges = []
    for node in nodes:
        for client in (i for i in node.interfaces if i.kind == "calls"):
            elsewhere = [s for s in servers if s[0] != node.container]
            if elsewhere and draw(st.booleans()):
                server = draw(st.sampled_from(elsewhere))
                service_bridges.append(((node.container, node.name, client.name), server))
    return LineSpec(containers, topics, nodes, bridges, service_bridges, [])


@settings(max_examples=examples(60), deadline=None)
@given(shared_flow_lines())
def test_products_with_flows_between_shared_instances(spec):
    with tempfile.TemporaryDirectory() as scratch:
        line = load_product_line(write_line(spec, Path(scratch) / "line"))
        check_random_product(resolve(line, selection_from_list("Root")).product)


@settings(max_examples=examples(40), deadline=None)
@given(
    shared_flow_lines(robots=1, modes=("protected", "protected", "public", "private")),
    st.integers(2, 3),
)
def test_fleets_with_flows_between_shared_instances(spec, teams):
    """A fleet of the line's robot in two groups: each group's protected instances, the
    public ones and each robot's private ones, bridged over the whole fleet at once."""
    groups = ["north", "south", "north"][:teams]
    with tempfile.TemporaryDirectory() as scratch:
        write_line(spec, Path(scratch) / "line")
        entries = "".join(
            f"  team{i}: {{group: {g}, features: [Root]}}\n" for i, g in enumerate(groups)
        )
        path = Path(scratch) / "fleet.yaml"
        path.write_text(f"fleet: random\nproduct_line: line\nrobots:\n{entries}")
        products = [entry.product for entry in deploy(check_fleet(load_fleet(path))).robots]
        if not affordable(products):
            return
        wiring = transport(*products)
        files = (
            zenoh.folder("fleet random", wiring)
            if wiring.carried
            else {"zenoh/": Skipped(wiring.reason or "")}
        )
        event(carried_exactly_or_none_is(products, files))
        event(f"searched: {searched(products)}")
