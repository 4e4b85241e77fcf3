"""``spl configure`` run for real refuses a request body over its limit
(docs/configure.md, "Limits") with 413 and the reason, without waiting for the body: a
request announcing 20 MB to ``/api/decide`` is answered before a byte of it is sent, a
chunked one as soon as it passes the limit (its end never sent), and the server closes
the connection rather than read on. A decision of ordinary size is still taken."""

from __future__ import annotations

import http.client
import json
from pathlib import Path

from spl.configure.body_limit import MAX_BODY

from support.configure_runs import configurator
from support.oversized_bodies import announced, chunked

MAPPING = Path(__file__).resolve().parents[2] / "product_lines" / "mapping3d"
JSON = {"Content-Type": "application/json", "Accept": "application/json"}


def test_an_oversized_decision_is_refused_with_413_before_its_body_is_read() -> None:
    with configurator(str(MAPPING)) as url:
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        refused = announced(port, "/api/decide", 20_000_000, JSON)
        assert refused.status == 413
        assert refused.body == {
            "error": f"the request body has 20000000 bytes; at most {MAX_BODY} are taken"
        }
        assert refused.headers["connection"] == "close" and refused.closed

        refused = chunked(port, "/api/decide", MAX_BODY + 1, JSON, chunk=64 * 1024)
        assert refused.status == 413
        assert refused.body == {"error": f"the request body has more than {MAX_BODY} bytes"}
        assert refused.closed

        # every other endpoint that takes a body has the same limit
        for path in ("/api/selection", "/api/capabilities", "/api/save", "/api/attribute"):
            refused = announced(port, path, MAX_BODY + 1, JSON)
            assert refused.status == 413 and refused.closed, path

        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        try:
            body = json.dumps({"feature": "AdditionalPC", "action": "select"})
            connection.request("POST", "/api/decide", body, JSON)
            answer = connection.getresponse()
            assert answer.status == 200
            assert json.loads(answer.read())["states"]["AdditionalPC"] == "selected"
        finally:
            connection.close()
