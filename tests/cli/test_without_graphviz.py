"""The main job needs nothing but Python: without Graphviz's ``dot`` on PATH, ``spl
resolve`` still writes the whole bundle (less the SVG, with a one-line warning and the
skip recorded in the manifest), and ``spl render`` / ``spl validate`` warn instead of
crashing. Every command runs in a subprocess whose PATH holds no ``dot`` at all."""

from __future__ import annotations

import json
import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from test_readme_commands import fenced_command

from spl.generators.bundle.validation import validate_bundle
from spl.generators.bundle.writer import bundle_files
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

ROOT = Path(__file__).resolve().parents[2]
WARNING = "architecture.svg not written: Graphviz 'dot' not found; install graphviz to get diagrams"


@pytest.fixture(scope="module")
def no_dot_env(tmp_path_factory) -> dict[str, str]:
    """The caller's environment with PATH replaced by a folder of links to the only
    programs the commands may start: the Python running the tests (never ``dot``)."""
    bin_dir = tmp_path_factory.mktemp("bin-without-dot")
    (bin_dir / "python3").symlink_to(sys.executable)
    env = {**os.environ, "PATH": str(bin_dir)}
    assert shutil.which("dot", path=env["PATH"]) is None
    return env


def spl(args: list[str], env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    script = Path(sys.executable).with_name("spl")  # the installed entry point, as in README
    command = [str(script)] if script.is_file() else [sys.executable, "-m", "spl"]
    return subprocess.run(
        [*command, *args], env=env, cwd=ROOT, capture_output=True, text=True, timeout=120
    )


def read_bundle(folder: Path) -> dict[str, bytes]:
    return {
        p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()
    }


def test_readme_main_command_writes_the_bundle_without_dot(no_dot_env, tmp_path):
    args = shlex.split(fenced_command("main-command").split("&& .venv/bin/spl ", 1)[1])
    out = args.index("-o") + 1
    args[out] = str(tmp_path / "first")
    result = spl(args, no_dot_env)
    assert result.returncode == 0, result.stderr
    assert f"warning: {WARNING}" in result.stderr.splitlines()
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr
    files = read_bundle(tmp_path / "first")
    assert "architecture.svg" not in files and validate_bundle(files) == []
    manifest = json.loads(files["manifest.json"])
    assert manifest["skipped"] == {"architecture.svg": WARNING.split(": ", 1)[1]}

    # the same bundle as with Graphviz, less the SVG (the manifest says so)
    features = args[args.index("--features") + 1]
    line = load_product_line(ROOT / args[1])
    with_dot = bundle_files(resolve(line, selection_from_list(features)).product)
    assert "architecture.svg" in with_dot and "architecture.dot" in with_dot
    assert files.keys() == with_dot.keys() - {"architecture.svg"}
    assert all(files[p] == with_dot[p] for p in files if p != "manifest.json")

    args[out] = str(tmp_path / "second")
    assert spl(args, no_dot_env).returncode == 0
    assert read_bundle(tmp_path / "second") == files  # deterministic without dot too


def test_render_without_dot_explains_and_still_writes_the_source(no_dot_env, tmp_path):
    svg = tmp_path / "product.svg"
    result = spl(["render", "product_lines/mapping3d", "-o", str(svg)], no_dot_env)
    assert result.returncode == 2 and not svg.exists()
    assert result.stderr.strip() == (
        "error: product.svg not written: Graphviz 'dot' not found; install graphviz to get "
        "diagrams (or write the source with -o product.dot)"
    )
    source = tmp_path / "product.dot"
    result = spl(["render", "product_lines/mapping3d", "-o", str(source)], no_dot_env)
    assert result.returncode == 0, result.stderr
    assert source.read_text(encoding="utf-8").startswith("digraph Mapping3D {")


def test_validate_without_dot_passes_and_warns_once_when_asked_for_diagrams(no_dot_env, tmp_path):
    """spl validate renders no diagram unless --diagrams asks (the source is checked
    always); asked without Graphviz, it warns once and records it in each case, and the
    warning, about this machine, fails no product under --strict (docs/ci.md)."""
    plain = spl(["validate", "product_lines/mapping3d"], no_dot_env)
    assert plain.returncode == 0, plain.stdout + plain.stderr
    assert plain.stderr == ""
    junit = tmp_path / "report.xml"
    args = ["validate", "product_lines/mapping3d", "--diagrams", "--strict", "--junit", str(junit)]
    result = spl(args, no_dot_env)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stderr.splitlines() == [f"warning: {WARNING} (this machine, for 5 products)"]
    assert result.stdout.splitlines()[-1] == "5 passed, 0 failed"  # not counted
    assert junit.read_text(encoding="utf-8").count(WARNING) == 5  # in each case's system-err
