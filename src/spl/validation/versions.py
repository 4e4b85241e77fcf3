"""A product line folder as it was at a git revision (``spl diff --rev REV DIR``, ``spl
validate --since REV``; docs/evolution.md, "Comparing two versions of a line").

The old version is read out of git into a temporary folder with ``git archive`` of the
tree ``REV:path``, so it is exactly what was committed (no checkout touches the work
tree, and the work tree's uncommitted edits are the new version). The copy is named as
the folder is, so the line has the same name in both versions.
"""

from __future__ import annotations

import io
import shutil
import subprocess
import tarfile
from pathlib import Path

from spl.core.diagnostics import ModelError
from spl.validation.bundle_changes import Version, relocated

# git gets this long for one question about a work tree (a slow file system, a big repository)
GIT_SECONDS = 300


class VersionProblem(Exception):
    """The old version cannot be read: not a git work tree, an unknown revision, no git;
    the message is one line saying which."""


def folder_at_revision(directory: Path, revision: str, into: Path) -> Path | None:
    """``directory`` as it was at ``revision``, written under ``into`` (a folder the
    caller owns and removes); None when the folder did not exist at that revision."""
    directory = Path(directory)
    if revision.startswith("-") or not revision.strip():
        raise VersionProblem(f"{revision!r} is not a git revision")
    top = _git(directory, "rev-parse", "--show-toplevel")
    if top is None:
        raise VersionProblem(f"{directory} is not in a git work tree")
    prefix = _git(directory, "rev-parse", "--show-prefix") or ""
    commit = _git(directory, "rev-parse", "--verify", "--quiet", f"{revision}^{{commit}}")
    if commit is None:
        raise VersionProblem(f"unknown git revision {revision!r} (in {top})")
    tree = f"{commit}:{prefix.rstrip('/')}" if prefix else commit
    if _git(directory, "cat-file", "-t", tree) != "tree":
        return None
    archive = _run(Path(top), "archive", "--format=tar", tree)  # from the top: a tree by its path
    if archive.returncode != 0:
        raise VersionProblem(f"git archive of {directory} at {revision!r} failed")
    target = Path(into) / directory.resolve().name
    if target.exists():
        shutil.rmtree(target)
    target.mkdir(parents=True)
    with tarfile.open(fileobj=io.BytesIO(archive.stdout)) as tar:
        tar.extractall(target, filter="data")  # no path may leave the folder
    return target


def _git(directory: Path, *arguments: str) -> str | None:
    """The first line git prints, or None when it fails."""
    result = _run(directory, *arguments)
    if result.returncode != 0:
        return None
    return result.stdout.decode("utf-8", "replace").strip()


def _run(directory: Path, *arguments: str) -> subprocess.CompletedProcess[bytes]:
    if shutil.which("git") is None:
        raise VersionProblem("git not found: install git to compare with a revision")
    try:
        return subprocess.run(
            ["git", "-C", str(directory), *arguments],
            capture_output=True,
            timeout=GIT_SECONDS,
            check=False,
        )
    except subprocess.TimeoutExpired:
        raise VersionProblem(f"git took over {GIT_SECONDS} s in {directory}") from None


def load_revision(directory: Path, revision: str, into: Path) -> Version | None:
    """The line in ``directory`` as it was at ``revision`` (None: no such folder then),
    loaded from its copy under ``into``; its models' errors are located as git names
    the files (``REV:folder/file.tsm:line:col``), not in the copy."""
    from spl.pipeline import load_line

    folder = folder_at_revision(directory, revision, into)
    if folder is None:
        return None
    try:
        return Version(folder, load_line(folder))
    except ModelError as exc:
        named = Path(f"{revision}:{Path(directory)}")
        raise ModelError([relocated(d, folder, named) for d in exc.diagnostics]) from None
