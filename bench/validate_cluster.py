"""What a validation on a Dask cluster costs, part by part (docs/scale.md).

    .venv/bin/python bench/validate_cluster.py [--workers 2] [--tasks 2000]

Measures, on the shipped product lines:

* a product's cost: ``spl validate --all`` with one job, divided by its products, and
  ``--smoke`` on the listed products of mapping3d (one rehearsal per product);
* the same runs on a LocalCluster of ``--workers`` workers (``--scheduler local:N``),
  wall clock including the cluster's start;
* the scheduler's own cost per task: ``--tasks`` empty tasks through the same cluster;
* what the client sends: each line's packed files, in bytes, and the time to pack them.

Every figure is the wall clock of one run on this machine, with the load average, as
docs/performance.md gives them.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LINES = sorted(str(p) for p in (ROOT / "product_lines").iterdir() if (p / "products").is_dir())
SPL = [str(Path(sys.executable).with_name("spl"))]


def timed(args: list[str]) -> tuple[float, str]:
    start = time.perf_counter()
    done = subprocess.run([*SPL, *args], cwd=ROOT, capture_output=True, text=True, check=True)
    return time.perf_counter() - start, done.stdout.splitlines()[-1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--tasks", type=int, default=2000)
    options = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}")

    one, summary = timed(["validate", *LINES, "--all"])
    products = int(summary.split()[0])
    print(
        f"--all, one job: {products} products in {one:.1f} s, {one / products * 1000:.0f} ms each"
    )
    cluster = f"local:{options.workers}"
    on_cluster, _ = timed(["validate", *LINES, "--all", "--scheduler", cluster])
    print(f"--all, {cluster}: {on_cluster:.1f} s (cluster start included)")

    smoked = [str(ROOT / "product_lines" / "mapping3d")]
    one, summary = timed(["validate", *smoked, "--smoke"])
    count = int(summary.split()[0])
    print(f"--smoke, one job: {count} products in {one:.1f} s, {one / count:.1f} s each")
    on_cluster, _ = timed(["validate", *smoked, "--smoke", "--scheduler", cluster])
    print(f"--smoke, {cluster}: {on_cluster:.1f} s (cluster start included)")

    from distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=options.workers, threads_per_worker=1, dashboard_address=None
        ) as local,
        Client(local) as client,
    ):
        start = time.perf_counter()
        client.gather(client.map(abs, range(options.tasks)))
        spent = time.perf_counter() - start
        print(
            f"scheduler: {options.tasks} empty tasks in {spent:.2f} s, "
            f"{spent / options.tasks * 1000:.2f} ms each"
        )

    from spl.validation.cluster import pack
    from spl.validation.line import load_lines

    for loaded in load_lines([Path(line) for line in LINES]):
        start = time.perf_counter()
        packed = pack(loaded)
        size = sum(len(data) for _, data in packed.files)
        print(
            f"line {loaded.name}: {len(packed.files)} files, {size / 1024:.1f} KiB, "
            f"packed in {(time.perf_counter() - start) * 1000:.1f} ms"
        )


if __name__ == "__main__":
    main()
