"""Line checks as functions over a ProductLine (resolver/line_checks/): every finding
of the broken line, located and worded, witnesses the engine agrees with, and no report
for conflicts the feature model rules out."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.resolver.line_checks import ActivationSolver, check_product_line
from spl.resolver.line_checks.conflicts import reachable_conflicts
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

ROOT = Path(__file__).resolve().parents[2]
BROKEN = Path(__file__).parents[1] / "models" / "line_checks" / "broken"
DATA = ROOT / "product_lines" / "data_acquisition"


@pytest.fixture(scope="module")
def broken():
    return load_product_line(BROKEN)


@pytest.fixture(scope="module")
def found(broken):
    return check_product_line(broken)


def where(d) -> tuple[str, int, int, str, str]:
    return (Path(d.location.file).name, d.location.line, d.location.col, d.severity, d.code)


def test_every_finding_of_the_broken_line_is_located(found):
    assert [where(d) for d in found] == [
        ("broken.fm", 25, 14, "info", "SPL014"),  # Beeper
        ("broken.rm", 6, 1, "error", "SPL010"),  # when Gripper selected
        ("broken.rm", 11, 1, "error", "SPL010"),  # when Sensing not selected
        ("broken.rm", 21, 5, "error", "SPL012"),  # implementation Driver
        ("broken.rm", 22, 5, "error", "SPL012"),  # parameter Driver.rate
        ("broken.rm", 30, 5, "error", "SPL012"),  # migrate Planner
        ("broken.rm", 54, 5, "error", "SPL012"),  # connect Teleop.cmd
        ("broken.rm", 61, 1, "error", "SPL012"),  # sharing of Mapper
        ("broken.rm", 70, 5, "error", "SPL012"),  # server of Lookup.find
        ("broken.tsm", 14, 20, "warning", "SPL045"),  # Driver.cmd, without Teleop
        ("broken.tsm", 21, 19, "warning", "SPL011"),  # GripperControl
        ("broken.tsm", 24, 19, "warning", "SPL011"),  # Spare
        ("broken.tsm", 48, 15, "warning", "SPL046"),  # Lookup.find, without a server
        ("invalid.yaml", 2, 12, "warning", "SPL015"),
        ("open.yaml", 1, 1, "warning", "SPL015"),
    ]


def test_dead_elements_name_the_feature_model_rules(found):
    dead = [d.message for d in found if d.code == "SPL010"]
    assert dead[0].startswith(
        "resolution element 'when Gripper selected' can never be active: "
        "feature Gripper is dead (in no product), because Gripper requires Arm ("
    )
    assert "Arm excludes Gripper (" in dead[0] and "broken.fm:30:5)" in dead[0]
    assert dead[1].startswith(
        "resolution element 'when Sensing not selected' can never be active: "
        "feature Sensing is core (in every product), because "
    )
    assert "Sensing is mandatory in Robot" in dead[1]


def test_unreachable_optional_nodes_say_why(found):
    messages = [d.message for d in found if d.code == "SPL011"]
    assert messages == [
        "optional node Robot.GripperControl is in no product: only resolution elements "
        "that can never be active require or transform it",
        "optional node Robot.Spare is in no product: no resolution element requires or "
        "transforms it",
    ]


def test_conflict_messages_name_both_elements_the_thing_and_a_witness(found):
    conflicts = {d.location.line: d.message for d in found if d.code == "SPL012"}
    assert conflicts[21].startswith("conflict: 'when Slow selected' (")
    assert "gives implementation slow_driver/driver_node to Driver" in conflicts[21]
    assert "to Driver, but 'when Fast selected' (" in conflicts[21]
    assert "gives fast_driver/driver_node (at " in conflicts[21]
    assert "gives value '1.5' to Driver.rate" in conflicts[22]
    assert "gives feature Fast.rate" in conflicts[22]
    assert "gives migration target Edge to Planner" in conflicts[30]
    assert "gives topic Robot.Manual to Teleop.cmd" in conflicts[54]
    assert "gives sharing mode private (default of feature Private) to Mapper" in conflicts[61]
    assert "gives server Services.ServerB.find to Lookup.find" in conflicts[70]
    assert "gives Services.ServerA.find (at " in conflicts[70]
    for message in conflicts.values():
        witness = message.split("both are active in the product ")[1].split(", ")
        assert witness == sorted(witness) and "Robot" in witness


def test_every_witness_makes_the_engine_report_the_same_conflict(broken, found):
    for d in (d for d in found if d.code == "SPL012"):
        witness = d.message.split("both are active in the product ")[1]
        with pytest.raises(ModelError) as caught:
            resolve(broken, selection_from_list(witness.replace(" ", "")))
        engine = [e for e in caught.value.diagnostics if e.code == "SPL020"]
        assert d.location in [e.location for e in engine], d.message


def test_conflicts_the_feature_model_rules_out_are_not_reported(found):
    # Wheeled/Legged are alternatives (lines 34-41), Heavy excludes Light (lines 42-47)
    lines = {d.location.line for d in found if d.location.file.endswith("broken.rm")}
    assert not lines & set(range(33, 48))


def test_witnesses_are_deterministic_and_small(broken):
    with ActivationSolver(broken) as solver:
        first = [d.message for d in reachable_conflicts(broken, solver)]
    assert first == [d.message for d in reachable_conflicts(broken, ActivationSolver(broken))]
    assert "both are active in the product Base, Fast, Legged, Robot, Sensing, Slow" in first[0]


def test_each_element_pair_is_asked_once(broken):
    solver = ActivationSolver(broken)
    asked = []
    decide = solver._possible

    def counting(literals):
        asked.append(tuple(literals))
        return decide(literals)

    solver._possible = counting
    reachable_conflicts(broken, solver)
    # Driver's implementation and rate are decided by the same pairs of elements
    assert len(asked) == len(set(asked))
    assert all(len(literals) == 2 for literals in asked)
    # Driver: Fast/Slow, not-Sensing/Fast, not-Sensing/Slow; then Remote/Local,
    # Wheeled/Legged, Heavy/Light, Joystick/Keyboard, Public/Private (Remote/Local also
    # decide Lookup's server: asked once)
    assert len(asked) == 8


def test_period_conflict_unused_store_and_feature_without_effect(tmp_path):
    line_dir = tmp_path / "data_acquisition"
    shutil.copytree(DATA, line_dir)
    rm_file = line_dir / "data.rm"
    extra = "when Positions selected {\n    parameter PositionStore.PositionInDEG.period = 2.0\n}\n"
    rm_file.write_text(rm_file.read_text(encoding="utf-8") + "\n" + extra, encoding="utf-8")
    fm_file = line_dir / "data.fm"
    fm_file.write_text(
        fm_file.read_text(encoding="utf-8").replace(
            "    optional FastRefresh {", "    optional Audit\n    optional FastRefresh {"
        ),
        encoding="utf-8",
    )
    tsm_file = line_dir / "data.tsm"
    tsm_file.write_text(
        tsm_file.read_text(encoding="utf-8").replace(
            "    optional store FollowStore {",
            "    optional store Archive {\n        raw Velocity\n    }\n"
            "    optional store FollowStore {",
        ),
        encoding="utf-8",
    )
    found = check_product_line(load_product_line(line_dir))
    assert [(d.code, d.location.line) for d in found] == [
        ("SPL014", 14),
        ("SPL012", 26),
        ("SPL011", 42),
        ("SPL052", 61),  # PositionReader.records: GpsDeg, which no node reads
    ]
    assert found[2].message == (
        "optional store DataCloud.Archive is in no product: no resolution element requires "
        "or transforms it"
    )
    assert found[0].message.startswith("feature Audit has no effect")
    assert re.search(
        r"gives period '2\.0' to PositionStore\.PositionInDEG\.period, but "
        r"'when FastRefresh selected' \(.*\) gives feature FastRefresh\.period",
        found[1].message,
    )
    assert found[1].message.endswith(
        "both are active in the product DataAcquisition, Embedded, FastRefresh, Positions, Storage"
    )
    # ... and the engine refuses that witness with the same conflict, naming the refinement
    # by its store and output (a refinement has no name of its own)
    witness = found[1].message.split("both are active in the product ")[1]
    with pytest.raises(ModelError) as caught:
        resolve(load_product_line(line_dir), selection_from_list(witness.replace(" ", "")))
    [engine] = [e for e in caught.value.diagnostics if e.code == "SPL020"]
    assert engine.location == found[1].location
    assert engine.message.startswith(
        "conflict: 'when Positions selected' (" + str(rm_file) + ":25:1) gives period 2.0 to "
        "DataCloud.PositionStore.PositionInDEG, but 'when FastRefresh selected' ("
    )


@pytest.mark.parametrize("name", ["mapping3d", "data_acquisition"])
def test_shipped_lines_have_no_finding(name):
    found = check_product_line(load_product_line(ROOT / "product_lines" / name))
    # but one info: the reader's GpsDeg, which no node of any product reads (SPL052)
    assert [(d.severity, d.code, d.location.line) for d in found] == (
        [("info", "SPL052", 58)] if name == "data_acquisition" else []
    )
