"""What the resolution model does to each node, per resolution element: the model the
fleet analysis reasons with instead of enumerating products.

For every node of the template this module lists the things a product decides about
it (*aspects*), and for each aspect which resolution elements set it to which value
when they are active (*effects*); with no effective element the template's value stays:

==================  ===========================================  =======================
aspect              set by                                       template value
==================  ===========================================  =======================
placement           ``migrate NODE to C``                        the node's container
sharing mode        the sharing mode of the element's feature    the node's ``sharing``
                    (product override, else the feature's
                    default) for its required nodes and targets
implementation      ``implementation NODE = pkg/exe``            the .tsm implementation
parameter P         ``parameter NODE.P = literal | feature F.a``  the .tsm value
topic of I          ``connect NODE.I to [new] topic T``          the .tsm binding
server of C         ``connect NODE.C to server S`` and service   the .tsm binding
                    bridges; the real server, where its node
                    runs, or none when its node is absent
==================  ===========================================  =======================

A node is present when it is stable, or when an active element requires or transforms
it (:func:`spl.resolver.resolution.transformations.touched_elements`, the
engine's ``keep``). Within one product two active elements never give one aspect two
values (the engine refuses that, SPL020), so an aspect's value is that of *the* active
effect, or the template's. Values are those the resolved model shows, so a prediction
can be compared with a resolution (:func:`observed`) and, in the fleet analysis, with
what other robots' resolved products ask.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import Location, location_of
from spl.metamodels import interface_kinds, tsm
from spl.resolver.architecture.placement import sharing_mode
from spl.resolver.architecture.product import topic_ros_name
from spl.resolver.resolution.data_clients import client_packages
from spl.resolver.resolution.transformations import kind_of, sharing_targets, touched_elements
from spl.resolver.resolution.transformations.migration import PLACEMENT

if TYPE_CHECKING:
    from spl.metamodels import rm_types, tsm_types
    from spl.resolver.architecture.product import AttributeValue, ResolvedProduct
    from spl.resolver.resolution.product_line import ProductLine

    # an aspect's value: a name (container, sharing mode, implementation, ROS name...),
    # a client's server (predicted: its id and where its node runs), or None (unset)
    Value = str | tuple[str, str] | tsm_types.ServiceServer | None
    # what an element sets an aspect to: a value, or a function of a robot's settings
    EffectValue = Value | Callable[["Settings"], str]

Active = Callable[["rm_types.ResolutionElement"], bool]  # is this resolution element active?
SHARING = "sharing mode"


@dataclass(frozen=True)
class Settings:
    """What a robot's product decides besides features: sharing overrides, attributes."""

    sharing: tuple[tuple[str, str], ...] = ()  # feature -> mode
    attributes: tuple[tuple[str, AttributeValue], ...] = ()  # "Feature.attr" -> value

    @classmethod
    def of(cls, sharing: dict[str, str], attributes: dict[str, AttributeValue]) -> Settings:
        return cls(tuple(sorted(sharing.items())), tuple(sorted(attributes.items())))


@dataclass(frozen=True)
class Effect:
    """An active ``element`` sets the aspect to ``value``; ``where`` is its statement."""

    element: rm_types.ResolutionElement
    value: EffectValue  # a value, or a function of the robot's Settings
    where: Location | None

    def value_for(self, settings: Settings) -> Value:
        return self.value(settings) if callable(self.value) else self.value


@dataclass
class Aspect:
    name: str
    default: Value
    default_where: Location | None
    effects: list[Effect] = field(default_factory=list)

    def effective(self, active: Active) -> Effect | None:
        """The active effect deciding the aspect (None: the template value stays)."""
        return next((e for e in self.effects if active(e.element)), None)

    def value(self, active: Active, settings: Settings) -> Value:
        effect = self.effective(active)
        return self.default if effect is None else effect.value_for(settings)


@dataclass
class NodeEffects:
    """Everything the resolution model can do to one template node."""

    node: tsm_types.Node
    origin: str  # the template container
    # elements making it present
    keepers: list[rm_types.ResolutionElement] = field(default_factory=list)
    aspects: dict[str, Aspect] = field(default_factory=dict)
    servers: dict[str, Aspect] = field(default_factory=dict)  # client -> template server

    @property
    def name(self) -> str:
        return self.node.name

    @property
    def key(self) -> tuple[str, str]:
        return (self.origin, self.node.name)

    def present(self, active: Active) -> bool:
        return not self.node.optional or any(active(e) for e in self.keepers)


class LineEffects:
    """The effects of a product line's resolution model on every node of its template."""

    def __init__(self, line: ProductLine) -> None:
        T = tsm()
        self.line = line
        self.nodes: dict[tuple[str, str], NodeEffects] = {}
        self.by_node: dict[int, NodeEffects] = {}
        self.robot_containers = {
            c.name for c in line.tsm.containers if isinstance(c, T.RobotContainer)
        }
        packages = client_packages(line.tsm)  # the writers' and readers' generated ones
        for container in line.tsm.containers:
            for node in container.nodes:
                effects = NodeEffects(node, container.name)
                where = location_of(node)
                effects.aspects[PLACEMENT] = Aspect(PLACEMENT, container.name, where)
                effects.aspects[SHARING] = Aspect(SHARING, sharing_mode(node), where)
                package = packages.get(id(node))
                implementation = (
                    f"{package}/{package}"
                    if package
                    else (f"{node.package}/{node.executable}" if node.package else None)
                )
                effects.aspects["implementation"] = Aspect("implementation", implementation, where)
                effects.aspects["args"] = Aspect("args", node.args, where)
                for parameter in node.parameters:
                    name = f"parameter {parameter.name}"
                    effects.aspects[name] = Aspect(name, parameter.value, location_of(parameter))
                for interface in node.interfaces:
                    kind = interface_kinds.kind_of(interface)
                    if kind.on_topic:
                        name = f"topic of {interface.name}"
                        topic = kind.bound_to(interface)
                        bound = topic_ros_name(topic) if topic else None
                        effects.aspects[name] = Aspect(name, bound, location_of(interface))
                    elif kind.calls:
                        server = real_server(kind.bound_to(interface), line.tsm)
                        effects.servers[interface.name] = Aspect(
                            f"server of {interface.name}", server, location_of(interface)
                        )
                self.nodes[effects.key] = effects
                self.by_node[id(node)] = effects
        self._system, self._elements = line.tsm, list(line.rm.elements)
        for element in line.rm.elements:
            self._add(element)

    def _add(self, element: rm_types.ResolutionElement) -> None:
        for touched in dict.fromkeys(touched_elements(element)):
            if id(touched) in self.by_node:
                self.by_node[id(touched)].keepers.append(element)
        for t in element.transformations:
            kind_of(t).predict(t, element, self)
        sharing = element.feature.sharing
        if sharing is not None:
            feature, default = element.feature.name, sharing.mode.name

            def mode(settings: Settings, feature: str = feature, default: str = default) -> str:
                return dict(settings.sharing).get(feature, default)

            for node in dict.fromkeys(sharing_targets(element)):  # a store: no node's
                self.effect(
                    cast("tsm_types.Node", node), SHARING, element, mode, location_of(element)
                )

    # -- what a statement does (TransformationKind.predict) ----------------------------
    def topic_value(self, connect: rm_types.ConnectToTopic | rm_types.ConnectToNewTopic) -> str:
        """The ROS name a connect statement binds its interface to. A `to topic` names the
        topic by (container, name) and is looked up when it runs (docs/semantics.md); the
        prediction reads it in the named container, else the node's own, else any topic of
        that name the template or an earlier `new topic` declares."""
        ref = connect.topic
        if ref.eClass.name != "TopicReference":  # a `new topic` holds the topic itself
            return topic_ros_name(cast("tsm_types.Topic", ref))
        ref = cast("rm_types.TopicReference", ref)
        home = ref.container or connect.interface.eContainer().eContainer()
        topics = [*home.topics, *(t for c in self._system.containers for t in c.topics)]
        created = (
            topic
            for e in self._elements
            for t in e.transformations
            if (topic := kind_of(t).created_topic(t)) is not None
        )
        for topic in [*topics, *created]:
            if topic.name == ref.name:
                return topic_ros_name(topic)
        return f"/{ref.name}"

    def effect(
        self,
        node: tsm_types.Node,
        aspect: str,
        element: rm_types.ResolutionElement,
        value: EffectValue,
        where: Location | None,
    ) -> None:
        """``element``, when active, sets ``aspect`` of ``node`` to ``value``."""
        effects = self.by_node.get(id(node))
        if effects is not None and aspect in effects.aspects:
            effects.aspects[aspect].effects.append(Effect(element, value, where))

    def server(
        self,
        client: tsm_types.ServiceClient,
        element: rm_types.ResolutionElement,
        server: tsm_types.ServiceServer,
        where: Location | None,
    ) -> None:
        """``element``, when active, binds ``client`` to ``server``."""
        node = self.by_node.get(id(client.eContainer()))
        if node is not None:
            node.servers[client.name].effects.append(Effect(element, server, where))

    # -- prediction ------------------------------------------------------------------
    def server_value(
        self, node: NodeEffects, client: str, active: Active, settings: Settings
    ) -> tuple[str, str] | None:
        """What the client calls: (server, where its node runs), or None."""
        server = cast(
            "tsm_types.ServiceServer | None", node.servers[client].value(active, settings)
        )
        if server is None:
            return None
        server_node = self.by_node.get(id(server.eContainer()))
        if server_node is None or not server_node.present(active):
            return None
        placement = cast("str", server_node.aspects[PLACEMENT].value(active, settings))
        return (server_id(server_node.origin, server_node.name, server.name), placement)

    def predict(self, node: NodeEffects, active: Active, settings: Settings) -> dict[str, Value]:
        """Every aspect of a present node in the product where ``active`` holds."""
        values = {name: aspect.value(active, settings) for name, aspect in node.aspects.items()}
        for client in node.servers:
            values[f"server of {client}"] = self.server_value(node, client, active, settings)
        return values


def server_id(container: str, node: str, server: str) -> str:
    return f"{container}.{node}.{server}"


def active_in(features: set[str] | frozenset[str]) -> Active:
    """The activation rule of the engine (docs/resolution.md, step 3) for a completed
    selection."""
    return lambda element: (element.feature.name in features) == element.activeIfSelected


def observed(node: tsm_types.Node, product: ResolvedProduct) -> dict[str, Value]:
    """The aspects of a node of a resolved product, in the values :class:`LineEffects`
    predicts (so predictions and resolutions compare)."""
    container = node.eContainer()
    values: dict[str, Value] = {
        PLACEMENT: container.name,
        SHARING: sharing_mode(node),
        "implementation": f"{node.package}/{node.executable}" if node.package else None,
        "args": node.args,
    }
    for parameter in node.parameters:
        values[f"parameter {parameter.name}"] = parameter.value
    for interface in node.interfaces:
        kind = interface_kinds.kind_of(interface)
        if kind.on_topic:
            topic = kind.bound_to(interface)
            values[f"topic of {interface.name}"] = topic_ros_name(topic) if topic else None
        elif kind.calls:
            server = real_server(kind.bound_to(interface), product.system)
            if server is None:
                values[f"server of {interface.name}"] = None
                continue
            server_node = cast("tsm_types.Node", server.eContainer())  # a node's server
            here = server_node.eContainer().name
            migration = product.migrated(server_node.name)
            origin = migration.source if migration is not None else here
            values[f"server of {interface.name}"] = (
                server_id(origin, server_node.name, server.name),
                here,
            )
    return values


def origin_of(node: tsm_types.Node, product: ResolvedProduct) -> str:
    """The template container of a node of a resolved product (before any migration)."""
    migration = product.migrated(node.name)
    return migration.source if migration is not None else node.eContainer().name


def real_server(
    server: tsm_types.ServiceServer | None, system: tsm_types.System
) -> tsm_types.ServiceServer | None:
    """The node's ServiceServer behind any chain of endpoint stand-ins (None: unserved)."""
    T = tsm()
    seen: set[int] = set()
    while server is not None and not isinstance(server.eContainer(), T.Node):
        if id(server) in seen:
            return None
        seen.add(id(server))
        caller = next(
            (
                c.target
                for c in system.connections
                if c.source is server and interface_kinds.kind_of(c.target).calls
            ),
            None,
        )
        server = cast("tsm_types.ServiceClient", caller).server if caller is not None else None
    return server
