"""``spl check FILE.uvl`` / ``FILE.xml``: a feature model in an interchange format is
checked as a .fm is (the same summary, the same located errors, exit 1 on an error)."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from spl.cli import main

from support.real_models import REAL_MODELS


def check(*args: object):
    return CliRunner().invoke(main, ["check", *map(str, args)])


def test_uvl_and_featureide_models_get_the_fm_summary(tmp_path: Path) -> None:
    for name in ("berkeleydb.uvl", "berkeleydb.xml"):
        result = check(REAL_MODELS / name)
        assert result.exit_code == 0, result.output
        assert result.output == f"{REAL_MODELS / name}: ok: 76 features, 20 constraints\n"
    converted = tmp_path / "berkeleydb.fm"
    assert CliRunner().invoke(main, ["convert", str(REAL_MODELS / "berkeleydb.uvl"),
                                     str(converted)]).exit_code == 0  # fmt: skip
    assert check(converted).output.endswith(": ok: 76 features, 20 constraints\n")


def test_errors_are_located_as_for_fm(tmp_path: Path) -> None:
    uvl = tmp_path / "bad.uvl"
    uvl.write_text("features\n\tR\n\t\toptional\n\t\t\tA\n\t\t\tA\nconstraints\n\tA => X\n")
    fm = tmp_path / "bad.fm"
    fm.write_text("feature model M\nroot R {\n  optional A\n  optional A\n}\n"
                  "constraints {\n  A => X\n}\n")  # fmt: skip
    results = {path.suffix: check(path) for path in (uvl, fm)}
    for result in results.values():
        assert result.exit_code == 1 and "Traceback" not in result.output
    assert results[".uvl"].output.splitlines() == [
        f"{uvl}:5:4: error: duplicate feature A",
        f"{uvl}:7:7: error: unknown feature X",
    ]
    fm_messages = [line.split(": error: ")[1] for line in results[".fm"].output.splitlines()]
    assert "unknown feature X" in fm_messages
    assert any(message.startswith("duplicate feature") for message in fm_messages)


def test_json_and_other_xml(tmp_path: Path) -> None:
    other = tmp_path / "pom.xml"
    other.write_text("<project><modelVersion/></project>\n")
    result = check(other, "--json")
    assert result.exit_code == 1
    report = json.loads(result.output)
    assert report["files"] == [{"ok": False, "path": str(other), "summary": None}]
    assert [(d["line"], d["message"]) for d in report["diagnostics"]] == [
        (1, "expected <featureModel>, got <project>")
    ]
