"""The editor's .rm model built from the one before it (``spl.dsl.rm.reuse.taken_over``)
is the model a full build of the text gives against the same .tsm and .fm models: the
same elements, values, places and references, through chains of edits of every
shipped line's .rm (elements added, removed, moved, copied, migrations and topics
created among them, lines moved). It takes over only elements of the model before,
and nothing of that model stays recorded on the template."""

from __future__ import annotations

import random
import re
from pathlib import Path

import pytest

from spl.core.diagnostics import DiagnosticSink, ModelError
from spl.core.emf import fingerprint, forget_references, references
from spl.dsl.parse_tree import Positions
from spl.dsl.rm import language as rm, reader as rm_reader
from spl.dsl.tsm.declaration_paths import declaration_of
from spl.dsl.tsm.declarations import BuiltTemplate
from spl.dsl.workspace import LastModels, Workspace
from spl.metamodels import tsm as tsm_metamodel

from support.typing_edits import model_edit

ROOT = Path(__file__).resolve().parents[2]
LINES = [
    *sorted((ROOT / "product_lines").iterdir()),
    ROOT / "tests/models/line_checks/warehouse",
]
EDITS = 60  # edits per line
ELEMENT = re.compile(r"when [^{]*\{[^}]*\}\n?")


def full_build(text: str, filename: str, system: object, feature_model: object) -> tuple:
    """The content of the model a build of ``text`` from nothing gives against these
    .tsm and .fm models (:func:`content`); its references then forgotten, as the editor
    forgets those of a model it drops."""
    tree = rm_reader.read(text) or rm._textx_tree(text, filename)
    sink = DiagnosticSink()
    model = rm._Builder(Positions(text, filename), system, feature_model, sink).build(tree)
    model.tsmPath, model.fmPath = tree.tsm, tree.fm  # as parse_text names them
    assert not sink.errors
    found = content(model)
    forget_references(model)
    return found


def content(model: object) -> tuple:
    """Everything of the model, places included, and the very .tsm and .fm elements it
    refers to."""
    return fingerprint(model, id)  # type: ignore[arg-type]


def refers_to(model: object, template: BuiltTemplate) -> dict:
    """The template's declarations ``model`` refers into, by their keys, found afresh."""
    keys = {id(element): key for key, element in template.elements.items()}
    found = {}
    for _, _, target in references(model):  # type: ignore[arg-type]
        if target.eClass.ePackage is tsm_metamodel().package:
            declaration = declaration_of(target)
            found[keys[id(declaration)]] = declaration
    return found


def element_edit(text: str, names: dict[str, list[str]], rng: random.Random) -> str:
    """An edit among the elements: one moved or copied elsewhere, or a new one (a
    migration, a topic created, an implementation) put between two, or one indented."""
    elements = list(ELEMENT.finditer(text))
    if not elements:
        return text
    at = rng.choice(elements).start()  # where an element starts
    choice = rng.random()
    if choice < 0.3:
        moved = rng.choice(elements)
        rest = text[: moved.start()] + text[moved.end() :]
        at = rng.choice([m.start() for m in ELEMENT.finditer(rest)] or [len(rest)])
        return rest[:at] + moved.group() + rest[at:]
    if choice < 0.45:
        return text[:at] + rng.choice(elements).group() + text[at:]
    if choice < 0.55:
        return text[:at] + "  " + text[at:]  # the element's column moves
    feature, node = rng.choice(names["features"]), rng.choice(names["nodes"])
    statement = rng.choice(
        (
            f"migrate {node} to {rng.choice(names['containers'])}",
            f"connect {node}.{rng.choice(names['interfaces'])} to new topic Made : std_msgs/String",
            f"implementation {node} = x/y",
        )
    )
    return text[:at] + f"when {feature} selected {{\n    {statement}\n}}\n" + text[at:]


@pytest.mark.parametrize("folder", LINES, ids=lambda p: p.name)
def test_edits_of_a_line_rm_build_what_a_full_build_builds(folder: Path) -> None:
    path = str(next(folder.glob("*.rm")))
    tsm_text = next(folder.glob("*.tsm")).read_text(encoding="utf-8")
    text = Path(path).read_text(encoding="utf-8")
    names = {
        "features": re.findall(r"when (\w+)", text) or ["Missing"],
        "nodes": re.findall(r"node (\w+)", tsm_text),
        "containers": re.findall(r"container (\w+)", tsm_text),
        "interfaces": re.findall(r"(?:publishes|subscribes) (\w+)", tsm_text) or ["x"],
    }
    workspace = Workspace(models=LastModels(), lines={})
    rng = random.Random(folder.name)
    taken = moved = built = 0
    last: list = []  # the elements of the last model built
    for _ in range(EDITS):
        if rng.random() < 0.5:
            edited = element_edit(text, names, rng)
        else:
            edited = model_edit(path, text, names, rng)
        lines = {id(e): e.srcLine for e in last}
        try:
            files = rm.load(path, workspace.reading({path: edited}))
        except ModelError as exc:
            with pytest.raises(ModelError) as full:  # what a build from nothing says
                rm.load(path, Workspace().reading({path: edited}))
            assert exc.diagnostics == full.value.diagnostics
            last = []  # nothing is kept of a model with errors
            continue
        assert content(files.rm) == full_build(edited, path, files.tsm, files.fm)
        for element in files.rm.elements:
            assert element.eContainer() is files.rm
            if id(element) in lines:
                taken += 1
                moved += element.srcLine != lines[id(element)]
            else:
                built += 1
        # what the kept model refers into, kept element by element, is what it refers to
        assert workspace.models is not None
        kept = workspace.models.resolution_models[path]
        assert kept.model is files.rm and kept.refers_to == refers_to(files.rm, kept.template)
        # nothing but the model now kept refers into the template
        inside = {id(files.rm), *(id(e) for e in files.rm.eAllContents())}
        inside |= {id(files.tsm), *(id(e) for e in files.tsm.eAllContents())}
        for element in files.tsm.eAllContents():
            outside = [(o, f.name) for o, f in element._inverse_rels if id(o) not in inside]
            assert not outside, (element, outside, edited)
        last = list(files.rm.elements)
        if rng.random() < 0.7:
            text = edited
    assert taken and moved and built  # every case met


MADE = "\nwhen Offload selected {\n    connect Localizer.pose to new topic Made : %s\n}\n"
READS = "\nwhen Detection selected {\n    connect Navigator.goal to topic Made\n}\n"
BETWEEN = "\nwhen Classification selected {\n    require Detector\n}\n"


def test_elements_after_an_edit_that_changes_no_names_are_taken_over() -> None:
    """An element put between others builds itself alone when it changes no names; one
    that changes what a name after it means (a topic created no longer, of another
    type) has the elements after it built again, refused as a full build refuses them."""
    folder = ROOT / "tests/models/line_checks/warehouse"
    path = str(folder / "warehouse.rm")
    text = Path(path).read_text(encoding="utf-8")
    workspace = Workspace(models=LastModels(), lines={})
    valid = text + MADE % "geometry_msgs/PoseStamped" + READS
    before = list(rm.load(path, workspace.reading({path: valid})).rm.elements)
    last_line = before[-1].srcLine
    between = text + MADE % "geometry_msgs/PoseStamped" + BETWEEN + READS
    files = rm.load(path, workspace.reading({path: between}))
    now = list(files.rm.elements)
    assert now[:-2] == before[:-1] and now[-1] is before[-1] and now[-2] not in before
    assert now[-1].srcLine == last_line + BETWEEN.count("\n")  # moved, in place
    assert content(files.rm) == full_build(between, path, files.tsm, files.fm)
    for changed in (text + MADE % "std_msgs/String" + BETWEEN + READS, text + BETWEEN + READS):
        with pytest.raises(ModelError) as kept:
            rm.load(path, workspace.reading({path: changed}))
        with pytest.raises(ModelError) as full:
            rm.load(path, Workspace().reading({path: changed}))
        assert kept.value.diagnostics == full.value.diagnostics
        assert any("Made" in d.message for d in kept.value.diagnostics)
        rm.load(path, workspace.reading({path: between}))  # built again, in full
