"""The JUnit XML report of `spl validate` (the Ant/Jenkins format every CI system reads)."""

from __future__ import annotations

from lxml import etree

from spl.line_validation import CaseResult


def junit_xml(results: list[CaseResult]) -> bytes:
    """The results as JUnit XML (the Ant/Jenkins format every CI system reads): one
    ``testsuite`` per product line, one ``testcase`` per product (classname = line,
    name = product), a ``failure`` carrying every located message, ``error`` for an
    internal error. No times or host names: the same results give the same bytes."""
    suites: dict[str, list[CaseResult]] = {}
    for result in results:
        suites.setdefault(result.classname, []).append(result)
    root = etree.Element(
        "testsuites",
        name="spl validate",
        tests=str(len(results)),
        failures=str(_count(results, "failed")),
        errors=str(_count(results, "error")),
    )
    for suite_name, cases in suites.items():
        suite = etree.SubElement(
            root,
            "testsuite",
            name=_xml_text(suite_name),
            tests=str(len(cases)),
            failures=str(_count(cases, "failed")),
            errors=str(_count(cases, "error")),
            skipped="0",
        )
        for result in cases:
            case = etree.SubElement(
                suite,
                "testcase",
                classname=_xml_text(result.classname),
                name=_xml_text(result.name),
            )
            if result.outcome != "passed":
                first = result.messages[0] if result.messages else "failed"
                problem = etree.SubElement(
                    case,
                    "failure" if result.outcome == "failed" else "error",
                    message=_xml_text(first),
                    type="ModelError" if result.outcome == "failed" else "InternalError",
                )
                problem.text = _xml_text("\n".join(result.messages))
            notes = result.warnings + result.skipped + ((result.checked,) if result.checked else ())
            if notes:
                etree.SubElement(case, "system-out").text = _xml_text("\n".join(notes))
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def _count(results: list[CaseResult], outcome: str) -> int:
    return sum(1 for r in results if r.outcome == outcome)


def _xml_text(text: str) -> str:
    """Messages and folder names are user input; characters XML 1.0 cannot carry are
    shown escaped instead of making lxml refuse the whole report."""
    return "".join(
        c
        if c in "\t\n\r" or (" " <= c <= "\ud7ff") or ("\ue000" <= c <= "\ufffd") or c > "\uffff"
        else f"\\x{ord(c):02x}"
        for c in text
    )
