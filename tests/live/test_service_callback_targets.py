"""Where a generated service's callback subscriptions may post (docs/services.md, "Where
callbacks may go"), through uvicorn as deployed. Every spelling of an internal address
(loopback, link-local, private, multicast, reserved, unspecified; decimal, hex, octal,
short, IPv4-mapped, NAT64 and 6to4 forms, trailing dots, names of /etc/hosts) is refused
with 400 and the reason, and a listener on every address of this machine at that port
gets nothing, not even through a proxy of the environment; a loopback receiver on the
allow list gets each record exactly once; a redirect is not followed; and with a
resolver that the test scripts in the service process, a name that resolved to a public
address when subscribed and to loopback when posting is not posted to, and a post goes
to the address that was checked, not to one the name resolves to a moment later."""

from __future__ import annotations

import ipaddress
import json
import sys
from pathlib import Path

import pytest

from spl.generators.service import generator as service

from support.callback_listeners import Listener
from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, wait_for, write_files
from support.tls import certificate_for

PACKAGE = "position_store_service"
STORE = "/PositionStore"
ALLOW = "POSITION_STORE_CALLBACK_HOSTS"
LOOPBACK = "a loopback address"
# (host as written in the URI, what the refusal says about it)
SPELLINGS = [
    ("127.0.0.1", f"127.0.0.1, {LOOPBACK}"),
    ("127.0.0.2", f"127.0.0.2, {LOOPBACK}"),
    ("localhost", "localhost is a loopback name"),
    ("LOCALHOST", "localhost is a loopback name"),
    ("localhost.", "localhost. is a loopback name"),
    ("api.localhost", "api.localhost is a loopback name"),
    ("127.1", f"127.1 is 127.0.0.1, {LOOPBACK}"),
    ("2130706433", f"2130706433 is 127.0.0.1, {LOOPBACK}"),
    ("0x7f000001", f"0x7f000001 is 127.0.0.1, {LOOPBACK}"),
    ("0177.0.0.1", f"0177.0.0.1 is 127.0.0.1, {LOOPBACK}"),
    ("0x7f.1", f"0x7f.1 is 127.0.0.1, {LOOPBACK}"),
    ("127.0.0.1.", f"127.0.0.1. is 127.0.0.1, {LOOPBACK}"),
    ("[::1]", f"::1, {LOOPBACK}"),
    ("[::ffff:127.0.0.1]", f"::ffff:127.0.0.1 is 127.0.0.1, {LOOPBACK}"),
    ("[::ffff:7f00:1]", f"::ffff:7f00:1 is 127.0.0.1, {LOOPBACK}"),
    ("[64:ff9b::7f00:1]", f"64:ff9b::7f00:1, {LOOPBACK} (through 127.0.0.1)"),
    ("[2002:7f00:1::]", f"2002:7f00:1::, {LOOPBACK} (through 127.0.0.1)"),
    ("[::127.0.0.1]", f"{LOOPBACK} (through 127.0.0.1)"),
    ("0.0.0.0", "0.0.0.0, the unspecified address"),
    ("0", "0 is 0.0.0.0, the unspecified address"),
    ("[::]", "::, the unspecified address"),
    ("169.254.169.254", "169.254.169.254, a link-local address"),
    ("[::ffff:169.254.169.254]", "is 169.254.169.254, a link-local address"),
    ("0xa9fea9fe", "0xa9fea9fe is 169.254.169.254, a link-local address"),
    ("[fe80::1]", "fe80::1, a link-local address"),
    ("10.0.0.1", "10.0.0.1, a private address"),
    ("172.16.0.1", "172.16.0.1, a private address"),
    ("192.168.1.1", "192.168.1.1, a private address"),
    ("012.0.0.1", "012.0.0.1 is 10.0.0.1, a private address"),
    ("[fd00::2]", "fd00::2, a private address"),
    ("100.64.0.1", "100.64.0.1, an address that is not globally routable"),
    ("224.0.0.1", "224.0.0.1, a multicast address"),
    ("[ff02::1]", "ff02::1, a multicast address"),
    ("240.0.0.1", "240.0.0.1, a reserved address"),
    ("255.255.255.255", "255.255.255.255, a reserved address"),
]


def hosts_file_names() -> list[tuple[str, str]]:
    """The names /etc/hosts gives an internal address, each with the refusal's words."""
    names = []
    for line in Path("/etc/hosts").read_text().splitlines():
        fields = line.partition("#")[0].split()
        if len(fields) < 2 or ipaddress.ip_address(fields[0]).is_global:
            continue
        for name in fields[1:]:
            if name == "localhost" or name.endswith(".localhost"):
                continue  # refused by name, above
            names.append((name, f"{name} resolves to "))
    return names


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = write_files(service.generate(product()), tmp_path_factory.mktemp("callbacks"))
    return root / "services" / "PositionStore"


@pytest.fixture(scope="module")
def listeners():  # type: ignore[no-untyped-def]
    """catcher: every address of this machine at one port, never allowed; allowed: a
    loopback receiver on the allow list; redirector: allowed, answering 307 to the
    catcher."""
    catcher = Listener("::")
    allowed = Listener()
    redirector = Listener(status=307, location=f"http://127.0.0.1:{catcher.port}/stolen")
    yield catcher, allowed, redirector
    for listener in (catcher, allowed, redirector):
        listener.close()


@pytest.fixture(scope="module")
def running(directory: Path, listeners):  # type: ignore[no-untyped-def]
    catcher, allowed, redirector = listeners
    proxy = f"http://127.0.0.1:{catcher.port}"
    environment = {
        "POSITION_STORE_TOKEN": TOKEN,
        "TRANSFORMER": "off",
        ALLOW: f"127.0.0.1:{allowed.port}, 127.0.0.1:{redirector.port}",
        # a proxy of the environment would resolve the host itself: never used
        **{name: proxy for name in ("HTTP_PROXY", "HTTPS_PROXY", "ALL_PROXY", "http_proxy")},
    }
    service_ = RunningService(directory, PACKAGE, environment).start()
    yield service_
    service_.stop()


def subscribe(url: str, callback: str) -> tuple[int, dict]:
    status, _, body = request(
        "GET", f"{url}{STORE}/records", headers={"Upgrade": "callback", "Callback": callback}
    )
    return status, body


def post(url: str, count: int, robot: str) -> list[int]:
    records = [
        {"robot": robot, "timestamp": 1e6 + i, "data": {"lat": 1.0, "lon": 2.0}}
        for i in range(count)
    ]
    status, _, body = request("POST", f"{url}{STORE}/records/batch", {"records": records})
    assert status == 201, body
    return body["ids"]


def record_id(body: bytes) -> int:
    return int(json.loads(body)["id"])


@pytest.mark.parametrize("scheme", ["http", "https"])
def test_every_internal_spelling_is_refused_with_the_reason_and_nothing_is_posted(
    running, listeners, scheme: str
) -> None:
    catcher, allowed, _ = listeners
    spellings = SPELLINGS + hosts_file_names()
    assert len(spellings) >= 30
    refused = []
    for host, reason in spellings:
        callback = f"{scheme}://{host}:{catcher.port}/hook"
        status, body = subscribe(running.url, callback)
        assert status == 400, (callback, body)
        assert reason in body["detail"] and ALLOW in body["detail"], (callback, body)
        refused.append(callback)
    # the same address at a port the allow list does not name
    status, body = subscribe(running.url, f"{scheme}://127.0.0.1:{allowed.port + 1}/")
    assert status == 400 and LOOPBACK in body["detail"]

    # nothing of them was stored, and a record posted now reaches only the allowed one
    receiver = f"http://127.0.0.1:{allowed.port}/hook"
    status, subscription = subscribe(running.url, receiver)
    assert status == 201, subscription
    listed = request("GET", f"{running.url}{STORE}/subscriptions")[2]["items"]
    assert not {item["callback"] for item in listed} & set(refused)
    try:
        ids = post(running.url, 5, f"spelled-{scheme}")
        last = post(running.url, 1, f"spelled-{scheme}-end")
        # in id order, so once the last has come every earlier one has, exactly once
        arrived = [record_id(a.body) for a in allowed.take(6)]
        assert arrived == ids + last
        assert allowed.all() == [] and catcher.all() == []
    finally:
        assert request("DELETE", f"{running.url}{subscription['href']}")[0] == 204


def test_an_allowed_address_is_allowed_in_every_spelling_at_its_port(running, listeners) -> None:
    catcher, allowed, _ = listeners
    status, subscription = subscribe(running.url, f"http://2130706433:{allowed.port}/decimal")
    assert status == 201, subscription
    try:
        (record,) = post(running.url, 1, "decimal")
        (arrival,) = allowed.take(1)
        assert (arrival.method, arrival.path) == ("POST", "/decimal")
        assert arrival.host == f"2130706433:{allowed.port}"  # the host as written
        assert record_id(arrival.body) == record
    finally:
        assert request("DELETE", f"{running.url}{subscription['href']}")[0] == 204
    assert catcher.all() == []


def test_a_redirect_is_not_followed(running, listeners) -> None:
    catcher, _, redirector = listeners
    status, subscription = subscribe(running.url, f"http://127.0.0.1:{redirector.port}/hook")
    assert status == 201, subscription
    try:
        (record,) = post(running.url, 1, "redirected")
        # the 307 is a failed post, tried again after the first pause (0.1 s); a client
        # that followed it would have posted to the catcher in between
        first, again = redirector.take(2)
        assert record_id(first.body) == record_id(again.body) == record
        assert catcher.all() == []
    finally:
        assert request("DELETE", f"{running.url}{subscription['href']}")[0] == 204
    assert "callback http://127.0.0.1:" in running.log.read_text()
    assert "answered 307" in running.log.read_text()


def test_https_posts_check_the_certificate_against_the_host_not_the_address(
    directory: Path, tmp_path: Path
) -> None:
    """Posted to the checked address, an https callback still verifies the receiver's
    certificate against the host of its URI (SNI): a certificate of ``localhost`` passes
    for ``https://localhost``, and fails for ``https://127.0.0.1`` at the same port."""
    tls = certificate_for("localhost", tmp_path)
    receiver = Listener(tls=tls)
    environment = {
        "POSITION_STORE_TOKEN": TOKEN,
        "TRANSFORMER": "off",
        "DATABASE_URL": f"sqlite:///{tmp_path}/tls.db",
        "SSL_CERT_FILE": str(tls[0]),  # the site's own authority
        ALLOW: f"localhost:{receiver.port},127.0.0.1:{receiver.port}",
    }
    running = RunningService(directory, PACKAGE, environment).start()
    try:
        status, named = subscribe(running.url, f"https://localhost:{receiver.port}/named")
        assert status == 201, named
        status, addressed = subscribe(running.url, f"https://127.0.0.1:{receiver.port}/addressed")
        assert status == 201, addressed
        (record,) = post(running.url, 1, "tls")
        (arrival,) = receiver.take(1)
        assert (arrival.path, arrival.host) == ("/named", f"localhost:{receiver.port}")
        assert record_id(arrival.body) == record
        wait_for(lambda: "certificate verify failed" in running.log.read_text())
        assert receiver.all() == []  # never to /addressed
    finally:
        running.stop()
        receiver.close()


# The service with a resolver the test scripts: SCRIPTED_NAMES maps a name to the answers
# of its successive look-ups (the last one repeats; "a,b": both addresses at once), the
# look-ups of every other name go to the system. Each look-up is logged.
SCRIPTED_RESOLVER = """
import json, os, socket, sys, threading

sys.path.insert(0, os.getcwd())  # the service's folder, as for python -m
answers = json.loads(os.environ["SCRIPTED_NAMES"])
asked, lock, system = {}, threading.Lock(), socket.getaddrinfo


def scripted(host, port, family=0, type=0, proto=0, flags=0):
    name = host.decode() if isinstance(host, bytes) else host
    if name not in answers:
        return system(host, port, family, type, proto, flags)
    with lock:
        turn = asked[name] = asked.get(name, 0) + 1
    addresses = answers[name][min(turn, len(answers[name])) - 1]
    print(f"resolved {name} ({turn}) to {addresses}", file=sys.stderr, flush=True)
    return [(socket.AF_INET, socket.SOCK_STREAM, socket.IPPROTO_TCP, "", (a, int(port)))
            for a in addresses.split(",")]


socket.getaddrinfo = scripted
from position_store_service import __main__ as entry

entry.main()
"""


def test_a_name_rebound_to_loopback_after_subscribing_is_not_posted_to(
    directory: Path, tmp_path: Path, listeners
) -> None:
    catcher, _, _ = listeners
    pinned_at = Listener("127.0.0.1")  # where pinned.test resolves when checked
    elsewhere = Listener("127.0.0.2", pinned_at.port)  # where it resolves a moment later
    names = {
        "rebind.test": ["93.184.216.34", "127.0.0.1"],
        "half.test": ["93.184.216.34,10.0.0.7"],
        "pinned.test": ["127.0.0.1", "127.0.0.1", "127.0.0.2"],
    }
    (tmp_path / "scripted_resolver.py").write_text(SCRIPTED_RESOLVER, encoding="utf-8")
    environment = {
        "POSITION_STORE_TOKEN": TOKEN,
        "TRANSFORMER": "off",
        "DATABASE_URL": f"sqlite:///{tmp_path}/rebinding.db",
        "SCRIPTED_NAMES": json.dumps(names),
        ALLOW: "pinned.test",
    }
    scripted = RunningService(directory, PACKAGE, environment)
    scripted.command = [sys.executable, str(tmp_path / "scripted_resolver.py")]
    scripted.start()
    try:
        # a name with one internal address among public ones is refused
        status, body = subscribe(scripted.url, "http://half.test/hook")
        assert status == 400
        assert "half.test resolves to 10.0.0.7, a private address" in body["detail"]

        rebound = f"http://rebind.test:{catcher.port}/hook"
        status, subscription = subscribe(scripted.url, rebound)
        assert status == 201, subscription  # public when subscribed
        (record,) = post(scripted.url, 1, "rebound")
        wait_for(
            lambda: (
                f"not posted: Callback {rebound!r}: rebind.test resolves to 127.0.0.1, "
                f"{LOOPBACK}" in scripted.log.read_text()
            )
        )
        assert catcher.all() == []
        assert request("DELETE", f"{scripted.url}{subscription['href']}")[0] == 204

        # allowed, and posted to the address checked, not to the later answer
        status, subscription = subscribe(scripted.url, f"http://pinned.test:{pinned_at.port}/p")
        assert status == 201, subscription
        (record,) = post(scripted.url, 1, "pinned")
        (arrival,) = pinned_at.take(1)
        assert record_id(arrival.body) == record
        assert arrival.host == f"pinned.test:{pinned_at.port}"
        assert elsewhere.all() == [] and catcher.all() == []
        log = scripted.log.read_text()
        assert "resolved pinned.test (2) to 127.0.0.1" in log
        assert "resolved pinned.test (3)" not in log  # the client did not look it up again
    finally:
        scripted.stop()
        pinned_at.close()
        elsewhere.close()


@pytest.mark.parametrize("entry", ["hooks:port", "hooks:0", "hooks:65536", "[::1", "[::1]x", ":80"])
def test_a_malformed_allow_list_stops_the_service_with_a_message(
    directory: Path, entry: str
) -> None:
    environment = {"POSITION_STORE_TOKEN": TOKEN, ALLOW: f"127.0.0.1:8080, {entry}"}
    with pytest.raises(RuntimeError) as stopped:
        RunningService(directory, PACKAGE, environment).start()
    assert f"{ALLOW}: {entry!r} is no host, host:port, [address] or [address]:port" in str(
        stopped.value
    )
    assert "Traceback" not in str(stopped.value)
