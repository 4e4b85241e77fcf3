"""Text output of a smoke rehearsal: one table per container and a verdict.

Columns: whether the check passed, the node (``endpoint`` for the container's Rapyuta
endpoint), the interface (or ``param NAME``, or ``(node)`` for the node itself), the
ROS name the model binds it to, what the model expects there and what the live graph
showed.
"""

from __future__ import annotations

from spl.diagnostics import counted
from spl.smoke.live import Row
from spl.smoke.rehearsal import SmokeResult

HEADER = ("", "NODE", "INTERFACE", "TOPIC", "EXPECTED", "SEEN")


def table(rows: list[Row]) -> list[str]:
    cells = [HEADER] + [
        ("ok" if r.ok else "FAIL", r.node, r.interface, r.topic, r.expected, r.seen) for r in rows
    ]
    widths = [max(len(line[i]) for line in cells) for i in range(len(HEADER) - 1)]
    return [
        "  ".join(
            [*(cell.ljust(width) for cell, width in zip(line[:-1], widths, strict=True)), line[-1]]
        )
        for line in cells
    ]


def text_report(result: SmokeResult) -> list[str]:
    lines = []
    for container, rows in result.rows.items():
        lines.append(f"{container}:")
        lines += [f"  {line}".rstrip() for line in table(rows)] if rows else ["  (no ROS nodes)"]
        lines.append("")
    checks = sum(len(rows) for rows in result.rows.values())
    if result.passed:
        lines.append(f"smoke {result.product}: all {checks} checks ok in {result.seconds:.1f} s")
    else:
        failures = result.failures()
        lines.append(
            f"smoke {result.product}: FAILED, {counted(len(failures), 'problem')} in "
            f"{result.seconds:.1f} s"
        )
        lines += [f"  {failure}" for failure in failures]
    return lines
