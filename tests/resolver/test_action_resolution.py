"""An action resolves like a call (docs/semantics.md, "Actions"): the flow table holds
one action flow from the client to the server, across the bridge or, after the planner
migrates, inside the robot; migration rewires the client; a product that prunes the
server leaves the client unfed (SPL046, with a witness product); and ``spl explain``
names what bound or rebound the client."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from spl.cli import main
from spl.metamodels.interface_kinds import ACTION
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

NAVIGATION = Path(__file__).parents[1] / "models" / "navigation"


def product(*features: str):
    line = load_product_line(NAVIGATION)
    return resolve(line, selection_from_list(",".join(["Navigation", *features]))).product


def action_flows(features: tuple[str, ...]) -> list[tuple[str, str, list[str]]]:
    return [
        (
            f"{f.source_container.name}.{f.source.eContainer().name}.{f.source.name}",
            f"{f.target_container.name}.{f.target.eContainer().name}.{f.target.name}",
            [c.name for c in f.hops()],
        )
        for f in product(*features).flows.flows
        if f.kind is ACTION
    ]


def test_the_cloud_planner_takes_goals_across_the_bridge() -> None:
    assert action_flows(("Planning",)) == [
        ("Robot.Behaviour.navigate", "Cloud.Planner.move_base", ["Robot", "Cloud"])
    ]


def test_migrating_the_planner_rewires_the_client_to_it_on_the_robot() -> None:
    system = product("Planning", "OnBoardPlanning").system
    robot = next(c for c in system.containers if c.name == "Robot")
    client = next(i for n in robot.nodes if n.name == "Behaviour" for i in n.interfaces)
    assert client.server.eContainer().name == "Planner"
    assert client.server.eContainer().eContainer() is robot
    assert action_flows(("Planning", "OnBoardPlanning")) == [
        ("Robot.Behaviour.navigate", "Robot.Planner.move_base", ["Robot"])
    ]


def test_without_the_planner_the_client_sends_goals_to_nothing() -> None:
    assert action_flows(()) == []


def test_the_line_check_warns_of_the_unserved_client_with_a_witness() -> None:
    result = CliRunner().invoke(main, ["check", str(NAVIGATION)])
    assert result.exit_code == 0, result.output
    warning = next(line for line in result.output.splitlines() if "[SPL046]" in line)
    assert warning == (
        f"{NAVIGATION / 'navigation.tsm'}:20:22: warning: action client Behaviour.navigate "
        "has no server in this product, in the product Navigation; its action server "
        "Planner.move_base is left out: optional node Planner is kept only by 'when "
        f"Planning selected' ({NAVIGATION / 'navigation.rm'}:5:1), 'when OnBoardPlanning "
        f"selected' ({NAVIGATION / 'navigation.rm'}:9:1) [SPL046]"
    )


def explain(features: str, element: str) -> list[str]:
    result = CliRunner().invoke(main, ["explain", str(NAVIGATION), "--features", features, element])
    assert result.exit_code == 0, result.output
    return result.output.splitlines()


def test_explain_names_what_bound_and_rebound_the_client() -> None:
    across = explain("Planning", "Behaviour.navigate")
    assert across[0] == "Behaviour.navigate: sends goals to Robot.endpoint.asrv_Planner_move_base"
    assert across[-1] == "  sends goals to Cloud.Planner.move_base through Robot -> Cloud"
    moved = explain("Planning,OnBoardPlanning", "Behaviour.navigate")
    assert moved[0] == "Behaviour.navigate: sends goals to Planner.move_base"
    assert "as Planner is migrated to Robot by 'when OnBoardPlanning selected'" in moved[1]
    assert moved[2].startswith(
        "  sends goals to Robot.Planner.move_base in Robot; Planner: migrated"
    )
    unserved = explain("Navigation", "Behaviour.navigate")
    assert unserved[-1] == "  sends goals to no action server of this product (SPL046)"
    server = explain("Planning", "Planner.move_base")
    assert server[0] == "Planner.move_base: serves action /move_base (move_base_msgs/MoveBase)"
    assert server[-1].startswith(
        "  takes goals from Robot.Behaviour.navigate through Robot -> Cloud"
    )


def test_an_rm_bridge_carries_the_action_like_the_tsm_bridge(tmp_path: Path) -> None:
    """The same line with the bridge written in the .rm (`connect bridge`) instead of
    the .tsm: the product's action flow crosses the same way."""
    tsm = (NAVIGATION / "navigation.tsm").read_text(encoding="utf-8")
    tsm = tsm.replace("bridge Robot.Behaviour.navigate -> Cloud.Planner.move_base\n", "")
    (tmp_path / "navigation.tsm").write_text(tsm, encoding="utf-8")
    (tmp_path / "navigation.fm").write_text(
        (NAVIGATION / "navigation.fm").read_text(encoding="utf-8"), encoding="utf-8"
    )
    (tmp_path / "navigation.rm").write_text(
        'resolution model Navigation\ntsm "navigation.tsm"\nfm  "navigation.fm"\n'
        "when Planning selected {\n    require Planner\n"
        "    connect bridge Behaviour.navigate -> Planner.move_base\n}\n",
        encoding="utf-8",
    )
    line = load_product_line(tmp_path)
    flows = resolve(line, selection_from_list("Navigation,Planning")).product.flows.flows
    assert [
        (f.source.name, f.target.name, [c.name for c in f.hops()])
        for f in flows
        if f.kind is ACTION
    ] == [("navigate", "move_base", ["Robot", "Cloud"])]
