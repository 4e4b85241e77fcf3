"""The print of a plain .tsm model (:mod:`spl.dsl.tsm.plain`): the tuples
:func:`spl.core.emf.fingerprint` gives, read by code made for each plain class.

Why: after every edit of a product line's .tsm the editor prints each container of the
template whole, to tell what the edit left alone (:mod:`spl.dsl.tsm.declarations`);
on a 10,000-node line that print was a fifth of a valid edit's check
(docs/performance.md, "Editor latency"). The generic print asks the class's plan for
each element and reads each feature through ``getattr``, and the source location
through three properties; the code made here reads each feature of a class by name in
one expression and the location once. The tuples are the generic print's, element for
element (``tests/dsl/test_tsm_plain_prints.py`` compares them on every model of the
repository), so prints made either way compare.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from spl.core.emf import Step, fingerprint
from spl.core.emf_copy import class_name, plan
from spl.dsl.tsm.plain import LOCATION, PlainElement

Visit = Callable[[Any, tuple[Step, ...]], None]
# a class's print: (element, its path, the print of a child, target, visit, base)
ClassPrint = Callable[[Any, tuple[Step, ...], Callable, Callable, Visit, int], tuple]


def plain_fingerprint(
    root: Any,
    target: Callable[[Any], object],
    visit: Visit | None = None,
    base: int = 0,
    leave_out: tuple[tuple[str, ...], ...] = (),
    made: dict[type, ClassPrint] | None = None,
) -> tuple:
    """:func:`spl.core.emf.fingerprint` of ``root``, read by the code of each plain
    class (kept in ``made``, which the caller owns, by class); any other root, or
    containments left out, are printed by the generic print."""
    if leave_out or not isinstance(root, PlainElement):
        return fingerprint(root, target, visit, base, leave_out)
    seen = visit if visit is not None else _unseen
    prints = made if made is not None else {}

    def child(element: Any, path: tuple[Step, ...]) -> tuple:
        made_for = prints.get(type(element))
        if made_for is None:
            made_for = prints[type(element)] = _class_print(element)
        return made_for(element, path, child, target, seen, base)

    return child(root, ())


def _unseen(element: Any, path: tuple[Step, ...]) -> None:
    """No visit asked for."""


def _class_print(sample: Any) -> ClassPrint:
    """The print of ``sample``'s class: its values in the plan's order, each location
    read from the element's one stored place (worked out once, as the properties of
    :mod:`spl.dsl.tsm.plain` do), then its references."""
    values, references = plan(sample)
    parts = [repr(class_name(sample))]
    lines = ["def made(obj, path, child, target, visit, base):", "    visit(obj, path)"]
    if any(name in LOCATION for name, *_ in values):
        lines += [
            "    where = obj._location",
            "    if len(where) == 2:",
            "        where = obj._location = where[0].place(where[1])",
        ]
    for name, many, containment, _, _ in values:
        if name == "srcLine":
            parts.append("(None if where[1] is None else where[1] - base)")
        elif name in LOCATION:
            parts.append(f"where[{LOCATION.index(name)}]")
        elif not containment:
            parts.append(f"tuple(obj.{name})" if many else f"obj.{name}")
        elif many:
            step = f"({name!r}, i)"
            parts.append(f"tuple([child(c, (*path, {step})) for i, c in enumerate(obj.{name})])")
        else:
            step = f"({name!r}, -1)"
            lines.append(f"    f_{name} = obj.{name}")
            parts.append(f"(None if f_{name} is None else child(f_{name}, (*path, {step})))")
    for name, many, _ in references:
        if many:
            parts.append(f"tuple([target(v) for v in obj.{name}])")
        else:
            lines.append(f"    f_{name} = obj.{name}")
            parts.append(f"(None if f_{name} is None else target(f_{name}))")
    lines.append(f"    return ({', '.join(parts)},)")
    namespace: dict[str, Any] = {}
    exec("\n".join(lines), namespace)  # the source is made of metamodel names only
    made: ClassPrint = namespace["made"]
    return made
