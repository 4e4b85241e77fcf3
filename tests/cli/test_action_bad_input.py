"""Bad actions through the command line (docs/tsm.md, "Actions"): each mistake a user can
make with an action in the navigation test line is, for `spl check` of the line and for
`spl resolve` of a product of it, one located error naming what is wrong (both ends where
a binding has two, each with where it is declared), exit 1, no traceback, and no bundle
written."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from support.cli_outcome import assert_clean, run

NAVIGATION = Path(__file__).parents[1] / "models" / "navigation"
CLIENT = "calls action navigate : move_base_msgs/MoveBase"
SERVER = 'provides action move_base : move_base_msgs/MoveBase name "/move_base"'
BRIDGE = "bridge Robot.Behaviour.navigate -> Cloud.Planner.move_base"
MIGRATE = "    migrate Planner to Robot\n"

# (what the case is, edits of the .tsm and of the .rm as (old, new) pairs, the error's
# place in its file and its message; {tsm} stands for the .tsm's path)
CASES = [
    (
        "an action type that is not package/Action",
        [(CLIENT, "calls action navigate : MoveBase")],
        [],
        ("navigation.tsm", 20, 33),
        "syntax error: expected a type package/Type, found 'MoveBase'",
    ),
    (
        "an action type that is a message actionlib generates",
        [(SERVER, SERVER.replace("MoveBase name", "MoveBaseAction name"))],
        [],
        ("navigation.tsm", 37, 37),
        "action server move_base: move_base_msgs/MoveBaseAction is the Action message "
        "generated from move_base_msgs/MoveBase; write the action's own type, "
        "move_base_msgs/MoveBase",
    ),
    (
        "a client bound to a service server",
        [
            (CLIENT, "calls action navigate -> Base.stop"),
            ("<- Cmd\n", "<- Cmd\n        provides stop : std_srvs/Empty\n"),
            (BRIDGE, ""),
        ],
        [],
        ("navigation.tsm", 20, 39),
        "kind mismatch: Robot.Behaviour.navigate ({tsm}:20:22) is an action client, "
        "Robot.Base.stop ({tsm}:26:18) is a service server, not an action server",
    ),
    (
        "a client bound to a topic's subscriber",
        [(CLIENT, "calls action navigate -> Base.cmd"), (BRIDGE, "")],
        [],
        ("navigation.tsm", 20, 39),
        "kind mismatch: Robot.Behaviour.navigate ({tsm}:20:22) is an action client, "
        "Robot.Base.cmd ({tsm}:25:20) is a topic subscriber, not an action server",
    ),
    (
        "client and server of different action types",
        [(SERVER, SERVER.replace("move_base_msgs/MoveBase", "nav2_msgs/NavigateToPose"))],
        [],
        ("navigation.tsm", 43, 50),
        "type mismatch: Robot.Behaviour.navigate ({tsm}:20:22) is move_base_msgs/MoveBase, "
        "Cloud.Planner.move_base ({tsm}:37:25) is nav2_msgs/NavigateToPose",
    ),
    (
        "a bridge from the server to its client",
        [(BRIDGE, "bridge Cloud.Planner.move_base -> Robot.Behaviour.navigate")],
        [],
        ("navigation.tsm", 43, 22),
        "action bridged the wrong way: Cloud.Planner.move_base ({tsm}:37:25) is an action "
        "server and Robot.Behaviour.navigate ({tsm}:20:22) is an action client; calls run from "
        "the client to its server: write 'bridge Robot.Behaviour.navigate -> "
        "Cloud.Planner.move_base'",
    ),
    (
        "an .rm connect from the server to its client",
        [],
        [(MIGRATE, MIGRATE + "    connect Planner.move_base to server Behaviour.navigate\n")],
        ("navigation.rm", 11, 5),
        "action connected the wrong way: Cloud.Planner.move_base ({tsm}:37:25) is an action "
        "server and Robot.Behaviour.navigate ({tsm}:20:22) is an action client; calls run from "
        "the client to its server: write 'connect Robot.Behaviour.navigate to server "
        "Cloud.Planner.move_base'",
    ),
    (
        "an .rm connect bridge from the server to its client",
        [],
        [
            (
                MIGRATE,
                "    connect bridge Cloud.Planner.move_base -> Robot.Behaviour.navigate\n",
            )
        ],
        ("navigation.rm", 10, 5),
        "action bridged the wrong way: Cloud.Planner.move_base ({tsm}:37:25) is an action "
        "server and Robot.Behaviour.navigate ({tsm}:20:22) is an action client; calls run from "
        "the client to its server: write 'connect bridge Robot.Behaviour.navigate -> "
        "Cloud.Planner.move_base'",
    ),
    (
        "an .rm connect joining an action client to a service",
        [(SERVER, SERVER + "\n        provides clear : std_srvs/Empty")],
        [(MIGRATE, MIGRATE + "    connect Behaviour.navigate to server Planner.clear\n")],
        ("navigation.rm", 11, 5),
        "kind mismatch: Robot.Behaviour.navigate ({tsm}:20:22) is an action client, "
        "Cloud.Planner.clear ({tsm}:38:18) is a service server, not an action server",
    ),
]


def edited_line(tmp_path: Path, tsm_edits: list, rm_edits: list) -> Path:
    """A copy of the navigation line with the edits made (each must apply once)."""
    line = tmp_path / "navigation"
    shutil.copytree(NAVIGATION, line)
    for name, edits in (("navigation.tsm", tsm_edits), ("navigation.rm", rm_edits)):
        path = line / name
        text = path.read_text(encoding="utf-8")
        for old, new in edits:
            assert text.count(old) == 1, old
            text = text.replace(old, new)
        path.write_text(text, encoding="utf-8")
    return line


@pytest.mark.parametrize(
    ("tsm_edits", "rm_edits", "place", "message"),
    [case[1:] for case in CASES],
    ids=[case[0] for case in CASES],
)
def test_a_bad_action_is_one_located_error_for_check_and_resolve(
    tmp_path: Path, tsm_edits: list, rm_edits: list, place: tuple, message: str
) -> None:
    line = edited_line(tmp_path, tsm_edits, rm_edits)
    file, row, col = place
    expected = f"{line / file}:{row}:{col}: error: " + message.format(tsm=line / "navigation.tsm")
    checked = run("check", line)
    assert_clean(checked, f"spl check {line}")
    assert checked.exit_code == 1
    assert checked.stderr.splitlines() == [expected]
    out = tmp_path / "out"
    out.mkdir()
    resolved = run("resolve", line, "--features", "Planning,OnBoardPlanning", "-o", out / "b")
    assert_clean(resolved, f"spl resolve {line}", out_parent=out)
    assert resolved.exit_code == 1
    assert resolved.stderr.splitlines() == [expected]
    assert not any(out.iterdir())
