"""The layering of docs/architecture.md, checked by import-linter's contracts in
pyproject.toml on a copy of the package tree (src/spl, Python files only), so that a
planted forbidden import breaks the copy and not the repository."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PYPROJECT = ROOT / "pyproject.toml"
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")


def installed_tree(destination: Path) -> Path:
    """The ``spl`` package laid out as pip installs it (Python files only)."""
    shutil.copytree(
        ROOT / "src" / "spl",
        destination / "spl",
        ignore=lambda _, names: [n for n in names if "." in n and not n.endswith(".py")],
    )
    return destination


def lint(tree: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(LINT_IMPORTS), "--config", str(PYPROJECT), "--no-cache"],
        cwd=tree, env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"},
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    return installed_tree(tmp_path)


def test_every_layering_contract_is_kept(tree: Path) -> None:
    result = lint(tree)
    assert result.returncode == 0, result.stdout + result.stderr
    assert ", 0 broken." in result.stdout


@pytest.mark.parametrize(
    "module, planted, contract",
    [
        ("spl/dsl/rosnames.py", "import spl.resolver.resolution.engine",
         "Pipeline layers: application -> generators -> resolver -> dsl -> metamodels"),
        ("spl/resolver/architecture/placement.py", "from spl.generators.bundle import writer",
         "Pipeline layers: application -> generators -> resolver -> dsl -> metamodels"),
        ("spl/generators/ros1/launch_files.py", "from spl.dsl.tsm import language",
         "Generators read the resolved model: they neither parse models nor resolve"),
        ("spl/generators/ros2/launch_files.py", "from spl.generators.rapyuta import configurations",
         "Each output target is generated independently of the others"),
    ],
)  # fmt: skip
def test_a_forbidden_import_fails_naming_its_contract(tree, module, planted, contract) -> None:
    path = tree / module
    path.write_text(path.read_text(encoding="utf-8") + f"\n{planted}\n", encoding="utf-8")
    result = lint(tree)
    assert result.returncode == 1
    assert f"{contract} BROKEN" in result.stdout
