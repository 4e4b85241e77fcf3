"""Subscribers for the service tests: a WebSocket client (the real ``websockets``
library) and an HTTP callback receiver in the test process."""

from __future__ import annotations

import json
import queue
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

import websockets
from websockets.sync.client import connect


def websocket_url(http_url: str, path: str, **query: Any) -> str:
    url = http_url.replace("http", "ws", 1) + path
    if query:
        url += "?" + "&".join(f"{k}={v}" for k, v in query.items())
    return url


class Frames:
    """A WebSocket subscription read in a thread: ``frames`` holds (arrival time, text)."""

    def __init__(self, url: str, headers: dict[str, str] | None = None, **options: Any) -> None:
        # entered here, left in close(): the connection outlives this constructor
        self.connection = connect(
            url, additional_headers=headers or {}, open_timeout=10, **options
        ).__enter__()
        self.frames: queue.Queue[tuple[float, str]] = queue.Queue()
        self.closed = threading.Event()
        self.thread = threading.Thread(target=self._read, daemon=True)
        self.thread.start()

    def _read(self) -> None:
        try:
            for message in self.connection:
                self.frames.put((time.perf_counter(), message))
        except websockets.ConnectionClosed:
            pass
        finally:
            self.closed.set()

    def take(self, count: int, timeout: float = 20.0) -> list[tuple[float, str]]:
        deadline = time.monotonic() + timeout
        taken = []
        while len(taken) < count:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise AssertionError(f"{len(taken)} of {count} frames within {timeout} s")
            try:
                taken.append(self.frames.get(timeout=remaining))
            except queue.Empty:
                continue
        return taken

    def json(self, count: int, timeout: float = 20.0) -> list[dict]:
        return [json.loads(text) for _, text in self.take(count, timeout)]

    def nothing_more(self, wait: float = 0.3) -> bool:
        time.sleep(wait)
        return self.frames.empty()

    def close(self) -> None:
        self.connection.close()
        self.thread.join(5)


class Receiver:
    """An HTTP server on 127.0.0.1 taking the callbacks: ``received`` holds (time,
    content type, body); ``answers`` (status codes) are given first, then 204."""

    def __init__(self, answers: list[int] | None = None) -> None:
        self.received: queue.Queue[tuple[float, str, bytes]] = queue.Queue()
        self.attempts: list[tuple[float, int]] = []
        self.answers = list(answers or [])
        lock = threading.Lock()
        outer = self

        class Handler(BaseHTTPRequestHandler):
            def do_POST(self) -> None:
                body = self.rfile.read(int(self.headers.get("content-length", 0)))
                with lock:
                    status = outer.answers.pop(0) if outer.answers else 204
                    outer.attempts.append((time.monotonic(), status))
                if status == 204:
                    outer.received.put((time.perf_counter(), self.headers["content-type"], body))
                self.send_response(status)
                self.send_header("Content-Length", "0")
                self.end_headers()

            def log_message(self, *_args: Any) -> None:
                pass

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.server.server_port}/hook"

    def take(self, count: int, timeout: float = 20.0) -> list[tuple[float, str, bytes]]:
        deadline = time.monotonic() + timeout
        taken = []
        while len(taken) < count:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise AssertionError(f"{len(taken)} of {count} callbacks within {timeout} s")
            try:
                taken.append(self.received.get(timeout=remaining))
            except queue.Empty:
                continue
        return taken

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()
