"""What ``spl explain`` says about one name in one product: the elements it names, in the
template and in the product, how each stands in the product and the trace entries about it.

A name is what the trace and the .rm use (``qualified``): a container or a node by its
name, a topic or a store as ``Container.Topic``, a parameter or an interface as
``Node.name``, an endpoint interface as ``Container.endpoint.name``. A user also writes
a topic or a store by its bare name (every container's one of that name is meant) and a
node, its parameters and interfaces prefixed with the container (``Robot.Planner.plan``):
both are accepted. A bare interface or parameter name is not (it is ambiguous across
nodes); the refusal lists the qualified names it could mean.

Besides the trace, an interface is explained by the product's flow table (who feeds a
subscriber, who answers a client, what an endpoint interface carries: the facts every
output follows) and a cloud node by the instances its sharing mode gives it: for a
private node, each robot's instance with the flow chain that keeps it, or why the robot
gets none (:mod:`spl.resolver.resolution.instance_explanation`, which also explains an instance
named by its tag).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

from spl.core.diagnostics import location_of
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import is_interface, kind_of
from spl.resolver.architecture.checks import awaits_feed
from spl.resolver.architecture.flows import node_of
from spl.resolver.architecture.product import ResolvedProduct, topic_ros_name
from spl.resolver.resolution.context import qualified
from spl.resolver.resolution.instance_explanation import node_instances
from spl.resolver.resolution.trace import Trace, TraceEntry

if TYPE_CHECKING:
    from spl.metamodels import tsm_types
    from spl.metamodels.model_types import EObject


@dataclass(frozen=True)
class NamedElement:
    """One element of a system with the names a user may ask about it by."""

    name: str  # qualified, as in the trace
    element: tsm_types.NamedElement
    aliases: tuple[str, ...]  # bare topic/store name, Container.-prefixed node names


def named_elements(system: tsm_types.System) -> Iterator[NamedElement]:
    """Every container, topic, store, node, parameter and interface of ``system``."""
    for container in system.containers:
        prefix = f"{container.name}."
        yield NamedElement(container.name, container, ())
        for element in [*container.topics, *container.stores]:
            yield NamedElement(qualified(element), element, (element.name,))
        for node in container.nodes:
            yield NamedElement(node.name, node, (prefix + node.name,))
            for element in [*node.parameters, *node.interfaces]:
                name = qualified(element)
                yield NamedElement(name, element, (prefix + name,))
        for interface in container.endpoint.interfaces:
            yield NamedElement(qualified(interface), interface, ())


# Decisions about a node or container that say where its parts are, or that they are gone.
MOVED_OR_GONE = frozenset({"migrated", "removed"})


def explanation(
    template: tsm_types.System,
    resolved: ResolvedProduct,
    trace: Trace,
    name: str,
    robot: str | None = None,
) -> list[str] | None:
    """The lines explaining the elements ``name`` means, product's first, then those only
    the template has; None when neither model has an element of that name. Each element
    gets how it stands in the product, the trace entries about it (and its parts), then
    those about the node or container holding it (a node's migration moved its
    interfaces too; a container's removal removed its topics), then its flows or its
    instances (``robot``: a private node's for that robotID alone)."""
    T = tsm()
    product = resolved.system
    in_product = list(named_elements(product))
    in_template = [e for e in named_elements(template) if _means(name, e)]
    meant = [e.name for e in in_product if _means(name, e)] + [e.name for e in in_template]
    if not meant:
        return None
    lines: list[str] = []
    for element_name in dict.fromkeys(meant):  # a node by its old container: where it is now
        present = [e.element for e in in_product if e.name == element_name]
        written = next((e.element for e in in_template if e.name == element_name), None)
        meant_element = present[0] if present else cast("tsm_types.NamedElement", written)
        owners = {qualified(o) for o in _holders(meant_element)}
        own = [e for e in trace.entries if _is_about(e.subject, element_name)]
        own += [e for element in present for e in _bridging(element, product, trace)]
        held = [e for e in trace.entries if e.subject in owners and e.decision in MOVED_OR_GONE]
        lines += [f"{element_name}: {_standing(element)}" for element in present]
        if not present:
            lines.append(f"{element_name}: not in this product")
        lines += [f"  {entry}" for entry in own + held]
        if present and not own + held and written is not None:
            where = location_of(written)
            lines.append(
                "  nothing in this product decided about it: as the template writes it"
                + (f" ({where})" if where else "")
            )
        for element in present:
            lines += [f"  {line}" for line in _flows(element, resolved, trace)]
            if isinstance(element, T.Node) and isinstance(element.eContainer(), T.CloudContainer):
                lines += [f"  {line}" for line in node_instances(element, resolved, robot)]
    return lines


def _bridging(
    element: tsm_types.NamedElement, system: tsm_types.System, trace: Trace
) -> list[TraceEntry]:
    """For an endpoint interface, the trace entries of the bridges it belongs to: the
    rewiring records a topic bridge under its source topic, a service bridge under the
    client it serves."""
    if not is_interface(element) or not isinstance(element.eContainer(), tsm().Endpoint):
        return []
    subjects = set()
    for connection in system.connections:
        if element not in (connection.source, connection.target):
            continue
        source = connection.source
        kind = kind_of(source)
        bound = kind.bound_to(source)
        if kind.subscribes and bound is not None:
            subjects.add(qualified(bound))
        elif kind.serves:
            subjects |= {
                qualified(i)
                for c in system.containers
                for n in c.nodes
                for i in n.interfaces
                if kind_of(i).calls and kind_of(i).bound_to(i) is source
            }
    return [e for e in trace.entries if e.subject in subjects and e.decision == "bridged"]


def _flows(element: tsm_types.NamedElement, product: ResolvedProduct, trace: Trace) -> list[str]:
    """The flows at an interface, or carried by an endpoint interface, in words."""
    if not is_interface(element):
        return []
    interface = cast("tsm_types.Interface", element)
    flows = product.flows
    if isinstance(element.eContainer(), tsm().Endpoint):
        carried = [
            flow
            for connection in product.system.connections
            if element in (connection.source, connection.target)
            for flow in flows.through(connection)
        ]
        return [f"carries {flow.describe()}" for flow in dict.fromkeys(carried)]
    lines = []
    for flow in flows.at(interface):
        mine = element is flow.source
        other: tsm_types.Interface = flow.target if mine else flow.source
        if flow.route:
            where = "through " + " -> ".join(c.name for c in flow.hops())
        else:
            where = f"in {flow.source_container.name}"
        twice = " (by two routes: each message arrives twice)" if flow.routes > 1 else ""
        moved = next(
            (e for e in trace.entries if e.subject == node_of(other).name
             and e.decision == "migrated"),
            None,
        )  # fmt: skip
        note = f"; {moved}" if moved is not None else ""
        # what the flow is, said at its start or at its end (Family.flow_verbs)
        verb = flow.kind.flow_verbs[0 if mine else 1]
        lines.append(f"{verb} {_end(other)} {where}{twice}{note}")
    kind = kind_of(interface)
    if not lines and awaits_feed(interface):
        code = "" if interface.external else f" ({kind.unfed_code})"
        lines.append(f"{kind.unfed_words}{code}")
    if interface.external:  # why no product warns about it (docs/tsm.md)
        lines.append(f"fed from outside the architecture: {interface.external}")
    return lines


def _end(interface: tsm_types.Interface) -> str:
    """A node interface as ``Container.Node.interface``."""
    node = node_of(interface)
    return f"{node.eContainer().name}.{node.name}.{interface.name}"


def qualified_candidates(
    template: tsm_types.System, product: tsm_types.System, name: str
) -> list[str]:
    """The qualified names of the interfaces and parameters whose own name is ``name``."""
    T = tsm()
    return sorted(
        {
            e.name
            for system in (template, product)
            for e in named_elements(system)
            if (is_interface(e.element) or isinstance(e.element, T.Parameter))
            and e.element.name == name
        }
    )


def _means(name: str, element: NamedElement) -> bool:
    return name == element.name or name in element.aliases


def _is_about(subject: str, name: str) -> bool:
    return subject == name or subject.startswith(f"{name}.")


def _holders(element: tsm_types.NamedElement) -> list[tsm_types.NamedElement]:
    """The node and container holding ``element`` (an endpoint's, its container)."""
    T = tsm()
    holders: list[tsm_types.NamedElement] = []
    owner: EObject | None = element.eContainer()
    while owner is not None and not isinstance(owner, T.System):
        if not isinstance(owner, T.Endpoint):
            holders.append(cast("tsm_types.NamedElement", owner))  # a node or a container
        owner = owner.eContainer()
    return holders


def _standing(element: tsm_types.NamedElement) -> str:
    """How an element present in the product stands there, in one phrase."""
    T = tsm()
    owner = cast("tsm_types.NamedElement", element.eContainer())  # in a system
    if isinstance(element, T.Container):
        return f"{'robot' if isinstance(element, T.RobotContainer) else 'cloud'} container present"
    if isinstance(element, T.Node):
        return f"present in container {owner.name}"
    if isinstance(element, T.Topic):
        return f"topic present, {topic_ros_name(element)} ({element.type})"
    if isinstance(element, T.Store):
        return f"store present in container {owner.name}"
    if isinstance(element, T.Parameter):
        return f"parameter = {element.value}" if element.value is not None else "parameter unset"
    interface = cast("tsm_types.Interface", element)  # the last elements named
    kind = kind_of(interface)
    if kind.binds is None:  # a server: called by its ROS name
        server = cast("tsm_types.ServiceServer", interface)
        return f"{kind.standing} {server.rosName or '/' + server.name} ({server.type})"
    return _bound(kind.standing, kind.bound_to(interface))


def _bound(verb: str, target: tsm_types.NamedElement | None) -> str:
    if target is None:
        return f"{verb.split()[0]} nothing: not connected in this product"
    return f"{verb} {qualified(target)}"
