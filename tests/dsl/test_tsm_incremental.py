"""Reading a changed .tsm from the reading before the change (spl.dsl.tsm.incremental)
gives the tree a full reading of the new text gives: after mapping the stored
positions, equal object for object, positions included, and refused exactly where the
full reading refuses. Checked on chains of edits of every shipped and test model, on
generated lines, and through the checks (``check_text`` with the last readings gives
what ``parse_text`` says).
"""

from __future__ import annotations

import random
from typing import Any

from hypothesis import given, settings, strategies as st
from test_tsm_plain import mutated_texts, outcome
from test_tsm_reader import SHIPPED

from spl.dsl.tsm import incremental as tsm_incremental, language as tsm, reader as tsm_reader

from support.hypothesis_budget import examples
from support.model_mutations import mutate, mutations
from support.random_lines import line_specs, tsm_text
from support.typing_edits import edits_of


def read_chain(texts: list[str]) -> None:
    """Each text read from the last reading of the texts before, as the editor reads
    them (a refused text leaves the last reading to start from)."""
    reading = None
    for text in texts:
        expected = tsm_reader.read(text)
        found = tsm_incremental.read(text, reading)
        if found is None:
            assert expected is None, "refused a text the reader reads"
            continue
        reading = found
        assert expected is not None, "read a text the reader refuses"
        assert tsm_incremental.located(reading.tree, reading.places) == expected


def test_edits_of_every_shipped_model_read_as_a_full_reading_reads_them() -> None:
    rng = random.Random(16)
    for path in SHIPPED:
        text = path.read_text(encoding="utf-8")
        read_chain([text, *edits_of(text, rng, 12), text])


def test_text_typed_right_after_an_element_is_read_with_it() -> None:
    """The reader peeks past an element's last token (``A.b`` may go on as ``A.b.c``,
    a topic may get ``name "..."``): an element ending where a change starts is read
    again, not taken over."""
    for path in SHIPPED[:20]:
        text = path.read_text(encoding="utf-8")
        first = tsm_incremental.read(text)
        if first is None:
            continue
        ends = sorted({end for _, end in [*first.elements.values(), *first.members.values()]})
        for end in ends:
            for typed in (".x", "x", ' name "/n"', "2", " {", " every 2 s"):
                read_chain_from(first, text[:end] + typed + text[end:])


def read_chain_from(first: tsm_incremental.Reading, text: str) -> None:
    reading = tsm_incremental.read(text, first)
    expected = tsm_reader.read(text)
    assert (reading is None) == (expected is None)
    if reading is not None:
        assert tsm_incremental.located(reading.tree, reading.places) == expected


def test_the_mutation_corpus_read_as_a_chain_reads_as_a_full_reading() -> None:
    read_chain(mutated_texts(300, 29))


@settings(max_examples=examples(25), deadline=None)
@given(line_specs(), st.data())
def test_edits_of_generated_lines_read_as_a_full_reading_reads_them(spec, data) -> None:
    text = tsm_text(spec)
    texts = [text]
    for _ in range(3):
        texts.append(mutate(text, data.draw(mutations(text))))
    read_chain([*texts, text])


def test_checks_of_a_changed_text_say_what_a_full_check_says() -> None:
    rng = random.Random(8)
    trees = tsm_incremental.Trees()
    for path in SHIPPED[:12]:
        text = path.read_text(encoding="utf-8")
        for edited in [text, *edits_of(text, rng, 6), text]:
            assert outcome(lambda t, f: tsm.check_text(t, f, trees), edited) == outcome(
                tsm.parse_text, edited
            )


def big_text(nodes: int) -> str:
    members = "\n".join(
        f"    node N{i} {{ implementation p/e{i}\n        publishes p : a/B -> T }}"
        for i in range(nodes)
    )
    return f"system S\nrobot container R {{\n    topic T : a/B\n{members}\n}}\n"


def test_an_edit_reads_the_changed_member_and_takes_the_others_over() -> None:
    text = big_text(300)
    first = tsm_incremental.read(text)
    at = text.index("node N150 ") + len("node N150")
    edited = text[:at] + "x" + text[at:]  # N150 -> N150x: one member read again
    second = tsm_incremental.read(edited, first)
    assert second is not None
    old: list[Any] = first.tree.elements[0].members
    new: list[Any] = second.tree.elements[0].members
    assert [n is o for n, o in zip(new, old, strict=True)].count(False) == 1
    # members[0] is the topic: N150 is members[151], read again; N151 after it is taken
    # over as it was read (not moved), its place mapped
    assert new[151] is not old[151] and new[152] is old[152]
    located = tsm_incremental.located(second.tree, second.places)
    assert located == tsm_reader.read(edited) and located.elements[0].members[152].position > at


def test_a_replaced_model_and_reading_are_freed_without_the_cycle_collector() -> None:
    """The editor replaces the model of a 10,000-node file on every change: a reference
    cycle in it would leave 100,000 objects to the collector's full passes (seconds)."""
    import gc

    text = big_text(200)
    edited = text.replace("node N100 ", "node N100x ")
    trees = tsm_incremental.Trees()
    tsm.check_text(text, "m.tsm")  # the plain classes made (pyecore's samples: garbage)
    gc.collect()
    gc.disable()
    try:
        for version in (text, edited, text):
            system = tsm.check_text(version, "m.tsm", trees)
            assert system.containers[0].nodes[5].eContainer() is system.containers[0]
            del system
        del trees
        assert gc.collect() == 0
    finally:
        gc.enable()
