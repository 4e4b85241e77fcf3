"""The keywords of spl's languages, read from their textX grammars (``dsl/*.tx``).

The grammars are the one source of the languages' words: the language server's
statement and completion sets (``spl.lsp.occurrences``, ``spl.lsp.completion``), the
words a feature may not be called (``spl.dsl.fm.vocabulary``) and those a data field
may not be called (``spl.dsl.tsm.transforms``) are derived here from the grammar text,
so a keyword added to a .tx file reaches them without another edit. What does not
derive them is compared with this by the tests: the VS Code TextMate grammars
(``tests/test_lsp_editors.py``), the fast readers, which follow their grammar by hand,
and the resolver's sharing modes (``tests/test_grammar_keywords.py``).

It reads the grammar text with a small parser of textX's grammar language (rules,
sequences, ordered choices, groups, repetitions, assignments, string and regex
matches), not with textX: building textX's metamodel costs a tenth of a second and more,
this a millisecond, once per process (every function is cached). Only what the sets
above need is read: the string matches (``'node'``), the rules' structure around them,
and two regular-expression forms: a terminal matching one of a few words
(``/(true|false)(?!...)/``) and a name refusing some (``/(?!(and|or)(?!...))[A-Za-z_].../``).
``tests/test_grammar_keywords.py`` checks the reading against the metamodel textX
compiles from the same files.

A *language* is the grammar file's stem (``"tsm"``, ``"fm"``, ``"rm"``, ``"capability"``);
its rules include those of the grammars it imports (``fm.tx`` imports ``capability.tx``).
"""

from __future__ import annotations

from functools import cache

from spl.dsl.grammar_text import (
    BUILT_IN,
    EXCLUDED_WORDS,
    LITERAL_WORDS,
    Expr,
    is_word,
    rules,
)

__all__ = [
    "block_heads",
    "excluded_words",
    "follows",
    "heads",
    "is_word",
    "keywords",
    "literal_words",
    "rules",
    "words_of",
]


class _Reading:
    """Questions about one language's rules, each answer kept."""

    def __init__(self, language: str) -> None:
        self.rules = rules(language)
        self._nullable: dict[str, bool] = {}
        self._keyword_only: dict[str, bool] = {}
        self._heads: dict[str, tuple[tuple[str, ...], ...]] = {}

    def rule(self, name: str) -> Expr:
        if name in self.rules:
            return self.rules[name]
        if name in BUILT_IN:
            return ("regex", "")
        raise KeyError(f"{name}: no such rule")

    def nullable(self, expr: Expr) -> bool:
        """Whether ``expr`` may match no text at all."""
        kind = expr[0]
        if kind == "ref":
            name = expr[1]
            if name not in self._nullable:
                self._nullable[name] = False  # a rule being asked about (recursion)
                self._nullable[name] = self.nullable(self.rule(name))
            return self._nullable[name]
        if kind == "seq":
            return all(self.nullable(e) for e in expr[1])
        if kind == "choice":
            return any(self.nullable(e) for e in expr[1])
        if kind == "rep":
            return expr[1] in ("?", "*") or self.nullable(expr[2])
        if kind == "assign":
            return expr[2] in ("?=", "*=") or self.nullable(expr[3])
        return kind == "pred"

    def keyword_only(self, expr: Expr) -> bool:
        """Whether ``expr`` matches keywords and nothing else (``'robot' 'container'``,
        ``(optional?='optional')?``, a rule ``'private' | 'public'``)."""
        kind = expr[0]
        if kind == "str":
            return is_word(expr[1])
        if kind == "ref":
            name = expr[1]
            if name not in self._keyword_only:
                self._keyword_only[name] = False
                self._keyword_only[name] = self.keyword_only(self.rule(name))
            return self._keyword_only[name]
        if kind in ("seq", "choice"):
            return all(self.keyword_only(e) for e in expr[1])
        if kind == "rep":
            return self.keyword_only(expr[2])
        if kind == "assign":
            return self.keyword_only(expr[3])
        return False

    def runs(self, expr: Expr) -> list[tuple[str, ...]]:
        """The keyword sequences a keyword-only ``expr`` matches (``()`` if it may
        match nothing); a repetition counts once."""
        kind = expr[0]
        if kind == "str":
            return [(expr[1],)]
        if kind == "ref":
            return self.runs(self.rule(expr[1]))
        if kind == "seq":
            found: list[tuple[str, ...]] = [()]
            for element in expr[1]:
                found = [a + b for a in found for b in self.runs(element)]
            return _unique(found)
        if kind == "choice":
            return _unique([run for e in expr[1] for run in self.runs(e)])
        inner = expr[2] if kind == "rep" else expr[3]
        optional = (kind == "rep" and expr[1] in ("?", "*")) or (
            kind == "assign" and expr[2] in ("?=", "*=")
        )
        return _unique(([()] if optional else []) + self.runs(inner))

    def heads(self, expr: Expr) -> tuple[tuple[str, ...], ...]:
        """The keyword runs that can open ``expr``: its leading keywords up to the first
        name or value (``robot container``, ``optional node``, ``node``)."""
        kind = expr[0]
        if kind == "str":
            return ((expr[1],),) if is_word(expr[1]) else ()
        if kind == "ref":
            name = expr[1]
            if name not in self._heads:
                self._heads[name] = ()
                self._heads[name] = self.heads(self.rule(name))
            return self._heads[name]
        if kind == "choice":
            return tuple(_unique([h for e in expr[1] for h in self.heads(e)]))
        if kind == "rep":
            return self.heads(expr[2])
        if kind == "assign":
            return self.heads(expr[3])
        if kind == "seq":
            return self.sequence_heads(expr[1])
        return ()

    def sequence_heads(self, elements: tuple[Expr, ...]) -> tuple[tuple[str, ...], ...]:
        open_runs: list[tuple[str, ...]] = [()]  # keywords read so far on each way in
        done: list[tuple[str, ...]] = []
        for element in elements:
            if self.keyword_only(element):
                open_runs = _unique([a + b for a in open_runs for b in self.runs(element)])
                continue
            done += [run for run in open_runs if run]
            if () not in open_runs:
                open_runs = []
                break
            # nothing read yet: this element's own keywords open the sequence
            done += self.heads(element)
            open_runs = [()] if self.nullable(element) else []
            if not open_runs:
                break
        done += [run for run in open_runs if run]
        return tuple(_unique(done))

    def first(self, expr: Expr, seen: frozenset[str] = frozenset()) -> list[str]:
        """The strings (keywords and punctuation) ``expr`` can start with."""
        kind = expr[0]
        if kind == "str":
            return [expr[1]]
        if kind == "ref":
            name = expr[1]
            return [] if name in seen else self.first(self.rule(name), seen | {name})
        if kind == "seq":
            found: list[str] = []
            for element in expr[1]:
                found += self.first(element, seen)
                if not self.nullable(element):
                    break
            return _unique(found)
        if kind == "choice":
            return _unique([s for e in expr[1] for s in self.first(e, seen)])
        if kind == "rep":
            return self.first(expr[2], seen)
        if kind == "assign":
            return self.first(expr[3], seen)
        return []

    def follows(self, expr: Expr, after: str) -> list[str]:
        """The strings that can come next after the string or assignment ``after`` in a
        sequence of ``expr`` (not looking past the sequence's end)."""
        kind = expr[0]
        found: list[str] = []
        if kind == "seq":
            elements = expr[1]
            for index, element in enumerate(elements):
                if (
                    element == ("str", after)
                    or (element[0] == "assign" and element[1] == after)
                    or (
                        element[0] == "rep" and element[2][0] == "assign" and element[2][1] == after
                    )
                ):
                    found += self.first(("seq", elements[index + 1 :]))
            parts = elements
        elif kind == "choice":
            parts = expr[1]
        elif kind == "rep":
            parts = (expr[2],)
        elif kind == "assign":
            parts = (expr[3],)
        else:
            parts = ()
        for part in parts:
            found += self.follows(part, after)
        return _unique(found)

    def block(self, expr: Expr) -> tuple[Expr, ...] | None:
        """The elements between ``'{'`` and ``'}'`` of the first braced block of ``expr``."""
        kind = expr[0]
        if kind == "seq":
            elements = expr[1]
            if ("str", "{") in elements:
                start = elements.index(("str", "{")) + 1
                end = elements.index(("str", "}"), start)
                return elements[start:end]
            parts = elements
        elif kind == "choice":
            parts = expr[1]
        elif kind == "rep":
            parts = (expr[2],)
        elif kind == "assign":
            parts = (expr[3],)
        else:
            return None
        for part in parts:
            found = self.block(part)
            if found is not None:
                return found
        return None

    def words(self, expr: Expr, seen: set[str]) -> list[str]:
        """Every keyword reachable from ``expr``, in the order the grammar writes them."""
        kind = expr[0]
        if kind == "str":
            return [expr[1]] if is_word(expr[1]) else []
        if kind == "ref":
            if expr[1] in seen:
                return []
            seen.add(expr[1])
            return self.words(self.rule(expr[1]), seen)
        if kind in ("seq", "choice"):
            return [w for e in expr[1] for w in self.words(e, seen)]
        if kind == "rep":
            return self.words(expr[2], seen)
        if kind == "assign":
            return self.words(expr[3], seen)
        return []


def _unique(items: list) -> list:
    return list(dict.fromkeys(items))


@cache
def _reading(language: str) -> _Reading:
    return _Reading(language)


@cache
def keywords(language: str) -> frozenset[str]:
    """Every keyword of the language: the words its grammars match as strings."""
    reading, every = _reading(language), set(_reading(language).rules)
    return frozenset(w for body in reading.rules.values() for w in reading.words(body, every))


@cache
def words_of(language: str, rule: str, deep: bool = True) -> tuple[str, ...]:
    """The keywords ``rule`` and the rules it uses match, in the grammar's order
    (``words_of("fm", "SharingModeName")`` is ``("public", "protected", "private")``);
    with ``deep=False`` only those written in the rule itself."""
    reading = _reading(language)
    seen = {rule} if deep else {rule, *reading.rules, *BUILT_IN}
    return tuple(_unique(reading.words(reading.rule(rule), seen)))


@cache
def heads(language: str, *names: str) -> tuple[tuple[str, ...], ...]:
    """The keyword runs that open the rules ``names``: their leading keywords up to the
    first name or value, through optional parts (``heads("tsm", "Node")`` is
    ``(("node",), ("optional", "node"))``)."""
    reading = _reading(language)
    return tuple(_unique([h for name in names for h in reading.heads(("ref", name))]))


@cache
def block_heads(language: str, *names: str) -> tuple[tuple[str, ...], ...]:
    """The keyword runs that open an item inside the braces of the rules ``names``
    (``block_heads("tsm", "Node")``: ``implementation``, ``param``, ``publishes``, ...)."""
    reading = _reading(language)
    found: list[tuple[str, ...]] = []
    for name in names:
        block = reading.block(reading.rule(name))
        if block is None:
            raise ValueError(f"rule {name} of {language}.tx has no block in braces")
        found += [h for element in block for h in reading.heads(element)]
    return tuple(_unique(found))


@cache
def follows(language: str, after: str, *names: str) -> tuple[str, ...]:
    """The strings (keywords and punctuation) that can come right after the string or
    the assignment to the attribute ``after`` in the rules ``names``: what may be typed
    next (``follows("rm", "feature", "Element")`` is ``("not", "selected")``)."""
    reading = _reading(language)
    return tuple(_unique([s for name in names for s in reading.follows(reading.rule(name), after)]))


def _regex(language: str, rule: str) -> str:
    body = _reading(language).rule(rule)
    if body[0] != "regex":
        raise ValueError(f"rule {rule} of {language}.tx is not a regular expression")
    return body[1]


@cache
def literal_words(language: str, rule: str) -> tuple[str, ...]:
    """The words a terminal of the form ``/(w1|w2)(?!...)/`` matches
    (``literal_words("fm", "BoolWord")`` is ``("true", "false")``)."""
    match = LITERAL_WORDS.match(_regex(language, rule))
    if match is None:
        raise ValueError(f"rule {rule} of {language}.tx matches no list of words")
    return tuple(match.group(1).split("|"))


@cache
def excluded_words(language: str, rule: str) -> frozenset[str]:
    """The words a name terminal refuses with a leading ``(?!(w1|w2)(?!...))``
    (``excluded_words("fm", "FeatureName")``: the words that cannot name a feature)."""
    match = EXCLUDED_WORDS.match(_regex(language, rule))
    if match is None:
        raise ValueError(f"rule {rule} of {language}.tx refuses no words")
    return frozenset(match.group(1).split("|"))
