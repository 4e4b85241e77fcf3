"""``implementation NODE = pkg/exe args "..."`` in the .rm (docs/rm.md): the arguments a
node runs with under that implementation reach every launch file, a conflicting one is
SPL012 like any other implementation, a statement without ``args`` keeps the node's own,
and hostile arguments are refused where they are written."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from click.testing import CliRunner

from spl.cli import main

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
STATEMENT = "    implementation RobotController = youbot_control/robot_controller\n"
YOUBOT = "YouBot,Stereo,AdditionalPC,Room"


def line_with(tmp_path: Path, replacement: str, extra: str = "") -> Path:
    folder = tmp_path / "line"
    shutil.copytree(MAPPING, folder)
    rm = folder / "mapping.rm"
    text = rm.read_text(encoding="utf-8")
    assert text.count(STATEMENT) == 1
    rm.write_text(text.replace(STATEMENT, replacement) + extra, encoding="utf-8")
    return folder


def spl(*args: object):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_args_reach_the_ros1_and_ros2_launch_files(tmp_path: Path) -> None:
    args = "--rate 20 _frame:=base_link"
    folder = line_with(tmp_path, STATEMENT.rstrip("\n") + f' args "{args}"\n')
    out = tmp_path / "bundle"
    result = spl("resolve", folder, "--features", YOUBOT, "-o", out)
    assert result.exit_code == 0, result.output
    ros1 = (out / "ros1" / "Robot.launch").read_text(encoding="utf-8")
    ros2 = (out / "ros2" / "Robot.launch.xml").read_text(encoding="utf-8")
    assert f'type="robot_controller" name="RobotController" args="{args}"' in ros1
    assert f'exec="robot_controller" name="RobotController" args="{args}"' in ros2
    explained = spl("explain", folder, "--features", YOUBOT, "RobotController").output
    assert "implementation: youbot_control/robot_controller, set by" in explained
    assert f"args: \"{args}\", set by 'when YouBot selected'" in explained


def test_without_args_the_node_keeps_its_own(tmp_path: Path) -> None:
    plain = tmp_path / "plain"
    assert spl("resolve", MAPPING, "--features", YOUBOT, "-o", plain).exit_code == 0
    folder = line_with(tmp_path, STATEMENT)  # unchanged statement: same bundle
    again = tmp_path / "again"
    assert spl("resolve", folder, "--features", YOUBOT, "-o", again).exit_code == 0
    for name in ("ros1/Robot.launch", "ros2/Robot.launch.xml"):
        assert (plain / name).read_bytes() == (again / name).read_bytes()


OTHER_ARGS = (  # YouBot with Stereo: both set RobotController's implementation
    "\nwhen Stereo selected {\n"
    '    implementation RobotController = youbot_control/robot_controller args "--rate 5"\n'
    "}\n"
)


def test_two_elements_giving_other_args_conflict(tmp_path: Path) -> None:
    folder = line_with(tmp_path, STATEMENT.rstrip("\n") + ' args "--rate 20"\n', OTHER_ARGS)
    conflicts = [line for line in spl("check", folder).output.splitlines() if "SPL012" in line]
    about_args = [line for line in conflicts if "gives args" in line]
    assert about_args, conflicts
    assert '"--rate 5" to RobotController' in about_args[0]
    assert 'gives "--rate 20"' in about_args[0]


def test_a_statement_without_args_decides_none(tmp_path: Path) -> None:
    """YouBot names the implementation only, Stereo the same one with arguments: no
    conflict about the arguments, and the product with both runs with Stereo's."""
    folder = line_with(tmp_path, STATEMENT, OTHER_ARGS)
    conflicts = [line for line in spl("check", folder).output.splitlines() if "SPL012" in line]
    assert not [line for line in conflicts if "YouBot" in line], conflicts
    out = tmp_path / "bundle"
    assert spl("resolve", folder, "--features", YOUBOT, "-o", out).exit_code == 0
    ros1 = (out / "ros1" / "Robot.launch").read_text(encoding="utf-8")
    assert 'name="RobotController" args="--rate 5"' in ros1


def test_hostile_args_are_refused_where_written(tmp_path: Path) -> None:
    folder = line_with(tmp_path, STATEMENT.rstrip("\n") + ' args "x; rm -rf /"\n')
    out = tmp_path / "bundle"
    result = spl("resolve", folder, "--features", YOUBOT, "-o", out)
    assert result.exit_code == 1 and "Traceback" not in result.output
    assert re.search(r"mapping\.rm:\d+:\d+: error: args may only contain", result.output)
    assert not out.exists()
