"""Diagram of a resolved (or template) architecture, drawn with Graphviz.

The diagram uses the visual vocabulary of the mapping paper's Fig. 4 (docs/outputs.md,
"Diagrams"; docs/index.md names the paper): grey nodes, green topics,
orange endpoints, interfaces as small squares coloured by kind: yellow publishers,
cyan subscribers, green service servers, red service clients, so a resolved product
can be compared with the paper's template at a glance. Labels, ids and rendering
follow :mod:`spl.generators.diagrams.graphviz_output`, so no model text can change the
diagram's structure and the same model gives the same bytes.

Endpoint connections are drawn with what the flow table says they carry: labelled with
the number of flows, the flows in the tooltip, and a connection that carries no flow
drawn dotted grey (a bridge nothing uses).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import graphviz

from spl.generators.bundle.paths import Skipped
from spl.generators.diagrams.graphviz_output import (
    DOT_MISSING,
    FONT,
    Digraph,
    graph_id,
    html_table,
    html_text,
    plain_label,
    render_bytes,
)
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import KINDS, kind_of
from spl.resolver.architecture.flows import FlowTable
from spl.resolver.architecture.product import ResolvedProduct, topic_ros_name
from spl.resolver.architecture.ros_names import server_ros_name

if TYPE_CHECKING:
    from collections.abc import Iterable

    from spl.metamodels import tsm_types

__all__ = ["architecture_graph", "generate"]

NODE_GREY = "#d9d9d9"
TOPIC_GREEN = "#9bd49b"
ENDPOINT_ORANGE = "#f5a54a"
STORE_BLUE = "#bcd4f0"
MIGRATED_RED = "#c0392b"
CONTAINER_STYLE = {
    "RobotContainer": {"style": "rounded,filled", "fillcolor": "#eef4fb", "color": "#2f5f8f"},
    "CloudContainer": {
        "style": "rounded,filled,dashed",
        "fillcolor": "#f4effa",
        "color": "#6a3d9a",
    },
}


def _port(interface: tsm_types.Interface) -> str:
    return f"i_{interface.name}"


def _owner_id(owner: tsm_types.Node | tsm_types.Endpoint) -> str:
    """Graph id of the node or endpoint holding interfaces."""
    if isinstance(owner, tsm().Endpoint):
        return graph_id(owner.eContainer().name, "endpoint")
    return graph_id(owner.eContainer().name, "node", cast("tsm_types.Node", owner).name)


def _interface_ref(interface: tsm_types.Interface) -> str:
    return f"{_owner_id(interface.eContainer())}:{_port(interface)}"


def _topic_id(topic: tsm_types.Topic) -> str:
    container = cast("tsm_types.Container", topic.eContainer())  # a topic of the system
    return graph_id(container.name, "topic", topic.name)


def _interface_rows(interfaces: Iterable[tsm_types.Interface]) -> list[str]:
    rows = []
    for interface in interfaces:
        colour = kind_of(interface).colour
        rows.append(
            f'<TR><TD PORT="{html_text(_port(interface))}" BGCOLOR="{colour}" '
            f'WIDTH="10" HEIGHT="10" FIXEDSIZE="TRUE" BORDER="1"></TD>'
            f'<TD ALIGN="LEFT"><FONT POINT-SIZE="10">{html_text(interface.name)}</FONT></TD></TR>'
        )
    return rows


def _node_label(node: tsm_types.Node, product: ResolvedProduct | None) -> str:
    migration = product.migrated(node.name) if product is not None else None
    border = (
        f'BORDER="3" COLOR="{MIGRATED_RED}"'
        if migration is not None
        else 'BORDER="1" COLOR="black"'
    )
    rows = [f'<TR><TD COLSPAN="2"><B>{html_text(node.name)}</B></TD></TR>']
    kind = node.eClass.name
    if kind in ("Writer", "Reader"):
        rows.append(f'<TR><TD COLSPAN="2"><FONT POINT-SIZE="9">«{kind.lower()}»</FONT></TD></TR>')
    if node.package and node.executable:
        rows.append(
            f'<TR><TD COLSPAN="2"><FONT POINT-SIZE="9">{html_text(node.package)}/'
            f"{html_text(node.executable)}</FONT></TD></TR>"
        )
    sharing = node.sharing.name if node.sharing is not None else "private"
    rows.append(f'<TR><TD COLSPAN="2"><FONT POINT-SIZE="9">«{html_text(sharing)}»</FONT></TD></TR>')
    if migration is not None:
        rows.append(
            f'<TR><TD COLSPAN="2"><FONT POINT-SIZE="9" COLOR="{MIGRATED_RED}">'
            f"migrated from {html_text(migration.source)}</FONT></TD></TR>"
        )
    rows.extend(_interface_rows(node.interfaces))
    return html_table(f'{border} CELLBORDER="0" CELLSPACING="2" BGCOLOR="{NODE_GREY}"', rows)


def _endpoint_label(container: tsm_types.Container) -> str:
    endpoint = container.endpoint
    rows = ['<TR><TD COLSPAN="2"><B>endpoint</B></TD></TR>']
    if endpoint.robotId:
        rows.append(
            f'<TR><TD COLSPAN="2"><FONT POINT-SIZE="9">robot {html_text(endpoint.robotId)}'
            "</FONT></TD></TR>"
        )
    rows.extend(_interface_rows(endpoint.interfaces))
    attributes = f'BORDER="1" CELLBORDER="0" CELLSPACING="2" BGCOLOR="{ENDPOINT_ORANGE}"'
    return html_table(attributes, rows)


def _container_label(container: tsm_types.Container) -> str:
    if isinstance(container, tsm().RobotContainer):
        text = f"«robot container» {container.name}"
    else:
        text = f"«cloud container» {container.name}"
        group = cast("tsm_types.CloudContainer", container).group
        if group:
            text += f"\ngroup {group}"
    if container.namespace:
        text += f"\nnamespace {container.namespace}"
    return text


def _add_container(
    graph: graphviz.Digraph, container: tsm_types.Container, product: ResolvedProduct | None
) -> None:
    style = CONTAINER_STYLE[container.eClass.name]
    with graph.subgraph(name=f"cluster_{container.name}") as cluster:
        cluster.attr(label=plain_label(_container_label(container)), fontname=FONT, **style)
        if container.endpoint is not None:
            cluster.node(
                graph_id(container.name, "endpoint"),
                label=_endpoint_label(container),
                shape="plain",
            )
        for topic in container.topics:
            text = f"{topic.name}\n{topic_ros_name(topic)}\n{topic.type}"
            cluster.node(
                _topic_id(topic),
                label=plain_label(text),
                shape="box",
                style="filled",
                fillcolor=TOPIC_GREEN,
                fontsize="10",
            )
        for store in container.stores:
            cluster.node(
                graph_id(container.name, "store", store.name),
                label=plain_label(
                    f"«store»\n{store.name}\n{store.raw.name if store.raw else ''}".rstrip()
                ),
                shape="cylinder",
                style="filled",
                fillcolor=STORE_BLUE,
                fontsize="10",
            )
        for node in container.nodes:
            cluster.node(
                graph_id(container.name, "node", node.name),
                label=_node_label(node, product),
                shape="plain",
            )


def _data_flow_edges(graph: graphviz.Digraph, container: tsm_types.Container) -> None:
    """Data runs from a publisher through its topic to each subscriber; a call's answer
    from the server to the client bound to it."""
    owners: list[tsm_types.Node | tsm_types.Endpoint] = [*container.nodes]
    if container.endpoint is not None:
        owners.append(container.endpoint)
    for owner in owners:
        for interface in owner.interfaces:
            kind = kind_of(interface)
            bound = kind.bound_to(interface)
            if bound is None:
                continue
            if kind.publishes:
                graph.edge(_interface_ref(interface), _topic_id(bound))
            elif kind.subscribes:
                graph.edge(_topic_id(bound), _interface_ref(interface))
            elif kind.calls:
                graph.edge(
                    _interface_ref(bound),
                    _interface_ref(interface),
                    label=plain_label(server_ros_name(bound, container.eContainer())),
                    fontsize="9",
                    color="#555555",
                )


def _store_edges(graph: graphviz.Digraph, system: tsm_types.System) -> None:
    T = tsm()
    for container in system.containers:
        for node in container.nodes:
            store: tsm_types.Store | None = getattr(node, "store", None)
            if store is None:
                continue
            store_id = graph_id(store.eContainer().name, "store", store.name)
            node_id = graph_id(container.name, "node", node.name)
            if isinstance(node, T.Writer):
                graph.edge(node_id, store_id, label="POST", style="dotted", fontsize="9")
            elif isinstance(node, T.Reader):
                graph.edge(store_id, node_id, label="GET", style="dotted", fontsize="9")


def _legend(graph: graphviz.Digraph, system: tsm_types.System) -> None:
    """The colours of the diagram: every kind of interface of the families shown on
    every diagram, and the kinds of the others (an action's) where the product has one."""
    present = {kind_of(i).family for c in system.containers for n in c.nodes for i in n.interfaces}
    rows = ['<TR><TD COLSPAN="2"><B>legend</B></TD></TR>']
    for colour, text in (
        *(
            (kind.colour, kind.title)
            for kind in KINDS
            if kind.family.in_every_legend or kind.family in present
        ),
        (NODE_GREY, "node"),
        (TOPIC_GREEN, "topic"),
        (ENDPOINT_ORANGE, "endpoint"),
    ):
        rows.append(
            f'<TR><TD BGCOLOR="{colour}" WIDTH="10" HEIGHT="10" FIXEDSIZE="TRUE" BORDER="1"></TD>'
            f'<TD ALIGN="LEFT"><FONT POINT-SIZE="9">{text}</FONT></TD></TR>'
        )
    rows.append(
        '<TR><TD COLSPAN="2" ALIGN="LEFT"><FONT POINT-SIZE="9">dashed: endpoint connection'
        "</FONT></TD></TR>"
    )
    graph.node(
        "legend",
        label=html_table('BORDER="1" CELLBORDER="0" CELLSPACING="2" BGCOLOR="white"', rows),
        shape="plain",
    )


def architecture_graph(
    system: tsm_types.System,
    product: ResolvedProduct | None = None,
    quoted: dict[tuple[type, str], str] | None = None,
) -> graphviz.Digraph:
    """The resolved (or template) architecture in the notation of the paper's Fig. 4
    (docs/index.md); ``quoted``: Graphviz's quoting of the texts met so far by the
    diagrams drawn with this one (a run's), else the diagram's own."""
    graph = Digraph(name=system.name or "system", quoted=quoted)
    graph.attr(
        rankdir="LR",
        fontname=FONT,
        compound="true",
        nodesep="0.25",
        ranksep="0.6",
        label=plain_label(
            f"{system.name}" + (f" — product {product.name}" if product is not None else "")
        ),
        labelloc="t",
    )
    graph.attr("node", fontname=FONT)
    graph.attr("edge", fontname=FONT, arrowsize="0.7")
    for container in system.containers:
        _add_container(graph, container, product)
    for container in system.containers:
        _data_flow_edges(graph, container)
    flows = product.flows if product is not None else FlowTable.of(system)
    for connection in system.connections:
        carried = flows.through(connection)
        style = (
            {"style": "dashed", "color": "#d9730d", "penwidth": "1.5"}
            if carried
            else {"style": "dotted", "color": "#999999", "penwidth": "1.0"}
        )
        graph.edge(
            _interface_ref(connection.source),
            _interface_ref(connection.target),
            label=plain_label(f"{len(carried)} flow{'s' if len(carried) != 1 else ''}"),
            tooltip=plain_label("; ".join(f.describe() for f in carried) or "carries no flow"),
            fontsize="8",
            **style,
        )
    _store_edges(graph, system)
    _legend(graph, system)
    return graph


def generate(
    product: ResolvedProduct,
    render: bool = True,
    quoted: dict[tuple[type, str], str] | None = None,
) -> dict[str, bytes | Skipped]:
    """``architecture.dot`` (the Graphviz source, always) and ``architecture.svg``
    (unless ``render`` is false: ``spl validate`` checks many products and would pay one
    ``dot`` process each for a picture nobody looks at).

    The SVG needs Graphviz's ``dot`` program; without it the SVG is :class:`Skipped`
    (the least important file must not take the bundle down) and the source can be
    rendered later with ``dot -Tsvg architecture.dot``.
    """
    graph = architecture_graph(product.system, product, quoted)
    files: dict[str, bytes | Skipped] = {"architecture.dot": graph.source.encode("utf-8")}
    if not render:
        return files
    try:
        files["architecture.svg"] = render_bytes(graph, "svg")
    except graphviz.ExecutableNotFound:
        files["architecture.svg"] = Skipped(DOT_MISSING)
    return files
