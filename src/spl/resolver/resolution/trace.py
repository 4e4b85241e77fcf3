"""The trace of one resolution: every decision the engine took and why.

`spl explain` answers "why is this element here / gone / over there / set like this"
from it, naming the resolution element, its feature and their file locations.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from spl.core.diagnostics import Location


@dataclass(frozen=True)
class TraceEntry:
    subject: str  # the element the decision is about: "Node", "Container.Topic", ...
    decision: str  # kept, removed, migrated, implementation, parameter, sharing, ...
    reason: str  # in words, naming the resolution element and feature
    location: Location | None = None  # of the resolution element or model element responsible

    def __str__(self) -> str:
        where = f" ({self.location})" if self.location else ""
        if self.reason.endswith(where):  # the reason names the element where it stands
            where = ""
        return f"{self.subject}: {self.decision}: {self.reason}{where}"


@dataclass
class Trace:
    entries: list[TraceEntry] = field(default_factory=list)

    def record(
        self, subject: str, decision: str, reason: str, location: Location | None = None
    ) -> None:
        self.entries.append(TraceEntry(subject, decision, reason, location))

    def about(self, name: str) -> list[TraceEntry]:
        """Entries for ``name`` (an element name or a qualified ``Container.Element``)."""
        return [
            e
            for e in self.entries
            if e.subject == name
            or e.subject.endswith(f".{name}")
            or e.subject.startswith(f"{name}.")
        ]
