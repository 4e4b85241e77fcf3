"""Random resolution models of the farm line (tests/models/semantics): statements whose
names and types are right, so whether they resolve depends on the statements before
them and on the product. Used by the SPL016 and dataflow agreement tests."""

from __future__ import annotations

import random
from pathlib import Path

MODELS = Path(__file__).parents[1] / "models" / "semantics"
FEATURES = ["Farm", "OnBoard", "Thumbs", "Planning", "LocalPlanning"]

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
