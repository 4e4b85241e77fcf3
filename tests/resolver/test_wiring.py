"""Which flows cross a deployment boundary (resolver.wiring), derived by hand for the
paper's product and for two robots sharing one cloud container."""

from __future__ import annotations

from pathlib import Path

from spl.resolver.architecture.flows import FlowTable
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.wiring import Wiring
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

from support.mapping_system import mapping_system

MAPPING = Path(__file__).resolve().parents[2] / "product_lines" / "mapping3d"


def crossings(system):
    """Robot name -> ``(kind, source tag, ROS name there, target tag, ROS name there)``."""
    errors = []
    placement = Placement(system, errors)
    wiring = Wiring(FlowTable.of(system), placement, errors)
    seen = {
        robot.name: [
            (str(c.kind), c.source.tag, c.source_name, c.target.tag, c.target_name)
            for c in wiring.crossings(robot)
        ]
        for robot in placement.robots
    }
    assert errors == []
    return seen


def test_the_papers_product_carries_camera_images_up_and_keeps_cmd_vel_on_the_robot():
    # youBot, stereo cameras, the MapOptimizer migrated onto the robot's additional PC
    selection = load_selection_file(MAPPING / "products" / "youbot_stereo_room.yaml")
    product = resolve(load_product_line(MAPPING), selection).product
    robot, private, shared = "youbot_07", "MappingCloud_youbot_07", "MappingCloud_mappers"
    assert crossings(product.system) == {
        "Robot": [
            # StereoVision's images to the VisualOdometry in the robot's private partition
            ("topic", robot, "/camera/rgb/image", private, "/camera/rgb/image"),
            ("topic", robot, "/camera/depth/image", private, "/camera/depth/image"),
            # the migrated MapOptimizer publishes poses to the shared StrategyPlanner ...
            ("topic", robot, "/mapping/pose_updated", shared, "/mapping/pose_updated"),
            # ... and takes the keyframes VisualOdometry still computes in the cloud
            ("topic", private, "/mapping/keyframes", robot, "/mapping/keyframes"),
            ("service", robot, "/exploration/next_target", shared, "/exploration/next_target"),
            ("service", robot, "/mapping/db/add_keyframe", shared, "/mapping/db/add_keyframe"),
            ("service", robot, "/mapping/db/update_poses", shared, "/mapping/db/update_poses"),
        ]
    }
    names = {name for flows in crossings(product.system).values() for f in flows for name in f}
    # /cmd_vel, the stereo pair's raw images and the map calls inside the shared
    # partition never leave their place
    assert not names & {"/cmd_vel", "/stereo/left/image_raw", "/mapping/db/get_map"}


def test_a_private_partition_serves_its_own_robot_alone():
    seen = crossings(mapping_system(robots=(("A", "robot_a"), ("B", "robot_b"))))
    shared = "MappingCloud_mappers"
    for robot_id, other in (("robot_a", "robot_b"), ("robot_b", "robot_a")):
        flows = seen["A" if robot_id == "robot_a" else "B"]
        private = f"MappingCloud_{robot_id}"
        # the other robot's camera never feeds this robot's private VisualOdometry
        assert not [f for f in flows if other in (f[1], f[3]) and private in (f[1], f[3])]
        assert not [f for f in flows if f"MappingCloud_{other}" in (f[1], f[3])]
        # but both robots call the one shared StrategyPlanner
        for caller in (robot_id, other):
            assert ("service", caller, "/next_target", shared, "/next_target") in flows
        # this robot's private MapOptimizer calls the shared Database
        assert ("service", private, "/db/add_keyframe", shared, "/db/add_keyframe") in flows
        assert ("topic", robot_id, "/camera/rgb/image", private, "/camera/rgb/image") in flows
