"""Running generated data-acquisition services for real in tests: write the generated
files, start the service with uvicorn on a free port of 127.0.0.1, import a generated
client's HTTP module, and a throw-away PostgreSQL cluster from Debian's binaries."""

from __future__ import annotations

import http.client
import importlib.util
import json
import os
import shutil
import signal
import socket
import ssl
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path
from types import ModuleType
from typing import Any

TOKEN = "test-token-not-a-secret"


def write_files(files: dict[str, bytes], root: Path) -> Path:
    for relative, data in files.items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    return root


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class RunningService:
    """One generated service process; ``kill()`` is kill -9, ``start()`` starts it again.
    With an SSL ``context`` it is reached by HTTPS (the service's TLS variables set);
    setting ``command`` starts it otherwise than ``python -m PACKAGE``."""

    def __init__(
        self,
        directory: Path,
        package: str,
        env: dict[str, str],
        context: ssl.SSLContext | None = None,
    ) -> None:
        self.directory = directory
        self.command = [sys.executable, "-m", package]  # what start() runs
        self.context = context
        self.package = package
        self.port = free_port()
        self.env = {**os.environ, "HOST": "127.0.0.1", "PORT": str(self.port), **env}
        self.process: subprocess.Popen | None = None
        self.log = directory / "service.log"

    @property
    def url(self) -> str:
        scheme = "https" if self.context is not None else "http"
        return f"{scheme}://127.0.0.1:{self.port}"

    def start(self) -> RunningService:
        log = self.log.open("ab")
        self.process = subprocess.Popen(
            self.command,
            cwd=self.directory,
            env=self.env,
            stdout=log,
            stderr=subprocess.STDOUT,
        )
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise RuntimeError(f"service exited: {self.log.read_text()[-3000:]}")
            try:
                with urllib.request.urlopen(self.url + "/", timeout=1, context=self.context):
                    return self
            except urllib.error.HTTPError:  # it answers (reads may need the token)
                return self
            except (urllib.error.URLError, OSError):
                time.sleep(0.05)
        raise RuntimeError(f"service did not start: {self.log.read_text()[-3000:]}")

    def kill(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.send_signal(signal.SIGKILL)
            self.process.wait()

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.kill()


def request(
    method: str,
    url: str,
    body: Any = None,
    token: str | None = TOKEN,
    headers: dict[str, str] | None = None,
    raw: bytes | None = None,
) -> tuple[int, dict[str, str], Any]:
    """(status, headers lower-cased, parsed JSON body or None) without raising on 4xx/5xx.
    Asks for JSON (``Accept: application/json``) as the generated clients do, unless
    ``headers`` name another Accept."""
    all_headers = {"Accept": "application/json", **(headers or {})}
    data = raw
    if body is not None:
        data = json.dumps(body).encode()
    if data is not None:
        all_headers.setdefault("Content-Type", "application/json")
    if token:
        all_headers["Authorization"] = f"Bearer {token}"
    req = urllib.request.Request(url, data=data, method=method, headers=all_headers)
    try:
        with urllib.request.urlopen(req, timeout=30) as response:
            status, head, content = response.status, response.headers, response.read()
    except urllib.error.HTTPError as error:
        status, head, content = error.code, error.headers, error.read()
    parsed = json.loads(content) if content else None
    return status, {k.lower(): v for k, v in head.items()}, parsed


def load_module(path: Path, name: str) -> ModuleType:
    """The module at ``path`` under ``name``; a module of a package (a client's
    store_client.py imports its runtime/ relatively) is loaded inside its package, which
    gets the name ``name`` + ``_package``, so that two bundles' packages never meet."""
    if (path.parent / "__init__.py").is_file():
        package = f"{name}_package"
        spec = importlib.util.spec_from_file_location(
            package, path.parent / "__init__.py", submodule_search_locations=[str(path.parent)]
        )
        sys.modules[package] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[package])
        name = f"{package}.{path.stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def wait_for(condition, timeout: float = 20.0, interval: float = 0.05) -> Any:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"condition not met within {timeout} s (last: {value!r})")
        time.sleep(interval)


def postgres_binaries() -> Path | None:
    candidates = sorted(Path("/usr/lib/postgresql").glob("*/bin/initdb"))
    return candidates[-1].parent if candidates else None


class PostgresCluster:
    """A temporary PostgreSQL server (initdb + postgres) on a free port, trust auth.

    PostgreSQL refuses to run as root; as root the cluster runs as ``nobody``.
    """

    def __init__(self, bin_dir: Path, base: Path) -> None:
        self.bin = bin_dir
        self.base = base
        self.data = base / "pgdata"
        self.port = free_port()
        self.process: subprocess.Popen | None = None
        self.prefix: list[str] = []
        if os.geteuid() == 0:
            self.prefix = ["runuser", "-u", "nobody", "--"]

    def _owned(self) -> None:
        if self.prefix:
            shutil.chown(self.base, "nobody")

    def start(self) -> PostgresCluster:
        self._owned()
        subprocess.run(
            [
                *self.prefix,
                str(self.bin / "initdb"),
                "-D",
                str(self.data),
                "-U",
                "spl",
                "--auth=trust",
                "--no-sync",
                "-E",
                "UTF8",
            ],
            check=True,
            capture_output=True,
        )
        self.process = subprocess.Popen(
            [
                *self.prefix,
                str(self.bin / "postgres"),
                "-D",
                str(self.data),
                "-p",
                str(self.port),
                "-h",
                "127.0.0.1",
                "-k",
                str(self.base),
                "-c",
                "fsync=off",
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        import psycopg

        def ready() -> bool:
            try:
                psycopg.connect(self.dsn("postgres"), connect_timeout=1).close()
                return True
            except psycopg.OperationalError:
                return False

        wait_for(ready, timeout=30, interval=0.1)
        with psycopg.connect(self.dsn("postgres"), autocommit=True) as conn:
            conn.execute("CREATE DATABASE spl")
        return self

    def dsn(self, database: str = "spl") -> str:
        return f"postgresql://spl@127.0.0.1:{self.port}/{database}"

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()  # runuser forwards SIGTERM: smart shutdown
            try:
                self.process.wait(15)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()


def post_in_batches(url: str, records: list[dict], size: int = 1000) -> None:
    for start in range(0, len(records), size):
        status, _, body = request("POST", url, {"records": records[start : start + size]})
        assert status == 201, body


def crash_during_transformation(
    running: RunningService,
    count_refined,
    total: int,  # type: ignore[no-untyped-def]
    kills: int = 2,
) -> None:
    """kill -9 the service while its transformer is part-way, ``kills`` times, restart
    it each time, and let it finish; ``count_refined()`` reads the database directly."""
    for _ in range(kills):
        before = count_refined()
        running.start()
        wait_for(lambda before=before: count_refined() > before, timeout=30, interval=0.002)
        running.kill()
        assert count_refined() < total, "transformation finished before the kill"
    running.start()
    wait_for(lambda: count_refined() == total, timeout=60, interval=0.05)


def post_concurrently(
    base: str,
    writers: int = 8,
    per_writer: int = 40,
    prefix: str = "w",
    answered: dict[int, dict] | None = None,
) -> dict[int, dict]:
    """``writers`` threads post at once to ``base`` (``.../<Store>``), each the position
    records of its own robot (``<prefix><n>``): singles, and every fifth post a batch of
    three. Returns (and fills ``answered`` as the answers come) each record by the id
    its 201 answer gave. A writer stops at its first connection error: the service was
    killed. Any answer but 201 fails the caller."""
    answered = {} if answered is None else answered
    refused: list[Any] = []
    lock = threading.Lock()

    def write(n: int) -> None:
        for i in range(per_writer):
            records = [
                {
                    "robot": f"{prefix}{n}",
                    "timestamp": 1e6 + i * 10 + j,
                    "data": {"lat": float(n * 100000 + i * 10 + j), "lon": -1.5},
                }
                for j in range(3 if i % 5 == 4 else 1)
            ]
            try:
                if len(records) == 1:
                    status, _, body = request("POST", f"{base}/records", records[0])
                    ids = [body["id"]] if status == 201 else []
                else:
                    status, _, body = request("POST", f"{base}/records/batch", {"records": records})
                    ids = body["ids"] if status == 201 else []
            except (OSError, http.client.HTTPException):
                return
            with lock:
                if status != 201:
                    refused.append((status, body))
                    return
                answered.update(zip(ids, records, strict=True))

    threads = [threading.Thread(target=write, args=(n,)) for n in range(writers)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not refused, refused[:3]
    return answered
