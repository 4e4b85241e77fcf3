"""The rm metamodel (src/spl/metamodels/rm.ecore) for the type checker.

Resolution Model (of "A Software Product Line Approach for Configuring Cloud Robotics Applications",
docs/index.md): resolution elements bind one feature to required elements of the Template System
Model and to the transformations that derive a product architecture. References point into the TSM
and FM metamodels.

Written by scripts/ecore_types.py from the .ecore file: do not edit (the test
tests/cli/test_ecore_types.py fails when it is stale). Import it under
``if TYPE_CHECKING:`` only.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from spl.metamodels.model_types import EObject, EPackage, Many

if TYPE_CHECKING:
    from spl.metamodels import fm_types as fm
    from spl.metamodels import rm_types as rm
    from spl.metamodels import tsm_types as tsm


class Located(EObject):
    # abstract: only its subclasses have instances

    srcFile: str
    srcLine: int
    srcCol: int


class ResolutionModel(Located):
    name: str
    tsmPath: str
    fmPath: str
    elements: Many[ResolutionElement]

    def __init__(
        self,
        *,
        name: str = ...,
        tsmPath: str = ...,
        fmPath: str = ...,
        elements: Iterable[ResolutionElement] = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...


class ResolutionElement(Located):
    """Active when its feature is selected (activeIfSelected true) or not selected (false). Required
    elements are nodes or stores of the TSM that the product keeps.
    """

    feature: fm.Feature
    activeIfSelected: bool
    required: Many[tsm.NamedElement]
    transformations: Many[Transformation]

    def __init__(
        self,
        *,
        feature: fm.Feature = ...,
        activeIfSelected: bool = ...,
        required: Iterable[tsm.NamedElement] = ...,
        transformations: Iterable[Transformation] = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionModel: ...


class Transformation(Located):
    # abstract: only its subclasses have instances

    def eContainer(self) -> ResolutionElement: ...


class Implementation(Transformation):
    node: tsm.Node
    package: str
    executable: str
    #: The node's command-line arguments with this implementation (the .tsm's args); unset: the node
    #: keeps those it has.
    args: str

    def __init__(
        self,
        *,
        node: tsm.Node = ...,
        package: str = ...,
        executable: str = ...,
        args: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionElement: ...


class TopicReference(Located):
    """A topic named by a statement, looked up when the statement runs in a product
    (docs/semantics.md): in container, or, when container is unset, in the container the
    statement's node is in at that point. By name, since the topic may be one an earlier
    statement created.
    """

    container: tsm.Container | None
    name: str

    def __init__(
        self,
        *,
        container: tsm.Container | None = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ConnectToTopic | ConnectBridge: ...


class ConnectToTopic(Transformation):
    interface: tsm.Interface
    topic: TopicReference

    def __init__(
        self,
        *,
        interface: tsm.Interface = ...,
        topic: TopicReference = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionElement: ...


class ConnectToNewTopic(Transformation):
    interface: tsm.Interface
    topic: tsm.Topic

    def __init__(
        self,
        *,
        interface: tsm.Interface = ...,
        topic: tsm.Topic = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionElement: ...


class ConnectService(Transformation):
    """A client bound to a server of its own container: a service client to a service server, an
    action client to an action server (the .rm builder checks the kinds, docs/rm.md).
    """

    client: tsm.Interface
    server: tsm.Interface

    def __init__(
        self,
        *,
        client: tsm.Interface = ...,
        server: tsm.Interface = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionElement: ...


class ConnectBridge(Transformation):
    """A bridge between containers: topic to topic (sourceTopic, targetTopic, each with its
    container) or a service or action client to a server of its kind in another container
    (client, server).
    """

    sourceTopic: TopicReference | None
    targetTopic: TopicReference | None
    client: tsm.Interface | None
    server: tsm.Interface | None

    def __init__(
        self,
        *,
        sourceTopic: TopicReference | None = ...,
        targetTopic: TopicReference | None = ...,
        client: tsm.Interface | None = ...,
        server: tsm.Interface | None = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionElement: ...


class ParameterValue(Transformation):
    """Sets a node parameter, or the period (seconds) of a store's refinement, to a literal
    (canonical text in value) or to a feature attribute's value in the product.
    """

    parameter: tsm.Parameter | None
    refinement: tsm.Refinement | None
    value: str
    attribute: fm.Attribute | None

    def __init__(
        self,
        *,
        parameter: tsm.Parameter | None = ...,
        refinement: tsm.Refinement | None = ...,
        value: str = ...,
        attribute: fm.Attribute | None = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionElement: ...


class NodeMigration(Transformation):
    node: tsm.Node
    target: tsm.Container

    def __init__(
        self,
        *,
        node: tsm.Node = ...,
        target: tsm.Container = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> ResolutionElement: ...


class Metamodel:
    """The rm metamodel as its classes and enums, as ``spl.metamodels.rm()`` gives it (and the plain
    twins, for the tsm).
    """

    package: EPackage
    Located: type[rm.Located]
    ResolutionModel: type[rm.ResolutionModel]
    ResolutionElement: type[rm.ResolutionElement]
    Transformation: type[rm.Transformation]
    Implementation: type[rm.Implementation]
    TopicReference: type[rm.TopicReference]
    ConnectToTopic: type[rm.ConnectToTopic]
    ConnectToNewTopic: type[rm.ConnectToNewTopic]
    ConnectService: type[rm.ConnectService]
    ConnectBridge: type[rm.ConnectBridge]
    ParameterValue: type[rm.ParameterValue]
    NodeMigration: type[rm.NodeMigration]
