"""The files a .rm names in its header, as the language server reads them on every
change from the start of the text only (``Project.header``), are those its whole text's
tokens name: whatever comes before the header, however long, and whatever the text
holds after it."""

from __future__ import annotations

import os

import pytest

from spl.lsp.project import Document, Project, header_paths

BODY = 'resolution model M\ntsm "models/a.tsm"\nfm "b.fm"\n\nwhen F selected {\n    require N\n}\n'
TEXTS = [
    BODY,
    "// when a comment says when, it is no element\n" + BODY,
    "/* " + "when " * 3000 + "*/\n" + BODY,  # a comment longer than the first look
    "// " + "x" * 20000 + "\n" + BODY,
    'resolution model M\ntsm "' + "d/" * 3000 + 'a.tsm"\nfm "b.fm"\n',  # a long path, no element
    'resolution model M\nfm "b.fm"\n' + "when F selected {\n}\n" * 2000 + 'tsm "late.tsm"\n',
    "",
    'resolution model M\ntsm "unterminated',
]


@pytest.mark.parametrize("text", TEXTS, ids=range(len(TEXTS)))
def test_the_header_read_from_the_start_is_the_whole_texts(text: str, tmp_path) -> None:
    path = os.path.join(tmp_path, "line.rm")
    project = Project()
    project.documents[path] = Document("file://" + path, path, 1, text)
    assert project.header(path) == header_paths(path, project.tokens(path))
    project.documents[path].text = text + "\nwhen G selected {\n}\n"  # a change: read again
    assert project.header(path) == header_paths(path, project.tokens(path))
