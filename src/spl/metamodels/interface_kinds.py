"""The kinds of interface a .tsm node has, each declared once (docs/architecture.md,
"Interface kinds").

A node publishes and subscribes topics, provides and calls services and actions. Every
part of spl asks the same few questions about an interface: what it binds to (a topic of its
container, or the server it calls), which side of its family it is (the side data or
answers come from, or the side that takes them and may be left unfed), how the .tsm
writes it, and how each output target names its role. They are answered here, by the
interface's kind (:func:`kind_of`), and nowhere else: a module that reads an interface
asks its kind, never its class, so a new kind is a new entry in :data:`KINDS` plus what
only it does (its grammar rule, and its ROS names where they differ).

A kind belongs to a :class:`Family`, the way its two sides meet: on a topic, many to
many (publishers and subscribers bound to the same topic of a container), or by call,
a consumer bound to the one provider it calls (service clients to servers, action
clients to action servers). The family says what a flow between the two sides is
(docs/semantics.md, F1 and F2): a topic flow runs from publisher to subscriber, a call
(a service request, an action goal) from client to server.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from spl.metamodels import tsm_types


@dataclass(frozen=True, order=True)
class Answers:
    """How `spl smoke` says a family's calls and what comes back (docs/smoke.md): one call
    a server counts, what a client expects back, one answer it saw, and what else its
    server sends back that must reach it too (an action's feedback)."""

    call: str = "call"
    expected: str = "answer"
    answered: str = "answered by"
    back: str | None = None


@dataclass(frozen=True, order=True)
class Family:
    """How the two sides of a ROS interface meet, and what a flow between them is."""

    name: str  # as messages and flow tables name it: "topic", "service", "action"
    on_topic: bool  # both sides bind to a topic (many to many); else a consumer calls one provider
    # what a flow is, said at the interface where it starts, and where it ends
    flow_verbs: tuple[str, str]
    # the zenoh-bridge-ros2dds allow list where the flow starts, and where it ends
    zenoh_lists: tuple[str, str]
    # what an input's unfed warning calls the providing end of a flow it lost (`spl check`)
    provider_role: str
    # the ROS 1 topics one interface of this family is, under its name, each remapped with
    # it and carried by a bridge (actionlib's five); () where it is its name alone
    ros1_topics: tuple[PartTopic, ...] = ()
    # whether the diagram's legend shows this family's kinds on every diagram (topics and
    # services, as it always has), or only on one holding an interface of the family
    in_every_legend: bool = False
    # endings of the message types ROS generates from an interface's type, refused as its
    # type (an action's type is its .action file, move_base_msgs/MoveBase, never the
    # move_base_msgs/MoveBaseAction message actionlib generates from it)
    generated_types: tuple[str, ...] = ()
    # whether `spl smoke` plays its kinds with actionlib, and so leaves them out, with a
    # warning, where actionlib is not installed (docs/smoke.md, "Actions")
    needs_actionlib: bool = False
    answers: Answers = Answers()

    @property
    def flows_from_provider(self) -> bool:
        """Whether a flow starts at the providing side (a topic's publisher) or at the
        consumer (a service's client, which sends the request)."""
        return self.on_topic

    def __str__(self) -> str:
        return self.name


TOPIC = Family(
    "topic",
    True,
    ("delivers to", "fed by"),
    ("publishers", "subscribers"),
    "feeder",
    in_every_legend=True,
)
SERVICE = Family(
    "service",
    False,
    ("answered by", "called by"),
    ("service_clients", "service_servers"),
    "server",
    in_every_legend=True,
)


@dataclass(frozen=True, order=True)
class PartTopic:
    """One of the ROS 1 topics an interface of a family is made of, under its name
    (actionlib's goal, cancel, status, feedback and result, docs/deployment.md "Actions")."""

    suffix: str  # the topic is NAME/suffix
    from_consumer: bool  # sent by the consumer (a client's goals), else back from the provider
    message: str  # its message type, "{type}" standing for the interface's type
    # what the part is in ROS 1, and so what a bridge carries it as: a topic, as each of
    # actionlib's five (a family whose parts include a service, dynamic_reconfigure's
    # set_parameters, says so here and is bridged without an edit of the bridges)
    carrier: Family = TOPIC

    def message_of(self, interface_type: str) -> str:
        return self.message.format(type=interface_type)


ACTION = Family(
    "action",
    False,
    ("sends goals to", "takes goals from"),
    ("action_clients", "action_servers"),
    "action server",
    (
        PartTopic("goal", True, "{type}ActionGoal"),
        PartTopic("cancel", True, "actionlib_msgs/GoalID"),
        PartTopic("status", False, "actionlib_msgs/GoalStatusArray"),
        PartTopic("feedback", False, "{type}ActionFeedback"),
        PartTopic("result", False, "{type}ActionResult"),
    ),
    generated_types=("Action", "ActionGoal", "ActionResult", "ActionFeedback"),
    needs_actionlib=True,
    answers=Answers("goal", "result and feedback", "result from", "feedback"),
)


@dataclass(frozen=True)
class InterfaceKind:
    """One kind of interface: which side of which family, and how every part names it."""

    eclass: str  # its class in tsm.ecore
    rule: str  # its statement's rule in tsm.tx
    keyword: str  # the .tsm keyword of the statement
    family: Family
    provides: bool  # the side data or answers come from (a publisher, a server)
    title: str  # as a reader is told: "topic publisher", "service client"
    # the Rapyuta interface type (iType) of a bridge's end of this kind; None for a kind
    # a bridge carries as its family's ros1_topics (an action, as five topics)
    rapyuta_role: str | None
    # what the rehearsal's stand-in plays; None: `spl smoke` has no stand-in for it yet
    smoke_role: str | None
    colour: str  # the architecture diagram's colour
    # the first word of the name of a bridge's endpoint interface of this kind
    # (``srv_Planner_plan``, docs/tsm.md "Bridges"): one of its own for each kind, so
    # that the endpoint interfaces for a service and an action of one name (servers
    # ``Db.get`` of two containers) are never one name in one endpoint
    endpoint_prefix: str
    # an input's warning when a product leaves it unfed, and how `spl explain` says it
    unfed_code: str | None = None
    unfed_words: str | None = None
    # how `spl explain` says what an interface of this kind does, before what it is
    # bound to (or, for a kind bound to nothing, the ROS name it answers under)
    standing: str = ""
    # the rehearsal's one word for an input of this kind that a product leaves unfed
    # ("unfed in the model (SPL045)", docs/smoke.md); None where unfed_code is
    gap_word: str | None = None

    @cached_property
    def on_topic(self) -> bool:
        return self.family.on_topic

    @property
    def a_title(self) -> str:
        """The title with its article, as messages say it: "an action server"."""
        return with_article(self.title)

    @property
    def a_class(self) -> str:
        """The class with its article, as messages say it: "an ActionServer"."""
        return with_article(self.eclass)

    @cached_property
    def publishes(self) -> bool:
        """Puts data on a topic."""
        return self.family.on_topic and self.provides

    @cached_property
    def subscribes(self) -> bool:
        """Takes data from a topic."""
        return self.family.on_topic and not self.provides

    @cached_property
    def serves(self) -> bool:
        """Answers the calls of the consumers bound to it."""
        return not self.family.on_topic and self.provides

    @cached_property
    def calls(self) -> bool:
        """Calls the one provider it is bound to."""
        return not self.family.on_topic and not self.provides

    @cached_property
    def binds(self) -> str | None:
        """The feature of the interface naming what it is bound to: "topic", "server",
        or None (a server is bound to nothing: its clients are bound to it)."""
        if self.family.on_topic:
            return "topic"
        return None if self.provides else "server"

    @property
    def zenoh_list(self) -> str:
        """The zenoh-bridge-ros2dds allow list that names an interface of this kind."""
        first, last = self.family.zenoh_lists
        return first if self.provides == self.family.flows_from_provider else last

    @property
    def arrow(self) -> str | None:
        """The .tsm arrow before what an interface of this kind is bound to, pointing the
        way its flow runs (the statements of docs/tsm.md, the editor's hover): "->" where
        the flow starts (a publisher to its topic, a client to its server), "<-" where it
        ends (a subscriber from its topic); None for a kind bound to nothing."""
        if self.binds is None:
            return None
        return "->" if self.provides == self.family.flows_from_provider else "<-"

    def bound_to(self, interface: tsm_types.Interface) -> Any:
        """The topic or server ``interface`` (of this kind) is bound to, or None."""
        return getattr(interface, self.binds) if self.binds is not None else None


def with_article(words: str) -> str:
    return f"{'an' if words[0].lower() in 'aeiou' else 'a'} {words}"


def calling_titles() -> str:
    """What may call a server, as a message says it: "service client or action client"."""
    return " or ".join(k.title for k in KINDS if k.calls)


KINDS = (
    InterfaceKind(
        "Publisher", "Publishes", "publishes", TOPIC, True, "topic publisher",
        "Publisher", "publisher", "#ffe135", "pub",
        standing="publishes to topic",
    ),
    InterfaceKind(
        "Subscriber", "Subscribes", "subscribes", TOPIC, False, "topic subscriber",
        "Subscriber", "subscriber", "#3fe0f0", "sub", "SPL045", "fed by no flow of this product",
        standing="subscribes to topic", gap_word="unfed",
    ),
    InterfaceKind(
        "ServiceServer", "Provides", "provides", SERVICE, True, "service server",
        "ServiceProvider", "server", "#2ca02c", "srv",
        standing="serves",
    ),
    InterfaceKind(
        "ServiceClient", "Calls", "calls", SERVICE, False, "service client",
        "ServiceClient", "client", "#e03131", "cli",
        "SPL046", "answered by no server of this product",
        standing="calls", gap_word="unserved",
    ),
    InterfaceKind(
        "ActionServer", "ProvidesAction", "provides action", ACTION, True, "action server",
        None, "action_server", "#7048e8", "asrv",
        standing="serves action",
    ),
    InterfaceKind(
        "ActionClient", "CallsAction", "calls action", ACTION, False, "action client",
        None, "action_client", "#c2255c", "acli", "SPL046",
        "sends goals to no action server of this product",
        standing="sends goals to", gap_word="unserved",
    ),
)  # fmt: skip
FAMILIES = (TOPIC, SERVICE, ACTION)
_BY_ECLASS = {kind.eclass: kind for kind in KINDS}
# ... by the EClass itself, as met: an EClass's name is read through pyecore's
# descriptor, and a resolution asks an interface's kind some ten thousand times for a
# product of 500 nodes (docs/performance.md, "Large product lines")
_BY_CLASS: dict[object, InterfaceKind] = {}


def kind_of(interface: tsm_types.Interface) -> InterfaceKind:
    """The kind of ``interface`` (a node's or an endpoint's)."""
    eclass = interface.eClass
    kind = _BY_CLASS.get(eclass)
    if kind is None:
        kind = _BY_CLASS[eclass] = _BY_ECLASS[eclass.name]
    return kind


def is_interface(element: Any) -> bool:
    """Whether a model element is an interface (of any kind)."""
    return getattr(element, "eClass", None) is not None and element.eClass.name in _BY_ECLASS


def side(family: Family, provides: bool) -> InterfaceKind:
    """The kind of ``family`` on the providing side, or on the other."""
    return next(k for k in KINDS if k.family is family and k.provides == provides)
