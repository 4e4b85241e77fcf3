"""What the data path of a rehearsal checks, computed from the model and the stand-ins'
statuses: the refined records the model's transforms make of the stored ones (compiled
by spl from ``resolved.tsm``, never taken from the generated service), the values the
stand-ins sent to a writer, and runs of values compared exactly once and in order."""

from __future__ import annotations

import math
from typing import Any

from spl.generators.service.expressions import function_name, neighbours_used, transforms_module
from spl.smoke.plan import SmokePlan


def cloud_stores(system: Any) -> list[tuple[Any, Any]]:
    """(container, store) of every store of a cloud container."""
    return [
        (container, store)
        for container in system.containers
        if container.eClass.name == "CloudContainer"
        for store in container.stores
    ]


def compiled_transforms(system: Any) -> dict[str, Any]:
    """The model's transforms compiled from ``resolved.tsm`` (spl's own compiler, not the
    service's file), by transform name."""
    transforms = {
        id(r.transform): r.transform
        for _, store in cloud_stores(system)
        for r in store.refinements
        if r.transform is not None
    }
    namespace: dict[str, Any] = {}
    exec(compile(transforms_module(transforms.values()), "<transforms>", "exec"), namespace)  # nosec B102: spl's compiler output
    return namespace


def refine(namespace: dict[str, Any], refinement: Any, raw: list[dict[str, Any]]) -> dict:
    """raw id -> the refined values the model's transform gives, per robot in the order
    the transformer takes (source timestamp, then id); a transform reading the next
    record leaves each robot's last one for later."""
    function = namespace[function_name(refinement.transform.name)]
    uses_next = "next" in neighbours_used(refinement.transform)
    by_robot: dict[str, list[dict[str, Any]]] = {}
    for record in raw:
        by_robot.setdefault(record["robot"], []).append(record)
    found = {}
    for records in by_robot.values():
        records.sort(key=lambda r: (r["timestamp"], r["id"]))
        values = [{**r["data"], "timestamp": r["timestamp"]} for r in records]
        for index, record in enumerate(records):
            following = values[index + 1] if index + 1 < len(values) else None
            if uses_next and following is None:
                continue
            before = values[index - 1] if index > 0 else None
            try:
                found[record["id"]] = function(values[index], before, following)
            except namespace["RecordError"]:
                continue
    return found


def sent_to(plan: SmokePlan, statuses: dict[str, dict[str, dict]], writer: Any) -> list[list]:
    """The values the stand-in publishers on a writer's topic sent, in order."""
    container = writer.eContainer().name
    writer_id = f"{container}.{writer.name}.records"
    sent = []
    for node in next(c for c in plan.containers if c.name == container).nodes:
        for interface in node.interfaces:
            if interface.values and feeds(plan, interface.id, writer_id):
                entry = (
                    statuses.get(container, {})
                    .get(node.ros_name, {})
                    .get("interfaces", {})
                    .get(interface.name, {})
                )
                sent += entry.get("values", [])
    return sent


def planned_to(plan: SmokePlan, writer: Any) -> int:
    container = writer.eContainer().name
    writer_id = f"{container}.{writer.name}.records"
    return sum(
        interface.values["count"]
        for c in plan.containers
        if c.name == container
        for node in c.nodes
        for interface in node.interfaces
        if interface.values and feeds(plan, interface.id, writer_id)
    )


def feeds(plan: SmokePlan, publisher: str, subscriber: str) -> bool:
    return any(i.id == subscriber and publisher in i.sources for i in plan.interfaces())


def same(got: list[list[Any]], wanted: list[list[Any]]) -> bool:
    if len(got) != len(wanted):
        return False
    for a, b in zip(got, wanted, strict=True):
        for x, y in zip(a, b, strict=True):
            if isinstance(x, float) or isinstance(y, float):
                if not math.isclose(float(x), float(y), rel_tol=1e-9, abs_tol=1e-9):
                    return False
            elif x != y:
                return False
    return True


def difference(got: list[list[Any]], wanted: list[list[Any]]) -> str:
    """Where two runs of values first differ, in words."""
    for index, (a, b) in enumerate(zip(got, wanted, strict=False)):
        if not same([a], [b]):
            return f"; #{index + 1} is {a}, expected {b}"
    if len(got) > len(wanted):
        extra = got[len(wanted)]
        return f"; {len(got) - len(wanted)} more than expected (#{len(wanted) + 1}: {extra})"
    if len(got) < len(wanted):
        return f"; {len(wanted) - len(got)} missing (from #{len(got) + 1}: {wanted[len(got)]})"
    return ""
