"""``spl smoke`` of actions with the real ROS 1 and the real actionlib (Debian's
``python3-actionlib``), on the shipped navigation line (docs/smoke.md, "Actions").

Across a bridge, the mission's goals on the rover reach the planner in the cloud and
its feedback and result come back, through both endpoints; after the planner migrates
onto the rover, the mission's goals meet it there without any endpoint, and the cloud
explorer's, rewired by the migration, cross down to it. Where the Python that runs the
stand-ins has no actionlib, the rest of the graph is still rehearsed and the actions
are named in one warning.
"""

from __future__ import annotations

from pathlib import Path

from spl.smoke.processes import RosInstall, find_ros
from spl.smoke.rehearsal import run_smoke

from support.smoke_runs import ROOT, rows_by_interface, smoke_json, write_product

NAVIGATION = ROOT / "product_lines" / "navigation"
PLANNER = "Planner.move_base"


def product(name: str, folder: Path) -> Path:
    return write_product(NAVIGATION, NAVIGATION / "products" / f"{name}.yaml", folder / "bundle")


def test_goals_cross_the_bridge_and_feedback_and_results_come_back(tmp_path) -> None:
    status, report = smoke_json(product("cloud_static_map", tmp_path))
    assert status == 0 and report["passed"], report["failures"]
    rows = rows_by_interface(report)
    # the client on the rover: every result answers one of its own goals
    navigate = rows["Rover.Mission.navigate"]
    assert navigate["topic"] == "/move_base"
    assert navigate["seen"].startswith(f"result from NavCloud.{PLANNER} (")
    assert f"feedback from NavCloud.{PLANNER} (" in navigate["seen"]
    # the goals passed the rover's stand-in for the planner, then the cloud's relay ...
    assert rows["Rover.endpoint.asrv_Planner_move_base"]["ok"]
    relay = rows["NavCloud.endpoint.acli_Planner_move_base"]
    assert relay["seen"].startswith(f"result from {PLANNER} (")
    # ... and were answered by the planner itself
    served = rows[f"NavCloud.{PLANNER}"]["seen"]
    assert served.startswith("provides action (") and "(0 goals" not in served


def test_after_the_migration_goals_meet_on_the_rover_and_cross_down_to_it(tmp_path) -> None:
    status, report = smoke_json(product("onboard_explore", tmp_path))
    assert status == 0 and report["passed"], report["failures"]
    rows = rows_by_interface(report)
    # the mission's goals meet the migrated planner on the rover, no endpoint between
    navigate = rows["Rover.Mission.navigate"]
    assert navigate["expected"] == f"result and feedback from {PLANNER}"
    assert navigate["seen"].startswith(f"result from {PLANNER} (")
    # the cloud explorer's client, rewired by the migration, reaches it through the
    # cloud's stand-in and the rover's relay, and is answered from the rover
    explorer = rows["NavCloud.Explorer.navigate"]
    assert explorer["seen"].startswith(f"result from Rover.{PLANNER} (")
    assert f"feedback from Rover.{PLANNER} (" in explorer["seen"]
    assert rows["NavCloud.endpoint.asrv_Planner_move_base"]["ok"]
    assert rows["Rover.endpoint.acli_Planner_move_base"]["seen"].startswith(
        f"result from {PLANNER} ("
    )


HIDE_ACTIONLIB = """
import runpy, sys

class Missing:
    # a Python as Debian's is without python3-actionlib
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] == "actionlib":
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None

sys.meta_path.insert(0, Missing())
arguments = [a for a in sys.argv[1:] if a != "-I"]
if arguments[0] == "-c":
    sys.argv = ["-c", *arguments[2:]]
    exec(compile(arguments[1], "<string>", "exec"), {"__name__": "__main__"})
else:
    sys.argv = arguments
    runpy.run_path(arguments[0], run_name="__main__")
"""


def test_without_actionlib_the_rest_is_rehearsed_and_the_actions_named(tmp_path) -> None:
    ros = find_ros()
    (tmp_path / "hide.py").write_text(HIDE_ACTIONLIB, encoding="utf-8")
    python = tmp_path / "python3"
    python.write_text(f'#!/bin/sh\nexec {ros.python} -I {tmp_path / "hide.py"} "$@"\n')
    python.chmod(0o755)
    bundle = product("onboard_slam", tmp_path)
    result = run_smoke(bundle, timeout=90, ros=RosInstall(ros.roscore, ros.roslaunch, str(python)))
    assert result.passed, result.failures()
    assert result.actions_skipped == (
        "actions not rehearsed, no goal, feedback or result of action client "
        "Rover.Mission.navigate, action server Rover.Planner.move_base is checked: "
        f"actionlib not importable by {python}: apt-get install python3-actionlib"
    )
    rows = {(r.node, r.interface) for rs in result.rows.values() for r in rs}
    assert ("Planner", "scan") in rows and ("Mission", "navigate") not in rows
