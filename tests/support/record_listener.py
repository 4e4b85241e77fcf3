"""A rospy subscriber for the tests of the generated readers: run with the Python that
has rospy, ``record_listener.py TOPIC PACKAGE/Type``, it prints one line per message
received, ``record {"field": value, ...}``, in the order received, and flushes each.

The message class is imported from ``PACKAGE.msg`` (the rehearsal's genpy message
packages, :func:`spl.smoke.processes.write_messages`, on ``PYTHONPATH``)."""

from __future__ import annotations

import importlib
import json
import sys


def main() -> None:
    import rospy

    topic, type_name = sys.argv[1], sys.argv[2]
    package, _, name = type_name.partition("/")
    message_class = getattr(importlib.import_module(f"{package}.msg"), name)
    rospy.init_node("record_listener")

    def received(message: object) -> None:
        values = {slot: getattr(message, slot) for slot in message.__slots__}
        print("record " + json.dumps(values, sort_keys=True), flush=True)

    rospy.Subscriber(topic, message_class, received, queue_size=1000)
    rospy.spin()


if __name__ == "__main__":
    main()
