"""The shipped products (``product_lines/*/products/*.yaml``) resolved, each line loaded
once: for tests that check something of every product's bundle."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

LINES = Path(__file__).resolve().parents[2] / "product_lines"


def shipped_products() -> Iterator[tuple[Path, ResolvedProduct]]:
    lines = {}
    for path in sorted(LINES.glob("*/products/*.yaml")):
        folder = path.parent.parent
        line = lines.get(folder) or lines.setdefault(folder, load_product_line(folder))
        yield path, resolve(line, load_selection_file(path)).product
