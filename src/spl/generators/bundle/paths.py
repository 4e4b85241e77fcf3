"""Bundle paths: one file per path, and no two paths that land on one file.

Generators build their files as ``{bundle path: bytes}``; a plain dict silently keeps
the last of two writes to one path, which is how two stores of one name once shared
``services/<store>/`` without anyone noticing. :class:`BundleFiles` refuses a second
write, and :func:`check_paths` refuses paths that are different strings but one file
on disk (``a//b``, ``A/B`` next to ``a/b`` on a case-insensitive file system) or a
file where another path needs a folder. Both are internal checks: a product line can
never cause them, only a generator bug, so they fail loudly rather than write a
bundle that is missing a file.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass


@dataclass(frozen=True)
class Skipped:
    """A file a generator could not produce on this machine, and why (one line): the
    bundle is written without it and its manifest says so."""

    reason: str


# files by bundle path, as a mapping or as (path, data) pairs
Files = Mapping[str, bytes] | Iterable[tuple[str, bytes]]


class BundlePathClash(RuntimeError):
    """Two files of one bundle would be written to one path (a generator bug)."""


class BundleFiles(dict[str, bytes]):
    """``{bundle path: bytes}`` that refuses to write a path twice."""

    def __init__(self, files: Files = ()) -> None:
        super().__init__()
        self.update(files)

    def __setitem__(self, path: str, data: bytes) -> None:
        if path in self:
            raise BundlePathClash(f"two files for bundle path {path}")
        super().__setitem__(path, data)

    def update(self, files: Files = ()) -> None:  # type: ignore[override]
        for path, data in files.items() if isinstance(files, Mapping) else files:
            self[path] = data


def check_paths(paths: Iterable[str]) -> None:
    """Every path relative, normalised and its own file: no ``.``/``..``/empty part, no
    two paths equal but for case, no path that is the folder of another."""
    seen: dict[str, str] = {}
    files: list[tuple[str, list[str]]] = []
    for path in paths:
        parts = path.split("/")
        if path.startswith("/") or any(part in ("", ".", "..") for part in parts):
            raise BundlePathClash(f"bundle path {path!r} is not a plain relative path")
        other = seen.setdefault(path.casefold(), path)
        if other != path:
            raise BundlePathClash(
                f"bundle paths {other} and {path} are one file on a case-insensitive file system"
            )
        files.append((path, parts))
    # every folder a path needs, by string: the paths are plain (checked above), so their
    # folders are their leading parts (PurePosixPath.parents gives the same plus ".",
    # which no plain path is, at ten times the cost: 0.5 ms of every product's bundle)
    folders = {
        "/".join(parts[:end]).casefold() for _, parts in files for end in range(1, len(parts))
    }
    for path, _ in files:
        if path.casefold() in folders:
            raise BundlePathClash(f"bundle path {path} is a file and the folder of another")
