"""The resolved mapping product of the mapping paper's Fig. 5, built with the metamodel classes.

YouBot, Stereo, AdditionalPC, Room: MapOptimizer migrated to the robot, the robot
endpoint mirroring its cloud-side connections (docs/product-lines.md).
Shared by the launch and diagram tests until resolved products come from .tsm text.
"""

from __future__ import annotations

from typing import Any

from spl.metamodels import tsm
from spl.resolver.architecture.product import NodeMigration, ResolvedProduct


def _node(container: Any, name: str, impl: str | None, **features: Any) -> Any:
    T = tsm()
    package, executable = impl.split("/") if impl else (None, None)
    node = T.Node(name=name, package=package, executable=executable, **features)
    container.nodes.append(node)
    return node


def _topic(container: Any, name: str, type_: str, ros_name: str | None = None) -> Any:
    topic = tsm().Topic(name=name, type=type_, rosName=ros_name)
    container.topics.append(topic)
    return topic


def _pub(owner: Any, name: str, topic: Any) -> Any:
    interface = tsm().Publisher(name=name, type=topic.type, topic=topic)
    owner.interfaces.append(interface)
    return interface


def _sub(owner: Any, name: str, topic: Any) -> Any:
    interface = tsm().Subscriber(name=name, type=topic.type, topic=topic)
    owner.interfaces.append(interface)
    return interface


def _server(owner: Any, name: str, type_: str, ros_name: str | None = None) -> Any:
    interface = tsm().ServiceServer(name=name, type=type_, rosName=ros_name)
    owner.interfaces.append(interface)
    return interface


def _client(owner: Any, name: str, server: Any) -> Any:
    interface = tsm().ServiceClient(name=name, type=server.type, server=server)
    owner.interfaces.append(interface)
    return interface


def _param(node: Any, name: str, kind: str, value: str | None) -> Any:
    T = tsm()
    parameter = T.Parameter(name=name, type=T.ParameterType.getEEnumLiteral(kind), value=value)
    node.parameters.append(parameter)
    return parameter


def mapping_product(string_value: str = "package://stereo_cam/calibration.yaml") -> ResolvedProduct:
    T = tsm()
    system = T.System(name="Mapping3D")
    robot = T.RobotContainer(name="Robot", namespace="/youbot")
    robot.endpoint = T.Endpoint(
        robotId="robot_1",
        url="wss://cloud.example.org:9000/",
        user="mapper",
        passwordEnv="RCE_PASSWORD",
    )
    cloud = T.CloudContainer(name="MappingCloud", group="mappers")
    cloud.endpoint = T.Endpoint()
    system.containers.extend([robot, cloud])

    rgb = _topic(robot, "RGBImg", "sensor_msgs/Image", "/camera/rgb/image")
    depth = _topic(robot, "DepthImg", "sensor_msgs/Image", "/camera/depth/image")
    pose = _topic(robot, "PoseUpdated", "std_msgs/Header", "/pose_updated")
    trajectory = _topic(
        robot, "Trajectory", "trajectory_msgs/MultiDOFJointTrajectory", "/trajectory"
    )
    twist = _topic(robot, "Twist", "geometry_msgs/Twist", "/cmd_vel")
    left = _topic(robot, "LeftImg", "sensor_msgs/Image", "/stereo/left")
    right = _topic(robot, "RightImg", "sensor_msgs/Image", "/stereo/right")
    keyframes_r = _topic(robot, "Keyframes", "rapyuta_msgs/Keyframe")

    c_rgb = _topic(cloud, "RGBImg", "sensor_msgs/Image", "/camera/rgb/image")
    c_depth = _topic(cloud, "DepthImg", "sensor_msgs/Image", "/camera/depth/image")
    c_pose = _topic(cloud, "PoseUpdated", "std_msgs/Header", "/pose_updated")
    keyframes = _topic(cloud, "Keyframes", "rapyuta_msgs/Keyframe")

    cam_l = _node(robot, "RGBCameraL", "stereo_cam/camera_node", optional=True)
    _pub(cam_l, "image", left)
    cam_r = _node(robot, "RGBCameraR", "stereo_cam/camera_node", optional=True)
    _pub(cam_r, "image", right)
    stereo = _node(robot, "StereoVision", "stereo_cam/stereo_vision", optional=True)
    _sub(stereo, "left", left)
    _sub(stereo, "right", right)
    _pub(stereo, "rgb", rgb)
    _pub(stereo, "depth", depth)
    controller = _node(robot, "RobotController", "youbot_control/robot_controller")
    _sub(controller, "pose_updated", pose)
    _pub(controller, "trajectory", trajectory)
    follower = _node(robot, "TrajectoryFollower", "youbot_control/trajectory_follower")
    _sub(follower, "trajectory", trajectory)
    _pub(follower, "cmd_vel", twist)
    driver = _node(robot, "RobotDriver", "youbot_driver/youbot_driver_node", args="--verbose")
    _param(driver, "port", "string", "/dev/ttyUSB0")
    _param(driver, "rate", "double", "20.0")
    _param(driver, "retries", "int", "3")
    _param(driver, "simulate", "bool", "false")
    _param(driver, "limits", "yaml", "{max_vel: 0.8, joints: [1, 2, 3]}")
    _param(driver, "frame", "string", None)
    _sub(driver, "cmd_vel", twist)
    optimizer = _node(robot, "MapOptimizer", "rapyuta_mapping/map_optimizer")
    _param(optimizer, "CameraInfo", "string", string_value)
    _sub(optimizer, "keyframes", keyframes_r)
    _pub(optimizer, "pose_updated", pose)

    odometry = _node(cloud, "VisualOdometry", "rapyuta_mapping/visual_odometry")
    _sub(odometry, "rgb", c_rgb)
    _sub(odometry, "depth", c_depth)
    _pub(odometry, "keyframes", keyframes)
    protected = T.SharingMode.protected
    database = _node(cloud, "Database", "rapyuta_mapping/database", sharing=protected)
    add_keyframe = _server(database, "add_keyframe", "rapyuta_msgs/AddKeyframe", "/db/add_keyframe")
    update_poses = _server(database, "update_poses", "rapyuta_msgs/UpdatePoses")
    get_map = _server(database, "get_map", "rapyuta_msgs/GetMap", "/db/get_map")
    merger = _node(cloud, "MapMerger", "rapyuta_mapping/map_merger", sharing=protected)
    _client(merger, "get_map", get_map)
    planner = _node(cloud, "StrategyPlanner", "exploration/room_strategy", sharing=protected)
    _sub(planner, "pose_updated", c_pose)
    _client(planner, "get_map", get_map)
    next_target = _server(planner, "next_target", "rapyuta_msgs/NextTarget", "/next_target")

    # Endpoint interfaces and connections, as the Resolution Engine creates them.
    ep_r, ep_c = robot.endpoint, cloud.endpoint
    bridges = [
        (_sub(ep_r, "sub_RGBImg", rgb), _pub(ep_c, "pub_RGBImg", c_rgb)),
        (_sub(ep_r, "sub_DepthImg", depth), _pub(ep_c, "pub_DepthImg", c_depth)),
        (_sub(ep_r, "sub_PoseUpdated", pose), _pub(ep_c, "pub_PoseUpdated", c_pose)),
        (_sub(ep_c, "sub_Keyframes", keyframes), _pub(ep_r, "pub_Keyframes", keyframes_r)),
    ]
    services = []
    for server in (add_keyframe, update_poses):
        stand_in = _server(ep_r, f"srv_Database_{server.name}", server.type, server.rosName)
        _client(optimizer, server.name, stand_in)
        services.append((stand_in, _client(ep_c, f"cli_Database_{server.name}", server)))
    stand_in = _server(
        ep_r, "srv_StrategyPlanner_next_target", next_target.type, next_target.rosName
    )
    _client(controller, "next_target", stand_in)
    services.append((stand_in, _client(ep_c, "cli_StrategyPlanner_next_target", next_target)))
    for source, target in bridges + services:
        system.connections.append(T.EndpointConnection(source=source, target=target))

    return ResolvedProduct(
        name="youbot_stereo_room",
        system=system,
        features=("AdditionalPC", "Mapping", "Room", "Stereo", "YouBot"),
        migrations=(NodeMigration("MapOptimizer", "MappingCloud", "Robot"),),
    )
