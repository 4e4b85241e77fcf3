"""SPL016 against the Resolution Engine, on random resolution models of the farm line
(tests/models/semantics): the witness product of every SPL016 finding fails to resolve,
at that statement or at one before it (SPL016 asks about each statement as if the ones
before it succeeded); and where a product first fails, for a reason SPL016 covers (a
topic missing where it is looked up, a client and server apart, a service bridge inside
one container, a migration onto a node name), SPL016 reported that statement. Seeds are
fixed and the number of lines bounded, so the test is deterministic and takes seconds."""

from __future__ import annotations

import itertools
import random
import shutil
from functools import cache
from pathlib import Path

from spl.diagnostics import ModelError
from spl.dsl import fm_formats, tsm
from spl.resolver.engine import resolve
from spl.resolver.line_checks import check_product_line
from spl.resolver.product_line import load_product_line
from spl.resolver.product_selection import selection_from_list

MODELS = Path(__file__).parents[1] / "models" / "semantics"
LINES = 25  # random lines that parse, each checked and resolved in all 12 products
FEATURES = ["Farm", "OnBoard", "Thumbs", "Planning", "LocalPlanning"]
COVERED = ("unknown topic", "cannot migrate", "is served in container", "a bridge connects")

IMAGE_INTERFACES = ["Tractor.Camera.thumbs", "Detector.thumbs", "Detector.image"]
PATH_INTERFACES = ["Planner.route", "Navigator.route"]
MIGRATIONS = [  # never to the declaring container, so never refused for that
    ("Planner", "Tractor"),
    ("Detector", "Tractor"),
    ("Tractor.Camera", "Cloud"),
    ("Drone.Camera", "Cloud"),
    ("Navigator", "Cloud"),
]
IMAGE_TOPICS = ["Images", "Thumbs", "Small", "Tractor.Thumbs", "Cloud.Thumbs", "Cloud.Images"]


def statement(r: random.Random) -> str:
    """A statement whose names and types are right; whether it resolves depends on the
    statements before it and on the product."""
    kind = r.choice([0, 0, 1, 2, 3, 4, 5, 6])
    if kind == 0:
        node, target = r.choice(MIGRATIONS)
        return f"migrate {node} to {target}"
    if kind == 1:
        return f"connect {r.choice(IMAGE_INTERFACES)} to topic {r.choice(IMAGE_TOPICS)}"
    if kind == 2:
        name = r.choice(["Thumbs", "Small"])
        return f"connect {r.choice(IMAGE_INTERFACES)} to new topic {name} : sensor_msgs/Image"
    if kind == 3:
        name = r.choice(["Route", "Path2"])
        return f"connect {r.choice(PATH_INTERFACES)} to new topic {name} : nav_msgs/Path"
    if kind == 4:
        topic = r.choice(["Route", "Path2", "Tractor.Route", "Cloud.Path2"])
        return f"connect {r.choice(PATH_INTERFACES)} to topic {topic}"
    if kind == 5:
        return r.choice(
            [
                "connect Navigator.plan to server Planner.plan",
                "connect bridge Navigator.plan -> Planner.plan",
            ]
        )
    ends = [
        f"{r.choice(['Tractor', 'Cloud', 'Drone'])}.{r.choice(['Thumbs', 'Images', 'Small'])}"
        for _ in range(2)
    ]
    return f"connect bridge {ends[0]} -> {ends[1]}"


def resolution_model(r: random.Random) -> str:
    text = 'resolution model Farm\ntsm "farm.tsm"\nfm "farm.fm"\n'
    for _ in range(r.randrange(2, 5)):
        negated = " not" if r.random() < 0.2 else ""
        feature = r.choice(FEATURES[1:] * 4 + FEATURES[:1])  # the root seldom
        text += f"when {feature}{negated} selected {{\n"
        text += "".join(f"    {statement(r)}\n" for _ in range(r.randrange(1, 5)))
        text += "}\n"
    return text


def products() -> list[list[str]]:
    """The farm line's 12 products (LocalPlanning requires Planning)."""
    found = []
    for choice in itertools.product([False, True], repeat=4):
        features = [f for f, on in zip(FEATURES[1:], choice, strict=True) if on]
        if "LocalPlanning" not in features or "Planning" in features:
            found.append(["Farm", *features])
    return found


def located(diagnostic) -> tuple[int, int]:
    return diagnostic.location.line, diagnostic.location.col


def in_rm(error: ModelError) -> list:
    """The errors of a resolution located in the .rm (statements, conflicts)."""
    found = [d for d in error.diagnostics if d.location and d.location.file.endswith(".rm")]
    assert found, [str(d) for d in error.diagnostics]
    return found


def test_spl016_agrees_with_resolving_every_product(tmp_path, monkeypatch):
    for name in ("farm.tsm", "farm.fm"):
        shutil.copy(MODELS / name, tmp_path / name)
    # the .tsm and .fm are the same for every line: parsed once (resolving copies them)
    monkeypatch.setattr(tsm, "parse_file", cache(tsm.parse_file))
    monkeypatch.setattr(fm_formats, "load_feature_model", cache(fm_formats.load_feature_model))
    checked = reported = failures = 0
    for seed in itertools.count():
        assert seed < 2000, "too few random lines parse"
        (tmp_path / "farm.rm").write_text(resolution_model(random.Random(seed)))
        try:
            line = load_product_line(tmp_path)
        except ModelError:
            continue  # refused statically: C1, tested elsewhere
        findings = [d for d in check_product_line(line, products=False) if d.code == "SPL016"]
        for finding in findings:  # the witness fails there, or at a statement before
            witness = finding.message.rsplit(", in the product ", 1)[1].replace(" ", "")
            try:
                resolve(line, selection_from_list(witness))
                raise AssertionError(f"seed {seed}: {finding} but {witness} resolves")
            except ModelError as error:
                assert min(located(d) for d in in_rm(error)) <= located(finding), seed
        flagged = {located(d) for d in findings}
        for features in products():  # where a product first fails, SPL016 said so
            try:
                resolve(line, selection_from_list(",".join(features)))
            except ModelError as error:
                first = min(in_rm(error), key=located)
                if any(kind in first.message for kind in COVERED):
                    failures += 1
                    assert located(first) in flagged, f"seed {seed}, {features}: {first}"
        reported += len(findings)
        checked += 1
        if checked == LINES:
            break
    assert reported >= 5 and failures >= 5, (reported, failures)  # SPL016 was exercised
