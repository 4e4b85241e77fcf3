"""The outline (document symbols) of a .tsm, .fm or .rm.

A .tsm or .fm is outlined from its last parsed model: containers with their topics,
nodes (interfaces, parameters), stores, writers and readers, data types, transforms;
the feature tree. A declaration whose name is no longer where the model says (the
text changed since) is left out rather than shown at a wrong place. A .rm is
outlined from its tokens, so a half-typed one still has its resolution elements.
"""

from __future__ import annotations

import os
from typing import Any

from lsprotocol import types

from spl.lsp.occurrences import RM_STATEMENTS, TSM_STATEMENTS
from spl.lsp.project import Project
from spl.lsp.tokens import Tokens
from spl.metamodels.interface_kinds import kind_of

Kind = types.SymbolKind


def symbols(path: str, project: Project) -> list[types.DocumentSymbol]:
    tokens = project.tokens(path)
    suffix = os.path.splitext(path)[1].lower()
    if suffix == ".rm":
        return _rm(tokens)
    model = project.model(path)
    if model is None:
        return []
    outline = _Outline(path, tokens)
    if suffix == ".tsm":
        return outline.system(model)
    if suffix == ".fm" and getattr(model, "root", None) is not None:
        return [s for s in [outline.feature(model.root)] if s]
    return []


class _Outline:
    def __init__(self, path: str, tokens: Tokens) -> None:
        self.path = path
        self.tokens = tokens
        self.lines = tokens.lines

    def symbol(
        self, element: Any, kind: Kind, children: list | None = None, detail: str | None = None
    ) -> types.DocumentSymbol | None:
        """The symbol of ``element``, spanning its block; None when its name is not at
        the place the model recorded (the text changed since it parsed)."""
        if getattr(element, "srcFile", None) != self.path or not element.srcLine:
            return None
        start = self.lines.spl_offset(element.srcLine, element.srcCol)
        name = element.name
        if self.tokens.text[start : start + len(name)] != name:
            return None
        end = self._block_end(start + len(name))
        line_start = self.lines.starts[element.srcLine - 1]
        indent = len(self.lines.line_text(element.srcLine - 1)) - len(
            self.lines.line_text(element.srcLine - 1).lstrip()
        )
        return types.DocumentSymbol(
            name=name,
            kind=kind,
            detail=detail,
            range=self.lines.range(min(line_start + indent, start), end),
            selection_range=self.lines.range(start, start + len(name)),
            children=[c for c in children or [] if c is not None],
        )

    def _block_end(self, after: int) -> int:
        """The end of the braces that follow a declaration's name, else of its line."""
        items = self.tokens.tokens
        index = self.tokens.at(after)
        index = (index + 1) if index is not None else 0
        while index < len(items) and items[index].start < after:
            index += 1
        end = self.tokens.text.find("\n", after)
        end = len(self.tokens.text) if end < 0 else end
        for step in range(index, min(index + 16, len(items))):
            token = items[step]
            if token.text == "}" or (token.kind == "name" and token.text in TSM_STATEMENTS):
                break
            if token.text == "{":
                close = self._matching(step)
                if close + 1 < len(items) and items[close + 1].text == "{":
                    close = self._matching(close + 1)  # a feature's group, then its body
                return items[close].end
        return end

    def _matching(self, opening: int) -> int:
        depth, items = 0, self.tokens.tokens
        for index in range(opening, len(items)):
            depth += {"{": 1, "}": -1}.get(items[index].text, 0)
            if depth == 0:
                return index
        return len(items) - 1

    def system(self, system: Any) -> list[types.DocumentSymbol]:
        found = [
            self.symbol(d, Kind.Struct, [self.symbol(f, Kind.Field) for f in d.fields])
            for d in system.dataTypes
        ]
        found += [self.symbol(t, Kind.Function) for t in system.transforms]
        for container in system.containers:
            children = [self.symbol(t, Kind.Event, detail=t.type) for t in container.topics]
            children += [self._node(n) for n in container.nodes]
            children += [self.symbol(s, Kind.Struct, detail="store") for s in container.stores]
            kind = "robot" if container.eClass.name == "RobotContainer" else "cloud"
            found.append(self.symbol(container, Kind.Module, children, f"{kind} container"))
        return sorted(
            (s for s in found if s), key=lambda s: (s.range.start.line, s.range.start.character)
        )

    def _node(self, node: Any) -> types.DocumentSymbol | None:
        children = [
            self.symbol(i, Kind.Interface, detail=kind_of(i).eclass) for i in node.interfaces
        ]
        children += [self.symbol(p, Kind.Property, detail="param") for p in node.parameters]
        return self.symbol(node, Kind.Class, children, node.eClass.name.lower())

    def feature(self, feature: Any) -> types.DocumentSymbol | None:
        children = [self.symbol(a, Kind.Field, detail="attribute") for a in feature.attributes]
        children += [self.feature(child) for group in feature.groups for child in group.features]
        return self.symbol(feature, Kind.EnumMember, children, "feature")


def _rm(tokens: Tokens) -> list[types.DocumentSymbol]:
    """``when F selected`` elements with their statements, from the tokens."""
    items, lines, found = tokens.tokens, tokens.lines, []
    index = 0
    while index < len(items):
        token = items[index]
        if not token.is_word("when"):
            index += 1
            continue
        depth, end, statements, cursor = 0, len(items) - 1, [], index
        while cursor < len(items):
            text = items[cursor].text
            depth += {"{": 1, "}": -1}.get(text, 0)
            if depth == 0 and text == "}":
                end = cursor
                break
            if depth == 1 and items[cursor].kind == "name" and text in RM_STATEMENTS - {"when"}:
                statements.append(cursor)
            if cursor > index and items[cursor].is_word("when") and depth == 0:
                end = cursor - 1
                break
            cursor += 1
        brace = next((k for k in range(index, end + 1) if items[k].text == "{"), None)
        header = items[index:brace] if brace is not None else items[index : index + 4]
        children = []
        for number, first in enumerate(statements):
            last = (statements[number + 1] - 1) if number + 1 < len(statements) else end - 1
            last = max(first, last)
            text = lines.text[items[first].start : items[last].end]
            children.append(
                types.DocumentSymbol(
                    name=" ".join(text.split())[:80],
                    kind=Kind.Method,
                    range=lines.range(items[first].start, items[last].end),
                    selection_range=lines.range(items[first].start, items[first].end),
                )
            )
        found.append(
            types.DocumentSymbol(
                name=" ".join(t.text for t in header),
                kind=Kind.Namespace,
                range=lines.range(token.start, items[end].end),
                selection_range=lines.range(token.start, header[-1].end),
                children=children,
            )
        )
        index = max(end, index) + 1
    return found
