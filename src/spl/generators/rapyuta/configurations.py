"""Rapyuta (RoboEarth Cloud Engine) configuration: one rce-ros file per robot container.

Sharing placement (docs/deployment.md) is :mod:`spl.resolver.architecture.placement`'s rule: a TSM
cloud
container ``C`` becomes up to three Rapyuta containers, ``<C>_<robotID>`` for private
nodes (one per robot that feeds them or that they feed), ``<C>_<group>`` for protected
nodes (one per group; carries ``"group": "<group>"``) and ``<C>_public`` for public nodes.

A robot *uses* ``C`` when endpoint connections link the two, directly or through other
cloud containers (robots never relay for each other). Each robot's file declares its
private containers; a shared container, with its nodes, parameters and interfaces (the
union over all robots), is declared by one file only, the first by name of the robots
using it, since the engine refuses a tag its user already has (:func:`declare_once`);
the other robots' files connect to its interfaces, so that file is applied first.
Instead of copying the TSM's endpoint interfaces, the files carry the flows that
cross from one Rapyuta endpoint to another (:mod:`spl.resolver.architecture.wiring`), each as one
bridge (:mod:`spl.generators.rapyuta.bridges`).

Parameters are set as ``/<nTag>/<param>`` (under the container's namespace, if any):
int, double and bool values are typed JSON; a yaml value is parsed and written as JSON
when it is a scalar or a list of scalars (what the engine's format carries), otherwise
as its YAML text. The password is the placeholder ``${VAR}`` naming the endpoint's
environment variable; a deployment substitutes it (``envsubst``), never this file.

The JSON is written with sorted keys, lists in a fixed order, indent 2 and a final
newline, then checked against the shipped schema and the engine's rules before it is
returned: a file the engine would refuse is never emitted.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from collections.abc import Iterable
from typing import TYPE_CHECKING, cast

import yaml

from spl.core.diagnostics import Diagnostic, ModelError, location_of
from spl.generators.json_text import Document, indented
from spl.generators.rapyuta.bridges import Bridges
from spl.generators.rapyuta.rules import CleanSets, check_all
from spl.resolver.architecture.placement import Place, Placement
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.ros_names import in_namespace

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

ENV_VAR = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
Entry = dict[str, object]  # one entry of a configuration's list (a container, a node, ...)


def parameter_value(parameter: tsm_types.Parameter) -> object:
    """The JSON value of a parameter from its canonical text, typed as the engine takes it."""
    kind = parameter.type.name if parameter.type is not None else "string"
    text = parameter.value
    if kind == "int":
        return int(text)
    if kind == "double":
        number = float(text)
        if not math.isfinite(number):
            raise ValueError(f"{text!r} is not a finite number")
        return number
    if kind == "bool":
        if text not in ("true", "false"):
            raise ValueError(f"{text!r} is not true or false")
        return text == "true"
    if kind == "yaml":
        data = yaml.safe_load(text)
        if _json_scalar(data) or (isinstance(data, list) and all(map(_json_scalar, data))):
            return data
        return text
    return text


def _json_scalar(value: object) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    return isinstance(value, (str, int, bool))


def _credentials(robot: tsm_types.Container, errors: list[Diagnostic]) -> dict[str, str]:
    endpoint = robot.endpoint
    if endpoint is None:
        errors.append(
            Diagnostic(
                location_of(robot),
                f"robot container {robot.name} has no endpoint (robot_id, url, user, password env)",
            )
        )
        return {}
    where = location_of(endpoint) or location_of(robot)
    values = {
        "url": endpoint.url,
        "userID": endpoint.user,
        "password": endpoint.passwordEnv,
    }
    for key, value in values.items():
        if not value:
            errors.append(
                Diagnostic(
                    where,
                    f"robot container {robot.name}: the endpoint "
                    f"has no {key} (needed by the rce-ros client)",
                )
            )
    env = endpoint.passwordEnv
    if env and not ENV_VAR.fullmatch(env):
        errors.append(
            Diagnostic(
                where,
                f"robot container {robot.name}: password env {env!r} "
                "is not an environment variable name",
            )
        )
    return {
        "url": endpoint.url or "",
        "userID": endpoint.user or "",
        "password": f"${{{env}}}",
    }


def _partition_entries(
    place: Place,
    cloud: tsm_types.CloudContainer,
    nodes: Iterable[tsm_types.Node],
    errors: list[Diagnostic],
) -> tuple[Entry, list[Entry], list[Entry]]:
    container: Entry = {"cTag": place.tag}
    if place.kind == "protected":
        container["group"] = place.owner
    for resource in ("size", "cpu", "memory", "bandwidth"):
        value = getattr(cloud, resource)
        if value is not None:
            container[resource] = value
    node_entries: list[Entry] = []
    parameter_entries: list[Entry] = []
    namespace = cloud.namespace
    for node in sorted(nodes, key=lambda n: n.name):
        if not node.package or not node.executable:
            errors.append(
                Diagnostic(
                    location_of(node),
                    f"node {node.name} has no implementation (package/executable)",
                )
            )
            continue
        entry: Entry = {
            "cTag": place.tag,
            "nTag": node.name,
            "pkg": node.package,
            "exe": node.executable,
            "name": node.name,
        }
        if node.args:
            entry["args"] = node.args
        if namespace:
            entry["namespace"] = namespace
        node_entries.append(entry)
        for parameter in node.parameters:
            if parameter.value is None:
                continue  # left to the node's default: nothing to set
            try:
                value = parameter_value(parameter)
            except (ValueError, yaml.YAMLError) as error:
                errors.append(
                    Diagnostic(
                        location_of(parameter), f"parameter {node.name}.{parameter.name}: {error}"
                    )
                )
                continue
            parameter_entries.append(
                {
                    "cTag": place.tag,
                    "name": in_namespace(f"{node.name}/{parameter.name}", namespace)
                    if namespace
                    else f"/{node.name}/{parameter.name}",
                    "value": value,
                }
            )
    return container, node_entries, parameter_entries


def configurations(product: ResolvedProduct) -> dict[str, Document]:
    """The rce-ros configuration of every robot container, by container name."""
    errors: list[Diagnostic] = []
    placement = Placement(product.system, errors, flows=product.flows)
    bridges = Bridges(product.flows, placement, errors)
    documents: dict[str, Document] = {}
    for robot in placement.robots:
        robot_id = placement.robot_ids[id(robot)]
        document: Document = {**_credentials(robot, errors), "robotID": robot_id}
        declared = {robot_id}
        containers: list[Entry] = []
        nodes: list[Entry] = []
        parameters: list[Entry] = []
        for instance in placement.partitions(robot):  # the private ones it gets, docs/deployment.md
            container, node_entries, parameter_entries = _partition_entries(
                instance.place, instance.container, instance.nodes, errors
            )
            declared.add(instance.place.tag)
            containers.append(container)
            nodes.extend(node_entries)
            parameters.extend(parameter_entries)
        interfaces = [spec for key, spec in bridges.interfaces.items() if key[0] in declared]
        connections = [b.as_json() for b in bridges.of_robot[id(robot)]]
        lists: dict[str, list[Entry] | list[dict[str, str]]] = {
            "containers": sorted(containers, key=lambda c: _tags(c, "cTag")),
            "nodes": sorted(nodes, key=lambda n: _tags(n, "cTag", "nTag")),
            "parameters": sorted(parameters, key=lambda p: _tags(p, "cTag", "name")),
            "interfaces": sorted(interfaces, key=lambda i: (i["eTag"], i["iTag"])),
            "connections": sorted(connections, key=lambda c: (c["tagA"], c["tagB"])),
        }
        document.update({key: value for key, value in lists.items() if value})
        documents[robot.name] = document
    if errors:
        raise ModelError(_unique(errors))
    declare_once(documents)
    return documents


# Per list: the fields identifying an entry, and the field naming the container it
# belongs to (None: a connection, which belongs to no container).
LISTS = {
    "containers": (("cTag",), "cTag"),
    "nodes": (("cTag", "nTag"), "cTag"),
    "parameters": (("cTag", "name"), "cTag"),
    "interfaces": (("eTag", "iTag"), "eTag"),
    "connections": (("tagA", "tagB"), None),
}


def _tags(entry: Entry, *fields: str) -> tuple[str, ...]:
    """The tags identifying an entry (text, each), in the order given, to sort by."""
    return cast("tuple[str, ...]", tuple(entry[field] for field in fields))


def declare_once(documents: dict[str, Document]) -> None:
    """Declare what several robots' files share in one file only, in place.

    The engine creates a container when the first file naming it is applied and refuses
    the tag from any later file of the same user; a connection made twice is refused
    too. So a container several files declare (a shared partition several robots use)
    stays in the first of them (by file name: the model's order does not matter) with
    its nodes and parameters and the union over all files of its interfaces, and each
    connection in the first file that has it; the later files connect to those
    interfaces, as the engine's ``lo_client.cfg`` connects to what ``lo_server.cfg``
    declares. An entry that differs from the first file's is left where it is, for the
    rules to refuse. Each user has containers of its own in the engine, so this holds
    among the files of one user (``userID``): robots of two users sharing a partition
    each get their user's instance of it."""
    users: dict[object, list[str]] = defaultdict(list)
    for name in sorted(documents):
        users[documents[name].get("userID")].append(name)
    for names in users.values():
        _declare_once(documents, names)


def _declare_once(documents: dict[str, Document], order: list[str]) -> None:
    """:func:`declare_once` over the files ``order`` of one user."""
    owners: dict[object, str] = {}
    for name in order:
        for entry in _list(documents[name], "containers"):
            owners.setdefault(entry["cTag"], name)
    first: dict[tuple[object, ...], tuple[str, Entry]] = {}  # identity -> (file, entry)
    moved: dict[tuple[str, str], list[Entry]] = defaultdict(list)
    for name in order:
        document = documents[name]
        for key, (fields, owner_field) in LISTS.items():
            entries = _list(document, key)
            if not entries:
                continue
            stay = []
            for entry in entries:
                identity = (key, *(entry[f] for f in fields))
                earlier = first.setdefault(identity, (name, entry))
                if earlier[0] != name:
                    if earlier[1] != entry:
                        stay.append(entry)  # declared differently: the rules say so
                    continue  # an earlier file declares it
                owner = owners.get(entry[owner_field]) if owner_field else None
                if earlier[1] is entry and owner is not None and owner != name:
                    moved[(owner, key)].append(entry)
                else:
                    stay.append(entry)
            document[key] = stay
    for (owner, key), entries in moved.items():
        cast("list[Entry]", documents[owner].setdefault(key, [])).extend(entries)
    for name in order:
        document = documents[name]
        for key, (fields, _) in LISTS.items():
            if key in document:
                if document[key]:
                    _list(document, key).sort(key=lambda e: _tags(e, *fields))
                else:
                    del document[key]


def _list(document: Document, key: str) -> list[Entry]:
    """One of a configuration's lists (LISTS), empty when it has none."""
    return cast("list[Entry]", document.get(key, ()))


def _unique(errors: list[Diagnostic]) -> list[Diagnostic]:
    return list(dict.fromkeys(errors))


def render(document: Document) -> bytes:
    """Deterministic JSON: sorted keys, indent 2, final newline."""
    return (indented(document, sort_keys=True, allow_nan=False) + "\n").encode()


def generate(product: ResolvedProduct, clean: CleanSets | None = None) -> dict[str, bytes]:
    """``rapyuta/<robot>.json`` for every robot container of the product, checked against
    the engine's rules (``clean``: the file sets found clean by the bundles written with
    this one, which the check adds to)."""
    documents = configurations(product)
    names = [f"{name}.json" for name in documents]
    problems = check_all(list(documents.values()), names, clean)
    if problems:
        raise ModelError(
            [Diagnostic(None, f"generated Rapyuta configuration refused: {p}") for p in problems]
        )
    return {f"rapyuta/{name}.json": render(doc) for name, doc in sorted(documents.items())}
