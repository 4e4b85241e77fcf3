"""The distribution works outside the source tree: a wheel carries every package and
its data files (.ecore, .tx, templates, schemas), and the installed `spl` runs."""

from __future__ import annotations

import subprocess
import sys
import tomllib
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT / "src"


def test_every_folder_of_python_modules_is_a_package():
    """setuptools ships the packages it finds under src/ (pyproject.toml): a folder of
    modules without an ``__init__.py`` would be left out of the wheel."""
    folders = {p.parent for p in (SOURCE / "spl").rglob("*.py") if "__pycache__" not in p.parts}
    missing = sorted(
        str(f.relative_to(SOURCE)) for f in folders if not (f / "__init__.py").is_file()
    )
    assert not missing, missing
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert config["packages"]["find"]["where"] == ["src"]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("dist")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "build",
            "--wheel",
            "--no-isolation",
            "--outdir",
            str(out),
            str(ROOT),
        ],
        check=True,
        capture_output=True,
    )
    (built,) = out.glob("spl_robotics-*.whl")
    return built


def test_wheel_ships_models_grammars_and_templates(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for required in (
        "spl/metamodels/tsm.ecore",
        "spl/metamodels/fm.ecore",
        "spl/metamodels/rm.ecore",
        "spl/dsl/tsm/tsm.tx",
        "spl/dsl/rm/rm.tx",
        "spl/dsl/fm/fm.tx",
        "spl/dsl/fm/capability.tx",
        "spl/cli/__init__.py",
        "spl/smoke/standin.py",  # run by the ROS Python from the installed package
    ):
        assert required in names, required
    assert not any(n.startswith(("dsl/", "resolver/", "tests/")) for n in names), (
        "generic top-level packages must not be installed"
    )


def test_installed_wheel_runs_outside_the_source_tree(wheel, tmp_path):
    """The wheel and the dependencies it declares go into a fresh virtual environment,
    by this environment's pip (``--python``: the new one needs no pip of its own, whose
    installation took a quarter of the test) without compiling them ahead (Python compiles
    what it imports)."""
    env_dir = tmp_path / "venv"
    venv.create(env_dir)
    python = env_dir / "bin" / "python"
    pip = [sys.executable, "-m", "pip", "--python", str(python)]
    subprocess.run(
        [*pip, "install", "-q", "--no-compile", str(wheel)], check=True, capture_output=True
    )
    spl = env_dir / "bin" / "spl"
    version = subprocess.run(
        [str(spl), "--version"], cwd=tmp_path, capture_output=True, text=True, check=True
    )
    assert version.stdout.startswith("spl, version ")
    where = subprocess.run(
        [str(python), "-c", "import spl.dsl; print(spl.dsl.__file__)"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=True,
    )
    assert str(env_dir) in where.stdout and str(ROOT) not in where.stdout
    model = ROOT / "product_lines" / "mapping3d" / "mapping.tsm"
    check = subprocess.run(
        [str(spl), "check", str(model)], cwd=tmp_path, capture_output=True, text=True
    )
    assert check.returncode == 0, check.stderr
    assert "containers" in check.stdout and "nodes" in check.stdout
    for line, features in (
        ("mapping3d", "YouBot,Stereo,AdditionalPC,Room"),
        ("data_acquisition", "Positions,Follow,Postgres"),
    ):
        out = tmp_path / "bundles" / line
        resolved = subprocess.run(
            [
                str(spl),
                "resolve",
                str(ROOT / "product_lines" / line),
                "--features",
                features,
                "-o",
                str(out),
            ],
            cwd=tmp_path,
            capture_output=True,
            text=True,
        )
        assert resolved.returncode == 0, resolved.stderr
        assert (out / "manifest.json").is_file() and (out / "architecture.svg").is_file()


def test_the_services_extra_is_what_the_generated_services_require():
    """`pip install 'spl-robotics[services]'` lets spl smoke run a bundle's services with
    spl's own Python: the extra lists exactly the generated requirements.txt."""
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    template = SOURCE / "spl" / "generators" / "service" / "templates" / "requirements.txt.j2"
    required = [line for line in template.read_text().splitlines() if line.strip()]
    assert extras["optional-dependencies"]["services"] == required
