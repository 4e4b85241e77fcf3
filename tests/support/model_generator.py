"""A small grammar-aware generator of whole product lines for the fuzz tests.

Where the migration tests need valid lines, this one wants the builders' corners:
every production of the three grammars (and of product selections) is drawn with names
picked from what the line declares, from near misses (a node where a topic belongs, a
name of another container, an interface as a node) and from outright unknowns, with
literals of every type whatever the declared type says. Most lines are invalid in some
way; the property is only that the commands say so with a located error.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from hypothesis import strategies as st

from support.random_lines import ROS_TOPICS, SERVICE_TYPES, LineSpec, line_specs, tsm_text

LITERALS = ('"text"', '"a: [1, 2]"', '"{"', "true", "false", "0", "-3", "2.5", "1e3", "1e999")
TYPES = ("string", "int", "double", "bool", "yaml")
FITTING = {  # literals of each type
    "string": ('"text"', '"a b"'),
    "int": ("0", "-3", "42"),
    "double": ("2.5", "0.0", "-1.5"),
    "bool": ("true", "false"),
    "yaml": ('"a: [1, 2]"', '"text"'),
}


def mostly(usual: st.SearchStrategy, rare: st.SearchStrategy) -> st.SearchStrategy:
    """``usual`` nine times in ten: most generated text is right, so the checks behind
    the first error are reached too."""
    return st.sampled_from([True] * 9 + [False]).flatmap(lambda ok: usual if ok else rare)


def literal(kind: str) -> st.SearchStrategy[str]:
    return mostly(st.sampled_from(FITTING[kind]), st.sampled_from(LITERALS))


ROS_TYPES = (*sorted(set(ROS_TOPICS.values())), *SERVICE_TYPES, "pkg/Type", "bad_msgs/X")


@dataclass
class Vocabulary:
    """Names a generated statement may use: the line's own, plus near misses."""

    containers: list[str]
    nodes: list[str]
    interfaces: list[str]  # NODE.INTERFACE
    topics: list[str]  # CONTAINER.TOPIC
    features: list[str]
    attributes: list[str]  # FEATURE.ATTRIBUTE

    def names(self, *kinds: str) -> st.SearchStrategy[str]:
        pools = [p for kind in kinds if (p := getattr(self, kind))]
        odd = ["Unknown", "Root", "Robot0", "when"]
        wrong = st.sampled_from(odd if kinds == ("features",) else [*odd, "x.y.z", "N0.p0.q"])
        return mostly(st.one_of(*(st.sampled_from(p) for p in pools)) if pools else wrong, wrong)

    def short(self, qualified: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
        """A qualified name, or its last part only (an unqualified reference)."""
        return st.one_of(qualified, qualified.map(lambda n: n.split(".")[-1]))


def vocabulary(spec: LineSpec, features: list[str], attributes: list[str]) -> Vocabulary:
    return Vocabulary(
        containers=list(spec.containers),
        nodes=[n.name for n in spec.nodes] + [f"{n.container}.{n.name}" for n in spec.nodes],
        interfaces=[f"{n.name}.{i.name}" for n in spec.nodes for i in n.interfaces],
        topics=[f"{t.container}.{t.name}" for t in spec.topics],
        features=features,
        attributes=attributes,
    )


@st.composite
def statements(draw, v: Vocabulary) -> str:
    kind = draw(st.integers(0, 8))
    if kind == 0:
        refs = draw(st.lists(v.names("nodes", "interfaces"), min_size=1, max_size=3))
        return "require " + ", ".join(refs)
    if kind == 1:
        args = draw(st.sampled_from(["", ' args "--rate 5 _frame:=map"', ' args "a;b"', " args"]))
        return f"implementation {draw(v.names('nodes'))} = {draw(st.sampled_from(ROS_TYPES))}{args}"
    if kind == 2:
        topic = draw(v.short(v.names("topics")))
        return f"connect {draw(v.names('interfaces'))} to topic {topic.split('.')[-1]}"
    if kind == 3:
        name = draw(st.sampled_from(["Fresh", "Scan", "Pose", "New1"]))
        ros = draw(st.sampled_from(["", ' name "/fresh"', ' name "bad name"', ' name "/scan"']))
        kind_type = draw(st.sampled_from(ROS_TYPES))
        return f"connect {draw(v.names('interfaces'))} to new topic {name} : {kind_type}{ros}"
    if kind == 4:
        return f"connect {draw(v.names('interfaces'))} to server {draw(v.names('interfaces'))}"
    if kind == 5:
        return f"connect bridge {draw(v.names('topics'))} -> {draw(v.names('topics'))}"
    if kind == 6:
        client = f"{draw(v.names('containers'))}.{draw(v.names('interfaces'))}"
        server = f"{draw(v.names('containers'))}.{draw(v.names('interfaces'))}"
        return f"connect bridge {client} -> {server}"
    if kind == 7:
        value = draw(
            st.one_of(
                st.sampled_from(LITERALS),
                v.names("attributes").map(lambda a: f"feature {a}"),
            )
        )
        return (
            f"parameter {draw(v.names('nodes'))}.{draw(st.sampled_from(['q', 'rate']))} = {value}"
        )
    return f"migrate {draw(v.names('nodes'))} to {draw(v.names('containers'))}"


@st.composite
def rm_texts(draw, v: Vocabulary) -> str:
    lines = ["resolution model Generated", 'tsm "gen.tsm"', 'fm "gen.fm"', ""]
    for _ in range(draw(st.integers(0, 4))):
        feature = draw(v.names("features"))
        state = draw(st.sampled_from(["selected", "not selected"]))
        body = draw(st.lists(statements(v), max_size=4))
        lines.append(f"when {feature} {state} {{")
        lines += [f"    {s}" for s in body]
        lines.append("}")
    return "\n".join(lines) + "\n"


@st.composite
def fm_texts(draw, features: list[str]) -> tuple[str, list[str]]:
    """A feature tree over ``features`` with random groups, attributes, sharing and
    constraints; also the FEATURE.ATTRIBUTE names it declares."""
    attributes: list[str] = []

    def body(name: str) -> str:
        parts = []
        for k in range(draw(st.integers(0, 2))):
            kind = draw(st.sampled_from(TYPES[:4]))
            parts.append(f"attribute a{k} : {kind} = {draw(literal(kind))}")
            attributes.append(f"{name}.a{k}")
        if draw(st.booleans()):
            parts.append(f"sharing {draw(st.sampled_from(['private', 'protected', 'public']))}")
        return f" {{ {' '.join(parts)} }}" if parts else ""

    children = []
    rest = list(features)
    while rest:
        take = draw(st.integers(1, min(3, len(rest))))
        group, rest = rest[:take], rest[take:]
        shape = draw(st.sampled_from(["optional", "mandatory", "xor", "or", "card"]))
        members = [f"{f}{body(f)}" for f in group]
        if shape in ("optional", "mandatory"):
            children += [f"    {shape} {m}" for m in members]
        elif shape == "card":
            low, high = (
                draw(st.sampled_from(["0", "1", "2", "5"])),
                draw(st.sampled_from(["1", "3", "*"])),
            )
            children.append(f"    group [{low}..{high}] {{ {' '.join(members)} }}")
        else:
            children.append(f"    {shape} {{ {' '.join(members)} }}")
    operators = st.sampled_from(["requires", "excludes", "and", "or", "=>", "<=>"])
    pool = mostly(st.sampled_from([*features, "Root"]), st.just("Ghost"))
    constraints = [
        f"    {draw(st.sampled_from(['', 'not ']))}{draw(pool)} {draw(operators)} {draw(pool)}"
        for _ in range(draw(st.integers(0, 3)))
    ]
    text = "feature model Generated\n\nroot Root {\n"
    text += "\n".join(children) + "\n}\n"
    if constraints:
        text += "\nconstraints {\n" + "\n".join(constraints) + "\n}\n"
    return text, attributes


@st.composite
def selection_texts(draw, v: Vocabulary) -> str:
    features = ["Root", *draw(st.lists(v.names("features"), max_size=4))]
    lines = [f"product: {draw(mostly(st.just('gen'), st.sampled_from(['bad name', '1x', '[a]'])))}"]
    lines.append(f"features: [{', '.join(features)}]")
    if draw(st.booleans()):
        lines.append(f"deselected: [{draw(v.names('features'))}]")
    if draw(st.booleans()):
        mode = draw(st.sampled_from(["private", "protected", "public", "secret", "[x]"]))
        lines.append(f"sharing: {{{draw(v.names('features'))}: {mode}}}")
    if draw(st.booleans()):
        value = draw(st.sampled_from(["1", "2.5", "true", "text", ".nan", "[1]", "!!int x"]))
        lines.append(f"attributes: {{{draw(v.names('attributes'))}: {value}}}")
    if draw(st.booleans()):
        setting = draw(st.sampled_from(["robot_id: r2", 'url: "wss://x.org:1/"', "url: ftp://x"]))
        lines.append(f"deployment: {{{draw(v.names('containers'))}: {{{setting}}}}}")
    if draw(mostly(st.just(False), st.just(True))):
        lines.append(draw(st.sampled_from(["unknown: 1", "features: [again]", "- list"])))
    return "\n".join(lines) + "\n"


@st.composite
def generated_lines(draw) -> dict[str, str]:
    """The files of one generated product line, by name."""
    spec = draw(line_specs())
    names = [f"F{k}" for k in range(draw(st.integers(1, 5)))]
    fm, attributes = draw(fm_texts(names))
    v = vocabulary(spec, names, attributes)
    tsm = tsm_text(spec)
    if draw(st.booleans()):  # parameters of every type with literals of every type
        kind = draw(st.sampled_from(TYPES))
        value = draw(literal(kind))
        tsm = re.sub(
            r"(        implementation \S+\n)",
            rf"\1        param q : {kind} = {value}\n",
            tsm,
            count=1,
        )
    return {
        "gen.tsm": tsm,
        "gen.fm": fm,
        "gen.rm": draw(rm_texts(v)),
        "products/gen.yaml": draw(selection_texts(v)),
    }
