"""The editor's template built from the one before it (``spl.dsl.tsm.declarations.build``)
is the model a full copy of the checked text gives: the same declarations, values,
places and references, through chains of edits of every shipped model and of generated
lines. It takes over from the template before exactly the declarations an edit left
alone, and nothing of that template stays reachable from it."""

from __future__ import annotations

import random
from pathlib import Path

from hypothesis import given, settings, strategies as st
from test_tsm_reader import SHIPPED

from spl.core.diagnostics import ModelError
from spl.core.emf import copy_model
from spl.dsl.tsm import language as tsm
from spl.dsl.tsm.declarations import BuiltTemplate, build, declarations

from support.hypothesis_budget import examples
from support.model_mutations import mutate, mutations
from support.random_lines import line_specs, tsm_text
from support.typing_edits import edits_of

FILE = "edited.tsm"
SHIPPED_LINE = Path(__file__).resolve().parents[2] / "product_lines" / "orchard"
EXTRA = """
cloud container Extra {
    topic Seen : std_msgs/String
    optional node Watcher {
        subscribes seen <- Seen
    }
}
"""


def printed(system) -> tuple:
    """Each declaration's print, and its lines: prints count lines from a declaration's
    first, so a declaration taken over must also have been moved right."""
    found = declarations(system)
    return found.own, [(key, d.print, d.lines) for key, d in found.items.items()]


def build_chain(texts: list[str]) -> list[BuiltTemplate]:
    """Each text that checks built from the last template built, as the editor builds
    them, and compared with a full copy."""
    built: list[BuiltTemplate] = []
    for text in texts:
        try:
            plain = tsm.check_text(text, FILE)
        except ModelError:
            continue
        previous = built[-1] if built else None
        template = build(plain, previous, text)
        assert printed(template.system) == printed(copy_model(tsm.check_text(text, FILE)))
        for key, element in template.elements.items():
            owner = template.system if len(key) == 2 else template.elements[key[:2]]
            if key[2:3] == ("interfaces",):  # an endpoint's
                owner = owner.endpoint
            assert element.eContainer() is owner
            if previous is not None and key not in template.rebuilt:
                assert element is previous.elements[key]
        # nothing but the template itself refers to its elements: the template before,
        # and what of it was not taken over, are not kept alive by them
        inside = {id(template.system), *(id(e) for e in template.system.eAllContents())}
        for element in template.system.eAllContents():
            assert all(id(owner) in inside for owner, _ in element._inverse_rels)
        built.append(template)
    return built


def test_edits_of_every_shipped_model_build_what_a_full_copy_builds() -> None:
    rng = random.Random(23)
    for path in SHIPPED:
        text = path.read_text(encoding="utf-8")
        build_chain([text, *edits_of(text, rng, 10), text])


@settings(max_examples=examples(25), deadline=None)
@given(line_specs(), st.data())
def test_edits_of_generated_lines_build_what_a_full_copy_builds(spec, data) -> None:
    text = tsm_text(spec)
    build_chain([text, mutate(text, data.draw(mutations(text))), text + EXTRA, text])


def test_an_edit_takes_over_every_declaration_it_left_alone() -> None:
    """A container added at the end is copied with its members and nothing else; a value
    changed in a node copies that node; lines added before every declaration only move
    them; a node added inside a container is the one declaration copied, the container
    and its other members taken over, in their new order."""
    text = (SHIPPED_LINE / "orchard.tsm").read_text(encoding="utf-8")
    extra = {("containers", "Extra"), *(("containers", "Extra", f, n) for f, n in WATCHED)}
    node = "    optional node Inserted {\n        implementation pkg/inserted\n    }\n"
    inner = text.rindex("\n", 0, text.index("optional node"))
    first, added, changed, moved, inserted = build_chain(
        [
            text,
            text + EXTRA,
            text + EXTRA.replace("subscribes seen", "subscribes heard"),
            "// a comment\n" + text + EXTRA,
            "// a comment\n" + text[: inner + 1] + node + text[inner + 1 :] + EXTRA,
        ]
    )
    assert first.rebuilt == set(first.elements)
    assert added.rebuilt == extra
    assert changed.rebuilt == {("containers", "Extra", "nodes", "Watcher")}
    assert moved.rebuilt == {("containers", "Extra", "nodes", "Watcher")}  # seen again
    (key,) = inserted.rebuilt
    assert key[2:] == ("nodes", "Inserted")
    assert inserted.elements[key[:2]] is moved.elements[key[:2]]  # its container


WATCHED = [("topics", "Seen"), ("nodes", "Watcher")]


STORED = """system Stored

data Reading { celsius : double  variance : double }
data Summary { fahrenheit : double }
transform Summarize : Reading -> Summary {
    fahrenheit = celsius * 9.0 / 5.0 + 32.0
}

robot container Rover {
    endpoint robot_id "rover_1" url "wss://cloud.example.org:9000/" user "rover"
             password env "RCE_PASSWORD"
    topic RReadings : sensor_msgs/Temperature
    writer RWriter : Reading to Planning.PlanningStore <- RReadings
    topic RT0 : sensor_msgs/PointCloud2 name "/R/t0"
    node RN0 {
        implementation pkg_rover/node_0
        publishes out -> RT0
        provides lookup : nav_msgs/GetMap name "/R/lookup0"
    }
    node RN1 {
        implementation pkg_rover/node_1
        calls lookup -> RN0.lookup
        subscribes in <- RT0
    }
}

cloud container Planning group "plannings" {
    store PlanningStore {
        raw Reading
        refined Summary by Summarize every 10 s
    }
    topic PT0 : sensor_msgs/PointCloud2 name "/P/t0"
    node PN0 {
        implementation pkg_planning/node_0
        publishes out -> PT0
    }
}
"""


def test_a_container_whose_text_is_unchanged_is_taken_over_unread(monkeypatch) -> None:
    """After an edit inside one container, another whose text is the same (only moved)
    is taken over without being printed, whole or member by member; one that refers
    into a declaration the edit changed is read, since its print may have changed with
    it. Either way the template is the one a full copy builds."""
    from spl.dsl.tsm import declarations as module

    read: list[tuple] = []  # the keys of the declarations printed, in every build
    for name in ("_read", "_read_whole"):
        real = getattr(module, name)

        def counted(root, key, *rest, real=real):
            read.append(key)
            return real(root, key, *rest)

        monkeypatch.setattr(module, name, counted)
    inside = STORED.index("    node RN1")
    added = STORED[:inside] + "    node Added {\n        implementation p/a\n    }\n"
    added += STORED[inside:]
    transformed = added.replace("* 9.0", "* 9.5")
    texts = [STORED, added, transformed, "// moved\n" + transformed]
    containers, previous = [], None
    for text in texts:
        plain = tsm.check_text(text, FILE)
        read.clear()
        previous = build(plain, previous, text)
        containers.append({key[1] for key in read if key[0] == "containers"})
        assert printed(previous.system) == printed(copy_model(tsm.check_text(text, FILE)))
    assert containers[1] == {"Rover"}  # a node added there, Planning's text as it was
    # the transform Planning's store refers to: Planning is read again
    assert containers[2] == {"Planning"}
    # every line moved, no text changed: no container printed again
    assert containers[3] == set()
