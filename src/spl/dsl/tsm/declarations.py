"""A template's declarations (data types, transforms, containers and their topics, nodes
and stores, bridges), each with a print of what it holds, so that what an edit left
alone can be told apart from what it changed.

Why: the editor checks a product line after every change of its .tsm, and a change
touches one declaration or two, while building the line's model and resolving its
witness products cost time in proportion to the whole template (docs/performance.md,
"Editor latency"). Two readings of a .tsm whose declaration has the same print built the
same objects there: the same values, at the same places relative to its first line (a
declaration that only moved has the same print), referring to the same things. A
reference is printed as the path of its target (the declaration it is in, then the
feature and position at each step down), never as an object, so prints compare across
readings.

A container's topics, nodes and stores are declarations of their own, keyed by the
container's key and theirs, so an edit inside a container of 2,000 nodes changes one of
them; the container's own print holds the rest of it (its values and endpoint). Each
declaration also lists the declarations it refers into (a bridge into the topics it
joins), the names declared in it (what a .rm may refer to), its lines, and whether a
product may drop it: a container all of whose nodes and stores are optional, or an
optional node or store.

A container whose text is the text it had, only moved, is not printed at all: the same
text holds the same values at the same places from its first line, under the same
names, so its print changes only with a declaration it refers into (a data type a store
keeps, a transform), and it is printed when one of those changed; its endpoint's
interfaces, which the bridges make, are printed each time. On a 10,000-node line an edit
inside one container left four of five containers to print whole, half of building the
template again.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, NamedTuple

from spl.core.emf import (
    Step,
    adopt,
    copy_trees,
    element_at,
    forget_references,
    move_lines,
    replace_members,
)
from spl.dsl.tsm.declaration_paths import MEMBERS, Key, Path, path_of, target_paths
from spl.dsl.tsm.plain_prints import ClassPrint, plain_fingerprint
from spl.metamodels import tsm as tsm_metamodel

FEATURES = ("dataTypes", "transforms", "containers", "connections")  # in model order
# a container's own print leaves its members out (MEMBERS: declarations of their own)
_SHELL = (("topics",), ("nodes",), ("stores",), ("endpoint", "interfaces"))


class Declaration(NamedTuple):  # a tuple: a 10,000-node template has some 15,000
    key: Key
    print: tuple  # values and places (from its first line), children, paths of references
    refers_to: frozenset[Key]  # other declarations it refers into
    names: frozenset[str]  # every name declared in it, its own included
    droppable: bool  # a container all of whose nodes and stores are optional, or an
    # optional node or store
    lines: tuple[int, int]  # the first and last line of its elements
    element: Any  # the declaration's element in the model read


@dataclass(frozen=True)
class Declarations:
    """Every declaration of a template, in model order (each container before its
    members), and the System's own values."""

    own: tuple
    items: dict[Key, Declaration]
    paths: dict[int, Path]  # id of each element of the model read -> its path
    unique: bool = True  # no two declarations with one key (the checks make sure)
    # each container's print as a whole, from its first line (given a reading before)
    wholes: dict[Key, tuple] = field(default_factory=dict)
    text: str | None = None  # what the model was read from, when known


def declarations(
    system: Any, before: Declarations | None = None, text: str | None = None
) -> Declarations:
    """The declarations of ``system`` (a plain or a pyecore System; ``text``: what it was
    read from, when known). Given those of a reading before, a container whose print as
    a whole is unchanged (it is the same, or only moved) keeps the declarations of its
    shell and members from then, moved along and holding the elements read now: it is
    read once, not once whole and once member by member; one that declares other
    members than before is read member by member at once; and one whose text is the
    text it had (:func:`_same_text`) is not read at all, unless it refers into a
    declaration the edit changed (then its print may have changed with it)."""
    paths: dict[int, Path] = {}
    read: list[tuple] = []  # (key, element, content, targets, names, lines) of each
    wholes: dict[Key, tuple] = {}
    whole: list[tuple[Key, Any]] = []  # containers to read whole
    unread: dict[Key, Any] = {}  # containers whose text is unchanged
    earlier = _by_container(before) if before is not None else {}
    same = _same_text(system, before, text) if before is not None else set()
    made: dict[type, ClassPrint] = {}  # the print of each plain class, made once here
    for feature in FEATURES:
        for position, root in enumerate(getattr(system, feature)):
            key = (feature, getattr(root, "name", None) or position)
            if feature != "containers":
                read.append(_read(root, key, paths, made))
            elif before is None or _other_members(root, earlier.get(key)):
                read += _read_members(root, key, paths, made)  # changed: no use reading it whole
            elif key in same:  # but its endpoint's interfaces, which the bridges make
                unread[key] = root
                read += [
                    _read(m, (*key, "interfaces", m.name), paths, made)
                    for m in _members(root, "interfaces")
                ]
            else:
                whole.append((key, root))
    taken: dict[Key, Declaration] = {}
    path_of_target = target_paths(system, paths)

    def take_over(key: Key, root: Any, read_interfaces: bool = False) -> None:
        """The container's declarations from the reading before, moved along (but its
        endpoint's interfaces, if ``read_interfaces``)."""
        assert before is not None
        moved = (root.srcLine or 0) - before.items[key].lines[0]
        now = {(f, m.name): m for f in MEMBERS for m in _members(root, f)}
        for old in earlier[key]:
            if read_interfaces and old.key[2:3] == ("interfaces",):
                continue
            element = root if len(old.key) == 2 else now[old.key[2:]]
            lines = (old.lines[0] + moved, old.lines[1] + moved)
            taken[old.key] = old._replace(lines=lines, element=element)

    def declare(found: list[tuple]) -> None:
        for key, root, content, targets, names, lines in found:
            printed = tuple(path_of_target(t) for t in targets)
            refers_to = frozenset(p[0] for p in printed if p[0] != key and p[0][0] != "outside")
            if len(key) == 2:
                droppable = key[0] == "containers" and all(
                    element.optional for element in (*root.nodes, *root.stores)
                )
            else:
                droppable = key[2] in ("nodes", "stores") and root.optional
            taken[key] = Declaration(
                key, (content, printed), refers_to, frozenset(names), droppable, lines, root
            )

    while True:
        for key, root in whole:
            content, targets = _read_whole(root, key, paths, made)
            wholes[key] = (content, tuple(path_of_target(t) for t in targets))
            if before is None or before.wholes.get(key) != wholes[key]:
                read += _read_members(root, key, paths, made)
            else:
                take_over(key, root)
        declare(read)
        read, whole = [], []
        # a container not read keeps its print while what it refers into keeps theirs
        changed = {k for k, d in taken.items() if before is None or _changed(before, k, d)}
        for key in list(unread):
            outside = {t for d in earlier[key] for t in d.refers_to if t[:2] != key}
            if any(t in changed or (t not in taken and t[:2] not in unread) for t in outside):
                whole.append((key, unread.pop(key)))
        if not whole:
            break
    for key, root in unread.items():
        assert before is not None
        take_over(key, root, read_interfaces=True)
        # its print as a whole is the one before if its interfaces' are, where they were
        moved = (root.srcLine or 0) - before.items[key].lines[0]
        interfaces = [d.key for d in earlier[key] if d.key[2:3] == ("interfaces",)]
        if key in before.wholes and all(
            not _changed(before, k, taken[k])
            and taken[k].lines[0] == before.items[k].lines[0] + moved
            for k in interfaces
        ):
            wholes[key] = before.wholes[key]
    keys = list(_keys(system))
    items = {key: taken[key] for key in keys}
    own = (system.name, system.srcFile, system.srcLine, system.srcCol)
    return Declarations(own, items, paths, len(items) == len(keys), wholes, text)


def _changed(before: Declarations, key: Key, declaration: Declaration) -> bool:
    """Whether a declaration read now prints other than it did (or is new)."""
    old = before.items.get(key)
    return old is None or old.print != declaration.print


def _same_text(system: Any, before: Declarations, text: str | None) -> set[Key]:
    """The containers whose text, from their first line to the next top-level
    declaration's (or the end), is the text the same container had before: they hold
    the same values at the same places from their first line, under the same names."""
    if text is None or before.text is None:
        return set()
    starts = sorted(
        (root.srcLine or 0, (feature, getattr(root, "name", None) or position))
        for feature in FEATURES
        for position, root in enumerate(getattr(system, feature))
    )
    old_starts = sorted((d.lines[0], k) for k, d in before.items.items() if len(k) == 2)
    now, old = _spans(starts, text), _spans(old_starts, before.text)
    now_lines, old_lines = text.split("\n"), before.text.split("\n")
    return {
        key
        for key, (first, end) in now.items()
        if key[0] == "containers"
        and key in old
        and old_lines[old[key][0] - 1 : old[key][1] - 1] == now_lines[first - 1 : end - 1]
    }


def _spans(starts: list[tuple[int, Key]], text: str) -> dict[Key, tuple[int, int]]:
    """Each top-level declaration's first line and the first line after it."""
    ends = [first for first, _ in starts[1:]] + [text.count("\n") + 2]
    return {key: (first, end) for (first, key), end in zip(starts, ends, strict=False)}


def _keys(system: Any) -> Iterator[Key]:
    """Every declaration's key, in model order (a container, then its members)."""
    for feature in FEATURES:
        for position, root in enumerate(getattr(system, feature)):
            key = (feature, getattr(root, "name", None) or position)
            yield key
            if feature == "containers":
                for member_feature in MEMBERS:
                    for member in _members(root, member_feature):
                        yield (*key, member_feature, member.name)


def _other_members(container: Any, before: list[Declaration] | None) -> bool:
    """Whether ``container`` declares other members than it did (the shell and members
    read ``before``, none for a container read the first time)."""
    if before is None:
        return False
    now = [(f, m.name) for f in MEMBERS for m in _members(container, f)]
    return now != [d.key[2:] for d in before[1:]]


def _by_container(found: Declarations) -> dict[Key, list[Declaration]]:
    grouped: dict[Key, list[Declaration]] = {}
    for key, declaration in found.items.items():
        if key[0] == "containers":
            grouped.setdefault(key[:2], []).append(declaration)
    return grouped


def _members(container: Any, feature: str) -> Any:
    """A container's members of ``feature`` (its endpoint's, for interfaces)."""
    if feature != "interfaces":
        return getattr(container, feature)
    return container.endpoint.interfaces if container.endpoint is not None else ()


def _read_members(
    root: Any, key: Key, paths: dict[int, Path], made: dict[type, ClassPrint]
) -> list[tuple]:
    """A container's shell and members, each read as a declaration (:func:`_read`)."""
    read = [_read(root, key, paths, made, _SHELL)]
    for member_feature in MEMBERS:
        for member in _members(root, member_feature):
            read.append(_read(member, (*key, member_feature, member.name), paths, made))
    return read


def _read(
    root: Any,
    key: Key,
    paths: dict[int, Path],
    made: dict[type, ClassPrint],
    leave_out: tuple[tuple[str, ...], ...] = (),
) -> tuple[Key, Any, tuple, list[int], set[str], tuple[int, int]]:
    """One declaration's content, what it refers to (in the order met), the
    names declared in it and its lines; the path of each of its elements goes to
    ``paths`` (``made``: :func:`spl.dsl.tsm.plain_prints.plain_fingerprint`'s)."""
    targets: list[Any] = []
    names: set[str] = set()
    first = root.srcLine or 0
    last = [first]

    def visit(element: Any, path: tuple[Step, ...]) -> None:
        paths[id(element)] = (key, path)
        if isinstance(named := getattr(element, "name", None), str):
            names.add(named)
        if (line := element.srcLine or 0) > last[0]:
            last[0] = line

    content = plain_fingerprint(root, targets.append, visit, first, leave_out, made)
    return key, root, content, targets, names, (first, last[0])


def _read_whole(
    root: Any, key: Key, paths: dict[int, Path], made: dict[type, ClassPrint]
) -> tuple[tuple, list[int]]:
    """A container's content as a whole (lines from its first), and what it refers to;
    the path of each element goes to ``paths``, from the declaration it is in (the
    shell, or a member)."""
    targets: list[Any] = []
    member: list[Any] = [key, 0]  # the member being read, and the depth of its root

    def visit(element: Any, path: tuple[Step, ...]) -> None:
        depth = 1 if path and path[0][0] in MEMBERS else 0
        if len(path) > 1 and path[0][0] == "endpoint" and path[1][0] == "interfaces":
            depth = 2
        if depth == 0:
            paths[id(element)] = (key, path)
            return
        if len(path) == depth:
            member[:] = (*key, path[depth - 1][0], element.name), depth
        paths[id(element)] = (member[0], path[member[1] :])

    content = plain_fingerprint(root, targets.append, visit, root.srcLine or 0, (), made)
    return content, targets


@dataclass(frozen=True)
class BuiltTemplate:
    """A template's pyecore model, with the declarations of the plain model it was built
    from and each declaration's element in it."""

    system: Any
    declarations: Declarations
    elements: dict[Key, Any]
    rebuilt: frozenset[Key]  # the declarations copied afresh (all, for a first build)


_NOTHING = Declarations((), {}, {})  # read before a first build: its containers whole too


def build(
    plain: Any, previous: BuiltTemplate | None = None, text: str | None = None
) -> BuiltTemplate:
    """The pyecore model of the checked plain model ``plain``. Given the template built
    before from the same file, each declaration whose print is unchanged, which refers
    only into declarations kept too, and whose container (for a member) is kept, is
    taken over from it as it is, its lines moved where the edit moved them; a container
    taken over gets its members anew, in order. The others are copied, their
    references into those taken over going to the elements there. The result is the
    model a full copy gives (``tests/dsl/test_tsm_declarations.py`` compares them
    through chains of edits)."""
    found = declarations(plain, previous.declarations if previous is not None else _NOTHING, text)
    items = found.items
    kept: set[Key] = set()
    if not (found.unique and previous is not None and previous.declarations.unique):
        previous = None  # keys tell declarations apart: without, a copy of them all
    if previous is not None:
        before = previous.declarations.items
        kept = {k for k, d in items.items() if k in before and before[k].print == d.print}
        while True:  # a declaration referring into one copied afresh is copied too
            dropped = {
                k
                for k in kept
                if not items[k].refers_to <= kept or (len(k) == 4 and k[:2] not in kept)
            }
            if not dropped:
                break
            kept -= dropped
        for key, declaration in before.items():  # what goes must not stay recorded on
            if key not in kept and declaration.refers_to & kept:  # what is kept
                forget_references(previous.elements[key])
        for key in kept:
            moved = items[key].lines[0] - before[key].lines[0]
            if moved:
                move_lines(previous.elements[key], moved, _SHELL if len(key) == 2 else ())
    rebuilt = [k for k in items if k not in kept]

    def taken_over(target: Any) -> Any:
        key, inner = found.paths.get(id(target)) or path_of(target)
        return element_at(previous.elements[key], inner)  # type: ignore[union-attr]

    # a declaration in one copied afresh (a member of a container copied) is copied with it
    roots = [items[k].element for k in rebuilt if len(k) == 2 or k[:2] in kept]
    _, copies = copy_trees(roots, taken_over)
    elements = {k: previous.elements[k] for k in kept} if previous is not None else {}
    elements.update((k, copies[id(items[k].element)]) for k in rebuilt)
    held: dict[Key, list[Any]] = {}  # a container taken over gets its members anew
    for key in items:
        if len(key) == 4 and key[:2] in kept:
            held.setdefault(key[:3], []).append(elements[key])
    for key in kept:
        if len(key) == 2 and key[0] == "containers":
            container = elements[key]
            for feature in MEMBERS:
                owner = container if feature != "interfaces" else container.endpoint
                if owner is not None:
                    replace_members(owner, feature, held.get((*key, feature), []))
    T = tsm_metamodel()
    system = T.System(name=plain.name)
    system.srcFile, system.srcLine, system.srcCol = plain.srcFile, plain.srcLine, plain.srcCol
    for feature in FEATURES:
        members = [elements[k] for k in items if len(k) == 2 and k[0] == feature]
        if members:
            adopt(system, feature, members)
    return BuiltTemplate(system, found, elements, frozenset(rebuilt))
