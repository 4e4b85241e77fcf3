"""The action roles of the smoke stand-ins: an action server and an action client made
with the real actionlib, over the synthetic action classes of ``standin_common``.

Run by the Python that has rospy and actionlib, imported by ``standin.py`` (never by spl
itself), and only for a plan with actions: the rehearsal leaves actions out, with a
warning, where actionlib is not installed (docs/smoke.md, "Actions").

Both are created under the interface name, as every stand-in interface is, so the
launch file's five remaps (``NAME/goal`` ... ``NAME/result``) alone decide the topics
they meet on. A server answers every goal it takes with feedback and then a result,
both carrying its own id; a client sends numbered goals carrying its id, one at a time,
and records who sent the feedback and the result of each (a result counts only when it
answers its own goal).
"""

from __future__ import annotations

import threading
import time

import actionlib
import rospy
from standin_common import CALL_PERIOD, Status, action_classes

FEEDBACKS = 2  # feedback messages a stand-in server sends before each result
FEEDBACK_PERIOD = 0.05  # seconds between them, and before the result
SERVER_WAIT = 1.0  # seconds a client waits for its server before it tries again
RESULT_WAIT = 5.0  # seconds a client waits for a goal's result before the next goal


def _spec(type_name: str) -> tuple[type, dict]:
    classes = action_classes(type_name)
    return classes[f"{type_name}Action"], classes


def _resolved(name: str) -> str:
    """Where the action's goals land, as its name: the launch file remaps its five topics
    one by one, never the name itself (each topic is checked on the master)."""
    return rospy.resolve_name(f"{name}/goal").rsplit("/", 1)[0]


def serve(interface: dict, own_id: str, status: Status):
    """An actionlib ActionServer under the interface's name, taking every goal."""
    name, type_name = interface["name"], interface["type"]
    spec, classes = _spec(type_name)
    entry = status.interface(name, _resolved(name))
    feedback_class = classes[f"{type_name}Feedback"]
    result_class = classes[f"{type_name}Result"]

    def answer(handle) -> None:
        goal = handle.get_goal()
        for _ in range(FEEDBACKS):
            handle.publish_feedback(feedback_class(server=own_id, seq=goal.seq))
            time.sleep(FEEDBACK_PERIOD)
        status.count(entry, "served", now=True)
        handle.set_succeeded(result_class(server=own_id, client=goal.client, seq=goal.seq))

    def take(handle) -> None:
        handle.set_accepted()
        # answered on a thread of its own: the goal subscriber's thread takes the next goal
        threading.Thread(target=answer, args=(handle,), daemon=True).start()

    server = actionlib.ActionServer(name, spec, take, auto_start=False)
    server.start()
    return server


def send_goals(interface: dict, own_id: str, status: Status):
    """An actionlib SimpleActionClient under the interface's name, sending a goal every
    ``CALL_PERIOD`` once its server is there."""
    name, type_name = interface["name"], interface["type"]
    spec, classes = _spec(type_name)
    entry = status.interface(name, _resolved(name))
    goal_class = classes[f"{type_name}Goal"]
    client = actionlib.SimpleActionClient(name, spec)

    def fed(feedback) -> None:
        status.count(entry, "feedback_from", feedback.server)

    def loop() -> None:
        seq = 0
        while not rospy.is_shutdown():
            try:
                if not client.wait_for_server(rospy.Duration(SERVER_WAIT)):
                    status.set(entry, "last_error", "no action server connected")
                    continue
                seq += 1
                client.send_goal(goal_class(client=own_id, seq=seq), feedback_cb=fed)
                if not client.wait_for_result(rospy.Duration(RESULT_WAIT)):
                    status.set(entry, "last_error", f"no result for goal {seq}")
                    continue
                result = client.get_result()
                if result is not None and result.client == own_id and result.seq == seq:
                    status.count(entry, "answered_by", result.server)
                else:
                    status.set(entry, "last_error", f"goal {seq} ended without its result")
            except (rospy.ROSException, OSError) as error:
                status.set(entry, "last_error", str(error).splitlines()[0][:200])
                if rospy.is_shutdown():
                    return
            time.sleep(CALL_PERIOD)

    threading.Thread(target=loop, daemon=True).start()
    return client
