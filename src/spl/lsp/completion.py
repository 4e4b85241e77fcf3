"""Completion: names where a name is expected, keywords elsewhere.

In a .rm: node names after ``require``, ``migrate``, ``implementation``,
``parameter`` and ``connect``; topic names after ``to topic``; container names after
``migrate N to``; feature names after ``when`` and ``feature``; after ``X.`` the
members of X (a node's interfaces or parameters, a container's nodes and topics, a
feature's attributes). In a .tsm, topics after ``->``/``<-``; in a .fm, features in
constraints. The text need not parse: this reads tokens only.
"""

from __future__ import annotations

import os
import re
from collections.abc import Set as AbstractSet
from typing import cast

from lsprotocol import types

from spl.dsl import grammar_keywords as grammar
from spl.lsp.occurrences import (
    FM_KEYWORDS,
    RM_STATEMENTS,
    TSM_CALL_STATEMENTS,
    TSM_MEMBER_HEADS,
    TSM_NODE_HEADS,
    TSM_STATEMENTS,
    TSM_TOP_HEADS,
    TSM_TOPIC_STATEMENTS,
)
from spl.lsp.symbols import Decl, SymbolIndex
from spl.lsp.tokens import Token, Tokens

_WORD_BEFORE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*\.?\Z|\Z")
KINDS = {
    "container": types.CompletionItemKind.Module,
    "node": types.CompletionItemKind.Class,
    "store": types.CompletionItemKind.Struct,
    "topic": types.CompletionItemKind.Event,
    "interface": types.CompletionItemKind.Interface,
    "parameter": types.CompletionItemKind.Property,
    "feature": types.CompletionItemKind.EnumMember,
    "attribute": types.CompletionItemKind.Field,
    "data": types.CompletionItemKind.Struct,
    "transform": types.CompletionItemKind.Function,
}
# The keywords offered where a statement starts, from the grammars (dsl/*.tx): at the top
# of a .rm (``when`` and the header's words), and in a .tsm every word of the runs that
# open an item at the top level, in a container and in a node.
RM_TOP = [
    *dict.fromkeys(run[0] for run in grammar.heads("rm", "Element")),
    *grammar.words_of("rm", "ResolutionModel", deep=False),
]
TSM_TOP = list(dict.fromkeys(word for run in TSM_TOP_HEADS for word in run))
TSM_MEMBERS = list(dict.fromkeys(word for run in TSM_MEMBER_HEADS for word in run))
TSM_NODE = list(dict.fromkeys(word for run in TSM_NODE_HEADS for word in run))
# The operators of a .fm constraint.
FM_OPERATORS = list(grammar.words_of("fm", "Constraint"))
# What may be typed next inside a .rm statement, by rm.tx.
_CONNECTS = ("ConnectTopicStmt", "ConnectNewTopicStmt", "ConnectServerStmt", "ConnectBridgeStmt")
AFTER_WHEN_FEATURE = list(grammar.follows("rm", "feature", "Element"))  # not, selected
PARAMETER_VALUES = list(grammar.follows("rm", "=", "ParameterStmt"))  # feature, true, false
AFTER_MIGRATE_NODE = list(grammar.follows("rm", "node", "MigrateStmt"))  # to
AFTER_CONNECT = list(grammar.follows("rm", "connect", *_CONNECTS))  # bridge
AFTER_CONNECT_INTERFACE = list(grammar.follows("rm", "interface", *_CONNECTS[:2]))  # to
AFTER_BRIDGE_SOURCE = list(grammar.follows("rm", "source", "ConnectBridgeStmt"))  # ->
AFTER_CONNECT_TO = list(grammar.follows("rm", "to", *_CONNECTS))  # topic, new, server
AFTER_NEW = list(grammar.follows("rm", "new", "ConnectNewTopicStmt"))  # topic


def complete(
    path: str, tokens: Tokens, offset: int, index: SymbolIndex
) -> list[types.CompletionItem]:
    """The completion items at ``offset`` of ``path``'s text."""
    typed = _WORD_BEFORE.search(tokens.text, max(0, offset - 200), offset)
    word = typed.group() if typed else ""
    qualifier = word.rsplit(".", 1)[0].split(".") if "." in word else []
    before = [t for t in tokens.tokens if t.end <= offset - len(word)]
    suffix = os.path.splitext(path)[1].lower()
    if suffix == ".rm":
        decls, keywords = _rm(before, qualifier, index)
    elif suffix == ".tsm":
        decls, keywords = _tsm(before, qualifier, index)
    elif suffix == ".fm":
        decls, keywords = _fm(before, index)
    else:
        decls, keywords = [], []
    return _items(decls, keywords)


def _items(decls: list[Decl], keywords: list[str]) -> list[types.CompletionItem]:
    items: dict[str, types.CompletionItem] = {}
    for decl in decls:
        label = decl.name
        if label in items and items[label].detail != _detail(decl):
            items[label].detail = "declared in more than one container: qualify it"
            continue
        items.setdefault(
            label,
            types.CompletionItem(label=label, kind=KINDS.get(decl.kind), detail=_detail(decl)),
        )
    for keyword in keywords:
        items.setdefault(
            keyword, types.CompletionItem(label=keyword, kind=types.CompletionItemKind.Keyword)
        )
    return list(items.values())


def _detail(decl: Decl) -> str:
    owner = ".".join(decl.qualified[:-1])
    return f"{decl.kind} in {owner}" if owner else decl.kind


def _statement(before: list[Token], keywords: AbstractSet[str]) -> Token | None:
    for token in reversed(before):
        if token.kind == "name" and token.text in keywords:
            return token
        if token.text in ("{", "}"):
            return None
    return None


def _depth(before: list[Token]) -> int:
    return sum(1 if t.text == "{" else -1 if t.text == "}" else 0 for t in before)


def _members(qualifier: list[str], index: SymbolIndex, topics: bool = True) -> list[Decl]:
    """What may follow ``QUALIFIER.``: a container's nodes, stores (and topics), a node's
    interfaces and parameters, a feature's attributes."""
    found: list[Decl] = []
    if len(qualifier) == 1 and qualifier[0] in index.containers:
        c = qualifier[0]
        found += [d for (owner, _), d in index.members.items() if owner == c]
        if topics:
            found += [d for (owner, _), d in index.topics.items() if owner == c]
    owners = index.elements(qualifier)[-1] if len(qualifier) <= 2 else []
    for owner in owners:
        found += [d for key, d in index.node_members.items() if key[:2] == owner.qualified]
    if len(qualifier) == 1 and qualifier[0] in index.features:
        found += [d for (f, _), d in index.attributes.items() if f == qualifier[0]]
    return found


def _nodes(index: SymbolIndex, stores: bool = False) -> list[Decl]:
    kinds = ("node", "store") if stores else ("node",)
    return [d for decls in index.by_name.values() for d in decls if d.kind in kinds]


def _rm(
    before: list[Token], qualifier: list[str], index: SymbolIndex
) -> tuple[list[Decl], list[str]]:
    if _depth(before) <= 0:
        last = before[-1] if before else None
        if last is not None and last.is_word("when"):
            return list(index.features.values()), []
        if (
            last is not None
            and last.kind == "name"
            and len(before) > 1
            and before[-2].is_word("when")
        ):
            return [], AFTER_WHEN_FEATURE
        return [], RM_TOP
    if qualifier:
        return _members(qualifier, index), []
    statement = _statement(before, RM_STATEMENTS)
    last = before[-1] if before else None
    word = last.text if last is not None else ""
    kind = statement.text if statement is not None else None
    if kind is None or (last is statement and kind == "when"):
        return [], sorted(RM_STATEMENTS - {"when"})
    if word in ("require", ",") and kind == "require":
        return _nodes(index, stores=True), []
    if word in ("implementation", "migrate", "parameter") and word == kind:
        return _nodes(index, stores=kind == "parameter"), []
    if kind == "migrate" and word == "to":
        return list(index.containers.values()), []
    if kind == "connect":
        return _connect(before, cast(Token, statement), word, index)  # kind: its text
    if kind == "parameter" and word == "=":
        return [], PARAMETER_VALUES
    if kind == "parameter" and word == "feature":
        return list(index.features.values()), []
    if kind == "migrate" and last is not None and last.kind == "name" and word != "to":
        return [], AFTER_MIGRATE_NODE
    return [], sorted(RM_STATEMENTS - {"when"})


def _connect(
    before: list[Token], statement: Token, word: str, index: SymbolIndex
) -> tuple[list[Decl], list[str]]:
    tail = before[before.index(statement) :]
    words = [t.text for t in tail]
    if word == "connect":
        return _nodes(index), AFTER_CONNECT
    if "bridge" in words[:2]:
        if word in ("bridge", "->"):
            return [*index.containers.values(), *_nodes(index)], []
        return [], AFTER_BRIDGE_SOURCE
    if word == "to":
        return [], AFTER_CONNECT_TO
    if word == "new":
        return [], AFTER_NEW
    if word == "topic" and "new" not in words:
        interface = tail[1] if len(tail) > 1 else None
        owners = index.elements(interface.parts[:-1])[-1] if interface is not None else []
        here = index.containers_of(owners)
        return [d for (c, _), d in index.topics.items() if c in here] or list(
            index.topics.values()
        ), []
    if word == "server":
        return _nodes(index), []
    if len(tail) == 2:
        return [], AFTER_CONNECT_INTERFACE
    return [], []


def _tsm(
    before: list[Token], qualifier: list[str], index: SymbolIndex
) -> tuple[list[Decl], list[str]]:
    if qualifier:
        return _members(qualifier, index), []
    last = before[-1] if before else None
    statement = _statement(before, TSM_STATEMENTS)
    if last is not None and last.text in ("->", "<-") and statement is not None:
        container = _container_at(before)
        if statement.text in TSM_TOPIC_STATEMENTS:
            return [d for (c, _), d in index.topics.items() if c == container], []
        if statement.text in TSM_CALL_STATEMENTS:
            return [d for (c, _), d in index.members.items() if c == container], []
        if statement.text == "bridge":
            return [*index.containers.values(), *_nodes(index)], []
    if last is not None and last.is_word("bridge"):
        return [*index.containers.values(), *_nodes(index)], []
    depth = _depth(before)
    keywords = TSM_TOP if depth <= 0 else TSM_MEMBERS if depth == 1 else TSM_NODE
    return [], keywords


def _container_at(before: list[Token]) -> str | None:
    for first, second in zip(reversed(before[1:]), reversed(before[:-1]), strict=False):
        if second.is_word("container"):
            return first.text
    return None


def _fm(before: list[Token], index: SymbolIndex) -> tuple[list[Decl], list[str]]:
    in_constraints = any(t.is_word("constraints") for t in before)
    if in_constraints:
        return list(index.features.values()), FM_OPERATORS
    return [], sorted(FM_KEYWORDS - set(grammar.literal_words("fm", "BoolWord")))
