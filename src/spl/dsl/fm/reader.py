"""A fast reader of ``fm.tx`` (with ``capability.tx``): the parse tree textX makes.

Building textX's metamodel of fm.tx alone took longer than the rest of ``spl check``
of a small line. This reader follows the grammar rule by rule, a PEG as textX's is:
ordered choices, optional parts and repetitions backtrack where an alternative fails
part-way (:class:`~spl.dsl.parse_tree.Tokens`), so where it reads a text to its end it
made textX's choices. Its objects carry the class names, attributes (``None``,
``False`` or ``[]`` where textX leaves them unset) and ``_tx_position`` textX gives,
so the builder (``spl.dsl.fm.language``) cannot tell them apart.

It never reports a problem: on anything it does not read to the end (a syntax error,
or features or formulas nested deeper than ``MAX_DEPTH``) it returns None and textX
parses the text, so syntax errors, and the refusal of nesting too deep for textX, stay
exactly textX's (``tests/test_fm_reader.py`` compares both trees).

It pays (``bench/readers.py``, docs/performance.md "Fast readers", CPU time on a loaded
2-core machine): ``spl check`` of the shipped mapping3d line takes 0.27 s of CPU with it
and 0.34 s without (textX's import and metamodel of fm.tx, 0.045 s and 0.027 s, are most
of the difference; the shipped .fm files' trees are 21x faster to make, the 10,000-node
synthetic line's 22x). The line's check target (under 0.3 s, docs/performance.md) is
met with the three readers.

A keyword added to ``fm.tx`` must be read here too:
``tests/test_grammar_keywords.py`` fails on one the reader never matches.
"""

from __future__ import annotations

import re
from typing import Any

from spl.dsl.parse_tree import BLANKS, Refused, Tokens, TooDeep, rule

# The terminals of fm.tx and capability.tx as textX compiles them (re.MULTILINE is
# arpeggio's default); the capability literals' expressions are the .fm literals'.
FEATURE_NAME = re.compile(
    r"(?!(abstract|and|attribute|constraints|excludes|group|mandatory|not|optional|or|requires"
    r"|sharing|xor)(?![A-Za-z0-9_]))[A-Za-z_][A-Za-z0-9_]*(?![A-Za-z0-9_]|[^\x00-\x7f])",
    re.MULTILINE,
)
IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?![A-Za-z0-9_]|[^\x00-\x7f])", re.MULTILINE)
NATURAL = re.compile(r"\d+", re.MULTILINE)
BOOL_WORD = re.compile(r"(true|false)(?![A-Za-z0-9_])", re.MULTILINE)
DOUBLE_NUMBER = re.compile(
    r"-?(\d+\.\d*|\.\d+|\d+(?=[eE]))([eE][-+]?\d+)?(?![A-Za-z0-9_.])", re.MULTILINE
)
INT_NUMBER = re.compile(r"-?\d+(?![A-Za-z0-9_.])", re.MULTILINE)
QUOTED_STRING = re.compile(r'"(\\["\\nt]|[^"\\\n])*"', re.MULTILINE)
CAPABILITY_QUOTED = re.compile(r'''"[^"'\\\n]*"''', re.MULTILINE)
CAPABILITY_KEY = re.compile(
    r"(?!(and|has)(?![A-Za-z0-9_]))[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*"
    r"(?![A-Za-z0-9_.]|[^\x00-\x7f])",
    re.MULTILINE,
)

# Features and formulas (parentheses, not) nested deeper are textX's: its own recursion
# refuses about 70 nested features and 44 parentheses.
MAX_DEPTH = 20

FeatureModelFile = rule("FeatureModelFile", "name root constraints")
FeatureDecl = rule("FeatureDecl", "abstract name head items")
XorGroup = rule("XorGroup", "members")
OrGroup = rule("OrGroup", "members")
CardinalityGroup = rule("CardinalityGroup", "lower upper members")
Child = rule("Child", "kind feature")
KindBlock = rule("KindBlock", "kind members")
AttributeDecl = rule("AttributeDecl", "name type value")
StringLiteral = rule("StringLiteral", "text")
BoolLiteral = rule("BoolLiteral", "text")
DoubleLiteral = rule("DoubleLiteral", "text")
IntLiteral = rule("IntLiteral", "text")
SharingDecl = rule("SharingDecl", "mode")
CapabilityDecl = rule("CapabilityDecl", "conditions")
CapabilityConditions = rule("CapabilityConditions", "conditions")
CapabilityCondition = rule("CapabilityCondition", "key operator value")
CapabilityString = rule("CapabilityString", "text")
CapabilityBool = rule("CapabilityBool", "text")
CapabilityDouble = rule("CapabilityDouble", "text")
CapabilityInt = rule("CapabilityInt", "text")
Constraint = rule("Constraint", "formula")
Iff = rule("Iff", "first rest")
IffTail = rule("IffTail", "operand")
Implication = rule("Implication", "first rest")
ImplicationTail = rule("ImplicationTail", "operator operand")
Disjunction = rule("Disjunction", "first rest")
DisjunctionTail = rule("DisjunctionTail", "operand")
Conjunction = rule("Conjunction", "first rest")
ConjunctionTail = rule("ConjunctionTail", "operand")
NotFormula = rule("NotFormula", "operand")
Reference = rule("Reference", "name")

_LITERALS = (
    (QUOTED_STRING, StringLiteral),
    (BOOL_WORD, BoolLiteral),
    (DOUBLE_NUMBER, DoubleLiteral),
    (INT_NUMBER, IntLiteral),
)
_CAPABILITY_LITERALS = (
    (CAPABILITY_QUOTED, CapabilityString),
    (BOOL_WORD, CapabilityBool),
    (DOUBLE_NUMBER, CapabilityDouble),
    (INT_NUMBER, CapabilityInt),
)


def read(text: str) -> Any:
    """The textX parse tree of ``text`` (a ``FeatureModelFile``), or None to leave it
    to textX."""
    reader = _Reader(text)
    try:
        tree = reader.feature_model()
    except (Refused, TooDeep):
        return None
    return tree if reader.at_end() else None


def read_capabilities(text: str) -> Any:
    """The tree of capability.tx's ``CapabilityConditions`` for ``text`` (the conditions
    a UVL or FeatureIDE attribute holds), or None to leave it to textX."""
    reader = _CapabilityReader(text)
    try:
        tree = CapabilityConditions(reader.skip(), reader.conditions())
    except Refused:
        return None
    return tree if reader.at_end() else None


class _Reader(Tokens):
    """The rules of fm.tx, one method each (the name of the rule in the comment)."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.depth = 0

    def feature_model(self) -> Any:
        start = self.keyword("feature")
        self.keyword("model")
        name = self.match(IDENT)[1]
        self.keyword("root")
        root = self.feature()
        constraints = self.optional(self.constraints, [])
        return FeatureModelFile(start, name, root, constraints)

    def constraints(self) -> list[Any]:
        """``'constraints' '{' constraints*=Constraint '}'``"""
        self.keyword("constraints")
        self.punct("{")
        found = self.repeated(self.constraint)
        self.punct("}")
        return found

    # -- features ----------------------------------------------------------------------
    def feature(self) -> Any:
        """FeatureDecl"""
        self.deeper()
        try:
            at, word = self.word()
            abstract = word == "abstract"
            if abstract:
                self.pos = at + len(word)
            name = self.match(FEATURE_NAME)[1]
            head = self.optional(self.head_group)
            items = self.optional(self.body, [])
            return FeatureDecl(at, abstract, name, head, items)
        finally:
            self.depth -= 1

    def deeper(self) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise TooDeep

    def body(self) -> list[Any]:
        """``'{' items*=BodyItem '}'``"""
        self.punct("{")
        items = self.repeated(self.body_item)
        self.punct("}")
        return items

    def head_group(self) -> Any:
        """HeadGroup: XorGroup | OrGroup | CardinalityGroup (each starts with a keyword
        of its own, so the next word chooses)."""
        word = self.word()[1]
        if word == "xor":
            return XorGroup(self.keyword("xor"), self.members())
        if word == "or":
            return OrGroup(self.keyword("or"), self.members())
        return self.cardinality_group()

    def cardinality_group(self) -> Any:
        start = self.keyword("group")
        self.punct("[")
        lower = self.match(NATURAL)[1]
        upper = self.optional(self.upper_bound)
        self.punct("]")
        return CardinalityGroup(start, lower, upper, self.members())

    def upper_bound(self) -> str:
        """``'..' upper=Bound`` with Bound: Natural | '*'"""
        self.punct("..")
        if self.at("*"):
            self.punct("*")
            return "*"
        return self.match(NATURAL)[1]

    def members(self) -> list[Any]:
        """``'{' members+=FeatureDecl '}'``"""
        self.punct("{")
        members = [self.feature(), *self.repeated(self.feature)]
        self.punct("}")
        return members

    def body_item(self) -> Any:
        """BodyItem: its alternatives start with keywords of their own, but for
        KindBlock and Child (``mandatory {`` and ``mandatory NAME``)."""
        at, word = self.word()
        if word == "attribute":
            return self.attribute(at)
        if word == "sharing":
            self.pos = at + len(word)
            return SharingDecl(at, self.one_of(("public", "protected", "private")))
        if word == "capability":
            self.pos = at + len(word)
            return CapabilityDecl(at, self.conditions())
        if word in ("mandatory", "optional"):
            self.pos = at + len(word)
            if self.at("{"):
                return KindBlock(at, word, self.members())
            return Child(at, word, self.feature())
        return self.head_group()

    def attribute(self, start: int) -> Any:
        """``'attribute' name=Ident ':' type=AttributeType '=' value=Literal``"""
        self.keyword("attribute")
        name = self.match(IDENT)[1]
        self.punct(":")
        kind = self.one_of(("int", "double", "string", "bool"))
        self.punct("=")
        return AttributeDecl(start, name, kind, self.literal(_LITERALS))

    def literal(self, alternatives: tuple[tuple[re.Pattern[str], Any], ...]) -> Any:
        """Literal / CapabilityLiteral: one terminal each, the first that matches."""
        at = self.skip()
        for regex, literal_rule in alternatives:
            found = regex.match(self.text, at)
            if found is not None:
                self.pos = found.end()
                return literal_rule(at, found.group())
        raise Refused

    # -- capability conditions (capability.tx) -----------------------------------------
    def conditions(self) -> list[Any]:
        """``conditions+=CapabilityCondition['and']``"""
        return [self.condition(), *self.repeated(self.and_condition)]

    def and_condition(self) -> Any:
        self.keyword("and")
        return self.condition()

    def condition(self) -> Any:
        """``key=CapabilityKey (operator=CapabilityOperator value=CapabilityLiteral)?``"""
        at, key = self.match(CAPABILITY_KEY)
        comparison = self.optional(self.comparison, (None, None))
        return CapabilityCondition(at, key, *comparison)

    def comparison(self) -> tuple[str, Any]:
        at = self.skip()
        for operator in (">=", "<=", "!=", "="):
            if self.text.startswith(operator, at):
                self.pos = at + len(operator)
                break
        else:
            operator = self.one_of(("has",))
        return operator, self.literal(_CAPABILITY_LITERALS)

    # -- constraints ---------------------------------------------------------------------
    # A rule's object starts at its first token, which for a formula in parentheses is
    # the '(' before the object of its first operand.
    def constraint(self) -> Any:
        return Constraint(self.skip(), self.iff())

    def iff(self) -> Any:
        at = self.skip()
        return Iff(at, self.implication(), self.repeated(self.iff_tail))

    def iff_tail(self) -> Any:
        return IffTail(self.punct("<=>"), self.implication())

    def implication(self) -> Any:
        at = self.skip()
        return Implication(at, self.disjunction(), self.repeated(self.implication_tail))

    def implication_tail(self) -> Any:
        at = self.skip()
        if self.text.startswith("=>", at):
            self.pos = at + 2
            operator = "=>"
        else:
            operator = self.one_of(("requires", "excludes"))
        return ImplicationTail(at, operator, self.disjunction())

    def disjunction(self) -> Any:
        at = self.skip()
        return Disjunction(at, self.conjunction(), self.repeated(self.disjunction_tail))

    def disjunction_tail(self) -> Any:
        return DisjunctionTail(self.keyword("or"), self.conjunction())

    def conjunction(self) -> Any:
        at = self.skip()
        return Conjunction(at, self.negation(), self.repeated(self.conjunction_tail))

    def conjunction_tail(self) -> Any:
        return ConjunctionTail(self.keyword("and"), self.negation())

    def negation(self) -> Any:
        """Negation: NotFormula | Primary; Primary: Reference | '(' Iff ')'"""
        self.deeper()
        try:
            at, word = self.word()
            if word == "not":
                self.pos = at + len(word)
                return NotFormula(at, self.negation())
            if self.at("("):
                self.punct("(")
                inner = self.iff()
                self.punct(")")
                return inner
            return Reference(*self.match(FEATURE_NAME))
        finally:
            self.depth -= 1


class _CapabilityReader(_Reader):
    """capability.tx on its own: it has no Comment rule, so only blanks are skipped."""

    skipped = BLANKS
