"""``spl products``: on a product-line folder and on feature-model files, in text and
JSON Lines, with the usage errors of its options."""

from __future__ import annotations

import json
import re
from pathlib import Path

from click.testing import CliRunner

from spl.cli import main
from spl.dsl.interop.formats import load_feature_model

from support.fm_semantics import is_product
from support.real_models import REAL_MODELS
from support.sample_checks import interactions

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"
SEARCH = Path(__file__).parents[1] / "models" / "validate" / "sampling" / "search.fm"


def run(*args: object):
    return CliRunner().invoke(main, ["products", *map(str, args)])


def test_all_products_of_a_line_resolve_as_listed() -> None:
    result = run(MAPPING)  # --all is the default
    assert result.exit_code == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == len(set(lines)) == 12 and result.stderr == "12 products\n"
    assert "YouBot,Stereo,AdditionalPC,Room" in lines
    assert not any("Roomba" in line and "AdditionalPC" in line for line in lines)
    assert run(MAPPING, "--all").stdout == result.stdout


def test_pairwise_sample_as_json_lines_covers_every_pair() -> None:
    model = load_feature_model(MAPPING / "mapping.fm")
    everything = [json.loads(line) for line in run(MAPPING, "--all", "--json").stdout.splitlines()]
    result = run(MAPPING, "--sample", "t=2", "--json")
    assert result.exit_code == 0
    sample = [json.loads(line) for line in result.stdout.splitlines()]
    assert [p["index"] for p in sample] == list(range(1, len(sample) + 1))
    assert all(is_product(model, set(p["features"])) for p in sample)
    names = everything[0]["features"]  # starts with the root; collect every name used
    names = sorted({name for p in everything for name in p["features"]} | {"AdditionalPC"})
    products = [frozenset(p["features"]) for p in everything]
    chosen = [frozenset(p["features"]) for p in sample]
    assert not interactions(products, names, 2) - interactions(chosen, names, 2)
    assert len(sample) < 12
    assert "valid 2-wise combinations" in result.stderr


def test_feature_model_files_in_every_format() -> None:
    uvl = run(REAL_MODELS / "berkeleydb.uvl", "--sample", "t=2")
    xml = run(REAL_MODELS / "berkeleydb.xml", "--sample", "2")
    assert uvl.exit_code == xml.exit_code == 0
    assert len(uvl.stdout.splitlines()) > 1
    # the size of the sample and the time it took, on stderr
    size = len(uvl.stdout.splitlines())
    assert re.fullmatch(rf"{size} products; they cover all 9965 valid 2-wise .* in \d+\.\d\d s\n",
                        uvl.stderr)  # fmt: skip
    assert run(SEARCH, "--random", "5", "--seed", "3").stdout.count("\n") == 5


def test_random_is_reproducible() -> None:
    first = run(SEARCH, "--random", "8", "--seed", "11", "--json")
    assert first.exit_code == 0
    assert run(SEARCH, "--random", "8", "--seed", "11", "--json").stdout == first.stdout
    model = load_feature_model(SEARCH)
    assert all(
        is_product(model, set(json.loads(line)["features"])) for line in first.stdout.splitlines()
    )


def test_usage_errors_exit_2(tmp_path: Path) -> None:
    assert run(MAPPING, "--sample", "t=7").exit_code == 2
    assert "t=1, t=2 or t=3" in run(MAPPING, "--sample", "pairs").stderr
    assert run(MAPPING, "--all", "--random", "3").exit_code == 2
    text = tmp_path / "model.txt"
    text.write_text("x")
    bad = run(text)
    assert bad.exit_code == 2 and "feature model" in bad.stderr


def test_model_errors_are_located(tmp_path: Path) -> None:
    broken = tmp_path / "broken.fm"
    broken.write_text("feature model B\nroot R {\n    optional A\n    optional A\n}\n")
    result = run(broken)
    assert result.exit_code == 1
    assert result.stderr.startswith(f"{broken}:")


def test_three_wise_on_automotive01_is_refused_with_the_figure() -> None:
    """BusyBox's triples fit in 124 MB of bits (bench/sampling.py samples them);
    automotive01's would take 5.2 GiB, refused before any product is built."""
    result = run(REAL_MODELS / "automotive01.uvl", "--sample", "t=3")
    assert result.exit_code == 1
    assert "2234 free features keeps 5.2 GiB of triple bits" in result.stderr


def test_a_reader_that_leaves_early_ends_spl_quietly() -> None:
    """`spl products LINE | head -1`: when the reader has gone, spl stops writing and
    exits 141 (as a tool killed by SIGPIPE) with nothing on stderr."""
    import os
    import subprocess
    import sys

    read, write = os.pipe()
    os.close(read)  # the reader is gone before the first line is written
    try:
        done = subprocess.run(
            [sys.executable, "-m", "spl", "products", str(ROOT / "product_lines" / "orchard"),
             "--json"],
            stdout=write, stderr=subprocess.PIPE, text=True, timeout=60,
        )  # fmt: skip
    finally:
        os.close(write)
    assert done.returncode == 141
    assert "error" not in done.stderr.lower()
    assert "Exception" not in done.stderr


def test_features_are_named_as_the_file_writes_them(tmp_path: Path) -> None:
    """A UVL name no .fm identifier can be (imported as ``_64BIT``, ``My_F``) is listed
    as written, quoted in text where a comma list would make it ambiguous."""
    path = tmp_path / "names.uvl"
    path.write_text(
        'features\n\t"64BIT"\n\t\toptional\n\t\t\t"My F"\n\t\t\t"a,b"\n\t\t\tPlain\n',
        encoding="utf-8",
    )
    text = run(path)
    assert text.exit_code == 0, text.stderr
    lines = set(text.stdout.splitlines())
    assert {"64BIT", '"My F"', '"a,b"', '"My F",Plain', '"My F","a,b",Plain'} <= lines
    assert len(lines) == 8 and not any("_" in line for line in lines)
    products = [json.loads(line) for line in run(path, "--json").stdout.splitlines()]
    everything = [p for p in products if p["selection"] == ["My F", "a,b", "Plain"]]
    assert [p["features"] for p in everything] == [["64BIT", "My F", "a,b", "Plain"]]
    assert all(p["features"][0] == "64BIT" for p in products)
