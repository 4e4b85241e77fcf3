"""What both roles of the smoke stand-ins share: synthetic message and service classes
(genpy, from the plan's definitions), the status file each process writes, the plan.

Run by the Python that has rospy, imported by ``standin.py`` (never by spl itself).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import threading
import time

import genpy.dynamic
import rospy

# Synthetic definitions; the constant makes the md5sum differ per type, so a subscriber
# or client of another type is refused at connection time, as with real messages.
MESSAGE = "string TYPE={}\nstring source\nstring route\nuint32 seq\n"
REQUEST = "string TYPE={}\nstring client\nuint32 seq\n"
RESPONSE = "string TYPE={}\nstring server\n"
# An action's goal, result and feedback (actionlib wraps each in its Action* message):
# the client's id and the goal's number go out, the server's id comes back with them
GOAL = "string TYPE={}\nstring client\nuint32 seq\n"
RESULT = "string TYPE={}\nstring server\nstring client\nuint32 seq\n"
FEEDBACK = "string TYPE={}\nstring server\nuint32 seq\n"
SEPARATOR = "\n" + "=" * 80 + "\n"  # between the definitions of one genpy text
PUBLISH_PERIOD = 0.2  # seconds between two messages of a publisher
CALL_PERIOD = 0.3  # seconds between two calls of a client

_messages: dict[str, object] = {}
_services: dict[str, object] = {}
_actions: dict[str, dict[str, object]] = {}
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
    node = nodes.get(caller) or {}
    for interface in node.get("interfaces", ()):
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


def action_classes(type_name: str) -> dict[str, object]:
    """The messages of action ``type_name`` (``pkg/Name``) by type: ``pkg/NameAction``,
    the specification actionlib's server and client take, and the ``ActionGoal``,
    ``ActionResult`` and ``ActionFeedback`` messages its topics carry, generated once per
    process from synthetic goal, result and feedback definitions around actionlib's own
    ``Header``, ``GoalID`` and ``GoalStatus`` (so the topics' types are the ones the
    master shows for the real action, and no message package is needed)."""
    if type_name not in _actions:
        import actionlib_msgs.msg
        import std_msgs.msg

        def own(cls) -> str:  # a class's own definition, without those it depends on
            return cls._full_text.split(SEPARATOR)[0].strip() + "\n"

        t = type_name
        texts = {
            f"{t}ActionGoal": f"Header header\nactionlib_msgs/GoalID goal_id\n{t}Goal goal\n",
            f"{t}ActionResult": f"Header header\nactionlib_msgs/GoalStatus status\n"
            f"{t}Result result\n",
            f"{t}ActionFeedback": f"Header header\nactionlib_msgs/GoalStatus status\n"
            f"{t}Feedback feedback\n",
            f"{t}Goal": GOAL.format(t),
            f"{t}Result": RESULT.format(t),
            f"{t}Feedback": FEEDBACK.format(t),
            "std_msgs/Header": own(std_msgs.msg.Header),
            "actionlib_msgs/GoalID": own(actionlib_msgs.msg.GoalID),
            "actionlib_msgs/GoalStatus": own(actionlib_msgs.msg.GoalStatus),
        }
        core = (f"{t}ActionGoal action_goal\n{t}ActionResult action_result\n"
                f"{t}ActionFeedback action_feedback\n")  # fmt: skip
        text = core + "".join(f"{SEPARATOR}MSG: {name}\n{body}" for name, body in texts.items())
        classes = genpy.dynamic.generate_dynamic(f"{t}Action", text)
        # the topics actionlib itself publishes with its own classes
        classes["actionlib_msgs/GoalID"] = actionlib_msgs.msg.GoalID
        classes["actionlib_msgs/GoalStatusArray"] = actionlib_msgs.msg.GoalStatusArray
        _actions[type_name] = classes
    return _actions[type_name]


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
        self.writing = threading.Lock()  # the writer thread and answers that write at once

    def interface(self, name: str, resolved: str) -> dict:
        with self.lock:
            entry = {
                "resolved": resolved,
                "received": {},
                "answered_by": {},
                "feedback_from": {},
                "sent": 0,
                "served": 0,
                "last_error": None,
            }
            self.data["interfaces"][name] = entry
            return entry

    def count(self, entry: dict, key: str, who: str | None = None, *, now: bool = False) -> None:
        """``now`` writes the file before the caller goes on: a server counts its answer
        that way before it sends it, so no report shows a result its server has not
        counted yet (the periodic writer may be up to a period behind)."""
        with self.lock:
            if who is None:
                entry[key] += 1
            else:
                entry[key][who] = entry[key].get(who, 0) + 1
        if now:
            self.write()

    def set(self, entry: dict, key: str, value) -> None:
        with self.lock:
            entry[key] = value

    def write(self) -> None:
        with self.writing:
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
