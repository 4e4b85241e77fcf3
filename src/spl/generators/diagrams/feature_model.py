"""Diagram of a feature model, drawn with Graphviz.

It follows the mapping paper's Fig. 5 (docs/outputs.md, "Diagrams") and the usual
feature-model notation (filled circle:
mandatory, hollow circle: optional, group connectors for xor / or / [n..m]),
highlighting a selection in green. Constraints are shown as the caller writes them
(``spl render`` passes the .fm printer's ``format_formula``: generators do not import
the languages' modules). Labels, ids and rendering follow
:mod:`spl.generators.diagrams.graphviz_output`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import graphviz

from spl.generators.diagrams.graphviz_output import (
    FONT,
    graph_id,
    html_table,
    html_text,
    plain_label,
)

if TYPE_CHECKING:
    from spl.metamodels import fm_types

__all__ = ["SELECTED_GREEN", "feature_model_graph"]

SELECTED_GREEN = "#8fd694"


def _feature_label(feature: fm_types.Feature) -> str:
    name = html_text(feature.name)
    rows = [
        f"<TR><TD>{'<I>' + name + '</I>' if feature.abstract else '<B>' + name + '</B>'}</TD></TR>"
    ]
    for attribute in feature.attributes:
        value = "" if attribute.value is None else f" = {attribute.value}"
        rows.append(
            f'<TR><TD><FONT POINT-SIZE="9">{html_text(attribute.name)} : '
            f"{html_text(attribute.type.name)}{html_text(value)}</FONT></TD></TR>"
        )
    if feature.sharing is not None:
        rows.append(
            f'<TR><TD><FONT POINT-SIZE="9">sharing {html_text(feature.sharing.mode.name)}'
            "</FONT></TD></TR>"
        )
    return html_table('BORDER="0" CELLBORDER="0" CELLSPACING="0"', rows)


def _group_text(group: fm_types.Group) -> str:
    kind = group.kind.name
    if kind == "alternative":
        return "xor"
    if kind == "or":
        return "or"
    upper = "*" if group.upper is None or group.upper < 0 else str(group.upper)
    return f"[{group.lower or 0}..{upper}]"


def feature_model_graph(
    fm: fm_types.FeatureModel,
    selected: set[str] | None = None,
    *,
    formula_text: Callable[[fm_types.Formula], str],
) -> graphviz.Digraph:
    """The feature tree in the notation of the paper's Fig. 5 (docs/index.md), selection
    in green; each
    constraint shown as ``formula_text`` writes its formula."""
    selected = set(selected or ())
    graph = graphviz.Digraph(name=fm.name or "features")
    title = plain_label(f"feature model {fm.name}")
    graph.attr(rankdir="TB", fontname=FONT, label=title, labelloc="t")
    graph.attr("node", fontname=FONT, shape="box", style="rounded,filled", fillcolor="white")
    graph.attr("edge", arrowsize="0.8")

    def add(feature: fm_types.Feature) -> None:
        fill = SELECTED_GREEN if feature.name in selected else "white"
        graph.node(graph_id("feature", feature.name), label=_feature_label(feature), fillcolor=fill)
        for index, group in enumerate(feature.groups):
            kind = group.kind.name
            if kind in ("mandatory", "optional"):
                head = "dot" if kind == "mandatory" else "odot"
                for child in group.features:
                    add(child)
                    graph.edge(
                        graph_id("feature", feature.name),
                        graph_id("feature", child.name),
                        arrowhead=head,
                        dir="forward",
                    )
                continue
            connector = graph_id("group", feature.name, str(index))
            graph.node(
                connector,
                label="",
                shape="invtriangle",
                width="0.25",
                height="0.2",
                style="filled",
                fillcolor="black" if kind == "or" else "white",
                xlabel=plain_label(_group_text(group)),
                fontsize="9",
            )
            graph.edge(graph_id("feature", feature.name), connector, arrowhead="none")
            for child in group.features:
                add(child)
                graph.edge(connector, graph_id("feature", child.name), arrowhead="none")

    add(fm.root)
    if fm.constraints:
        rows = "".join(
            f'<TR><TD ALIGN="LEFT">{html_text(formula_text(c.formula))}</TD></TR>'
            for c in fm.constraints
        )
        graph.node(
            "constraints",
            label='<<TABLE BORDER="0" CELLBORDER="0">'
            f'<TR><TD ALIGN="LEFT"><B>constraints</B></TD></TR>{rows}</TABLE>>',
            shape="note",
            style="filled",
            fillcolor="#fff9db",
            fontsize="10",
        )
    return graph
