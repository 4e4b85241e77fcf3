"""The declarations of a .tsm, a .fm and the `new topic` statements of a .rm, and how
a (dotted) name of the three languages reaches them.

A declaration keeps the element the parser built (for hover) and the place the
parser recorded (``srcFile:srcLine:srcCol``, at the name), so "go to definition"
lands where ``spl check`` would point. Lookups follow the naming rules of the .rm
(docs/semantics.md) as far as they are known without a product: an unqualified node
declared in two containers, or a topic that a migration may have moved next to its
node, gives every candidate rather than a guess.
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any


@dataclass(frozen=True)
class Decl:
    """One declaration: ``kind`` (container, node, store, topic, interface, parameter,
    data, field, transform, feature, attribute, file), its qualified name and place."""

    kind: str
    qualified: tuple[str, ...]
    file: str
    line: int
    col: int
    element: Any = field(default=None, compare=False, hash=False, repr=False)

    @property
    def name(self) -> str:
        return self.qualified[-1]


# The topics a .rm declares with `connect ... to new topic NAME`, by name.
NewTopics = dict[str, list[Decl]]


def _decl(kind: str, qualified: tuple[str, ...], element: Any) -> Decl:
    return Decl(
        kind,
        qualified,
        getattr(element, "srcFile", None) or "",
        getattr(element, "srcLine", None) or 0,
        getattr(element, "srcCol", None) or 0,
        element,
    )


class SymbolIndex:
    """Every declaration of one set of models, by name and by place."""

    def __init__(
        self,
        system: Any = None,
        feature_model: Any = None,
        line_of: Callable[[str, int], str] | None = None,
    ) -> None:
        """``line_of(file, line)`` gives a line of a model's text: some elements are
        located at their keyword (``attribute rate``), and a declaration is kept at its
        name."""
        self.line_of = line_of
        self.containers: dict[str, Decl] = {}
        self.members: dict[tuple[str, str], Decl] = {}  # (container, node|store)
        self.by_name: dict[str, list[Decl]] = defaultdict(list)  # nodes and stores
        self.topics: dict[tuple[str, str], Decl] = {}  # (container, topic)
        self.topic_names: dict[str, list[Decl]] = defaultdict(list)
        self.node_members: dict[tuple[str, ...], Decl] = {}  # (c, n, kind, name)
        self.data_types: dict[str, Decl] = {}
        self.fields: dict[tuple[str, str], Decl] = {}
        self.transforms: dict[str, Decl] = {}
        self.features: dict[str, Decl] = {}
        self.attributes: dict[tuple[str, str], Decl] = {}
        self.at_place: dict[tuple[str, int, int], Decl] = {}
        if system is not None:
            self._add_system(system)
        if feature_model is not None and feature_model.root is not None:
            self._add_feature(feature_model.root)

    def _put(self, decl: Decl) -> Decl:
        if decl.line and self.line_of is not None:
            text = self.line_of(decl.file, decl.line)
            if text[decl.col - 1 : decl.col - 1 + len(decl.name)] != decl.name:
                found = re.compile(rf"\b{re.escape(decl.name)}\b").search(text, decl.col - 1)
                if found:
                    decl = replace(decl, col=found.start() + 1)
        if decl.line:
            self.at_place.setdefault((decl.file, decl.line, decl.col), decl)
        return decl

    def _add_system(self, system: Any) -> None:
        for data_type in system.dataTypes:
            self.data_types[data_type.name] = self._put(_decl("data", (data_type.name,), data_type))
            for f in data_type.fields:
                key = (data_type.name, f.name)
                self.fields[key] = self._put(_decl("field", key, f))
        for transform in system.transforms:
            self.transforms[transform.name] = self._put(
                _decl("transform", (transform.name,), transform)
            )
        for container in system.containers:
            c = container.name
            self.containers[c] = self._put(_decl("container", (c,), container))
            for topic in container.topics:
                decl = self._put(_decl("topic", (c, topic.name), topic))
                self.topics[(c, topic.name)] = decl
                self.topic_names[topic.name].append(decl)
            for member in [*container.nodes, *container.stores]:
                kind = "store" if member.eClass.name == "Store" else "node"
                decl = self._put(_decl(kind, (c, member.name), member))
                self.members[(c, member.name)] = decl
                self.by_name[member.name].append(decl)
                for what, items in (
                    ("interface", getattr(member, "interfaces", ())),
                    ("parameter", getattr(member, "parameters", ())),
                ):
                    for item in items:
                        member_key = (c, member.name, what, item.name)
                        self.node_members[member_key] = self._put(
                            _decl(what, (c, member.name, item.name), item)
                        )

    def _add_feature(self, feature: Any) -> None:
        self.features[feature.name] = self._put(_decl("feature", (feature.name,), feature))
        for attribute in feature.attributes:
            key = (feature.name, attribute.name)
            self.attributes[key] = self._put(_decl("attribute", key, attribute))
        for group in feature.groups:
            for child in group.features:
                self._add_feature(child)

    # -- lookups: each gives, per part of a dotted name, what that part names ----------------
    def elements(self, parts: list[str]) -> list[list[Decl]]:
        """``NAME`` or ``CONTAINER.NAME``: a node or store (every candidate)."""
        if len(parts) == 1:
            return [list(self.by_name.get(parts[0], ()))]
        if len(parts) == 2:
            container = self.containers.get(parts[0])
            member = self.members.get((parts[0], parts[1]))
            return [[container] if container else [], [member] if member else []]
        return [[] for _ in parts]

    def node_items(self, parts: list[str], what: str) -> list[list[Decl]]:
        """``[CONTAINER.]NODE.NAME``: an interface or parameter of a node."""
        if not 2 <= len(parts) <= 3:
            return [[] for _ in parts]
        owners = self.elements(parts[:-1])
        found = [
            item
            for owner in owners[-1]
            if (item := self.node_members.get((*owner.qualified, what, parts[-1])))
        ]
        return [*owners, found]

    def topic(
        self, parts: list[str], containers: list[str], created: NewTopics | None = None
    ) -> list[list[Decl]]:
        """``TOPIC`` (looked up in ``containers`` and among the .rm's `new topic`s, else
        anywhere) or ``CONTAINER.TOPIC``."""
        created = created or {}
        if len(parts) == 2:
            container = self.containers.get(parts[0])
            topic = self.topics.get((parts[0], parts[1]))
            found = [topic] if topic else list(created.get(parts[1], ()))
            return [[container] if container else [], found]
        if len(parts) != 1:
            return [[] for _ in parts]
        name = parts[0]
        here = [t for c in containers if (t := self.topics.get((c, name)))]
        here += created.get(name, [])
        return [here or list(self.topic_names.get(name, ()))]

    def bridge_end(self, parts: list[str], created: NewTopics | None = None) -> list[list[Decl]]:
        """``CONTAINER.TOPIC`` or ``[CONTAINER.]NODE.INTERFACE``; both readings when both
        exist (the parser reports that ambiguity)."""
        if len(parts) == 3:
            return self.node_items(parts, "interface")
        if len(parts) != 2:
            return [[] for _ in parts]
        as_topic = self.topic(parts, [], created)
        if not as_topic[0]:
            as_topic = [[], []]
        as_interface = self.node_items(parts, "interface")
        return [as_topic[i] + as_interface[i] for i in range(2)]

    def parameter(self, parts: list[str]) -> list[list[Decl]]:
        """``[CONTAINER.]NODE.PARAMETER`` or ``[CONTAINER.]STORE.REFINED_TYPE.period``."""
        if len(parts) in (3, 4) and parts[-1] == "period":
            owners = self.elements(parts[:-2])
            if any(d.kind == "store" for d in owners[-1]):
                return [*owners, [d for d in [self.data_types.get(parts[-2])] if d], []]
        return self.node_items(parts, "parameter")

    def feature_attribute(self, parts: list[str]) -> list[list[Decl]]:
        feature = self.features.get(parts[0])
        found = [[feature] if feature else []]
        if len(parts) == 2:
            attribute = self.attributes.get((parts[0], parts[1]))
            found.append([attribute] if attribute else [])
        return found

    def containers_of(self, decls: list[Decl]) -> list[str]:
        """The declaring containers of nodes (for an unqualified topic's lookup)."""
        return [d.qualified[0] for d in decls if d.kind in ("node", "store")]
