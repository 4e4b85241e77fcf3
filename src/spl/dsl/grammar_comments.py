"""Comments in the three grammars, which syntax errors leave out of what they expected.

``fm.tx``, ``rm.tx`` and ``tsm.tx`` share one comment rule (``// ...`` and ``/* ... */``).
textX lists its regular expressions among the expected rules wherever a comment may
start, which is everywhere; shown to a user they are noise (``expected '\\/\\/[^\\n]*' or
'feature'`` for an empty file), so the messages name only what the file lacks.
"""

from __future__ import annotations

import re
from typing import Any

COMMENT_PATTERNS = frozenset({r"\/\/[^\n]*", r"\/\*(.|\n)*?\*\/"})
# the same patterns for Python's re (which reads ``\/`` as ``/``), to find comments in a text
COMMENT = re.compile("|".join(sorted(COMMENT_PATTERNS)))


def is_comment(rule: Any) -> bool:
    """Whether a rule textX says it expected is one of the comment patterns."""
    return (getattr(rule, "to_match", None) or str(rule)) in COMMENT_PATTERNS
