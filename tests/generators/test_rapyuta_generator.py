"""Rapyuta generator: sharing placement, partition bridging, credentials, determinism.

Models are built with the metamodel's classes (bridges with the resolver's canonical
endpoint helpers, exactly as the .tsm builder and the Resolution Engine create them)."""

from __future__ import annotations

import json

import pytest

from spl.core.diagnostics import ModelError
from spl.generators.rapyuta.configurations import generate, parameter_value
from spl.generators.rapyuta.rules import check_all
from spl.metamodels import tsm
from spl.resolver.architecture import endpoints
from spl.resolver.architecture.product import ResolvedProduct

from support.mapping_system import (
    calls,
    cloud,
    mapping_system,
    node,
    provides,
    pub,
    robot,
    sub,
    topic,
)

T = tsm()


def product(system):
    return ResolvedProduct(name="p", system=system, features=())


def documents(files):
    return {path: json.loads(data) for path, data in files.items()}


def assert_engine_accepts(files):
    configs = list(documents(files).values())
    names = [path.rsplit("/", 1)[1] for path in files]
    assert [str(p) for p in check_all(configs, names)] == []


def test_mapping3d_file_places_nodes_by_sharing_and_bridges_partitions():
    files = generate(product(mapping_system()))
    assert list(files) == ["rapyuta/Robot.json"]
    assert_engine_accepts(files)
    doc = documents(files)["rapyuta/Robot.json"]
    assert doc["containers"] == [
        {"cTag": "MappingCloud_mappers", "cpu": 2, "group": "mappers", "memory": 2048},
        {"cTag": "MappingCloud_robot_1", "cpu": 2, "memory": 2048},
    ]
    assert [(n["cTag"], n["nTag"]) for n in doc["nodes"]] == [
        ("MappingCloud_mappers", "Database"),
        ("MappingCloud_mappers", "MapMerger"),
        ("MappingCloud_mappers", "StrategyPlanner"),
        ("MappingCloud_robot_1", "MapOptimizer"),
        ("MappingCloud_robot_1", "VisualOdometry"),
    ]
    assert doc["nodes"][3] == {
        "cTag": "MappingCloud_robot_1",
        "nTag": "MapOptimizer",
        "name": "MapOptimizer",
        "pkg": "rapyuta_mapping",
        "exe": "map_optimizer",
    }
    assert [(c["tagA"], c["tagB"]) for c in doc["connections"]] == [
        # private MapOptimizer -> protected Database (services) and StrategyPlanner (topic)
        (
            "MappingCloud_robot_1/srv_Database_add_keyframe",
            "MappingCloud_mappers/cli_Database_add_keyframe",
        ),
        (
            "MappingCloud_robot_1/srv_Database_update_poses",
            "MappingCloud_mappers/cli_Database_update_poses",
        ),
        ("MappingCloud_robot_1/sub_PoseUpdated", "MappingCloud_mappers/pub_PoseUpdated"),
        ("MappingCloud_robot_1/sub_PoseUpdated", "robot_1/pub_PoseUpdated"),
        (
            "robot_1/srv_StrategyPlanner_next_target",
            "MappingCloud_mappers/cli_StrategyPlanner_next_target",
        ),
        ("robot_1/sub_DepthImg", "MappingCloud_robot_1/pub_DepthImg"),
        ("robot_1/sub_RGBImg", "MappingCloud_robot_1/pub_RGBImg"),
    ]
    interfaces = {(i["eTag"], i["iTag"]): i for i in doc["interfaces"]}
    assert interfaces[("robot_1", "sub_RGBImg")] == {
        "eTag": "robot_1",
        "iTag": "sub_RGBImg",
        "iType": "SubscriberConverter",
        "iCls": "sensor_msgs/Image",
        "addr": "/camera/rgb/image",
    }
    assert interfaces[("MappingCloud_mappers", "cli_Database_add_keyframe")] == {
        "eTag": "MappingCloud_mappers",
        "iTag": "cli_Database_add_keyframe",
        "iType": "ServiceClientInterface",
        "iCls": "rapyuta_msgs/AddKeyframe",
        "addr": "/db/add_keyframe",
    }
    assert interfaces[("robot_1", "srv_StrategyPlanner_next_target")]["iType"] == (
        "ServiceProviderConverter"
    )
    # minimal: every interface carries something; nothing local is bridged
    used = {tag for c in doc["connections"] for tag in (c["tagA"], c["tagB"])}
    assert {f"{e}/{i}" for e, i in interfaces} == used
    assert not any("Keyframes" in tag or "get_map" in tag for tag in used)


def test_parameters_are_typed_and_named_after_the_node():
    doc = documents(generate(product(mapping_system())))["rapyuta/Robot.json"]
    values = {p["name"]: p["value"] for p in doc["parameters"]}
    assert values == {
        "/MapOptimizer/CameraInfo": "package://rapyuta_mapping/cam/default.yaml",
        "/MapOptimizer/iterations": 10,
        "/MapOptimizer/robust": True,
        "/MapOptimizer/weights": [1, 2.5, "x"],
        "/MapOptimizer/bounds": "{min: 0, max: 3}",  # a mapping stays YAML text
    }
    assert {p["cTag"] for p in doc["parameters"]} == {"MappingCloud_robot_1"}
    # robot-side parameters belong to the robot's launch file, not to the engine
    assert "/RobotDriver/port" not in values


@pytest.mark.parametrize(
    ("ptype", "text", "value"),
    [
        ("int", "-3", -3),
        ("double", "2.0", 2.0),
        ("bool", "false", False),
        ("string", "a b", "a b"),
        ("yaml", "3", 3),
        ("yaml", "[a, [b]]", "[a, [b]]"),
    ],
)
def test_parameter_values(ptype, text, value):
    parameter = T.Parameter(name="p", type=T.ParameterType.getEEnumLiteral(ptype), value=text)
    result = parameter_value(parameter)
    assert result == value and type(result) is type(value)


def test_password_is_a_placeholder_never_the_secret(monkeypatch):
    monkeypatch.setenv("RCE_PASSWORD", "s3cret-Value")
    files = generate(product(mapping_system()))
    data = files["rapyuta/Robot.json"]
    assert b"s3cret-Value" not in data
    doc = json.loads(data)
    assert doc["password"] == "${RCE_PASSWORD}"
    assert (doc["url"], doc["userID"], doc["robotID"]) == (
        "wss://cloud.example.org:9000/",
        "mapper",
        "robot_1",
    )


def test_output_is_deterministic_and_independent_of_model_order():
    first = generate(product(mapping_system(robots=(("A", "robot_a"), ("B", "robot_b")))))
    again = generate(product(mapping_system(robots=(("A", "robot_a"), ("B", "robot_b")))))
    reordered = generate(
        product(mapping_system(robots=(("A", "robot_a"), ("B", "robot_b")), reverse=True))
    )
    assert first == again == reordered
    text = first["rapyuta/A.json"].decode()
    assert text.endswith("}\n") and text.startswith('{\n  "connections": [')
    assert text == json.dumps(json.loads(text), indent=2, sort_keys=True) + "\n"


def test_two_robots_share_the_protected_container_and_keep_private_ones():
    files = generate(product(mapping_system(robots=(("A", "robot_a"), ("B", "robot_b")))))
    assert_engine_accepts(files)
    a, b = documents(files)["rapyuta/A.json"], documents(files)["rapyuta/B.json"]

    def of(doc, key, tag_key, tag):
        return [e for e in doc[key] if e[tag_key] == tag]

    shared = "MappingCloud_mappers"
    # the shared container is declared by the first robot's file only (the engine refuses
    # a tag its user already has); B's file connects to the interfaces A's declares
    for key, tag_key in (
        ("containers", "cTag"),
        ("nodes", "cTag"),
        ("parameters", "cTag"),
        ("interfaces", "eTag"),
    ):
        assert key == "parameters" or of(a, key, tag_key, shared), key  # it has none
        assert of(b, key, tag_key, shared) == [], key
    assert of(a, "containers", "cTag", shared) == [
        {"cTag": shared, "cpu": 2, "group": "mappers", "memory": 2048}
    ]
    assert [c["cTag"] for c in a["containers"]] == [shared, "MappingCloud_robot_a"]
    assert [c["cTag"] for c in b["containers"]] == ["MappingCloud_robot_b"]
    # A's file declares the shared interfaces B's private optimizer and robot connect to
    assert {i["iTag"] for i in of(a, "interfaces", "eTag", shared)} >= {
        "cli_Database_add_keyframe",
        "cli_StrategyPlanner_next_target",
    }
    # each robot's private optimizer calls the one shared Database through one client
    assert {
        "tagA": "MappingCloud_robot_b/srv_Database_add_keyframe",
        "tagB": f"{shared}/cli_Database_add_keyframe",
    } in b["connections"]
    assert not any("robot_a" in json.dumps(c) for c in b["connections"])
    assert not any(i["eTag"] in ("robot_a", "MappingCloud_robot_a") for i in b["interfaces"])
    assert {i["eTag"] for i in a["interfaces"]} == {"robot_a", "MappingCloud_robot_a", shared}
    # the shared planner's stand-in client serves both robots
    assert {
        "tagA": "robot_a/srv_StrategyPlanner_next_target",
        "tagB": f"{shared}/cli_StrategyPlanner_next_target",
    } in a["connections"]
    assert {
        "tagA": "robot_b/srv_StrategyPlanner_next_target",
        "tagB": f"{shared}/cli_StrategyPlanner_next_target",
    } in b["connections"]


def test_public_nodes_go_to_one_container_for_everybody():
    system = mapping_system(robots=(("A", "robot_a"), ("B", "robot_b")))
    cloud_container = next(c for c in system.containers if c.name == "MappingCloud")
    merger = next(n for n in cloud_container.nodes if n.name == "MapMerger")
    merger.sharing = T.SharingMode.public
    files = generate(product(system))
    assert_engine_accepts(files)
    a, b = documents(files)["rapyuta/A.json"], documents(files)["rapyuta/B.json"]
    assert [c for c in a["containers"] if c["cTag"] == "MappingCloud_public"] == [
        {"cTag": "MappingCloud_public", "cpu": 2, "memory": 2048}
    ]
    assert [n["nTag"] for n in a["nodes"] if n["cTag"] == "MappingCloud_public"] == ["MapMerger"]
    # public merger -> protected database: one connection, in the file declaring both
    bridge = {
        "tagA": "MappingCloud_public/srv_Database_get_map",
        "tagB": "MappingCloud_mappers/cli_Database_get_map",
    }
    assert bridge in a["connections"] and bridge not in b["connections"]
    assert not any(c["cTag"].endswith(("_public", "_mappers")) for c in b["containers"])


def test_group_defaults_to_the_container_name():
    system = mapping_system()
    next(c for c in system.containers if c.name == "MappingCloud").group = None
    doc = documents(generate(product(system)))["rapyuta/Robot.json"]
    assert doc["containers"][0] == {
        "cTag": "MappingCloud_MappingCloud",
        "cpu": 2,
        "group": "MappingCloud",
        "memory": 2048,
    }


def test_cloud_behind_a_cloud_is_used_and_relays_are_skipped():
    # Robot -> Relay (no node) -> Archive: the robot feeds the archive directly
    system = T.System(name="S")
    r = robot(system, "Robot", "robot_1")
    scan = topic(r, "Scan", "sensor_msgs/LaserScan", "/scan")
    pub(node(r, "Lidar", "lidar/driver"), "scan", scan)
    relay = cloud(system, "Relay")
    relay_scan = topic(relay, "Scan", "sensor_msgs/LaserScan", "/scan")
    archive = cloud(system, "Archive")
    archive_scan = topic(archive, "Scans", "sensor_msgs/LaserScan", "/archive/scan")
    sub(node(archive, "Recorder", "archive/recorder", sharing="public"), "scan", archive_scan)
    endpoints.topic_bridge(system, scan, relay_scan)
    endpoints.topic_bridge(system, relay_scan, archive_scan)
    files = generate(product(system))
    assert_engine_accepts(files)
    doc = documents(files)["rapyuta/Robot.json"]
    assert [c["cTag"] for c in doc["containers"]] == ["Archive_public"]
    assert doc["connections"] == [{"tagA": "robot_1/sub_Scan", "tagB": "Archive_public/pub_Scans"}]
    assert [i["addr"] for i in doc["interfaces"]] == ["/archive/scan", "/scan"]


def test_a_robot_without_cloud_gets_credentials_only():
    system = T.System(name="S")
    robot(system, "Lonely", "lonely")
    doc = documents(generate(product(system)))["rapyuta/Lonely.json"]
    assert sorted(doc) == ["password", "robotID", "url", "userID"]


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda s: setattr(s.containers[1].endpoint, "robotId", 'x", "evil": "1'),
            "is not a Rapyuta tag",
        ),
        (  # was "robot_id None is not a Rapyuta tag"
            lambda s: setattr(s.containers[1].endpoint, "robotId", None),
            "no robot_id: give the robot's endpoint one",
        ),
        (
            lambda s: setattr(s.containers[1].endpoint, "passwordEnv", "$(reboot)"),
            "is not an environment variable name",
        ),
        (lambda s: setattr(s.containers[1].endpoint, "passwordEnv", None), "has no password"),
        (lambda s: setattr(s.containers[0], "group", "a/b"), "is not a Rapyuta tag"),
        (lambda s: setattr(s.containers[1].endpoint, "robotId", "mappers"), "would name both"),
    ],
)
def test_unusable_model_values_are_located_errors(edit, message):
    system = mapping_system(robots=(("Robot", "robot_1"), ("Other", "robot_2")))
    edit(system)
    system.containers[1].endpoint.srcFile = "m.tsm"
    system.containers[1].endpoint.srcLine = 7
    system.containers[1].endpoint.srcCol = 5
    system.containers[0].srcFile, system.containers[0].srcLine = "m.tsm", 20
    with pytest.raises(ModelError) as caught:
        generate(product(system))
    text = str(caught.value)
    assert message in text
    assert "m.tsm:" in text


def test_type_mismatch_across_a_bridge_is_refused():
    system = mapping_system()
    next(c for c in system.containers if c.name == "MappingCloud").topics[
        0
    ].type = "sensor_msgs/CompressedImage"
    with pytest.raises(ModelError, match="sensor_msgs/Image but it expects"):
        generate(product(system))


def test_namespaces_and_unnamed_ros_names_resolve_as_in_the_launch_files():
    system = T.System(name="S")
    r = robot(system, "Robot", "robot_1")
    c = cloud(system, "Cloud", namespace="mapping")
    odom_cloud = topic(c, "Odom", "nav_msgs/Odometry", None)  # launch: /Odom
    odom_robot = topic(r, "Odom", "nav_msgs/Odometry", None)
    planner = node(c, "Planner", "nav/planner", params=[("rate", "double", "5")])
    pub(planner, "odom", odom_cloud)
    plan = provides(planner, "plan", "nav_msgs/GetPlan", None)  # relative: plan
    navigator = node(r, "Navigator", "nav/navigator")
    sub(navigator, "odom", odom_robot)
    client = calls(navigator, "plan", plan)
    endpoints.topic_bridge(system, odom_cloud, odom_robot)
    endpoints.service_bridge(system, client, plan)
    files = generate(product(system))
    assert_engine_accepts(files)
    doc = documents(files)["rapyuta/Robot.json"]
    assert {(i["eTag"], i["iTag"]): i["addr"] for i in doc["interfaces"]} == {
        ("Cloud_robot_1", "cli_Planner_plan"): "/mapping/plan",
        ("Cloud_robot_1", "sub_Odom"): "/Odom",
        ("robot_1", "pub_Odom"): "/Odom",
        ("robot_1", "srv_Planner_plan"): "plan",
    }
    assert doc["nodes"][0]["namespace"] == "mapping"
    assert doc["parameters"] == [
        {"cTag": "Cloud_robot_1", "name": "/mapping/Planner/rate", "value": 5.0}
    ]


def test_robot_to_robot_bridge_like_the_engines_loopback_example():
    # as lo_client.cfg / lo_server.cfg: each robot declares its own converters
    system = T.System(name="S")
    server, client = robot(system, "Server", "server"), robot(system, "Client", "client")
    request_s = topic(server, "Req", "std_msgs/String", "/stringEchoReq")
    request_c = topic(client, "Req", "std_msgs/String", "/clientReq")
    echo = node(server, "Echo", "Test/stringEcho")
    sub(echo, "req", request_s)
    echo_service = provides(echo, "echo", "Test/StringEcho", "/stringEchoService")
    user = node(client, "User", "Test/user")
    pub(user, "req", request_c)
    endpoints.topic_bridge(system, request_c, request_s)
    endpoints.service_bridge(system, calls(user, "echo", echo_service), echo_service)
    files = generate(product(system))
    assert_engine_accepts(files)
    docs = documents(files)
    assert docs["rapyuta/Client.json"]["interfaces"] == [
        {
            "addr": "/stringEchoService",
            "eTag": "client",
            "iCls": "Test/StringEcho",
            "iTag": "srv_Echo_echo",
            "iType": "ServiceProviderConverter",
        },
        {
            "addr": "/clientReq",
            "eTag": "client",
            "iCls": "std_msgs/String",
            "iTag": "sub_Req",
            "iType": "SubscriberConverter",
        },
    ]
    assert [i["iType"] for i in docs["rapyuta/Server.json"]["interfaces"]] == [
        "ServiceClientConverter",
        "PublisherConverter",
    ]
    # each connection is made once, by the first robot's file (as lo_client.cfg makes them)
    assert len(docs["rapyuta/Client.json"]["connections"]) == 2
    assert "connections" not in docs["rapyuta/Server.json"]
    assert "containers" not in docs["rapyuta/Client.json"]


def test_two_robots_with_one_robot_id_are_refused():
    system = mapping_system(robots=(("Robot", "robot_1"), ("Other", "robot_1")))
    other = system.containers[2]
    other.srcFile, other.srcLine, other.srcCol = "m.tsm", 40, 1
    with pytest.raises(ModelError) as caught:
        generate(product(system))
    assert str(caught.value) == (
        "m.tsm:40:1: error: Rapyuta tag 'robot_1' would name both robot container Robot and "
        "robot container Other: rename a container, group or robot_id"
    )
