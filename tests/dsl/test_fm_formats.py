"""Format dispatch and the renaming of feature names the .fm language cannot carry."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.core.emf_compare import differences
from spl.dsl.fm import language as fm
from spl.dsl.interop.formats import load_feature_model, render_feature_model, save_feature_model
from spl.dsl.interop.interchange import FeatureNames, sanitise

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d" / "mapping.fm"

TRICKY = [
    "a b",
    "a_b",
    "a-b",
    "a.b",
    "a_b_2",
    "1st",
    "_1st",
    "or",
    "or_",
    "xor",
    "root",
    "Café",
    "Cafe_",
    "",
    " ",
    "__",
    "x\ty",
    "ß",
    "A",
    "a",
]


def test_renaming_is_injective_valid_and_keeps_valid_names() -> None:
    names = FeatureNames(TRICKY)
    identifiers = [names[n] for n in TRICKY]
    assert len(set(identifiers)) == len(TRICKY)
    assert all(fm.is_feature_name(i) for i in identifiers)
    for original in TRICKY:
        if fm.is_feature_name(original):
            assert names[original] == original
    assert names["a b"] == "a_b_3" and names["a-b"] == "a_b_4" and names["or"] == "or__2"


def test_renaming_depends_only_on_the_names_in_order() -> None:
    assert [FeatureNames(TRICKY)[n] for n in TRICKY] == [FeatureNames(TRICKY)[n] for n in TRICKY]


@pytest.mark.parametrize(
    ("name", "expected"),
    [("a.b", "a_b"), ("1x", "_1x"), ("not", "not_"), ("Straße", "Stra_e"), ("", "_")],
)
def test_sanitise(name: str, expected: str) -> None:
    assert sanitise(name) == expected


def test_load_and_save_dispatch_on_the_suffix(tmp_path: Path) -> None:
    model = load_feature_model(MAPPING)
    for suffix in (".fm", ".uvl", ".xml"):
        target = tmp_path / f"Mapping3D{suffix.upper() if suffix == '.xml' else suffix}"
        save_feature_model(model, target)
        assert target.read_bytes() == render_feature_model(model, suffix)
        again = load_feature_model(target)
        assert sum(1 for _ in fm.all_features(again)) == 12
    assert list(differences(model, load_feature_model(tmp_path / "Mapping3D.fm"))) == []
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "Mapping3D.XML",
        "Mapping3D.fm",
        "Mapping3D.uvl",
    ]


def test_unknown_formats_are_refused(tmp_path: Path) -> None:
    with pytest.raises(ModelError, match=r"unsupported feature-model format '\.json'"):
        load_feature_model(tmp_path / "model.json")
    with pytest.raises(ValueError, match="unsupported feature-model format"):
        save_feature_model(load_feature_model(MAPPING), tmp_path / "model.dimacs")
    assert list(tmp_path.iterdir()) == []
