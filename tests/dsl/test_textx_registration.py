"""The languages and emitters are registered with textX: `textx check` runs spl's checks
and `textx generate --target ros1|ros2|rapyuta` writes what `spl resolve` would."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
TEXTX = Path(sys.executable).parent / "textx"


def textx(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(TEXTX), *args], cwd=cwd, capture_output=True, text=True)


def test_languages_and_generators_are_registered(tmp_path):
    result = textx("list-languages", cwd=tmp_path)
    languages = result.stdout + result.stderr
    for name, pattern in (("spl-tsm", "*.tsm"), ("spl-fm", "*.fm"), ("spl-rm", "*.rm")):
        assert f"{name} ({pattern})" in languages
    result = textx("list-generators", cwd=tmp_path)
    generators = result.stdout + result.stderr
    for target in ("ros1", "ros2", "rapyuta"):
        assert f"spl-rm -> {target}" in generators


def test_textx_check_runs_the_spl_checks(tmp_path):
    ok = textx("check", *(str(MAPPING / f"mapping.{k}") for k in ("tsm", "fm", "rm")), cwd=tmp_path)
    assert ok.returncode == 0, ok.stderr
    bad = tmp_path / "bad.tsm"
    bad.write_text(
        "data A { x : double }\ndata B { y : int }\ntransform T : A -> B {\n    y = x / 2.0\n}\n"
    )
    result = textx("check", str(bad), cwd=tmp_path)
    assert result.returncode == 1
    assert f"{bad}:4:5: transform T: cannot assign double to B.y of type int" in result.stderr


def test_textx_generate_targets(tmp_path):
    features = "YouBot,Stereo,AdditionalPC,Room"
    for target in ("ros1", "ros2", "rapyuta"):
        result = textx(
            "generate",
            str(MAPPING / "mapping.rm"),
            "--target",
            target,
            "--features",
            features,
            "-o",
            str(tmp_path / "out"),
            cwd=tmp_path,
        )
        assert result.returncode == 0, result.stderr
    out = tmp_path / "out"
    assert 'name="MapOptimizer"' in (out / "ros1" / "Robot.launch").read_text()
    assert (out / "ros2" / "MappingCloud.launch.xml").is_file()
    assert json.loads((out / "rapyuta" / "Robot.json").read_text())["robotID"] == "robot_1"
    refused = textx(
        "generate",
        str(MAPPING / "mapping.rm"),
        "--target",
        "ros1",
        "--features",
        "Roomba,AdditionalPC",
        "-o",
        str(tmp_path / "x"),
        cwd=tmp_path,
    )
    assert refused.returncode == 1 and "Roomba excludes AdditionalPC" in refused.stderr
    assert not (tmp_path / "x").exists()
