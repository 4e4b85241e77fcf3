"""Print one SHA-256 per bundle of every shipped product: listed products and every valid
product of each line in product_lines/, each resolved by this checkout's `spl` command.

A refactoring must not change what spl writes: run this before and after and compare
(`python scripts/bundle_digests.py > before.txt`, change, `... > after.txt`,
`diff before.txt after.txt`). The digest covers every file's path and bytes; with
`--exclude PREFIX` (repeatable) it leaves out the files under that bundle path, to show
that a change meant for some outputs (`--exclude kubernetes/ --exclude deploy/`) left the
others byte-identical.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SPL = [sys.executable, "-m", "spl"]


EXCLUDED: tuple[str, ...] = ()


def bundle_digest(folder: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(p for p in folder.rglob("*") if p.is_file()):
        if path.relative_to(folder).as_posix().startswith(EXCLUDED):
            continue
        digest.update(path.relative_to(folder).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def selections(line: Path) -> list[tuple[str, str]]:
    """(label, --features argument) of the line's listed and all valid products."""
    listed = [(f"listed/{y.stem}", str(y)) for y in sorted(line.glob("products/*.yaml"))]
    out = subprocess.run(
        [*SPL, "products", str(line), "--json"], capture_output=True, text=True, check=True
    ).stdout
    valid = [json.loads(row) for row in out.splitlines() if row.strip()]
    return listed + [(f"all/{p['index']}", ",".join(p["selection"])) for p in valid]


def resolve(line: Path, label: str, features: str) -> str:
    with tempfile.TemporaryDirectory() as folder:
        bundle = Path(folder) / "bundle"
        run = subprocess.run(
            [*SPL, "resolve", str(line), "--features", features, "-o", str(bundle)],
            capture_output=True, text=True,
        )  # fmt: skip
        outcome = bundle_digest(bundle) if run.returncode == 0 else f"exit {run.returncode}"
    return f"{line.name}/{label} {outcome}"


def main() -> None:
    global EXCLUDED
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--exclude", action="append", default=[], metavar="PREFIX",
        help="leave out the bundle files whose path starts with PREFIX (repeatable)",
    )  # fmt: skip
    EXCLUDED = tuple(parser.parse_args().exclude)
    jobs = [
        (line, label, features)
        for line in sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir())
        for label, features in selections(line)
    ]
    with ThreadPoolExecutor(max_workers=2) as pool:
        for row in pool.map(lambda job: resolve(*job), jobs):
            print(row)


if __name__ == "__main__":
    main()
