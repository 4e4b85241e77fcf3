"""``spl import launch``: a product line from the ROS 1 launch files a team already runs.

The launch files are read by roslaunch's own loader once per combination of the
argument values asked for (:mod:`.reading`), the combinations are compared into
features, optional nodes and parameter statements (:mod:`.variability`), and the line
is written as text (:mod:`.line_text`), checked by spl's own reading of a line before
it replaces anything (docs/import.md).
"""

from __future__ import annotations

import fnmatch
import os
import re
import shutil
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from spl.importers.graph.master import Graph
from spl.importers.launch.line_text import (
    fm_text,
    graph_omissions,
    product_files,
    report_text,
    rm_text,
    tsm_text,
)
from spl.importers.launch.reading import (
    Argument,
    ImportRefused,
    LoadedNode,
    Omission,
    RosMissing,
    load_combinations,
    parse_argument,
)
from spl.importers.launch.variability import ImportedLine, build_line
from spl.importers.naming import feature_name

__all__ = [
    "ImportRefused",
    "LaunchImport",
    "RosMissing",
    "import_launch",
    "parse_argument",
    "refuse_existing",
    "write_line",
]

REPORT = "import-report.txt"


@dataclass(frozen=True)
class LaunchImport:
    line: ImportedLine
    files: dict[str, str]  # path in the output folder -> text

    @property
    def warnings(self) -> list[Omission]:
        return self.line.warnings


def import_launch(
    files: list[Path],
    arguments: list[Argument],
    package_path: list[Path],
    robot_patterns: Sequence[str] = (),
    graph: Graph | None = None,
) -> LaunchImport:
    """The files of the product line the launch files describe (nothing is written); the
    nodes a live ``graph`` of the same system runs get its topics and services."""
    stem = re.sub(r"[^A-Za-z0-9_]", "_", files[0].name.split(".")[0])
    stem = stem if re.match(r"[A-Za-z]", stem) else f"line_{stem}"  # also the endpoint user
    name = feature_name(stem, set(), f"{stem}_line")
    combinations, warnings = load_combinations(files, arguments, package_path)

    def is_robot(node: LoadedNode) -> bool:
        if not robot_patterns:
            return False
        names = (node.ros_name, node.name, node.machine)
        return any(fnmatch.fnmatchcase(n, p) for p in robot_patterns for n in names if n)

    line = build_line(name, arguments, combinations, warnings, is_robot)
    if graph is not None:
        line.warnings.extend(graph_omissions(line, graph))
    sources = [f.name for f in files]
    texts = {
        f"{name}.tsm": tsm_text(line, sources, graph),
        f"{name}.fm": fm_text(line, sources),
        f"{name}.rm": rm_text(line, name, sources),
        **product_files(line),
        REPORT: report_text(line),
    }
    return LaunchImport(line, texts)


def write_line(
    files: dict[str, str], out: Path, check: Callable[[Path], list[str]] | None = None
) -> None:
    """The line's files in ``out``, all or none: written into a fresh sibling folder,
    checked there (``check`` gives the errors of a line folder), then renamed into place.
    ``out`` must not exist or be empty: an imported line is a starting point that will
    be edited, never overwritten."""
    refuse_existing(out)
    parent = out.parent if str(out.parent) else Path(".")
    parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=parent))
    try:
        for relative, text in files.items():
            target = staging / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(text, encoding="utf-8")
        errors = check(staging) if check is not None else []
        if errors:
            raise ImportRefused(f"the imported line does not pass spl check: {errors[0]}")
        os.chmod(staging, 0o777 & ~_umask())
        if out.exists():
            out.rmdir()
        os.rename(staging, out)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def refuse_existing(out: Path) -> None:
    """Refused: ``out`` exists and is not an empty folder (checked before loading too)."""
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise ImportRefused(f"{out} exists and is not an empty folder; import into a new one")


def _umask() -> int:
    mask = os.umask(0o022)  # the only way to read it is to set it
    os.umask(mask)
    return mask
