"""Fuzzing the command line with mutated and generated models (no internal
error on any valid or invalid input).

The shipped product lines and the test corpora are mutated one file at a time (.tsm,
.fm, .rm or a product selection, tests/model_mutations.py), and whole lines are drawn
from the grammars (tests/model_generator.py); both run through the real commands,
``spl check FILE``,
``spl check DIR`` and ``spl resolve DIR --features ... -o OUT``: each must exit 0, or
exit 1 with a located error, never fail with an internal error or a traceback, and
never leave anything in the output folder when it fails (tests/cli_outcome.py).
Counterexamples hypothesis found became the regression tests of test_fuzz_regressions.py.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from hypothesis import given, settings, strategies as st

from support.cli_outcome import assert_clean, run
from support.hypothesis_budget import examples
from support.model_generator import generated_lines
from support.model_mutations import IDENT, mutate, mutations

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models"
LINES = sorted({p.parent for base in (ROOT / "product_lines", MODELS) for p in base.rglob("*.rm")})
SINGLE_FILES = sorted(
    p for p in MODELS.rglob("*") if p.suffix in (".tsm", ".fm", ".rm") and p.parent not in LINES
)
MODEL_SUFFIXES = (".tsm", ".fm", ".rm")


def line_files(line: Path) -> list[Path]:
    """The files of a line that can be mutated: its models and its product selections."""
    return sorted(p for p in line.rglob("*") if p.suffix in (*MODEL_SUFFIXES, ".yaml"))


@st.composite
def mutated_lines(draw):
    """(line folder, relative path of the mutated file, mutated text, features)."""
    line = draw(st.sampled_from(LINES))
    target = draw(st.sampled_from(line_files(line)))
    text = target.read_text(encoding="utf-8")
    mutated = mutate(text, draw(mutations(text)))
    relative = target.relative_to(line)
    if target.suffix == ".yaml":
        features = str(relative)
    else:
        products = sorted((line / "products").glob("*.yaml"))
        fm_text = "".join(f.read_text(encoding="utf-8") for f in line.glob("*.fm"))
        feature_names = sorted(set(IDENT.findall(fm_text))) or ["Root"]
        features = draw(
            st.one_of(
                st.sampled_from([str(p.relative_to(line)) for p in products] or ["Root"]),
                st.lists(st.sampled_from(feature_names), min_size=1, max_size=5).map(",".join),
            )
        )
    return line, relative, mutated, features


def check_line(line: Path, relative: Path, text: str, features: str) -> None:
    """Write the mutant into a copy of the line and run the three commands on it."""
    with tempfile.TemporaryDirectory() as scratch:
        copy = Path(scratch) / line.name
        shutil.copytree(line, copy)
        (copy / relative).write_text(text, encoding="utf-8", errors="surrogateescape")
        about = f"line {line.relative_to(ROOT)}, {relative} mutated to:\n{text!r}"
        if relative.suffix in MODEL_SUFFIXES:
            assert_clean(run("check", copy / relative), f"spl check FILE on {about}")
        assert_clean(run("check", copy), f"spl check DIR on {about}")
        out_parent = Path(scratch) / "out"
        out_parent.mkdir()
        selection = str(copy / features) if features.endswith(".yaml") else features
        assert_clean(
            run("resolve", copy, "--features", selection, "-o", out_parent / "bundle"),
            f"spl resolve --features {features} on {about}",
            out_parent,
        )


@settings(max_examples=examples(60))
@given(mutated_lines())
def test_mutated_product_lines_never_fail_internally(case):
    check_line(*case)


@st.composite
def mutated_files(draw):
    target = draw(st.sampled_from(SINGLE_FILES))
    text = target.read_text(encoding="utf-8")
    return target, mutate(text, draw(mutations(text)))


@settings(max_examples=examples(40))
@given(mutated_files())
def test_mutated_single_models_never_fail_internally(case):
    source, text = case
    with tempfile.TemporaryDirectory() as scratch:
        path = Path(scratch) / source.name
        path.write_text(text, encoding="utf-8", errors="surrogateescape")
        assert_clean(run("check", path), f"spl check {source.name} mutated to:\n{text!r}")


@settings(max_examples=examples(60))
@given(generated_lines())
def test_generated_product_lines_never_fail_internally(files):
    """Lines drawn from the grammars, their names picked from what they declare, near
    misses and unknowns; checked and resolved both from a feature list and from the
    line's generated product selection."""
    with tempfile.TemporaryDirectory() as scratch:
        line = Path(scratch) / "gen"
        (line / "products").mkdir(parents=True)
        for name, text in files.items():
            (line / name).write_text(text, encoding="utf-8")
        about = "generated line:\n" + "\n".join(f"--- {n}\n{t}" for n, t in files.items())
        for name in ("gen.tsm", "gen.fm", "gen.rm"):
            assert_clean(run("check", line / name), f"spl check {name} on {about}")
        assert_clean(run("check", line), f"spl check DIR on {about}")
        out_parent = Path(scratch) / "out"
        out_parent.mkdir()
        for features in (str(line / "products" / "gen.yaml"), "Root,F0"):
            assert_clean(
                run("resolve", line, "--features", features, "-o", out_parent / "bundle"),
                f"spl resolve --features {features} on {about}",
                out_parent,
            )
            shutil.rmtree(out_parent / "bundle", ignore_errors=True)
