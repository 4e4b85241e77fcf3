"""What a smoke rehearsal found (:class:`SmokeResult`), its progress line, and its
text output: one table per container and a verdict.

Columns: whether the check passed, the node (``endpoint`` for the container's Rapyuta
endpoint), the interface (or ``param NAME``, or ``(node)`` for the node itself), the
ROS name the model binds it to, what the model expects there and what the live graph
showed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from spl.core.diagnostics import counted
from spl.smoke.live import NOT_MODELLED, Row


@dataclass
class Progress:
    seconds: float
    masters_up: int
    containers: int
    ready: int
    stand_ins: int
    rows_ok: int
    rows: int

    def line(self) -> str:
        return (
            f"smoke: {self.masters_up}/{self.containers} masters, {self.ready}/{self.stand_ins} "
            f"nodes up, {self.rows_ok}/{self.rows} checks ok, {self.seconds:.1f} s"
        )


@dataclass
class SmokeResult:
    product: str
    bundle: str
    seconds: float
    rows: dict[str, list[Row]]  # container -> rows, in model order
    problems: list[str] = field(default_factory=list)  # what failed outside the rows
    skipped: str | None = None  # why the data path was not rehearsed, when it was not
    actions_skipped: str | None = None  # why the actions were not, when they were not

    @property
    def passed(self) -> bool:
        return not self.problems and all(r.ok for rows in self.rows.values() for r in rows)

    def failures(self) -> list[str]:
        """One line per failed check, naming container, node and interface."""
        failed = [
            f"{r.container}.{r.node}.{r.interface} ({r.topic}): {r.seen}, not in the model"
            if r.expected == NOT_MODELLED
            else f"{r.container}.{r.node}.{r.interface} ({r.topic}): expected {r.expected}; "
            f"seen {r.seen}"
            for rows in self.rows.values()
            for r in rows
            if not r.ok
        ]
        return [*self.problems, *failed]

    def as_dict(self) -> dict[str, Any]:
        return {
            "product": self.product,
            "bundle": self.bundle,
            "passed": self.passed,
            "seconds": round(self.seconds, 2),
            "containers": [
                {"name": name, "rows": [r.as_dict() for r in rows]}
                for name, rows in self.rows.items()
            ],
            "failures": self.failures(),
            "skipped": self.skipped,
            "actions_skipped": self.actions_skipped,
        }


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
