"""An option added to a statement of ``tsm.tx`` (a closing ``('KEYWORD' attr=VALUE)?``)
with its attribute in ``tsm.ecore`` needs no edit of the fast reader, the builder or the
printer (docs/architecture.md, "Adding one .tsm element, end to end"): rehearsed on a
copy of the source tree whose grammar and metamodel give service clients a ``timeout``,
the fast reader reads every form of the statement as textX reads it, the builder copies
the value into the model and refuses one out of its type's range at its column, and
the printer writes it back (``resolved.tsm``)."""

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
SERVICE_CLIENT = (
    '<eClassifiers xsi:type="ecore:EClass" name="ServiceClient" eSuperTypes="#//Interface">\n'
)
TIMEOUT_ATTRIBUTE = (
    '<eStructuralFeatures xsi:type="ecore:EAttribute" name="timeout" '
    'eType="ecore:EDataType http://www.eclipse.org/emf/2002/Ecore#//EDouble"/>\n'
)

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

from spl.core.diagnostics import ModelError
from spl.dsl.tsm import printer
text = head + forms[1] + "\n  calls d -> M.s\n }\n}\n"
model = language.parse_text(text, "m.tsm")
first, second = model.containers[0].nodes[1].interfaces
print(first.timeout, first.external, second.timeout)
printed = printer.print_model(model)
print([line.strip() for line in printed.splitlines() if line.strip().startswith("calls")])
assert printer.print_model(language.parse_text(printed, "again.tsm")) == printed
try:
    language.parse_text(head + "calls c -> M.s timeout 1e999\n }\n}\n", "bad.tsm")
except ModelError as error:
    print(error)
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
    metamodel = source / "spl" / "metamodels" / "tsm.ecore"
    text = metamodel.read_text(encoding="utf-8")
    assert SERVICE_CLIENT in text
    metamodel.write_text(text.replace(SERVICE_CLIENT, SERVICE_CLIENT + TIMEOUT_ATTRIBUTE))
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
    read, built, printed, refused = done.stdout.split("\n")[:4]
    assert read == "Calls ('position', 'name', 'type', 'server', 'timeout', 'external') 2.5"
    assert built == "0.5 a driver 0.0"  # the metamodel's default where none is written
    assert printed == str(['calls c -> M.s timeout 0.5 external "a driver"', "calls d -> M.s"])
    assert refused == "bad.tsm:5:26: error: timeout 1e999 is out of range of EDouble"


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
