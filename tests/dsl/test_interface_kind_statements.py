"""A statement that joins interfaces names the kinds it joins (docs/tsm.md, docs/rm.md):
an interface of another kind is a located error saying what it is and what the
statement takes, in the .tsm and in the .rm alike."""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.dsl.rm import language as rm
from spl.dsl.tsm import language as tsm
from spl.dsl.tsm.printer import print_model
from spl.metamodels.interface_kinds import KINDS

FARM = Path(__file__).parents[1] / "models" / "semantics"
HEADER = 'resolution model Farm\ntsm "farm.tsm"\nfm  "farm.fm"\n'


def tsm_errors(text: str) -> list[str]:
    with pytest.raises(ModelError) as caught:
        tsm.parse_text(textwrap.dedent(text), "bad.tsm")
    return [str(d) for d in caught.value.diagnostics]


def rm_errors(tmp_path: Path, *statements: str) -> list[str]:
    """The errors of a farm .rm whose one element holds ``statements``, from line 5 on."""
    shutil.copy(FARM / "farm.tsm", tmp_path / "farm.tsm")
    shutil.copy(FARM / "farm.fm", tmp_path / "farm.fm")
    body = "".join(["when Planning selected {\n", *(f"    {s}\n" for s in statements), "}\n"])
    (tmp_path / "farm.rm").write_text(HEADER + body, encoding="utf-8")
    with pytest.raises(ModelError) as caught:
        rm.load(tmp_path / "farm.rm")
    return [str(d).replace(f"{tmp_path}/", "") for d in caught.value.diagnostics]


def test_a_tsm_bridge_joins_a_client_to_a_server_of_its_family() -> None:
    assert tsm_errors(
        """\
        robot container R {
            topic T : std_msgs/String
            node N {
                calls c : std_srvs/Empty
                publishes p -> T
                subscribes s <- T
            }
        }
        cloud container C {
            topic T : std_msgs/String
            node M {
                provides srv : std_srvs/Empty
                calls cli : std_srvs/Empty
                publishes out -> T
            }
        }
        bridge R.N.c -> C.M.out
        bridge R.N.c -> C.M.cli
        bridge R.N.p -> C.M.srv
        bridge R.N.s -> C.M.srv
        """
    ) == [
        "bad.tsm:17:21: error: kind mismatch: R.N.c (bad.tsm:4:15) is a service client, C.M.out "
        "(bad.tsm:14:19) is a topic publisher, not a service server",
        "bad.tsm:18:21: error: kind mismatch: R.N.c (bad.tsm:4:15) is a service client, C.M.cli "
        "(bad.tsm:13:15) is a service client, not a service server",
        "bad.tsm:19:12: error: N.p is a Publisher, not a service client or action client",
        "bad.tsm:20:12: error: N.s is a Subscriber, not a service client or action client",
    ]


def test_rm_connections_take_the_kinds_they_join(tmp_path: Path) -> None:
    assert rm_errors(
        tmp_path,
        "connect Planner.plan to topic Weeds",
        "connect Navigator.plan to new topic Plans : farm_msgs/Plan",
        "connect Navigator.cmd to server Planner.plan",
        "connect Navigator.plan to server Planner.route",
        "connect bridge Navigator.route -> Planner.plan",
        "connect bridge Navigator.plan -> Planner.weeds",
    ) == [
        "farm.rm:5:5: error: Planner.plan is a ServiceServer, not a publisher or subscriber",
        "farm.rm:6:5: error: Navigator.plan is a ServiceClient, not a publisher or subscriber",
        "farm.rm:7:5: error: Navigator.cmd is a Publisher, not a service client or action client",
        "farm.rm:8:5: error: kind mismatch: Tractor.Navigator.plan (farm.tsm:25:20) is a service "
        "client, Cloud.Planner.route (farm.tsm:61:20) is a topic publisher, not a service server",
        "farm.rm:9:5: error: Navigator.route is a Subscriber, not a service client or action "
        "client",
        "farm.rm:10:5: error: kind mismatch: Tractor.Navigator.plan (farm.tsm:25:20) is a service "
        "client, Cloud.Planner.weeds (farm.tsm:60:20) is a topic subscriber, not a service server",
    ]


def test_each_kind_is_printed_with_its_keyword_and_arrow() -> None:
    """The printer writes an interface as its kind's statement, the arrow pointing the
    way the flow runs, and what it writes parses back to the same statement."""
    text = textwrap.dedent(
        """\
        system S
        robot container R {
            topic T : std_msgs/String
            node N {
                publishes p -> T
                subscribes s <- T
                calls c -> M.srv
            }
            node M {
                provides srv : std_srvs/Empty name "/m/srv"
            }
        }
        """
    )
    printed = print_model(tsm.parse_text(text, "kinds.tsm"))
    lines = [line.strip() for line in printed.splitlines()]
    assert "publishes p -> T" in lines and "subscribes s <- T" in lines
    assert "calls c -> M.srv" in lines
    assert 'provides srv : std_srvs/Empty name "/m/srv"' in lines
    # a kind bound to nothing (a server) has no arrow: nothing follows its type
    assert [k.keyword for k in KINDS if k.arrow is None] == ["provides", "provides action"]
    assert print_model(tsm.parse_text(printed, "printed.tsm")) == printed
