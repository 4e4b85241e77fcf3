"""The rce-ros schema and the engine's rules: the engine's own files pass, checked
together; each rule refuses a hand-broken variant, naming the file and JSON path."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest

from spl.generators.rapyuta.rules import check_all, check_configurations
from spl.generators.rapyuta.schema import schema_problems

# The three configuration files of the engine's own test folder, unchanged.
EXAMPLES = Path(__file__).parents[1] / "models" / "rapyuta" / "rce-examples"
NAMES = ["debug.cfg", "lo_client.cfg", "lo_server.cfg"]


@pytest.fixture
def real():
    return [json.loads((EXAMPLES / name).read_text()) for name in NAMES]


def rules(configs):
    return [str(p) for p in check_configurations(configs, NAMES)]


def test_the_engines_own_files_pass_schema_and_rules_together(real):
    assert check_all(real, NAMES) == []


def test_a_connection_to_another_robots_interface_needs_that_robots_file(real):
    alone = check_configurations(real[1:2], NAMES[1:2])
    assert {p.rule for p in alone} == {"unresolved-tag"}
    assert str(alone[0]).startswith("lo_client.cfg: connections[0].tagB: server/stringEchoService")


def test_interface_type_on_robot_endpoint(real):
    real[0]["interfaces"][1]["iType"] = "ServiceProviderInterface"
    assert rules(real) == [
        "debug.cfg: interfaces[1].iType: interface testRobot/stringEchoService is on robot "
        "'testRobot': a robot endpoint takes ServiceProviderConverter or "
        "ServiceProviderForwarder, not ServiceProviderInterface [interface-type-on-robot]"
    ]


def test_interface_type_on_container_endpoint(real):
    real[0]["interfaces"][2]["iType"] = "PublisherConverter"
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "debug.cfg",
        "interfaces[2].iType",
        "interface-type-on-container",
    )


def test_forwarder_is_a_robot_type(real):
    real[2]["interfaces"][1]["iType"] = "PublisherForwarder"
    assert check_all(real, NAMES) == []


def test_unconnectable_pair(real):
    real[0]["interfaces"][3]["iType"] = "PublisherConverter"  # publisher with publisher
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "debug.cfg",
        "connections[1]",
        "unconnectable-pair",
    )
    assert "cTag_01/stringEchoReq (PublisherInterface)" in problem.message
    # the pairs the engine connects, the side a flow starts at first
    assert problem.message.endswith(
        ": only Publisher with Subscriber or ServiceClient with ServiceProvider"
    )


def test_publisher_with_service_side_is_unconnectable(real):
    real[2]["interfaces"][0]["iType"] = "SubscriberConverter"
    real[2]["interfaces"][0]["iCls"] = "Test/StringEcho"
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "lo_client.cfg",
        "connections[0]",
        "unconnectable-pair",
    )


def test_message_class_mismatch(real):
    real[2]["interfaces"][2]["iCls"] = "std_msgs/Header"
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "lo_client.cfg",
        "connections[2]",
        "message-class-mismatch",
    )
    assert "std_msgs/String" in problem.message and "std_msgs/Header" in problem.message


def test_unresolved_tag(real):
    real[0]["connections"][3]["tagB"] = "testRobot/nosuch"
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "debug.cfg",
        "connections[3].tagB",
        "unresolved-tag",
    )


def test_malformed_tag_is_refused_by_schema_and_rules(real):
    real[0]["connections"][0]["tagA"] = "cTag_01"
    assert [(p.path, p.rule) for p in check_configurations(real, NAMES)] == [
        ("connections[0].tagA", "malformed-tag")
    ]
    assert [p.path for p in schema_problems(real[0], "debug.cfg")] == ["connections[0].tagA"]


def test_duplicate_connection_in_either_order(real):
    connection = real[0]["connections"][2]
    real[0]["connections"].append({"tagA": connection["tagB"], "tagB": connection["tagA"]})
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "debug.cfg",
        "connections[4]",
        "duplicate-connection",
    )
    assert "connections[2]" in problem.message


def test_duplicate_interface_tag_on_one_endpoint(real):
    clash = copy.deepcopy(real[0]["interfaces"][0])
    clash["iType"] = "SubscriberInterface"
    real[0]["interfaces"].append(clash)
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "debug.cfg",
        "interfaces[8]",
        "duplicate-interface",
    )


def test_same_tag_on_two_endpoints_is_fine(real):
    # debug.cfg itself uses stringEchoService on both cTag_01 and testRobot
    assert check_configurations(real[:1], NAMES[:1]) == []


def test_interface_on_an_undeclared_endpoint(real):
    real[0]["interfaces"][0]["eTag"] = "cTag_02"
    problems = check_configurations(real, NAMES)
    assert ("debug.cfg", "interfaces[0].eTag", "unknown-endpoint") in [
        (p.file, p.path, p.rule) for p in problems
    ]
    # and the connection naming the old place no longer resolves
    assert "unresolved-tag" in {p.rule for p in problems}


def test_node_and_parameter_need_a_declared_container(real):
    real[0]["nodes"][1]["cTag"] = "nowhere"
    real[0]["parameters"][4]["cTag"] = "nowhere"
    assert [(p.path, p.rule) for p in check_configurations(real, NAMES)] == [
        ("nodes[1]", "unknown-container"),
        ("parameters[4]", "unknown-container"),
    ]


def test_duplicate_container_node_and_parameter_in_one_file(real):
    real[0]["containers"].append({"cTag": "cTag_01"})
    real[0]["nodes"].append(dict(real[0]["nodes"][0]))
    real[0]["parameters"].append(dict(real[0]["parameters"][0], value="other"))
    assert [(p.path, p.rule) for p in check_configurations(real, NAMES)] == [
        ("containers[3]", "duplicate-container"),
        ("nodes[2]", "duplicate-node"),
        ("parameters[5]", "duplicate-parameter"),
    ]


def test_a_container_declared_in_two_files_is_refused_alike_or_not(real):
    # rce-core's view_createContainer refuses a tag the user already has: applying the
    # second file fails even when it declares the container exactly as the first
    shared = {"cTag": "shared", "group": "g"}
    real[1]["containers"] = [dict(shared)]
    real[2]["containers"] = [dict(shared)]
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "lo_server.cfg",
        "containers[0]",
        "redeclared-container",
    )
    assert "lo_client.cfg (containers[0])" in problem.message
    real[2]["containers"] = [dict(shared, group="h")]
    (problem,) = check_configurations(real, NAMES)
    assert (problem.file, problem.path, problem.rule) == (
        "lo_server.cfg",
        "containers[0]",
        "conflicting-container",
    )
    assert "lo_client.cfg (containers[0])" in problem.message


def test_container_tag_may_not_be_a_robot(real):
    real[0]["containers"].append({"cTag": "server"})
    assert [(p.path, p.rule) for p in check_configurations(real, NAMES)] == [
        ("containers[3]", "endpoint-tag-clash")
    ]


def test_two_files_for_one_robot(real):
    real[1]["robotID"] = "server"
    assert "duplicate-robot" in {p.rule for p in check_configurations(real, NAMES)}


@pytest.mark.parametrize(
    ("edit", "path"),
    [
        (lambda c: c.pop("password"), ""),
        (lambda c: c.update(robotID="a/b"), "robotID"),
        (lambda c: c["containers"][1].update(groupIp="10.0.0.300"), "containers[1].groupIp"),
        (lambda c: c["containers"][1].update(groupIp="10.0.0"), "containers[1].groupIp"),
        (lambda c: c["interfaces"][0].update(iType="ServiceInterface"), "interfaces[0].iType"),
        (lambda c: c["interfaces"][0].update(iCls="StringEcho"), "interfaces[0].iCls"),
        (lambda c: c["parameters"][0].update(value={"a": 1}), "parameters[0].value"),
        (lambda c: c["nodes"][0].update(pkg="Test; rm -rf /"), "nodes[0].pkg"),
        (lambda c: c["nodes"][0].update(extra=1), "nodes[0]"),
        (lambda c: c.update(url="localhost"), "url"),
    ],
)
def test_schema_refuses_broken_files(real, edit, path):
    config = real[0]
    edit(config)
    problems = schema_problems(config, "debug.cfg")
    assert [p.path for p in problems] == [path]
    assert str(problems[0]).startswith("debug.cfg: ")


def test_groupip_accepts_an_address(real):
    real[0]["containers"][1]["groupIp"] = "10.0.3.254"
    assert schema_problems(real[0], "debug.cfg") == []


def test_connection_of_an_interface_to_itself(real):
    real[0]["connections"][0]["tagB"] = real[0]["connections"][0]["tagA"]
    problems = check_configurations(real, NAMES)
    assert ("connections[0]", "self-connection") in [(p.path, p.rule) for p in problems]


def test_interface_declared_differently_by_two_files(real):
    twin = dict(real[2]["interfaces"][0], iCls="Test/Other")
    real[1]["interfaces"].append(twin)
    problems = check_configurations(real, NAMES)
    assert ("lo_server.cfg", "interfaces[0]", "conflicting-interface") in [
        (p.file, p.path, p.rule) for p in problems
    ]


def test_a_connection_made_in_two_files_is_refused(real):
    # the engine refuses a pair already connected, whichever robot's file made it first
    made = real[1]["connections"][0]
    real[2].setdefault("connections", []).append(dict(made))
    rules = [(p.file, p.rule) for p in check_configurations(real, NAMES)]
    assert rules == [("lo_server.cfg", "duplicate-connection")]


def test_a_file_connects_only_to_interfaces_of_its_own_user(real):
    # lo_client.cfg connects to what lo_server.cfg declares: under another user, the
    # engine resolves none of those tags
    real[2]["userID"] = "otherUser"
    problems = check_configurations(real, NAMES)
    assert problems and {(p.file, p.rule) for p in problems} == {
        ("lo_client.cfg", "unresolved-tag")
    }
    assert "no file of user 'testUser' declares" in problems[0].message


def test_each_user_may_declare_a_container_of_its_own(real):
    shared = {"cTag": "shared", "group": "g"}
    real[1]["containers"] = [dict(shared)]
    real[2]["containers"] = [dict(shared)]
    real[2]["userID"] = "otherUser"
    real[2].pop("connections", None)  # its connections would name the other user's tags
    real[1].pop("connections", None)
    assert check_configurations(real, NAMES) == []
