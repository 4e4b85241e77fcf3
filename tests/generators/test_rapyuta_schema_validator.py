"""The Rapyuta schema's validator is built once, from a copy of the schema with its
``$ref``s inlined (for speed): it must find exactly what the schema as written finds,
same messages at the same JSON paths, on valid and on damaged configurations. A file set
found clean is not checked again, and only a set with the same content is taken for it."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import jsonschema
from hypothesis import given, strategies as st

from spl.generators.rapyuta import rules
from spl.generators.rapyuta.schema import inline_references, schema, validator

EXAMPLES = Path(__file__).parents[1] / "models" / "rapyuta" / "rce-examples"
NAMES = ["debug.cfg", "lo_client.cfg", "lo_server.cfg"]
CONFIGS = [json.loads((EXAMPLES / name).read_text()) for name in NAMES]


PLAIN = jsonschema.Draft202012Validator(
    schema(), format_checker=jsonschema.Draft202012Validator.FORMAT_CHECKER
)


def as_written(config: object) -> list[tuple[str, str]]:
    """(JSON path, message) of every error of the schema as shipped, references and all."""
    return sorted(
        ("/".join(map(str, e.absolute_path)), e.message) for e in PLAIN.iter_errors(config)
    )


def inlined(config: object) -> list[tuple[str, str]]:
    return sorted(
        ("/".join(map(str, e.absolute_path)), e.message) for e in validator().iter_errors(config)
    )


def test_the_validator_is_built_once_and_has_no_reference_left():
    assert validator() is validator()
    text = json.dumps({k: v for k, v in validator().schema.items() if k != "$defs"})
    assert '"$ref"' not in text
    assert '"$ref"' in json.dumps(schema())  # the shipped file still uses them


def test_a_recursive_definition_stays_a_reference():
    either = {"anyOf": [{"$ref": "#/$defs/leaf"}, {"$ref": "#/$defs/tree"}]}
    defs = {"tree": {"type": "array", "items": either}, "leaf": {"type": "string"}}
    document = {"properties": {"t": {"$ref": "#/$defs/tree"}}, "$defs": defs}
    result = inline_references(document, defs)
    assert result["properties"]["t"] == {
        "type": "array",
        "items": {"anyOf": [{"type": "string"}, {"$ref": "#/$defs/tree"}]},
    }
    check = jsonschema.Draft202012Validator(result)
    assert check.is_valid({"t": ["a", ["b", []]]})
    assert not check.is_valid({"t": ["a", [1]]})


def test_data_that_looks_like_a_reference_is_left_alone():
    defs = {"x": {"type": "string"}}
    document = {"enum": [{"$ref": "#/$defs/x"}], "properties": {"$ref": {"$ref": "#/$defs/x"}}}
    assert inline_references(document, defs) == {
        "enum": [{"$ref": "#/$defs/x"}],
        "properties": {"$ref": {"type": "string"}},
    }


def test_the_engines_own_files_are_valid_both_ways():
    for config in CONFIGS:
        assert as_written(config) == inlined(config) == []


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-3, 3) | st.floats(-2, 2) | st.text(max_size=6),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner),
    max_leaves=6,
)
# Strings that sit at the edges of the schema's patterns and lengths.
EDGY_TEXT = st.sampled_from(
    [
        "",
        "a",
        "a/b",
        "/a",
        "~a",
        "a\n",
        "a b",
        "\x1c",
        "9a",
        "A_b-1",
        "http://x",
        "wss://a b",
        "std_msgs/String",
        "1.2.3.4",
        "256.1.1.1",
        "PublisherInterface",
        "Publisher",
    ]
)


# One damage at a time at every place of the engine's files: a value of each JSON type,
# strings at the edges of the patterns, the key dropped.
SWEEP_VALUES = [None, True, 1, -1, 2.5, "", "a b", "a/b", "a\n", "9a", [], {}, ["x"], {"k": 1}]


def test_every_single_damage_gets_the_same_errors_as_from_the_schema_as_written():
    compared = 0
    for full in CONFIGS:  # two entries of each list are enough (and keep the test short)
        base = {k: v[:2] if isinstance(v, list) else v for k, v in full.items()}
        for path in _paths(base)[1:]:
            for value in [*SWEEP_VALUES, DROP]:
                config = copy.deepcopy(base)
                parent = config
                for part in path[:-1]:
                    parent = parent[part]
                if value is DROP:
                    del parent[path[-1]]
                else:
                    parent[path[-1]] = value
                assert inlined(config) == as_written(config), (path, value)
                compared += 1
    assert compared > 1000


DROP = object()


def _paths(node: object, prefix: tuple = ()) -> list[tuple]:
    found = [prefix]
    if isinstance(node, dict):
        for key, value in node.items():
            found += _paths(value, (*prefix, key))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            found += _paths(value, (*prefix, index))
    return found


@given(
    base=st.sampled_from(CONFIGS),
    edits=st.lists(
        st.tuples(
            st.integers(0, 10_000),
            st.sampled_from(["set", "drop", "add"]),
            JSON_VALUES | EDGY_TEXT,
            st.text(max_size=4),
        ),
        min_size=1,
        max_size=4,
    ),
)
def test_damaged_configurations_get_the_same_errors_as_from_the_schema_as_written(base, edits):
    config = copy.deepcopy(base)
    for pick, action, value, key in edits:
        paths = _paths(config)
        path = paths[pick % len(paths)]
        if not path:
            parent, last = None, None
        else:
            parent = config
            for part in path[:-1]:
                parent = parent[part]
            last = path[-1]
        if action == "set" and parent is not None:
            parent[last] = value
        elif action == "drop" and parent is not None:
            del parent[last]
        elif action == "add":
            target = config if parent is None else parent[last]
            if isinstance(target, dict):
                target[key] = value
            elif isinstance(target, list):
                target.append(value)
    assert inlined(config) == as_written(config)


# --- file sets found clean are not checked again, by whoever keeps them -------------


def test_a_clean_set_is_checked_once_whatever_the_order_of_its_keys(monkeypatch):
    configs = copy.deepcopy(CONFIGS)
    clean = rules.CleanSets()
    assert rules.check_all(configs, NAMES, clean) == []
    checked = []
    monkeypatch.setattr(rules, "schema_problems", lambda c, n: checked.append(n) or [])
    reordered = [dict(reversed(list(c.items()))) for c in json.loads(json.dumps(configs))]
    assert rules.check_all(reordered, NAMES, clean) == []
    assert checked == []
    assert rules.check_all(reordered, list(reversed(NAMES)), clean) == []  # another set: checked
    assert checked == list(reversed(NAMES))
    assert rules.check_all(reordered, NAMES) == []  # no memo given: nothing is remembered
    assert rules.check_all(reordered, NAMES, rules.CleanSets()) == []  # nor by another one
    assert checked == list(reversed(NAMES)) + NAMES + NAMES


def test_a_value_of_another_type_with_the_same_json_is_checked_again():
    configs = copy.deepcopy(CONFIGS)
    clean = rules.CleanSets()
    assert rules.check_all(configs, NAMES, clean) == []
    configs[0]["containers"] = tuple(configs[0]["containers"])  # JSON writes it as a list
    problems = rules.check_all(configs, NAMES, clean)
    assert ("debug.cfg", "containers", "schema") in [(p.file, p.path, p.rule) for p in problems]
    configs[0]["containers"] = list(configs[0]["containers"])
    configs[0]["nodes"][0]["cTag"] = "ghost"  # a changed value: checked, found
    assert {p.rule for p in rules.check_all(configs, NAMES, clean)} == {"unknown-container"}


def test_the_clean_sets_kept_are_bounded():
    clean = rules.CleanSets()
    for index in range(rules.CLEAN_SETS + 5):
        config = dict(CONFIGS[2], password=f"secret{index}")
        assert rules.check_all([config], ["lo_server.cfg"], clean) == []
    assert len(clean.keys) == rules.CLEAN_SETS
