"""zenoh-bridge-ros2dds configurations: read back with a real JSON5 reader, only keys
the bridge (and zenoh) document, allow lists derived by hand for the paper's product,
and for every product exactly the names that cross, nothing robot-local."""

from __future__ import annotations

from pathlib import Path

import json5
import pytest
import yaml

from spl.core.diagnostics import ModelError
from spl.dsl.tsm import language as tsm_language
from spl.generators.bundle.paths import Skipped
from spl.generators.kubernetes import manifests as kubernetes
from spl.generators.zenoh import configurations as zenoh
from spl.metamodels import tsm
from spl.resolver.analysis.formula import enumerate_products
from spl.resolver.architecture.product import ResolvedProduct, topic_ros_name
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import ProductSelection, selection_from_list

ROOT = Path(__file__).resolve().parents[2]
LINES = sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir())
MAPPING = ROOT / "product_lines" / "mapping3d"

# Every key path the configurations may use, as documented in
# eclipse-zenoh/zenoh-plugin-ros2dds DEFAULT_CONFIG.json5 (release 1.10.0): the bridge's
# plugins.ros2dds keys and the zenoh keys it shows; and, for authentication, zenoh's own
# DEFAULT_CONFIG.json5 (eclipse-zenoh/zenoh, transport.auth.usrpwd).
KINDS = (
    "publishers",
    "subscribers",
    "service_servers",
    "service_clients",
    "action_servers",
    "action_clients",
)
DOCUMENTED = {
    *(
        f"plugins.ros2dds.{key}"
        for key in (
            "nodename",
            "namespace",
            "domain",
            "ros_localhost_only",
            "ros_automatic_discovery_range",
            "ros_static_peers",
            "transient_local_cache_multiplier",
            "shm_enabled",
            "pub_max_frequencies",
            "pub_priorities",
            "reliable_routes_blocking",
            "queries_timeout",
            "work_thread_num",
            "max_block_thread_num",
        )
    ),
    *(f"plugins.ros2dds.{block}.{kind}" for block in ("allow", "deny") for kind in KINDS),
    "plugins.rest.http_port",
    "mode",
    "connect.endpoints",
    "listen.endpoints",
    *(
        f"scouting.multicast.{key}"
        for key in ("enabled", "address", "interface", "autoconnect", "listen")
    ),
    *(f"scouting.gossip.{key}" for key in ("enabled", "multihop", "autoconnect")),
    *(f"transport.auth.usrpwd.{key}" for key in ("user", "password", "dictionary_file")),
}


def leaf_keys(document: dict, prefix: str = "") -> set[str]:
    keys = set()
    for key, value in document.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict) and value:
            keys |= leaf_keys(value, path + ".")
        else:
            keys.add(path)
    return keys


def configs(files: dict[str, bytes], read: dict[bytes, dict] | None = None) -> dict[str, dict]:
    """Every JSON5 file of ``zenoh/``, read by the json5 reader (comments and all). What
    it reads is a function of the bytes, and the products of a line share most of their
    files: given ``read``, each distinct content is read once, into it."""
    read = {} if read is None else read
    found = {}
    for path, data in files.items():
        if path.endswith(".json5"):
            if data not in read:
                read[data] = json5.loads(data.decode("utf-8"))
            found[path.removeprefix("zenoh/").removesuffix(".json5")] = read[data]
    return found


def allow(document: dict) -> dict[str, list[str]]:
    return document["plugins"]["ros2dds"]["allow"]


def test_paper_product_allow_lists_derived_by_hand():
    line = load_product_line(MAPPING)
    product = resolve(line, selection_from_list("YouBot,Stereo,AdditionalPC,Room")).product
    found = configs(zenoh.generate(product))
    assert sorted(found) == [
        "MappingCloud_mappers",
        "MappingCloud_robot_1",
        "robot_1",
        "zenoh-router",
    ]
    # On the robot: the stereo pipeline's images go to VisualOdometry (private, in the
    # cloud), the map optimizer (migrated on board) sends its poses to StrategyPlanner
    # and calls the Database (both protected); keyframes come back from VisualOdometry.
    # /cmd_vel, the camera topics /stereo/left|right and /planning/trajectory stay.
    assert allow(found["robot_1"]) == {
        "publishers": ["/camera/depth/image", "/camera/rgb/image", "/mapping/pose_updated"],
        "subscribers": ["/mapping/keyframes"],
        "service_servers": [],
        "service_clients": [
            "/exploration/next_target",
            "/mapping/db/add_keyframe",
            "/mapping/db/update_poses",
        ],
        "action_servers": [],
        "action_clients": [],
    }
    assert allow(found["MappingCloud_robot_1"]) == {
        "publishers": ["/mapping/keyframes"],
        "subscribers": ["/camera/depth/image", "/camera/rgb/image"],
        **{kind: [] for kind in KINDS[2:]},
    }
    # get_map is called inside the protected instance only: it does not cross
    assert allow(found["MappingCloud_mappers"]) == {
        "publishers": [],
        "subscribers": ["/mapping/pose_updated"],
        "service_servers": [
            "/exploration/next_target",
            "/mapping/db/add_keyframe",
            "/mapping/db/update_poses",
        ],
        **{kind: [] for kind in KINDS[3:]},
    }
    # every bridge talking with robot_1 routes under its namespace: robot_1's keys only
    for name in ("robot_1", "MappingCloud_robot_1", "MappingCloud_mappers"):
        assert found[name]["plugins"]["ros2dds"]["namespace"] == "/robot_1"
    robot = found["robot_1"]
    assert robot["mode"] == "client"
    assert robot["connect"]["endpoints"] == ["tcp/cloud.example.org:7447"]
    assert robot["transport"]["auth"]["usrpwd"] == {"user": "mapper", "password": "${RCE_PASSWORD}"}
    assert found["MappingCloud_mappers"]["mode"] == "router"
    router = found["zenoh-router"]
    assert router["connect"]["endpoints"] == [
        "tcp/mappingcloud-mappers:7447",
        "tcp/mappingcloud-robot-1:7447",
    ]
    # the files the Kubernetes pods mount are these very configurations
    manifests = kubernetes.generate(product)
    assert b"/camera/depth/image" in manifests["kubernetes/mappingcloud-robot-1.yaml"]


def names_outside(system, robot) -> set[str]:
    """ROS names of the topics, services and actions nodes of other containers use, and
    of the robot's topics an endpoint connection takes elsewhere (under another name)."""
    T = tsm()
    names = set()
    for connection in system.connections:
        for end in (connection.source, connection.target):
            topic = end.topic if isinstance(end, T.Publisher | T.Subscriber) else None
            if topic is not None and topic.eContainer() is robot:
                names.add(topic_ros_name(topic))
    for container in system.containers:
        if container is robot:
            continue
        for node in container.nodes:
            for interface in node.interfaces:
                if isinstance(interface, T.Publisher | T.Subscriber) and interface.topic:
                    names.add(topic_ros_name(interface.topic))
                elif isinstance(interface, T.ServiceServer | T.ActionServer) and interface.rosName:
                    names.add(interface.rosName)
                elif isinstance(interface, T.ServiceClient | T.ActionClient) and interface.server:
                    # a server elsewhere, e.g. on the robot, called through an endpoint's
                    # stand-in named as it is
                    names |= {interface.server.rosName} - {None}
    return names


@pytest.mark.parametrize("directory", LINES, ids=lambda p: p.name)
def test_every_product_configuration_reads_back_with_documented_keys(directory):
    line = load_product_line(directory)
    carried = products = 0
    read: dict[bytes, dict] = {}
    for features in enumerate_products(line.fm):
        product = resolve(line, ProductSelection("p", sorted(features))).product
        files = zenoh.generate(product)
        products += 1
        if list(files) == ["zenoh/"]:
            assert isinstance(files["zenoh/"], Skipped)
            assert "Zenoh cannot carry this product" in files["zenoh/"].reason
            continue
        carried += 1
        if list(files) == ["zenoh/README.md"]:  # nothing crosses: nothing to configure
            assert "Zenoh has\nnothing to carry" in files["zenoh/README.md"].decode()
            continue
        found = configs(files, read)
        for name, document in found.items():
            assert leaf_keys(document) <= DOCUMENTED, name
        places = {n: d for n, d in found.items() if n != "zenoh-router"}
        # what one bridge routes out under a key, another routes in: both ends of every
        # crossing (a key is the bridge's namespace and the ROS name)
        for out_kind, in_kind in (
            ("publishers", "subscribers"),
            ("service_clients", "service_servers"),
            ("action_clients", "action_servers"),
        ):
            sent = {key for d in places.values() for key in keys(d, out_kind)}
            received = {key for d in places.values() for key in keys(d, in_kind)}
            assert sent == received, (features, out_kind)
        # a robot's bridge carries only names some node elsewhere uses, under its own
        # namespace, which no other robot's bridge uses
        robots = [c for c in product.system.containers if c.eClass.name == "RobotContainer"]
        spaces = [namespace(found[r.endpoint.robotId]) for r in robots]
        assert len(set(spaces)) == len(spaces) and "" not in spaces
        for robot in robots:
            lists = allow(found[robot.endpoint.robotId])
            used = {x for kind in KINDS for x in lists[kind]}
            assert used <= names_outside(product.system, robot), (features, robot.name)
    assert carried == products  # every product of the shipped lines


def namespace(document: dict) -> str:
    return document.get("plugins", {}).get("ros2dds", {}).get("namespace", "")


def keys(document: dict, kind: str) -> set[str]:
    return {namespace(document) + name for name in allow(document)[kind]}


def test_two_robots_are_isolated_by_their_namespaces():
    """Both robots publish /camera/rgb/image, each for its own private VisualOdometry:
    each robot's bridge, and each bridge talking with it, routes under the robot's
    namespace, so no instance receives the other robot's images; the protected instance
    serves each robot through a bridge of its own."""
    system = tsm_language.parse_file(Path(__file__).parents[1] / "models/rapyuta/two_robots.tsm")
    found = configs(zenoh.generate(ResolvedProduct("two", system, ())))
    spaces = {name: namespace(document) for name, document in found.items()}
    assert spaces == {
        "alpha": "/alpha",
        "beta": "/beta",
        "MappingCloud_alpha": "/alpha",
        "MappingCloud_beta": "/beta",
        "MappingCloud_mappers": "",  # get_map for the public MapMerger
        "MappingCloud_mappers.2": "/alpha",
        "MappingCloud_mappers.3": "/beta",
        "MappingCloud_public": "",
        "zenoh-router": "",
    }
    assert keys(found["alpha"], "publishers") == {"/alpha/camera/rgb/image"}
    assert keys(found["MappingCloud_beta"], "subscribers") == {"/beta/camera/rgb/image"}
    assert keys(found["MappingCloud_mappers.3"], "service_servers") == {
        "/beta/exploration/next_target",
        "/beta/mapping/db/add_keyframe",
    }
    assert keys(found["MappingCloud_mappers"], "service_servers") == {"/mapping/db/get_map"}
    # the shared pod runs three bridges, the router connects to each
    router = found["zenoh-router"]["connect"]["endpoints"]
    assert [e for e in router if "mappers" in e] == [
        "tcp/mappingcloud-mappers:7447",
        "tcp/mappingcloud-mappers:7448",
        "tcp/mappingcloud-mappers:7449",
    ]
    manifests = kubernetes.generate(ResolvedProduct("two", system, ()))
    pod = yaml.safe_load_all(manifests["kubernetes/mappingcloud-mappers.yaml"])
    deployment = next(d for d in pod if d["kind"] == "Deployment")
    sidecars = deployment["spec"]["template"]["spec"]["containers"][1:]
    assert [(c["name"], c["ports"][0]["containerPort"]) for c in sidecars] == [
        ("zenoh-bridge", 7447),
        ("zenoh-bridge-2", 7448),
        ("zenoh-bridge-3", 7449),
    ]


def test_orchard_renames_by_the_robots_namespace():
    """The harvester's /camera/image_raw is /harvester/camera/image_raw in the cloud:
    the harvester's bridge routes under /harvester, the cloud end under no namespace."""
    line = load_product_line(ROOT / "product_lines" / "orchard")
    selection = selection_from_list(
        "CloudDetection,CloudPlanning,SoftGripper,Scouting,YieldMapping"
    )
    found = configs(zenoh.generate(resolve(line, selection).product))
    assert keys(found["harvester_1"], "publishers") == {"/harvester/camera/image_raw"}
    assert keys(found["scout_1"], "publishers") == {"/scout/camera/image_raw"}
    assert keys(found["OrchardCloud_harvester_1"], "subscribers") == {"/harvester/camera/image_raw"}
    assert keys(found["OrchardCloud_orchard"], "subscribers") == {"/scout/camera/image_raw"}
    # the detections go back to the harvester under its namespace
    assert keys(found["OrchardCloud_harvester_1.2"], "publishers") == {
        "/harvester/fruit/detections"
    }


def test_a_product_zenoh_cannot_carry_is_skipped_with_the_reason(tmp_path):
    """A bridge renaming /scan to /laser: no namespace in front of a name gives it."""
    path = tmp_path / "small.tsm"
    path.write_text(
        ONE_ROBOT.replace("ROBOT_ID", "rover_1")
        .replace("DRONE_PASSWORD", "ROVER_PASSWORD")
        .replace(
            'Cloud {\n    topic Scan : sensor_msgs/LaserScan name "/scan"',
            'Cloud {\n    topic Scan : sensor_msgs/LaserScan name "/laser"',
        )
    )
    product = ResolvedProduct("small", tsm_language.parse_file(path), ())
    files = zenoh.generate(product)
    reason = files["zenoh/"].reason
    assert reason == (
        "Zenoh cannot carry this product: the topic /scan of rover_1 arrives in "
        "Cloud_rover_1 as /laser (Rover.Lidar.scan -> Cloud.Mapper.scan), which no bridge "
        "namespace gives"
    )
    readme = kubernetes.generate(product)["kubernetes/README.md"].decode()
    assert "NOT carried" in readme
    manifests = kubernetes.generate(product)
    assert b"zenoh-bridge" not in manifests["kubernetes/cloud-rover-1.yaml"]
    assert "kubernetes/zenoh-router.yaml" not in manifests


ONE_ROBOT = """system Small

robot container Rover {
    endpoint robot_id "ROBOT_ID" url "wss://cloud.example.org:9000/" user "rover"
             password env "ROVER_PASSWORD"
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Lidar {
        implementation urg_node/urg_node
        publishes scan -> Scan
    }
}

robot container Drone {
    endpoint robot_id "drone_1" url "wss://cloud.example.org:9000/" user "rover"
             password env "DRONE_PASSWORD"
}

cloud container Cloud {
    topic Scan : sensor_msgs/LaserScan name "/scan"
    node Mapper {
        implementation gmapping/slam_gmapping
        subscribes scan <- Scan
    }
}

bridge Rover.Scan -> Cloud.Scan
"""


@pytest.mark.parametrize(
    ("robot_id", "drone_env", "message"),
    [
        (
            "zenoh-router",
            "ROVER_PASSWORD",
            "robot_id 'zenoh-router' is the Zenoh router's file name",
        ),
        (
            "rover_1",
            "DRONE_PASSWORD",
            "user rover authenticates with password env DRONE_PASSWORD here and ROVER_PASSWORD "
            "in robot container Rover: the Zenoh router keeps one password per user",
        ),
    ],
)
def test_robot_names_and_users_the_router_cannot_take_are_located_errors(
    tmp_path, robot_id, drone_env, message
):
    path = tmp_path / "small.tsm"
    path.write_text(ONE_ROBOT.replace("ROBOT_ID", robot_id).replace("DRONE_PASSWORD", drone_env))
    product = ResolvedProduct("small", tsm_language.parse_file(path), ())
    with pytest.raises(ModelError) as raised:
        zenoh.generate(product)
    (diagnostic,) = raised.value.diagnostics
    assert diagnostic.message == message
    assert str(diagnostic).startswith(f"{path}:")


def test_a_small_product_carried_with_its_users():
    path_text = ONE_ROBOT.replace("ROBOT_ID", "rover_1").replace("DRONE_PASSWORD", "ROVER_PASSWORD")
    system = tsm_language.parse_text(path_text, "small.tsm")
    found = configs(zenoh.generate(ResolvedProduct("small", system, ())))
    assert allow(found["rover_1"])["publishers"] == ["/scan"]
    assert allow(found["Cloud_rover_1"])["subscribers"] == ["/scan"]
    assert allow(found["drone_1"]) == {kind: [] for kind in KINDS}
    files = kubernetes.generate(ResolvedProduct("small", system, ()))
    readme = files["kubernetes/README.md"].decode()
    assert '--from-literal=rover-password="$ROVER_PASSWORD"' in readme


@pytest.mark.parametrize("directory", LINES, ids=lambda p: p.name)
def test_zenoh_and_kubernetes_agree_on_the_router(directory):
    """A bundle runs a Zenoh router exactly when some data crosses between places: then
    both folders have it and the robots' bridges connect to it; otherwise neither has
    it, zenoh/ holds no bridge pointing at it, and both READMEs say so."""
    line = load_product_line(directory)
    quiet = 0
    for features in enumerate_products(line.fm):
        product = resolve(line, ProductSelection("p", sorted(features))).product
        files = {**zenoh.generate(product), **kubernetes.generate(product)}
        routed = "kubernetes/zenoh-router.yaml" in files
        assert routed == ("zenoh/zenoh-router.json5" in files), sorted(features)
        if not routed:
            quiet += 1
            assert [p for p in files if p.startswith("zenoh/")] == ["zenoh/README.md"]
            assert "no Zenoh router" in files["kubernetes/README.md"].decode()
    # data acquisition carries its data over HTTP to the stores: nothing crosses in ROS
    assert quiet > 0 or directory.name != "data_acquisition"
