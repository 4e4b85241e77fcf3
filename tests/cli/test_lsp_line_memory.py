"""What the editor keeps of a line between its checks (docs/editors.md, "What the editor
keeps"): the facts of the template alone while the template is the same model, and
the .rm's elements an edit left alone; every answer is a full check's."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

from test_lsp_line_checks import EXTRA, SPARE, WAREHOUSE, copied, full_check

from spl.dsl.tsm.incremental import Trees
from spl.lsp import checking
from spl.resolver.line_checks.dataflow_memory import DataflowFindings
from spl.resolver.resolution.product_line import TemplateFacts

CONFLICT = (
    "\nwhen Sensing selected {\n    implementation Localizer = a/b\n}\n"
    "when CameraSensing selected {\n    implementation Localizer = c/d\n}\n"
)


def test_the_template_facts_are_computed_again_only_for_another_template(
    tmp_path, monkeypatch
) -> None:
    """An edit of the .rm or .fm leaves the template the same model: none of its facts
    (its flows, reach, unreferred optionals, the image products are copied from) is
    computed again, also when witness products are resolved again; an edit of the .tsm
    makes another template, whose facts the check then computes anew."""
    from spl.resolver.resolution import engine

    folder, inputs = copied(WAREHOUSE, tmp_path)
    paths = {kind: str(folder / f"warehouse.{kind}") for kind in ("tsm", "rm", "fm")}
    original = {kind: Path(path).read_text(encoding="utf-8") for kind, path in paths.items()}
    checks, trees = checking.LineChecks(), Trees()
    memory = checks.workspace.line_memory(folder)
    assert memory is not None
    facts = memory.of(TemplateFacts)
    resolved: list[object] = []
    real = engine.resolve
    monkeypatch.setattr(engine, "resolve", lambda *a: resolved.append(a) or real(*a))

    def check(**edits: str) -> tuple[Counter[str], int]:
        """The facts this check computed, and the witness products it resolved."""
        texts = {paths[kind]: text for kind, text in {**original, **edits}.items()}
        before = Counter(facts.made)
        resolved.clear()
        found, _ = checks.check(str(folder), texts, trees, inputs)
        made, resolutions = facts.made - before, len(resolved)
        assert found == full_check(folder, texts)  # (which keeps no facts)
        return made, resolutions

    every = Counter(template_image=1, template_flows=1, template_reach=1, unreferred_optionals=1)
    assert check() == (every, 2)  # one witness product per unfed input
    # a conflict both witnesses activate: they are resolved again, from the kept image
    made, resolutions = check(rm=original["rm"] + CONFLICT)
    assert not made and resolutions > 0
    # the elements the witnesses activate moved: resolved again, from the kept image
    assert check(rm=original["rm"].replace("when CameraSensing", "\nwhen CameraSensing")) == (
        Counter(),
        2,
    )
    docking = original["fm"].replace("optional Offload", "optional Offload\n    optional Docking")
    assert check(fm=docking) == (Counter(), 2)
    # a container every product drops: another template, whose facts are its own
    assert check(tsm=original["tsm"] + SPARE) == (every, 2)
    # a value of a node both witnesses keep: resolved again, from the new template's image
    value = original["tsm"].replace("amcl/amcl", "amcl/amcl_fast")
    assert check(tsm=value) == (every, 2)
    assert check(tsm=value, rm=original["rm"] + CONFLICT)[0] == Counter()


TYPED = "    optional node Typed {\n        implementation spare/typed\n    }\n"
LISTENER = (
    "    optional node Listener {\n        implementation spare/listener\n"
    "        subscribes scan <- Scan\n    }\n"
)
TALKER = (
    "    optional node Talker {\n        implementation spare/talker\n"
    "        publishes scan -> Scan\n    }\n"
)


def test_the_dataflow_findings_are_found_again_only_when_what_the_check_reads_changed(
    tmp_path,
) -> None:
    """The editor keeps the dataflow check's findings (SPL045, SPL046) while the check
    would read the same: a node typed in that no element requires yet and that has no
    publisher or server, or a container of only such nodes, leaves them as they were,
    moved with their declarations; a node that could feed an input, or one an element
    requires, has them found again. Every answer is a full check's."""
    folder, inputs = copied(WAREHOUSE, tmp_path)
    paths = {kind: str(folder / f"warehouse.{kind}") for kind in ("tsm", "rm")}
    original = {kind: Path(path).read_text(encoding="utf-8") for kind, path in paths.items()}
    checks, trees = checking.LineChecks(), Trees()
    memory = checks.workspace.line_memory(folder)
    assert memory is not None
    kept = memory.of(DataflowFindings)
    top = original["tsm"].index("    optional node Lidar")

    def check(**edits: str) -> tuple[int, list[tuple[str, int]]]:
        """How often the dataflow check ran, and where its findings are."""
        texts = {paths[kind]: text for kind, text in {**original, **edits}.items()}
        before = kept.checks
        found, _ = checks.check(str(folder), texts, trees, inputs)
        assert found == full_check(folder, texts)
        unfed = [(d.code or "", d.location.line) for d in found if d.code in ("SPL045", "SPL046")]
        return kept.checks - before, unfed

    ran, unfed = check()
    assert ran == 1 and [code for code, _ in unfed] == ["SPL045", "SPL046"]

    def above_lidar(text: str) -> str:
        return original["tsm"][:top] + text + original["tsm"][top:]

    # three lines above every finding: kept, each moved with its node
    assert check(tsm=above_lidar(TYPED)) == (0, [(c, line + 3) for c, line in unfed])
    assert check(tsm=above_lidar(TYPED + LISTENER))[0] == 0  # an input in no product
    assert check(tsm=original["tsm"] + EXTRA)[0] == 0  # a container of only such a node
    assert check(tsm=above_lidar(TALKER))[0] == 1  # it could feed Localizer.scan
    required = original["rm"] + "\nwhen Offload selected {\n    require Typed\n}\n"
    assert check(tsm=above_lidar(TYPED), rm=required)[0] == 1  # a product may keep it
    # another node typed in beside it: the .rm model is kept, and the findings with it
    assert check(tsm=above_lidar(TYPED + LISTENER), rm=required)[0] == 0
