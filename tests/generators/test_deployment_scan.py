"""The consumers' own scanners accept the deployments spl writes (docs/kubernetes.md,
"Checked by the consumers' own tools"): checkov (Kubernetes and Dockerfile frameworks)
fails no check and skips only the two waived ones, hadolint finds nothing in the
Dockerfiles and bandit nothing of medium or high severity in the generated services and
clients, for the paper's product (cloud instances, Zenoh router) and a data-acquisition
product with PostgreSQL (data services, database, clients). The scan is
scripts/deployment_scan.py's, which CI runs on every listed product and fleet; each tool
is first shown to report what it should, so a scanner that ran nothing cannot pass."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from support.cli_outcome import run

ROOT = Path(__file__).resolve().parents[2]
LINES = ROOT / "product_lines"
PRODUCTS = [
    LINES / "mapping3d" / "products" / "youbot_stereo_room.yaml",
    LINES / "data_acquisition" / "products" / "follow_postgres.yaml",
]


def load_scan():  # type: ignore[no-untyped-def]
    path = ROOT / "scripts" / "deployment_scan.py"
    spec = importlib.util.spec_from_file_location("deployment_scan", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["deployment_scan"] = module
    spec.loader.exec_module(module)
    return module


scan = load_scan()


@pytest.fixture(scope="module")
def bundles(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("scan")
    for features in PRODUCTS:
        line = features.parent.parent
        result = run("resolve", line, "--features", features, "-o", out / features.stem)
        assert result.exit_code == 0, result.output
    return out


def test_checkov_fails_nothing_and_skips_only_the_waived_checks(bundles: Path) -> None:
    counts, problems = scan.checkov(scan.checkov_program(None), bundles)
    assert problems == []
    assert counts["failed"] == 0 and counts["passed"] > 400
    # digest and pull policy, once per workload: the paper's two cloud instances and its
    # router, FollowStore's service and PostgreSQL
    assert counts["skipped"] == 2 * 5


def test_hadolint_and_bandit_find_nothing(bundles: Path) -> None:
    dockerfiles = sorted(bundles.rglob("Dockerfile"))
    assert len(dockerfiles) == 1
    assert scan.hadolint(dockerfiles) == []
    code = [bundles / "follow_postgres" / "services", bundles / "follow_postgres" / "clients"]
    assert scan.bandit(code) == []


def test_every_tool_reports_what_it_should(tmp_path: Path) -> None:
    (tmp_path / "pod.yaml").write_text(
        "apiVersion: v1\nkind: Pod\nmetadata:\n  name: root\n  namespace: x\nspec:\n"
        "  containers:\n  - name: c\n    image: busybox:1.36\n"
        "    securityContext:\n      privileged: true\n"
    )
    counts, problems = scan.checkov(scan.checkov_program(None), tmp_path)
    assert counts["failed"] > 5 and any("CKV_K8S_16" in p for p in problems)  # privileged
    (tmp_path / "Dockerfile").write_text("FROM python:latest\nRUN cd /app && pip install x\n")
    assert any("DL3007" in finding for finding in scan.hadolint([tmp_path / "Dockerfile"]))
    (tmp_path / "fetch.py").write_text(
        "import urllib.request\n\n\ndef get(url):\n    return urllib.request.urlopen(url)\n"
    )
    assert any("B310" in finding for finding in scan.bandit([tmp_path]))
    manifest = tmp_path / "bad.yaml"
    manifest.write_text("apiVersion: v1\nkind: Service\nmetadata:\n  name: s\nspec:\n  port: 1\n")
    assert scan.validate([manifest]) != []
