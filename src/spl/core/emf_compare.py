"""Two models compared element by element, for the printers' round trips: a printed
model parses back to the same model when :func:`differences` finds nothing.

Containment is compared in order, references by the path of names to their target, and
source locations not at all (a printed model has its own), unlike
:func:`spl.core.emf.fingerprint`, which is exact.
"""

from __future__ import annotations

from collections.abc import Iterator

from pyecore.ecore import EAttribute, EObject

from spl.core.emf_copy import all_features


def _path(obj: EObject | None) -> str:
    parts = []
    while obj is not None:
        name = getattr(obj, "name", None)
        parts.append(name if name else obj.eClass.name)
        obj = obj.eContainer()
    return ".".join(reversed(parts))


def differences(a: EObject, b: EObject, where: str = "") -> Iterator[str]:
    """Human-readable differences between two models (empty when they are equal).

    Containment is compared in order; plain references are compared by the path of
    their target, so two separately parsed models can be compared.
    """
    where = where or a.eClass.name
    if a.eClass is not b.eClass:
        yield f"{where}: {a.eClass.name} != {b.eClass.name}"
        return
    for feature in all_features(a):
        if isinstance(feature, EAttribute) and feature.transient:
            continue
        va, vb = a.eGet(feature), b.eGet(feature)
        here = f"{where}.{feature.name}"
        if isinstance(feature, EAttribute):
            if (list(va) if feature.many else va) != (list(vb) if feature.many else vb):
                yield f"{here}: {va!r} != {vb!r}"
        elif feature.containment:
            la = list(va) if feature.many else [v for v in (va,) if v is not None]
            lb = list(vb) if feature.many else [v for v in (vb,) if v is not None]
            if len(la) != len(lb):
                yield f"{here}: {len(la)} elements != {len(lb)}"
                continue
            for i, (ca, cb) in enumerate(zip(la, lb, strict=True)):
                yield from differences(ca, cb, f"{here}[{i}]")
        else:
            pa = [_path(v) for v in va] if feature.many else _path(va)
            pb = [_path(v) for v in vb] if feature.many else _path(vb)
            if pa != pb:
                yield f"{here}: -> {pa} != -> {pb}"
