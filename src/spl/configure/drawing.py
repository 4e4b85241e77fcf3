"""The resolved architecture drawn as SVG in Python, for the configurator's page
(docs/configure.md, "The architecture").

Why not Graphviz: the page must draw without a system program, and a vendored
WebAssembly Graphviz is a megabyte of JavaScript for a drawing whose shape is always the
same: containers side by side (robot containers first, then cloud containers, in the
model's order), their nodes stacked inside, the bridges between containers as lines
labelled with how many endpoint connections they carry. Nodes a ``migrate`` moved are
outlined red with their origin; nodes the resolution removed, and containers pruning
left out (docs/resolution.md), are listed struck through, the containers with the reason.
The layout is a pure function of the product, so the same product gives the same bytes.
The bundle's own ``architecture.svg`` (Graphviz, docs/outputs.md "Diagrams") stays the
full diagram with topics and interfaces.
"""

from __future__ import annotations

from html import escape
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from spl.resolver.resolution.engine import Resolution

COLUMN = 220  # width of a container
GAP = 60  # between containers
NODE_HEIGHT = 44
HEADER = 46
MARGIN = 20
ROBOT_FILL, ROBOT_LINE = "#eef4fb", "#2f5f8f"
CLOUD_FILL, CLOUD_LINE = "#f4effa", "#6a3d9a"
MIGRATED = "#c0392b"


def architecture_svg(resolution: Resolution) -> str:
    """The drawing of one resolved product."""
    product = resolution.product
    system = product.system
    containers = sorted(
        system.containers, key=lambda c: 0 if c.eClass.name == "RobotContainer" else 1
    )
    column_of = {c.name: i for i, c in enumerate(containers)}
    tallest = max((len(c.nodes) for c in containers), default=0)
    bridge_room = 30 + 18 * len(containers) ** 2
    height = MARGIN * 2 + HEADER + tallest * (NODE_HEIGHT + 10) + 10 + bridge_room
    # removed nodes, and containers pruning left out (no file of the bundle deploys them)
    removed = [(key, key, "data-node-removed") for key in resolution.removed_nodes]
    removed += [(name, f"{name}: {why}", "data-left-out") for name, why in product.left_out]
    height += 24 + 18 * len(removed) if removed else 0
    width = MARGIN * 2 + max(1, len(containers)) * (COLUMN + GAP) - GAP
    longest = max((len(label) for _, label, _ in removed), default=0)
    width = max(width, MARGIN * 2 + 10 + 7 * longest)  # ~7 px a character at 12 px
    box_bottom = MARGIN + HEADER + tallest * (NODE_HEIGHT + 10) + 10
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" role="img" '
        f'aria-label="resolved architecture of {escape(product.name)}" '
        'font-family="sans-serif" font-size="12">',
        f"<title>resolved architecture of {escape(product.name)}</title>",
    ]
    for container in containers:
        x = MARGIN + column_of[container.name] * (COLUMN + GAP)
        robot = container.eClass.name == "RobotContainer"
        fill, line = (ROBOT_FILL, ROBOT_LINE) if robot else (CLOUD_FILL, CLOUD_LINE)
        kind = "robot container" if robot else "cloud container"
        dash = "" if robot else ' stroke-dasharray="6 3"'
        parts.append(f'<g data-container="{escape(container.name)}">')
        parts.append(
            f'<rect x="{x}" y="{MARGIN}" width="{COLUMN}" height="{box_bottom - MARGIN}" '
            f'rx="10" fill="{fill}" stroke="{line}" stroke-width="2"{dash}/>'
        )
        parts.append(
            f'<text x="{x + 10}" y="{MARGIN + 18}" font-weight="bold">'
            f"{escape(container.name)}</text>"
        )
        parts.append(f'<text x="{x + 10}" y="{MARGIN + 34}" fill="#555">«{kind}»</text>')
        for row, node in enumerate(container.nodes):
            y = MARGIN + HEADER + row * (NODE_HEIGHT + 10)
            migration = product.migrated(node.name)
            stroke = f'stroke="{MIGRATED}" stroke-width="3"' if migration else 'stroke="#333"'
            sharing = node.sharing.name if node.sharing is not None else "private"
            mark = f' data-migrated="{escape(migration.source)}"' if migration else ""
            parts.append(f'<g data-node="{escape(node.name)}"{mark}>')
            parts.append(
                f'<rect x="{x + 10}" y="{y}" width="{COLUMN - 20}" height="{NODE_HEIGHT}" '
                f'rx="4" fill="#d9d9d9" {stroke}/>'
            )
            parts.append(f'<text x="{x + 18}" y="{y + 17}">{escape(node.name)}</text>')
            note = f"«{sharing}»"
            if migration:
                note += f" migrated from {migration.source}"
            colour = MIGRATED if migration else "#555"
            parts.append(
                f'<text x="{x + 18}" y="{y + 34}" font-size="10" fill="{colour}">'
                f"{escape(note)}</text>"
            )
            parts.append("</g>")
        parts.append("</g>")
    parts += _bridges(resolution, column_of, box_bottom)
    if removed:
        y = height - MARGIN - 18 * len(removed)
        parts.append('<g data-removed="">')
        parts.append(f'<text x="{MARGIN}" y="{y}" font-weight="bold">removed</text>')
        for i, (key, label, mark) in enumerate(removed):
            parts.append(
                f'<text x="{MARGIN + 10}" y="{y + 18 * (i + 1)}" fill="#777" '
                f'text-decoration="line-through" {mark}="{escape(key)}">'
                f"{escape(label)}</text>"
            )
        parts.append("</g>")
    parts.append("</svg>")
    return "\n".join(parts)


def _bridges(resolution: Resolution, column_of: dict[str, int], top: int) -> list[str]:
    """One line per pair of containers an endpoint connection joins, under the boxes."""
    pairs: dict[tuple[str, str], int] = {}
    for connection in resolution.product.system.connections:
        ends = []
        for interface in (connection.source, connection.target):
            owner = interface.eContainer() if interface is not None else None
            container = owner.eContainer() if owner is not None else None
            ends.append(getattr(container, "name", None))
        a, b = ends
        if a is None or b is None or a == b or a not in column_of or b not in column_of:
            continue
        key = (a, b) if column_of[a] < column_of[b] else (b, a)
        pairs[key] = pairs.get(key, 0) + 1
    parts = []
    for level, ((a, b), count) in enumerate(sorted(pairs.items())):
        y = top + 20 + 18 * level
        xa = MARGIN + column_of[a] * (COLUMN + GAP) + COLUMN // 2
        xb = MARGIN + column_of[b] * (COLUMN + GAP) + COLUMN // 2
        label = f"{count} bridge{'s' if count != 1 else ''}"
        parts.append(
            f'<g data-bridge="{escape(a)} {escape(b)}">'
            f'<line x1="{xa}" y1="{top}" x2="{xa}" y2="{y}" stroke="#f5a54a" stroke-width="2"/>'
            f'<line x1="{xa}" y1="{y}" x2="{xb}" y2="{y}" stroke="#f5a54a" stroke-width="2"/>'
            f'<line x1="{xb}" y1="{y}" x2="{xb}" y2="{top}" stroke="#f5a54a" stroke-width="2"/>'
            f'<text x="{(xa + xb) // 2}" y="{y - 4}" text-anchor="middle" font-size="10">'
            f"{label}</text></g>"
        )
    return parts
