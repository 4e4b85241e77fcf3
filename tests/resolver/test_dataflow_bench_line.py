"""The generated line of bench/line_checks.py (docs/performance.md) still says what its
figures claim: 1,000 inputs, 200 features, every tenth topic fed only by an optional
publisher, so 100 inputs some product leaves unfed, all shown by one witness product,
the product selecting no feature (one resolution for all of them)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from spl.resolver.line_checks import ActivationSolver
from spl.resolver.line_checks.dataflow import Feeds, unfed_inputs_in_line
from spl.resolver.resolution.product_line import load_product_line

BENCH = Path(__file__).resolve().parents[2] / "bench" / "line_checks.py"


def bench_module():
    spec = importlib.util.spec_from_file_location("line_checks_bench", BENCH)
    assert spec is not None and spec.loader is not None
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    return bench


def test_the_bench_line_has_100_unfed_inputs_and_one_witness(tmp_path, monkeypatch):
    bench = bench_module()
    bench.dataflow_line(tmp_path)
    line = load_product_line(tmp_path)
    resolved: list[tuple[str, ...]] = []
    warning = Feeds.warning

    def counted(self, witness, code, where):
        resolved.append(witness)
        return warning(self, witness, code, where)

    monkeypatch.setattr(Feeds, "warning", counted)
    with ActivationSolver(line) as solver:
        found = unfed_inputs_in_line(line, solver)
    assert len(found) == 100 and {d.code for d in found} == {"SPL045"}
    assert found[0].message == (
        "C0.in0 subscribes Robot.T0, which no node of the product publishes, in the product "
        "Root; its feeder P0.out is left out: optional node P0 is kept only by 'when F0 "
        f"selected' ({tmp_path / 'flows.rm'}:5:1)"
    )
    assert set(resolved) == {("Root",)}


def test_the_bench_scaling_line_is_checked_as_its_figures_say() -> None:
    """The bench's scaling part runs the checks it names on its generated line (a check
    moved to another module once broke it, and its figures with it): one conflict per
    fifty groups and one optional node no element keeps per ten (at 250 groups the
    figures count 5 and 25, among 1,500 elements and 1,751 features)."""
    result = bench_module().measure(50)
    assert (result["conflicts"], result["unreachable"]) == (1, 5)
    assert (result["elements"], result["features"]) == (300, 351)
