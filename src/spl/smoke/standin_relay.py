"""The ``endpoint`` role of the smoke stand-ins: a container's Rapyuta endpoint, relaying
topic data, service calls and actions' topics to the peer endpoints over XML-RPC, along
the product's flow table. Run by the Python that has rospy, imported by ``standin.py``.
"""

from __future__ import annotations

import json
import sys
import threading
import xmlrpc.client
from socketserver import ThreadingMixIn
from typing import cast
from xmlrpc.server import SimpleXMLRPCServer

import rospy
from standin_common import (
    Status,
    action_classes,
    load_plan,
    message_class,
    serialize,
    service_class,
    source_of,
    status_path,
)


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
    # (XML-RPC hands them what the peers marshalled: a name and a Binary)
    server.register_function(relay.deliver, "deliver")  # type: ignore[arg-type]
    server.register_function(relay.call, "call")  # type: ignore[arg-type]
    threading.Thread(target=server.serve_forever, daemon=True).start()
    status.data["port"] = server.server_address[1]
    status.data["ready"] = True
    status.keep_writing()
    rospy.spin()
    server.shutdown()


class _Relay:
    """Forwards along the endpoint connections: topic data from a ``sub_`` interface to
    the peers' ``pub_`` (each message over the connections its flows take), service calls
    from a ``srv_`` interface to the peer's ``cli_``, an action's topics between the
    ``asrv_`` standing in for its server and the ``acli_`` by the server, both ways."""

    def __init__(self, plan: dict, container: str, status: Status) -> None:
        self.plan, self.container, self.status = plan, container, status
        self.nodes = plan["containers"][container]["nodes"]
        self.publishers: dict[str, rospy.Publisher] = {}
        self.proxies: dict[str, rospy.ServiceProxy] = {}
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
        elif kind in ("action_server", "action_client"):
            self._add_action(interface, entry, kind == "action_server")
        elif kind == "server":
            cls = service_class(type_name)

            def answer(request, entry=entry, forward=forward, cls=cls):
                self.status.count(entry, "served")
                if forward is None:
                    raise rospy.ServiceException("no endpoint connection")
                data = self._peer(forward[0]).call(forward[1], serialize(request))
                return cls._response_class().deserialize(cast(xmlrpc.client.Binary, data).data)

            self.keep.append(rospy.Service(ros_name, cls, answer))
        else:
            self.proxies[name] = rospy.ServiceProxy(ros_name, service_class(type_name))

    def _add_action(self, interface: dict, entry: dict, stands_for_server: bool) -> None:
        """An action's five topics, as the Rapyuta bridge carries them: the stand-in for
        a server elsewhere takes what the clients here send (goals, cancels) and passes
        it to the peer endpoint's client, which publishes it by the server; what comes
        back (status, feedback, results) takes the reverse way to every endpoint whose
        clients it answers (``peers``)."""
        name, ros_name = interface["name"], interface["ros_name"]
        classes = action_classes(interface["type"])
        forward = interface.get("forward")
        peers = [forward] if stands_for_server and forward else interface.get("peers") or []
        for part in interface["parts"]:
            topic, cls = f"{ros_name}/{part['suffix']}", classes[part["type"]]
            key = f"{name}/{part['suffix']}"
            if part["from_consumer"] != stands_for_server:
                self.publishers[key] = rospy.Publisher(topic, cls, queue_size=100)
                self.entries[key] = entry
                continue

            def received(message, suffix=part["suffix"]) -> None:
                if suffix == "goal":
                    self.status.count(entry, "served")
                elif suffix == "result":
                    self.status.count(entry, "answered_by", message.result.server)
                elif suffix == "feedback":
                    self.status.count(entry, "feedback_from", message.feedback.server)
                for container, peer in peers:
                    try:
                        self._peer(container).deliver(f"{peer}/{suffix}", serialize(message))
                    except (OSError, xmlrpc.client.Error, KeyError) as error:
                        self.status.set(entry, "last_error", f"relay: {error}"[:200])

            self.keep.append(rospy.Subscriber(topic, cls, received, queue_size=100))

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
