"""The editor's product-line check (``spl check FOLDER`` for a .tsm, .fm or .rm of a
line) answers what a full check of the same texts answers, through a chain of edits a
user makes, while it re-checks only when an input changed and skips the model build of
a .tsm that does not build (docs/editors.md)."""

from __future__ import annotations

import gc
import os
import random
import re
import shutil
import weakref
from pathlib import Path

import pytest

from spl.dsl.tsm import language as tsm
from spl.dsl.tsm.incremental import Trees
from spl.dsl.workspace import Workspace
from spl.lsp import checking

from support.typing_edits import model_edit

ROOT = Path(__file__).resolve().parents[2]
WAREHOUSE = ROOT / "tests" / "models" / "line_checks" / "warehouse"
EDITS = 80  # edits per line in the random chains
EXTRA = """
cloud container Extra {
    optional node ExtraNode {
        implementation p/e
    }
}
"""


def copied(line: Path, tmp_path: Path) -> tuple[Path, set[str]]:
    """A copy of the product line ``line`` to edit, and the files its check reads."""
    folder = tmp_path / line.name
    shutil.copytree(line, folder)
    return folder, {os.path.join(folder, name) for name in os.listdir(folder)}


def full_check(folder: Path, texts: dict[str, str]) -> tuple:
    """What ``spl check FOLDER`` says of these texts, every model built afresh (a new
    workspace, which keeps no models)."""
    return checking.check_line(str(folder), Workspace().reading(texts))


def tsm_builds(monkeypatch) -> list[str]:
    """The .tsm builds made from now on, each "plain" or "pyecore" (its metamodel)."""
    from spl.dsl.tsm import plain as tsm_plain

    builds: list[str] = []
    real = tsm._parse

    def counted(text, filename, metamodel, *rest):
        builds.append("plain" if metamodel is tsm_plain.metamodel() else "pyecore")
        return real(text, filename, metamodel, *rest)

    monkeypatch.setattr(tsm, "_parse", counted)
    return builds


def test_the_line_check_follows_every_edit_and_reuses_only_unchanged_inputs(tmp_path) -> None:
    folder = tmp_path / "orchard"
    shutil.copytree(ROOT / "product_lines" / "orchard", folder)
    path = str(folder / "orchard.tsm")
    original = Path(path).read_text(encoding="utf-8")
    checks, trees = checking.LineChecks(), Trees()

    def inputs() -> set[str]:
        return {os.path.join(folder, name) for name in os.listdir(folder)}

    made: list[checking.FileCheck] = []  # every .tsm check the line checks made

    def check(text: str) -> tuple[tuple, bool]:
        """The answer, and whether the .tsm was checked for it (else it came with a kept
        answer: the very check, and model, made for the same text before)."""
        texts = {path: text}
        found, plain = checks.check(str(folder), texts, trees, inputs())
        assert found == full_check(folder, texts)
        [tsm_check] = plain  # the requests read its model: one per answer, kept or new
        assert tsm_check.path == path
        ran = not any(tsm_check is earlier for earlier in made)
        made.append(tsm_check)
        return found, ran

    found, ran = check(original)
    assert ran and not any(d.severity == "error" for d in found)
    assert check(original) == (found, False)  # nothing changed: the last answer

    broken = original + "bridge Harvester.Image -> Nowhere.Image\n"
    refused, ran = check(broken)
    assert ran and [d.message for d in refused] == ["unknown container Nowhere"]
    syntax, ran = check(original.replace("robot container Scout {", "robot container Scout {{"))
    assert ran and syntax[0].severity == "error"

    assert check(original) == (found, False)  # the edit undone
    for edit in range(2 * checking.LineChecks.KEPT):  # edits, each undone: still kept
        assert check(original + f"// {edit}\n")[1]
        assert check(original) == (found, False)

    # an emptied buffer is checked as empty, not as the file saved on disk (textX read
    # that when given an empty text): the .rm's names then lead nowhere
    emptied, ran = check("")
    assert ran and "unknown node or store FruitDetector" in [d.message for d in emptied]

    extended, ran = check(original + EXTRA)  # valid, and only the line's checks see it
    assert ran and any(d.code == "SPL011" and "ExtraNode" in d.message for d in extended)

    # files the editor has not open count by what is on disk: the feature model ...
    fm = folder / "orchard.fm"
    fm.write_text(fm.read_text(encoding="utf-8") + "\n// saved again\n", encoding="utf-8")
    _, ran = check(original)
    assert ran
    # ... and the listed products
    (folder / "products" / "broken.yaml").write_text("product: broken\nfeatures: [Nothing]\n")
    with_broken, ran = check(original)
    assert ran and any(d.code == "SPL015" for d in with_broken)


def test_a_refused_tsm_is_built_once_in_plain_objects(tmp_path, monkeypatch) -> None:
    """A .tsm that does not build is read once, by the plain build: loading the line,
    then its files one by one, meets the problems the plain build found."""
    folder = tmp_path / "orchard"
    shutil.copytree(ROOT / "product_lines" / "orchard", folder)
    path = str(folder / "orchard.tsm")
    broken = Path(path).read_text(encoding="utf-8") + "bridge Harvester.Image -> Nowhere.Image\n"
    builds = tsm_builds(monkeypatch)
    inputs = {os.path.join(folder, name) for name in os.listdir(folder)}
    found, _ = checking.LineChecks().check(str(folder), {path: broken}, Trees(), inputs)
    assert [d.message for d in found] == ["unknown container Nowhere"]
    assert builds == ["plain"]


def test_an_edit_builds_its_tsm_once_for_its_diagnostics_and_the_line(
    tmp_path, monkeypatch
) -> None:
    """A valid edit of a line's .tsm is built once, in plain objects: the model its own
    diagnostics came from is the one the line's template is built from (the workspace's
    record of both), and an edit undone builds nothing."""
    folder, inputs = copied(ROOT / "product_lines" / "orchard", tmp_path)
    path = str(folder / "orchard.tsm")
    original = Path(path).read_text(encoding="utf-8")
    builds = tsm_builds(monkeypatch)
    checks, trees = checking.LineChecks(), Trees()
    models = checks.workspace.models
    assert models is not None

    def check(text: str) -> tuple[checking.FileCheck, list[str]]:
        """The .tsm's check, and the builds the editor's check made (not the full one's)."""
        builds.clear()
        found, [own] = checks.check(str(folder), {path: text}, trees, inputs)
        built = list(builds)
        assert found == full_check(folder, {path: text})
        if built:  # the model shown on the file is the one the line's template came from
            assert built == ["plain"]
            assert models.checked[path] == (text, own.model)
            template = models.templates[path]
            assert models.systems[path] == (text, template.system)
            for container in own.model.containers:
                key = ("containers", container.name)
                assert template.declarations.items[key].element is container
        return own, built

    first, built = check(original)
    assert built == ["plain"]
    assert check(original + EXTRA)[1] == ["plain"]
    assert check(original) == (first, [])  # undone: its check, and model, as they were
    assert check(original + EXTRA.replace("Extra", "Other"))[1] == ["plain"]


def test_witness_products_are_resolved_again_only_when_what_they_read_changed(
    tmp_path, monkeypatch
) -> None:
    """The dataflow check resolves a witness product per unfed input; the editor keeps
    those resolutions while the template, the feature model and the elements the witness
    activates stay as they were, and answers as a full check does either way."""
    from spl.resolver.resolution import engine

    folder, inputs = copied(WAREHOUSE, tmp_path)
    rm, fm = str(folder / "warehouse.rm"), str(folder / "warehouse.fm")
    original = {rm: Path(rm).read_text(encoding="utf-8"), fm: Path(fm).read_text(encoding="utf-8")}
    checks, trees = checking.LineChecks(), Trees()
    resolved: list[str] = []
    real = engine.resolve

    def counted(line, selection):
        resolved.append(",".join(selection.features))
        return real(line, selection)

    monkeypatch.setattr(engine, "resolve", counted)

    def check(**edits: str) -> tuple[list[str], int]:
        texts = dict(original)
        texts.update({rm if name == "rm" else fm: text for name, text in edits.items()})
        resolved.clear()
        found, _ = checks.check(str(folder), texts, trees, inputs)
        resolutions = len(resolved)
        assert found == full_check(folder, texts)
        codes = [d.code or "" for d in found if d.code in ("SPL045", "SPL046", "SPL012")]
        return codes, resolutions

    unfed, resolutions = check()
    assert unfed == ["SPL045", "SPL046"] and resolutions == 2  # one witness each

    # a new element for a feature neither witness selects: nothing they read changed
    lidar = "\nwhen LidarSensing selected {\n    implementation Lidar = x/y\n}\n"
    assert check(rm=original[rm] + lidar) == (["SPL045", "SPL046"], 0)
    # a comment at the end of the feature model: the same model, at the same places
    assert check(fm=original[fm] + "// reviewed\n") == (["SPL045", "SPL046"], 0)

    # an element both witnesses activate, which makes them fail to resolve: the inputs
    # are no longer reported with them (a kept resolution would still report them)
    conflict = (
        "\nwhen Sensing selected {\n    implementation Localizer = a/b\n}\n"
        "when CameraSensing selected {\n    implementation Localizer = c/d\n}\n"
    )
    unfed, resolutions = check(rm=original[rm] + conflict)
    assert unfed == ["SPL012"] and resolutions > 0

    # the elements the witnesses activate moved down a line: their places are read again
    moved = original[rm].replace("when CameraSensing", "\nwhen CameraSensing")
    unfed, resolutions = check(rm=moved)
    assert unfed == ["SPL045", "SPL046"] and resolutions == 2
    # a feature added to the feature model: resolved again
    more = original[fm].replace("optional Offload", "optional Offload\n    optional Docking")
    unfed, resolutions = check(fm=more)
    assert unfed == ["SPL045", "SPL046"] and resolutions == 2


SPARE = """
cloud container Spare {
    topic Seen : std_msgs/String
    optional node Watcher {
        implementation spare/watcher
        subscribes seen <- Seen
    }
}
"""


DROPPED = "    optional node Dropped {\n        implementation spare/dropped\n    }\n"


def test_a_tsm_edit_builds_again_only_what_it_touched(tmp_path, monkeypatch) -> None:
    """After an edit of the .tsm, the line's .rm model is built again only when the edit
    touched a declaration it refers into or declares a name it mentions, and a witness
    product is resolved again only when the edit touched a declaration it keeps (lines
    that only moved are not touched: the warnings move with them); every answer is a
    full check's. What each model refers to is forgotten when the next is
    built: the template holds no more references after many edits than after one."""
    from spl.dsl.rm import language as rm
    from spl.resolver.resolution import engine

    folder, inputs = copied(WAREHOUSE, tmp_path)
    path = str(folder / "warehouse.tsm")
    original = Path(path).read_text(encoding="utf-8")
    checks, trees = checking.LineChecks(), Trees()
    counts = {"rm": 0, "resolve": 0}

    def counting(name, real):
        def counted(*args, **kwargs):
            counts[name] += 1
            return real(*args, **kwargs)

        return counted

    monkeypatch.setattr(rm._Builder, "build", counting("rm", rm._Builder.build))
    monkeypatch.setattr(engine, "resolve", counting("resolve", engine.resolve))

    def check(text: str) -> tuple[list[str], int, int]:
        counts.update(rm=0, resolve=0)
        found, _ = checks.check(str(folder), {path: text}, trees, inputs)
        done = counts["rm"], counts["resolve"]
        assert found == full_check(folder, {path: text})
        codes = [d.code or "" for d in found if d.code in ("SPL045", "SPL046")]
        return codes, *done

    def references() -> int:
        models = checks.workspace.models
        assert models is not None
        system = models.built_template(models.systems[path][1]).system  # type: ignore[union-attr]
        return sum(len(e._inverse_rels) for e in system.eAllContents())

    assert check(original) == (["SPL045", "SPL046"], 1, 2)
    # a container every product drops, named with words the .rm does not use
    assert check(original + SPARE) == (["SPL045", "SPL046"], 0, 0)
    held = references()
    # its node now named as a node the .rm requires: the name is ambiguous there
    codes, built, _ = check(original + SPARE.replace("Watcher", "Lidar"))
    assert built and not codes
    # a value of a node both witnesses keep, which the .rm refers to
    value = original.replace("amcl/amcl", "amcl/amcl_fast")
    assert check(value) == (["SPL045", "SPL046"], 1, 2)
    # lines above every declaration: all of them, and the warnings, only move
    assert check("// moved\n//\n" + value) == (["SPL045", "SPL046"], 0, 0)
    # an optional node nothing keeps, inside a container both witnesses keep
    inside = value.replace("    optional node Lidar {", DROPPED + "    optional node Lidar {")
    assert check("// moved\n//\n" + inside) == (["SPL045", "SPL046"], 0, 0)
    for edit in range(3):  # new texts: an answer kept from before would build nothing
        check(original.replace("amcl/amcl", f"amcl/amcl_{edit}"))
        check(original + SPARE + f"// {edit}\n")
    assert references() == held


def test_the_rm_own_checks_run_again_only_on_another_rm_or_fm_model(tmp_path, monkeypatch) -> None:
    """The checks that read only the .rm, the .fm and the template elements the .rm
    names (SPL010, SPL012, SPL014, SPL016) run again only when the editor built another
    .rm or .fm model; every answer is a full check's."""
    from spl.resolver.line_checks import statements

    folder, inputs = copied(WAREHOUSE, tmp_path)
    tsm_path, rm = str(folder / "warehouse.tsm"), str(folder / "warehouse.rm")
    original = {p: Path(p).read_text(encoding="utf-8") for p in (tsm_path, rm)}
    checks, trees = checking.LineChecks(), Trees()
    runs: list[object] = []
    real = statements._checked
    monkeypatch.setattr(statements, "_checked", lambda line: runs.append(line) or real(line))

    def check(**edits: str) -> tuple[int, list[str]]:
        texts = {**original, **{tsm_path if k == "tsm" else rm: v for k, v in edits.items()}}
        runs.clear()
        found, _ = checks.check(str(folder), texts, trees, inputs)
        ran = len(runs)
        assert found == full_check(folder, texts)
        return ran, [d.code or "" for d in found if d.code == "SPL012"]

    assert check() == (1, [])
    assert check(tsm=original[tsm_path] + SPARE) == (0, [])  # the .rm means the same
    assert check(tsm="// moved\n" + original[tsm_path] + SPARE) == (0, [])
    # a value of a node the .rm refers to: the .rm is built again, and so checked
    assert check(tsm=original[tsm_path].replace("amcl/amcl", "amcl/amcl_fast")) == (1, [])
    conflict = (
        "\nwhen Sensing selected {\n    implementation Localizer = a/b\n}\n"
        "when CameraSensing selected {\n    implementation Localizer = c/d\n}\n"
    )
    assert check(rm=original[rm] + conflict) == (1, ["SPL012"])
    assert check(rm=original[rm] + conflict, tsm=original[tsm_path] + SPARE) == (0, ["SPL012"])


LINES = [*sorted((ROOT / "product_lines").iterdir()), ROOT / "tests/models/line_checks/warehouse"]


@pytest.mark.parametrize("folder", LINES, ids=lambda p: p.name)
def test_random_edits_of_a_line_are_answered_as_a_full_check_answers_them(
    folder: Path, tmp_path: Path
) -> None:
    """Edits a user makes, and worse, to a line's .tsm and .rm, one after the other (each
    from the models the last one left, as the editor keeps them): every answer is the
    one a full check of the same texts gives."""
    line, inputs = copied(folder, tmp_path)
    rm = str(next(line.glob("*.rm")))
    tsm_path = str(next(line.glob("*.tsm")))
    texts = {p: Path(p).read_text(encoding="utf-8") for p in (rm, tsm_path)}
    names = {
        "features": re.findall(r"when (\w+)", texts[rm]) or ["Missing"],
        "nodes": [*re.findall(r"node (\w+)", texts[tsm_path]), "Watcher"],  # SPARE's too
    }
    checks, trees = checking.LineChecks(), Trees()
    rng = random.Random(folder.name)
    for _ in range(EDITS):
        path = rng.choice((rm, tsm_path))
        text = texts[path]
        if path == tsm_path and rng.random() < 0.15:  # a container, maybe with a used name
            name = rng.choice(names["nodes"])
            edited = text + SPARE.replace("Watcher", name).replace("Spare", f"Spare{name}")
        else:
            edited = model_edit(path, text, names, rng)
        current = {**texts, path: edited}
        found, _ = checks.check(str(line), current, trees, inputs)
        assert found == full_check(line, current), (path, edited)
        # a valid edit often stays (the next builds on it), one that breaks a model not
        if rng.random() < 0.6 and not any(d.severity == "error" and not d.code for d in found):
            texts = current


def test_the_editor_lets_go_of_a_template_it_will_not_build_on_again(tmp_path) -> None:
    """After an edit that moves every declaration (each is built afresh), nothing the
    editor keeps (the last models, the .rm model, the witness resolutions, also those of
    witnesses no longer asked about) holds the template before: a long session does not
    pile up templates."""
    folder, inputs = copied(WAREHOUSE, tmp_path)
    path = str(folder / "warehouse.tsm")
    original = Path(path).read_text(encoding="utf-8")
    checks, trees = checking.LineChecks(), Trees()
    found, _ = checks.check(str(folder), {path: original + SPARE}, trees, inputs)
    assert any(d.code == "SPL045" for d in found)  # witness products were resolved
    models = checks.workspace.models
    assert models is not None
    before = weakref.ref(models.systems[path][1])
    # every declaration moved, and no input left unfed: no witness is asked again
    fed = re.sub(r"\n.*(subscribes scan|calls classify).*", "", original)
    found, _ = checks.check(str(folder), {path: "// moved\n" + fed + SPARE}, trees, inputs)
    assert not any(d.code in ("SPL045", "SPL046") for d in found)
    gc.collect()
    assert before() is None
