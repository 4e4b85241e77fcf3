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

import pytest

from support.real_models import REAL_MODELS

ROOT = Path(__file__).resolve().parents[2]
HEAVY = ("textx", "pyecore", "lxml", "jinja2", "networkx", "graphviz", "jsonschema", "yaml")


def imported_after(*arguments: str, planted: str = "") -> set[str]:
    """Top-level packages and spl.cli.commands modules imported by ``spl ARGUMENTS``
    (``planted``: code run first, as a module of spl could run it when imported)."""
    script = (
        "import json, sys\n"
        f"{planted}\n"
        "from spl.cli import main\n"
        "try:\n"
        f"    main({list(arguments)!r})\n"
        "except SystemExit as exc:\n"
        "    assert not exc.code, exc.code\n"
        "names = {m.split('.')[0] for m in sys.modules}\n"
        "names |= {m for m in sys.modules if m.startswith(('spl.cli.commands.', 'importlib.'))}\n"
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
    assert {m for m in found if m.startswith("spl.cli.commands.")} == {"spl.cli.commands.analyze"}


# What no check of a shipped model imports: textX (and its parser arpeggio) only parses
# what the fast readers leave, and importlib.resources' files() pulls zipfile, tempfile...
NOT_FOR_CHECKING = {"textx", "arpeggio", "lxml", "jinja2", "networkx", "graphviz", "jsonschema"}


def test_check_of_a_line_loads_only_what_checking_uses() -> None:
    found = imported_after("check", "product_lines/mapping3d")
    assert {"pyecore", "pysat", "yaml"} <= found
    assert not found & NOT_FOR_CHECKING, found & NOT_FOR_CHECKING
    assert "importlib.resources" not in found
    assert {m for m in found if m.startswith("spl.cli.commands.")} == {"spl.cli.commands.check"}


@pytest.mark.parametrize(
    "model", ["mapping.fm", "mapping.rm", "mapping.tsm"], ids=lambda name: name.split(".")[1]
)
def test_check_of_one_model_needs_no_textx(model: str) -> None:
    found = imported_after("check", f"product_lines/mapping3d/{model}")
    assert not found & NOT_FOR_CHECKING, found & NOT_FOR_CHECKING


def test_an_eager_import_of_textx_in_the_check_path_is_found() -> None:
    """The checks above fail when a module ``spl check`` imports imports textX itself:
    here planted in spl.dsl.rm.language as an import at its top would do."""
    planted = "import spl.dsl.rm.language; exec('import textx', vars(spl.dsl.rm.language))"
    found = imported_after("check", "product_lines/mapping3d", planted=planted)
    assert "textx" in found & NOT_FOR_CHECKING


def test_help_still_lists_every_command() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "spl", "--help"], cwd=ROOT, capture_output=True, text=True
    )
    assert done.returncode == 0
    listed = {line.split()[0] for line in done.stdout.split("Commands:")[1].splitlines() if line}
    modules = {  # a command's module is named like it, with _ for - (import_: a keyword)
        p.stem.rstrip("_").replace("_", "-")
        for p in (ROOT / "src" / "spl" / "cli" / "commands").glob("*.py")
        if not p.stem.startswith("_")
    }
    assert listed == modules - {"selection-options"}
