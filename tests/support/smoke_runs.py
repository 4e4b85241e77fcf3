"""Running ``spl smoke`` and ``spl validate --smoke`` for real in the tests, and proving
afterwards that nothing they started is still running.

Every command runs in a subprocess whose environment carries a fresh tag; everything it
starts (roscore, rosmaster, rosout, roslaunch, stand-ins, relays) inherits the tag, so
a scan of ``/proc`` finds exactly the processes of that one command, even while other
tests run their own ROS graphs next to it. The caller's ``ROS_MASTER_URI`` points at a
port nothing listens on: a rehearsal that used it could not pass.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
import uuid
from pathlib import Path
from typing import Any

from spl.generators.bundle.writer import bundle_files, write_bundle
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file, selection_from_list

ROOT = Path(__file__).resolve().parents[2]
TAG = "SPL_TEST_SMOKE_TAG"
ROS_PROGRAMS = ("roscore", "rosmaster", "rosout", "roslaunch", "standin.py")


def write_product(line_dir: Path, selection: str | Path, out: Path) -> Path:
    """Resolve a product (a feature list or a selection file) and write its bundle."""
    line = load_product_line(line_dir)
    if isinstance(selection, Path):
        chosen = load_selection_file(selection)
    else:
        chosen = selection_from_list(selection)
    write_bundle(bundle_files(resolve(line, chosen).product), out)
    return out


def spl_command() -> list[str]:
    script = Path(sys.executable).with_name("spl")
    return [str(script)] if script.is_file() else [sys.executable, "-m", "spl"]


def tagged_env(tag: str, **extra: str) -> dict[str, str]:
    return {**os.environ, TAG: tag, "ROS_MASTER_URI": "http://127.0.0.1:9/", **extra}


def run_spl(
    args: list[str], timeout: float = 240, cwd: Path = ROOT, **extra: str
) -> subprocess.CompletedProcess:
    """Run spl in ``cwd`` with a fresh tag; afterwards no process of that run may be left."""
    tag = uuid.uuid4().hex
    result = subprocess.run(
        [*spl_command(), *args],
        env=tagged_env(tag, **extra),
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert leftovers(tag) == [], "processes left behind"
    return result


def smoke_json(bundle: Path, *options: str) -> tuple[int, dict[str, Any]]:
    result = run_spl(["smoke", str(bundle), "--json", "--timeout", "90", *options])
    assert result.returncode in (0, 1), result.stderr
    return result.returncode, json.loads(result.stdout)


def leftovers(tag: str, wait: float = 0.0) -> list[str]:
    """Command lines of running processes carrying ``tag`` (after up to ``wait`` s)."""
    needle = f"{TAG}={tag}".encode() + b"\0"
    deadline = time.monotonic() + wait
    while True:
        found = []
        for entry in os.scandir("/proc"):
            if not entry.name.isdigit():
                continue
            try:
                environ = Path(f"/proc/{entry.name}/environ").read_bytes() + b"\0"
                if needle not in environ:
                    continue
                stat = Path(f"/proc/{entry.name}/stat").read_bytes()
                if stat.rsplit(b")", 1)[1].split()[0] in (b"Z", b"X"):
                    continue
                cmdline = Path(f"/proc/{entry.name}/cmdline").read_bytes()
            except (OSError, IndexError):
                continue
            found.append(cmdline.replace(b"\0", b" ").decode(errors="replace").strip())
        if not found or time.monotonic() >= deadline:
            return found
        time.sleep(0.1)


def rows_by_interface(report: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """``Container.Node.interface`` -> row of a ``--json`` report."""
    return {
        f"{container['name']}.{row['node']}.{row['interface']}": row
        for container in report["containers"]
        for row in container["rows"]
    }
