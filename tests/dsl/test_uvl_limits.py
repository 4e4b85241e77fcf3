"""The bounds docs/fm.md ("Limits") gives, at the bound and one past it."""

from __future__ import annotations

from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.fm import language as fm
from spl.dsl.interop.featureide import read_featureide
from spl.dsl.interop.uvl import read_uvl, write_uvl
from spl.dsl.interop.uvl_reader import MAX_TREE_DEPTH, parse_uvl_plain
from spl.resolver.analysis.formula import FeatureModelFormula


def nested_features(levels: int) -> str:
    """A UVL tree ``levels`` features deep: F1 above F2 above ... (each optional)."""
    lines = ["features", "\tF1"]
    for level in range(2, levels + 1):
        lines.append("\t" * (2 * level - 2) + "optional")
        lines.append("\t" * (2 * level - 1) + f"F{level}")
    return "\n".join(lines) + "\n"


def test_a_tree_at_the_bound_is_read_analysed_and_written(tmp_path: Path) -> None:
    path = tmp_path / "deep.uvl"
    path.write_text(nested_features(MAX_TREE_DEPTH))
    model = read_uvl(path)
    with FeatureModelFormula(parse_uvl_plain(path.read_text(), str(path))) as formula:
        assert formula.core_features() == ["F1"]
        assert formula.count(None).value == MAX_TREE_DEPTH  # F1..Fk for k = 1..300
    assert write_uvl(model).count("optional") == MAX_TREE_DEPTH - 1


def test_a_tree_past_the_bound_is_refused_at_the_feature() -> None:
    with pytest.raises(ModelError) as refused:
        parse_uvl_plain(nested_features(MAX_TREE_DEPTH + 5), "deep.uvl")
    at = 2 * (MAX_TREE_DEPTH + 1)  # F301: on line 602, after 601 tabs
    assert [str(d) for d in refused.value.diagnostics] == [
        f"deep.uvl:{at}:{at}: error: feature F301 is nested 301 levels "
        "deep (at most 300): the readers and writers of the tree would run out of stack"
    ]


def test_ten_thousand_operands_in_a_uvl_chain_read_and_analyse() -> None:
    names = [f"F{i}" for i in range(10_000)]
    text = (
        "features\n\tR\n\t\toptional\n"
        + "".join(f"\t\t\t{name}\n" for name in names)
        + f"constraints\n\t{' | '.join(names)}\n\t!({' & '.join(names)})\n"
    )
    with FeatureModelFormula(parse_uvl_plain(text, "chain.uvl")) as formula:
        assert formula.core_features() == ["R"] and formula.dead_features() == []


def test_long_chains_read_in_every_format(tmp_path: Path) -> None:
    names = [f"F{i}" for i in range(500)]  # over the 200 levels a chain was refused at
    fm_model = fm.parse_text(
        f"feature model M root R {{ optional {{ {' '.join(names)} }} }} constraints {{\n"
        f"  {' or '.join(names)}\n  not ({' and '.join(names)})\n}}\n"
    )
    xml = tmp_path / "m.xml"
    xml.write_text(
        '<featureModel><struct><and name="R">'
        + "".join(f'<feature name="{n}"/>' for n in names)
        + "</and></struct><constraints><rule><disj>"
        + "".join(f"<var>{n}</var>" for n in names)
        + "</disj></rule><rule><not><conj>"
        + "".join(f"<var>{n}</var>" for n in names)
        + "</conj></not></rule></constraints></featureModel>"
    )
    uvl = tmp_path / "m.uvl"
    uvl.write_text(write_uvl(fm_model))  # balanced chains print with parentheses
    for model in (fm_model, read_featureide(xml), read_uvl(uvl)):
        assert len(model.constraints) == 2
        with FeatureModelFormula(model) as formula:
            # at least one feature, never all: nothing is core or dead but R
            assert formula.core_features() == ["R"] and formula.dead_features() == []
