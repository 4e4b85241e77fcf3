"""How many subscribers a generated reader waits for before it publishes a record
(docs/services.md, "Robot-side writers and readers"): the nodes of its own ROS graph the
flow table delivers its records to, the endpoint once for those that go on over a
bridge, at least one; a launch or ``rosrun`` may set another number (``subscribers``)."""

from __future__ import annotations

from spl.dsl.tsm import language as tsm_language
from spl.generators.clients import generator as clients

from support.service_models import PRODUCT_LINE, product

# the data-acquisition line's EV3B with two more listeners of the commands on the robot
# (one of them subscribing twice: one connection) and the commands bridged to the cloud
LISTENERS = """
cloud container Fleet {
    topic FleetCommands : ev3_msgs/Command name "/fleet/command"
    node Dashboard {
        implementation fleet/dashboard
        subscribes command <- FleetCommands
    }
}
robot container EV3C {
    endpoint robot_id "ev3_c" url "wss://cloud.example.org:9000/" user "ev3c"
             password env "RCE_PASSWORD"
    topic Commands : ev3_msgs/Command name "/ev3/command"
    node Follower {
        implementation ev3_control/command_follower
        subscribes command <- Commands
    }
    node Logger {
        implementation ev3_control/command_logger
        subscribes command <- Commands
        subscribes again <- Commands
    }
    reader LoggedReader : Command from DataCloud.FollowStore -> Commands subscribe every 0.5 s
}
bridge EV3C.Commands -> Fleet.FleetCommands
"""


def reader_sources(resolved) -> dict[tuple[str, str], str]:  # type: ignore[no-untyped-def]
    """(ros1 | ros2, package) -> the generated reader node's source."""
    return {
        (path.split("/")[1], path.split("/")[2]): data.decode()
        for path, data in clients.generate(resolved).items()
        if path.endswith("/reader_node.py")
    }


def test_a_reader_waits_for_each_node_it_feeds_and_the_endpoint_once() -> None:
    text = (PRODUCT_LINE / "data.tsm").read_text(encoding="utf-8") + LISTENERS
    resolved = product(system=tsm_language.parse_text(text, "listeners.tsm"))
    reader = next(
        n for c in resolved.system.containers for n in c.nodes if n.name == "LoggedReader"
    )
    # Follower, Logger (two subscriptions, one connection) and the endpoint to the cloud
    assert clients.listeners(reader, resolved) == 3
    sources = reader_sources(resolved)
    assert 'rospy.get_param("~subscribers", 3)' in sources["ros1", "logged_reader"]
    assert 'self.declare_parameter("subscribers", 3)' in sources["ros2", "logged_reader"]


def test_a_reader_nothing_in_the_model_listens_to_waits_for_one_subscriber() -> None:
    resolved = product()
    readers = {n.name: n for c in resolved.system.containers for n in c.nodes
               if n.eClass.name == "Reader"}  # fmt: skip
    # no node of the line listens to /gps/deg; CommandFollower listens to /ev3/command
    assert clients.listeners(readers["PositionReader"], resolved) == 1
    assert clients.listeners(readers["CommandReader"], resolved) == 1
    sources = reader_sources(resolved)
    assert 'rospy.get_param("~subscribers", 1)' in sources["ros1", "position_reader"]
    # and writers carry no wait: they publish nothing
    files = clients.generate(resolved)
    writer = files["clients/ros1/position_writer/src/position_writer/store_client.py"]
    assert b"import Listeners" not in writer and b'"Listeners"' not in writer
    reader = files["clients/ros1/position_reader/src/position_reader/store_client.py"]
    assert b"from .runtime.reading import Listeners, PollingReader" in reader
