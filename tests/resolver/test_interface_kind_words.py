"""What ``spl explain`` and ``spl resolve`` say about an interface is its kind's words
(spl.metamodels.interface_kinds): how each kind stands in the product, what a flow is at
each of its ends, how an input no flow feeds is reported, external or not. One small
line holds every kind bound, unbound, fed and unfed, so a kind whose words drift, or a
question asked of the wrong kind, shows here."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from spl.cli import main

YARD_TSM = """system Yard
robot container Mower {
    endpoint robot_id "mower_1" url "wss://x.example.org:9000/" user "u" password env "P"
    topic Grass : std_msgs/String name "/grass"
    topic Rain : std_msgs/String name "/rain"
    node Cutter {
        implementation yard/cutter
        publishes height -> Grass
        publishes idle : std_msgs/String
        subscribes rain <- Rain
        subscribes loose : std_msgs/String
        calls route : nav_msgs/GetPlan
        calls spare : nav_msgs/GetPlan
        calls weather : nav_msgs/GetPlan external "the farm's own weather station"
    }
}
cloud container Base {
    topic Grass : std_msgs/String name "/grass"
    node Planner {
        implementation yard/planner
        subscribes grass <- Grass
        provides plan : nav_msgs/GetPlan name "/plan"
    }
}
bridge Mower.Grass -> Base.Grass
bridge Mower.Cutter.route -> Base.Planner.plan
"""
YARD_FM = "feature model Yard\nroot Yard { optional Extra }\n"
YARD_RM = 'resolution model Yard\ntsm "y.tsm"\nfm "y.fm"\n'


def yard(tmp_path: Path) -> Path:
    folder = tmp_path / "yard"
    folder.mkdir()
    for name, text in (("y.tsm", YARD_TSM), ("y.fm", YARD_FM), ("y.rm", YARD_RM)):
        (folder / name).write_text(text, encoding="utf-8")
    return folder


def explain(folder: Path, element: str) -> list[str]:
    result = CliRunner().invoke(main, ["explain", str(folder), "--features", "Yard", element])
    assert result.exit_code == 0, result.output
    # the first line and the flow lines: the trace's "as the template writes it" between
    lines = result.output.splitlines()
    return [lines[0], *(line for line in lines[1:] if "as the template writes it" not in line)]


def test_each_kind_stands_in_the_product_in_its_own_words(tmp_path):
    folder = yard(tmp_path)
    assert explain(folder, "Cutter.height") == [
        "Cutter.height: publishes to topic Mower.Grass",
        "  delivers to Base.Planner.grass through Mower -> Base",
    ]
    assert explain(folder, "Planner.grass") == [
        "Planner.grass: subscribes to topic Base.Grass",
        "  fed by Mower.Cutter.height through Mower -> Base",
    ]
    assert explain(folder, "Planner.plan") == [
        "Planner.plan: serves /plan (nav_msgs/GetPlan)",
        "  called by Mower.Cutter.route through Mower -> Base",
    ]
    assert explain(folder, "Cutter.route") == [
        "Cutter.route: calls Mower.endpoint.srv_Planner_plan",
        "  answered by Base.Planner.plan through Mower -> Base",
    ]


def test_an_unbound_interface_says_so_and_only_an_input_is_unfed(tmp_path):
    folder = yard(tmp_path)
    # an output bound to nothing waits for nothing; a subscriber bound to no topic
    # neither; a client bound to no server goes unanswered
    assert explain(folder, "Cutter.idle") == [
        "Cutter.idle: publishes nothing: not connected in this product"
    ]
    assert explain(folder, "Cutter.loose") == [
        "Cutter.loose: subscribes nothing: not connected in this product"
    ]
    assert explain(folder, "Cutter.spare") == [
        "Cutter.spare: calls nothing: not connected in this product",
        "  answered by no server of this product (SPL046)",
    ]
    assert explain(folder, "Cutter.rain") == [
        "Cutter.rain: subscribes to topic Mower.Rain",
        "  fed by no flow of this product (SPL045)",
    ]
    # fed from outside: said, with no warning code
    assert explain(folder, "Cutter.weather") == [
        "Cutter.weather: calls nothing: not connected in this product",
        "  answered by no server of this product",
        "  fed from outside the architecture: the farm's own weather station",
    ]


def test_resolve_warns_of_each_unfed_input_in_its_kinds_words(tmp_path):
    folder = yard(tmp_path)
    result = CliRunner().invoke(
        main, ["resolve", str(folder), "--features", "Yard", "-o", str(tmp_path / "out")]
    )
    assert result.exit_code == 0, result.output
    tsm = folder / "y.tsm"
    warnings = [line for line in result.output.splitlines() if "[SPL04" in line]
    assert warnings == [
        f"{tsm}:10:20: warning: Cutter.rain subscribes Mower.Rain, which no node of the "
        "product publishes [SPL045]",
        f"{tsm}:13:15: warning: service client Cutter.spare has no server in this product [SPL046]",
    ]
