"""Completion: names where a name is expected, keywords elsewhere.

In a .rm: node names after ``require``, ``migrate``, ``implementation``,
``parameter`` and ``connect``; topic names after ``to topic``; container names after
``migrate N to``; feature names after ``when`` and ``feature``; after ``X.`` the
members of X (a node's interfaces or parameters, a container's nodes and topics, a
feature's attributes). In a .tsm, topics after ``->``/``<-``; in a .fm, features in
constraints. The text need not parse: this reads tokens only.

Where a client's server is named (a client's ``->``, a bridge from a client, ``connect
CLIENT to server``), only the nodes serving the client's kind and their servers of that
kind are offered, asked of the registry (docs/architecture.md, "Interface kinds"); after
an interface statement's ``:``, the types the line gives that kind's family (docs/tsm.md,
"Actions": an action client is offered action types).
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
    TSM_TOP_HEADS,
    TSM_TOPIC_STATEMENTS,
    tsm_statement_before,
)
from spl.lsp.symbols import Decl, SymbolIndex
from spl.lsp.tokens import Token, Tokens
from spl.metamodels.interface_kinds import KINDS as INTERFACE_KINDS, InterfaceKind, kind_of, side

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
    "type": types.CompletionItemKind.TypeParameter,
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
# Where a statement starts, the words that open one and each run of several words whole
# (``provides``, ``provides action``); after a run's first word, the words that may follow
# it (``action``).
OPENINGS = {
    heads: [
        *(word for word in words if any(run[0] == word for run in heads)),
        *(" ".join(run) for run in heads if len(run) > 1),
    ]
    for heads, words in (
        (TSM_TOP_HEADS, TSM_TOP),
        (TSM_MEMBER_HEADS, TSM_MEMBERS),
        (TSM_NODE_HEADS, TSM_NODE),
    )
}
# The interface kind of each .tsm statement opening one (``calls action``: an action client).
STATEMENT_KINDS = {kind.keyword: kind for kind in INTERFACE_KINDS}
# A ROS type being typed before the cursor (``move_base_msgs/Mo``).
_TYPE_BEFORE = re.compile(r"[A-Za-z0-9_]+(?:/[A-Za-z0-9_]*)?\Z|\Z")
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
    items = _items(decls, keywords)
    typed_type = _TYPE_BEFORE.search(tokens.text, max(0, offset - 200), offset)
    start = typed_type.start() if typed_type else offset
    for item in items:
        if item.kind == KINDS["type"]:  # replaces ``package/`` too, not the word after it
            item.text_edit = types.TextEdit(tokens.lines.range(start, offset), item.label)
    return items


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
    statement = _statement(before, RM_STATEMENTS)
    if qualifier:
        found = _members(qualifier, index)
        wanted = _rm_server_wanted(before, statement, index)
        if wanted is not None:
            return [d for d in found if d.kind == "interface" and kind_of(d.element) is wanted], []
        return found, []
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
        wanted = _rm_server_wanted(before, statement, index)
        return [d for d in _nodes(index) if wanted is None or _has(d, wanted)], []
    if len(tail) == 2:
        return [], AFTER_CONNECT_INTERFACE
    return [], []


def _rm_server_wanted(
    before: list[Token], statement: Token | None, index: SymbolIndex
) -> InterfaceKind | None:
    """After ``connect CLIENT to server`` or ``connect bridge CLIENT ->``, the kind of
    server the client may call: only those are offered."""
    if statement is None or not statement.is_word("connect") or not before:
        return None
    tail = before[before.index(statement) :]
    bridge = len(tail) > 1 and tail[1].is_word("bridge")
    client = tail[2 if bridge else 1] if len(tail) > (2 if bridge else 1) else None
    if client is None or not (before[-1].is_word("server") or (bridge and before[-1].text == "->")):
        return None
    found = index.node_items(client.parts, "interface")[-1]
    kind = kind_of(found[0].element) if found and found[0].element is not None else None
    return side(kind.family, True) if kind is not None and kind.calls else None


def _tsm(
    before: list[Token], qualifier: list[str], index: SymbolIndex
) -> tuple[list[Decl], list[str]]:
    last = before[-1] if before else None
    statement = tsm_statement_before(before)
    kind = STATEMENT_KINDS.get(statement or "")
    if qualifier:
        found = _members(qualifier, index)
        wanted = _server_wanted(before, statement, kind, index)
        if wanted is not None:
            return [d for d in found if d.kind == "interface" and kind_of(d.element) is wanted], []
        return found, []
    if last is not None and last.text in ("->", "<-") and statement is not None:
        container = _container_at(before)
        if statement in TSM_TOPIC_STATEMENTS:
            return [d for (c, _), d in index.topics.items() if c == container], []
        if statement in TSM_CALL_STATEMENTS and kind is not None:
            provider = side(kind.family, True)
            return [
                d for (c, _), d in index.members.items() if c == container and _has(d, provider)
            ], []
        if statement == "bridge":
            return [*index.containers.values(), *_nodes(index)], []
    if last is not None and last.text == ":" and kind is not None:
        return _types(kind, index), []
    if last is not None and last.is_word("bridge"):
        return [*index.containers.values(), *_nodes(index)], []
    depth = _depth(before)
    heads = TSM_TOP_HEADS if depth <= 0 else TSM_MEMBER_HEADS if depth == 1 else TSM_NODE_HEADS
    if last is not None and last.kind == "name" and _opens(before):
        follow = [run[1] for run in heads if len(run) > 1 and run[0] == last.text]
        if follow:
            return [], follow
    return [], OPENINGS[heads]


def _server_wanted(
    before: list[Token], statement: str | None, kind: InterfaceKind | None, index: SymbolIndex
) -> InterfaceKind | None:
    """After ``->`` of a client's statement or of a bridge from a client, the kind of
    server it may call (an action client's, an action server): only those are offered."""
    if not before or before[-1].text != "->":
        return None
    if statement == "bridge" and len(before) >= 2:
        sources = index.node_items(before[-2].parts, "interface")[-1]
        kind = kind_of(sources[0].element) if sources and sources[0].element else None
    if kind is None or not kind.calls:
        return None
    return side(kind.family, True)


def _has(decl: Decl, provider: InterfaceKind) -> bool:
    """Whether node ``decl`` has an interface of kind ``provider``."""
    return any(kind_of(i) is provider for i in getattr(decl.element, "interfaces", ()))


def _types(kind: InterfaceKind, index: SymbolIndex) -> list[Decl]:
    """The types the line gives interfaces of ``kind``'s family (and, for a topic's
    family, its topics): an action client is offered the action types."""
    found = {
        d.element.type
        for d in index.node_members.values()
        if d.kind == "interface" and d.element is not None and d.element.type
        if kind_of(d.element).family is kind.family
    }
    if kind.on_topic:
        found |= {d.element.type for d in index.topics.values() if d.element is not None}
    return [Decl("type", (t,), "", 0, 0) for t in sorted(t for t in found if t)]


def _opens(before: list[Token]) -> bool:
    """Whether the last token may open a statement: nothing, a brace or the end of
    another statement is before it, not a word that wants a name (``node``)."""
    if len(before) < 2:
        return True
    previous = before[-2]
    if previous.text in ("{", "}"):
        return True
    return previous.kind in ("name", "string", "type", "number") and (
        previous.text not in grammar.keywords("tsm")
    )


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
