"""``spl smoke`` of a warehouse camera product (tests/models/line_checks/warehouse) with the
real ROS 1: the inputs the model leaves unfed are the ones ``spl resolve`` warns about
and ``spl check`` finds for the line (SPL045, SPL046), reported as modelled gaps and not
as a failed rehearsal; the input the model says is fed from outside carries its reason."""

from __future__ import annotations

from support.smoke_runs import ROOT, rows_by_interface, smoke_json, write_product

WAREHOUSE = ROOT / "tests" / "models" / "line_checks" / "warehouse"


def test_modelled_gaps_are_no_failed_rehearsal(tmp_path):
    bundle = write_product(WAREHOUSE, "CameraSensing,Detection", tmp_path / "bundle")
    status, report = smoke_json(bundle)
    assert status == 0 and report["passed"], report["failures"]
    rows = rows_by_interface(report)
    scan, odom = rows["Amr.Localizer.scan"], rows["Amr.Localizer.odom"]
    assert (scan["expected"], scan["seen"], scan["ok"]) == (
        "nothing: unfed in the model (SPL045)",
        "nothing received",
        True,
    )
    assert odom["expected"] == (
        "nothing: fed from outside the architecture: wheel odometry of the base driver, "
        "which the robot's bring-up starts"
    )
    assert odom["ok"]
    classify = rows["Cloud.Detector.classify"]
    assert classify["expected"] == "nothing: unserved in the model (SPL046)"
    assert classify["ok"]
    # where the model says data flows, it must: the camera's images reach the detector
    assert rows["Cloud.Detector.image"]["seen"].startswith("from Amr.Camera.image (")
