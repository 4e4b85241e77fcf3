"""Four consecutive monthly BusyBox feature models (2007), compared pairwise.

The witnesses are checked here without spl's CNF or solver: each is evaluated against
both versions' own trees and constraints (tests/support/fm_semantics.py), and must be a
product of the version it is claimed for and not of the other (a feature the other
version lacks, selected, is enough to reject it there). The counts are checked where an
independent figure exists: a version that adds a core feature shares no product with
the one before, so the products removed are all of OLD's and the products added all of
NEW's, which ``FeatureModelFormula.count`` of each version alone gives.
"""

from __future__ import annotations

from itertools import pairwise

import pytest

from spl.dsl.interop.uvl import read_uvl
from spl.resolver.analysis.formula import FeatureModelFormula
from spl.resolver.analysis.operations.edit_classification import ModelEdit

from support.analysis_models import all_features
from support.fm_semantics import is_product
from support.real_models import REAL_MODELS

FOLDER = REAL_MODELS / "evolution" / "busybox"
VERSIONS = sorted(path.stem for path in FOLDER.glob("*.uvl"))
# found by spl diff and confirmed by the witnesses below; the first two files hold the
# same model with its features and constraints in another order
CLASSES = ["refactoring", "arbitrary", "arbitrary"]


def load(version: str):
    return read_uvl(FOLDER / f"{version}.uvl")


def accepts(model, product: list[str]) -> bool:
    """Whether ``product`` (selected names; every other feature deselected) is a product
    of ``model``: its features only, its tree and every constraint."""
    return set(product) <= set(all_features(model)) and is_product(model, set(product))


def test_the_four_versions_are_there() -> None:
    assert VERSIONS == [
        "2007-05-20_17-12-43",
        "2007-06-01_14-40-03",
        "2007-07-01_14-53-06",
        "2007-08-01_23-30-54",
    ]


@pytest.mark.parametrize(
    ("old_version", "new_version", "expected"),
    [(*versions, kind) for versions, kind in zip(pairwise(VERSIONS), CLASSES, strict=True)],
)
def test_consecutive_versions(old_version: str, new_version: str, expected: str) -> None:
    old, new = load(old_version), load(new_version)
    with ModelEdit(old, new) as edit:
        old_not_new, new_not_old = edit.witnesses()
        assert edit.classification == expected
        removed, added = edit.counts(None)
    if old_not_new is None:
        assert removed.value == 0
    else:
        assert accepts(old, old_not_new) and not accepts(new, old_not_new)
        assert removed.value is not None and removed.value >= 1
    if new_not_old is None:
        assert added.value == 0
    else:
        assert accepts(new, new_not_old) and not accepts(old, new_not_old)
        assert added.value is not None and added.value >= 1


def test_a_refactoring_has_no_structural_change_either() -> None:
    with ModelEdit(load(VERSIONS[0]), load(VERSIONS[1])) as edit:
        assert edit.classification == "refactoring"
        assert (edit.added, edit.removed, edit.moved) == ([], [], [])
        assert (edit.constraints_added, edit.constraints_removed) == ([], [])


def test_the_july_to_august_edit_adds_a_core_feature_and_removes_every_product() -> None:
    old, new = load(VERSIONS[2]), load(VERSIONS[3])
    with FeatureModelFormula(new) as formula:
        assert "CONFIG_IFUPDOWN_IFSTATE_PATH" in formula.core_features()
        new_count = formula.count(None).value
    assert "CONFIG_IFUPDOWN_IFSTATE_PATH" not in all_features(old)
    with FeatureModelFormula(old) as formula:
        old_count = formula.count(None).value
    with ModelEdit(old, new) as edit:
        removed, added = edit.counts(None)
        assert edit.added == [
            "CONFIG_FEATURE_SETFILES_CHECK_OPTION",
            "CONFIG_FEATURE_UDHCPD_WRITE_LEASES_EARLY",
            "CONFIG_IFUPDOWN_IFSTATE_PATH",
            "CONFIG_RESTORECON",
            "CONFIG_SETFILES",
        ]
        assert "CONFIG_IFUPDOWN_IFSTATE_PATH" in edit.constraints_added
    assert (removed.value, added.value) == (old_count, new_count)


def test_june_to_july_removes_a_feature_and_its_constraint() -> None:
    with ModelEdit(load(VERSIONS[1]), load(VERSIONS[2])) as edit:
        assert edit.removed == ["CONFIG_WATCH"]
        assert edit.constraints_removed == ["CONFIG_DATE or not CONFIG_WATCH"]
        assert len(edit.added) == 16 and len(edit.constraints_added) == 18
