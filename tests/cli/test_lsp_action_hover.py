"""The editor's hover says an action interface as its .tsm statement says it
(docs/tsm.md, "Actions"; docs/editors.md): its keyword, name, type and the server it
sends goals to, asked of its kind like every other interface."""

from __future__ import annotations

import textwrap

from spl.dsl.tsm import language as tsm
from spl.lsp import hover

TEXT = textwrap.dedent(
    """\
    robot container R {
        node N {
            calls action goal -> M.move_base
            calls action spare : move_base_msgs/MoveBase
        }
        node M {
            provides action move_base : move_base_msgs/MoveBase name "/move_base"
        }
    }
    """
)


def test_hover_lines_of_action_interfaces() -> None:
    system = tsm.parse_text(TEXT, "nav.tsm")
    lines = [hover._interface_line(i) for n in system.containers[0].nodes for i in n.interfaces]
    assert lines == [
        "calls action `goal` : `move_base_msgs/MoveBase` -> `M.move_base`",
        "calls action `spare` : `move_base_msgs/MoveBase`",
        "provides action `move_base` : `move_base_msgs/MoveBase`",
    ]
