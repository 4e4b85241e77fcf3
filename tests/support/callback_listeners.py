"""HTTP listeners for the callback security tests: each records every request that
reaches it (method, path, Host header, body) and answers with a fixed status, and a
``Location`` when given one (a redirect). Bound to any address and port, including
``::`` for both IPv4 and IPv6, so that one listener catches a post to any address of
this machine: 127.0.0.1, 127.0.0.2, ::1, 0.0.0.0 and the machine's own addresses; with
a certificate of a name (``support.tls.certificate_for``), over HTTPS."""

from __future__ import annotations

import queue
import socket
import ssl
import threading
from dataclasses import dataclass
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class Arrival:
    method: str
    path: str
    host: str
    body: bytes


class _DualStack(ThreadingHTTPServer):
    address_family = socket.AF_INET6

    def server_bind(self) -> None:
        self.socket.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 0)
        super().server_bind()


class Listener:
    """An HTTP server on ``address``:``port`` (``port`` 0: a free one) answering every
    request with ``status`` (and ``Location: location`` when given); HTTPS with the
    certificate and key files ``tls`` names."""

    def __init__(
        self,
        address: str = "127.0.0.1",
        port: int = 0,
        status: int = 204,
        location: str = "",
        tls: tuple[Path, Path] | None = None,
    ) -> None:
        self.arrivals: queue.Queue[Arrival] = queue.Queue()
        outer = self

        class Handler(BaseHTTPRequestHandler):
            def _any(self) -> None:
                length = int(self.headers.get("content-length") or 0)
                body = self.rfile.read(length)
                outer.arrivals.put(
                    Arrival(self.command, self.path, self.headers.get("host", ""), body)
                )
                self.send_response(status)
                if location:
                    self.send_header("Location", location)
                self.send_header("Content-Length", "0")
                self.end_headers()

            do_GET = do_POST = do_PUT = do_DELETE = do_HEAD = _any

            def log_message(self, *_args: Any) -> None:
                pass

        server_class = _DualStack if address == "::" else ThreadingHTTPServer
        self.server = server_class((address, port), Handler)
        if tls is not None:
            context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
            context.load_cert_chain(*tls)
            self.server.socket = context.wrap_socket(self.server.socket, server_side=True)
        self.port = self.server.server_address[1]
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    def take(self, count: int, timeout: float = 20.0) -> list[Arrival]:
        taken = []
        for _ in range(count):
            try:
                taken.append(self.arrivals.get(timeout=timeout))
            except queue.Empty:
                raise AssertionError(
                    f"{len(taken)} of {count} requests within {timeout} s"
                ) from None
        return taken

    def all(self) -> list[Arrival]:
        """What arrived so far (taken out)."""
        found = []
        while not self.arrivals.empty():
            found.append(self.arrivals.get_nowait())
        return found

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()
