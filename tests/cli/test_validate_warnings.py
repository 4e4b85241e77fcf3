"""``spl validate`` and the warnings of a product (docs/ci.md): an input nothing feeds
(SPL045, as ``spl check`` finds it for the line and ``spl resolve`` for the product) is
a warning in its JUnit test case, and a failure only with ``--strict``; an input the
model says is fed from outside is neither."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner
from lxml import etree

from spl.cli import main

ROOT = Path(__file__).resolve().parents[2]
WAREHOUSE = ROOT / "tests" / "models" / "line_checks" / "warehouse"
SCHEMA = etree.XMLSchema(etree.parse(str(ROOT / "tests" / "junit" / "junit.xsd")))


def validate(tmp_path: Path, *options: str) -> tuple[int, str, dict[str, etree._Element]]:
    junit = tmp_path / "report.xml"
    result = CliRunner().invoke(main, ["validate", str(WAREHOUSE), "--junit", str(junit), *options])
    document = etree.parse(str(junit))
    assert SCHEMA.validate(document), SCHEMA.error_log
    found = {case.get("name"): case for case in document.getroot().iter("testcase")}
    return result.exit_code, result.stdout, found


def test_an_unfed_input_is_a_warning_of_its_test_case(tmp_path):
    code, stdout, found = validate(tmp_path)
    assert code == 0
    camera = found["camera_detect"]
    assert camera.findall("failure") == []
    out = camera.findtext("system-out")
    assert (
        "warehouse.tsm:28:20: warning: Localizer.scan subscribes Amr.Scan, which no node of " in out
    )
    assert "[SPL045]" in out and "odom" not in out  # fed from outside: silent
    assert found["lidar_offload"].findtext("system-out") is None  # the rewiring feeds it
    assert "ok   warehouse :: camera_detect" in stdout
    assert "    " + out.splitlines()[0] in stdout.splitlines()
    assert stdout.splitlines()[-1] == "2 passed, 1 of them with warnings, 0 failed"


def test_strict_fails_the_product_with_the_warning(tmp_path):
    code, stdout, found = validate(tmp_path, "--strict")
    assert code == 1
    (failure,) = found["camera_detect"].findall("failure")
    assert "Localizer.scan subscribes Amr.Scan" in failure.get("message")
    assert "[SPL045]" in failure.text
    assert found["lidar_offload"].findall("failure") == []
    assert "FAIL warehouse :: camera_detect" in stdout
    assert stdout.splitlines()[-1] == "1 passed, 1 failed"
