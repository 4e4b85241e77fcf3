"""spl imports a dependency only where the command run needs it.

Start-up time is measured by ``bench/cli_start.py``; this checks the mechanism that keeps
it low, in a fresh interpreter per command: which third-party packages (and which spl
commands) a command run leaves in ``sys.modules``.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from real_models import REAL_MODELS

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("textx", "pyecore", "lxml", "jinja2", "networkx", "graphviz", "jsonschema", "yaml")


def imported_after(*arguments: str) -> set[str]:
    """Top-level packages and spl.commands modules imported by ``spl ARGUMENTS``."""
    script = (
        "import json, sys\n"
        "from spl.cli import main\n"
        "try:\n"
        f"    main({list(arguments)!r})\n"
        "except SystemExit as exc:\n"
        "    assert not exc.code, exc.code\n"
        "names = {m.split('.')[0] for m in sys.modules}\n"
        "names |= {m for m in sys.modules if m.startswith('spl.commands.')}\n"
        "print(json.dumps(sorted(names)), file=sys.stderr)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, check=True
    )
    return set(json.loads(done.stderr.strip().splitlines()[-1]))


def test_analyze_of_a_uvl_file_needs_neither_textx_nor_pyecore() -> None:
    found = imported_after("analyze", "--json", str(REAL_MODELS / "berkeleydb.uvl"))
    assert "pysat" in found
    assert not found & set(HEAVY), found & set(HEAVY)
    assert {m for m in found if m.startswith("spl.commands.")} == {"spl.commands.analyze"}


def test_check_of_a_line_loads_only_what_checking_uses() -> None:
    found = imported_after("check", "product_lines/mapping3d")
    assert {"textx", "pyecore", "pysat", "yaml"} <= found
    assert not found & {"lxml", "jinja2", "networkx", "graphviz", "jsonschema"}
    assert {m for m in found if m.startswith("spl.commands.")} == {"spl.commands.check"}


def test_help_still_lists_every_command() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "spl", "--help"], cwd=ROOT, capture_output=True, text=True
    )
    assert done.returncode == 0
    listed = {line.split()[0] for line in done.stdout.split("Commands:")[1].splitlines() if line}
    modules = {
        p.stem for p in (ROOT / "spl" / "commands").glob("*.py") if not p.stem.startswith("_")
    }
    assert listed == modules - {"selection_options"}
