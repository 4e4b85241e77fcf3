"""Where a callback subscription of a store may post (docs/services.md, "Where
callbacks may go").

A callback makes the service send requests to a URI a client chose, from inside the
cluster: without a check, a client could make it post into the pod network, to the
service's own database or to the cloud's metadata address (169.254.169.254), a
server-side request forgery. So a callback must name a public host: every address its
host is, or resolves to, must be globally routable. Loopback, link-local, private,
multicast, reserved, unspecified and other non-global addresses are refused in every
spelling the resolver takes (``127.1``, ``2130706433``, ``0x7f000001``, ``0177.0.0.1``,
``[::ffff:127.0.0.1]``, a trailing dot, names that resolve to them), unless
the store's allow list (``<STORE>_CALLBACK_HOSTS``: ``host`` or ``host:port``, comma-separated)
names the host: a site's own receiver may be internal.

The check runs when the subscription is made (400 with the reason) and again before
every post: the name is resolved once, every address checked, and the post connects to
a checked address (the original host in the Host header and, for https, in SNI and
certificate checks), so a name that resolves to a public address when checked and to
an internal one a moment later (DNS rebinding) is never posted to.
"""

from __future__ import annotations

import ipaddress
import os
import re
import socket
import ssl
import urllib.parse
from dataclasses import dataclass

Address = ipaddress.IPv4Address | ipaddress.IPv6Address
MAX_URI = 2000
# what a host name may hold (lower case); anything else is no name a resolver takes alike
NAME = re.compile(r"[a-z0-9_](?:[a-z0-9_.-]*[a-z0-9_])?\.?\Z")
# IPv6 ranges that carry an IPv4 address in their last 32 bits and reach it: NAT64's
# well-known prefix (RFC 6052) and the deprecated IPv4-compatible addresses
CARRIERS = (ipaddress.ip_network("64:ff9b::/96"), ipaddress.ip_network("::/96"))
LOCAL_NAT64 = ipaddress.ip_network("64:ff9b:1::/48")  # RFC 8215: a site's own translator
DEFAULT_PORTS = {"http": 80, "https": 443}


@dataclass(frozen=True)
class AllowList:
    """The internal hosts a site lets callbacks post to: (host, port or None for any
    port), read from the environment variable ``variable`` (named in refusals)."""

    variable: str
    hosts: frozenset[tuple[str, int | None]]


def allow_list(variable: str, value: str | None) -> AllowList:
    """``host``, ``host:port``, ``[v6]`` or ``[v6]:port`` entries, comma-separated; a
    malformed entry stops the service with a message naming the variable."""
    entries = set()
    for entry in (value or "").split(","):
        entry = entry.strip().lower()
        if not entry:
            continue
        if entry.startswith("["):  # [v6] or [v6]:port
            host, bracket, rest = entry[1:].partition("]")
            colon, port = rest[:1], rest[1:]
            if not bracket or rest[:1] not in ("", ":"):
                host = ""
        elif entry.count(":") == 1:
            host, colon, port = entry.partition(":")
        else:  # a name, an IPv4 address or a bare IPv6 address
            host, colon, port = entry, "", ""
        number = port.isascii() and port.isdigit() and 0 < int(port) < 65536
        if not host or (colon and not number):
            raise SystemExit(
                f"{variable}: {entry!r} is no host, host:port, "
                "[address] or [address]:port (a port from 1 to 65535)"
            )
        entries.add((host, int(port) if colon else None))
    return AllowList(variable, frozenset(entries))


class CallbackRefused(ValueError):
    """A callback URI the service does not post to, with the reason (400)."""


@dataclass(frozen=True)
class Callback:
    """A callback URI taken apart once, as the service will use it."""

    uri: str
    scheme: str
    host: str  # lower case, without brackets
    port: int
    netloc: str  # the Host header: the host and port as written
    target: str  # the path and query posted to

    def url(self, address: str) -> str:
        """The URL that reaches this callback at ``address`` (one it resolved to)."""
        # an IPv6 address in brackets, its zone (fe80::1%eth0) written %25 in a URL
        literal = f"[{address.replace('%', '%25')}]" if ":" in address else address
        return f"{self.scheme}://{literal}:{self.port}{self.target}"

    @property
    def server_name(self) -> str | None:
        """The name a TLS certificate must hold (None: the host is an address)."""
        return None if literal(self.host) is not None else self.host.rstrip(".")


@dataclass(frozen=True)
class Destination:
    """One checked address to post a callback to."""

    url: str
    host_header: str
    server_name: str | None


def literal(host: str) -> Address | None:
    """The address ``host`` spells, as the resolver reads it (None: a name). Besides
    the standard forms, the resolver takes the inet_aton forms: ``127.1``,
    ``2130706433``, ``0x7f000001``, ``0177.0.0.1``; a trailing dot is dropped, as
    browsers and resolvers do."""
    text = host[:-1] if host.endswith(".") else host
    try:
        return ipaddress.ip_address(text)
    except ValueError:
        pass
    if not re.fullmatch(r"[0-9a-fx.]+", text):
        return None
    try:
        return ipaddress.IPv4Address(socket.inet_aton(text))
    except OSError:
        return None


def _embedded(address: ipaddress.IPv6Address) -> list[ipaddress.IPv4Address]:
    """The IPv4 addresses an IPv6 address reaches through (6to4, Teredo, NAT64)."""
    found = []
    if address.sixtofour is not None:
        found.append(address.sixtofour)
    if address.teredo is not None:
        found.extend(address.teredo)
    if any(address in carrier for carrier in CARRIERS) and int(address) > 1:
        found.append(ipaddress.IPv4Address(int(address) & 0xFFFFFFFF))
    return found


def refusal(address: Address) -> str | None:
    """Why the service does not post to ``address`` (None: a public address)."""
    if isinstance(address, ipaddress.IPv6Address):
        if address.ipv4_mapped is not None:  # ::ffff:a.b.c.d is a.b.c.d
            return refusal(address.ipv4_mapped)
        for inner in _embedded(address):
            reason = refusal(inner)
            if reason is not None:
                return f"{reason} (through {inner})"
        if address in LOCAL_NAT64:
            return "a private address (a site's own NAT64 translator)"
    if address.is_loopback:
        return "a loopback address"
    if address.is_unspecified:
        return "the unspecified address (this machine)"
    if address.is_link_local:
        return "a link-local address (where cloud metadata services answer)"
    if address.is_multicast:
        return "a multicast address"
    if address.is_reserved:
        return "a reserved address"
    if address.is_private:
        return "a private address"
    if not address.is_global:
        return "an address that is not globally routable"
    return None


def parse(uri: str | None) -> Callback:
    """The callback URI of a ``Callback`` header, taken apart (CallbackRefused: why not)."""
    if not uri:
        raise CallbackRefused(
            "Upgrade: callback needs a Callback header with the URI to post new records to"
        )
    uri = uri.strip()
    if any(c.isspace() or ord(c) < 0x21 or ord(c) == 0x7F for c in uri) or len(uri) > MAX_URI:
        raise CallbackRefused(
            f"Callback {uri[:100]!r}: spaces, control characters or more than {MAX_URI} characters"
        )
    try:
        parts = urllib.parse.urlsplit(uri)
        port = parts.port  # a port that is no number, or out of range, raises here
    except ValueError as exc:
        raise CallbackRefused(f"Callback {uri!r} is not a URI: {exc}") from None
    if parts.scheme not in DEFAULT_PORTS or not parts.hostname:
        raise CallbackRefused(
            f"Callback {uri!r}: only http and https URIs with a host are called back"
        )
    if "@" in parts.netloc or "\\" in uri:
        raise CallbackRefused(
            f"Callback {uri!r}: user information and backslashes are "
            "refused (put a secret of the receiver in its path)"
        )
    host = parts.hostname
    bracketed = parts.netloc.startswith("[")
    if (bracketed and not isinstance(literal(host), ipaddress.IPv6Address)) or (
        not bracketed and not NAME.match(host)
    ):
        raise CallbackRefused(
            f"Callback {uri!r}: {host!r} is no host name or address "
            "(an internationalised name is written in its xn-- form)"
        )
    if port == 0:
        raise CallbackRefused(f"Callback {uri!r}: port 0 is no port")
    target = (parts.path or "/") + (f"?{parts.query}" if parts.query else "")
    return Callback(
        uri, parts.scheme, host, port or DEFAULT_PORTS[parts.scheme], parts.netloc, target
    )


def _canonical(host: str) -> str:
    found = literal(host)
    return str(found) if found is not None else host.lower().removesuffix(".")


def allowed(callback: Callback, allow: AllowList) -> bool:
    """Whether the site lists the callback's host (any port, or its port)."""
    host = _canonical(callback.host)
    return any(
        _canonical(name) == host and port in (None, callback.port) for name, port in allow.hosts
    )


def addresses(callback: Callback) -> list[str]:
    """The addresses the callback's host is or resolves to, each once, in the order
    the resolver gives them."""
    found = literal(callback.host)
    if found is not None:
        return [str(found)]
    try:
        answers = socket.getaddrinfo(
            callback.host, callback.port, type=socket.SOCK_STREAM, proto=socket.IPPROTO_TCP
        )
    except (OSError, UnicodeError) as exc:
        raise CallbackRefused(
            f"Callback {callback.uri!r}: {callback.host} does not resolve ({exc})"
        ) from None
    return list(dict.fromkeys(str(answer[4][0]) for answer in answers))


def destinations(uri: str | None, allow: AllowList) -> tuple[Callback, list[Destination]]:
    """The callback and the checked addresses to post to, in order; CallbackRefused with
    the reason when its host is internal and not listed. Run when a subscription is
    made and before every post: it resolves the name (blocking, in a thread)."""
    callback = parse(uri)
    host = callback.host.removesuffix(".")
    listed = allowed(callback, allow)
    if not listed and (host == "localhost" or host.endswith(".localhost")):
        raise CallbackRefused(_refused(callback, allow, f"{callback.host} is a loopback name"))
    found = addresses(callback)
    if not listed:
        for address in found:
            reason = refusal(ipaddress.ip_address(address.partition("%")[0]))
            if reason is not None:
                raise CallbackRefused(
                    _refused(callback, allow, f"{_spelled(callback, address)}, {reason}")
                )
    return callback, [
        Destination(callback.url(address), callback.netloc, callback.server_name)
        for address in found
    ]


def _spelled(callback: Callback, address: str) -> str:
    found = literal(callback.host)
    if found is None:
        return f"{callback.host} resolves to {address}"
    if isinstance(found, ipaddress.IPv6Address) and found.ipv4_mapped is not None:
        address = str(found.ipv4_mapped)  # what it reaches, rather than ::ffff:7f00:1
    return address if callback.host == address else f"{callback.host} is {address}"


def authorities() -> ssl.SSLContext | bool:
    """What an https callback's certificate is checked against: the files SSL_CERT_FILE
    or SSL_CERT_DIR name when set (a site's own authority), else httpx's default. Read
    here because the delivery client takes nothing else from the environment."""
    cafile, capath = os.environ.get("SSL_CERT_FILE"), os.environ.get("SSL_CERT_DIR")
    if cafile or capath:
        return ssl.create_default_context(cafile=cafile or None, capath=capath or None)
    return True


def _refused(callback: Callback, allow: AllowList, why: str) -> str:
    return (
        f"Callback {callback.uri!r}: {why}; the service posts only to public "
        f"addresses, or to hosts {allow.variable} lists"
    )
