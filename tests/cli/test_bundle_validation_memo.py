"""`validate_bundle` checks a file's bytes once per process: a file whose bytes passed
its check passes again without being parsed again (products share many files); a file
with problems is checked and reported every time, and so is a changed one."""

from __future__ import annotations

import hashlib
import json

from spl.generators.bundle import validation as bundle_validation
from spl.generators.bundle.validation import validate_bundle


def bundle(files: dict[str, bytes]) -> dict[str, bytes]:
    """``files`` plus a manifest that lists them correctly."""
    listed = {path: hashlib.sha256(data).hexdigest() for path, data in files.items()}
    return {**files, "manifest.json": json.dumps({"files": listed}).encode()}


def counting_loads(monkeypatch) -> list[bytes]:
    parsed: list[bytes] = []
    real = bundle_validation._yaml

    def check(path, data):
        parsed.append(data)
        return real(path, data)

    monkeypatch.setattr(bundle_validation, "_yaml", check)
    return parsed


def test_bytes_that_passed_are_not_parsed_again_under_any_path(monkeypatch):
    parsed = counting_loads(monkeypatch)
    good = b"kind: ConfigMap\ndata: {a: '1'}\nmemo-test: first\n"
    assert validate_bundle(bundle({"kubernetes/a.yaml": good})) == []
    assert parsed == [good]
    assert validate_bundle(bundle({"kubernetes/a.yaml": good, "deploy/b.yaml": good})) == []
    assert parsed == [good]
    changed = good + b"more: 2\n"
    assert validate_bundle(bundle({"kubernetes/a.yaml": changed})) == []
    assert parsed == [good, changed]


def test_a_broken_file_is_reported_every_time(monkeypatch):
    parsed = counting_loads(monkeypatch)
    broken = b"kind: [unclosed\nmemo-test: broken\n"
    for _ in range(2):
        (problem,) = validate_bundle(bundle({"kubernetes/a.yaml": broken}))
        assert problem.startswith("kubernetes/a.yaml: not YAML: ")
    assert parsed == [broken, broken]


def test_a_clean_result_belongs_to_its_check():
    # the same bytes pass as YAML but not as a ROS 1 launch file
    text = b"memo-test: launch\n"
    assert validate_bundle(bundle({"config/x.yaml": text})) == []
    problems = validate_bundle(bundle({"ros1/x.launch": text}))
    assert problems and problems[0].startswith("ros1/x.launch:")


def test_the_files_kept_are_bounded():
    for index in range(bundle_validation.CLEAN_FILES + 3):
        data = f"memo-test: {index}\n".encode()
        assert validate_bundle(bundle({"a.yaml": data})) == []
    assert len(bundle_validation._CLEAN_FILES) == bundle_validation.CLEAN_FILES
