"""The Template System Model language (.tsm): parse, resolve names, check, build pyecore.

The grammar (``tsm.tx``) only shapes the text; everything that needs a reason
(ROS naming rules, references, types, credentials, transform expressions) is checked
by the builder so every problem is reported at once, at the column of the offending
name, as ``file:line:col: error: message``. The result is a ``tsm.System`` of
``src/spl/metamodels/tsm.ecore``; nothing in a model is ever evaluated.

The builder is split by what the language declares: containers (``tsm_containers``),
nodes (``tsm_nodes``), stores, writers and readers (``tsm_data``), data types and
transforms (``tsm_transforms``) and bridges (``tsm_bridges``, which also names the
endpoint interfaces a bridge becomes); ``tsm_names`` holds the names and locations
they share, ``tsm_syntax`` the wording of syntax errors. The text is read by
``tsm_reader`` (fast) or, for what it leaves, by textX: both give the same tree.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import Any

from spl.core.cyclic_gc import without_cyclic_gc
from spl.core.diagnostics import (
    Diagnostic,
    DiagnosticSink,
    Location,
    ModelError,
    counted,
)
from spl.core.emf import copy_model
from spl.dsl.textx_text import model_from_text
from spl.dsl.tsm import (
    bridges as tsm_bridges,
    containers as tsm_containers,
    declarations as tsm_declarations,
    incremental as tsm_incremental,
    plain as tsm_plain,
    reader as tsm_reader,
    syntax_excerpt as tsm_syntax_excerpt,
    transform_types,
    transforms as tsm_transforms,
)
from spl.dsl.tsm.bridges import (
    bridged_clients,
    endpoint_client_name,
    endpoint_name_choices,
    endpoint_publisher_name,
    endpoint_server_name,
    endpoint_subscriber_name,
)
from spl.dsl.tsm.names import Names
from spl.dsl.tsm.syntax import kind, syntax_diagnostic
from spl.dsl.workspace import Workspace, last_built, text_of
from spl.metamodels.interface_kinds import kind_of

__all__ = [
    "check_file",
    "check_text",
    "endpoint_client_name",
    "endpoint_name_choices",
    "endpoint_publisher_name",
    "endpoint_server_name",
    "endpoint_subscriber_name",
    "normalize_endpoints",
    "parse_file",
    "parse_text",
    "summary",
]


# -- public entry points ------------------------------------------------------------------
@cache
def _grammar() -> Any:
    from textx import metamodel_from_file  # only what the fast reader leaves needs textX

    return metamodel_from_file(
        str(Path(__file__).with_name("tsm.tx")), autokwd=True, use_regexp_group=False
    )


def parse_file(path: str | Path, workspace: Workspace | None = None) -> Any:
    """Parse and check a .tsm file; raise ModelError with every problem found. Read as
    the editor's ``workspace`` has it, when given (:mod:`spl.dsl.workspace`)."""
    return parse_text(text_of(path, workspace), str(path), workspace)


def parse_text(text: str, filename: str = "<string>", workspace: Workspace | None = None) -> Any:
    """Parse and check .tsm text; ``filename`` is what diagnostics name. In an editor's
    ``workspace`` that keeps its line checks' models, a text built before gives the same
    model, and a changed one is built from what the file's last template holds."""
    if workspace is not None:
        workspace.refused.raise_if_refused(text, filename)
    last = workspace.models if workspace is not None else None
    known = last_built(last.systems, text, filename) if last is not None else None
    if known is not None:
        return known
    # Built and checked over plain objects, then set up in pyecore in one pass, which
    # skips pyecore's descriptors, type checks and notifications: half the time of
    # building through them (a 10,000-node file: 0.56 s against 1.06 s), the same
    # model (tests/dsl/test_tsm_plain.py compares the two builds).
    plain = check_text(text, filename, workspace=workspace)
    # the model's objects all stay alive: the collector's passes over them free nothing
    with without_cyclic_gc():
        if last is None:
            return copy_model(plain)
        # the editor's: what the last build of the file holds and the edit left alone is
        # taken over, and the declarations are kept for the next build
        built = tsm_declarations.build(plain, last.templates.get(filename), text)
    last.templates[filename] = built
    last.systems[filename] = (text, built.system)
    return built.system


def check_file(
    path: str | Path,
    trees: tsm_incremental.Trees | None = None,
    workspace: Workspace | None = None,
) -> Any:
    """``spl check FILE.tsm``: every problem of a .tsm file (raised as a ModelError), or
    the checked System made of plain objects (:mod:`spl.dsl.tsm.plain`)."""
    return check_text(text_of(path, workspace), str(path), trees, workspace)


def check_text(
    text: str,
    filename: str = "<string>",
    trees: tsm_incremental.Trees | None = None,
    workspace: Workspace | None = None,
) -> Any:
    """The problems :func:`parse_text` finds, found by the same builder over plain
    objects, several times faster; for checks that need no pyecore model (the command
    line's and the editor's diagnostics of one .tsm). With ``trees`` (the last reading
    of each file), a file read before is read again incrementally. In a ``workspace``,
    a text refused before is refused again without building anything, and one checked
    last is not checked again where the workspace keeps its line checks' models."""
    if workspace is not None:
        workspace.refused.raise_if_refused(text, filename)
    last = workspace.models if workspace is not None else None
    known = last_built(last.checked, text, filename) if last is not None else None
    if known is not None:
        return known
    try:
        with without_cyclic_gc():
            system = _parse(text, filename, tsm_plain.metamodel(), trees)
    except ModelError as exc:
        if workspace is not None:
            workspace.refused.refuse(text, filename, exc.diagnostics)
        raise
    if workspace is not None:
        workspace.refused.built(filename)
    if last is not None:
        last.checked[filename] = (text, system)
    return system


def _parse(
    text: str, filename: str, metamodel: Any, trees: tsm_incremental.Trees | None = None
) -> Any:
    sink = DiagnosticSink()
    try:
        # the fast reader takes what it can; textX parses the rest and words syntax errors
        if trees is not None:
            tree, places = trees.read(filename, text) or (None, None)
        else:
            tree, places = tsm_reader.read(text), None
        if tree is None:
            tree = _textx_tree(text, filename)
        if isinstance(tree, str):  # textX gives '' for text holding no element at all
            return metamodel.System(srcFile=filename, srcLine=1, srcCol=1)
        offset = places.offset if places is not None else None
        system = _build(tree, Names(text, filename, sink, metamodel, offset))
        sink.raise_if_errors()
        # types of transform expressions, once every name is known to resolve
        sink.diagnostics.extend(transform_types.check_system(system))
    except RecursionError:  # only transform expressions nest; a hostile file nests deep
        message = "a transform expression is nested too deeply or too long"
        where = _deepest(text, filename)
        raise ModelError([Diagnostic(where, message)]) from None
    sink.raise_if_errors()
    return system


def _deepest(text: str, filename: str) -> Location:
    """Where an expression too deep or too long for the parsers is: the outermost
    parenthesis of the most deeply nested ones, or else the start of the longest line."""
    depth = deepest = 0
    at = outermost = -1
    for offset, char in enumerate(text):
        if char == "(":
            outermost = offset if depth == 0 else outermost
            depth += 1
            if depth > deepest:
                deepest, at = depth, outermost
        elif char == ")":
            depth = max(depth - 1, 0)
    lines = text.split("\n")
    if deepest < 32:  # a long chain (a + a + ...) rather than nesting
        row = max(range(len(lines)), key=lambda i: len(lines[i]))
        return Location(filename, row + 1, 1)
    row = text.count("\n", 0, at)
    return Location(filename, row + 1, at - (text.rfind("\n", 0, at) + 1) + 1)


def _textx_tree(text: str, filename: str) -> Any:
    """textX's parse tree of ``text``; a syntax error as a located ModelError."""
    from textx import TextXSyntaxError

    excerpt = tsm_syntax_excerpt.error_excerpt(text)
    try:
        if excerpt is not None:
            # the reader gave up where it did: textX words the error from an excerpt
            model_from_text(_grammar(), excerpt, filename)
        return model_from_text(_grammar(), text, filename)
    except TextXSyntaxError as exc:
        raise ModelError([syntax_diagnostic(exc, text, filename)]) from None


def _build(tree: Any, names: Names) -> Any:
    """The System of a parse tree: every element declared in file order, then every
    reference resolved, then the bridges (which need the resolved clients)."""
    T = names.T
    names.system = system = T.System()
    if tree.name is not None:
        system.name = tree.name.name
        names.locate(system, tree.name)
    else:
        names.locate(system, tree)
    bridges = []
    for element in tree.elements:
        rule = kind(element)
        if rule == "DataType":
            system.dataTypes.append(tsm_transforms.data_type(names, element))
        elif rule == "Transform":
            system.transforms.append(tsm_transforms.transform(names, element))
        elif rule in ("RobotContainer", "CloudContainer"):
            system.containers.append(tsm_containers.container(names, element))
        else:
            bridges.append(element)
    for resolve, element, element_tree in names.pending:
        resolve(names, element, element_tree)
    wiring = tsm_bridges.Bridges(names)
    for bridge in bridges:
        wiring.add(bridge)
    return system


def summary(system: Any) -> str:
    """One line of counts for ``spl check``."""
    nodes = [n for c in system.containers for n in c.nodes]
    parts = [
        counted(len(system.containers), "container"),
        counted(len(nodes), "node"),
        counted(sum(len(c.topics) for c in system.containers), "topic"),
        counted(sum(len(n.interfaces) for n in nodes), "interface"),
        counted(len(system.connections), "bridge"),
    ]
    stores = sum(len(c.stores) for c in system.containers)
    if system.dataTypes or system.transforms or stores:
        parts += [
            counted(len(system.dataTypes), "data type"),
            counted(len(system.transforms), "transform"),
            counted(stores, "store"),
        ]
    return ", ".join(parts)


def normalize_endpoints(system: Any) -> None:
    """Order endpoint interfaces the way parsing the printed model creates them.

    The printer writes connections as bridges in ``System.connections`` order and the
    parser creates endpoint interfaces in bridge order; a transformation that adds or
    removes endpoint interfaces calls this so that print/parse round trips stay exact.
    """
    order: dict[int, int] = {}

    def see(interface: Any) -> None:
        order.setdefault(id(interface), len(order))

    for connection in system.connections:
        source, target = connection.source, connection.target
        if kind_of(source).serves:  # a stand-in server: printed only while a client calls it
            if any(True for _ in bridged_clients(source)):
                see(source)
                see(target)
        else:
            see(source)
            see(target)
    for container in system.containers:
        interfaces = list(container.endpoint.interfaces) if container.endpoint else []
        ranked = sorted(enumerate(interfaces), key=lambda p: order.get(id(p[1]), len(order) + p[0]))
        if [i for _, i in ranked] != interfaces:
            container.endpoint.interfaces.clear()
            container.endpoint.interfaces.extend(i for _, i in ranked)
