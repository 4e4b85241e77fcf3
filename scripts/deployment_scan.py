"""Scan the deployments of every shipped product and fleet with the tools a platform team
runs on them (docs/kubernetes.md, "Checked by the consumers' own tools"; docs/ci.md).

Builds the bundle of every listed product (products/*.yaml) and fleet (fleets/*.yaml)
of every line in product_lines/ with this checkout's spl, then:

- checkov, frameworks kubernetes and dockerfile, over all bundles in one run: 0 failed
  checks, and no check skipped but the two waived in the manifests (CKV_K8S_43, image
  digest; CKV_K8S_15, pull policy);
- hadolint on every Dockerfile: 0 findings;
- bandit ``-ll`` (medium and high severity) on the generated services and clients:
  0 findings;
- kubernetes-validate ``--strict`` (Kubernetes 1.33 schemas) on every manifest.

Prints one line per tool with its counts and time, and exits 1 when any finds anything.
checkov pins a networkx older than spl's, so it lives in a virtual environment of its
own: ``--checkov`` names its program (default: ``$CHECKOV``, ``.venv-scan/bin/checkov``
when it exists, else ``checkov`` on PATH).

    python scripts/deployment_scan.py [--out build/scan] [LINE ...]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
SPL = [sys.executable, "-m", "spl"]
WAIVED = frozenset({"CKV_K8S_43", "CKV_K8S_15"})
KUBERNETES_VERSION = "1.33.0"


def bundle_jobs(lines: list[Path], out: Path) -> list[tuple[list[str], Path]]:
    """(spl command, bundle folder) of every listed product and fleet of ``lines``."""
    jobs = []
    for line in lines:
        for product in sorted(line.glob("products/*.yaml")):
            folder = out / line.name / product.stem
            jobs.append(([*SPL, "resolve", str(line), "--features", str(product)], folder))
        for fleet in sorted(line.glob("fleets/*.yaml")):
            folder = out / line.name / f"fleet-{fleet.stem}"
            jobs.append(([*SPL, "fleet", "resolve", str(fleet)], folder))
    return jobs


def build(jobs: list[tuple[list[str], Path]]) -> list[str]:
    """Write every bundle; the failures, one line each."""

    def run(job: tuple[list[str], Path]) -> str | None:
        command, folder = job
        done = subprocess.run([*command, "-o", str(folder)], capture_output=True, text=True)
        return None if done.returncode == 0 else f"{folder}: {done.stderr.strip()}"

    with ThreadPoolExecutor(max_workers=2) as pool:
        return [problem for problem in pool.map(run, jobs) if problem]


def checkov_program(given: str | None) -> str:
    """The checkov to run: ``given``, $CHECKOV, the scan venv's, or PATH's."""
    local = ROOT / ".venv-scan" / "bin" / "checkov"
    program = given or os.environ.get("CHECKOV") or (str(local) if local.exists() else None)
    program = program or shutil.which("checkov")
    if program is None:
        raise SystemExit(
            "checkov not found: python3 -m venv .venv-scan && .venv-scan/bin/pip install "
            "checkov (its own environment: it pins networkx<2.7), or pass --checkov"
        )
    return str(Path(program).resolve()) if os.sep in program else program


def checkov(program: str, folder: Path) -> tuple[Counter[str], list[str]]:
    """(counts: passed/failed/skipped, problems) of checkov over ``folder``."""
    command = [program, "-d", str(folder), "--framework", "kubernetes", "dockerfile"]
    command += ["-o", "json", "--compact", "--skip-download"]
    done = subprocess.run(command, capture_output=True, text=True, cwd=folder)
    try:
        reports = json.loads(done.stdout)
    except json.JSONDecodeError:
        return Counter(), [f"checkov did not report: {done.stderr.strip()[-2000:]}"]
    counts: Counter[str] = Counter()
    problems = []
    for report in reports if isinstance(reports, list) else [reports]:
        if "results" not in report:  # a framework that found no file reports its summary only
            continue
        results = report["results"]
        counts["passed"] += report["summary"]["passed"]
        for failed in results.get("failed_checks", []):
            problems.append(
                f"checkov {failed['check_id']} {failed['file_path']} "
                f"{failed['resource']}: {failed['check_name']}"
            )
        for skipped in results.get("skipped_checks", []):
            counts["skipped"] += 1
            if skipped["check_id"] not in WAIVED:
                problems.append(f"checkov skips {skipped['check_id']} in {skipped['file_path']}")
    counts["failed"] = sum(p.startswith("checkov CKV") for p in problems)
    return counts, problems


def hadolint(dockerfiles: list[Path]) -> list[str]:
    """hadolint's findings on ``dockerfiles``, one line each."""
    if not dockerfiles:
        return []
    program = shutil.which("hadolint") or str(Path(sys.executable).parent / "hadolint")
    done = subprocess.run(
        [program, "--no-color", *map(str, dockerfiles)], capture_output=True, text=True
    )
    return [line for line in done.stdout.splitlines() if line.strip()] or (
        [f"hadolint failed: {done.stderr.strip()}"] if done.returncode else []
    )


def bandit(folders: list[Path]) -> list[str]:
    """bandit's medium and high findings in ``folders``, one line each."""
    if not folders:
        return []
    program = shutil.which("bandit") or str(Path(sys.executable).parent / "bandit")
    command = [program, "-ll", "-q", "-f", "json", "-r", *map(str, folders)]
    done = subprocess.run(command, capture_output=True, text=True)
    try:
        results = json.loads(done.stdout)["results"]
    except (json.JSONDecodeError, KeyError):
        return [f"bandit did not report: {done.stderr.strip()[-2000:]}"]
    return [
        f"bandit {r['test_id']} {r['filename']}:{r['line_number']}: {r['issue_text']}"
        for r in results
    ]


def validate(manifests: list[Path]) -> list[str]:
    """kubernetes-validate --strict's refusals of the documents in ``manifests``."""
    import kubernetes_validate

    problems = []
    for path in manifests:
        for document in yaml.safe_load_all(path.read_text(encoding="utf-8")):
            if not isinstance(document, dict) or "apiVersion" not in document:
                continue
            if str(document["apiVersion"]).startswith("kustomize.config.k8s.io/"):
                continue  # kustomize's own file, not an object of the cluster
            try:
                kubernetes_validate.validate(document, KUBERNETES_VERSION, strict=True)
            except Exception as error:  # the validator's several error classes
                problems.append(f"kubernetes-validate {path}: {error}")
    return problems


def scan(out: Path, lines: list[Path], checkov_path: str | None) -> int:
    """Build and scan; the number of problems found (0: all clean)."""
    program = checkov_program(checkov_path)
    shutil.rmtree(out, ignore_errors=True)
    started = time.monotonic()
    jobs = bundle_jobs(lines, out)
    problems = build(jobs)
    print(f"built {len(jobs)} bundles in {time.monotonic() - started:.1f} s")
    started = time.monotonic()
    counts, found = checkov(program, out)
    print(
        f"checkov: {counts['passed']} passed, {counts['failed']} failed, "
        f"{counts['skipped']} skipped (waived) in {time.monotonic() - started:.1f} s"
    )
    problems += found
    started = time.monotonic()
    dockerfiles = sorted(out.rglob("Dockerfile"))
    found = hadolint(dockerfiles)
    print(f"hadolint: {len(found)} findings in {len(dockerfiles)} Dockerfiles")
    problems += found
    code = sorted({p for p in out.rglob("*") if p.is_dir() and p.name in ("services", "clients")})
    found = bandit(code)
    print(f"bandit -ll: {len(found)} findings in {len(code)} folders")
    problems += found
    manifests = sorted(p for p in out.rglob("*.yaml") if "kubernetes" in p.parts)
    found = validate(manifests)
    print(f"kubernetes-validate --strict: {len(found)} refused of {len(manifests)} files")
    problems += found
    print(f"hadolint, bandit, kubernetes-validate in {time.monotonic() - started:.1f} s")
    for problem in problems:
        print(problem)
    return len(problems)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("lines", nargs="*", type=Path, help="product lines (default: all)")
    parser.add_argument("--out", type=Path, default=ROOT / "build" / "scan")
    parser.add_argument("--checkov", help="the checkov program to run")
    arguments = parser.parse_args()
    lines = arguments.lines or sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir())
    sys.exit(1 if scan(arguments.out.resolve(), lines, arguments.checkov) else 0)


if __name__ == "__main__":
    main()
