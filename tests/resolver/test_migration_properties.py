"""Property-based tests of node migration with endpoint rewiring (docs/resolution.md).

Random small templates (2-4 robot and cloud containers, publishers, subscribers,
service servers and clients, topic and service bridges) and random migration sets,
each under its own feature, are resolved through the public API and the resolved
architecture is checked against docs/resolution.md (tests/support/flow_invariants.py):
every template
flow between kept nodes still delivered, every client reaching its server, no bridge
inside a container, no hairpin, no duplicate bridge, a migrated node's interfaces all
wired; the output is deterministic, and resolving the resolved model again with no
resolution element changes nothing. Shrunk counterexamples are the ordinary tests of
test_migration_regressions.py.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import given, settings, strategies as st

from spl.dsl.tsm.printer import print_model
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.flow_invariants import check_resolved
from support.hypothesis_budget import examples
from support.random_lines import LineSpec, line_specs, write_line


def resolved_text(directory: Path, features: list[str]) -> str:
    line = load_product_line(directory)
    product = resolve(line, selection_from_list(",".join(["Root", *features]))).product
    return print_model(product.system)


def check_line(spec: LineSpec, selected: set[str]) -> None:
    with tempfile.TemporaryDirectory() as scratch:
        directory = write_line(spec, Path(scratch) / "random")
        line = load_product_line(directory)
        selection = ",".join(["Root", *sorted(selected)])
        product = resolve(line, selection_from_list(selection)).product
        check_resolved(spec, selected, product.system, product.warnings)
        text = print_model(product.system)
        again = resolve(line, selection_from_list(selection)).product
        assert print_model(again.system) == text, "resolving twice gave two models"

        identity = Path(scratch) / "identity"
        identity.mkdir()
        (identity / "random.tsm").write_text(text, encoding="utf-8")
        (identity / "random.fm").write_text("feature model Random\nroot Root\n", encoding="utf-8")
        (identity / "random.rm").write_text(
            'resolution model Random\ntsm "random.tsm"\nfm "random.fm"\n', encoding="utf-8"
        )
        assert resolved_text(identity, []) == text, "resolving the resolved model changed it"


@st.composite
def lines_and_selections(draw):
    spec = draw(line_specs())
    selected = draw(st.sets(st.sampled_from(spec.features()))) if spec.elements else set()
    return spec, selected


@settings(max_examples=examples(150))
@given(lines_and_selections())
def test_migrations_keep_every_flow_and_call_with_minimal_bridges(case):
    check_line(*case)
