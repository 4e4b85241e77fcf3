"""The Arithmetic and Type levels of UVL: typed features, feature cardinalities, equations.

A model that uses them is a :class:`TypedFeatureModel`: the Boolean model every other
reader makes (its tree and Boolean constraints, which the SAT path and every Boolean
consumer read unchanged) plus what only an SMT solver can carry: the feature types,
the feature cardinalities and the constraints with arithmetic, comparisons, strings and
aggregate functions (:class:`Equation`). Their semantics are docs/fm.md's ("Typed
features, cardinalities and arithmetic"); :mod:`spl.resolver.analysis.smt` implements
them.

An equation is a tuple tree, position last, like a Boolean formula
(:mod:`spl.dsl.fm.plain`), with these nodes besides ``and or implies iff not ref``:

* ``("cmp", op, left, right, pos)``: ``op`` one of ``== != < <= > >=``;
* ``("arith", op, left, right, pos)``: ``op`` one of ``+ - * /``;
* ``("num", text, pos)``, ``("str", text, pos)``: literals as written;
* ``("value", feature, pos)``: a typed feature's value;
* ``("selected", feature, pos)``: a Boolean feature as a number (1 or 0);
* ``("attr", feature, attribute, sort, value or None, pos)``: an attribute's value
  (``sort`` num or str; ``None``: declared nowhere, a variable);
* ``("sum" | "avg", ((feature, value), ...), pos)``: the values of the features
  selected;
* ``("len" | "floor" | "ceil", operand, pos)``.
"""

from __future__ import annotations

from spl.dsl.fm.plain import Feature, FeatureModel, Located, Source

# UVL type keyword -> the sort of its value ("Boolean" features are plain features)
SORTS = {"Integer": "num", "Real": "num", "String": "str"}
NUMERIC_ATTRIBUTES = ("int", "double")


class Equation(Located):
    """A constraint of the Arithmetic or Type level (the module docstring's tree)."""

    __slots__ = ("formula",)

    def __init__(self, source: Source, position: int, formula: tuple) -> None:
        super().__init__(source, position)
        self.formula = formula


class TypedFeatureModel(FeatureModel):
    """A feature model with parts of the Arithmetic or Type level.

    ``types``: feature identifier -> ``Integer``, ``Real`` or ``String``;
    ``cardinalities``: feature identifier -> (lower, upper), upper -1 meaning ``*``, and
    where each was written; ``equations``: the constraints only an SMT solver reads."""

    __slots__ = ("cardinalities", "equations", "types")

    def __init__(self, plain: FeatureModel) -> None:
        super().__init__(plain.source, plain.name, plain.written_name)
        self.root = plain.root
        self.constraints = plain.constraints
        self.types: dict[str, str] = {}
        self.cardinalities: dict[str, tuple[int, int, int]] = {}
        self.equations: list[Equation] = []


def is_typed(model: object) -> bool:
    """Whether analysis needs the SMT solver for this model."""
    return isinstance(model, TypedFeatureModel)


def subtree_features(root: Feature | None) -> list[Feature]:
    """``root`` and every feature below it, in pre-order."""
    found: list[Feature] = []
    work = [root] if root is not None else []
    while work:
        feature = work.pop()
        found.append(feature)
        for group in reversed(feature.groups):
            work.extend(reversed(group.features))
    return found


def features_of(model: FeatureModel) -> list[Feature]:
    """Every feature in pre-order (the encoding's numbering, docs/analysis.md)."""
    return subtree_features(model.root)


def renamed_equation(formula: tuple, names: dict[str, str]) -> tuple:
    """An imported model's equation over the importing model's identifiers (explicit
    stacks: any chain length)."""
    done: list[tuple] = []
    work: list[tuple[tuple, bool]] = [(formula, False)]
    while work:
        node, ready = work.pop()
        head = node[0]
        slots = _SLOTS.get(head, ())
        children = [v for _, v in node[1]] if head in ("sum", "avg") else [node[i] for i in slots]
        if children and not ready:
            work.append((node, True))
            work.extend((child, False) for child in reversed(children))
            continue
        built = done[len(done) - len(children) :] if children else []
        if children:
            del done[len(done) - len(children) :]
        if head in ("ref", "value", "selected", "attr"):
            done.append((head, names[node[1]], *node[2:]))
        elif head in ("sum", "avg"):
            terms = tuple((names[f], v) for (f, _), v in zip(node[1], built, strict=True))
            done.append((head, terms, node[2]))
        else:
            rebuilt = list(node)
            for slot, child in zip(slots, built, strict=True):
                rebuilt[slot] = child
            done.append(tuple(rebuilt))
    return done[0]


# where each inner node of an equation holds its operands
_SLOTS = {
    "and": (1, 2),
    "or": (1, 2),
    "implies": (1, 2),
    "iff": (1, 2),
    "not": (1,),
    "len": (1,),
    "floor": (1,),
    "ceil": (1,),
    "cmp": (2, 3),
    "arith": (2, 3),
}
