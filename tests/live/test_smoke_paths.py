"""``spl smoke BUNDLE`` rehearses the same bundle whichever way BUNDLE names it:
relative to a working directory that is not the repository's, through ``..``, with a
space in it, a trailing slash or a symbolic link (docs/smoke.md). The product has data
clients, whose generated writers and readers and services run from the bundle's own
folders in other working directories: a path relative to the caller's named another
folder there, and every one of them failed (``can't open file .../da1/clients/...``)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from support.smoke_runs import ROOT, rows_by_interface, run_spl, write_product

DATA = ROOT / "product_lines" / "data_acquisition"


@pytest.fixture(scope="module")
def places(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``x y/da1`` (the bundle), ``elsewhere/`` and ``link`` -> ``x y/da1``."""
    root = tmp_path_factory.mktemp("paths")
    selection = DATA / "products" / "both_fast_refresh.yaml"
    write_product(DATA, selection, root / "x y" / "da1")
    (root / "elsewhere").mkdir()
    (root / "link").symlink_to(Path("x y") / "da1")
    return root


@pytest.mark.parametrize(
    ("cwd", "bundle"),
    [("x y", "da1"), ("elsewhere", "../x y/da1/"), (".", "./link/")],
    ids=["relative", "dotdot-space-slash", "symlink"],
)
def test_a_bundle_named_from_another_directory_is_rehearsed_whole(
    places: Path, cwd: str, bundle: str
) -> None:
    result = run_spl(["smoke", bundle, "--json", "--timeout", "90"], cwd=places / cwd)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    report = json.loads(result.stdout)
    assert report["passed"] and report["skipped"] is None, report["failures"]
    assert report["bundle"] == str((places / "x y" / "da1").resolve())
    rows = rows_by_interface(report)
    # the generated writers and readers ran from the bundle (not stand-ins), and the data
    # they moved arrived: stored, refined and received
    generated = [key for key, row in rows.items() if row["expected"].endswith("(generated node)")]
    assert {"Rover.PositionWriter.records", "EV3B.CommandReader.records"} <= set(generated)
    assert rows["DataCloud.PositionStore.stored from PositionWriter"]["seen"] == "12 stored"
    received = [row for key, row in rows.items() if key.startswith("EV3B.CommandFollower.")]
    assert received and all(row["ok"] for row in received)
