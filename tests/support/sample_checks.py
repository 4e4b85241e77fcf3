"""Independent coverage count for the sampling tests: the t-combinations a set of
products covers, counted from the feature names (no CNF, no sampler). Products
themselves are checked with ``fm_semantics.is_product``.
"""

from __future__ import annotations

from itertools import combinations
from typing import Any


def interactions(products: Any, names: list[str], t: int) -> set[tuple[tuple[str, bool], ...]]:
    """Every t-combination of feature literals (name, selected) some product contains."""
    found: set[tuple[tuple[str, bool], ...]] = set()
    for product in products:
        literals = [(name, name in product) for name in names]
        found.update(combinations(literals, t))
    return found
