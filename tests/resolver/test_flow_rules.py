"""The rules of docs/semantics.md "Flows" (F1-F6), one test or more each, on small lines
written here: what the flow table holds, what a robot relays, how private instances
split flows between robots (SPL050, from spl resolve and spl check), data reaching a
subscriber twice (SPL051), and what Rapyuta and the smoke plan make of it."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from click.testing import CliRunner

from spl.cli import main
from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.writer import build_bundle, write_bundle
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list
from spl.smoke.planning import load_plan

ROOT = Path(__file__).resolve().parents[2]
ENDPOINT = 'endpoint robot_id "{id}" url "wss://x.example.org:9000/" user "u" password env "P"'


def robot(name: str, body: str) -> str:
    return f"robot container {name} {{\n    {ENDPOINT.format(id=name.lower())}\n{body}}}\n"


def write(directory: Path, tsm: str, rm: str = "", features: str = "") -> Path:
    directory.mkdir()
    (directory / "l.tsm").write_text(f"system L\n{tsm}", encoding="utf-8")
    (directory / "l.fm").write_text(f"feature model L\nroot L {{ {features} }}\n")
    (directory / "l.rm").write_text(f'resolution model L\ntsm "l.tsm"\nfm "l.fm"\n{rm}')
    return directory


def product(directory: Path, features: str = "L"):
    return resolve(load_product_line(directory), selection_from_list(features)).product


def codes(product_, code: str) -> list[str]:
    return [d.message for d in product_.warnings if d.code == code]


def flows(product_) -> set[tuple[str, str, str]]:
    return {
        (str(f.kind), f"{f.source.eContainer().name}.{f.source.name}", f.target.eContainer().name)
        for f in product_.flows
    }


# F1, F2: fan-out, fan-in and services of several containers are rows of the table ----------
FAN = (
    robot("R", '    topic T : std_msgs/String name "/t"\n    node P { implementation d/p '
          "publishes out -> T }\n")
    + 'cloud container A {\n    topic T : std_msgs/String name "/t"\n'
    "    node SA { implementation d/sa subscribes inp <- T publishes back -> T }\n}\n"
    + 'cloud container B {\n    topic T : std_msgs/String name "/t"\n'
    "    node SB { implementation d/sb subscribes inp <- T }\n}\n"
    "bridge R.T -> A.T\nbridge R.T -> B.T\n"
)  # fmt: skip


def test_fan_out_is_one_row_per_subscriber_and_each_bridge_carries_its_own(tmp_path):
    fan = product(write(tmp_path / "fan", FAN))
    assert flows(fan) == {
        ("topic", "P.out", "SA"),
        ("topic", "P.out", "SB"),
        ("topic", "SA.back", "SA"),  # inside A: no bridge
    }
    routes = {f.target.eContainer().name: [c.target.eContainer().eContainer().name
                                           for c in f.route] for f in fan.flows}  # fmt: skip
    assert routes == {"SA": [], "SB": ["B"]} or routes["SB"] == ["B"]
    # the smoke plan: one relay per connection of R's endpoint subscriber, each passing P's
    bundle = tmp_path / "bundle"
    write_bundle(build_bundle(fan, BundleOptions(render_diagrams=False)).files, bundle)
    plan = {i.id: i for i in load_plan(bundle).interfaces()}
    relays = plan["R.endpoint.sub_T"].relays
    assert sorted((r.container, r.passes) for r in relays) == [
        ("A", ("R.P.out|",)),
        ("B", ("R.P.out|",)),
    ]
    assert plan["A.SA.inp"].sources == ("A.SA.back", "R.P.out")
    assert plan["B.SB.inp"].sources == ("R.P.out",)


def test_a_server_called_from_two_containers_has_a_row_per_client(tmp_path):
    tsm = (
        robot("R1", "    node C1 { implementation d/c calls get : nav_msgs/GetMap }\n")
        + robot("R2", "    node C2 { implementation d/c calls get : nav_msgs/GetMap }\n")
        + "cloud container M {\n    node Map sharing public { implementation d/m "
        'provides get : nav_msgs/GetMap name "/map" }\n}\n'
        "bridge R1.C1.get -> M.Map.get\nbridge R2.C2.get -> M.Map.get\n"
    )
    served = product(write(tmp_path / "svc", tsm))
    assert flows(served) == {("service", "C1.get", "Map"), ("service", "C2.get", "Map")}
    assert codes(served, "SPL046") == []


# F3: a robot passes on only its own data ------------------------------------------------
def test_data_relayed_through_another_robot_is_cut_and_said_why(tmp_path):
    tsm = (
        'cloud container C {\n    topic T : std_msgs/String name "/t"\n'
        "    node Pub sharing public { implementation d/p publishes out -> T }\n}\n"
        + robot("R", '    topic T : std_msgs/String name "/t"\n'
                "    node Local { implementation d/l subscribes inp <- T }\n")
        + 'cloud container D {\n    topic T : std_msgs/String name "/t"\n'
        "    node Sub sharing public { implementation d/s subscribes inp <- T }\n}\n"
        "bridge C.T -> R.T\nbridge R.T -> D.T\n"
    )  # fmt: skip
    cut = product(write(tmp_path / "relay", tsm))
    assert ("topic", "Pub.out", "Local") in flows(cut)
    assert ("topic", "Pub.out", "Sub") not in flows(cut)
    (warning,) = codes(cut, "SPL045")
    assert warning == (
        "Sub.inp subscribes D.T, which only Pub.out publishes, through robot container R; "
        "a robot passes on no data but its own"
    )


# F4: private instances and flows between robots -----------------------------------------
CROSS = (
    robot("R1", '    topic In : std_msgs/String name "/in"\n'
          "    node P { implementation d/p publishes out -> In }\n")
    + robot("R2", '    topic Out : std_msgs/String name "/out"\n'
            "    node S { implementation d/s subscribes inp <- Out }\n")
    + 'cloud container C {\n    topic In : std_msgs/String name "/in"\n'
    '    topic Out : std_msgs/String name "/out"\n'
    "    node X { implementation d/x subscribes inp <- In publishes out -> Out }\n}\n"
    "bridge R1.In -> C.In\nbridge C.Out -> R2.Out\n"
)  # fmt: skip


def rapyuta_connections(product_) -> set[tuple[str, str]]:
    files = build_bundle(product_, BundleOptions(render_diagrams=False)).files
    return {
        (c["tagA"], c["tagB"])
        for path, data in files.items()
        if path.startswith("rapyuta/")
        for c in json.loads(data).get("connections", ())
    }


def test_a_flow_from_one_robot_through_a_private_node_to_another_is_warned(tmp_path):
    line = write(tmp_path / "cross", CROSS)
    cross = product(line)
    (warning,) = codes(cross, "SPL050")
    assert warning.startswith(
        "S.inp on robot container R2 is fed by X.out of its own instance of X, which is "
        "private as the .tsm gives it"
    )
    assert "the data X takes from robot container R1 (R1.P.out -> C.X.inp via R1.In -> C.In)" in (
        warning
    )
    # what the deployment does: r1 feeds its instance, and r2 gets none, as nothing of r2
    # would feed it (docs/deployment.md, "Private instances"); nothing crosses to r2
    assert rapyuta_connections(cross) == {("r1/sub_In", "C_r1/pub_In")}
    # spl check finds it from the template, with the product that shows it
    result = CliRunner().invoke(main, ["check", str(line)])
    assert result.exit_code == 0
    assert f"{line / 'l.tsm'}:10:" in result.output
    assert "[SPL050]" in result.output and ", in the product L [SPL050]" in result.output


def test_no_warning_when_the_node_is_shared_or_each_robot_feeds_its_own(tmp_path):
    shared = product(
        write(tmp_path / "shared", CROSS.replace("node X {", "node X sharing protected {"))
    )
    assert codes(shared, "SPL050") == []
    assert ("r1/sub_In", "C_C/pub_In") in rapyuta_connections(shared)
    assert ("C_C/sub_Out", "r2/pub_Out") in rapyuta_connections(shared)
    both = (
        CROSS.replace(
            "    node S { implementation d/s subscribes inp <- Out }\n",
            "    node S { implementation d/s subscribes inp <- Out }\n"
            '    topic In : std_msgs/String name "/in"\n'
            "    node Q { implementation d/q publishes out -> In }\n",
        )
        + "bridge R2.In -> C.In\n"
    )
    assert codes(product(write(tmp_path / "both", both)), "SPL050") == []


def test_a_chain_of_private_nodes_and_a_private_server_are_followed(tmp_path):
    chain = CROSS.replace(
        "node X { implementation d/x subscribes inp <- In publishes out -> Out }",
        '    topic Mid : std_msgs/String name "/mid"\n'
        "    node X { implementation d/x subscribes inp <- In publishes out -> Mid }\n"
        "    node Y { implementation d/y subscribes inp <- Mid publishes out -> Out }",
    )
    (warning,) = codes(product(write(tmp_path / "chain", chain)), "SPL050")
    assert warning.startswith(
        "S.inp on robot container R2 is fed by Y.out of its own instance of Y"
    )
    server = CROSS.replace(
        "publishes out -> Out }", 'provides ask : std_srvs/Trigger name "/ask" }'
    )
    server = server.replace(
        "node S { implementation d/s subscribes inp <- Out }",
        "node S { implementation d/s calls ask : std_srvs/Trigger }",
    ).replace("bridge C.Out -> R2.Out", "bridge R2.S.ask -> C.X.ask")
    (warning,) = codes(product(write(tmp_path / "server", server)), "SPL050")
    assert warning.startswith("S.ask on robot container R2 is fed by X.ask of its own instance")


def test_check_names_a_product_where_the_feature_makes_the_node_private(tmp_path):
    rm = "when Solo selected {\n    require X\n}\n"
    line = write(
        tmp_path / "feature",
        CROSS.replace("node X {", "node X sharing public {").replace(
            "  node X", "  optional node X"
        ),
        rm,
        "optional Solo { sharing private }",
    )
    result = CliRunner().invoke(main, ["check", str(line)])
    assert "in the product L, Solo [SPL050]" in result.output
    assert codes(product(line, "L"), "SPL050") == []  # X is not in the product without Solo
    (warning,) = codes(product(line, "L,Solo"), "SPL050")
    assert "which is private (feature model default of feature Solo)" in warning


# F5: data reaching a subscriber twice ---------------------------------------------------
TWICE = (
    robot("R", '    topic T : std_msgs/String name "/t"\n    node P { implementation d/p '
          "publishes out -> T }\n")
    + "".join(
        f'cloud container {c} {{\n    topic T : std_msgs/String name "/t"\n'
        f"    node S{c} sharing public {{ implementation d/s subscribes inp <- T{extra} }}\n}}\n"
        for c, extra in (("A", " publishes out -> T"), ("B", " publishes out -> T"), ("C", ""))
    )
    + "bridge R.T -> A.T\nbridge R.T -> B.T\nbridge A.T -> C.T\nbridge B.T -> C.T\n"
)  # fmt: skip


def test_data_reaching_a_subscriber_by_two_chains_of_bridges_is_warned_and_carried_once(tmp_path):
    twice = product(write(tmp_path / "twice", TWICE))
    (warning,) = codes(twice, "SPL051")
    assert warning.startswith("SC.inp gets the data of P.out along two chains of bridges or more")
    (row,) = [f for f in twice.flows if f.routes > 1]
    assert (row.source.name, row.target.eContainer().name) == ("out", "SC")
    bundle = build_bundle(twice, BundleOptions(render_diagrams=False))
    # Zenoh would deliver it twice through A's and B's bridges: not carried, and it says so
    assert bundle.skipped["zenoh/"].endswith("C.SC.inp would get the data of R.P.out a second time")
    folder = tmp_path / "bundle"
    write_bundle(bundle.files, folder)
    sc = {i.id: i for i in load_plan(folder).interfaces()}["C.SC.inp"]
    assert sc.sources == ("A.SA.out", "B.SB.out", "R.P.out")  # once each


def test_check_reports_a_listed_product_whose_sharing_choice_splits_a_flow(tmp_path):
    """The orchard's yield map made private by a listed product's choice: the harvester's
    planner would read its own instance, which the scout's images never reach (the
    shipped product made that choice until spl check could see it)."""
    orchard = tmp_path / "orchard"
    shutil.copytree(ROOT / "product_lines" / "orchard", orchard)
    (orchard / "products" / "private_yield.yaml").write_text(
        "product: private_yield\n"
        "features: [CloudDetection, OnboardPlanning, VacuumGripper, Scouting, YieldMapping]\n"
        "sharing: {YieldMapping: private}\n"
    )
    result = CliRunner().invoke(main, ["check", str(orchard)])
    assert result.exit_code == 0  # a warning
    (line,) = [text for text in result.output.splitlines() if "[SPL050]" in text]
    assert line.startswith(f"{orchard / 'orchard.tsm'}:97:20: warning: PathPlanner.yield_map on ")
    assert "which is private (product selection of feature YieldMapping)" in line
    assert line.endswith("in the listed product private_yield [SPL050]")
