"""The fm metamodel (src/spl/metamodels/fm.ecore) for the type checker.

Written by scripts/ecore_types.py from the .ecore file: do not edit (the test
tests/cli/test_ecore_types.py fails when it is stale). Import it under
``if TYPE_CHECKING:`` only.
"""

from __future__ import annotations

import builtins
from collections.abc import Iterable
from typing import TYPE_CHECKING, Literal

from spl.metamodels.model_types import EnumLiteral, EnumType, EObject, EPackage, Many

if TYPE_CHECKING:
    from spl.metamodels import fm_types as fm


class GroupKind(EnumLiteral):
    """A literal of the enum GroupKind."""

    name: Literal["mandatory", "optional", "alternative", "or", "cardinality"]


class GroupKindEnum(EnumType):
    """The enum GroupKind: its literals by name."""

    mandatory: GroupKind
    optional: GroupKind
    alternative: GroupKind
    # or: a keyword, reached through getEEnumLiteral('or')
    cardinality: GroupKind

    def getEEnumLiteral(self, name: builtins.str) -> GroupKind | None: ...


class AttributeType(EnumLiteral):
    """A literal of the enum AttributeType."""

    name: Literal["int", "double", "string", "bool"]


class AttributeTypeEnum(EnumType):
    """The enum AttributeType: its literals by name."""

    int: AttributeType
    double: AttributeType
    string: AttributeType
    bool: AttributeType

    def getEEnumLiteral(self, name: builtins.str) -> AttributeType | None: ...


class SharingMode(EnumLiteral):
    """A literal of the enum SharingMode."""

    name: Literal["private", "protected", "public"]


class SharingModeEnum(EnumType):
    """The enum SharingMode: its literals by name."""

    private: SharingMode
    protected: SharingMode
    public: SharingMode

    def getEEnumLiteral(self, name: builtins.str) -> SharingMode | None: ...


class Located(EObject):
    # abstract: only its subclasses have instances

    srcFile: str
    srcLine: int
    srcCol: int


class NamedElement(Located):
    # abstract: only its subclasses have instances

    name: str


class FeatureModel(NamedElement):
    root: Feature
    constraints: Many[Constraint]

    def __init__(
        self,
        *,
        root: Feature = ...,
        constraints: Iterable[Constraint] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...


class Feature(NamedElement):
    abstract: bool
    attributes: Many[Attribute]
    sharing: SharingConfig | None
    groups: Many[Group]
    #: robot capabilities that select the feature (all of them must hold); a capability file that
    #: declares the capabilities but fails a condition deselects it
    capabilities: Many[CapabilityCondition]

    def __init__(
        self,
        *,
        abstract: bool = ...,
        attributes: Iterable[Attribute] = ...,
        sharing: SharingConfig | None = ...,
        groups: Iterable[Group] = ...,
        capabilities: Iterable[CapabilityCondition] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> FeatureModel | Group: ...


class Group(Located):
    """lower/upper only matter for `cardinality`; upper -1 means `*`"""

    kind: GroupKind
    lower: int
    upper: int
    features: Many[Feature]

    def __init__(
        self,
        *,
        kind: GroupKind = ...,
        lower: int = ...,
        upper: int = ...,
        features: Iterable[Feature] = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Feature: ...


class Attribute(NamedElement):
    type: AttributeType
    #: canonical text of the default value
    value: str

    def __init__(
        self,
        *,
        type: AttributeType = ...,
        value: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Feature: ...


class SharingConfig(Located):
    """SharingConfig (of "A Software Product Line Approach for Configuring Cloud Robotics
    Applications", docs/index.md): default sharing mode of the feature's functionality
    """

    mode: SharingMode

    def __init__(
        self,
        *,
        mode: SharingMode = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Feature: ...


class CapabilityCondition(Located):
    """`capability KEY [OP VALUE]` on a feature: KEY is a (dotted) capability name of a robot
    capability file; operator is empty (the capability is true), =, !=, has (a list holds the
    value), >= or <=; value is the canonical text of a literal of valueType
    """

    key: str
    operator: str
    value: str
    valueType: AttributeType

    def __init__(
        self,
        *,
        key: str = ...,
        operator: str = ...,
        value: str = ...,
        valueType: AttributeType = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Feature: ...


class Constraint(Located):
    formula: Formula

    def __init__(
        self,
        *,
        formula: Formula = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> FeatureModel: ...


class Formula(Located):
    # abstract: only its subclasses have instances

    def eContainer(self) -> Constraint | Not | BinaryFormula: ...


class FeatureRef(Formula):
    feature: Feature

    def __init__(
        self,
        *,
        feature: Feature = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Constraint | Not | BinaryFormula: ...


class Not(Formula):
    operand: Formula

    def __init__(
        self,
        *,
        operand: Formula = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Constraint | Not | BinaryFormula: ...


class BinaryFormula(Formula):
    """operator: and, or, implies, iff, requires, excludes (the last two kept as written so
    explanations can quote the rule the way its author wrote it)
    """

    operator: str
    left: Formula
    right: Formula

    def __init__(
        self,
        *,
        operator: str = ...,
        left: Formula = ...,
        right: Formula = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Constraint | Not | BinaryFormula: ...


class Metamodel:
    """The fm metamodel as its classes and enums, as ``spl.metamodels.fm()`` gives it (and the plain
    twins, for the tsm).
    """

    package: EPackage
    GroupKind: fm.GroupKindEnum
    AttributeType: fm.AttributeTypeEnum
    SharingMode: fm.SharingModeEnum
    Located: type[fm.Located]
    NamedElement: type[fm.NamedElement]
    FeatureModel: type[fm.FeatureModel]
    Feature: type[fm.Feature]
    Group: type[fm.Group]
    Attribute: type[fm.Attribute]
    SharingConfig: type[fm.SharingConfig]
    CapabilityCondition: type[fm.CapabilityCondition]
    Constraint: type[fm.Constraint]
    Formula: type[fm.Formula]
    FeatureRef: type[fm.FeatureRef]
    Not: type[fm.Not]
    BinaryFormula: type[fm.BinaryFormula]
