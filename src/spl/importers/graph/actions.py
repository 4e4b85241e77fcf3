"""Actions in a live ROS 1 graph: the topics actionlib makes of each (docs/import.md, "A
live graph").

The master knows no actions, only topics; actionlib makes an action NAME the topics
its family declares (``Family.ros1_topics``: NAME/goal, cancel, status, feedback and
result, with their message types). A group of those topics becomes one action where the
graph shows it whole: every topic there with the type the action's type gives it, one
node on the providing side of all of them (an actionlib server subscribes goal and
cancel and publishes the rest) and every other node using them on the other side of all
of them (a client). Anything less (a topic missing, a type that does not match, no
server or two, a node using some of the topics only) leaves the group as its topics,
with a note saying why, so that nothing the graph shows is lost.
"""

from __future__ import annotations

from dataclasses import dataclass

from spl.dsl import rosnames
from spl.metamodels.interface_kinds import FAMILIES, Family


@dataclass(frozen=True)
class GraphAction:
    name: str  # the action's ROS name, the topics' namespace
    type: str  # pkg/Name of its .action file
    server: str  # the ROS name of the node serving it
    clients: tuple[str, ...]  # the ROS names of the nodes sending it goals
    topics: tuple[str, ...]  # the ROS 1 topics it is made of


def find_actions(
    publishes: dict[str, set[str]],
    subscribes: dict[str, set[str]],
    types: dict[str, str],
    families: tuple[Family, ...] = FAMILIES,
) -> tuple[list[GraphAction], list[str]]:
    """The actions of a graph, from what each node (by ROS name) publishes and subscribes
    and the topics' types; and a note for each group of topics that looks like an action
    (one of its topics has an actionlib type) but is left as its topics, and why. Of the
    registry's ``families``, those made of topics alone are looked for: the master lists
    every part of those, and no other's service (``PartTopic.carrier``)."""
    found: list[GraphAction] = []
    notes: list[str] = []
    used = {t for topics in (*publishes.values(), *subscribes.values()) for t in topics}
    for family in (f for f in families if f.ros1_topics and _all_topics(f)):
        suffixes = {part.suffix for part in family.ros1_topics}
        groups = sorted({t.rsplit("/", 1)[0] for t in used if t.rsplit("/", 1)[-1] in suffixes})
        for group in (g for g in groups if g):
            action, problem = _action(family, group, publishes, subscribes, types, used)
            if action is not None:
                found.append(action)
            elif problem is not None:
                notes.append(f"{family} {group} imported as its topics: {problem}")
    return found, notes


def _all_topics(family: Family) -> bool:
    return all(part.carrier.on_topic for part in family.ros1_topics)


def _action_type(family: Family, group: str, types: dict[str, str]) -> str | None:
    """The action type the group's topics name (``pkg/Name`` of ``pkg/NameActionGoal``),
    or None where none of them has a type made from an action's."""
    for part in family.ros1_topics:
        head, _, ending = part.message.partition("{type}")
        found = types.get(f"{group}/{part.suffix}", "")
        if not head and ending and found.endswith(ending) and len(found) > len(ending):
            return found[: -len(ending)]
    return None


def _action(
    family: Family,
    group: str,
    publishes: dict[str, set[str]],
    subscribes: dict[str, set[str]],
    types: dict[str, str],
    used: set[str],
) -> tuple[GraphAction | None, str | None]:
    """The action of ``group``, or why it is none (None: it is no action's at all)."""
    parts = family.ros1_topics
    action_type = _action_type(family, group, types)
    if action_type is None:
        if any(types.get(f"{group}/{p.suffix}") == p.message for p in parts):
            return None, "no topic of the group has a type made from an action's"
        return None, None  # topics that happen to be named like an action's
    if not rosnames.is_type(action_type):
        return None, f"{action_type!r} is no valid action type"
    missing = [f"{group}/{p.suffix}" for p in parts if f"{group}/{p.suffix}" not in used]
    if missing:
        return None, f"{', '.join(missing)} {'is' if len(missing) == 1 else 'are'} missing"
    for part in parts:
        topic, wanted = f"{group}/{part.suffix}", part.message_of(action_type)
        if types.get(topic) != wanted:
            return None, f"{topic} is {types.get(topic) or 'of no known type'}, not {wanted}"
    provider = {p.suffix for p in parts if not p.from_consumer}
    consumer = {p.suffix for p in parts if p.from_consumer}
    servers, clients, others = [], [], []
    for node in sorted(publishes.keys() | subscribes.keys()):
        sent = _suffixes(publishes.get(node, set()), group) & (provider | consumer)
        taken = _suffixes(subscribes.get(node, set()), group) & (provider | consumer)
        if not sent and not taken:
            continue
        if (sent, taken) == (provider, consumer):
            servers.append(node)
        elif (sent, taken) == (consumer, provider):
            clients.append(node)
        else:
            others.append(node)
    if others:
        return None, (
            f"node {others[0]} publishes or subscribes only some of its topics, as neither "
            f"an actionlib server nor a client does"
        )
    if len(servers) != 1:
        if not servers:
            takes = _listed([p.suffix for p in parts if p.from_consumer])
            sends = _listed([p.suffix for p in parts if not p.from_consumer])
            return None, f"no node serves it (subscribes {takes}, publishes {sends})"
        return None, f"nodes {', '.join(servers)} all serve it"
    topics = tuple(f"{group}/{p.suffix}" for p in parts)
    return GraphAction(group, action_type, servers[0], tuple(clients), topics), None


def _suffixes(topics: set[str], group: str) -> set[str]:
    """The last names of the topics directly under ``group``."""
    return {t.rsplit("/", 1)[1] for t in topics if t.rsplit("/", 1)[0] == group}


def _listed(words: list[str]) -> str:
    """``a, b and c``."""
    return " and ".join([", ".join(words[:-1]), words[-1]] if len(words) > 1 else words)
