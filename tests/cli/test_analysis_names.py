"""Feature names as the file writes them: ``spl analyze`` (text and JSON) and ``spl
convert`` never show an identifier made up on import (docs/fm.md, "Interchange")."""

from __future__ import annotations

import json
import re
from pathlib import Path

from click.testing import CliRunner
from hypothesis import given, settings, strategies as st

from spl.cli import main
from spl.dsl.interop.formats import load_feature_model, save_feature_model
from spl.dsl.interop.interchange import written_names

from support.real_models import REAL_MODELS

SHARED = Path("/work/shared/data/feature-models")
ODD = ["64BIT", "++", "Größe", "My Feature", "a/b", "1st, 2nd", "x+y"]


def analyze(path: Path, *options: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["analyze", str(path), "--count-seconds", "0", *options])
    return result.exit_code, result.output


def model_text(mandatory: list[str], optional: list[str]) -> str:
    """A root with mandatory (core) and optional children; every optional one is dead."""
    lines = ['namespace "my model-1"', "features", '\t"Root"', "\t\tmandatory"]
    lines += [f'\t\t\t"{name}"' for name in mandatory]
    lines += ["\t\toptional"] + [f'\t\t\t"{name}"' for name in optional]
    lines += ["constraints"] + [f'\t!"{name}"' for name in optional]
    return "\n".join(lines) + "\n"


def test_odd_names_are_reported_as_written(tmp_path: Path) -> None:
    path = tmp_path / "odd.uvl"
    path.write_text(model_text(ODD[:4], ODD[4:]), encoding="utf-8")
    code, output = analyze(path, "--json")
    assert code == 0, output
    report = json.loads(output)
    assert report["name"] == "my model-1"
    assert report["core"] == sorted(["Root", *ODD[:4]])
    assert report["dead"] == sorted(ODD[4:])
    code, output = analyze(path)
    # bare where a comma list stays unambiguous, quoted as UVL quotes them otherwise
    assert '  core (5): ++, 64BIT, Größe, "My Feature", Root' in output.splitlines()
    assert '  dead (3): "1st, 2nd", a/b, x+y' in output.splitlines()
    assert not re.search(r"_64BIT|Gr__e|__", output)


def test_conversion_keeps_names_as_written(tmp_path: Path) -> None:
    source = tmp_path / "odd.uvl"
    source.write_text(model_text(ODD[:4], ODD[4:]), encoding="utf-8")
    model = load_feature_model(source)
    for suffix in (".uvl", ".xml", ".fm"):
        target = tmp_path / f"out{suffix}"
        save_feature_model(model, target)
        assert sorted(written_names(load_feature_model(target)).values()) == sorted(
            ["Root", *ODD]
        ), suffix
    uvl = (tmp_path / "out.uvl").read_text(encoding="utf-8")
    assert '"64BIT"' in uvl and '"Größe"' in uvl and "_64BIT" not in uvl


# what a quoted UVL name may hold (the reference grammar: no '.', '"' or line break)
names = st.text(
    alphabet=st.characters(blacklist_categories=("Cs", "Cc"), blacklist_characters='."\n\r'),
    min_size=1,
    max_size=10,
)


@settings(max_examples=40, deadline=None)
@given(st.lists(names, min_size=2, max_size=8, unique=True).filter(lambda n: "Root" not in n))
def test_generated_names_come_back_as_written(tmp_path_factory, chosen: list[str]) -> None:
    folder = tmp_path_factory.mktemp("names")
    path = folder / "generated.uvl"
    half = len(chosen) // 2
    path.write_text(model_text(chosen[:half], chosen[half:]), encoding="utf-8")
    code, output = analyze(path, "--json")
    assert code == 0, output
    report = json.loads(output)
    assert report["core"] == sorted(["Root", *chosen[:half]])
    assert report["dead"] == sorted(chosen[half:])
    target = folder / "back.xml"
    save_feature_model(load_feature_model(path), target)
    assert sorted(written_names(load_feature_model(target)).values()) == sorted(["Root", *chosen])


def _names_in(text: str) -> set[str]:
    """Every name a UVL file writes: quoted ones and bare words."""
    return set(re.findall(r'"([^"\n]+)"', text)) | set(re.findall(r"[A-Za-z_0-9]+", text))


def test_community_models_report_only_names_of_their_files() -> None:
    folders = [REAL_MODELS, *([SHARED] if SHARED.is_dir() else [])]
    paths = sorted({p.name: p for f in folders for p in f.glob("*.uvl")}.values())
    assert paths
    for path in paths:
        code, output = analyze(path, "--json")
        assert code == 0, output
        report = json.loads(output)
        written = _names_in(path.read_text(encoding="utf-8"))
        for kind in ("core", "dead", "false_optional"):
            assert set(report[kind]) <= written, (path.name, set(report[kind]) - written)


def test_a_featureide_model_is_named_by_its_file_as_written(tmp_path: Path) -> None:
    path = tmp_path / "berkeley-db 2.xml"
    path.write_bytes((REAL_MODELS / "berkeleydb.xml").read_bytes())
    code, output = analyze(path, "--json")
    assert code == 0, output
    assert json.loads(output)["name"] == "berkeley-db 2"
