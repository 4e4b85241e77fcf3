"""The JUnit XML report of `spl validate` (the Ant/Jenkins format every CI system reads),
and the merge of the reports of a sharded run into the report of the whole run."""

from __future__ import annotations

import re
from collections.abc import Iterable

from lxml import etree

from spl.validation.line import CaseResult, Shard

TOOL = "spl validate"
SHARD_TITLE = re.compile(
    rf"{TOOL} --shard (?P<shard>[1-9][0-9]*/[1-9][0-9]*) \(plan (?P<plan>[0-9a-f]+)\)"
)


class ReportProblem(Exception):
    """A report that cannot be merged; the message says where and why."""


def junit_xml(
    results: list[CaseResult], shard: Shard | None = None, plan: str | None = None
) -> bytes:
    """The results as JUnit XML: one ``testsuite`` per product line, one ``testcase`` per
    product (classname = line, name = product), a ``failure`` carrying every located
    message, ``error`` for an internal error, the product's warnings (and those about
    this machine) in ``system-err`` one a line, as ``spl resolve`` prints them on stderr,
    the smoke rehearsal's summary in ``system-out``. No times or host names: the same
    results give the same bytes. A shard's report also names its shard and its run's plan, which
    is all a merge needs to put the shards back together."""
    return _report(((r.classname, _testcase(r)) for r in results), shard, plan)


def merge_junit(reports: list[tuple[str, bytes]]) -> bytes:
    """The report of the whole run from its shards' reports (``(file name, bytes)``, in
    any order): the same bytes the unsharded run writes. Refused, naming the file, when
    a report is not a shard's of ``spl validate``, a shard is missing or given twice, or
    the reports come from different runs."""
    shards: dict[int, list[tuple[str, etree._Element]]] = {}
    counts, plans = set(), set()
    for name, data in reports:
        root = _parse(name, data)
        title = root.get("name") or ""
        if root.tag != "testsuites" or not title.startswith(TOOL):
            raise ReportProblem(f"{name}: not a report of {TOOL}")
        found = SHARD_TITLE.fullmatch(title)
        if found is None:
            raise ReportProblem(
                f"{name}: not the report of a shard (spl validate --shard K/N --junit FILE)"
            )
        try:
            shard = Shard.parse(found["shard"])
        except ValueError as exc:
            raise ReportProblem(f"{name}: {exc}") from None
        if shard.index in shards:
            raise ReportProblem(f"{name}: shard {shard} is given twice")
        counts.add(shard.count)
        plans.add(found["plan"])
        shards[shard.index] = [
            (case.get("classname") or "", case) for case in root.iter("testcase")
        ]
    if len(counts) > 1 or len(plans) > 1:
        raise ReportProblem(
            "the reports are of different runs (other lines, options, shard counts or spl "
            "versions): merge the shards of one run"
        )
    [count] = counts or {0}
    missing = [str(k) for k in range(1, count + 1) if k not in shards]
    if missing or not shards:
        raise ReportProblem(f"shard {', '.join(missing) or '1'} of {count or 1} is missing")
    return _report(case for k in sorted(shards) for case in shards[k])


def summary_of(report: bytes) -> tuple[int, int]:
    """(passed, failed or in error) of a report this module wrote."""
    root = etree.fromstring(report)
    tests = int(root.get("tests", "0"))
    failed = int(root.get("failures", "0")) + int(root.get("errors", "0"))
    return tests - failed, failed


def _parse(name: str, data: bytes) -> etree._Element:
    parser = etree.XMLParser(
        resolve_entities=False, no_network=True, load_dtd=False, remove_blank_text=True
    )
    try:
        return etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        line, col = exc.position
        reason = re.sub(r"(, line \d+, column \d+)+$", "", exc.msg)
        raise ReportProblem(f"{name}:{line}:{col}: not XML: {reason}") from None


def _testcase(result: CaseResult) -> etree._Element:
    case = etree.Element(
        "testcase", classname=_xml_text(result.classname), name=_xml_text(result.name)
    )
    if result.outcome == "skipped":  # its bundle is unchanged: messages say since when
        reason = result.messages[0] if result.messages else "skipped"
        etree.SubElement(case, "skipped", message=_xml_text(reason))
    elif result.outcome != "passed":
        first = result.messages[0] if result.messages else "failed"
        kind = "ModelError" if result.outcome == "failed" else "InternalError"
        if result.messages and result.messages == result.product_warnings:
            kind = "Warning"  # --strict failed it for its warnings alone (docs/ci.md)
        problem = etree.SubElement(
            case,
            "failure" if result.outcome == "failed" else "error",
            message=_xml_text(first),
            type=kind,
        )
        problem.text = _xml_text("\n".join(result.messages))
    if result.checked:
        etree.SubElement(case, "system-out").text = _xml_text(result.checked)
    if result.warnings:
        warnings = "\n".join(str(warning) for warning in result.warnings)
        etree.SubElement(case, "system-err").text = _xml_text(warnings)
    return case


def _report(
    cases: Iterable[tuple[str, etree._Element]],
    shard: Shard | None = None,
    plan: str | None = None,
) -> bytes:
    """The document of the test cases, grouped into one suite per line in the order the
    lines first appear, with the counts of what failed."""
    suites: dict[str, list[etree._Element]] = {}
    for suite_name, case in cases:
        suites.setdefault(suite_name, []).append(case)
    every = [case for members in suites.values() for case in members]
    # a shard's title says which shard of which run it is (the JUnit schema has no
    # attribute for it, and an empty shard has no suite to carry properties)
    title = TOOL if shard is None else f"{TOOL} --shard {shard} (plan {plan})"
    root = etree.Element("testsuites", name=title, **_counts(every))
    for suite_name, members in suites.items():
        suite = etree.SubElement(root, "testsuite", name=_xml_text(suite_name))
        for key, value in _counts(members).items():
            suite.set(key, value)
        suite.set("skipped", str(sum(1 for c in members if c.find("skipped") is not None)))
        suite.extend(members)
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def _counts(cases: list[etree._Element]) -> dict[str, str]:
    return {
        "tests": str(len(cases)),
        "failures": str(sum(1 for c in cases if c.find("failure") is not None)),
        "errors": str(sum(1 for c in cases if c.find("error") is not None)),
    }


def _xml_text(text: str) -> str:
    """Messages and folder names are user input; characters XML 1.0 cannot carry are
    shown escaped instead of making lxml refuse the whole report."""
    return "".join(
        c
        if c in "\t\n\r" or (" " <= c <= "\ud7ff") or ("\ue000" <= c <= "\ufffd") or c > "\uffff"
        else f"\\x{ord(c):02x}"
        for c in text
    )
