"""The tsm metamodel (src/spl/metamodels/tsm.ecore) for the type checker.

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
    from spl.metamodels import rm_types as rm
    from spl.metamodels import tsm_types as tsm


class SharingMode(EnumLiteral):
    """A literal of the enum SharingMode."""

    name: Literal["private", "protected", "public"]


class SharingModeEnum(EnumType):
    """The enum SharingMode: its literals by name."""

    private: SharingMode
    protected: SharingMode
    public: SharingMode

    def getEEnumLiteral(self, name: builtins.str) -> SharingMode | None: ...


class ParameterType(EnumLiteral):
    """A literal of the enum ParameterType."""

    name: Literal["string", "int", "double", "bool", "yaml"]


class ParameterTypeEnum(EnumType):
    """The enum ParameterType: its literals by name."""

    string: ParameterType
    int: ParameterType
    double: ParameterType
    bool: ParameterType
    yaml: ParameterType

    def getEEnumLiteral(self, name: builtins.str) -> ParameterType | None: ...


class FieldType(EnumLiteral):
    """A literal of the enum FieldType."""

    name: Literal["double", "int", "string", "bool"]


class FieldTypeEnum(EnumType):
    """The enum FieldType: its literals by name."""

    double: FieldType
    int: FieldType
    string: FieldType
    bool: FieldType

    def getEEnumLiteral(self, name: builtins.str) -> FieldType | None: ...


class Located(EObject):
    # abstract: only its subclasses have instances

    srcFile: str
    srcLine: int
    srcCol: int


class NamedElement(Located):
    # abstract: only its subclasses have instances

    name: str


class System(NamedElement):
    dataTypes: Many[DataType]
    transforms: Many[Transform]
    containers: Many[Container]
    connections: Many[EndpointConnection]

    def __init__(
        self,
        *,
        dataTypes: Iterable[DataType] = ...,
        transforms: Iterable[Transform] = ...,
        containers: Iterable[Container] = ...,
        connections: Iterable[EndpointConnection] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...


class Container(NamedElement):
    # abstract: only its subclasses have instances

    namespace: str
    endpoint: Endpoint
    topics: Many[Topic]
    nodes: Many[Node]
    stores: Many[Store]

    def eContainer(self) -> System: ...


class RobotContainer(Container):
    def __init__(
        self,
        *,
        namespace: str = ...,
        endpoint: Endpoint = ...,
        topics: Iterable[Topic] = ...,
        nodes: Iterable[Node] = ...,
        stores: Iterable[Store] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> System: ...


class CloudContainer(Container):
    group: str
    size: int | None
    cpu: int | None
    memory: int | None
    bandwidth: int | None

    def __init__(
        self,
        *,
        group: str = ...,
        size: int | None = ...,
        cpu: int | None = ...,
        memory: int | None = ...,
        bandwidth: int | None = ...,
        namespace: str = ...,
        endpoint: Endpoint = ...,
        topics: Iterable[Topic] = ...,
        nodes: Iterable[Node] = ...,
        stores: Iterable[Store] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> System: ...


class Endpoint(Located):
    """A container's single gateway to the others (Rapyuta's EndPoint). Robot endpoints carry the
    cloud-engine credentials; the password is only ever the name of an environment variable.
    """

    robotId: str
    url: str
    user: str
    passwordEnv: str
    interfaces: Many[Interface]

    def __init__(
        self,
        *,
        robotId: str = ...,
        url: str = ...,
        user: str = ...,
        passwordEnv: str = ...,
        interfaces: Iterable[Interface] = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Container: ...


class Interface(NamedElement):
    """The interface kinds (topic publishers and subscribers, service and action servers and
    clients), owned by a Node or by an Endpoint (the endpoint's specialised interfaces of the
    paper). `type` is the ROS message, service or action type. `external` is set on a node's
    input (a subscriber, a service or action client) that something outside the architecture
    feeds, such as a driver the robot's own bring-up starts: the model's reason, for which no
    product warns that nothing feeds it (docs/tsm.md).
    """

    # abstract: only its subclasses have instances

    type: str
    external: str

    def eContainer(self) -> Endpoint | Node: ...


class Publisher(Interface):
    topic: Topic | None

    def __init__(
        self,
        *,
        topic: Topic | None = ...,
        type: str = ...,
        external: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Endpoint | Node: ...


class Subscriber(Interface):
    topic: Topic | None

    def __init__(
        self,
        *,
        topic: Topic | None = ...,
        type: str = ...,
        external: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Endpoint | Node: ...


class ServiceServer(Interface):
    rosName: str

    def __init__(
        self,
        *,
        rosName: str = ...,
        type: str = ...,
        external: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Endpoint | Node: ...


class ServiceClient(Interface):
    server: ServiceServer | None

    def __init__(
        self,
        *,
        server: ServiceServer | None = ...,
        type: str = ...,
        external: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Endpoint | Node: ...


class ActionServer(Interface):
    """A ROS action a node serves (actionlib in ROS 1, an action server in ROS 2): `type` is the
    action's type, `package/Name` of its .action file, and `rosName` the name its goals are sent
    to (docs/tsm.md, "Actions").
    """

    rosName: str

    def __init__(
        self,
        *,
        rosName: str = ...,
        type: str = ...,
        external: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Endpoint | Node: ...


class ActionClient(Interface):
    """A node's client of an action: it sends goals to the one action server it is bound to and
    takes its feedback and result (docs/tsm.md, "Actions").
    """

    server: ActionServer | None

    def __init__(
        self,
        *,
        server: ActionServer | None = ...,
        type: str = ...,
        external: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Endpoint | Node: ...


class EndpointConnection(Located):
    """Data flows from source to target: an endpoint Subscriber to an endpoint Publisher in another
    container, or an endpoint ServiceServer (where calls arrive) to an endpoint ServiceClient
    (which calls the real server).
    """

    source: Interface
    target: Interface

    def __init__(
        self,
        *,
        source: Interface = ...,
        target: Interface = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> System: ...


class Topic(NamedElement):
    type: str
    rosName: str

    def __init__(
        self,
        *,
        type: str = ...,
        rosName: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Container | rm.ConnectToNewTopic: ...


class Node(NamedElement):
    optional: bool
    sharing: SharingMode
    package: str
    executable: str
    args: str
    parameters: Many[Parameter]
    interfaces: Many[Interface]

    def __init__(
        self,
        *,
        optional: bool = ...,
        sharing: SharingMode = ...,
        package: str = ...,
        executable: str = ...,
        args: str = ...,
        parameters: Iterable[Parameter] = ...,
        interfaces: Iterable[Interface] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Container: ...


class Parameter(NamedElement):
    type: ParameterType
    #: canonical text of the typed value; unset when the TSM leaves it to a feature
    value: str

    def __init__(
        self,
        *,
        type: ParameterType = ...,
        value: str = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Node: ...


class DataType(NamedElement):
    """Data acquisition (after "Architecture and framework for data acquisition in cloud robotics",
    docs/services.md)
    """

    fields: Many[Field]

    def __init__(
        self,
        *,
        fields: Iterable[Field] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> System: ...


class Field(NamedElement):
    type: FieldType

    def __init__(
        self,
        *,
        type: FieldType = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> DataType: ...


class Transform(NamedElement):
    input: DataType
    output: DataType
    assignments: Many[Assignment]

    def __init__(
        self,
        *,
        input: DataType = ...,
        output: DataType = ...,
        assignments: Iterable[Assignment] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> System: ...


class Assignment(Located):
    field: str
    expression: Expression

    def __init__(
        self,
        *,
        field: str = ...,
        expression: Expression = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Transform: ...


class Expression(Located):
    # abstract: only its subclasses have instances

    def eContainer(self) -> Assignment | BinaryExpression | UnaryExpression | CallExpression: ...


class BinaryExpression(Expression):
    operator: str
    left: Expression
    right: Expression

    def __init__(
        self,
        *,
        operator: str = ...,
        left: Expression = ...,
        right: Expression = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Assignment | BinaryExpression | UnaryExpression | CallExpression: ...


class UnaryExpression(Expression):
    operator: str
    operand: Expression

    def __init__(
        self,
        *,
        operator: str = ...,
        operand: Expression = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Assignment | BinaryExpression | UnaryExpression | CallExpression: ...


class CallExpression(Expression):
    function: str
    arguments: Many[Expression]

    def __init__(
        self,
        *,
        function: str = ...,
        arguments: Iterable[Expression] = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Assignment | BinaryExpression | UnaryExpression | CallExpression: ...


class FieldReference(Expression):
    """`record` is empty for the current record, or `prev` / `next` for the neighbouring record of
    the same robot ordered by source timestamp. `timestamp` is an implicit field.
    """

    record: str
    field: str

    def __init__(
        self,
        *,
        record: str = ...,
        field: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Assignment | BinaryExpression | UnaryExpression | CallExpression: ...


class NumberLiteral(Expression):
    value: str

    def __init__(
        self,
        *,
        value: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Assignment | BinaryExpression | UnaryExpression | CallExpression: ...


class BooleanLiteral(Expression):
    value: bool

    def __init__(
        self,
        *,
        value: bool = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Assignment | BinaryExpression | UnaryExpression | CallExpression: ...


class Store(NamedElement):
    optional: bool
    raw: DataType
    refinements: Many[Refinement]

    def __init__(
        self,
        *,
        optional: bool = ...,
        raw: DataType = ...,
        refinements: Iterable[Refinement] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Container: ...


class Refinement(Located):
    output: DataType
    transform: Transform
    #: transformer period in seconds
    period: float

    def __init__(
        self,
        *,
        output: DataType = ...,
        transform: Transform = ...,
        period: float = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Store: ...


class Writer(Node):
    """Writers and readers are ROS nodes (the WriteRTC/ReadRTC of "Architecture and framework for
    data acquisition in cloud robotics", docs/services.md): a writer subscribes a topic and posts
    to a store; a reader polls a store and publishes.
    """

    dataType: DataType
    store: Store

    def __init__(
        self,
        *,
        dataType: DataType = ...,
        store: Store = ...,
        optional: bool = ...,
        sharing: SharingMode = ...,
        package: str = ...,
        executable: str = ...,
        args: str = ...,
        parameters: Iterable[Parameter] = ...,
        interfaces: Iterable[Interface] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Container: ...


class Reader(Node):
    dataType: DataType
    store: Store
    period: float
    subscribe: bool

    def __init__(
        self,
        *,
        dataType: DataType = ...,
        store: Store = ...,
        period: float = ...,
        subscribe: bool = ...,
        optional: bool = ...,
        sharing: SharingMode = ...,
        package: str = ...,
        executable: str = ...,
        args: str = ...,
        parameters: Iterable[Parameter] = ...,
        interfaces: Iterable[Interface] = ...,
        name: str = ...,
        srcFile: str = ...,
        srcLine: int = ...,
        srcCol: int = ...,
    ) -> None: ...

    def eContainer(self) -> Container: ...


class Metamodel:
    """The tsm metamodel as its classes and enums, as ``spl.metamodels.tsm()`` gives it (and the
    plain twins, for the tsm).
    """

    package: EPackage
    located_later: bool  # the plain twins only (spl.dsl.tsm.plain)
    SharingMode: tsm.SharingModeEnum
    ParameterType: tsm.ParameterTypeEnum
    FieldType: tsm.FieldTypeEnum
    Located: type[tsm.Located]
    NamedElement: type[tsm.NamedElement]
    System: type[tsm.System]
    Container: type[tsm.Container]
    RobotContainer: type[tsm.RobotContainer]
    CloudContainer: type[tsm.CloudContainer]
    Endpoint: type[tsm.Endpoint]
    Interface: type[tsm.Interface]
    Publisher: type[tsm.Publisher]
    Subscriber: type[tsm.Subscriber]
    ServiceServer: type[tsm.ServiceServer]
    ServiceClient: type[tsm.ServiceClient]
    ActionServer: type[tsm.ActionServer]
    ActionClient: type[tsm.ActionClient]
    EndpointConnection: type[tsm.EndpointConnection]
    Topic: type[tsm.Topic]
    Node: type[tsm.Node]
    Parameter: type[tsm.Parameter]
    DataType: type[tsm.DataType]
    Field: type[tsm.Field]
    Transform: type[tsm.Transform]
    Assignment: type[tsm.Assignment]
    Expression: type[tsm.Expression]
    BinaryExpression: type[tsm.BinaryExpression]
    UnaryExpression: type[tsm.UnaryExpression]
    CallExpression: type[tsm.CallExpression]
    FieldReference: type[tsm.FieldReference]
    NumberLiteral: type[tsm.NumberLiteral]
    BooleanLiteral: type[tsm.BooleanLiteral]
    Store: type[tsm.Store]
    Refinement: type[tsm.Refinement]
    Writer: type[tsm.Writer]
    Reader: type[tsm.Reader]
