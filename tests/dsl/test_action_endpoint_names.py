"""Endpoint interfaces of a bridge take the endpoint prefix of their kind (docs/tsm.md,
"Bridges"): ``srv_``/``cli_`` for a service, ``asrv_``/``acli_`` for an action. A service
and an action of one name on two nodes of one name (servers ``Db.get`` of two
containers) then never give one endpoint two interfaces of one name: not where bridges
are written, and not where a node migration makes them, whose resolved model parses
back to the same names.
"""

from __future__ import annotations

from pathlib import Path

from spl.dsl.tsm.language import parse_text
from spl.dsl.tsm.printer import print_model
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.architecture_view import view

TSM = """system Clash

robot container R {
    endpoint robot_id "r1" url "wss://r.example.org:9000/" user "r" password env "RCE_PASSWORD"
    node Stay {
        implementation p/stay
    }
}

cloud container C1 {
    node Db {
        implementation p/db
        provides get : std_srvs/Empty name "/get_s"
    }
    optional node UserS {
        implementation p/users
        calls get -> Db.get
    }
}

cloud container C2 {
    node Db {
        implementation p/dba
        provides action get : actionlib/TwoInts name "/get_a"
    }
    optional node UserA {
        implementation p/usera
        calls action get -> Db.get
    }
}
"""
RM = """resolution model Clash
tsm "clash.tsm"
fm  "clash.fm"

when Move selected {
    require C1.UserS, C2.UserA
    migrate C1.UserS to R
    migrate C2.UserA to R
}
"""
FM = "feature model Clash\n\nroot Clash {\n    optional Move\n}\n"
ENDPOINTS = {
    "R": ["ActionServer:asrv_Db_get", "ServiceServer:srv_Db_get"],
    "C1": ["ServiceClient:cli_Db_get"],
    "C2": ["ActionClient:acli_Db_get"],
}


def test_migrated_clients_get_stand_ins_of_names_of_their_own(tmp_path: Path) -> None:
    for name, text in (("clash.tsm", TSM), ("clash.rm", RM), ("clash.fm", FM)):
        (tmp_path / name).write_text(text)
    product = resolve(load_product_line(tmp_path), selection_from_list("Clash,Move")).product
    v = view(product.system)
    assert v["endpoints"] == ENDPOINTS
    assert v["bindings"]["UserS.get"] == "R.endpoint.srv_Db_get"
    assert v["bindings"]["UserA.get"] == "R.endpoint.asrv_Db_get"
    # the resolved model, printed, parses back to the same endpoint interfaces
    assert view(parse_text(print_model(product.system)))["endpoints"] == ENDPOINTS


BRIDGED = """system Clash

robot container R {
    endpoint robot_id "r1" url "wss://r.example.org:9000/" user "r" password env "RCE_PASSWORD"
    node UserS {
        implementation p/users
        calls get : std_srvs/Empty
    }
    node UserA {
        implementation p/usera
        calls action get : actionlib/TwoInts
    }
}

cloud container C1 {
    node Db {
        implementation p/db
        provides get : std_srvs/Empty name "/get_s"
    }
}

cloud container C2 {
    node Db {
        implementation p/dba
        provides action get : actionlib/TwoInts name "/get_a"
    }
}

bridge R.UserS.get -> C1.Db.get
bridge R.UserA.get -> C2.Db.get
"""


def test_bridges_written_in_the_template_get_the_same_names() -> None:
    assert view(parse_text(BRIDGED))["endpoints"] == ENDPOINTS
