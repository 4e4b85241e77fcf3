"""Fleets on the mapping3d line: robots sharing the protected map of their group or the
public one, conflicts refused with their reasons, options computed with the SAT solver,
and one bundle for the fleet."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.generators.launch.launch_schema import validate_ros1_launch, validate_ros2_launch
from spl.generators.rapyuta.rules import check_all

from support.one_feature_line import MAP_SERVER_BRIDGE, MAP_SERVER_TSM, one_feature_line

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
RM = MAPPING / "mapping.rm"
ROOM = f"'when Room selected' ({RM}:48:1)"
CORRIDOR = f"'when Corridor selected' ({RM}:52:1)"


def fleet(tmp_path: Path, robots: str, line: Path = MAPPING, name: str = "lab.yaml") -> Path:
    path = tmp_path / name
    path.write_text(f"fleet: lab\nproduct_line: {line}\nrobots:\n{robots}")
    return path


def run(*args: str | Path) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, [str(a) for a in args])
    return result.exit_code, result.stdout, result.stderr


CONFLICTING = (
    "  youbot_1: {group: lab, features: [YouBot, Stereo, Room]}\n"
    "  youbot_2: {group: lab, features: [YouBot, Depth, Corridor]}\n"
)


def test_two_robots_of_a_group_asking_two_strategies_are_refused(tmp_path) -> None:
    path = fleet(tmp_path, CONFLICTING)
    code, stdout, stderr = run("fleet", "check", path)
    assert code == 1 and stdout == ""
    (error,) = stderr.splitlines()
    assert error.startswith(f"{path}:5:3: error: conflict on shared node StrategyPlanner: ")
    assert "robots youbot_1 and youbot_2 ask for a different implementation" in error
    assert f"youbot_1 has exploration/room_strategy (by feature Room: {ROOM} at {RM}:49:5)" in error
    assert f"youbot_2 has exploration/corridor_strategy (by feature Corridor: {CORRIDOR}" in error
    assert error.endswith("[SPL040]")


def test_the_same_robots_with_a_private_map_are_accepted(tmp_path) -> None:
    path = fleet(
        tmp_path, CONFLICTING.replace("Corridor]}", "Corridor], sharing: {SharedMap: private}}")
    )
    code, stdout, stderr = run("fleet", "check", path)
    assert code == 0, stderr
    assert stdout.splitlines() == [
        "fleet lab: 2 robots in 1 group (lab), 1 shared cloud instance, no conflict",
        "  MappingCloud_lab (protected, group lab): Database, MapMerger, StrategyPlanner; "
        "used by youbot_1",
    ]


def test_options_for_a_third_robot_forbid_corridor_with_the_reason(tmp_path) -> None:
    path = fleet(
        tmp_path, CONFLICTING.replace("Corridor]}", "Corridor], sharing: {SharedMap: private}}")
    )
    code, stdout, stderr = run("fleet", "options", path, "--robot", "youbot_3", "--group", "lab")
    assert code == 0, stderr
    lines = stdout.splitlines()
    assert lines[0] == "robot youbot_3 in group lab: can join (shared nodes fixed by youbot_1)"
    fixed = (
        "StrategyPlanner must have implementation exploration/room_strategy, as youbot_1 fixed "
        "it (MappingCloud_lab, protected for group lab)"
    )
    assert lines[1] == f"forced Room: {fixed}"
    assert lines[2] == (
        f"forbidden Corridor: {fixed}; Corridor makes it exploration/corridor_strategy ({CORRIDOR})"
    )
    assert lines[3] == "free: YouBot, Roomba, Stereo, Depth, AdditionalPC"
    # another group shares nothing with the lab: everything is free there
    code, stdout, _ = run(
        "fleet", "options", path, "--robot", "youbot_3", "--group", "hall", "--json"
    )
    answer = json.loads(stdout)
    assert code == 0 and answer["fixed_by"] == []
    assert {f: v["status"] for f, v in answer["features"].items()} == {
        f: "free"
        for f in ("YouBot", "Roomba", "Stereo", "Depth", "AdditionalPC", "Room", "Corridor")
    }


def test_a_robot_that_cannot_join_is_told_why_and_how_it_could(tmp_path) -> None:
    path = fleet(
        tmp_path, CONFLICTING.replace("Corridor]}", "Corridor], sharing: {SharedMap: private}}")
    )
    path.write_text(
        path.read_text()
        + "  youbot_9: {group: lab, features: [YouBot], sharing: {SharedMap: public}}\n"
    )
    code, stdout, stderr = run("fleet", "options", path, "--robot", "youbot_9")
    assert code == 1
    assert "robot youbot_9 in group lab: cannot join" in stdout
    (error,) = stderr.splitlines()
    assert error.startswith(f"{path}:6:3: error: robot youbot_9 cannot join group lab: ")
    assert "must be shared protected, as youbot_1 fixed it" in error
    assert error.endswith("(it could with sharing SharedMap: private or SharedMap: protected)")


def test_a_public_map_is_one_instance_across_groups(tmp_path) -> None:
    public = "sharing: {SharedMap: public}"
    robots = (
        f"  roomba_1: {{group: hall, features: [Roomba, Depth, Corridor], {public}}}\n"
        f"  roomba_2: {{group: cellar, features: [Roomba, Stereo, Corridor], {public}}}\n"
        "  roomba_3: {group: attic, features: [Roomba, Depth, Room]}\n"
    )
    code, stdout, stderr = run("fleet", "check", fleet(tmp_path, robots))
    assert code == 0, stderr
    assert (
        "  MappingCloud_public (public, every group): Database, MapMerger, StrategyPlanner; "
        "used by roomba_1, roomba_2"
    ) in stdout.splitlines()
    assert "  MappingCloud_attic (protected, group attic): " in stdout
    clash = robots.replace("Stereo, Corridor]", "Stereo, Room]")
    code, _, stderr = run("fleet", "check", fleet(tmp_path, clash, name="clash.yaml"))
    assert code == 1
    assert "conflict on shared node StrategyPlanner: robots roomba_1 and roomba_2" in stderr
    assert "roomba_1 has exploration/corridor_strategy" in stderr
    path = fleet(tmp_path, robots)
    code, stdout, _ = run("fleet", "options", path, "--robot", "roomba_4", "--group", "attic")
    assert code == 0 and any(
        line.startswith("forbidden Corridor: ") for line in stdout.splitlines()
    )
    # sharing publicly from a fourth group: the public map fixed by roomba_1 decides
    code, stdout, _ = run(
        "fleet",
        "options",
        path,
        "--robot",
        "roomba_4",
        "--group",
        "garage",
        "--sharing",
        "SharedMap=public",
    )
    lines = stdout.splitlines()
    assert code == 0 and lines[0].endswith("(shared nodes fixed by roomba_1)")
    assert lines[1].startswith(
        "forbidden Room: StrategyPlanner must have implementation "
        "exploration/corridor_strategy, as roomba_1 fixed it "
        "(MappingCloud_public, public for every group)"
    )


def test_resolve_writes_each_shared_instance_once(tmp_path) -> None:
    path = fleet(
        tmp_path,
        "  youbot_1: {group: lab, features: [YouBot, Stereo, AdditionalPC, Room]}\n"
        "  youbot_2: {group: lab, features: [YouBot, Depth, Room]}\n"
        "  roomba_1: {group: hall, features: [Roomba, Depth, Corridor], sharing: {SharedMap: "
        "public}}\n"
        "  roomba_2: {group: cellar, features: [Roomba, Depth, Corridor], sharing: {SharedMap: "
        "public}}\n",
    )
    out = tmp_path / "out"
    code, _, stderr = run("fleet", "resolve", path, "-o", out)
    assert code == 0, stderr
    files = {p.relative_to(out).as_posix(): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    shared = sorted(p for p in files if p.startswith("shared/"))
    assert shared == [
        "shared/ros1/MappingCloud_lab.launch",
        "shared/ros1/MappingCloud_public.launch",
        "shared/ros2/MappingCloud_lab.launch.xml",
        "shared/ros2/MappingCloud_public.launch.xml",
    ]
    for name, data in files.items():
        if name.endswith(".launch"):
            assert validate_ros1_launch(data) == [], name
        elif name.endswith(".launch.xml"):
            assert validate_ros2_launch(data) == [], name
    # the lab's shared nodes are in the lab's launch file, nowhere else
    for node in ("StrategyPlanner", "Database", "MapMerger"):
        holders = [
            p for p, d in files.items() if p.endswith(".launch") and f'name="{node}"' in d.decode()
        ]
        assert holders == [
            "shared/ros1/MappingCloud_lab.launch",
            "shared/ros1/MappingCloud_public.launch",
        ]
    assert b'type="room_strategy"' in files["shared/ros1/MappingCloud_lab.launch"]
    assert b'type="corridor_strategy"' in files["shared/ros1/MappingCloud_public.launch"]
    # the first robot's Rapyuta file declares a shared container, the others connect to
    # it (the engine refuses a tag twice); together they pass
    documents = {p: json.loads(d) for p, d in files.items() if "/rapyuta/" in p}
    assert check_all(list(documents.values()), list(documents)) == []
    lab = [
        [
            e
            for e in documents[f"robots/{r}/rapyuta/Robot.json"][key]
            if e.get("cTag", e.get("eTag")) == "MappingCloud_lab"
        ]
        for r in ("youbot_1", "youbot_2")
        for key in ("containers", "nodes", "interfaces")
    ]
    assert lab[0] == [{"cTag": "MappingCloud_lab", "group": "lab"}] and all(lab[1:3])
    assert lab[3:] == [[], [], []]
    assert documents["robots/roomba_2/rapyuta/Robot.json"]["robotID"] == "roomba_2"
    manifest = json.loads(files["fleet.json"])
    assert manifest["shared"]["MappingCloud_public"]["robots"] == ["roomba_1", "roomba_2"]
    assert manifest["robots"]["youbot_1"]["group"] == "lab"
    for name, digest in manifest["files"].items():
        assert hashlib.sha256(files[name]).hexdigest() == digest
    assert set(manifest["files"]) == set(files) - {"fleet.json"}
    again = tmp_path / "again"
    assert run("fleet", "resolve", path, "-o", again)[0] == 0
    assert {
        p.relative_to(again).as_posix(): p.read_bytes() for p in again.rglob("*") if p.is_file()
    } == files


def test_resolve_of_a_conflicting_fleet_writes_nothing(tmp_path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "earlier.txt").write_text("kept")
    code, _, stderr = run("fleet", "resolve", fleet(tmp_path, CONFLICTING), "-o", out)
    assert code == 1 and "conflict on shared node StrategyPlanner" in stderr
    assert [p.name for p in out.iterdir()] == ["earlier.txt"]
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("fleet: lab\nrobots:\n  a: {features: [YouBot]}\n", "1:1: error: no product_line"),
        (
            "fleet: lab\nproduct_line: nowhere\nrobots:\n  a: {features: [YouBot]}\n",
            "2:15: error: product_line: no such folder nowhere",
        ),
        (f"fleet: lab\nproduct_line: {MAPPING}\nrobots: [a]\n", "3:9: error: robots: expected"),
        (
            f"fleet: lab\nproduct_line: {MAPPING}\nrobots:\n  a: {{features: [X], colour: red}}\n",
            "4:22: error: unknown key 'colour' (expected features, deselected, sharing, "
            "attributes, deployment, capabilities, group)",
        ),
        (
            f"fleet: lab\nproduct_line: {MAPPING}\nrobots:\n  '$(x)': {{features: [X]}}\n",
            "4:3: error: robot name '$(x)': expected a letter, then up to 63 letters",
        ),
        (
            f"fleet: lab\nproduct_line: {MAPPING}\nrobots:\n  a: {{features: [X]}}\n"
            "  a: {features: [X]}\n",
            "5:3: error: robot a is listed twice",
        ),
        (
            f"fleet: lab\nproduct_line: {MAPPING}\nrobots:\n  a: {{group: 'l b', features: [X]}}\n",
            "4:14: error: group: expected a group name",
        ),
        (
            f"fleet: lab\nproduct_line: {MAPPING}\nrobots:\n  a: {{group: lab}}\n",
            "4:3: error: robot a: no features",
        ),
        ("fleet: [lab\n", "error: invalid YAML"),
        ("fleet: lab\nrobots: \udcff\n", "2:9: error: file is not UTF-8 text (invalid start byte)"),
        ("fleet: " + "[" * 5000 + "]" * 5000 + "\n", "1:1: error: invalid YAML: nested too deeply"),
        (
            "fleets: lab\n",
            "1:1: error: unknown key 'fleets' (expected fleet, product_line, robots)",
        ),
    ],
)
def test_bad_fleet_files_are_located_errors(tmp_path, text: str, expected: str) -> None:
    path = tmp_path / "f.yaml"
    path.write_bytes(text.encode("utf-8", "surrogateescape"))
    code, _, stderr = run("fleet", "check", path)
    assert code == 1
    assert expected in stderr, stderr
    assert "Traceback" not in stderr


def test_robot_errors_are_located_in_the_fleet_file_and_name_the_robot(tmp_path) -> None:
    path = fleet(
        tmp_path,
        "  a: {features: [Roomba, AdditionalPC, Depth, Room]}\n"
        "  b: {features: [YouBot, Depth, Room], deployment: {Robot: {robot_id: a}}}\n",
    )
    code, _, stderr = run("fleet", "check", path)
    assert code == 1
    first, second = stderr.splitlines()
    assert first.startswith(f"{path}:4:18: error: robot a: invalid selection: selecting Roomba")
    assert "Roomba excludes AdditionalPC" in first
    assert second == (
        f"{path}:5:3: error: robot b: robot_id a of container Robot is already robot a's [SPL041]"
    )


def test_the_shipped_fleets_check_and_resolve(tmp_path) -> None:
    for path in sorted(ROOT.glob("product_lines/*/fleets/*.yaml")):
        code, _, stderr = run("fleet", "resolve", path, "-o", tmp_path / path.stem)
        assert code == 0, stderr
    lab = json.loads((tmp_path / "lab" / "fleet.json").read_text())
    assert lab["robots"]["youbot_1"]["features"] == [
        "AdditionalPC",
        "Environment",
        "Mapping",
        "MobileBase",
        "PerceptionSensor",
        "Room",
        "SharedMap",
        "Stereo",
        "YouBot",
    ]
    assert any("selects Stereo" in c for c in lab["robots"]["youbot_1"]["capabilities"])
    assert lab["robots"]["roomba_2"]["robot_ids"] == {"Robot": "roomba-cellar"}


def test_options_of_a_robot_with_capabilities_follow_its_hardware() -> None:
    path = ROOT / "product_lines" / "mapping3d" / "fleets" / "lab.yaml"
    code, stdout, stderr = run("fleet", "options", path, "--robot", "youbot_1", "--json")
    assert code == 0, stderr
    features = json.loads(stdout)["features"]
    assert {f: v["status"] for f, v in features.items()} == {
        "YouBot": "forced",
        "Roomba": "forbidden",
        "Stereo": "forced",
        "Depth": "forbidden",
        "AdditionalPC": "forced",
        "Room": "forced",
        "Corridor": "forbidden",
    }
    assert features["AdditionalPC"]["reasons"][0].startswith("capability onboard_pc: true (")
    assert "selects AdditionalPC: onboard_pc holds" in features["AdditionalPC"]["reasons"][0]


@pytest.mark.parametrize(
    ("robots", "message"),
    [
        (  # a group called public: its protected instance took the public one's name
            "  youbot_1: {group: public, features: [YouBot, Depth, Room]}\n"
            "  roomba_1: {group: hall, features: [Roomba, Depth, Room], "
            "sharing: {SharedMap: public}}\n",
            "5:3: error: robot roomba_1: instance MappingCloud_public would be both the "
            "protected partition of MappingCloud (robot youbot_1) and the public partition of "
            "MappingCloud: rename the group or robot_id",
        ),
        (  # a robotID equal to another robot's group
            "  youbot_1: {group: lab, features: [YouBot, Depth, Room]}\n"
            "  youbot_2: {group: hall, features: [YouBot, Depth, Room], "
            "deployment: {Robot: {robot_id: lab}}}\n",
            "5:3: error: robot youbot_2: instance MappingCloud_lab would be both the protected "
            "partition of MappingCloud (robot youbot_1) and the private partition of "
            "MappingCloud: rename the group or robot_id",
        ),
    ],
)
def test_two_instances_of_one_name_are_refused_by_check(tmp_path, robots, message) -> None:
    # were: "no conflict" from fleet check, then fleet resolve refused with "containers
    # entry {'cTag': 'MappingCloud_public'} differs from ...", unlocated
    path = fleet(tmp_path, robots)
    code, _, stderr = run("fleet", "check", path)
    assert code == 1
    assert stderr.splitlines() == [f"{path}:{message}"]
    code, _, stderr = run("fleet", "resolve", path, "-o", tmp_path / "out")
    assert code == 1 and f"{path}:{message}" in stderr
    assert not (tmp_path / "out").exists()


def test_options_refuse_a_sharing_override_with_nothing_to_override(tmp_path) -> None:
    # was: "can join" with a confident forced/free list for a misspelt feature
    path = MAPPING / "fleets" / "lab.yaml"
    code, _, stderr = run(
        "fleet",
        "options",
        path,
        "--robot",
        "x",
        "--sharing",
        "SharedMaps=public",
        "--sharing",
        "Stereo=public",
    )
    assert code == 1
    assert stderr.splitlines() == [
        "--sharing:1:1: error: unknown feature SharedMaps",
        "--sharing:1:1: error: sharing given for Stereo, which has no sharing attribute",
    ]
    assert run("fleet", "options", path, "--robot", "x", "--sharing", "SharedMap=public")[0] == 0


def test_robot_problems_are_at_the_robots_entry_and_only_real_ones(tmp_path) -> None:
    # were: an open choice located in the .fm (the rule's place) rather than at the robot;
    # a robot_id "taken" in a container the line does not have, beside "no robot container"
    path = fleet(
        tmp_path,
        "  a: {features: [YouBot, Depth, Room]}\n"
        "  b: {features: [YouBot, Room]}\n"
        "  c: {features: [YouBot, Depth, Room], deployment: {Kitchen: {robot_id: a}}}\n",
    )
    code, _, stderr = run("fleet", "check", path)
    assert code == 1
    lines = stderr.splitlines()
    assert len(lines) == 2, lines
    assert lines[0].startswith(f"{path}:5:3: error: robot b: open choice: ")
    assert f"({MAPPING / 'mapping.fm'}:" in lines[0]  # the rule's place, in the message
    assert lines[1].startswith(f"{path}:6:") and "no robot container Kitchen" in lines[1]


SURVEY_TSM = """system Survey
robot container Rover {
    endpoint robot_id "rover_1" url "wss://cloud.example.org:9000/" user "rover"
             password env "RCE_PASSWORD"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    optional node Lidar { implementation urg_node/urg_node publishes scan -> Scan }
}
robot container Drone {
    endpoint robot_id "drone_1" url "wss://cloud.example.org:9000/" user "drone"
             password env "RCE_PASSWORD"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    optional node Lidar2 { implementation urg_node/urg_node publishes scan -> Scan }
}
cloud container SurveyCloud {
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Mapper { implementation survey/mapper subscribes scan <- Scan }
}
bridge Rover.Scan -> SurveyCloud.Scan
bridge Drone.Scan -> SurveyCloud.Scan
"""
SURVEY_FM = """feature model Survey
root Survey {
    mandatory Map { sharing public }
    mandatory Platform xor { Ground Aerial }
}
"""
SURVEY_RM = """resolution model Survey
tsm "survey.tsm"
fm "survey.fm"
when Map selected { require Mapper }
when Ground selected { require Rover.Lidar }
when Aerial selected { require Drone.Lidar2 }
"""


def test_a_fleet_warns_of_robots_of_two_users_sharing_an_instance(tmp_path) -> None:
    # was: not mentioned; on Rapyuta each user gets a Mapper of its own, while
    # kubernetes/ and zenoh/ deploy one shared Mapper
    line = tmp_path / "survey"
    line.mkdir()
    for suffix, text in (("tsm", SURVEY_TSM), ("fm", SURVEY_FM), ("rm", SURVEY_RM)):
        (line / f"survey.{suffix}").write_text(text)
    path = fleet(
        tmp_path,
        "  rover: {features: [Ground]}\n"
        "  drone: {features: [Aerial]}\n"
        "  rover2: {features: [Ground]}\n",
        line=line,
    )
    code, stdout, stderr = run("fleet", "check", path)
    assert code == 0, stderr
    assert (
        "SurveyCloud_public (public, every group): Mapper; used by rover, drone, rover2" in stdout
    )
    assert stderr == (
        f"{path}:5:3: warning: robot drone: shared instance SurveyCloud_public is used by "
        "robots of different Rapyuta users (rover as 'rover', drone as 'drone', rover2 as "
        "'rover'); the engine keeps each user's containers apart, so on Rapyuta they share "
        "nothing (kubernetes/ and zenoh/ deploy one instance): give these robots one user "
        "[SPL047]\n"
    )
    code, _, resolved = run("fleet", "resolve", path, "-o", tmp_path / "bundle")
    assert (code, resolved) == (0, stderr)
    one_user = fleet(
        tmp_path,
        "  rover: {features: [Ground]}\n  rover2: {features: [Ground]}\n",
        line=line,
        name="one.yaml",
    )
    assert run("fleet", "check", one_user)[::2] == (0, "")


def test_a_fleet_shows_its_robots_product_warnings_and_the_shipped_ones_have_none(
    tmp_path,
) -> None:
    # was: a robot's product warnings (two users within its product here) never shown
    line = tmp_path / "orchard"
    shutil.copytree(ROOT / "product_lines" / "orchard", line)
    tsm_file = line / "orchard.tsm"
    scout = 'robot_id "scout_1" url "wss://orchard.example.org:9000/" user "orchard"'
    tsm_file.write_text(tsm_file.read_text().replace(scout, scout.replace('orchard"', 'scout"')))
    features = "[CloudDetection, CloudPlanning, SoftGripper, Scouting, YieldMapping]"
    path = fleet(tmp_path, f"  north: {{features: {features}}}\n", line=line)
    code, _, stderr = run("fleet", "check", path)
    assert code == 0, stderr
    (warning,) = stderr.splitlines()
    assert warning.startswith(f"{path}:4:3: warning: robot north: cloud container OrchardCloud: ")
    assert warning.endswith(f"({tsm_file}:{_line_of(tsm_file, 'cloud container')}:17) [SPL047]")
    for shipped in sorted(ROOT.glob("product_lines/*/fleets/*.yaml")):
        assert run("fleet", "check", shipped)[2] == "", shipped


def _line_of(path: Path, text: str) -> int:
    return next(i for i, t in enumerate(path.read_text().splitlines(), 1) if text in t)


def test_a_public_node_calling_each_groups_own_server_is_warned_about(tmp_path) -> None:
    # was silent: the one public FleetManager was wired to C_hall's MapServer in a's
    # Rapyuta file and to C_dock's in b's (reported by a from-scratch user test)
    line = one_feature_line(tmp_path / "line", MAP_SERVER_TSM + MAP_SERVER_BRIDGE)
    robots = "  a: {group: hall, features: [M]}\n  b: {group: dock, features: [M]}\n"
    code, _, stderr = run("fleet", "check", fleet(tmp_path, robots, line=line))
    assert code == 0
    template = f"as the template has it ({line / 'm.tsm'}:7:10)"
    assert stderr == (
        f"{tmp_path / 'lab.yaml'}:5:3: warning: shared node FleetManager cannot call both "
        "servers: robots a and b ask for a different server instance of map: a has MapServer "
        f"in C_hall, protected for group hall (MapServer's sharing: {template}), b has "
        f"MapServer in C_dock, protected for group dock (MapServer's sharing: {template}); the "
        "deployment connects its one instance to one of them, so give the server the node's "
        "sharing [SPL049]\n"
    )
    # one group: one MapServer for the one FleetManager
    same = "  a: {group: hall, features: [M]}\n  b: {group: hall, features: [M]}\n"
    code, _, stderr = run("fleet", "check", fleet(tmp_path, same, line=line, name="one.yaml"))
    assert (code, stderr) == (0, "")


RENAMING_TSM = """system M
robot container R {
    endpoint robot_id "r" url "wss://x.example.org:9000/" user "u" password env "P"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Lidar { implementation a/lidar publishes scan -> Scan }
}
cloud container C {
    topic Laser : sensor_msgs/LaserScan name "/laser"
    node Mapper { implementation a/map subscribes laser <- Laser }
}
bridge R.Scan -> C.Laser
"""


def test_fleet_resolve_says_when_zenoh_cannot_carry_the_fleet(tmp_path) -> None:
    # was silent: no zenoh/, the reason only in kubernetes/README.md
    line = one_feature_line(tmp_path / "line", RENAMING_TSM)
    out = tmp_path / "out"
    path = fleet(tmp_path, "  a: {features: [M]}\n", line=line)
    code, _, stderr = run("fleet", "resolve", path, "-o", out)
    assert code == 0, stderr
    assert stderr.startswith("warning: zenoh/ not written: Zenoh cannot carry this fleet: ")
    reason = stderr.removeprefix("warning: zenoh/ not written: ").rstrip("\n")
    assert "/scan" in reason and "/laser" in reason
    assert json.loads((out / "fleet.json").read_text())["skipped"] == {"zenoh/": reason}
    assert not (out / "zenoh").exists()
