"""Literal values the languages accept: integer ranges and YAML text.

Parameter values, attribute defaults, container resources and cardinality bounds are
written as literals in .tsm, .fm and .rm files and end up in launch files, Rapyuta
configurations and XMI. Each check here returns the value or says what is wrong, so
every language reports it at the literal's location; none of them lets Python's own
limits (a literal of thousands of digits, a YAML tag that does not convert) surface
as an internal error.
"""

from __future__ import annotations

import re

INT32_MAX = 2**31 - 1  # EInt in the metamodels, Rapyuta's resource fields
INT64_MAX = 2**63 - 1  # feature attributes
# ROS integer parameters: ROS 1's parameter server speaks XML-RPC, whose integers are
# 32-bit (rospy refuses a larger one when roslaunch sets it: "int exceeds XML-RPC
# limits"), and every bundle has ROS 1 launch files
ROS_INT_MAX = INT32_MAX
ROS_INT_RANGE = f"ROS 1 parameters are 32-bit integers, at most {ROS_INT_MAX} in magnitude"

_DECIMAL = re.compile(r"[-+]?0*(\d+)")


def int_literal(text: str, limit: int = INT64_MAX) -> int | None:
    """The value of a decimal literal ``[-+]?DIGITS`` whose magnitude is at most
    ``limit``; None for anything else. Digits are counted before converting."""
    match = _DECIMAL.fullmatch(text)
    if match is None or len(match.group(1)) > len(str(limit)):
        return None
    value = int(text)
    return value if abs(value) <= limit else None


def problem_yaml(text: str) -> str | None:
    """None when ``text`` is a YAML document a ROS node can load; else why not."""
    import yaml  # only models with yaml parameters pay for it

    try:
        yaml.safe_load(text)
    except yaml.MarkedYAMLError as exc:
        return f"invalid YAML: {exc.problem or exc.context}"
    except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:
        # a tag whose text does not convert (``!!float x``, ``!!binary ?``)
        return f"invalid YAML: {exc}"
    return None
