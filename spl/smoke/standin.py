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
    subscribes, serves and calls, and records what it saw in a status file.
``endpoint``
    The container's Rapyuta endpoint: its interfaces use the model's ROS names and relay
    data and service calls to the peer endpoints (over XML-RPC on the loopback
    interface), exactly along the routes of the product's flow table: an endpoint
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

import hashlib
import io
import json
import os
import sys
import threading
import time
import traceback
import xmlrpc.client
from socketserver import ThreadingMixIn
from xmlrpc.server import SimpleXMLRPCServer

import genpy.dynamic
import rospy

# Synthetic definitions; the constant makes the md5sum differ per type, so a subscriber
# or client of another type is refused at connection time, as with real messages.
MESSAGE = "string TYPE={}\nstring source\nstring route\nuint32 seq\n"
REQUEST = "string TYPE={}\nstring client\nuint32 seq\n"
RESPONSE = "string TYPE={}\nstring server\n"
PUBLISH_PERIOD = 0.2  # seconds between two messages of a publisher
CALL_PERIOD = 0.3  # seconds between two calls of a client

_messages: dict[str, object] = {}
_services: dict[str, object] = {}
DEFINITIONS: dict[str, str] = {}  # the plan's data-typed messages, by type
TRACKING = ("source", "route", "seq")
VALUES_KEPT = 2000  # values a subscriber records, at most


def _generated(type_name: str, definition: str):
    return genpy.dynamic.generate_dynamic(type_name, definition)[type_name]


def message_class(type_name: str):
    """The class of messages of ``type_name``, generated once per process."""
    if type_name not in _messages:
        definition = DEFINITIONS.get(type_name) or MESSAGE.format(type_name)
        _messages[type_name] = _generated(type_name, definition)
    return _messages[type_name]


def data_fields(message) -> list[str]:
    """The data type's fields of a message (none for a synthetic one)."""
    return [name for name in message.__slots__ if name not in TRACKING]


def value_of(kind: str, seq: int, index: int):
    """The value a stand-in publisher sends in field ``index`` of message ``seq``:
    distinct per message and field, exact in JSON and in every ROS type."""
    if kind == "double":
        return seq * 3.25 + index * 0.5
    if kind == "int":
        return seq * 10 + index
    if kind == "bool":
        return (seq + index) % 2 == 0
    return f"v{seq}-{index}"


def source_of(message, topic: str, nodes: dict) -> str:
    """Who published ``message`` on ``topic``: its own tracking field, or (a generated
    node sets none) the publisher interface on that topic of the node its connection
    header names."""
    if message.source:
        return message.source
    caller = (getattr(message, "_connection_header", None) or {}).get("callerid", "")
    node = nodes.get(caller)
    for interface in (node or {}).get("interfaces", ()):
        if interface["kind"] == "publisher" and interface["ros_name"] == topic:
            return f"{node['id']}.{interface['name']}"
    return caller or "?"


def service_class(type_name: str):
    """A service class for ``type_name`` as rospy expects one (request and response
    classes, type and md5sum), built from two generated messages."""
    if type_name not in _services:
        request_class = _generated(type_name + "Request", REQUEST.format(type_name))
        response_class = _generated(type_name + "Response", RESPONSE.format(type_name))
        digest = hashlib.md5((request_class._md5sum + response_class._md5sum).encode())
        _services[type_name] = type(
            "Service",
            (),
            {
                "_type": type_name,
                "_md5sum": digest.hexdigest(),
                "_request_class": request_class,
                "_response_class": response_class,
            },
        )
    return _services[type_name]


def serialize(message) -> bytes:
    buffer = io.BytesIO()
    message.serialize(buffer)
    return buffer.getvalue()


class Status:
    """What this process saw, written atomically as JSON whenever it changes."""

    def __init__(self, path: str, node: str) -> None:
        self.path = path
        self.lock = threading.Lock()
        self.data: dict = {
            "node": node,
            "pid": os.getpid(),
            "ready": False,
            "error": None,
            "interfaces": {},
        }
        self.written = ""

    def interface(self, name: str, resolved: str) -> dict:
        with self.lock:
            entry = {
                "resolved": resolved,
                "received": {},
                "answered_by": {},
                "sent": 0,
                "served": 0,
                "last_error": None,
            }
            self.data["interfaces"][name] = entry
            return entry

    def count(self, entry: dict, key: str, who: str | None = None) -> None:
        with self.lock:
            if who is None:
                entry[key] += 1
            else:
                entry[key][who] = entry[key].get(who, 0) + 1

    def set(self, entry: dict, key: str, value) -> None:
        with self.lock:
            entry[key] = value

    def write(self) -> None:
        with self.lock:
            text = json.dumps(self.data, sort_keys=True)
        if text == self.written:
            return
        partial = self.path + ".partial"
        with open(partial, "w", encoding="utf-8") as stream:
            stream.write(text)
        os.replace(partial, self.path)
        self.written = text

    def keep_writing(self) -> None:
        def loop() -> None:
            while not rospy.is_shutdown():
                self.write()
                time.sleep(0.1)

        threading.Thread(target=loop, daemon=True).start()


def load_plan() -> tuple[dict, str, dict]:
    with open(os.environ["SPL_SMOKE_PLAN"], encoding="utf-8") as stream:
        plan = json.load(stream)
    DEFINITIONS.update(plan.get("messages") or {})
    container = os.environ["SPL_SMOKE_CONTAINER"]
    return plan, container, plan["containers"][container]


def status_path(plan: dict, container: str, node: str) -> str:
    folder = os.path.join(plan["status_dir"], container)
    os.makedirs(folder, exist_ok=True)
    # '.' is in no ROS name, so two nodes never share a file (with '__', /a/b and /a__b did)
    return os.path.join(folder, node.strip("/").replace("/", ".") + ".json")


# --------------------------------------------------------------------------- node role


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
    if kind == "server":
        cls = service_class(type_name)
        entry = status.interface(name, rospy.resolve_name(name))

        def answer(request):
            status.count(entry, "served")
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


# ----------------------------------------------------------------------- endpoint role


class _Server(ThreadingMixIn, SimpleXMLRPCServer):
    daemon_threads = True


def run_endpoint() -> None:
    plan, container, description = load_plan()
    node = description["endpoint"]
    # the name the plan gave it (no node of the container has it); the namespace comes
    # from ROS_NAMESPACE, as roslaunch gives it to nodes
    rospy.init_node(node["ros_name"].rsplit("/", 1)[-1], argv=sys.argv[:1])
    name = rospy.get_name()
    status = Status(status_path(plan, container, name), name)
    relay = _Relay(plan, container, status)
    for interface in node["interfaces"]:
        relay.add(interface)
    server = _Server(("127.0.0.1", 0), logRequests=False, allow_none=True)
    server.register_function(relay.deliver, "deliver")
    server.register_function(relay.call, "call")
    threading.Thread(target=server.serve_forever, daemon=True).start()
    status.data["port"] = server.server_address[1]
    status.data["ready"] = True
    status.keep_writing()
    rospy.spin()
    server.shutdown()


class _Relay:
    """Forwards along the endpoint connections: topic data from a ``sub_`` interface to
    the peers' ``pub_`` (each message over the connections its flows take), service calls
    from a ``srv_`` interface to the peer's ``cli_``."""

    def __init__(self, plan: dict, container: str, status: Status) -> None:
        self.plan, self.container, self.status = plan, container, status
        self.nodes = plan["containers"][container]["nodes"]
        self.publishers: dict[str, object] = {}
        self.proxies: dict[str, object] = {}
        self.entries: dict[str, dict] = {}
        self.keep: list = []

    def add(self, interface: dict) -> None:
        name, kind, type_name = interface["name"], interface["kind"], interface["type"]
        ros_name, forward = interface["ros_name"], interface.get("forward")
        relays = interface.get("relays") or []
        entry = self.entries[name] = self.status.interface(name, rospy.resolve_name(ros_name))
        if kind == "publisher":
            self.publishers[name] = rospy.Publisher(
                ros_name, message_class(type_name), queue_size=10
            )
        elif kind == "subscriber":

            def received(message, entry=entry, relays=relays, topic=ros_name) -> None:
                source = source_of(message, rospy.resolve_name(topic), self.nodes)
                self.status.count(entry, "received", source)
                message.source = source  # a generated node's data is known by its node
                crossed = message.route
                for relay in relays:
                    if f"{source}|{crossed}" not in relay["passes"]:
                        continue  # no flow of this publisher takes this connection here
                    message.route = f"{crossed},{relay['connection']}".lstrip(",")
                    try:
                        self._peer(relay["container"]).deliver(
                            relay["interface"], serialize(message)
                        )
                        self.status.count(entry, "sent")
                    except (OSError, xmlrpc.client.Error, KeyError) as error:
                        self.status.set(entry, "last_error", f"relay: {error}"[:200])

            self.keep.append(rospy.Subscriber(ros_name, message_class(type_name), received))
        elif kind == "server":
            cls = service_class(type_name)

            def answer(request, entry=entry, forward=forward, cls=cls):
                self.status.count(entry, "served")
                if forward is None:
                    raise rospy.ServiceException("no endpoint connection")
                data = self._peer(forward[0]).call(forward[1], serialize(request))
                return cls._response_class().deserialize(data.data)

            self.keep.append(rospy.Service(ros_name, cls, answer))
        else:
            self.proxies[name] = rospy.ServiceProxy(ros_name, service_class(type_name))

    def _peer(self, container: str) -> xmlrpc.client.ServerProxy:
        path = status_path(
            self.plan, container, self.plan["containers"][container]["endpoint"]["ros_name"]
        )
        with open(path, encoding="utf-8") as stream:
            port = json.load(stream)["port"]  # KeyError until the peer is up
        return xmlrpc.client.ServerProxy(f"http://127.0.0.1:{port}/", allow_none=True)

    def deliver(self, name: str, data: xmlrpc.client.Binary) -> bool:
        publisher = self.publishers[name]
        message = publisher.data_class().deserialize(data.data)
        publisher.publish(message)
        self.status.count(self.entries[name], "sent")
        return True

    def call(self, name: str, data: xmlrpc.client.Binary) -> xmlrpc.client.Binary:
        proxy = self.proxies[name]
        entry = self.entries[name]
        try:
            response = proxy(proxy.request_class().deserialize(data.data))
        except (rospy.ServiceException, rospy.ROSException) as error:
            self.status.set(entry, "last_error", str(error).splitlines()[0][:200])
            raise
        self.status.count(entry, "answered_by", response.server)
        return xmlrpc.client.Binary(serialize(response))


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
