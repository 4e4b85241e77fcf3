"""SPL045 and SPL046 before any product is chosen: every input that some product of the
line leaves unfed, with a witness product (docs/semantics.md F8).

An *input* is a node subscriber or a node service client. ``spl resolve`` warns when
the flow table of the product it derives (:mod:`spl.resolver.architecture.flows`) delivers nothing
to one (SPL045 for a subscriber, SPL046 for a client). This check asks the same for
every product at once, with one SAT question per input: a product that keeps the
input's node and in which none of the ways it may be fed holds. A way is a template
flow while the node at its other end is kept (:class:`.presence.Presence`) and no
active statement rebinds either end (``TransformationKind.rebinds``); or a statement
putting a publisher where its data reaches the input's topic, binding the input to a
topic such a publisher feeds, or binding a client to a server, while its element is
active. A migration breaks no template flow: the endpoint rewiring keeps them
(docs/resolution.md; the rows it cannot keep it warns about itself, SPL031 and SPL032).
Each way feeds the input wherever it holds, so an input for which the question has no
answer is fed in every product, and needs no resolution.

A product the solver finds is resolved, and the input is reported as that product's
resolution warns about it, naming the product and what removed the feeders. A
candidate the resolution feeds after all (a way the check does not count) is ruled out,
with every product activating the same resolution elements (they derive the same
architecture), and the solver is asked again, up to :data:`RETRIES` times. An input the
.tsm declares fed from outside the architecture (``external "why"``, docs/tsm.md) is
neither asked about nor warned.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

from spl.core.diagnostics import Diagnostic, Location, location_of
from spl.dsl.rm.names import Names, Placement
from spl.metamodels import interface_kinds
from spl.resolver.architecture.checks import awaits_feed
from spl.resolver.architecture.flows import FlowTable, bound_topic, node_of
from spl.resolver.line_checks.activation import ActivationSolver
from spl.resolver.line_checks.presence import Clauses, Presence
from spl.resolver.line_checks.witnesses import Witness, witness_warnings
from spl.resolver.resolution.context import describe, qualified
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.transformations import kind_of
from spl.resolver.resolution.transformations.kind import Binding

if TYPE_CHECKING:
    from spl.dsl.workspace import Workspace
    from spl.metamodels import rm_types, tsm_types

# products ruled out per input before the check stops asking about it: each costs one
# resolution, and a line needs many only when statements feed an input in most products
RETRIES = 16

Key = tuple[int, str]  # a topic as a statement names it: (id of its container, name)


class _Option(NamedTuple):
    """One way an input may be fed: in a product where every element of ``active`` is
    active, none of ``inactive`` is, and ``feeder``'s node is kept."""

    feeder: tsm_types.Interface
    active: tuple[rm_types.ResolutionElement, ...]
    inactive: tuple[rm_types.ResolutionElement, ...]


_Place = tuple[str | None, Location | None]  # a warning's code and place


class Feeds:
    """What the questions about every input share: the solver, presence clauses, the
    statements rebinding each interface, the publishers statements put on each topic,
    and the warnings of the products resolved."""

    def __init__(
        self, line: ProductLine, solver: ActivationSolver, workspace: Workspace | None = None
    ) -> None:
        self.line, self.solver, self.workspace = line, solver, workspace
        self.root = line.fm.root.name
        self.presence = Presence(line, solver)
        # interface -> (element, binding, the topic it binds to when certain)
        self.rebinding: dict[int, list[tuple[rm_types.ResolutionElement, Binding, Key | None]]]
        self.rebinding = {}
        names = Names(line.tsm)  # where each statement's node is (docs/semantics.md C1)
        for element in line.rm.elements:
            names.begin_element(element)
            for t in element.transformations:
                for binding in kind_of(t).rebinds(t):
                    key = _key(binding, names.placement(node_of(binding.interface)))
                    self.rebinding.setdefault(id(binding.interface), []).append(
                        (element, binding, key)
                    )
                names.apply(t)
        # the topics data put on each topic reaches, by the template's bridges
        reached = line.template_reach
        topics = {(id(c), t.name): t for c in line.tsm.containers for t in c.topics}

        def onward(key: Key) -> list[Key]:
            topic = topics.get(key)
            if topic is None:  # a topic a statement creates: no bridge leaves it
                return [key]
            return [(id(t.eContainer()), t.name) for t in reached[id(topic)]]

        # the publishers feeding each topic: the template's, and those statements bind
        self.publishing: dict[Key, list[_Option]] = {}
        for container in line.tsm.containers:
            for node in container.nodes:
                for interface in node.interfaces:
                    if not interface_kinds.kind_of(interface).publishes:
                        continue
                    topic = bound_topic(interface)
                    if topic is not None:
                        option = _Option(interface, (), tuple(self.rebinders(interface)))
                        for there in onward((id(container), topic.name)):
                            self.publishing.setdefault(there, []).append(option)
                    for element, _, key in self.rebinding.get(id(interface), ()):
                        if key is None:
                            continue
                        # data put on another container's topic goes no further: the
                        # rewiring bridges it to its subscribers there, and a robot
                        # relays no data but its own (docs/semantics.md F3)
                        local = key[0] == id(container)
                        for there in onward(key) if local else [key]:
                            option = _Option(interface, (element,), ())
                            self.publishing.setdefault(there, []).append(option)
        # a statement's bridge carries what reaches its source on to its target
        robots = {id(c) for c in line.tsm.containers if c.eClass.name == "RobotContainer"}
        for element in line.rm.elements:
            for t in element.transformations:
                for source, target in kind_of(t).routes(t):
                    if source.container is None or target.container is None:
                        continue
                    start = (id(source.container), source.name)
                    end = (id(target.container), target.name)
                    carried = [
                        _Option(o.feeder, (*o.active, element), o.inactive)
                        for o in self.publishing.get(start, ())
                    ]
                    # a robot passes on no data but its own (docs/semantics.md F3)
                    for there in [end] if end[0] in robots else onward(end):
                        self.publishing.setdefault(there, []).extend(carried)
        # the feature variables of the elements: products alike on them derive alike
        self.variables = sorted({abs(solver.literal(e)) for e in line.rm.elements})
        # each witness's warnings by code and place: a line with many unfed inputs asks
        # one product about each of them
        self.resolved: dict[Witness, dict[_Place, Diagnostic]] = {}
        # the witness products of a line share most of their warnings (on a 10,000-node
        # line some 5,000 each, and hundreds of products): each is kept once
        self.known: dict[Diagnostic, tuple[_Place, Diagnostic]] = {}

    def rebinders(self, interface: tsm_types.Interface) -> list[rm_types.ResolutionElement]:
        return [element for element, _, _ in self.rebinding.get(id(interface), ())]

    def warning(self, witness: Witness, code: str, where: Location | None) -> Diagnostic | None:
        """The warning ``code`` at ``where`` of the product ``witness`` (none when the
        product fails for other reasons, which resolve, validate and the other checks
        report)."""
        if witness not in self.resolved:
            found = self.resolved[witness] = {}
            for warning in witness_warnings(self.line, witness, self.workspace):
                place, kept = self.known.setdefault(
                    warning, ((warning.code, warning.location), warning)
                )
                found.setdefault(place, kept)
        return self.resolved[witness].get((code, where))

    def ruled_out(self, witness: Witness) -> list[int]:
        """A clause excluding every product that activates the resolution elements
        ``witness`` activates."""
        selected = set(witness)
        names = self.solver.cnf.names
        return [-v if names[v - 1] in selected else v for v in self.variables]


def _key(binding: Binding, placement: Placement) -> Key | None:
    """The topic a statement binds its interface to, when it is certain: the container
    is named, or the node is certainly in one when the statement runs (a migration
    earlier in its element, or none in any element before); None otherwise, and the
    binding is not counted on to feed anything."""
    if binding.topic is None:
        return None
    container = binding.container or placement.certain
    if container is None and not placement.moves:
        container = placement.node.eContainer()
    return None if container is None else (id(container), binding.topic)


def unfed_inputs_in_line(
    line: ProductLine, solver: ActivationSolver, workspace: Workspace | None = None
) -> list[Diagnostic]:
    """The inputs some product of the line leaves unfed, each with its witness product
    (resolved again in the editor's ``workspace`` only when what it reads changed)."""
    shared = Feeds(line, solver, workspace)
    template = line.template_flows
    found: list[Diagnostic] = []
    for container in line.tsm.containers:
        for node in container.nodes:
            for interface in node.interfaces:
                code = interface_kinds.kind_of(interface).unfed_code
                if interface.external or code is None:
                    continue  # fed from outside, or an output
                if not awaits_feed(interface) and not shared.rebinders(interface):
                    continue  # bound to no topic in any product: nothing to feed
                clauses = _unfed(shared, _options(shared, template, interface), interface)
                if clauses is not None:
                    found += _confirmed(shared, template, interface, clauses, code)
    return found


def _options(shared: Feeds, template: FlowTable, interface: tsm_types.Interface) -> list[_Option]:
    """The ways ``interface`` may be fed, each certain to feed it where it holds: a
    template flow while neither end is rebound, a publisher a statement binds to the
    input's topic, the publishers on the topic or the server a statement binds the input
    to."""
    own = tuple(shared.rebinders(interface))
    options = []
    for flow in template.feeding(interface):
        feeder = flow.provider
        options.append(_Option(feeder, (), own + tuple(shared.rebinders(feeder))))
    topic = bound_topic(interface)
    if topic is not None:  # statements putting a publisher where the topic gets data
        home = (id(topic.eContainer()), topic.name)
        for option in shared.publishing.get(home, ()):
            if option.active:
                options.append(_Option(option.feeder, option.active, own))
    for element, binding, key in shared.rebinding.get(id(interface), ()):
        if binding.server is not None:
            options.append(_Option(binding.server, (element,), ()))
        elif key is not None:
            for option in shared.publishing.get(key, ()):
                active = (element, *option.active)
                options.append(_Option(option.feeder, active, option.inactive))
    return options


def _unfed(shared: Feeds, options: list[_Option], interface: tsm_types.Interface) -> Clauses | None:
    """Clauses of a product keeping ``interface``'s node (bound, for a subscriber) in
    which none of ``options`` holds; None when every such product feeds it."""
    solver = shared.solver
    clauses = shared.presence.present(node_of(interface))
    if clauses is None:
        return None  # in no product
    if not awaits_feed(interface):  # a subscriber only statements bind
        clauses = [*clauses, [solver.literal(e) for e in shared.rebinders(interface)]]
    for option in options:
        broken = [-solver.literal(e) for e in option.active]
        broken += [solver.literal(e) for e in option.inactive]
        absent = shared.presence.absent(node_of(option.feeder))
        if absent is not None:
            gone = solver.fresh()  # implies the feeder's node is left out
            clauses = clauses + [[-gone, *clause] for clause in absent]
            broken.append(gone)
        if not broken:
            return None  # this option holds wherever the input is
        clauses = [*clauses, broken]
    return clauses


def _confirmed(
    shared: Feeds,
    template: FlowTable,
    interface: tsm_types.Interface,
    clauses: Clauses,
    code: str,
) -> list[Diagnostic]:
    """The warning of the first product the solver finds in which the resolution leaves
    ``interface`` unfed, naming the product and why; none when no product does. The
    product is made subset-minimal first (:func:`_smallest`), and is the solver's own
    where the smaller one's resolution feeds the input after all."""
    where = location_of(interface)
    for _ in range(RETRIES):
        found = shared.solver.witness_where(None, clauses)
        if found is None:
            return []
        for witness in dict.fromkeys((_smallest(shared, clauses, found), found)):
            warning = shared.warning(witness, code, where)
            if warning is not None:
                message = f"{warning.message}, in the product {', '.join(witness)}"
                why = _why(shared, template, interface, set(witness))
                if why:
                    message += f"; {why}"
                return [Diagnostic(where, message, warning.severity, code)]
            clauses = [*clauses, shared.ruled_out(witness)]
    return []


def _smallest(shared: Feeds, clauses: Clauses, witness: Witness) -> Witness:
    """``witness`` with every feature left out that can be, one at a time, while the
    feature model and ``clauses`` still hold and no feature left out comes back: a
    product none of whose features can be dropped (not always the one with fewest)."""
    cnf = shared.solver.cnf
    features = cnf.names[: cnf.num_features]
    selected = set(witness)
    for name in witness:
        if name not in selected or name == shared.root:
            continue  # left out with an earlier one; the root is in every product
        kept_out = [-cnf.var[f] for f in features if f not in selected or f == name]
        smaller = shared.solver.witness_where(None, clauses, kept_out)
        if smaller is not None:
            selected = set(smaller)
    return tuple(sorted(selected))


def _why(
    shared: Feeds, template: FlowTable, interface: tsm_types.Interface, selected: set[str]
) -> str:
    """What keeps the template's feeders of ``interface`` from it in the product
    ``selected``: the resolution elements that would keep a feeder's node and are not
    active, or the active statements that rebind an end."""

    def active(element: rm_types.ResolutionElement) -> bool:
        return (element.feature.name in selected) == element.activeIfSelected

    reasons: list[str] = []
    moving = [e for e in shared.rebinders(interface) if active(e)]
    if moving:
        reasons.append(f"{qualified(interface)} is rebound by {describe(moving[0])}")
    for flow in template.feeding(interface):
        feeder = flow.provider
        node = node_of(feeder)
        role = flow.kind.provider_role
        keepers = shared.presence.keepers(node)
        if node.optional and not any(active(e) for e in keepers):
            kept_by = ", ".join(describe(e) for e in keepers) or "no resolution element"
            reasons.append(
                f"its {role} {qualified(feeder)} is left out: optional node {node.name} is "
                f"kept only by {kept_by}"
            )
        elif any(active(e) for e in shared.rebinders(feeder)):
            element = next(e for e in shared.rebinders(feeder) if active(e))
            reasons.append(f"its {role} {qualified(feeder)} is rebound by {describe(element)}")
    return "; ".join(dict.fromkeys(reasons))
