"""The data-acquisition part of the .tsm language: stores, writers and readers.

A store (in a cloud container) keeps records of a raw data type and refines them by
transforms into further types; a writer is a generated node taking records from a
topic into a store, a reader one publishing what a store keeps. The types along that
path must agree, or the generated service would drop every record at run time; each
disagreement is reported at the name that causes it.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from spl.dsl import rosnames
from spl.dsl.tsm.names import Names
from spl.dsl.tsm.nodes import implementation, node_common, parameters
from spl.metamodels.interface_kinds import TOPIC, InterfaceKind, side

if TYPE_CHECKING:
    from spl.dsl.tsm import tree as tsm_tree


# -- stores -------------------------------------------------------------------------------
def store(names: Names, tree: tsm_tree.Store) -> Any:
    """The Store of a ``store`` block; its types and refinements resolve later."""
    store = names.locate(names.T.Store(name=tree.name.name), tree.name)
    store.optional = bool(tree.optional)
    names.check(tree.name, rosnames.problem_base_name(store.name, "store name"))
    names.later(_resolve_store, store, tree)
    return store


def _resolve_store(names: Names, store: Any, tree: tsm_tree.Store) -> None:
    store.raw = names.data_type(tree.raw)
    outputs: dict[str, Any] = {}
    for refinement_tree in tree.refinements:
        refinement = names.locate(names.T.Refinement(), refinement_tree.output)
        output = names.data_type(refinement_tree.output)
        transform = names.transforms.get(refinement_tree.transform.name)
        if transform is None:
            names.error(
                refinement_tree.transform,
                f"unknown transform {refinement_tree.transform.name}",
            )
        if output is not None:
            if output.name in outputs:
                names.error(
                    refinement_tree.output,
                    f"store {store.name} already refines into {output.name}",
                )
            outputs[output.name] = refinement
        if (
            transform is not None
            and store.raw is not None
            and transform.input not in (None, store.raw)
        ):
            names.error(
                refinement_tree.transform,
                f"transform {transform.name} reads {transform.input.name}, "
                f"but store {store.name} keeps {store.raw.name}",
            )
        if transform is not None and output is not None and transform.output not in (None, output):
            names.error(
                refinement_tree.transform,
                f"transform {transform.name} makes {transform.output.name}, not {output.name}",
            )
        refinement.output, refinement.transform = output, transform
        refinement.period = _period(names, refinement_tree.period)
        store.refinements.append(refinement)


# seconds: a transformer or a polling reader runs at most a thousand times a second (a
# shorter period is a busy loop against the store, 5e-324 s one in name only) and at
# least once a year
MIN_PERIOD = 0.001
MAX_PERIOD = 86400 * 366
PERIOD_RANGE = "at least 0.001 s and at most a year"


def period_fits(value: float) -> bool:
    """Whether a transformer's or reader's period (s) is one: from 1 ms to a year."""
    return math.isfinite(value) and MIN_PERIOD <= value <= MAX_PERIOD


def _period(names: Names, tree: tsm_tree.Period) -> float | None:
    value = float(tree.value)
    if not period_fits(value):
        names.error(tree, f"period {tree.value} s must be {PERIOD_RANGE}")
        return None
    return value


# -- writers and readers ------------------------------------------------------------------
def writer(names: Names, tree: tsm_tree.Writer) -> Any:
    """The Writer of a ``writer`` statement: records from a topic into a store."""
    return _data_node(names, names.T.Writer(name=tree.name.name), tree, side(TOPIC, False))


def reader(names: Names, tree: tsm_tree.Reader) -> Any:
    """The Reader of a ``reader`` statement: what a store keeps, published as it is
    pushed (``subscribe``) or polled every ``period``."""
    reader = _data_node(names, names.T.Reader(name=tree.name.name), tree, side(TOPIC, True))
    reader.period = _period(names, tree.period)
    reader.subscribe = bool(tree.subscribe)
    return reader


def _data_node(
    names: Names, node: Any, tree: tsm_tree.Writer | tsm_tree.Reader, records_kind: InterfaceKind
) -> Any:
    """``node`` with its one interface, ``records``: the topic side a writer takes its
    records from, or a reader puts them on."""
    node_common(names, node, tree)
    node.sharing = names.T.SharingMode.private
    records = names.locate(getattr(names.T, records_kind.eclass)(name="records"), tree.topic)
    node.interfaces.append(records)
    implementation(names, node, tree)
    parameters(names, node, tree.parameters)
    names.later(_resolve_data_node, node, tree)
    return node


def _resolve_data_node(names: Names, node: Any, tree: tsm_tree.Writer | tsm_tree.Reader) -> None:
    reads = node.eClass.name == "Reader"
    node.dataType = names.data_type(tree.dataType)
    container = node.eContainer()
    records = node.interfaces[0]
    topic = names.topic(container, tree.topic)
    if topic is not None:
        records.topic, records.type = topic, topic.type
    parts = tree.store.parts
    if len(parts) != 2:
        names.error(tree.store, "expected CONTAINER.STORE")
        return
    store_container = names.container(parts[0])
    if store_container is None:
        return
    store = next((s for s in store_container.stores if s.name == parts[1].name), None)
    if store is None:
        names.error(parts[1], f"unknown store {parts[1].name} in container {parts[0].name}")
        return
    node.store = store
    if node.dataType is None or store.raw is None:
        return
    if not reads and node.dataType is not store.raw:
        names.error(
            tree.dataType,
            f"writer {node.name} writes {node.dataType.name}, but store {store.name} "
            f"takes raw {store.raw.name}",
        )
    kept = [store.raw] + [r.output for r in store.refinements if r.output is not None]
    if reads and node.dataType not in kept:
        kept_names = ", ".join(d.name for d in kept)
        names.error(
            tree.dataType,
            f"store {store.name} keeps no {node.dataType.name} (it keeps {kept_names})",
        )
