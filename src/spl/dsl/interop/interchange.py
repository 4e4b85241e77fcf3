"""What the feature-model formats share when they import and export one another's models.

UVL and FeatureIDE allow feature names our tools cannot carry (spaces, dots,
non-ASCII letters, words of the .fm language): those names end up in generated XML,
JSON and shell files, so importers give such a feature a valid identifier and keep its
original name in a string attribute ``original_name``. Exporters write the original
name back, so a community model survives import and export unchanged. A feature's
capability conditions travel in one string attribute, ``capability``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Any

from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.dsl.fm.vocabulary import RESERVED_WORDS, is_feature_name

ORIGINAL_NAME = "original_name"
# UVL attributes no typed attribute can hold (nested ``{...}`` and vector ``[...]``
# values, names that are not identifiers) travel as written, joined by ", ", in one
# string attribute of this name; the UVL writer writes them back verbatim.
UVL_ATTRIBUTES = "uvl_attributes"
# UVL and FeatureIDE carry a feature's capability conditions in one string attribute of
# this name, written as the .fm language writes them after `capability`.
CAPABILITY = "capability"


def sanitise(name: str) -> str:
    """A valid .fm identifier close to ``name``: invalid characters become ``_``."""
    text = re.sub(r"[^A-Za-z0-9_]", "_", name)
    if not text or text[0].isdigit():
        text = "_" + text
    if text in RESERVED_WORDS:
        text += "_"
    return text


class FeatureNames:
    """The injective renaming of an imported model's feature names.

    Names that are already valid identifiers keep themselves; every other name gets
    :func:`sanitise` of itself, suffixed ``_2``, ``_3``... on a collision with any name
    of the model, in the order the names are given, so the result depends only on the
    input file.
    """

    def __init__(self, originals: Iterable[str]) -> None:
        ordered = list(dict.fromkeys(originals))
        self.identifiers: dict[str, str] = {}
        used = {name for name in ordered if is_feature_name(name)}
        for name in ordered:
            if is_feature_name(name):
                self.identifiers[name] = name
                continue
            base = sanitise(name)
            candidate, counter = base, 2
            while candidate in used:
                candidate, counter = f"{base}_{counter}", counter + 1
            used.add(candidate)
            self.identifiers[name] = candidate

    def __getitem__(self, original: str) -> str:
        return self.identifiers[original]


def model_name(name: str) -> str:
    """A model name (namespace, file stem) as a valid identifier."""
    text = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return text if text and not text[0].isdigit() else "_" + text


def original_name(feature: Any) -> str:
    """The name a feature had in the format it was imported from (its name otherwise)."""
    for attribute in feature.attributes:
        if attribute.name == ORIGINAL_NAME and attribute.type.name == "string":
            return attribute.value or feature.name
    return feature.name


def written_names(model: Any) -> dict[str, str]:
    """Each feature's identifier -> its name as its file writes it (the kept original
    name, else the identifier), for a pyecore or a plain (:mod:`spl.dsl.fm.plain`) model.

    What a user reads (analysis reports, their JSON) names features so: an identifier
    made up on import never leaves the toolchain (docs/fm.md, "Interchange").
    """
    written: dict[str, str] = {}
    stack = [model.root] if model.root is not None else []
    while stack:
        feature = stack.pop()
        written[feature.name] = written_name(feature)
        stack.extend(child for group in feature.groups for child in group.features)
    return written


def written_name(feature: Any) -> str:
    """A feature's name as its file writes it: the kept original name, else its own."""
    for attribute in feature.attributes:
        kind = attribute.type if isinstance(attribute.type, str) else attribute.type.name
        if attribute.name == ORIGINAL_NAME and kind == "string" and attribute.value:
            return str(attribute.value)
    return str(feature.name)


def exported_attributes(feature: Any) -> list[Any]:
    """The attributes an exporter writes as attributes (not the kept original name)."""
    return [a for a in feature.attributes if a.name != ORIGINAL_NAME]


def add_capabilities(feature: Any, type_name: str, text: str, where: Location | None) -> None:
    """Read the ``capability`` attribute of an imported feature into its conditions;
    raise ModelError (located at the attribute) when it is not a condition string."""
    from spl.dsl.fm.capability import parse_capability_conditions

    if type_name != "string":
        message = f"{CAPABILITY} takes a condition string, like 'base = \"youbot\" and onboard_pc'"
        raise ModelError([Diagnostic(where, message)])
    if feature.capabilities:
        raise ModelError(
            [Diagnostic(where, f"feature {feature.name} has two {CAPABILITY} attributes")]
        )
    feature.capabilities.extend(parse_capability_conditions(text, where))
