"""Where the names of a model text point: one pass over the tokens of a .tsm, .fm or
.rm gives every name (each part of a dotted name) with the declarations it denotes.

Go to definition, find references and hover all read this list, so a name means the
same to each of them; it is computed once per version of a document. The passes use
the statement a name stands in (the keyword that opened it and the token before the
name), as the grammars place references (src/spl/dsl/tsm/tsm.tx, src/spl/dsl/fm/fm.tx,
src/spl/dsl/rm/rm.tx).
"""

from __future__ import annotations

import os
from collections import defaultdict
from dataclasses import dataclass

from spl.dsl import grammar_keywords as grammar
from spl.lsp.symbols import Decl, NewTopics, SymbolIndex
from spl.lsp.tokens import Token, Tokens
from spl.metamodels.interface_kinds import KINDS

# The keyword runs that open an item of a .tsm, at the top level (``system``, ``robot
# container``, ``bridge``, ...), in a container (``optional node``, ``topic``, ...) and in
# a node, writer or reader (``implementation``, ``param``, ``publishes``, ...): tsm.tx's.
TSM_TOP_HEADS = grammar.heads("tsm", "System")
TSM_MEMBER_HEADS = grammar.block_heads("tsm", "RobotContainer", "CloudContainer")
TSM_NODE_HEADS = grammar.block_heads("tsm", "Node", "Writer", "Reader")
# The word that opens a .tsm statement is the last of its run (``robot container``,
# ``optional node``); ``system`` and ``namespace`` open none whose names the walks read,
# and a topic may be called ``namespace``.
_TSM_HEADS = TSM_TOP_HEADS + TSM_MEMBER_HEADS + TSM_NODE_HEADS
TSM_STATEMENTS = frozenset(run[-1] for run in _TSM_HEADS) - {"system", "namespace"}
# A .rm statement is opened by the first word of its run (``connect bridge``), as is an
# element (``when``): rm.tx's.
RM_STATEMENTS = frozenset(run[0] for run in grammar.heads("rm", "Element", "Statement"))
# The statements opened by a run of two statement words (``provides action``, ``calls
# action``): the second word alone opens none, and is a name where no name follows it.
TSM_RUNS = frozenset(
    " ".join(run) for run in _TSM_HEADS if len(run) == 2 and run[0] in TSM_STATEMENTS
)
# The .tsm statements whose arrow names a topic of their container (an interface bound to a
# topic, a writer's or reader's records), and those whose arrow names the server called.
TSM_TOPIC_STATEMENTS = frozenset({k.keyword for k in KINDS if k.on_topic} | {"writer", "reader"})
TSM_CALL_STATEMENTS = frozenset(k.keyword for k in KINDS if k.calls)
# Every keyword of fm.tx and capability.tx, and the literals true and false.
FM_KEYWORDS = grammar.keywords("fm") | set(grammar.literal_words("fm", "BoolWord"))


def tsm_statement(tokens: list[Token], i: int) -> str:
    """The statement the statement word ``tokens[i]`` opens: the run it closes
    (``calls action``) where a name follows it, else its own word (``provides action :
    T`` is a service named ``action``)."""
    word, first = tokens[i].text, tokens[i - 1].text if i > 0 else ""
    after = tokens[i + 1] if i + 1 < len(tokens) else None
    run = f"{first} {word}"
    if run not in TSM_RUNS:
        return word
    return run if after is None or after.kind == "name" else first


def tsm_statement_before(tokens: list[Token]) -> str | None:
    """The statement the end of ``tokens`` stands in (:func:`tsm_statement`), or None
    where a block opens or closes first."""
    for i in range(len(tokens) - 1, -1, -1):
        token = tokens[i]
        if token.kind == "name" and token.text in TSM_STATEMENTS:
            return tsm_statement(tokens, i)
        if token.text in ("{", "}"):
            return None
    return None


@dataclass(frozen=True)
class Occurrence:
    start: int  # character offsets of the name (one part of a dotted name)
    end: int
    decls: tuple[Decl, ...]
    declaration: bool = False  # the name of the declaration itself


def language_of(path: str) -> str:
    return os.path.splitext(path)[1].lower()


def occurrences(path: str, tokens: Tokens, index: SymbolIndex) -> list[Occurrence]:
    """Every name of the text of ``path`` that denotes a declaration, in text order."""
    walker = {".tsm": _TsmWalk, ".fm": _FmWalk, ".rm": _RmWalk}.get(language_of(path))
    if walker is None:
        return []
    return walker(path, tokens, index).run()


class _Walk:
    def __init__(self, path: str, tokens: Tokens, index: SymbolIndex) -> None:
        self.path = path
        self.tokens = tokens.tokens
        self.lines = tokens.lines
        self.index = index
        self.found: list[Occurrence] = []

    def place(self, token: Token) -> tuple[str, int, int]:
        return (self.path, *self.lines.spl_place(token.start))

    def declared(self, token: Token) -> Decl | None:
        return self.index.at_place.get(self.place(token))

    def emit(self, token: Token, per_part: list[list[Decl]], declaration: bool = False) -> None:
        for (start, end), decls in zip(token.part_spans(), per_part, strict=False):
            if decls:
                self.found.append(Occurrence(start, end, tuple(decls), declaration))

    def prev(self, i: int) -> Token | None:
        return self.tokens[i - 1] if i > 0 else None

    def run(self) -> list[Occurrence]:
        for i, token in enumerate(self.tokens):
            if token.kind == "name":
                decl = self.declared(token)
                if decl is not None:
                    self.on_declaration(decl)
                    self.emit(token, [[decl]], declaration=True)
                else:
                    self.on_name(i, token)
            elif token.kind == "string":
                self.on_string(i, token)
        return self.found

    def on_declaration(self, decl: Decl) -> None:
        pass

    def on_name(self, i: int, token: Token) -> None:
        pass

    def on_string(self, i: int, token: Token) -> None:
        pass


class _TsmWalk(_Walk):
    container: str | None = None
    statement: str | None = None

    def on_declaration(self, decl: Decl) -> None:
        if decl.kind == "container":
            self.container = decl.name

    def on_name(self, i: int, token: Token) -> None:
        before = self.prev(i)
        if before is not None and before.is_word("container"):
            self.container = token.text
            return
        if token.text in TSM_STATEMENTS:
            self.statement = tsm_statement(self.tokens, i)
            return
        parts, index = token.parts, self.index
        follows = before.text if before is not None else ""
        here = [self.container] if self.container else []
        statement = self.statement
        if follows in ("->", "<-") and statement in TSM_TOPIC_STATEMENTS:
            self.emit(token, index.topic(parts, here))
        elif follows == "->" and statement in TSM_CALL_STATEMENTS:
            if len(parts) == 2 and self.container:
                self.emit(token, index.node_items([self.container, *parts], "interface")[1:])
            else:
                self.emit(token, index.node_items(parts, "interface"))
        elif statement == "bridge" and follows in ("bridge", "->"):
            self.emit(token, index.bridge_end(parts))
        elif (statement == "transform" and follows in (":", "->")) or (
            statement in ("store", "writer", "reader") and follows in ("raw", "refined", ":")
        ):
            self.emit(token, [[d] if (d := index.data_types.get(token.text)) else []])
        elif statement == "store" and follows == "by":
            self.emit(token, [[d] if (d := index.transforms.get(token.text)) else []])
        elif statement in ("writer", "reader") and follows in ("to", "from"):
            self.emit(token, index.elements(parts))


class _FmWalk(_Walk):
    def on_name(self, i: int, token: Token) -> None:
        if token.text in FM_KEYWORDS:
            return
        before = self.prev(i)
        if before is not None and before.is_word("attribute", "capability", "has"):
            return
        feature = self.index.features.get(token.text)
        if feature is not None:
            self.emit(token, [[feature]])


class _RmWalk(_Walk):
    """Statements of a .rm: the keyword that opens one decides what its names are."""

    def __init__(self, path: str, tokens: Tokens, index: SymbolIndex) -> None:
        super().__init__(path, tokens, index)
        self.created: NewTopics = defaultdict(list)
        self.moves: dict[str, list[str]] = defaultdict(list)  # node name -> containers
        self.statement: str | None = None
        self.owners: list[Decl] = []  # the node(s) of a `connect` statement's interface
        self.bridge = False  # the running statement is `connect bridge A -> B`
        self._collect()

    def _collect(self) -> None:
        """`new topic` declarations and migrations, wherever they are in the file."""
        tokens = self.tokens
        for i in range(len(tokens) - 3):
            a, b, c, d = tokens[i : i + 4]
            if a.is_word("new") and b.is_word("topic") and c.kind == "name":
                _, line, col = self.place(c)
                decl = Decl("topic", ("new topic", c.text), self.path, line, col)
                self.created[c.text].append(decl)
            if a.is_word("migrate") and b.kind == "name" and c.is_word("to") and d.kind == "name":
                self.moves[b.parts[-1]].append(d.text)

    def declared(self, token: Token) -> Decl | None:
        place = self.place(token)
        for decl in self.created.get(token.text, ()):
            if (decl.file, decl.line, decl.col) == place:
                return decl
        return None

    def on_string(self, i: int, token: Token) -> None:
        before = self.prev(i)
        if before is not None and before.is_word("tsm", "fm") and self.statement is None:
            target = os.path.normpath(os.path.join(os.path.dirname(self.path), token.string_value))
            decl = Decl("file", (token.string_value,), target, 1, 1)
            self.found.append(Occurrence(token.start, token.end, (decl,)))

    def on_name(self, i: int, token: Token) -> None:
        if token.text in RM_STATEMENTS:
            self.statement, self.owners, self.bridge = token.text, [], False
            return
        before = self.prev(i)
        follows = before.text if before is not None and before.kind != "name" else ""
        word = before.text if before is not None and before.kind == "name" else ""
        index, parts, statement = self.index, token.parts, self.statement
        if statement == "when" and word == "when":
            self.emit(token, [[d] if (d := index.features.get(token.text)) else []])
        elif (statement == "require" and follows == ",") or (
            statement in ("require", "implementation", "migrate") and word == statement
        ):
            self.emit(token, index.elements(parts))
        elif statement == "migrate" and word == "to":
            self.emit(token, [[d] if (d := index.containers.get(token.text)) else []])
        elif statement == "parameter" and word == "parameter":
            self.emit(token, index.parameter(parts))
        elif statement == "parameter" and word == "feature":
            self.emit(token, index.feature_attribute(parts))
        elif statement == "connect":
            self._connect(token, word, follows)

    def _connect(self, token: Token, word: str, follows: str) -> None:
        index, parts = self.index, token.parts
        if word == "connect" and token.text == "bridge":
            self.bridge = True
        elif word == "connect":
            found = index.node_items(parts, "interface")
            self.owners = found[-2] if len(found) >= 2 else []
            self.emit(token, found)
        elif self.bridge and (word == "bridge" or follows == "->"):
            self.emit(token, index.bridge_end(parts, self.created))
        elif word == "topic":
            containers = index.containers_of(self.owners)
            for owner in self.owners:
                containers += self.moves.get(owner.name, [])
            self.emit(token, index.topic(parts, containers, self.created))
        elif word == "server":
            self.emit(token, index.node_items(parts, "interface"))
