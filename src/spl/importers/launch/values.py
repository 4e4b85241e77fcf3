"""Names and parameter values in the words of spl's languages.

A node's private parameters (``/node/a``, ``/node/b/c``) become the node's ``.tsm``
parameters by their first segment (``a``, and ``b`` as YAML holding ``{c: ...}``), as
the generated launch file gives them back: ``<param>`` for a scalar, ``<rosparam>`` for
YAML, which roslaunch unrolls into the same keys (docs/import.md). Each value is
written as a literal of the parameter's type; values of different types across
combinations make the parameter ``yaml``, which holds them all.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from spl.dsl.literals import ROS_INT_MAX, problem_yaml
from spl.importers.launch.reading import Combination, Omission
from spl.importers.naming import is_name, string_literal

if TYPE_CHECKING:
    from collections.abc import Mapping

MISSING = ""  # no literal is empty: the parameter is not set in that combination


@dataclass
class NodeParameter:
    name: str
    type: str  # string | int | double | bool | yaml
    default: str | None  # the literal every combination has, if one
    literals: dict[tuple[str, ...], str]  # per combination with the node; MISSING if unset


def _kind(value: Any) -> str:
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int" if abs(value) <= ROS_INT_MAX else "yaml"
    if isinstance(value, float):
        return "double" if math.isfinite(value) else "yaml"
    return "string" if isinstance(value, str) else "yaml"


def _yaml(value: Any) -> str:
    """YAML flow text that ``yaml.safe_load`` (YAML 1.1) reads back as ``value``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        text = repr(value)
        # YAML 1.1 reads 1e-05 as a string: its floats need a dot
        return text if "." in text or "e" not in text else text.replace("e", ".0e", 1)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(_yaml(v) for v in value) + "]"
    items = (f"{json.dumps(k, ensure_ascii=False)}: {_yaml(v)}" for k, v in value.items())
    return "{" + ", ".join(items) + "}"


def literal(value: Any, kind: str) -> str | None:
    """The literal of ``value`` for a parameter of type ``kind`` (None: none fits)."""
    if kind == "bool":
        return "true" if value else "false"
    if kind in ("int", "double"):
        return str(value) if kind == "int" else _yaml(value)
    if kind == "string":
        return string_literal(value)
    text = _yaml(value)
    return None if problem_yaml(text) else string_literal(text)


def node_parameters(
    ros_name: str, combinations: Mapping[tuple[str, ...], Combination]
) -> tuple[list[NodeParameter], list[Omission]]:
    """The ``.tsm`` parameters of one node, from its private parameters in every
    combination that has it, and what could not be carried over."""
    prefix = f"{ros_name}/"
    per_name: dict[str, dict[tuple[str, ...], Any]] = {}
    places: dict[str, tuple[str, int]] = {}
    for values, combination in combinations.items():
        tree: dict[str, Any] = {}
        for key, value in combination.params.items():
            if not key.startswith(prefix):
                continue
            top, _, rest = key[len(prefix) :].partition("/")
            places.setdefault(top, combination.param_places.get(key, ("", 0)))
            if not rest:
                tree[top] = value
                continue
            branch = tree.setdefault(top, {})
            *parents, leaf = rest.split("/")
            for parent in parents:
                branch = branch.setdefault(parent, {})
            branch[leaf] = value
        for top, value in tree.items():
            per_name.setdefault(top, {})[values] = value
    parameters: list[NodeParameter] = []
    warnings: list[Omission] = []
    for name in sorted(per_name):
        seen = per_name[name]
        kinds = {_kind(v) for v in seen.values()}
        kind = kinds.pop() if len(kinds) == 1 else "yaml"
        written = {c: literal(seen[c], kind) if c in seen else MISSING for c in combinations}
        literals = {c: text for c, text in written.items() if text is not None}
        file, line = places[name]
        if not is_name(name) or len(literals) < len(written):
            reason = "its name is not an identifier" if not is_name(name) else (
                "its value has no literal in the .tsm (control characters, a null or an "
                "empty mapping)")  # fmt: skip
            warnings.append(Omission(file, line, f"parameter {prefix}{name} left out: {reason}"))
            continue
        known = set(literals.values())
        default = known.pop() if len(known) == 1 and MISSING not in known else None
        parameters.append(NodeParameter(name, kind, default, literals))
    return parameters, warnings
