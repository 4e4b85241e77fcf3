"""``spl validate``: one JUnit test case per product, located failures, exit status,
the same report whatever the number of worker processes."""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from types import SimpleNamespace

import pytest
from click.testing import CliRunner
from lxml import etree

from spl.cli import main
from spl.generators.bundle.options import BundleOptions
from spl.pipeline import ProductWarning
from spl.validation.junit import junit_xml
from spl.validation.line import CaseResult

from support.smoke_runs import run_spl

ROOT = Path(__file__).resolve().parents[2]
LINES = ROOT / "product_lines"
MODELS = Path(__file__).parents[1] / "models" / "validate"
CONFLICTING = MODELS / "conflicting"
SCHEMA = etree.XMLSchema(etree.parse(str(Path(__file__).parents[1] / "junit" / "junit.xsd")))


def run(*args: object):
    """``spl validate ARGS`` in this process; with ``--jobs`` above 1 in a process of its
    own, as a user runs it: worker processes forked from this one, whose other threads
    (pytest-xdist's) may hold a lock at that moment, could wait on it for ever."""
    argv = ["validate", *map(str, args)]
    if "--jobs" not in argv or argv[argv.index("--jobs") + 1] == "1":
        return CliRunner().invoke(main, argv)
    done = run_spl(argv, timeout=600)  # which also finds no process of it left behind
    return SimpleNamespace(
        exit_code=done.returncode, stdout=done.stdout, output=done.stdout + done.stderr
    )


def report(path: Path) -> etree._Element:
    """The JUnit file, parsed and validated against the JUnit schema."""
    document = etree.parse(str(path))
    assert SCHEMA.validate(document), SCHEMA.error_log
    return document.getroot()


def cases(root: etree._Element) -> dict[tuple[str, str], etree._Element]:
    return {(c.get("classname"), c.get("name")): c for c in root.iter("testcase")}


def failure_text(case: etree._Element) -> str:
    (failure,) = case.findall("failure")
    assert failure.get("message") == failure.text.splitlines()[0]
    return failure.text


@pytest.fixture(scope="module")
def shipped(tmp_path_factory):
    out = tmp_path_factory.mktemp("junit") / "shipped.xml"
    # 61 products: the workers get them several at a time (chunks of 3)
    result = run(
        LINES / "mapping3d",
        LINES / "data_acquisition",
        LINES / "orchard",
        "--all",
        "--jobs",
        "2",
        "--junit",
        out,
    )
    return result, out


@pytest.fixture(scope="module")
def broken(tmp_path_factory):
    """The broken lines, once with one process and once with two."""
    folder = tmp_path_factory.mktemp("broken")
    runs = []
    for jobs in (1, 2):
        out = folder / f"jobs{jobs}.xml"
        runs.append(
            (run(CONFLICTING, MODELS / "unloadable", "--all", "--jobs", jobs, "--junit", out), out)
        )
    return runs


def test_every_shipped_product_passes(shipped) -> None:
    result, out = shipped
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[-1] == "61 passed, 0 failed"
    assert "ok   mapping3d :: youbot_stereo_room" in result.stdout  # plain lines off a tty
    root = report(out)
    suites = {s.get("name"): s for s in root.iter("testsuite")}
    assert {name: s.get("tests") for name, s in suites.items()} == {
        "mapping3d": "17",
        "data_acquisition": "15",
        "orchard": "29",
    }
    assert root.get("tests") == "61" and root.get("failures") == "0"
    names = {name for (line, name) in cases(root) if line == "mapping3d"}
    # listed products by their YAML name, generated ones by their features
    assert {"youbot_stereo_room", "roomba_stereo_corridor_private"} <= names
    assert "YouBot,Stereo,AdditionalPC,Room" in names
    assert len([n for n in names if "," in n]) == 12
    assert not any(c.findall("failure") for c in root.iter("testcase"))


def test_broken_lines_fail_with_located_messages(broken) -> None:
    result, out = broken[0]
    assert result.exit_code == 1
    assert result.stdout.splitlines()[-1] == "6 passed, 4 failed"
    found = cases(report(out))
    rm, fm = CONFLICTING / "conflicting.rm", CONFLICTING / "conflicting.fm"
    products = CONFLICTING / "products"
    # a conflict reachable in one product of the feature model
    conflict = failure_text(found[("conflicting", "Fast,Slow")])
    assert conflict.startswith(f"{rm}:9:5: error: conflict:")
    assert f"{rm}:6:5" in conflict
    # an invalid selection file: the file's line and the violated rule's location
    invalid = failure_text(found[("conflicting", "slow_extra")])
    assert invalid.startswith(f"{products / 'slow_extra.yaml'}:3:12: error: invalid selection")
    assert f"Extra excludes Slow ({fm}:12:5)" in invalid
    misspelt = failure_text(found[("conflicting", "misspelt")])
    assert misspelt.startswith(f"{products / 'misspelt.yaml'}:3:1: error: unknown key 'sharng'")
    unloadable = failure_text(found[("unloadable", "(product line)")])
    assert f"{MODELS / 'unloadable' / 'unloadable.rm'}:2:1: error: tsm file" in unloadable
    passed = {name for (line, name), c in found.items() if not c.findall("failure")}
    assert passed == {"fast_extra", "Robot", "Fast", "Slow", "Extra", "Fast,Extra"}
    assert f"FAIL conflicting :: Fast,Slow\n    {rm}:9:5: error: conflict:" in result.stdout


def test_report_does_not_depend_on_jobs_or_run(broken, tmp_path: Path) -> None:
    (one, out1), (two, out2) = broken
    assert two.exit_code == 1 and out1.read_bytes() == out2.read_bytes()
    assert one.stdout == two.stdout
    again = tmp_path / "again.xml"
    run(CONFLICTING, MODELS / "unloadable", "--all", "--junit", again)
    assert again.read_bytes() == out1.read_bytes()


def test_pairwise_sample_reaches_the_conflict(tmp_path: Path) -> None:
    out = tmp_path / "sample.xml"
    result = run(CONFLICTING, "--sample", "t=2", "--junit", out)
    assert result.exit_code == 1
    failing = [c for c in report(out).iter("testcase") if c.findall("failure")]
    # every pair of literals is covered, so Fast with Slow is in some sampled product
    assert any(failure_text(c).startswith(f"{CONFLICTING / 'conflicting.rm'}:9:5") for c in failing)


def test_product_whose_rapyuta_configuration_breaks_a_rule(tmp_path: Path) -> None:
    line = MODELS / "rapyuta_clash"
    out = tmp_path / "clash.xml"
    result = run(line, "--all", "--junit", out)
    assert result.exit_code == 1
    assert result.stdout.splitlines()[-1] == "3 passed, 1 failed"
    found = cases(report(out))
    failing = {name for (_, name), c in found.items() if c.findall("failure")}
    # only the product with a private and a protected node in one cloud container
    assert failing == {"OwnMap,TeamArchive"}
    message = failure_text(found[("rapyuta_clash", "OwnMap,TeamArchive")])
    assert message.startswith(
        f"{line / 'clash.tsm'}:17:17: error: Rapyuta tag 'Cloud_r1' "
        "would name both the private partition of Cloud and the "
        "protected partition of Cloud"
    )


def test_open_selection_fails_that_product_only(tmp_path: Path) -> None:
    line = tmp_path / "mapping3d"
    shutil.copytree(LINES / "mapping3d", line)
    (line / "products" / "open.yaml").write_text("product: open\nfeatures: [YouBot]\n")
    out = tmp_path / "open.xml"
    result = run(line, "--junit", out)
    assert result.exit_code == 1
    assert result.stdout.splitlines()[-1] == "5 passed, 1 failed"
    message = failure_text(cases(report(out))[("mapping3d", "open")])
    # located at the group the selection leaves open
    text = (line / "mapping.fm").read_text().splitlines()
    row = next(i for i, t in enumerate(text, 1) if "mandatory PerceptionSensor xor" in t)
    col = text[row - 1].index("xor") + 1
    assert message.startswith(f"{line / 'mapping.fm'}:{row}:{col}: error: open choice:")
    assert "exactly one of Stereo, Depth" in message


def test_usage_errors() -> None:
    assert run(CONFLICTING, "--all", "--sample", "t=2").exit_code == 2
    assert run(CONFLICTING, "--sample", "t=5").exit_code == 2
    assert run(MODELS / "no_such_line").exit_code == 2
    assert run().exit_code == 2


def test_junit_carries_hostile_text_and_internal_errors() -> None:
    results = [
        CaseResult("line", 'a<b>&"c"', "failed", ("x.fm:1:2: error: bad \x01 name <&>",)),
        CaseResult("line", "crash", "error", ("internal error: KeyError: 'x'",)),
        CaseResult(
            "line", "fine", "passed", warnings=(ProductWarning("x.tsm:3:4: warning: unfed"),)
        ),
    ]
    root = etree.fromstring(junit_xml(results))
    assert SCHEMA.validate(root), SCHEMA.error_log
    found = cases(root)
    assert "\\x01 name <&>" in failure_text(found[("line", 'a<b>&"c"')])
    (error,) = found[("line", "crash")].findall("error")
    assert error.get("type") == "InternalError"
    assert found[("line", "fine")].findtext("system-err") == "x.tsm:3:4: warning: unfed"
    suite = root.find("testsuite")
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("3", "1", "1")


def test_folder_name_xml_cannot_carry(tmp_path: Path) -> None:
    line = tmp_path / "lab\x01line"
    shutil.copytree(LINES / "mapping3d", line)
    out = tmp_path / "odd.xml"
    result = run(line, "--junit", out)
    assert result.exit_code == 0, result.output
    assert {c for (c, _) in cases(report(out))} == {"lab\\x01line"}


def test_diagrams_are_rendered_only_when_asked() -> None:
    """A product's diagram source is always generated and checked; rendering it costs a
    Graphviz process per product, so `spl validate` does it with --diagrams only."""
    from spl import pipeline
    from spl.resolver.resolution.product_selection import load_selection_file

    line = pipeline.load_line(LINES / "mapping3d")
    selection = load_selection_file(LINES / "mapping3d" / "products" / "youbot_stereo_room.yaml")
    quick = pipeline.derive(line, selection, BundleOptions(render_diagrams=False)).bundle
    full = pipeline.derive(line, selection).bundle
    assert "architecture.dot" in quick.files and "architecture.svg" not in quick.files
    assert quick.skipped == {}  # nothing to warn about: it was not asked for
    assert full.files["architecture.svg"].startswith(b"<?xml")
    assert quick.files["architecture.dot"] == full.files["architecture.dot"]


def test_what_is_no_selection_file_in_products_fails_its_product_and_never_blocks(tmp_path):
    # were: "internal error: IsADirectoryError" for a folder, and validate and check
    # waiting for ever on a named pipe (found by fuzzing)
    line = tmp_path / "line"
    shutil.copytree(ROOT / "product_lines" / "data_acquisition", line)
    products = line / "products"
    (products / "folder.yaml").mkdir()
    os.mkfifo(products / "pipe.yaml")
    (products / "dangling.yaml").symlink_to(tmp_path / "nowhere.yaml")
    result = CliRunner().invoke(main, ["validate", str(line)])
    assert result.exit_code == 1
    assert "internal error" not in result.output
    lines = result.output.splitlines()
    for name, reason in (("folder", "a folder"), ("pipe", "not a file"), ("dangling", "missing")):
        failed = lines.index(f"FAIL line :: {name}")
        assert lines[failed + 1] == f"    {products / name}.yaml:1:1: error: cannot read: {reason}"
    checked = CliRunner().invoke(main, ["check", str(line)])
    assert f"{products / 'pipe'}.yaml:1:1: warning: product pipe: cannot read: not a file" in (
        checked.stderr
    )
