"""A module a reader takes in at once: every hand-written module of spl is at most 400
lines (docs/architecture.md). Past that, a module is split by responsibility, as
src/spl/dsl/rm/messages.py was from rm_names.py. Modules written by a script from a source of
truth (the typed metamodels, from the .ecore files) are exempt: nobody edits them, and
tests/cli/test_ecore_types.py checks they are what the script writes."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FOLDERS = ("src", "scripts", "bench")
LIMIT = 400
GENERATED = "Written by scripts/ecore_types.py from the .ecore file: do not edit"


def _modules() -> list[Path]:
    return sorted(
        path
        for folder in FOLDERS
        for path in (ROOT / folder).rglob("*.py")
        if "__pycache__" not in path.parts
    )


def test_no_hand_written_module_is_over_400_lines() -> None:
    too_long = []
    for path in _modules():
        text = path.read_text(encoding="utf-8")
        if GENERATED in text[:2000]:
            continue
        lines = text.count("\n")
        if lines > LIMIT:
            too_long.append(f"{path.relative_to(ROOT)}: {lines} lines")
    assert not too_long, "split these by responsibility: " + "; ".join(too_long)


def test_the_exemption_covers_only_the_generated_metamodels() -> None:
    exempt = [
        path.relative_to(ROOT).as_posix()
        for path in _modules()
        if GENERATED in path.read_text(encoding="utf-8")[:2000]
    ]
    assert exempt == [
        "src/spl/metamodels/fm_types.py",
        "src/spl/metamodels/rm_types.py",
        "src/spl/metamodels/tsm_types.py",
    ]
