"""A feature model held in plain Python objects, turned into pyecore only on demand.

Why: building a pyecore object costs tens of microseconds (every attribute set goes
through notification and type checks), and a community model such as the Linux
kernel's has 6,500 features and 3,500 constraints with some 70,000 formula nodes; the
UVL reader spent seconds on pyecore alone. Analysis needs none of it: the CNF encoder
(:mod:`spl.resolver.analysis.cnf`) reads these objects directly, and :func:`to_ecore` builds the
``fm.FeatureModel`` (src/spl/metamodels/fm.ecore) with the very same elements, values and
source locations when EMF interop needs it (conversion, the resolver, the printers).

Formulas are tuple trees, the shape the encoder works on: ``("ref", name, position)``,
``("not", operand, position)``, ``(operator, left, right, position)``, operator one of
the metamodel's binary operators; ``name`` is the feature's identifier (``Feature.name``)
and ``position`` the character offset the element was read at.
"""

from __future__ import annotations

import bisect
from typing import TYPE_CHECKING, TypeVar, cast

from spl.core.diagnostics import Location

if TYPE_CHECKING:
    from spl.metamodels import fm_types

Located_ = TypeVar("Located_", bound="fm_types.Located")  # an element being built


class Source:
    """A file read: its name, and where its lines start (offsets -> line and column)."""

    __slots__ = ("file", "line_starts")

    def __init__(self, file: str, text: str) -> None:
        self.file = file
        starts = [0]
        find = text.find
        at = find("\n")
        while at >= 0:
            starts.append(at + 1)
            at = find("\n", at + 1)
        self.line_starts = starts

    def location(self, position: int) -> Location:
        line = bisect.bisect_right(self.line_starts, position)
        return Location(self.file, line, position - self.line_starts[line - 1] + 1)


class Located:
    """An element read at ``position`` of ``source``; answers ``srcFile/srcLine/srcCol``
    like the metamodels' ``Located`` so diagnostics locate both kinds of model alike."""

    __slots__ = ("position", "source")

    def __init__(self, source: Source, position: int) -> None:
        self.source = source
        self.position = position

    @property
    def srcFile(self) -> str:  # the metamodel spells it so
        return self.source.file

    @property
    def srcLine(self) -> int:
        return self.source.location(self.position).line

    @property
    def srcCol(self) -> int:
        return self.source.location(self.position).col


class Attribute(Located):
    """``type`` is one of int, double, string, bool; ``value`` its canonical text."""

    __slots__ = ("name", "type", "value")

    def __init__(self, source: Source, position: int, name: str, type: str, value: str) -> None:
        super().__init__(source, position)
        self.name, self.type, self.value = name, type, value


class Sharing(Located):
    __slots__ = ("mode",)

    def __init__(self, source: Source, position: int, mode: str) -> None:
        super().__init__(source, position)
        self.mode = mode


class Feature(Located):
    __slots__ = ("abstract", "attributes", "capability", "groups", "name", "sharing")

    def __init__(self, source: Source, position: int, name: str) -> None:
        super().__init__(source, position)
        self.name = name
        self.abstract = False
        self.attributes: list[Attribute] = []
        self.sharing: Sharing | None = None
        # (type, text, position) of a UVL ``capability`` attribute: conditions as .fm text
        self.capability: tuple[str, str, int] | None = None
        self.groups: list[Group] = []


class Group(Located):
    """``kind``: mandatory, optional, alternative, or, cardinality (``lower``/``upper``,
    upper -1 meaning unbounded)."""

    __slots__ = ("features", "kind", "lower", "upper")

    def __init__(self, source: Source, position: int, kind: str) -> None:
        super().__init__(source, position)
        self.kind = kind
        self.lower = 0
        self.upper = -1
        self.features: list[Feature] = []


class Constraint(Located):
    __slots__ = ("formula",)

    def __init__(self, source: Source, position: int, formula: tuple) -> None:
        super().__init__(source, position)
        self.formula = formula


class FeatureModel(Located):
    """``name`` is an identifier (the .fm language needs one); ``written_name`` the name
    as the file gives it (a UVL namespace, a file stem), which reports show."""

    __slots__ = ("constraints", "name", "root", "written_name")

    def __init__(self, source: Source, name: str, written_name: str | None = None) -> None:
        super().__init__(source, 0)
        self.name = name
        self.written_name = name if written_name is None else written_name
        self.root: Feature | None = None
        self.constraints: list[Constraint] = []


if TYPE_CHECKING:
    # A feature model as analysis reads it, in either form: pyecore's (fm.ecore), or held
    # in the plain objects of this module; and its parts.
    FmModel = fm_types.FeatureModel | FeatureModel
    FmFeature = fm_types.Feature | Feature
    FmGroup = fm_types.Group | Group
    FmConstraint = fm_types.Constraint | Constraint


def to_ecore(model: FeatureModel) -> fm_types.FeatureModel:
    """The same model as an ``fm.FeatureModel`` (pyecore), every element located."""
    from spl.metamodels import fm as fm_metamodel

    return _Converter(fm_metamodel(), model.source).model(model)


class _Converter:
    def __init__(self, F: fm_types.Metamodel, source: Source) -> None:
        self.F = F
        self.source = source
        self.features: dict[str, fm_types.Feature] = {}

    def locate(self, element: Located_, position: int, source: Source | None = None) -> Located_:
        """Locate ``element`` in ``source`` (an imported UVL file's elements are located
        in it), the model's file by default."""
        where = (source or self.source).location(position)
        element.srcFile, element.srcLine, element.srcCol = where.file, where.line, where.col
        return element

    def model(self, plain: FeatureModel) -> fm_types.FeatureModel:
        F = self.F
        model = self.locate(F.FeatureModel(name=plain.name), plain.position)
        model.root = self.feature(cast(Feature, plain.root))  # a model read has its root
        for constraint in plain.constraints:
            element = self.locate(F.Constraint(), constraint.position, constraint.source)
            element.formula = self.formula(constraint.formula, constraint.source)
            model.constraints.append(element)
        return model

    def feature(self, plain: Feature) -> fm_types.Feature:
        F = self.F
        feature = self.locate(F.Feature(name=plain.name), plain.position, plain.source)
        self.features[plain.name] = feature
        if plain.abstract:
            feature.abstract = True
        for attribute in plain.attributes:
            element = self.locate(
                F.Attribute(name=attribute.name), attribute.position, attribute.source
            )
            element.type = cast(
                "fm_types.AttributeType", F.AttributeType.getEEnumLiteral(attribute.type)
            )
            element.value = attribute.value
            feature.attributes.append(element)
        if plain.sharing is not None:
            config = self.locate(F.SharingConfig(), plain.sharing.position, plain.source)
            config.mode = cast(
                "fm_types.SharingMode", F.SharingMode.getEEnumLiteral(plain.sharing.mode)
            )
            feature.sharing = config
        if plain.capability is not None:
            from spl.dsl.interop.interchange import (
                add_capabilities,  # the .fm grammar: only if used
            )

            type_name, text, position = plain.capability
            add_capabilities(feature, type_name, text, plain.source.location(position))
        for plain_group in plain.groups:
            group = self.locate(F.Group(), plain_group.position, plain_group.source)
            group.kind = cast("fm_types.GroupKind", F.GroupKind.getEEnumLiteral(plain_group.kind))
            if plain_group.kind == "cardinality":
                group.lower, group.upper = plain_group.lower, plain_group.upper
            for child in plain_group.features:
                group.features.append(self.feature(child))
            feature.groups.append(group)
        return feature

    def formula(self, tree: tuple, source: Source) -> fm_types.Formula:
        F = self.F
        head = tree[0]
        if head == "ref":
            return self.locate(F.FeatureRef(feature=self.features[tree[1]]), tree[2], source)
        if head == "not":
            return self.locate(F.Not(operand=self.formula(tree[1], source)), tree[2], source)
        left, right = self.formula(tree[1], source), self.formula(tree[2], source)
        binary = F.BinaryFormula(operator=head, left=left, right=right)
        return self.locate(binary, tree[3], source)
