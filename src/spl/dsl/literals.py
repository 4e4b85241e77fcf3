"""Literal values the languages accept: integer ranges and YAML text.

Parameter values, attribute defaults, container resources and cardinality bounds are
written as literals in .tsm, .fm and .rm files and end up in launch files, Rapyuta
configurations and XMI. Each check here returns the value or says what is wrong, so
every language reports it at the literal's location; none of them lets Python's own
limits (a literal of thousands of digits, a YAML tag that does not convert) surface
as an internal error.
"""

from __future__ import annotations

import math
import re
from typing import Any

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
    """None when ``text`` is a YAML parameter value both ROS generations can load; else
    why not. ROS 2 turns a mapping into nested parameters and has no null or empty
    parameter, so neither the value nor any mapping's entry in it may be null or ``{}``."""
    import yaml  # only models with yaml parameters pay for it

    try:
        value = yaml.safe_load(text)
    except yaml.MarkedYAMLError as exc:
        return f"invalid YAML: {exc.problem or exc.context}"
    except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:
        # a tag whose text does not convert (``!!float x``, ``!!binary ?``)
        return f"invalid YAML: {exc}"
    empty = _empty_entry(value, ())
    if empty is not None:
        where = f" (at {'.'.join(empty)})" if empty else ""
        return f"ROS 2 parameters cannot be null or empty{where}"
    return None


def _empty_entry(value: object, path: tuple[str, ...]) -> tuple[str, ...] | None:
    """The key path of the first null or empty mapping among nested mappings, or None."""
    if value is None or value == {}:
        return path
    if isinstance(value, dict):
        for key, item in value.items():
            found = _empty_entry(item, (*path, str(key)))
            if found is not None:
                return found
    return None


def attribute_fits(attribute_type: str, parameter_type: str) -> bool:
    """Whether a feature attribute of one type can give a parameter of the other its value."""
    return attribute_type == parameter_type or (attribute_type, parameter_type) in {
        ("int", "double"),
        ("string", "yaml"),
    }


def parameter_literal(value: Any, ptype: str) -> tuple[str | None, str | None]:
    """The canonical text of a literal for a parameter of type ``ptype`` (TSM convention)."""
    kind, text = type(value).__name__, value.value
    if kind == "StringValue":
        if ptype not in ("string", "yaml"):
            return None, f"expected a {ptype} value, got a string"
        if any(ord(c) < 32 and c not in "\n\t" for c in text):
            return None, "control characters are not allowed in values"
        if ptype == "yaml":
            problem = problem_yaml(text)
            if problem:
                return None, problem
        return text, None
    if kind == "BoolValue":
        return (text, None) if ptype == "bool" else (None, f"expected a {ptype} value, got {text}")
    if ptype == "int" and text.lstrip("+-").isdigit():
        value = int_literal(text, ROS_INT_MAX)
        if value is None:
            return None, f"{text} is out of range: {ROS_INT_RANGE}"
        return str(value), None
    if ptype == "double":
        value = float(text)
        return (repr(value), None) if math.isfinite(value) else (None, f"{text} is out of range")
    return None, f"expected a {ptype} value, got {text}"
