"""What hovering a name shows: the declaration it denotes, in the words of the models
(a feature's group, parent, attributes, sharing mode and constraints; a node's
container, implementation and interfaces; a topic's type and ROS name)."""

from __future__ import annotations

from typing import Any

from spl.lsp.symbols import Decl, SymbolIndex
from spl.metamodels.interface_kinds import kind_of

GROUPS = {
    "mandatory": "mandatory",
    "optional": "optional",
    "alternative": "xor group",
    "or": "or group",
}


def describe(decls: tuple[Decl, ...], index: SymbolIndex) -> str:
    """Markdown for every declaration a name denotes (two for an ambiguous name)."""
    return "\n\n---\n\n".join(text for d in decls if (text := _describe(d, index)))


def _describe(decl: Decl, index: SymbolIndex) -> str:
    element = decl.element
    where = f"{decl.file}:{decl.line}:{decl.col}" if decl.line else decl.file
    if decl.kind == "file":
        return f"**file** `{decl.file}`"
    if element is None:  # a `new topic` of the .rm
        return f"**topic** `{decl.name}`, created by `connect ... to new topic` ({where})"
    describe_kind = _KINDS.get(decl.kind)
    body = describe_kind(element, index) if describe_kind else []
    title = f"**{decl.kind}** `{'.'.join(decl.qualified)}`"
    return "\n\n".join([title, *body, f"declared at {where}"])


def _literal(value: Any) -> str:
    return "" if value is None else str(value)


def _feature(feature: Any, index: SymbolIndex) -> list[str]:
    from spl.dsl.fm.printer import format_formula

    lines = []
    group = feature.eContainer()
    if group is not None and group.eClass.name == "Group":
        parent = group.eContainer()
        kind = _literal(group.kind.name if group.kind is not None else "")
        if kind == "cardinality":
            upper = "*" if group.upper == -1 else group.upper
            kind = f"group [{group.lower}..{upper}]"
        siblings = [f.name for f in group.features if f is not feature]
        shown = GROUPS.get(kind, kind)
        members = f" with {', '.join(siblings)}" if siblings and shown.endswith("group") else ""
        lines.append(f"{shown}{members}, child of `{parent.name}`")
    else:
        lines.append("root feature")
    if feature.abstract:
        lines.append("abstract")
    for attribute in feature.attributes:
        kind = attribute.type.name if attribute.type is not None else ""
        lines.append(f"attribute `{attribute.name} : {kind} = {attribute.value}`")
    if feature.sharing is not None:
        lines.append(f"sharing `{feature.sharing.mode.name}`")
    model = _root_model(feature)
    for constraint in getattr(model, "constraints", ()):
        if any(r.feature is feature for r in _references(constraint.formula)):
            lines.append(f"constraint `{format_formula(constraint.formula)}`")
    return lines


def _root_model(element: Any) -> Any:
    while element.eContainer() is not None:
        element = element.eContainer()
    return element


def _references(formula: Any) -> list[Any]:
    kind = formula.eClass.name
    if kind == "FeatureRef":
        return [formula]
    if kind == "Not":
        return _references(formula.operand)
    return _references(formula.left) + _references(formula.right)


def _attribute(attribute: Any, index: SymbolIndex) -> list[str]:
    kind = attribute.type.name if attribute.type is not None else ""
    owner = attribute.eContainer().name
    return [f"`{attribute.name} : {kind} = {attribute.value}` of feature `{owner}`"]


def _node(node: Any, index: SymbolIndex) -> list[str]:
    container = node.eContainer()
    kind = "robot" if container.eClass.name == "RobotContainer" else "cloud"
    lines = [f"in {kind} container `{container.name}`"]
    traits = [t for t in ("optional" if node.optional else "",) if t]
    sharing = getattr(node, "sharing", None)
    if sharing is not None:
        traits.append(f"sharing {sharing.name}")
    if traits:
        lines.append(", ".join(traits))
    if getattr(node, "package", None):
        args = f" args `{node.args}`" if node.args else ""
        lines.append(f"implementation `{node.package}/{node.executable}`{args}")
    rows = [f"- {_interface_line(i)}" for i in getattr(node, "interfaces", ())]
    rows += [f"- param `{p.name} : {_literal(p.type)}`{_value(p)}" for p in node.parameters]
    if rows:
        lines.append("\n".join(rows))
    return lines


def _value(parameter: Any) -> str:
    return f" = `{parameter.value}`" if parameter.value is not None else ""


def _interface_line(interface: Any) -> str:
    """The interface as its .tsm statement says it (docs/tsm.md): keyword, name, type,
    and what it is bound to, a topic or the server it calls."""
    kind = kind_of(interface)
    line = f"{kind.keyword} `{interface.name}`"
    if interface.type:
        line += f" : `{interface.type}`"
    bound = kind.bound_to(interface)
    if bound is not None and kind.on_topic:
        line += f" {kind.arrow} topic `{bound.name}`"
    elif bound is not None:
        line += f" {kind.arrow} `{bound.eContainer().name}.{bound.name}`"
    return line


def _interface(interface: Any, index: SymbolIndex) -> list[str]:
    title = kind_of(interface).title
    return [_interface_line(interface), f"{title} of node `{interface.eContainer().name}`"]


def _topic(topic: Any, index: SymbolIndex) -> list[str]:
    ros_name = topic.rosName or f"/{topic.name}"
    return [
        f"type `{topic.type}`",
        f"ROS name `{ros_name}`",
        f"in container `{topic.eContainer().name}`",
    ]


def _container(container: Any, index: SymbolIndex) -> list[str]:
    kind = "robot" if container.eClass.name == "RobotContainer" else "cloud"
    counts = f"{len(container.nodes)} nodes, {len(container.topics)} topics"
    return [f"{kind} container", counts]


def _parameter(parameter: Any, index: SymbolIndex) -> list[str]:
    return [f"`{parameter.name} : {_literal(parameter.type)}`{_value(parameter)}"]


def _store(store: Any, index: SymbolIndex) -> list[str]:
    lines = [f"in container `{store.eContainer().name}`", f"raw `{store.raw.name}`"]
    lines += [
        f"refined `{r.output.name}` by `{r.transform.name}` every {r.period} s"
        for r in store.refinements
    ]
    return lines


def _data(data_type: Any, index: SymbolIndex) -> list[str]:
    return ["\n".join(f"- `{f.name} : {_literal(f.type)}`" for f in data_type.fields)]


def _transform(transform: Any, index: SymbolIndex) -> list[str]:
    return [f"`{transform.input.name}` -> `{transform.output.name}`"]


_KINDS = {
    "feature": _feature,
    "attribute": _attribute,
    "node": _node,
    "interface": _interface,
    "topic": _topic,
    "container": _container,
    "parameter": _parameter,
    "store": _store,
    "data": _data,
    "transform": _transform,
}
