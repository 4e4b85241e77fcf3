"""The mapping3d architecture of case study 1 built with the metamodel's classes, with
one or several robots, bridges made by the resolver's canonical endpoint helpers (as the
.tsm builder and the Resolution Engine make them); small builders for each element."""

from __future__ import annotations

from spl.metamodels import tsm
from spl.resolver.architecture import endpoints

T = tsm()


def robot(system, name, robot_id, env="RCE_PASSWORD"):
    container = T.RobotContainer(name=name)
    container.endpoint = T.Endpoint(
        robotId=robot_id, url="wss://cloud.example.org:9000/", user="mapper", passwordEnv=env
    )
    system.containers.append(container)
    return container


def cloud(system, name, group=None, **resources):
    container = T.CloudContainer(name=name, group=group, **resources)
    container.endpoint = T.Endpoint()
    system.containers.append(container)
    return container


def topic(container, name, type_, ros):
    t = T.Topic(name=name, type=type_, rosName=ros)
    container.topics.append(t)
    return t


def node(container, name, impl, sharing="private", params=()):
    package, executable = impl.split("/")
    n = T.Node(
        name=name,
        package=package,
        executable=executable,
        sharing=T.SharingMode.getEEnumLiteral(sharing),
    )
    for pname, ptype, value in params:
        n.parameters.append(
            T.Parameter(name=pname, type=T.ParameterType.getEEnumLiteral(ptype), value=value)
        )
    container.nodes.append(n)
    return n


def pub(n, name, t):
    n.interfaces.append(T.Publisher(name=name, topic=t, type=t.type))


def sub(n, name, t):
    n.interfaces.append(T.Subscriber(name=name, topic=t, type=t.type))


def provides(n, name, type_, ros):
    server = T.ServiceServer(name=name, type=type_, rosName=ros)
    n.interfaces.append(server)
    return server


def calls(n, name, server):
    client = T.ServiceClient(name=name, server=server, type=server.type)
    n.interfaces.append(client)
    return client


def add_robot_side(system, name, robot_id, cloud_container, cloud_topics, planner):
    r = robot(system, name, robot_id)
    rgb = topic(r, "RGBImg", "sensor_msgs/Image", "/camera/rgb/image")
    depth = topic(r, "DepthImg", "sensor_msgs/Image", "/camera/depth/image")
    pose = topic(r, "PoseUpdated", "std_msgs/Header", "/pose_updated")
    traj = topic(r, "Trajectory", "trajectory_msgs/MultiDOFJointTrajectory", "/trajectory")
    twist = topic(r, "Twist", "geometry_msgs/Twist", "/cmd_vel")
    camera = node(r, "DepthCamera", "openni2_camera/openni2_camera_node")
    pub(camera, "rgb", rgb)
    pub(camera, "depth", depth)
    controller = node(r, "RobotController", "youbot_control/robot_controller")
    sub(controller, "pose_updated", pose)
    pub(controller, "trajectory", traj)
    next_target = calls(controller, "next_target", planner)
    follower = node(r, "TrajectoryFollower", "youbot_control/trajectory_follower")
    sub(follower, "trajectory", traj)
    pub(follower, "cmd_vel", twist)
    driver = node(
        r,
        "RobotDriver",
        "youbot_driver/youbot_driver_node",
        params=[("port", "string", "/dev/ttyUSB0"), ("rate", "double", "20.0")],
    )
    sub(driver, "cmd_vel", twist)
    endpoints.topic_bridge(system, rgb, cloud_topics["RGBImg"])
    endpoints.topic_bridge(system, depth, cloud_topics["DepthImg"])
    endpoints.topic_bridge(system, cloud_topics["PoseUpdated"], pose)
    endpoints.service_bridge(system, next_target, planner)
    return r


def mapping_system(robots=(("Robot", "robot_1"),), reverse=False):
    """The mapping3d architecture (case study 1), with one or several robots."""
    system = T.System(name="Mapping3D")
    c = cloud(system, "MappingCloud", group="mappers", cpu=2, memory=2048)
    topics = {
        "RGBImg": topic(c, "RGBImg", "sensor_msgs/Image", "/camera/rgb/image"),
        "DepthImg": topic(c, "DepthImg", "sensor_msgs/Image", "/camera/depth/image"),
        "PoseUpdated": topic(c, "PoseUpdated", "std_msgs/Header", "/pose_updated"),
    }
    keyframes = topic(c, "Keyframes", "rapyuta_msgs/Keyframe", "/keyframes")
    vo = node(c, "VisualOdometry", "rapyuta_mapping/visual_odometry")
    sub(vo, "rgb", topics["RGBImg"])
    sub(vo, "depth", topics["DepthImg"])
    pub(vo, "keyframes", keyframes)
    db = node(c, "Database", "rapyuta_mapping/database", sharing="protected")
    add_kf = provides(db, "add_keyframe", "rapyuta_msgs/AddKeyframe", "/db/add_keyframe")
    update = provides(db, "update_poses", "rapyuta_msgs/UpdatePoses", "/db/update_poses")
    get_map = provides(db, "get_map", "rapyuta_msgs/GetMap", "/db/get_map")
    optimizer = node(
        c,
        "MapOptimizer",
        "rapyuta_mapping/map_optimizer",
        params=[
            ("CameraInfo", "string", "package://rapyuta_mapping/cam/default.yaml"),
            ("iterations", "int", "10"),
            ("robust", "bool", "true"),
            ("weights", "yaml", "[1, 2.5, x]"),
            ("bounds", "yaml", "{min: 0, max: 3}"),
        ],
    )
    sub(optimizer, "keyframes", keyframes)
    pub(optimizer, "pose_updated", topics["PoseUpdated"])
    calls(optimizer, "add_keyframe", add_kf)
    calls(optimizer, "update_poses", update)
    merger = node(c, "MapMerger", "rapyuta_mapping/map_merger", sharing="protected")
    calls(merger, "get_map", get_map)
    planner = node(c, "StrategyPlanner", "exploration/room_strategy", sharing="protected")
    sub(planner, "pose_updated", topics["PoseUpdated"])
    calls(planner, "get_map", get_map)
    next_target = provides(planner, "next_target", "rapyuta_msgs/NextTarget", "/next_target")
    for name, robot_id in robots:
        add_robot_side(system, name, robot_id, c, topics, next_target)
    if reverse:  # same architecture, every list in the opposite order
        for container in system.containers:
            for collection in (container.nodes, container.topics, container.endpoint.interfaces):
                reverse_in_place(collection)
        reverse_in_place(system.containers)
        reverse_in_place(system.connections)
    return system


def reverse_in_place(collection):
    items = list(collection)
    collection.clear()
    collection.extend(reversed(items))
