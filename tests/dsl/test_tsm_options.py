"""An option added to a statement of ``tsm.tx`` (a closing ``('KEYWORD' attr=VALUE)?``)
needs no edit of the fast reader (docs/architecture.md, "Adding one .tsm element, end to
end"): rehearsed on a copy of the source tree whose grammar gives service clients a
``timeout``, the fast reader reads every form of the statement as textX reads it."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from spl.dsl.tsm.options import options
from spl.dsl.tsm.tree import INTERFACE_RULES, QUOTED_STRING

ROOT = Path(__file__).resolve().parents[2]
CALLS = """Calls: 'calls' name=Name ( (':' type=TypeRef ('->' server=QRef)?) | ('->' server=QRef) )
    ('external' external=Str)?;"""
TIMEOUT = CALLS.replace("('external'", "('timeout' timeout=NumberLiteral)? ('external'")

REHEARSAL = r"""
import spl
from pathlib import Path
from support.textx_trees import assert_reads_as_textx
from spl.dsl.tsm import language, reader

assert Path(spl.__file__).is_relative_to(Path(__SRC__)), spl.__file__
head = "system S\ncloud container C {\n node M { provides s : p/S }\n node N {\n  "
forms = [
    "calls c -> M.s timeout 2.5",
    "calls c : p/S -> M.s timeout .5 external \"a driver\"",
    "calls c : p/S timeout 3",
    "calls c -> M.s external \"x\"",
    "calls c -> M.s timeout",
    "calls c -> M.s external \"x\" timeout 2",
    "calls action c -> M.s timeout 2",
]
for form in forms:
    text = head + form + "\n }\n}\n"
    assert_reads_as_textx(reader.read, language._grammar(), text)
(container,) = reader.read(head + forms[0] + "\n }\n}\n").elements
client = container.members[1].members[0]
print(type(client).__name__, client._fields, client.timeout.value)
"""


def _rehearsal_tree(tmp_path: Path) -> Path:
    """A copy of ``src/`` whose grammar gives a service client a ``timeout``."""
    source = tmp_path / "src"
    shutil.copytree(
        ROOT / "src" / "spl", source / "spl", ignore=shutil.ignore_patterns("__pycache__")
    )
    grammar = source / "spl" / "dsl" / "tsm" / "tsm.tx"
    text = grammar.read_text(encoding="utf-8")
    assert CALLS in text
    grammar.write_text(text.replace(CALLS, TIMEOUT), encoding="utf-8")
    return source


def test_an_option_added_to_the_grammar_is_read_as_textx_reads_it(tmp_path: Path) -> None:
    source = _rehearsal_tree(tmp_path)
    script = REHEARSAL.replace("__SRC__", repr(str(source)))
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(source), str(ROOT / "tests")])}
    done = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        env=environment,
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[0] == (
        "Calls ('position', 'name', 'type', 'server', 'timeout', 'external') 2.5"
    )


@pytest.mark.parametrize(
    ("rule", "declared"),
    [("Provides", [("name", "rosName")]), ("Calls", [("external", "external")])],
)
def test_the_options_of_a_rule_are_its_closing_keyword_parts(rule, declared) -> None:
    found = options(rule)
    assert [(o.keyword, o.attribute) for o in found] == declared
    assert all(o.value == "Str" and o.terminal.pattern == QUOTED_STRING.pattern for o in found)
    assert INTERFACE_RULES[rule]._fields[-len(found) :] == tuple(a for _, a in declared)
    assert options("Publishes") == ()
