"""escape_substitutions escapes exactly backslash, dollar and both quotes (one backslash
before each), and hands back texts without them unchanged."""

from __future__ import annotations

import pytest

from spl.generators.launch.ros2_launch import escape_substitutions


@pytest.mark.parametrize(
    ("text", "escaped"),
    [
        ("plain/text_1", "plain/text_1"),
        ("", ""),
        ("$(env HOME)", "\\$(env HOME)"),
        ("it's", "it\\'s"),
        ('say "hi"', 'say \\"hi\\"'),
        ("a\\b", "a\\\\b"),
        ("$'\"\\", "\\$\\'\\\"\\\\"),
    ],
)
def test_escaped_exactly_where_the_grammar_needs_it(text, escaped):
    assert escape_substitutions(text) == escaped
