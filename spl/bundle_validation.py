"""Validation of a whole deployment bundle: every artifact against its own rules.

Launch files against the shipped XSDs, Rapyuta configurations against the JSON Schema
and the engine's rules (all robots' files of the bundle together), generated Python
compiled, deployment YAML parsed, the resolved model re-parsed, the diagram parsed as
XML and the manifest's hashes recomputed. Used by the tests and by ``spl validate``.

It judges the generators' output by its consumers, spl's own .tsm parser among them,
so it sits above both the languages (dsl/) and the generators.
"""

from __future__ import annotations

import hashlib
import json

import yaml
from lxml import etree

from spl.diagnostics import ModelError
from spl.dsl.tsm import parse_text
from spl.generators.launch_schema import validate_ros1_launch, validate_ros2_launch
from spl.generators.rapyuta_rules import check_all


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
                list(yaml.safe_load_all(data))
            except yaml.YAMLError as exc:
                problems.append(f"{path}: not YAML: {exc}")
        elif path.endswith((".svg", ".xmi", ".xml")):
            try:
                etree.fromstring(data)
            except etree.XMLSyntaxError as exc:
                problems.append(f"{path}: not XML: {exc}")
        elif path == "resolved.tsm":
            try:
                parse_text(data.decode("utf-8"), path)
            except ModelError as exc:
                problems += [str(d) for d in exc.diagnostics]
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
