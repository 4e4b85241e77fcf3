"""Stand-in ROS 1 processes of a smoke rehearsal, run by the Python that has rospy.

This file is executed as a script by the interpreter of Debian's ROS 1 (``python3 -I
standin.py ROLE``), never imported by spl itself: rospy is importable only there, and
``-I`` keeps the virtual environment's packages and this folder off its ``sys.path``.
It imports nothing from spl; everything it needs comes from the plan (JSON) the
rehearsal wrote, named by ``SPL_SMOKE_PLAN``, and ``SPL_SMOKE_CONTAINER``.

Roles:

``node``
    Stands in for one node of the product. roslaunch starts it in place of the real
    executable, with the node name, namespace, remappings and parameters of the bundle's
    launch file (data clients are started the same way by the rehearsal). It finds its
    interfaces in the plan by the node name rospy resolved, creates each one under its
    *interface name* so that only the remappings decide the ROS name, publishes,
    subscribes, serves and calls, serves and sends action goals with actionlib
    (``standin_action.py``), and records what it saw in a status file.
``endpoint``
    The container's Rapyuta endpoint: its interfaces use the model's ROS names and relay
    data, service calls and actions' five topics to the peer endpoints (over XML-RPC on
    the loopback interface), exactly along the routes of the product's flow table: an endpoint
    subscriber passes a message over a connection when the plan lists the message's
    publisher and the connections it crossed so far for it.

Message and service classes are generated at run time with genpy from a synthetic
definition registered under the model's type name, so the master shows the model's
types and no message package needs to be installed. Every message carries the id of
the publisher that produced it and the endpoint connections it crossed; every answer
the id of the server that gave it. The topics of writers and readers carry their data
type's fields too (the plan's ``messages``, which the generated nodes import under the
same definitions): a stand-in publisher there sends a known run of values, and a
stand-in subscriber records the values it receives. A message a generated node
publishes carries no source: it is known by the publishing node's name (its
connection header's ``callerid``).
"""

from __future__ import annotations

import os
import sys
import threading
import time
import traceback

# run as a script with -I: its own folder is not on the path; its two helpers are there
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy
from standin_common import (
    CALL_PERIOD,
    PUBLISH_PERIOD,
    VALUES_KEPT,
    Status,
    data_fields,
    load_plan,
    message_class,
    service_class,
    source_of,
    status_path,
    value_of,
)
from standin_relay import run_endpoint


def run_node() -> None:
    rospy.init_node("spl_smoke_standin", argv=sys.argv)
    plan, container, description = load_plan()
    name = rospy.get_name()
    status = Status(status_path(plan, container, name), name)
    status.keep_writing()
    node = description["nodes"].get(name)
    if node is None:
        status.data["error"] = f"{name} is not a node of container {container} in the model"
        status.data["ready"] = True
        rospy.spin()
        return
    keep = []  # rospy objects must stay referenced for the life of the process
    for interface in node["interfaces"]:
        keep.append(_node_interface(interface, node["id"], description["nodes"], status))
    status.data["ready"] = True
    rospy.spin()


def _node_interface(interface: dict, node_id: str, nodes: dict, status: Status):
    name, kind, type_name = interface["name"], interface["kind"], interface["type"]
    own_id = f"{node_id}.{name}"
    if kind == "publisher":
        publisher = rospy.Publisher(name, message_class(type_name), queue_size=100)
        entry = status.interface(name, publisher.resolved_name)
        if interface.get("values"):
            _publish_values(publisher, own_id, interface["values"], status, entry)
        else:
            _publish_forever(publisher, own_id, status, entry)
        return publisher
    if kind == "subscriber":
        topic = rospy.resolve_name(name)
        entry = status.interface(name, topic)
        entry["values"] = []

        def received(message) -> None:
            source = source_of(message, topic, nodes)
            status.count(entry, "received", source)
            fields = data_fields(message)
            if fields and len(entry["values"]) < VALUES_KEPT:
                with status.lock:
                    entry["values"].append([source, [getattr(message, f) for f in fields]])

        return rospy.Subscriber(name, message_class(type_name), received, queue_size=1000)
    if kind in ("action_server", "action_client"):  # only a plan with actions needs actionlib
        import standin_action

        if kind == "action_server":
            return standin_action.serve(interface, own_id, status)
        return standin_action.send_goals(interface, own_id, status)
    if kind == "server":
        cls = service_class(type_name)
        entry = status.interface(name, rospy.resolve_name(name))

        def answer(request):
            status.count(entry, "served", now=True)
            return cls._response_class(server=own_id)

        return rospy.Service(name, cls, answer)
    entry = status.interface(name, rospy.resolve_name(name))
    _call_forever(rospy.ServiceProxy(name, service_class(type_name)), own_id, status, entry)
    return None


def _publish_values(publisher, own_id: str, plan: dict, status: Status, entry) -> None:
    """Once ``wait_for`` subscribers are connected (at most 20 s), ``count`` messages of
    known values, recorded in the status as sent."""
    entry["values"] = []

    def loop() -> None:
        deadline = time.monotonic() + 20.0
        while publisher.get_num_connections() < plan["wait_for"] and time.monotonic() < deadline:
            if rospy.is_shutdown():
                return
            time.sleep(0.05)
        time.sleep(0.2)  # the last subscriber's connection settles on its side too
        for seq in range(1, plan["count"] + 1):
            values = [value_of(kind, seq, i) for i, (_, kind) in enumerate(plan["fields"])]
            message = publisher.data_class(source=own_id, route="", seq=seq)
            for (field, _), value in zip(plan["fields"], values, strict=True):
                setattr(message, field, value)
            try:
                publisher.publish(message)
            except rospy.ROSException:
                return  # shutting down
            with status.lock:
                entry["values"].append(values)
            status.count(entry, "sent")
            time.sleep(PUBLISH_PERIOD)

    threading.Thread(target=loop, daemon=True).start()


def _publish_forever(publisher, own_id: str, status: Status, entry) -> None:
    def loop() -> None:
        seq = 0
        while not rospy.is_shutdown():
            seq += 1
            try:
                publisher.publish(publisher.data_class(source=own_id, route="", seq=seq))
                status.count(entry, "sent")
            except rospy.ROSException:
                return  # shutting down
            time.sleep(PUBLISH_PERIOD)

    threading.Thread(target=loop, daemon=True).start()


def _call_forever(proxy, own_id: str, status: Status, entry) -> None:
    def loop() -> None:
        seq = 0
        while not rospy.is_shutdown():
            seq += 1
            try:
                response = proxy(proxy.request_class(client=own_id, seq=seq))
                status.count(entry, "answered_by", response.server)
            except (rospy.ServiceException, rospy.ROSException, OSError) as error:
                status.set(entry, "last_error", str(error).splitlines()[0][:200])
            time.sleep(CALL_PERIOD)

    threading.Thread(target=loop, daemon=True).start()


def main() -> None:
    role = sys.argv[1] if len(sys.argv) > 1 else ""
    try:
        if role == "node":
            run_node()
        elif role == "endpoint":
            run_endpoint()
        else:
            sys.exit(f"standin.py: unknown role {role!r} (node or endpoint)")
    except Exception:
        traceback.print_exc()
        sys.exit(1)


if __name__ == "__main__":
    main()
