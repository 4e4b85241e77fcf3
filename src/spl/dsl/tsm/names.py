"""What the names of a .tsm file mean while it is built, and where each is written.

A .tsm file may use a name before declaring it (a node subscribes to a topic declared
further down, a bridge names containers anywhere in the file), so building is two
passes: the declaration pass creates every element and registers its name here, then
the resolution pass looks references up. :class:`Names` is the state both passes
share: the tables of declared names, the resolution steps still to run, the problems
found so far, and the source location of every parse-tree object, so each problem is
reported at the column of the offending name.
"""

from __future__ import annotations

import bisect
import re
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from spl.core.diagnostics import DiagnosticSink, Location
from spl.metamodels import tsm as tsm_metamodel

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

# A resolution step: (names, model element, its parse tree) -> None
Resolve = Callable[["Names", Any, Any], None]


class Lines:
    """Where the lines of a text start, to turn a parse tree's position into a place.
    Plain elements keep this (not :class:`Names`, which holds them: no cycle)."""

    __slots__ = ("filename", "offset", "starts")

    def __init__(self, text: str, filename: str, offset: Callable[[int], int] | None) -> None:
        self.filename = filename
        self.starts = [0] + [m.end() for m in re.finditer("\n", text)]
        # the offset of a parse tree's stored position (an incremental reading's trees
        # keep the positions they were read at: spl.dsl.tsm.incremental)
        self.offset = offset

    def loc(self, tree: Any) -> Location:
        pos = tree._tx_position
        if self.offset is not None:
            pos = self.offset(pos)
        index = bisect.bisect_right(self.starts, pos) - 1
        return Location(self.filename, index + 1, pos - self.starts[index] + 1)

    def place(self, tree: Any) -> tuple[str, int, int]:
        """``(file, line, column)`` of ``tree``."""
        where = self.loc(tree)
        return where.file, where.line, where.col


class Names:
    """The declared names of one .tsm file, the located problems and pending references."""

    def __init__(
        self,
        text: str,
        filename: str,
        sink: DiagnosticSink,
        metamodel: tsm_types.Metamodel | None = None,
        places: Callable[[int], int] | None = None,
    ) -> None:
        self.filename = filename
        self.sink = sink
        # the classes elements are made of: pyecore's, or spl.dsl.tsm.plain's for a check
        self.T = metamodel if metamodel is not None else tsm_metamodel()
        self._located_later = getattr(self.T, "located_later", False)
        self.lines = Lines(text, filename, places)
        self.system: Any = None
        self.containers: dict[str, Any] = {}
        self.data_types: dict[str, Any] = {}
        self.transforms: dict[str, Any] = {}
        # container id -> name -> the first topic / node of that name declared in it, so a
        # reference costs a dictionary look-up, not a scan of the container
        self.topics: dict[int, dict[str, Any]] = {}
        self.nodes: dict[int, dict[str, Any]] = {}
        self._literals: dict[tuple[str, str], Any] = {}
        # resolution steps in declaration order, run once every name is declared
        self.pending: list[tuple[Resolve, Any, Any]] = []

    # -- locations and problems --------------------------------------------------------
    def loc(self, tree: Any) -> Location:
        return self.lines.loc(tree)

    def locate(self, element: Any, tree: Any) -> Any:
        """``element`` with the source location of ``tree`` recorded on it (plain
        elements, spl.dsl.tsm.plain, work it out when it is first read)."""
        if self._located_later:
            element._location = (self.lines, tree)
            return element
        where = self.lines.loc(tree)
        element.srcFile, element.srcLine, element.srcCol = where.file, where.line, where.col
        return element

    def error(self, tree: Any, message: str) -> None:
        self.sink.error(self.loc(tree), message)

    def check(self, tree: Any, problem: str | None) -> bool:
        """Report ``problem`` (if any) at ``tree``; True when there is none."""
        if problem:
            self.error(tree, problem)
        return problem is None

    def literal(self, enum: str, name: str) -> Any:
        """The literal ``name`` of the metamodel's enumeration ``enum`` (looked up once)."""
        key = (enum, name)
        found = self._literals.get(key)
        if found is None:
            found = self._literals[key] = getattr(self.T, enum).getEEnumLiteral(name)
        return found

    # -- declarations ------------------------------------------------------------------
    def declare(
        self, scope: dict[str, Any], element: Any, name_tree: Any, what: str, where: str = ""
    ) -> None:
        """Register ``element`` under its name in ``scope``; report a duplicate."""
        first = scope.get(element.name)
        if first is not None:
            self.error(
                name_tree,
                f"duplicate {what} name {element.name}{where} "
                f"(first declared at line {first.srcLine})",
            )
        else:
            scope[element.name] = element

    def later(self, resolve: Resolve, element: Any, tree: Any) -> None:
        """Run ``resolve`` for ``element`` in the resolution pass."""
        self.pending.append((resolve, element, tree))

    # -- references --------------------------------------------------------------------
    def data_type(self, ref: Any) -> Any:
        found = self.data_types.get(ref.name)
        if found is None:
            self.error(ref, f"unknown data type {ref.name}")
        return found

    def container(self, ref: Any) -> Any:
        found = self.containers.get(ref.name)
        if found is None:
            self.error(ref, f"unknown container {ref.name}")
        return found

    def topic(self, container: Any, ref: Any) -> Any:
        """Topic ``ref`` of ``container`` (the first declared of that name)."""
        topic = self.topics[id(container)].get(ref.name)
        if topic is None:
            self.error(ref, f"unknown topic {ref.name} in container {container.name}")
        return topic

    def find_node(self, container: Any, name: str) -> Any:
        """Node ``name`` of ``container`` (the first declared of that name), or None."""
        return self.nodes[id(container)].get(name)

    def node(self, container: Any, ref: Any) -> Any:
        node = self.find_node(container, ref.name)
        if node is None:
            self.error(ref, f"unknown node {ref.name} in container {container.name}")
        return node


def find_interface(node: Any, name: str) -> Any:
    """Interface ``name`` of ``node`` (the first declared of that name), or None."""
    return next((i for i in node.interfaces if i.name == name), None)
