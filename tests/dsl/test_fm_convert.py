"""``spl convert``: every shared model survives every format, errors and exit codes."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from spl.cli import main
from spl.core.emf_compare import differences
from spl.dsl.interop.formats import load_feature_model

from support.fm_semantics import equivalent, relations
from support.real_models import REAL_MODELS

ROOT = Path(__file__).resolve().parents[2]
DATA = REAL_MODELS
SHARED = sorted(
    [*DATA.glob("*.uvl"), *DATA.glob("*.xml"), *ROOT.glob("product_lines/*/*.fm")],
    key=lambda p: p.name,
)
OTHER = {".fm": [".uvl", ".xml"], ".uvl": [".fm", ".xml"], ".xml": [".fm", ".uvl"]}


def convert(*args: str | Path) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["convert", *map(str, args)])
    return result.exit_code, result.output


def test_shared_models_are_found() -> None:
    suffixes = {p.suffix for p in SHARED}
    assert suffixes == {".fm", ".uvl", ".xml"} and len(SHARED) >= 7


@pytest.mark.parametrize("source", SHARED, ids=lambda p: p.name)
def test_round_trip_through_every_format(source: Path, tmp_path: Path) -> None:
    original = load_feature_model(source)
    for via in OTHER[source.suffix]:
        middle = tmp_path / via[1:] / f"{source.stem}{via}"
        back = tmp_path / via[1:] / "back" / source.name
        back.parent.mkdir(parents=True)
        code, output = convert(source, middle)
        assert code == 0, output
        assert code == 0 and convert(middle, back)[0] == 0
        again = load_feature_model(back)
        if via == ".xml" or source.suffix == ".xml":
            # FeatureIDE has no requires/excludes and one decomposition per feature
            assert relations(again) == relations(original)
            for mine, theirs in zip(again.constraints, original.constraints, strict=True):
                assert equivalent(mine.formula, theirs.formula)
        elif source.suffix == ".fm" and via == ".uvl":
            # UVL spells requires/excludes with => and !
            assert relations(again) == relations(original)
            assert [a.srcLine for a in again.constraints] or not original.constraints
        else:
            assert list(differences(original, again)) == []


def test_fm_through_uvl_keeps_everything_but_the_operator_spelling(tmp_path: Path) -> None:
    source = ROOT / "tests" / "models" / "fm" / "all_constructs.fm"
    original = load_feature_model(source)
    assert convert(source, tmp_path / "a.uvl")[0] == 0
    assert convert(tmp_path / "a.uvl", tmp_path / "all_constructs.fm")[0] == 0
    again = load_feature_model(tmp_path / "all_constructs.fm")
    tree = list(differences(original.root, again.root))
    assert tree == []
    for mine, theirs in zip(again.constraints, original.constraints, strict=True):
        assert equivalent(mine.formula, theirs.formula)


def test_output_is_deterministic(tmp_path: Path) -> None:
    source = DATA / "berkeleydb.uvl"
    for suffix in (".fm", ".xml", ".uvl"):
        first, second = tmp_path / f"1{suffix}", tmp_path / f"2{suffix}"
        assert convert(source, first)[0] == 0 and convert(source, second)[0] == 0
        assert first.read_bytes() == second.read_bytes()


def test_unsupported_extension_is_a_usage_error(tmp_path: Path) -> None:
    code, output = convert(DATA / "axTLS.uvl", tmp_path / "out.json")
    assert code == 2 and "unsupported feature-model format '.json'" in output
    code, output = convert(tmp_path / "in.dimacs", tmp_path / "out.fm")
    assert code == 2
    code, output = convert(tmp_path / "missing.uvl", tmp_path / "out.fm")
    assert code == 2 and "does not exist" in output
    code, output = convert(DATA / "axTLS.uvl", tmp_path / "nowhere" / "out.fm")
    assert code == 2 and "nowhere does not exist" in output


def test_bad_input_is_a_located_error_and_writes_nothing(tmp_path: Path) -> None:
    bad = tmp_path / "bad.uvl"
    bad.write_text("features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA => B\n")
    code, output = convert(bad, tmp_path / "out.fm")
    assert code == 1
    assert f"{bad}:6:7: error: unknown feature B" in output
    assert "Traceback" not in output
    assert not (tmp_path / "out.fm").exists()


def test_a_model_the_target_cannot_express_leaves_the_old_file(tmp_path: Path) -> None:
    source = tmp_path / "mixed.fm"
    source.write_text("feature model M\nroot R {\n  mandatory A { }\n  xor { B C }\n}\n")
    target = tmp_path / "mixed.xml"
    target.write_bytes(b"previous")
    code, output = convert(source, target)
    assert code == 1 and "mixed.fm:2:6: error:" in output
    assert target.read_bytes() == b"previous"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mixed.fm", "mixed.xml"]


def test_convert_uses_the_shipped_data_unchanged(tmp_path: Path) -> None:
    copy = tmp_path / "berkeleydb.xml"
    shutil.copy(DATA / "berkeleydb.xml", copy)
    code, output = convert(copy, tmp_path / "berkeleydb.fm")
    assert code == 0 and "76 features, 20 constraints" in output


def test_out_naming_in_itself_is_refused(tmp_path) -> None:
    # was: the input replaced by its own conversion, read-only or not
    source = tmp_path / "axTLS.xml"
    shutil.copy(REAL_MODELS / "axTLS.xml", source)
    source.chmod(0o444)
    before = source.read_bytes()
    for target in (source, tmp_path / "." / "axTLS.xml"):
        result = CliRunner().invoke(main, ["convert", str(source), str(target)])
        assert result.exit_code == 2
        assert "is IN itself; give another file" in result.output
    assert source.read_bytes() == before


def test_a_void_uvl_group_is_not_written_as_a_fm_file_the_fm_reader_refuses(tmp_path) -> None:
    # was: written, and spl analyze of the written file failed (found by fuzzing)
    source = tmp_path / "void.uvl"
    source.write_text("features\n\tR\n\t\t[2]\n\t\t\tA\n")
    target = tmp_path / "void.fm"
    result = CliRunner().invoke(main, ["convert", str(source), str(target)])
    assert result.exit_code == 1
    assert result.stderr == (
        f"{source}:3:3: error: feature R: its group [2..2] asks for more features than its 1, "
        "which the .fm language refuses (no product could choose that many: the model is void)\n"
    )
    assert not target.exists()
    to_uvl = CliRunner().invoke(main, ["convert", str(source), str(tmp_path / "same.uvl")])
    assert to_uvl.exit_code == 0  # UVL itself reads it: a void model, said by analyze


def test_a_uvl_implication_chain_the_fm_reader_cannot_follow_is_not_written(tmp_path) -> None:
    # UVL's A => B => C is (A => B) => C: written in .fm with a parenthesis per implication;
    # 60 of them were written, and the .fm reader refused its own output (found by fuzzing)
    source = tmp_path / "chain.uvl"
    chain = " => ".join(["A"] * 60)
    source.write_text(f"features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\tA | A\n\t{chain}\n")
    target = tmp_path / "chain.fm"
    result = CliRunner().invoke(main, ["convert", str(source), str(target)])
    assert result.exit_code == 1
    assert result.stderr.startswith(
        f"{source}:7:2: error: this constraint is written with 58 nested parentheses in .fm "
        "(an implication chain associates the other way there), which the .fm reader refuses"
    )
    assert not target.exists()
    short = " => ".join(["A"] * 20)  # what the reader follows is written, and reads back
    source.write_text(f"features\n\tR\n\t\toptional\n\t\t\tA\nconstraints\n\t{short}\n")
    assert CliRunner().invoke(main, ["convert", str(source), str(target)]).exit_code == 0
    assert CliRunner().invoke(main, ["check", str(target)]).exit_code == 0
