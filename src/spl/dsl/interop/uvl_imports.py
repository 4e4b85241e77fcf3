"""UVL language levels (``include``) and composition (``imports``), for the UVL reader.

A mixin of :class:`spl.dsl.interop.uvl_reader.UvlReader`, which owns the tokens, the
position and the diagnostics (docs/fm.md, "Language levels and composition").

* ``include`` names the language levels a model uses. spl reads every level (Boolean,
  Arithmetic, Type and their minor levels); a name that is none is refused at its line.
* ``imports`` names other UVL files by a dotted path beside the importing file
  (``submodels.Size`` is ``submodels/Size.uvl``), each under an alias (``as top``; the
  path without one). The importing tree places an imported model's root as
  ``alias.Root``, and the whole imported tree, constraints included, joins the model
  there; constraints reach any imported feature as ``alias.Feature`` (and through the
  imported model's own imports, ``alias.inner.Feature``). Those dotted names are the
  features' names as written: reports show them so. A missing file and an import cycle
  are refused at the import.
"""

from __future__ import annotations

from collections.abc import Callable
from itertools import pairwise
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

from spl.core.diagnostics import ModelError
from spl.dsl.fm.plain import Constraint, Feature, FeatureModel, Source
from spl.dsl.interop.interchange import ORIGINAL_NAME

if TYPE_CHECKING:
    from spl.core.diagnostics import DiagnosticSink

MAJOR_LEVELS = ("Boolean", "Arithmetic", "Type")
MINOR_LEVELS = (
    "group-cardinality",
    "feature-cardinality",
    "aggregate-function",
    "string-constraints",
)


class Imported:
    """One imported model, read with its own imports composed in, and whether the
    importing tree has placed its root yet (once at most)."""

    def __init__(self, model: FeatureModel) -> None:
        self.model = model
        self.placed = False


class ImportReader:
    """The ``include`` and ``imports`` rules; the reader class provides the state below."""

    tokens: list[tuple[str, str, int]]
    index: int
    source: Source
    sink: DiagnosticSink
    importing: tuple[str, ...]  # files being read, outermost first (cycles)
    imported: dict[str, Imported]  # alias -> imported model
    unread: set[str]  # aliases of imports refused (their features are not reported again)
    error: Callable[[int, str], None]
    fail: Callable[[str], NoReturn]
    expect: Callable[[str, str], tuple[str, str, int]]

    def lines(self) -> list[list[tuple[str, str, int]]]:
        """The indented lines after a section keyword, as token lists."""
        self.index += 1
        self.expect("NL", "a line break")
        self.expect("INDENT", "its entries, indented")  # the grammar's INDENT: one at least
        found: list[list[tuple[str, str, int]]] = []
        while self.tokens[self.index][0] not in ("DEDENT", "EOF"):
            start = self.index
            while self.tokens[self.index][0] not in ("NL", "EOF", "INDENT", "DEDENT"):
                self.index += 1
            if self.tokens[self.index][0] != "NL":
                self.fail("expected one entry a line")
            found.append(self.tokens[start : self.index])
            self.index += 1
        self.expect("DEDENT", "the end of the section")
        return found

    def language_levels(self) -> None:
        """``include`` lines: ``Major(.minor|.*)?``: every level is read."""
        for line in self.lines():
            level = "".join(text for _, text, _ in line)
            major, _, minor = level.partition(".")
            position = line[0][2]
            # the grammar's tokens: the major level one word, the minor one after the dot
            # (blanks may stand only around the dot)
            gaps = [a[2] + len(a[1]) != b[2] for a, b in pairwise(line)]
            apart = any(
                gap and "." not in (line[at][1], line[at + 1][1]) for at, gap in enumerate(gaps)
            )
            written = line[0][1] + "".join(
                (" " if gap else "") + token[1] for gap, token in zip(gaps, line[1:], strict=True)
            )
            if apart or major not in MAJOR_LEVELS or (minor and minor not in (*MINOR_LEVELS, "*")):
                self.error(
                    position,
                    f"expected a language level ({', '.join(MAJOR_LEVELS)}, each optionally "
                    f"followed by .minor or .*), got {written}",
                )

    def imports(self, read_file: Callable[[Path, tuple[str, ...]], FeatureModel]) -> None:
        """``imports`` lines: ``path (as alias)?``, each file read beside this one."""
        here = Path(self.source.file).parent
        for line in self.lines():
            parts, alias = _import_line(line)
            position = line[0][2]
            if parts is None:
                self.error(position, "expected an import: a dotted path, optionally 'as ALIAS'")
                continue
            path = here.joinpath(*parts[:-1], parts[-1] + ".uvl")
            name = alias or ".".join(parts)
            key = str(path.resolve())
            if name in self.imported:
                self.error(position, f"{name} is imported twice")
            elif key in self.importing:
                cycle = " -> ".join(Path(file).name for file in (*self.importing, key))
                self.error(position, f"import cycle: {cycle}")
            elif not path.is_file():
                self.error(position, f"imported model {'.'.join(parts)} not found: no file {path}")
            else:
                try:
                    model = read_file(path, (*self.importing, key))
                except ModelError as exc:  # its own problems, located in it
                    self.sink.diagnostics.extend(exc.diagnostics)
                    self.unread.add(name)
                    continue
                self.imported[name] = Imported(model)
                continue
            self.unread.add(name)

    def placed(self, parts: list[str], position: int) -> tuple[str, Feature] | None:
        """The imported root a dotted tree entry ``alias.Root`` places, and its alias;
        None (reported) when it names none."""
        alias = ".".join(parts[:-1])
        imported = self.imported.get(alias)
        if imported is None and alias in self.unread:
            return None  # refused at its import already
        if imported is None:
            known = ", ".join(sorted(self.imported)) or "none"
            self.error(position, f"{alias} is not an imported model (imports: {known})")
            return None
        root = imported.model.root
        if root is None or written_name(root) != parts[-1]:
            written = written_name(root) if root is not None else "?"
            self.error(
                position,
                f"only the root feature of imported model {alias} ({written}) can be placed "
                "in the tree",
            )
            return None
        if imported.placed:
            self.error(position, f"imported model {alias} is placed twice")
            return None
        imported.placed = True
        return alias, root


def _import_line(line: list[tuple[str, str, int]]) -> tuple[list[str] | None, str | None]:
    """``(id .)* id (as (id .)* id)?`` as (path parts, alias) or (None, None)."""
    words: list[list[str]] = [[]]
    expecting_name = True
    for kind, text, _ in line:
        if expecting_name and kind in ("id", "qid"):
            words[-1].append(text[1:-1] if kind == "qid" else text)
            expecting_name = False
        elif not expecting_name and kind == ".":
            expecting_name = True
        elif not expecting_name and kind == "as" and len(words) == 1:
            words.append([])
            expecting_name = True
        else:
            return None, None
    if expecting_name:
        return None, None
    return words[0], (".".join(words[1]) if len(words) > 1 else None)


def written_name(feature: Feature) -> str:
    """A plain feature's name as its file writes it."""
    for attribute in feature.attributes:
        if attribute.name == ORIGINAL_NAME:
            return attribute.value
    return feature.name


def splice(alias: str, root: Feature) -> list[tuple[Feature, str]]:
    """The imported tree under ``root``, pre-order, each feature with its name as the
    importing model writes it (``alias.Name``); their kept original names are dropped
    (the importing model names them afresh)."""
    found: list[tuple[Feature, str]] = []
    stack = [root]
    while stack:
        feature = stack.pop()
        found.append((feature, f"{alias}.{written_name(feature)}"))
        feature.attributes = [a for a in feature.attributes if a.name != ORIGINAL_NAME]
        stack.extend(reversed([child for group in feature.groups for child in group.features]))
    return found


def renamed(constraint: Constraint, names: dict[str, str]) -> Constraint:
    """An imported model's constraint over the importing model's identifiers (``names``:
    the imported identifier -> the importing one)."""
    done: list[tuple] = []
    work: list[tuple[tuple, bool]] = [(constraint.formula, False)]
    while work:
        node, built = work.pop()
        head = node[0]
        if head == "ref":
            done.append(("ref", names[node[1]], *node[2:]))
        elif not built:
            work.append((node, True))
            work.extend(
                (child, False) for child in reversed(node[1:2] if head == "not" else node[1:3])
            )
        elif head == "not":
            done.append(("not", done.pop(), *node[2:]))
        else:
            right, left = done.pop(), done.pop()
            done.append((head, left, right, *node[3:]))
    return Constraint(constraint.source, constraint.position, done[0])
