"""``external "why"`` on an input (docs/tsm.md): the model keeps the reason, the printer
writes it back, and a missing reason is refused at its column."""

from __future__ import annotations

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.tsm import language as tsm
from spl.dsl.tsm.printer import print_model

TEXT = """system S

robot container R {
    topic Odom : nav_msgs/Odometry

    node Localizer {
        implementation amcl/amcl
        subscribes odom <- Odom external "wheel odometry of the base driver"
        calls map : nav_msgs/GetMap external "the site's map server"
    }
}
"""


def test_the_reason_is_kept_and_printed_back():
    system = tsm.parse_text(TEXT)
    (node,) = system.containers[0].nodes
    odom, map_client = node.interfaces
    assert odom.external == "wheel odometry of the base driver"
    assert map_client.external == "the site's map server"
    assert print_model(system) == TEXT
    assert print_model(tsm.parse_text(print_model(system))) == TEXT


@pytest.mark.parametrize("reason", ['""', '"   "'])
def test_an_empty_reason_is_refused_at_its_column(reason):
    text = TEXT.replace('"the site' + "'" + 's map server"', reason)
    with pytest.raises(ModelError) as error:
        tsm.parse_text(text, "s.tsm")
    (problem,) = error.value.diagnostics
    assert (problem.location.line, problem.location.col) == (9, 46)
    assert problem.message == (
        "external needs a reason: what outside the architecture feeds this input"
    )
