"""ROS actions in the .tsm (docs/tsm.md, "Actions"): `provides action` and `calls
action` read by textX and the fast reader alike, bound like services (in a container,
across a bridge, by an .rm `connect`), printed back, and refused with a located reason
when the type is not the action's own or a client is bound to another kind's server."""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.rm import language as rm
from spl.dsl.tsm import language as tsm, reader as tsm_reader
from spl.dsl.tsm.printer import print_model
from spl.metamodels.interface_kinds import kind_of

from support.cli_outcome import assert_clean, run
from support.textx_trees import assert_reads_as_textx as reads_as_textx

NAVIGATION = Path(__file__).parents[1] / "models" / "navigation"


def assert_reads_as_textx(text: str, must_read: bool = False) -> None:
    reads_as_textx(tsm_reader.read, tsm._grammar(), text, must_read)


def interfaces(system) -> dict[str, object]:
    return {
        f"{c.name}.{n.name}.{i.name}": i
        for c in system.containers
        for n in c.nodes
        for i in n.interfaces
    }


def errors(text: str) -> list[str]:
    with pytest.raises(ModelError) as caught:
        tsm.parse_text(textwrap.dedent(text), "bad.tsm")
    return [str(d) for d in caught.value.diagnostics]


def test_the_navigation_line_reads_its_action_and_its_bridge() -> None:
    text = (NAVIGATION / "navigation.tsm").read_text(encoding="utf-8")
    assert_reads_as_textx(text, must_read=True)
    system = tsm.parse_text(text, "navigation.tsm")
    found = interfaces(system)
    client = found["Robot.Behaviour.navigate"]
    server = found["Cloud.Planner.move_base"]
    assert (kind_of(client).title, kind_of(server).title) == ("action client", "action server")
    assert (client.type, server.type, server.rosName) == (
        "move_base_msgs/MoveBase",
        "move_base_msgs/MoveBase",
        "/move_base",
    )
    # the bridge binds the client to the robot endpoint's stand-in of the cloud server
    assert client.server.eContainer() is system.containers[0].endpoint
    assert kind_of(client.server).title == "action server"
    assert [(kind_of(c.source).title, kind_of(c.target).title) for c in system.connections][-1] == (
        "action server",
        "action client",
    )


def test_action_statements_print_back_to_the_same_model() -> None:
    text = textwrap.dedent(
        """\
        system S
        robot container R {
            node N {
                calls action goal -> M.move_base
                calls action spare : move_base_msgs/MoveBase external "a teleop panel"
                provides action : std_srvs/Empty
            }
            node M {
                provides action move_base : move_base_msgs/MoveBase name "/nav/move_base"
            }
        }
        """
    )
    printed = print_model(tsm.parse_text(text, "a.tsm"))
    lines = [line.strip() for line in printed.splitlines()]
    assert "calls action goal -> M.move_base" in lines
    assert 'calls action spare : move_base_msgs/MoveBase external "a teleop panel"' in lines
    assert "provides action : std_srvs/Empty" in lines  # a service named action
    assert 'provides action move_base : move_base_msgs/MoveBase name "/nav/move_base"' in lines
    assert print_model(tsm.parse_text(printed, "printed.tsm")) == printed


def test_an_action_type_is_the_action_files_own() -> None:
    assert errors(
        """\
        robot container R {
            node N {
                calls action goal : move_base_msgs/MoveBaseAction
                provides action serve : move_base_msgs/MoveBaseActionGoal name "not a name"
            }
        }
        """
    ) == [
        "bad.tsm:3:29: error: action client goal: move_base_msgs/MoveBaseAction is the Action "
        "message generated from move_base_msgs/MoveBase; write the action's own type, "
        "move_base_msgs/MoveBase",
        "bad.tsm:4:33: error: action server serve: move_base_msgs/MoveBaseActionGoal is the "
        "ActionGoal message generated from move_base_msgs/MoveBase; write the action's own "
        "type, move_base_msgs/MoveBase",
        "bad.tsm:4:72: error: action name 'not a name' is not a valid ROS graph name (names "
        "of a letter then letters, digits, underscores, separated by '/'; at most 255 "
        "characters)",
    ]


def test_a_client_is_bound_only_to_a_server_of_its_own_kind_and_type() -> None:
    assert errors(
        """\
        robot container R {
            topic T : std_msgs/String
            node N {
                calls action to_service -> M.srv
                calls action to_topic -> M.out
                calls action mismatched : move_base_msgs/MoveBase -> M.dock
                calls service_to_action -> M.dock
            }
            node M {
                provides srv : std_srvs/Empty
                publishes out -> T
                provides action dock : dock_msgs/Dock
            }
        }
        """
    ) == [
        "bad.tsm:4:38: error: kind mismatch: R.N.to_service (bad.tsm:4:22) is an action client, "
        "R.M.srv (bad.tsm:10:18) is a service server, not an action server",
        "bad.tsm:5:36: error: kind mismatch: R.N.to_topic (bad.tsm:5:22) is an action client, "
        "R.M.out (bad.tsm:11:19) is a topic publisher, not an action server",
        "bad.tsm:6:64: error: type mismatch: R.N.mismatched (bad.tsm:6:22) is "
        "move_base_msgs/MoveBase, R.M.dock (bad.tsm:12:25) is dock_msgs/Dock",
        "bad.tsm:7:38: error: kind mismatch: R.N.service_to_action (bad.tsm:7:15) is a service "
        "client, R.M.dock (bad.tsm:12:25) is an action server, not a service server",
    ]


def test_a_bridge_carries_an_action_client_to_an_action_server_only() -> None:
    assert errors(
        """\
        robot container R {
            node N {
                calls action goal : move_base_msgs/MoveBase
                calls plan : nav_msgs/GetPlan
            }
        }
        cloud container C {
            node M {
                provides action move_base : move_base_msgs/MoveBase
                provides srv : nav_msgs/GetPlan
                provides action other : dock_msgs/Dock
            }
        }
        bridge R.N.goal -> C.M.srv
        bridge R.N.plan -> C.M.move_base
        bridge R.N.goal -> C.M.other
        bridge C.M.move_base -> R.N.goal
        """
    ) == [
        "bad.tsm:14:24: error: kind mismatch: R.N.goal (bad.tsm:3:22) is an action client, "
        "C.M.srv (bad.tsm:10:18) is a service server, not an action server",
        "bad.tsm:15:24: error: kind mismatch: R.N.plan (bad.tsm:4:15) is a service client, "
        "C.M.move_base (bad.tsm:9:25) is an action server, not a service server",
        "bad.tsm:16:24: error: type mismatch: R.N.goal (bad.tsm:3:22) is move_base_msgs/MoveBase, "
        "C.M.other (bad.tsm:11:25) is dock_msgs/Dock",
        "bad.tsm:17:12: error: action bridged the wrong way: C.M.move_base (bad.tsm:9:25) is an "
        "action server and R.N.goal (bad.tsm:3:22) is an action client; calls run from the "
        "client to its server: write 'bridge R.N.goal -> C.M.move_base'",
    ]


def test_rm_connect_binds_an_action_client_like_a_service_client(tmp_path: Path) -> None:
    for name in ("navigation.tsm", "navigation.fm"):
        shutil.copy(NAVIGATION / name, tmp_path / name)
    header = 'resolution model Navigation\ntsm "navigation.tsm"\nfm  "navigation.fm"\n'
    (tmp_path / "navigation.rm").write_text(
        header
        + "when OnBoardPlanning selected {\n"
        + "    migrate Planner to Robot\n"
        + "    connect Behaviour.navigate to server Planner.move_base\n"
        + "    connect Behaviour.navigate to server Planner.cmd_vel\n"
        + "    connect Lidar.scan to server Planner.move_base\n"
        + "    connect Planner.move_base to server Behaviour.navigate\n"
        + "    connect bridge Cloud.Planner.move_base -> Robot.Behaviour.navigate\n"
        + "}\n",
        encoding="utf-8",
    )
    with pytest.raises(ModelError) as caught:
        rm.load(tmp_path / "navigation.rm")
    assert [str(d).replace(f"{tmp_path}/", "") for d in caught.value.diagnostics] == [
        "navigation.rm:7:5: error: kind mismatch: Robot.Behaviour.navigate (navigation.tsm:20:22) "
        "is an action client, Cloud.Planner.cmd_vel (navigation.tsm:36:19) is a topic publisher, "
        "not an action server",
        "navigation.rm:8:5: error: Lidar.scan is a Publisher, not a service client or action "
        "client",
        "navigation.rm:9:5: error: action connected the wrong way: Cloud.Planner.move_base "
        "(navigation.tsm:37:25) is an action server and Robot.Behaviour.navigate "
        "(navigation.tsm:20:22) is an action client; calls run from the client to its server: "
        "write 'connect Robot.Behaviour.navigate to server Cloud.Planner.move_base'",
        "navigation.rm:10:5: error: action bridged the wrong way: Cloud.Planner.move_base "
        "(navigation.tsm:37:25) is an action server and Robot.Behaviour.navigate "
        "(navigation.tsm:20:22) is an action client; calls run from the client to its server: "
        "write 'connect bridge Robot.Behaviour.navigate -> Cloud.Planner.move_base'",
    ]


def test_spl_check_refuses_a_bad_action_located_with_exit_1(tmp_path: Path) -> None:
    bad = tmp_path / "bad.tsm"
    bad.write_text(
        "robot container R {\n  node N {\n    calls action goal : move_base_msgs/MoveBaseAction\n"
        "  }\n}\n",
        encoding="utf-8",
    )
    result = run("check", bad)
    assert_clean(result, "spl check bad.tsm")
    assert result.exit_code == 1
    assert f"{bad}:3:25: error: action client goal: move_base_msgs/MoveBaseAction" in result.stderr


def test_a_bound_action_client_is_told_to_declare_itself_unbound_as_an_action() -> None:
    assert errors(
        """\
        robot container R {
            node N {
                calls action goal -> M.move_base
            }
            node M {
                provides action move_base : move_base_msgs/MoveBase
            }
        }
        cloud container C {
            node P {
                provides action move_base : move_base_msgs/MoveBase
            }
        }
        bridge R.N.goal -> C.P.move_base
        """
    ) == [
        "bad.tsm:14:12: error: client N.goal is already bound to M.move_base; declare it "
        "unbound ('calls action goal : TYPE') to bridge it",
    ]
