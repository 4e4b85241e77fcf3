"""The Kubernetes objects of a product's cloud side, as documents (see
:mod:`spl.generators.kubernetes.manifests` for the folder they are written to).

Per cloud instance: a ``ConfigMap`` ``<name>-config`` holding the ROS 2 launch file of
exactly the instance's nodes (``launch.xml``) and, when data crosses its boundary, the
configuration of each of its ``zenoh-bridge-ros2dds`` bridges (``zenoh-bridge.json5``,
``zenoh-bridge-2.json5``, ...: one per namespace, see :mod:`spl.generators.transport.routes`);
a ``Deployment`` ``<name>`` running ``ros2 launch`` of that file in the product's ROS
image (the official image's entrypoint sources ROS, so the command is given as
``args``), with the cloud container's ``cpu`` and ``memory`` (MiB) as requests and
limits and one more container per bridge; a ``Service`` ``<name>`` on the bridges'
Zenoh ports (7447, 7448, ...), which the Zenoh router connects to. The nodes run with
``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` and the bridges with the same setting in
their configuration, so DDS discovery stays inside the pod, where the bridges carry
exactly the crossing topics and services. Every pod runs at the restricted Pod
Security level (:mod:`spl.generators.workloads.security`), with requests, limits and
probes (:mod:`spl.generators.workloads.resources`), in its product's namespace, behind
a NetworkPolicy allowing only its connections
(:mod:`spl.generators.workloads.network_policy`). The Zenoh router's objects are
:mod:`spl.generators.kubernetes.router`'s.

Labels name the product, TSM container, instance (placement tag) and sharing mode.
Keys are written in the order built and YAML without anchors: same product, same bytes.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple, cast

import yaml

from spl import __version__
from spl.generators.json_text import Document
from spl.generators.kubernetes.yaml_text import block_yaml
from spl.generators.transport.bridge import ZENOH_PORT, CloudBridge
from spl.generators.workloads.names import CONFIG_SUFFIX, label_value
from spl.generators.workloads.network_policy import Connection, workload_policy
from spl.generators.workloads.resources import (
    FIRST_ADMIN_PORT,
    admin_port_name,
    resources,
    ros_node_names,
    ros_probes,
    zenoh_probes,
)
from spl.generators.workloads.security import harden, ros_environment, waiver_annotations
from spl.resolver.architecture.placement import Instance
from spl.resolver.architecture.product import ResolvedProduct

ROS_IMAGE = "ros:jazzy-ros-core"
BRIDGE_IMAGE = "eclipse/zenoh-bridge-ros2dds:1.10.0"
ROUTER_IMAGE = "eclipse/zenoh:1.10.0"
CONFIG_DIR = "/etc/spl"
LABEL = "spl.robotics"
MANAGED_BY = {"app.kubernetes.io/managed-by": "spl-robotics"}


class _Literal(str):
    """A multi-line string written as a YAML literal block (launch files, configs)."""


def with_known_tags(base: type) -> type:
    """``base`` (a PyYAML loader or dumper) looking each plain scalar's implicit tag up
    once per process: PyYAML matches every scalar against its resolvers' regular
    expressions, twice per scalar when writing, and a product's manifests repeat the same
    keys and values many times over. The tag depends on the scalar's text and the
    resolvers alone (path resolvers, which would make it depend on the place too, are
    not used: then every scalar is resolved as before)."""
    known: dict[tuple[str, tuple[bool, bool]], str] = {}

    class KnownTags(base):
        def resolve(self, kind: type, value: str, implicit: tuple[bool, bool]) -> str:
            if kind is not yaml.ScalarNode or self.yaml_path_resolvers or len(value) > 64:
                return super().resolve(kind, value, implicit)
            key = (value, implicit)
            tag = known.get(key)
            if tag is None:
                if len(known) >= 50_000:
                    known.clear()
                tag = known[key] = super().resolve(kind, value, implicit)
            return tag

    KnownTags.__name__ = KnownTags.__qualname__ = f"KnownTags{base.__name__}"
    return KnownTags


_STR = "tag:yaml.org,2002:str"
_SCALARS: dict[type, tuple[str, Callable[[object], str]]] = {
    str: (_STR, str),
    int: ("tag:yaml.org,2002:int", str),
    bool: ("tag:yaml.org,2002:bool", lambda value: "true" if value else "false"),
    type(None): ("tag:yaml.org,2002:null", lambda value: "null"),
}


class _DocumentNodes:
    """The nodes PyYAML's safe representer builds for a document of dicts, lists, str,
    int, bool, None and :class:`_Literal` (keys in the order built, block style), built
    without its per-value walk through the representer table, alias bookkeeping and
    style guessing (two thirds of writing a product's manifests besides the emitter);
    any other value goes through the representer. New node objects every time: the
    emitter anchors a node met twice. tests/test_kubernetes_products.py checks the bytes
    equal to PyYAML's own representer's for every shipped product."""

    def represent(self, data: object) -> None:
        self.serialize(self._node(data))  # type: ignore[attr-defined]
        # as PyYAML's represent leaves them
        self.represented_objects: dict[int, yaml.Node] = {}
        self.object_keeper: list[object] = []
        self.alias_key = None

    def _node(self, data: object) -> yaml.Node:
        kind = type(data)
        if kind is dict:
            mapping = cast("dict[object, object]", data)
            pairs = [(self._node(key), self._node(value)) for key, value in mapping.items()]
            return yaml.MappingNode("tag:yaml.org,2002:map", pairs, flow_style=False)
        if kind is list:
            items = [self._node(item) for item in cast("list[object]", data)]
            return yaml.SequenceNode("tag:yaml.org,2002:seq", items, flow_style=False)
        if kind is _Literal:
            return yaml.ScalarNode(_STR, str(data), style="|")
        scalar = _SCALARS.get(kind)
        if scalar is None:
            return self.represent_data(data)  # type: ignore[attr-defined]
        return yaml.ScalarNode(scalar[0], scalar[1](data), style=None)


def _dumper(base: type, nodes: bool = True) -> type:
    """Safe YAML without anchors (every object written out in full), literal blocks for
    :class:`_Literal`, on ``base``'s emitter; with ``nodes``, a document's nodes built by
    :class:`_DocumentNodes` (the same nodes, faster)."""

    class Dumper(*((_DocumentNodes,) if nodes else ()), with_known_tags(base)):  # type: ignore[misc]
        def ignore_aliases(self, data: object) -> bool:
            return True

    # str(): libyaml's emitter takes exact str objects only
    Dumper.add_representer(
        _Literal,
        lambda dumper, text: dumper.represent_scalar("tag:yaml.org,2002:str", str(text), "|"),
    )
    return Dumper


# libyaml's emitter where PyYAML has it (five times faster on a product's manifests), the
# pure-Python one elsewhere; tests/test_kubernetes_manifests.py checks that both write the
# same bytes for every shipped product, so a bundle does not depend on the machine.
PYTHON_DUMPER = _dumper(yaml.SafeDumper)
DUMPER = _dumper(getattr(yaml, "CSafeDumper", yaml.SafeDumper))
# Documents of the shapes kubernetes_yaml writes are written by it (the emitters' bytes,
# tests/test_kubernetes_yaml.py), others by DUMPER; None: every document by DUMPER.
WRITER: Callable[[list[Document], type, dict[str, bool] | None], str | None] | None = block_yaml


def render(documents: list[Document], header: str, plain: dict[str, bool] | None = None) -> bytes:
    """Documents as one YAML stream, keys in the order built, a comment header;
    ``plain``: the strings found plain so far by the caller (:func:`block_yaml`)."""
    body = WRITER(documents, _Literal, plain) if WRITER is not None else None
    if body is None:
        body = yaml.dump_all(
            documents, Dumper=DUMPER, sort_keys=False, default_flow_style=False, width=2**16
        )
    return f"# {header}\n{body}".encode()


def title(owner: str, what: str, kind: str = "product") -> str:
    """The comment heading a generated manifest of a product (or fleet) ``owner``; no
    timestamp: same inputs, same bytes."""
    return (
        f"Generated by spl-robotics {__version__} for {kind} {label_value(owner)}, "
        f"{what}. Edit the models, not this file."
    )


def instance_labels(product_name: str, instance: Instance, name: str) -> dict[str, str]:
    """The labels of an instance's objects; ``name`` alone selects its pod."""
    place = instance.place
    return {
        "app.kubernetes.io/name": name,
        "app.kubernetes.io/part-of": label_value(product_name),
        **MANAGED_BY,
        f"{LABEL}/container": label_value(place.container),
        f"{LABEL}/placement": label_value(place.tag),
        f"{LABEL}/sharing": place.kind,
    }


def _localhost_env() -> list[dict[str, str]]:
    return [{"name": "ROS_AUTOMATIC_DISCOVERY_RANGE", "value": "LOCALHOST"}]


class Placed(NamedTuple):
    """Where a product's (or fleet's) objects go and what they may connect to: the
    namespace, the product whose feature attributes size the containers (None: the
    defaults), and the connections the policies allow."""

    namespace: str
    product: ResolvedProduct | None
    connections: list[Connection]


def instance_documents(
    product_name: str,
    instance: Instance,
    name: str,
    launch_xml: bytes,
    bridges: list[CloudBridge],
    placed: Placed,
) -> list[Document]:
    """ConfigMap, Deployment, NetworkPolicy and (with bridges) Service of one instance."""
    labels = instance_labels(product_name, instance, name)
    namespace = placed.namespace
    metadata: Document = {
        "name": name,
        "namespace": namespace,
        "labels": labels,
        "annotations": {
            f"{LABEL}/product": product_name,
            f"{LABEL}/nodes": ", ".join(node.name for node in instance.nodes),
            f"{LABEL}/robots": ", ".join(instance.robots),
            **waiver_annotations(),
        },
    }
    data = {"launch.xml": _Literal(launch_xml.decode("utf-8"))}
    sidecars = [bridge_name(n) for n in range(len(bridges))]
    for sidecar, bridge in zip(sidecars, bridges, strict=True):
        data[f"{sidecar}.json5"] = _Literal(bridge.config)
    config_map: Document = {
        "apiVersion": "v1",
        "kind": "ConfigMap",
        "metadata": {"name": name + CONFIG_SUFFIX, "namespace": namespace, "labels": labels},
        "data": data,
    }
    mount = [{"name": "config", "mountPath": CONFIG_DIR, "readOnly": True}]
    cloud = instance.container
    ros: Document = {
        "name": "ros",
        "image": ROS_IMAGE,
        "args": ["ros2", "launch", f"{CONFIG_DIR}/launch.xml"],
        "env": _localhost_env() + ros_environment(),
        "volumeMounts": list(mount),
        "resources": resources("ros", placed.product, cloud.cpu, cloud.memory),
        **ros_probes(ros_node_names(cloud.namespace, [node.name for node in instance.nodes])),
    }
    containers: list[Document] = [ros]
    for index, (sidecar, bridge) in enumerate(zip(sidecars, bridges, strict=True)):
        admin = admin_port_name(index)
        containers.append(
            {
                "name": sidecar,
                "image": BRIDGE_IMAGE,
                "args": [
                    "-c",
                    f"{CONFIG_DIR}/{sidecar}.json5",
                    "--rest-http-port",
                    str(FIRST_ADMIN_PORT + index),
                ],
                "ports": [
                    {"name": port_name(bridge), "containerPort": bridge.port, "protocol": "TCP"},
                    {"name": admin, "containerPort": FIRST_ADMIN_PORT + index, "protocol": "TCP"},
                ],
                "volumeMounts": list(mount),
                "resources": resources("bridge", placed.product),
                **zenoh_probes(admin),
            }
        )
    pod = {
        "containers": containers,
        "volumes": [{"name": "config", "configMap": {"name": name + CONFIG_SUFFIX}}],
    }
    deployment: Document = {
        "apiVersion": "apps/v1",
        "kind": "Deployment",
        "metadata": metadata,
        "spec": {
            "replicas": 1,
            "selector": {"matchLabels": {"app.kubernetes.io/name": name}},
            "template": {"metadata": {"labels": labels}, "spec": harden(pod)},
        },
    }
    documents: list[Document] = [config_map, deployment]
    documents.append(workload_policy(name, namespace, labels, placed.connections))
    if bridges:
        ports = [(port_name(bridge), bridge.port) for bridge in bridges]
        documents.append(service(name, namespace, labels, "ClusterIP", ports))
    return documents


def bridge_name(index: int) -> str:
    """The sidecar running an instance's ``index``-th bridge (and its config file)."""
    return "zenoh-bridge" if index == 0 else f"zenoh-bridge-{index + 1}"


def port_name(bridge: CloudBridge) -> str:
    """A container port name (at most 15 characters): ``zenoh``, ``zenoh-7448``, ..."""
    return "zenoh" if bridge.port == ZENOH_PORT else f"zenoh-{bridge.port}"


def service(
    name: str, namespace: str, labels: dict[str, str], kind: str, ports: list[tuple[str, int]]
) -> Document:
    """A Service selecting workload ``name``'s pods on named ``ports``."""
    return {
        "apiVersion": "v1",
        "kind": "Service",
        "metadata": {"name": name, "namespace": namespace, "labels": labels},
        "spec": {
            "type": kind,
            "selector": {"app.kubernetes.io/name": name},
            "ports": [
                {"name": port, "port": number, "targetPort": port, "protocol": "TCP"}
                for port, number in ports
            ],
        },
    }
