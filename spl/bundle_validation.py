"""Validation of a whole deployment bundle: every artifact against its own rules.

Launch files against the shipped XSDs, Rapyuta configurations against the JSON Schema
and the engine's rules (all robots' files of the bundle together), generated Python
compiled, deployment YAML parsed, the diagram parsed as XML and the manifest's hashes
recomputed. Used by the tests and by ``spl validate``.

``resolved.tsm`` is not parsed again here: it was printed from the model just resolved,
and that the printer's text parses back to the same model is a property the test suite
checks on generated product lines (tests/test_migration_properties.py); `spl smoke` reads
it as a user would.
"""

from __future__ import annotations

import hashlib
import json

import yaml
from lxml import etree

from spl.generators.launch_schema import validate_ros1_launch, validate_ros2_launch
from spl.generators.rapyuta_rules import check_all

# libyaml's parser when PyYAML has it (Debian's and PyPI's wheels do): the same documents,
# ten times faster than the pure-Python one on the Kubernetes manifests of every product
YAML_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def validate_bundle(files: dict[str, bytes]) -> list[str]:
    """Problems found in the bundle ``files`` (bundle path -> bytes); empty when valid."""
    problems: list[str] = []
    configs, config_names = [], []
    for path, data in sorted(files.items()):
        if path.startswith("ros1/") and path.endswith(".launch"):
            problems += [f"{path}:{m}" for m in validate_ros1_launch(data)]
        elif path.startswith("ros2/") and path.endswith(".launch.xml"):
            problems += [f"{path}:{m}" for m in validate_ros2_launch(data)]
        elif path.startswith("rapyuta/") and path.endswith(".json"):
            try:
                configs.append(json.loads(data))
                config_names.append(path.removeprefix("rapyuta/"))
            except ValueError as exc:
                problems.append(f"{path}: not JSON: {exc}")
        elif path.endswith(".py"):
            try:
                compile(data, path, "exec")
            except SyntaxError as exc:
                problems.append(f"{path}:{exc.lineno}:{exc.offset}: {exc.msg}")
        elif path.endswith((".yml", ".yaml")):
            try:
                list(yaml.load_all(data, Loader=YAML_LOADER))
            except yaml.YAMLError as exc:
                problems.append(f"{path}: not YAML: {exc}")
        elif path.endswith((".svg", ".xmi", ".xml")):
            try:
                etree.fromstring(data)
            except etree.XMLSyntaxError as exc:
                problems.append(f"{path}: not XML: {exc}")
    problems += [str(p) for p in check_all(configs, config_names)] if configs else []
    problems += _manifest_problems(files)
    return problems


def _manifest_problems(files: dict[str, bytes]) -> list[str]:
    if "manifest.json" not in files:
        return ["manifest.json: missing"]
    listed = json.loads(files["manifest.json"])["files"]
    present = {p for p in files if p != "manifest.json"}
    problems = [
        f"manifest.json: lists {p}, which is not in the bundle" for p in listed.keys() - present
    ]
    problems += [f"manifest.json: does not list {p}" for p in present - listed.keys()]
    for path in sorted(present & listed.keys()):
        if hashlib.sha256(files[path]).hexdigest() != listed[path]:
            problems.append(f"manifest.json: sha256 of {path} does not match")
    return problems
