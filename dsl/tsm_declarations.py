"""A template's top-level declarations (data types, transforms, containers, bridges), each
with a print of what it holds, so that what an edit left alone can be told apart from
what it changed.

Why: the editor checks a product line after every change of its .tsm, and a change
touches one declaration or two, while building the line's model and resolving its
witness products cost time in proportion to the whole template (docs/performance.md,
"Editor latency"). Two readings of a .tsm whose declaration has the same print built the
same objects there: the same values, at the same places (a declaration whose lines moved
has another print), referring to the same things. A reference is printed as the path of
its target (the declaration it is in, then the feature and position at each step down),
never as an object, so prints compare across readings.

Each declaration also lists the declarations it refers into (a bridge into the two
containers it joins), the names declared in it (what a .rm may refer to), and, for a
container, whether a product may drop it whole: every node and store in it is optional.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from spl.emf import Step, adopt, copy_trees, element_at, fingerprint, forget_references
from spl.metamodels import tsm as tsm_metamodel

FEATURES = ("dataTypes", "transforms", "containers", "connections")  # in model order
Key = tuple[str, object]  # (feature, name), or (feature, position) for an unnamed bridge
Path = tuple[Key, tuple[Step, ...]]  # the declaration, then the steps down to the element


@dataclass(frozen=True)
class Declaration:
    key: Key
    print: tuple  # values and places, children, then the paths of its references
    refers_to: frozenset[Key]  # other declarations it refers into
    names: frozenset[str]  # every name declared in it, its own included
    droppable: bool  # a container all of whose nodes and stores are optional
    element: Any = field(compare=False)  # the declaration's element in the model read


@dataclass(frozen=True)
class Declarations:
    """Every declaration of a template, in model order, and the System's own values."""

    own: tuple  # the System's name and place
    items: dict[Key, Declaration]
    paths: dict[int, Path]  # id of each element of the model read -> its path


def declarations(system: Any) -> Declarations:
    """The declarations of ``system`` (a plain or a pyecore System)."""
    paths: dict[int, Path] = {}
    read = [
        _read(root, (feature, getattr(root, "name", None) or position), paths)
        for feature in FEATURES
        for position, root in enumerate(getattr(system, feature))
    ]
    items: dict[Key, Declaration] = {}
    for key, root, content, targets, names in read:
        found = [paths.get(t) for t in targets]
        # a target outside the model (none is) never prints as anything seen before
        printed = tuple(p or ("outside", t) for p, t in zip(found, targets, strict=True))
        refers_to = frozenset(p[0] for p in found if p is not None and p[0] != key)
        droppable = key[0] == "containers" and all(
            element.optional for element in (*root.nodes, *root.stores)
        )
        items[key] = Declaration(
            key, (content, printed), refers_to, frozenset(names), droppable, root
        )
    own = (system.name, system.srcFile, system.srcLine, system.srcCol)
    return Declarations(own, items, paths)


def _read(
    root: Any, key: Key, paths: dict[int, Path]
) -> tuple[Key, Any, tuple, list[int], set[str]]:
    """One declaration's content, the ids of what it refers to (in the order met) and the
    names declared in it; the path of each of its elements goes to ``paths``."""
    targets: list[int] = []
    names: set[str] = set()

    def visit(element: Any, path: tuple[Step, ...]) -> None:
        paths[id(element)] = (key, path)
        if isinstance(named := getattr(element, "name", None), str):
            names.add(named)

    content = fingerprint(root, lambda target: targets.append(id(target)), visit)
    return key, root, content, targets, names


def declaration_of(element: Any) -> Any:
    """The top-level declaration ``element`` is in (itself, for a declaration)."""
    while (owner := element.eContainer()) is not None and owner.eContainer() is not None:
        element = owner
    return element


@dataclass(frozen=True)
class BuiltTemplate:
    """A template's pyecore model, with the declarations of the plain model it was built
    from and each declaration's element in it."""

    system: Any
    declarations: Declarations
    elements: dict[Key, Any]
    rebuilt: frozenset[Key]  # the declarations copied afresh (all, for a first build)


def build(plain: Any, previous: BuiltTemplate | None = None) -> BuiltTemplate:
    """The pyecore model of the checked plain model ``plain``. Given the template built
    before from the same file, each declaration whose print is unchanged, and which
    refers only into declarations kept too, is taken over from it as it is (moved into
    the new System); the others are copied, their references into those taken over
    going to the elements there. The result is the model a full copy gives
    (``tests/dsl/test_tsm_declarations.py`` compares them through chains of edits)."""
    found = declarations(plain)
    kept: set[Key] = set()
    if previous is not None:
        before = previous.declarations.items
        kept = {k for k, d in found.items.items() if k in before and before[k].print == d.print}
        while True:  # a declaration referring into one copied afresh is copied too
            dropped = {k for k in kept if not found.items[k].refers_to <= kept}
            if not dropped:
                break
            kept -= dropped
    rebuilt = [k for k in found.items if k not in kept]
    if previous is not None:  # what is dropped must not stay recorded on what is kept
        for key, element in previous.elements.items():
            if key not in kept and previous.declarations.items[key].refers_to & kept:
                forget_references(element)

    def taken_over(target: Any) -> Any:
        key, inner = found.paths[id(target)]
        return element_at(previous.elements[key], inner)  # type: ignore[union-attr]

    copies, _ = copy_trees([found.items[k].element for k in rebuilt], taken_over)
    elements = {k: previous.elements[k] for k in kept} if previous is not None else {}
    elements.update(zip(rebuilt, copies, strict=True))
    T = tsm_metamodel()
    system = T.System(name=plain.name)
    system.srcFile, system.srcLine, system.srcCol = plain.srcFile, plain.srcLine, plain.srcCol
    for feature in FEATURES:
        members = [elements[k] for k in found.items if k[0] == feature]
        if members:
            adopt(system, feature, members)
    return BuiltTemplate(system, found, elements, frozenset(rebuilt))
