"""The runtime's refusal of callbacks to internal addresses, imported directly
(docs/services.md, "Where callbacks may go"): every spelling of an internal address is
refused with the reason, the allow list lets a listed host (and port) through, and a
malformed allow list stops the service naming its variable. The live test
(tests/live/test_service_callback_targets.py) shows the same through a running service."""

from __future__ import annotations

import ipaddress

import pytest

from spl.generators.service.runtime.callback_targets import (
    AllowList,
    CallbackRefused,
    allow_list,
    destinations,
    parse,
    refusal,
)

VARIABLE = "SHOP_STORE_CALLBACK_HOSTS"
NOTHING = AllowList(VARIABLE, frozenset())


@pytest.mark.parametrize(
    ("address", "reason"),
    [
        ("127.0.0.1", "a loopback address"),
        ("::1", "a loopback address"),
        ("0.0.0.0", "the unspecified address (this machine)"),
        ("169.254.169.254", "a link-local address (where cloud metadata services answer)"),
        ("fe80::1", "a link-local address (where cloud metadata services answer)"),
        ("10.1.2.3", "a private address"),
        ("192.168.0.1", "a private address"),
        ("fd00::1", "a private address"),
        ("224.0.0.1", "a multicast address"),
        ("240.0.0.1", "a reserved address"),
        ("100.64.0.1", "an address that is not globally routable"),
        ("::ffff:127.0.0.1", "a loopback address"),
        ("64:ff9b::a00:1", "a private address (through 10.0.0.1)"),
        ("2002:7f00:1::", "a loopback address (through 127.0.0.1)"),
        ("64:ff9b:1::1", "a private address (a site's own NAT64 translator)"),
        ("93.184.216.34", None),
        ("2606:4700::1111", None),
    ],
)
def test_each_internal_address_is_refused_with_its_reason(address: str, reason: str) -> None:
    assert refusal(ipaddress.ip_address(address)) == reason


@pytest.mark.parametrize(
    ("host", "said"),
    [
        ("127.1", "127.1 is 127.0.0.1, a loopback address"),
        ("2130706433", "2130706433 is 127.0.0.1, a loopback address"),
        ("0x7f000001", "0x7f000001 is 127.0.0.1, a loopback address"),
        ("0177.0.0.1", "0177.0.0.1 is 127.0.0.1, a loopback address"),
        ("[::ffff:127.0.0.1]", "::ffff:127.0.0.1 is 127.0.0.1, a loopback address"),
        ("127.0.0.1.", "127.0.0.1. is 127.0.0.1, a loopback address"),
        ("localhost", "localhost is a loopback name"),
        ("api.LOCALHOST", "api.localhost is a loopback name"),
    ],
)
def test_every_spelling_of_an_internal_host_is_refused(host: str, said: str) -> None:
    with pytest.raises(CallbackRefused) as refused:
        destinations(f"http://{host}:9/hook", NOTHING)
    assert said in str(refused.value)
    assert f"or to hosts {VARIABLE} lists" in str(refused.value)


def test_a_public_address_is_posted_to_as_checked() -> None:
    callback, found = destinations("https://93.184.216.34/hook?x=1", NOTHING)
    assert (callback.scheme, callback.port, callback.target) == ("https", 443, "/hook?x=1")
    [target] = found
    assert target.url == "https://93.184.216.34:443/hook?x=1"
    assert (target.host_header, target.server_name) == ("93.184.216.34", None)


def test_the_allow_list_admits_a_listed_host_at_its_port_only() -> None:
    listed = allow_list(VARIABLE, " 127.0.0.1:8080 , [::1] ,")
    assert listed.hosts == frozenset({("127.0.0.1", 8080), ("::1", None)})
    _, [target] = destinations("http://127.0.0.1:8080/in", listed)
    assert target.url == "http://127.0.0.1:8080/in"
    _, [target] = destinations("http://[::1]:9/in", listed)
    assert target.url == "http://[::1]:9/in"
    with pytest.raises(CallbackRefused, match="a loopback address"):
        destinations("http://127.0.0.1:8081/in", listed)
    # the listed address in another spelling is the same host
    _, [target] = destinations("http://127.1:8080/in", listed)
    assert target.url == "http://127.0.0.1:8080/in"


@pytest.mark.parametrize("entry", ["host:0", "host:65536", "host:http", "[::1", "[::1]x", ":80"])
def test_a_malformed_allow_list_stops_the_service_naming_its_variable(entry: str) -> None:
    with pytest.raises(SystemExit) as stopped:
        allow_list(VARIABLE, f"ok.example, {entry}")
    assert str(stopped.value).startswith(f"{VARIABLE}: {entry!r} is no host")


@pytest.mark.parametrize(
    ("uri", "reason"),
    [
        (None, "needs a Callback header"),
        ("ftp://example.org/x", "only http and https URIs"),
        ("http://user:pw@example.org/x", "user information and backslashes are refused"),
        ("http://example.org\\@evil/x", "user information and backslashes are refused"),
        ("http://example.org:0/x", "port 0 is no port"),
        ("http://exa mple.org/x", "spaces, control characters"),
        ("http://bücher.example/x", "is no host name or address"),
        ("http://example.org:99999/x", "is not a URI"),
    ],
)
def test_a_callback_that_is_no_usable_uri_is_refused(uri: str | None, reason: str) -> None:
    with pytest.raises(CallbackRefused, match=reason):
        parse(uri)
