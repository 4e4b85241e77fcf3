"""Small feature models with known answers, built with the metamodel classes.

Every element gets a source location (``mapping.fm:line:col``) the way the ``.fm``
builder sets them, so explanations can be checked with their locations.
"""

from __future__ import annotations

import itertools
from typing import Any

from spl.metamodels import fm

from support.fm_semantics import is_product

F = fm()


def at(element: Any, line: int, col: int = 5, file: str = "mapping.fm") -> Any:
    element.srcFile, element.srcLine, element.srcCol = file, line, col
    return element


def feature(name: str, *groups: Any, line: int = 1, abstract: bool = False) -> Any:
    f = at(F.Feature(name=name, abstract=abstract), line)
    for group in groups:
        f.groups.append(group)
    return f


def group(kind: str, *features: Any, line: int = 1, lower: int = 0, upper: int = -1) -> Any:
    g = at(F.Group(kind=F.GroupKind.getEEnumLiteral(kind), lower=lower, upper=upper), line)
    for f in features:
        g.features.append(f)
    return g


def model(root: Any, *constraints: Any, name: str = "M") -> Any:
    m = F.FeatureModel(name=name)
    m.root = root
    for c in constraints:
        m.constraints.append(c)
    return m


def ref(name: str, m_features: dict[str, Any]) -> Any:
    r = F.FeatureRef()
    r.feature = m_features[name]
    return r


def constraint(formula: Any, line: int) -> Any:
    c = at(F.Constraint(), line)
    c.formula = formula
    return c


def binary(op: str, left: Any, right: Any) -> Any:
    b = F.BinaryFormula(operator=op)
    b.left, b.right = left, right
    return b


def negate(operand: Any) -> Any:
    n = F.Not()
    n.operand = operand
    return n


def all_features(m: Any) -> dict[str, Any]:
    out = {}
    stack = [m.root]
    while stack:
        f = stack.pop()
        out[f.name] = f
        stack.extend(c for g in f.groups for c in g.features)
    return out


def mapping3d() -> tuple[Any, dict[str, Any]]:
    """docs/fm.md's Mapping3D, with ``Roomba excludes AdditionalPC`` added (line 17)."""
    root = feature(
        "Mapping",
        group(
            "mandatory",
            feature(
                "MobileBase",
                group("alternative", feature("YouBot", line=4), feature("Roomba", line=4), line=4),
                line=4,
            ),
            feature(
                "PerceptionSensor",
                group("alternative", feature("Stereo", line=5), feature("Depth", line=5), line=5),
                line=5,
            ),
            feature(
                "Environment",
                group("alternative", feature("Room", line=7), feature("Corridor", line=7), line=7),
                line=7,
            ),
            line=4,
        ),
        group(
            "optional",
            feature("AdditionalPC", line=6),
            feature("CollaborativeMapping", line=8),
            feature("Logging", line=11),
            line=6,
        ),
        line=3,
    )
    m = model(root, name="Mapping3D")
    fs = all_features(m)
    m.constraints.append(constraint(binary("excludes", ref("Roomba", fs), ref("Stereo", fs)), 16))
    either = binary("or", ref("AdditionalPC", fs), ref("Depth", fs))
    m.constraints.append(constraint(binary("requires", ref("Stereo", fs), either), 17))
    return m, fs


# --- an independent brute-force evaluator of the semantics (no SAT, no CNF) -----------


def brute_force_products(m: Any) -> list[frozenset[str]]:
    names = sorted(all_features(m))
    out = []
    for bits in itertools.product((False, True), repeat=len(names)):
        product = {n for n, b in zip(names, bits, strict=True) if b}
        if is_product(m, product):
            out.append(frozenset(product))
    return out
