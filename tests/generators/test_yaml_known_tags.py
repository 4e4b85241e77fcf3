"""PyYAML loaders and dumpers that look each plain scalar's implicit tag up once per
process read and write exactly what PyYAML's own do, for scalars of every implicit
type, repeated, and in every quoting."""

from __future__ import annotations

import pytest
import yaml

from spl.generators.kubernetes.objects import with_known_tags

# Plain scalars that resolve to each of YAML 1.1's implicit types, and look-alikes.
SCALARS = [
    "yes",
    "No",
    "on",
    "OFF",
    "true",
    "y",
    "~",
    "null",
    "",
    "1_000",
    "0x1F",
    "0o17",
    "017",
    "0b101",
    "-12",
    "+3",
    "1:30",
    "1:30.5",
    "3.14",
    "1e5",
    "1.0e+5",
    ".inf",
    "-.Inf",
    ".nan",
    "2002-12-14",
    "2001-12-14t21:59:43.10-05:00",
    "2002-13-45",
    "<<",
    "=",
    "plain",
    "with space",
    "a: b",
    "- x",
    "#no",
    "7447",
    "tcp/[::]:7447",
    "x" * 70,
]

# a date that does not exist; a merge key outside a mapping
REFUSED = {"2002-13-45": ValueError, "<<": yaml.constructor.ConstructorError}


def outcome(source: str, loader: type) -> tuple:
    """What loading gives: the data, or the kind of error (PyYAML writes ``<<`` plain
    in a list, then refuses to read it back)."""
    try:
        return ("data", yaml.load(source, Loader=loader))
    except (yaml.YAMLError, ValueError) as error:
        return ("error", type(error), str(error))


def test_loading_and_dumping_match_pyyaml_scalar_by_scalar():
    for base_loader, base_dumper in (
        (yaml.SafeLoader, yaml.SafeDumper),
        (
            getattr(yaml, "CSafeLoader", yaml.SafeLoader),
            getattr(yaml, "CSafeDumper", yaml.SafeDumper),
        ),
    ):
        loader, dumper = with_known_tags(base_loader), with_known_tags(base_dumper)
        document = {"values": SCALARS, "keys": dict.fromkeys(SCALARS, 1), "again": SCALARS}
        for _ in range(2):  # the second round answers from what the first looked up
            text = yaml.dump(document, Dumper=dumper, sort_keys=False)
            assert text == yaml.dump(document, Dumper=base_dumper, sort_keys=False)
            listed = [
                x for x in SCALARS if x and not x.startswith(("-", "#")) and x != "2002-13-45"
            ]
            plain = "\n".join(f"- {x}" for x in listed)
            quoted = "\n".join(f"- '{x}'" for x in listed)
            for source in (text, plain, quoted):
                assert outcome(source, loader) == outcome(source, base_loader)
            for each in (loader, base_loader):  # both refuse these as plain scalars
                for scalar, error in REFUSED.items():
                    with pytest.raises(error):
                        yaml.load(f"- {scalar}", Loader=each)


def test_document_nodes_write_what_pyyaml_representer_writes():
    """kubernetes_objects' own node building against PyYAML's representer, on both
    emitters, for every kind of value (and one it leaves to the representer)."""
    from spl.generators.kubernetes.objects import _dumper, _Literal

    shared = {"a": "b"}  # met twice: written twice, never as an anchor
    document = {
        "scalars": SCALARS,
        "kinds": [True, False, None, 0, -7, 7447, 2.5, "", _Literal("line 1\nline 2\n")],
        "keys": {1: "one", False: "no", None: "none"},
        "empty": [{}, [], {"x": []}],
        "shared": [shared, shared],
        "tuple": (1, "two"),
    }
    for base in (yaml.SafeDumper, getattr(yaml, "CSafeDumper", yaml.SafeDumper)):
        fast, own = _dumper(base), _dumper(base, nodes=False)
        for _ in range(2):
            options = {"sort_keys": False, "default_flow_style": False, "width": 2**16}
            text = yaml.dump_all([document, shared], Dumper=fast, **options)
            assert text == yaml.dump_all([document, shared], Dumper=own, **options)
