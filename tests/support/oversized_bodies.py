"""Requests whose body is larger than a server takes, sent on a raw socket so that the
test decides how much of the body ever leaves: one that announces its length
(``Content-Length``) and sends none of it, and one sent chunked without a length that
stops after a given number of bytes, never ending the body. Either gets its answer
only if the server answers without waiting for the rest; ``closed`` then says whether
the server also closed the connection rather than reading on."""

from __future__ import annotations

import http.client
import json
import socket
from dataclasses import dataclass
from typing import Any

WAIT = 30.0  # seconds for an answer: the server is refusing, not working


@dataclass
class Refusal:
    status: int
    headers: dict[str, str]
    body: Any  # parsed JSON
    closed: bool  # the server ended the connection after its answer


def _head(method: str, path: str, host: str, headers: dict[str, str]) -> bytes:
    lines = [f"{method} {path} HTTP/1.1", f"Host: {host}"]
    lines += [f"{name}: {value}" for name, value in headers.items()]
    return ("\r\n".join(lines) + "\r\n\r\n").encode()


def _answer(connection: socket.socket) -> Refusal:
    response = http.client.HTTPResponse(connection)
    response.begin()
    content = response.read()
    headers = {k.lower(): v for k, v in response.getheaders()}
    try:
        closed = connection.recv(1) == b""
    except ConnectionResetError:
        closed = True
    return Refusal(response.status, headers, json.loads(content) if content else None, closed)


def announced(
    port: int, path: str, length: int, headers: dict[str, str], method: str = "POST"
) -> Refusal:
    """The answer to a request announcing ``length`` bytes of body and sending none."""
    with socket.create_connection(("127.0.0.1", port), timeout=WAIT) as connection:
        connection.sendall(
            _head(method, path, f"127.0.0.1:{port}", {**headers, "Content-Length": str(length)})
        )
        return _answer(connection)


def chunked(port: int, path: str, size: int, headers: dict[str, str], chunk: int = 4096) -> Refusal:
    """The answer to a chunked body of which ``size`` bytes (JSON-looking spaces after
    an opening brace) are sent and whose last chunk never is."""
    with socket.create_connection(("127.0.0.1", port), timeout=WAIT) as connection:
        connection.sendall(
            _head("POST", path, f"127.0.0.1:{port}", {**headers, "Transfer-Encoding": "chunked"})
        )
        sent, data = 0, b"{" + b" " * (size - 1)
        try:
            while sent < size:
                part = data[sent : sent + chunk]
                connection.sendall(f"{len(part):x}\r\n".encode() + part + b"\r\n")
                sent += len(part)
        except (BrokenPipeError, ConnectionResetError):
            pass  # the server answered and closed while the body was still coming
        return _answer(connection)
