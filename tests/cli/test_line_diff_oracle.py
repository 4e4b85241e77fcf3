"""``spl diff OLD_DIR NEW_DIR --all`` and ``spl validate --changed-from`` against brute
force (docs/evolution.md, "Comparing two versions of a line").

The oracle is not spl's comparison: every product of both versions is written by ``spl
resolve`` into folders, the two versions read from one and the same folder one after
the other (so the folder is the same by construction), and the bundles are compared
here file by file with :mod:`filecmp`. ``spl diff`` is given the versions in two other
folders, so it must also find that the folder is no change. Each shipped line (found
by globbing ``product_lines/``) gets scripted edits of four kinds: a parameter's value
in the .tsm, a migration taken out of the .rm, a new optional feature and a tightened
constraint in the .fm. The paper's line (12 products, one of the smallest, and the
one every edit applies to) is compared with ``--all``; the others by their listed
products, so the test stays cheap.
"""

from __future__ import annotations

import filecmp
import json
import re
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
from click.testing import CliRunner
from lxml import etree

from spl.cli import main

ROOT = Path(__file__).resolve().parents[2]
LINES = sorted(p.parent for p in (ROOT / "product_lines").glob("*/products"))
EVERY_PRODUCT = "mapping3d"  # the line compared with --all; the others by their listed products
PICTURE = "architecture.svg"  # drawn from architecture.dot, which spl diff compares


def spl(*args: str | Path) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert "Traceback" not in result.output, result.output
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.stdout, result.stderr


def keys(folder: Path) -> list[str]:
    code, out, err = spl("products", folder, "--all")
    assert code == 0, err
    return out.split()


# --- the scripted edits: each changes a copy of the line in place; False: not applicable


def edit_parameter(folder: Path, _: list[str]) -> bool:
    """A parameter's default value in the .tsm: the first string one, else a number."""
    tsm = next(folder.glob("*.tsm"))
    text = tsm.read_text(encoding="utf-8")
    found = re.search(r'param \w+\s*:\s*string\s*=\s*"[^"]*(?=")', text)
    if found is not None:
        text = text[: found.end()] + "-v2" + text[found.end() :]
    else:
        found = re.search(r"param \w+\s*:\s*(?:double|int)\s*=\s*\d+", text)
        if found is None:
            return False
        text = text[: found.end()] + "1" + text[found.end() :]
    tsm.write_text(text, encoding="utf-8")
    return True


def edit_migration(folder: Path, _: list[str]) -> bool:
    """The .rm's first migration whose removal leaves a line that loads, taken out (a
    later statement may name what the migration made)."""
    rm = next(folder.glob("*.rm"))
    text = rm.read_text(encoding="utf-8")
    for found in re.finditer(r"^[ \t]*migrate [^\n]*\n", text, flags=re.M):
        rm.write_text(text[: found.start()] + text[found.end() :], encoding="utf-8")
        if spl("check", folder)[0] == 0:
            return True
    rm.write_text(text, encoding="utf-8")
    return False


def edit_new_feature(folder: Path, _: list[str]) -> bool:
    """A new optional feature under the root, which nothing else mentions."""
    fm = next(folder.glob("*.fm"))
    text = fm.read_text(encoding="utf-8")
    edited = re.sub(
        r"^(root \w+ \{\n)", r"\1    optional EvolvedExtra\n", text, count=1, flags=re.M
    )
    fm.write_text(edited, encoding="utf-8")
    return edited != text


def edit_constraint(folder: Path, products: list[str]) -> bool:
    """``A excludes B`` for the first two features some products select together and
    others do not: some products go, others stay."""
    chosen = [set(p.split(",")) for p in products]
    names = list(dict.fromkeys(name for p in products for name in p.split(",")))
    pairs = [(a, b) for i, a in enumerate(names) for b in names[i + 1 :]]
    both = [(a, b) for a, b in pairs if 0 < sum({a, b} <= p for p in chosen) < len(chosen)]
    if not both:
        return False
    fm = next(folder.glob("*.fm"))
    text = fm.read_text(encoding="utf-8")
    rule = f"    {both[0][0]} excludes {both[0][1]}\n"
    if re.search(r"^constraints \{\n", text, flags=re.M):
        text = re.sub(
            r"^(constraints \{\n)", lambda m: m.group(1) + rule, text, count=1, flags=re.M
        )
    else:
        text += f"\nconstraints {{\n{rule}}}\n"
    fm.write_text(text, encoding="utf-8")
    return True


EDITS: dict[str, Callable[[Path, list[str]], bool]] = {
    "parameter": edit_parameter,
    "migration": edit_migration,
    "new optional feature": edit_new_feature,
    "tightened constraint": edit_constraint,
}


# --- the brute force


def resolved_products(folder: Path, out: Path, every: bool) -> dict[object, tuple[str, Path]]:
    """Every product of the line written by ``spl resolve``, by identity (a listed one
    by its file name, a generated one by all the features its manifest lists): its
    name as ``spl validate`` reports it, and its bundle."""
    found: dict[object, tuple[str, Path]] = {}
    for selection in sorted((folder / "products").glob("*.yaml")):
        bundle = out / "listed" / selection.stem
        code, stdout, _ = spl("resolve", folder, "--features", selection, "-o", bundle)
        if code == 0:
            name = re.match(r"product (\S+):", stdout)
            assert name is not None, stdout
            found["listed", selection.name] = name.group(1), bundle
    for index, key in enumerate(keys(folder) if every else []):
        bundle = out / "all" / str(index)
        code, _, err = spl("resolve", folder, "--features", key, "-o", bundle)
        assert code == 0, err
        manifest = json.loads((bundle / "manifest.json").read_text(encoding="utf-8"))
        found["product", frozenset(manifest["features"])] = key, bundle
    return found


def differing_files(a: Path, b: Path) -> set[str]:
    """The files of two bundles that differ, or that only one has (filecmp, byte for byte)."""
    files = {str(p.relative_to(root)) for root in (a, b) for p in root.rglob("*") if p.is_file()}
    return {
        f
        for f in files
        if not (
            (a / f).is_file() and (b / f).is_file() and filecmp.cmp(a / f, b / f, shallow=False)
        )
    }


@pytest.fixture(scope="module")
def versions(tmp_path_factory: pytest.TempPathFactory) -> Callable[[Path], dict]:
    """Per line, once: the pristine copy, the folder the versions are resolved in, and
    the old version's products."""
    memo: dict[Path, dict] = {}

    def of(line: Path) -> dict:
        if line not in memo:
            base = tmp_path_factory.mktemp(line.name)
            pristine, work = base / "old" / line.name, base / "work" / line.name
            shutil.copytree(line, pristine)
            shutil.copytree(line, work)
            every = line.name == EVERY_PRODUCT
            old = resolved_products(work, base / "old_bundles", every)
            memo[line] = {
                "base": base,
                "pristine": pristine,
                "work": work,
                "every": every,
                "old": old,
            }
        return memo[line]

    return of


@pytest.mark.parametrize("edit", list(EDITS))
@pytest.mark.parametrize("line", LINES, ids=[line.name for line in LINES])
def test_diff_and_changed_from_match_the_bundles_spl_resolve_writes(
    line: Path, edit: str, versions: Callable[[Path], dict]
) -> None:
    known = versions(line)
    base, pristine, work, every = known["base"], known["pristine"], known["work"], known["every"]
    shutil.rmtree(work)
    shutil.copytree(pristine, work)
    if not EDITS[edit](work, keys(pristine)):
        pytest.skip(f"{line.name} has nothing for this edit")
    new = resolved_products(work, base / f"bundles_{edit.replace(' ', '_')}", every)
    old = known["old"]
    differing = {i: differing_files(old[i][1], new[i][1]) for i in old.keys() & new.keys()}
    changed = {new[i][0]: files for i, files in differing.items() if files}
    added = {new[i][0] for i in new.keys() - old.keys()}
    removed = {old[i][0] for i in old.keys() - new.keys()}

    scope = ["--all"] if every else []
    code, out, err = spl("diff", pristine, work, *scope, "--json")
    assert code == 0, err
    products = json.loads(out)["products"]
    assert {p["product"] for p in products["changed"]} == set(changed)
    assert {p["product"] for p in products["added"]} == added
    assert {p["product"] for p in products["removed"]} == removed
    assert products["unchanged"] == len(differing) - len(changed)
    for product in products["changed"]:
        paths = {f["path"] for f in product["files"]}
        assert paths == changed[product["product"]] - {PICTURE}, product["product"]
        assert all(f["reason"] for f in product["files"])
        # the edit is traced to a line of the new version's models
        assert any(
            re.search(rf"{re.escape(str(work))}/\S+:\d+:\d+", f["reason"]) for f in product["files"]
        )

    junit = base / f"report_{edit.replace(' ', '_')}.xml"
    code, out, err = spl("validate", work, *scope, "--changed-from", pristine, "--junit", junit)
    # a listed product the new version refuses is removed, and its case fails as in a full run
    refused = {old[i][0] for i in old.keys() - new.keys() if i[0] == "listed"}
    assert code == (1 if refused else 0), out + err
    cases = etree.parse(str(junit)).getroot().iter("testcase")
    ran, skipped = set(), {}
    for case in cases:
        skip = case.find("skipped")
        if skip is None:
            ran.add(case.get("name"))
        else:
            skipped[case.get("name")] = skip.get("message")
    assert ran == set(changed) | added | refused
    assert set(skipped.values()) <= {f"bundle unchanged from {pristine}"}
    assert len(skipped) == products["unchanged"]
