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
from collections import OrderedDict
from collections.abc import Callable

import yaml
from lxml import etree

from spl.generators.kubernetes.objects import with_known_tags
from spl.generators.launch.launch_schema import validate_ros1_launch, validate_ros2_launch
from spl.generators.rapyuta.rules import CleanSets, check_all

# libyaml's parser when PyYAML has it (Debian's and PyPI's wheels do): the same documents,
# ten times faster than the pure-Python one on the Kubernetes manifests of every product;
# each scalar's implicit tag looked up once per process
YAML_LOADER = with_known_tags(getattr(yaml, "CSafeLoader", yaml.SafeLoader))
_YAML_PARSER = getattr(getattr(yaml, "_yaml", None), "CParser", None)


def validate_bundle(files: dict[str, bytes], clean: CleanSets | None = None) -> list[str]:
    """Problems found in the bundle ``files`` (bundle path -> bytes); empty when valid.
    ``clean``: the Rapyuta file sets found clean so far (the bundle's memo), not checked
    again."""
    problems: list[str] = []
    configs, config_names = [], []
    digests = {path: hashlib.sha256(data).hexdigest() for path, data in files.items()}
    for path, data in sorted(files.items()):
        if path.startswith("rapyuta/") and path.endswith(".json"):
            try:
                configs.append(json.loads(data))
                config_names.append(path.removeprefix("rapyuta/"))
            except ValueError as exc:
                problems.append(f"{path}: not JSON: {exc}")
            continue
        check = _file_check(path)
        if check is None:
            continue
        key = (check, digests[path])
        if key in _CLEAN_FILES:
            _CLEAN_FILES.move_to_end(key)
            continue
        found = check(path, data)
        if found:
            problems += found
        else:
            _CLEAN_FILES[key] = None
            if len(_CLEAN_FILES) > CLEAN_FILES:
                _CLEAN_FILES.popitem(last=False)
    problems += [str(p) for p in check_all(configs, config_names, clean)] if configs else []
    problems += _manifest_problems(files, digests)
    return problems


def _ros1_launch(path: str, data: bytes) -> list[str]:
    return [f"{path}:{m}" for m in validate_ros1_launch(data)]


def _ros2_launch(path: str, data: bytes) -> list[str]:
    return [f"{path}:{m}" for m in validate_ros2_launch(data)]


def _python(path: str, data: bytes) -> list[str]:
    try:
        compile(data, path, "exec")
    except SyntaxError as exc:
        return [f"{path}:{exc.lineno}:{exc.offset}: {exc.msg}"]
    return []


def _yaml(path: str, data: bytes) -> list[str]:
    try:
        if not _loads_plainly(data):
            list(yaml.load_all(data, Loader=YAML_LOADER))
    except (yaml.YAMLError, ValueError) as exc:  # ValueError: a scalar that does not construct
        return [f"{path}: not YAML: {exc}"]
    return []


def _loads_plainly(data: bytes) -> bool:
    """True when PyYAML's safe loader reads the stream ``data`` without error, decided
    from libyaml's events without building the documents (a third of the load's cost on
    a product's manifests); False when that is not decided here, and the stream is
    loaded. Decided here: streams of mappings with scalar keys, sequences and scalars,
    without tags, anchors or aliases, whose plain scalars construct (each implicit tag's
    constructor is run on it: ``0b_`` is an int that does not), which is all a generator
    writes. Mapping keys that are collections (unhashable), tags, aliases (perhaps
    undefined) and syntax errors are left to the loader, so the verdict and its message
    are the loader's own (tests/test_yaml_check.py compares them)."""
    if _YAML_PARSER is None:
        return False
    loader = YAML_LOADER(b"")  # its resolver and constructor, on no stream
    text_tag = loader.DEFAULT_SCALAR_TAG
    resolve, constructors = loader.resolve, loader.yaml_constructors
    scalar, alias = yaml.ScalarEvent, yaml.AliasEvent
    mapping, sequence = yaml.MappingStartEvent, yaml.SequenceStartEvent
    ends = (yaml.MappingEndEvent, yaml.SequenceEndEvent)
    # the open collection's state: True a mapping expecting a key, False a mapping
    # expecting a value, None a sequence (or none open); the enclosing ones' on a stack
    state: bool | None = None
    enclosing: list[bool | None] = []
    get_event = _YAML_PARSER(data).get_event
    try:
        while (event := get_event()) is not None:
            kind = type(event)
            if kind is scalar:
                if event.anchor is not None or event.tag is not None:
                    return False
                if event.implicit[0]:  # plain: its tag is resolved from its text
                    tag = resolve(yaml.ScalarNode, event.value, (True, False))
                    if tag != text_tag:
                        constructors[tag](loader, yaml.ScalarNode(tag, event.value))
                if state is not None:
                    state = not state
            elif kind is mapping or kind is sequence:
                if event.anchor is not None or event.tag is not None or state:
                    return False  # state: a collection as a key
                enclosing.append(state if state is None else True)
                state = True if kind is mapping else None
            elif kind in ends:
                state = enclosing.pop()
            elif kind is alias:
                return False
    except Exception:  # a syntax error, a scalar that does not construct: the loader's say
        return False
    finally:
        loader.dispose()
    return True


def _xml(path: str, data: bytes) -> list[str]:
    try:
        etree.fromstring(data)
    except etree.XMLSyntaxError as exc:
        return [f"{path}: not XML: {exc}"]
    return []


def _file_check(path: str) -> Callable[[str, bytes], list[str]] | None:
    """The check of one file by its path, or None (a file only the manifest covers)."""
    if path.startswith("ros1/") and path.endswith(".launch"):
        return _ros1_launch
    if path.startswith("ros2/") and path.endswith(".launch.xml"):
        return _ros2_launch
    if path.endswith(".py"):
        return _python
    if path.endswith((".yml", ".yaml")):
        return _yaml
    if path.endswith((".svg", ".xmi", ".xml")):
        return _xml
    return None


# Files found clean in this process, by check and content. Products of a line share
# files (the same Kubernetes manifest, kustomization or service code in many bundles),
# and whether a file passes its check depends on its bytes alone (a path only names it
# in a message), so a file whose bytes already passed the same check passes; only clean
# results are kept, problems are always found anew. The oldest go first.
CLEAN_FILES = 4096
_CLEAN_FILES: OrderedDict[tuple[Callable[[str, bytes], list[str]], str], None] = OrderedDict()


def _manifest_problems(files: dict[str, bytes], digests: dict[str, str]) -> list[str]:
    if "manifest.json" not in files:
        return ["manifest.json: missing"]
    listed = json.loads(files["manifest.json"])["files"]
    present = {p for p in files if p != "manifest.json"}
    problems = [
        f"manifest.json: lists {p}, which is not in the bundle" for p in listed.keys() - present
    ]
    problems += [f"manifest.json: does not list {p}" for p in present - listed.keys()]
    for path in sorted(present & listed.keys()):
        if digests[path] != listed[path]:
            problems.append(f"manifest.json: sha256 of {path} does not match")
    return problems
