"""YAML files read as located nodes: selections, robot capability files and fleet files
are composed (not loaded) so that every value keeps its line and column for messages,
and hostile YAML (invalid, nested beyond the parser, or holding itself through
aliases) is a located error instead of a crash or an endless walk."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

import yaml

from spl.core.diagnostics import DiagnosticSink, Location, model_text


def read_yaml(
    path: Path, sink: DiagnosticSink, unsaved: Mapping[str, str] | None = None
) -> tuple[yaml.Node | None, Callable]:
    """The YAML of ``path`` composed into nodes (which keep their line and column), and the
    function giving a node's location; invalid YAML is raised as a located error.
    ``unsaved``: an editor's texts, which stand in for the files on disk."""
    filename = str(path)
    text = model_text(path, unsaved)
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except RecursionError:
        sink.error(Location(filename, 1, 1), "invalid YAML: nested too deeply")
        sink.raise_if_errors()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark
        where = Location(filename, mark.line + 1, mark.column + 1) if mark else None
        sink.error(where or Location(filename, 1, 1), f"invalid YAML: {exc.problem}")
    except yaml.reader.ReaderError as exc:  # a character YAML does not allow; no mark
        line = text.count("\n", 0, exc.position) + 1
        column = exc.position - text.rfind("\n", 0, exc.position)
        sink.error(
            Location(filename, line, column),
            f"invalid YAML: character U+{exc.character:04X} is not allowed",
        )
    sink.raise_if_errors()

    def at(node: yaml.Node) -> Location:
        return Location(filename, node.start_mark.line + 1, node.start_mark.column + 1)

    recursive = _recursive_node(root)
    if recursive is not None:  # `x: &a {y: *a}`: every walk of it would never end
        sink.error(at(recursive), "invalid YAML: a recursive alias (a node that holds itself)")
        sink.raise_if_errors()
    return root, at


def _recursive_node(root: yaml.Node | None) -> yaml.Node | None:
    """A collection node that holds itself through aliases, or None. Depth first, without
    recursion: (node, its children not yet visited); a child already on the path closes a
    cycle, one finished before (an alias used twice) does not."""
    if root is None:
        return None
    on_path: set[int] = set()
    done: set[int] = set()
    stack = [(root, iter(_children(root)))]
    on_path.add(id(root))
    while stack:
        node, children = stack[-1]
        child = next(children, None)
        if child is None:
            stack.pop()
            on_path.discard(id(node))
            done.add(id(node))
        elif id(child) in on_path:
            return child
        elif id(child) not in done:
            on_path.add(id(child))
            stack.append((child, iter(_children(child))))
    return None


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.MappingNode):
        return [part for pair in node.value for part in pair]
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    return []
