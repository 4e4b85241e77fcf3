"""The typed metamodel modules (src/spl/metamodels/tsm_types.py, fm_types.py, rm_types.py) are
what scripts/ecore_types.py writes from the .ecore files: a metamodel changed without
running the script fails here, naming the command. They are for the type checker only:
``spl check`` never imports them."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "ecore_types.py"


def _writer():
    spec = importlib.util.spec_from_file_location("ecore_types_script", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", ["tsm", "fm", "rm"])
def test_the_typed_module_is_what_the_script_writes(name: str) -> None:
    path = ROOT / "src" / "spl" / "metamodels" / f"{name}_types.py"
    written = _writer().modules()[path]
    assert path.read_text(encoding="utf-8") == written, (
        f"{path.relative_to(ROOT)} is stale: run .venv/bin/python scripts/ecore_types.py"
    )


def test_every_metaclass_and_feature_is_declared() -> None:
    from pyecore.ecore import EClass, EEnum

    from spl.metamodels import packages

    for name, package in packages().items():
        text = (ROOT / "src" / "spl" / "metamodels" / f"{name}_types.py").read_text(
            encoding="utf-8"
        )
        for classifier in package.eClassifiers:
            if isinstance(classifier, EClass):
                assert f"\nclass {classifier.name}(" in text
                for feature in classifier.eStructuralFeatures:
                    assert f"    {feature.name}: " in text, (classifier.name, feature.name)
            elif isinstance(classifier, EEnum):
                assert f"\nclass {classifier.name}Enum(EnumType):" in text


def test_the_check_option_reports_a_stale_module(tmp_path: Path, monkeypatch) -> None:
    writer = _writer()
    monkeypatch.setattr(writer, "FOLDER", tmp_path)
    assert writer.main(["--check"]) == 1  # none written yet
    assert writer.main([]) == 0
    assert writer.main(["--check"]) == 0
    written = tmp_path / "fm_types.py"
    written.write_text(written.read_text(encoding="utf-8") + "# edited\n", encoding="utf-8")
    assert writer.main(["--check"]) == 1


def test_spl_check_imports_no_typed_module() -> None:
    code = (
        "import sys\n"
        "from spl.cli import main\n"
        "try:\n"
        "    main(['check', 'product_lines/mapping3d'])\n"
        "except SystemExit as exc:\n"
        "    assert not exc.code, exc.code\n"
        "print(sorted(m for m in sys.modules if m.startswith('spl.metamodels.')))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr
    loaded = result.stdout.strip().splitlines()[-1]
    assert "spl.metamodels.ecore_files" in loaded
    for module in ("model_types", "tsm_types", "fm_types", "rm_types"):
        assert f"spl.metamodels.{module}" not in loaded
