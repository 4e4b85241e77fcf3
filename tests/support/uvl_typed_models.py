"""Random small models of UVL's Arithmetic and Type levels, for hypothesis: typed
features (each with a finite domain declared by constraints, so brute force can
enumerate them: support/fm_typed_semantics.py), a feature cardinality, number
attributes, and equations with arithmetic, comparisons, strings and aggregates."""

from __future__ import annotations

from hypothesis import strategies as st

DOMAINS = {
    "Integer": "{name} >= 0 & {name} <= 2",
    "Real": "{name} == 0 | {name} == 0.5 | {name} == 1.5",
    "String": "len({name}) == 0 | {name} == 'a' | {name} == 'bc'",
}


@st.composite
def typed_models(draw: st.DrawFn) -> str:
    count = draw(st.integers(2, 4))
    kinds = [draw(st.sampled_from([None, None, "Integer", "Real", "String"])) for _ in range(count)]
    prices = [draw(st.sampled_from([None, "1", "2", "3", "0.5"])) for _ in range(count)]
    group = draw(st.sampled_from(["optional", "or", "alternative", "[1..2]"]))
    lines = ["features", "\tR", f"\t\t{group}"]
    for index, (kind, price) in enumerate(zip(kinds, prices, strict=True)):
        typed = f"{kind} " if kind else ""
        attributes = f" {{Price {price}}}" if price else ""
        cardinality = " cardinality [1..3]" if draw(st.booleans()) and index == 0 else ""
        lines.append(f"\t\t\t{typed}F{index}{cardinality}{attributes}")
    numbers = [f"F{i}" for i, k in enumerate(kinds) if k in ("Integer", "Real", None)]
    numbers += [f"F{i}.Price" for i, p in enumerate(prices) if p]
    if any(prices):
        numbers += ["sum(Price)", "avg(Price)", "sum(Price, R)"]
    numbers += [f"len(F{i})" for i, k in enumerate(kinds) if k == "String"]
    numbers += [f"floor(F{i})" for i, k in enumerate(kinds) if k == "Real"]
    numbers += ["1", "2", "0.5"]
    strings = [f"F{i}" for i, k in enumerate(kinds) if k == "String"] + ["'a'"]
    constraints = [DOMAINS[k].format(name=f"F{i}") for i, k in enumerate(kinds) if k]
    for _ in range(draw(st.integers(1, 3))):
        if draw(st.integers(0, 4)) == 0:
            left, right = draw(st.sampled_from(strings)), draw(st.sampled_from(strings))
            equation = f"{left} {draw(st.sampled_from(['==', '!=']))} {right}"
        else:
            left = draw(st.sampled_from(numbers))
            if draw(st.booleans()):
                left = f"({left} {draw(st.sampled_from('+-*/'))} {draw(st.sampled_from(numbers))})"
            relation = draw(st.sampled_from(["==", "!=", "<", "<=", ">", ">="]))
            equation = f"{left} {relation} {draw(st.sampled_from(numbers))}"
        feature = f"F{draw(st.integers(0, count - 1))}"
        shape = draw(st.sampled_from(["{e}", "{f} => {e}", "{e} | !{f}", "!({e})"]))
        constraints.append(shape.format(e=equation, f=feature))
    return "\n".join([*lines, "constraints", *(f"\t{c}" for c in constraints)]) + "\n"
