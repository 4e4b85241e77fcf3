"""HTTPS (R0.2 of the Linked Data requirements, docs/services.md): the generated
service serves TLS when its two environment
variables name a certificate and a key file, here a self-signed certificate made in the
test with ``cryptography``; reads, writes and WebSocket subscriptions (wss) go through
it, and a plain HTTP request to it is no answer at all."""

from __future__ import annotations

import http.client
import json
import ssl
from pathlib import Path

import pytest

from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import TOKEN, RunningService, write_files
from support.subscription_clients import Frames
from support.tls import self_signed


class HttpsService(RunningService):
    """Started and probed over HTTPS, trusting only the test's certificate."""

    def call(self, method: str, path: str, body: dict | None = None) -> tuple[int, dict]:
        connection = http.client.HTTPSConnection(
            "127.0.0.1", self.port, timeout=10, context=self.context
        )
        headers = {
            "Authorization": f"Bearer {TOKEN}",
            "Accept": "application/json",
            "Content-Type": "application/json",
        }
        connection.request(method, path, json.dumps(body) if body else None, headers)
        answer = connection.getresponse()
        result = answer.status, json.loads(answer.read() or b"null")
        connection.close()
        return result


def test_the_service_serves_https_with_the_named_certificate(tmp_path: Path) -> None:
    root = write_files(service.generate(product()), tmp_path / "bundle")
    cert_file, key_file = self_signed(tmp_path)
    context = ssl.create_default_context(cafile=str(cert_file))
    env = {
        "POSITION_STORE_TOKEN": TOKEN,
        "POSITION_STORE_TLS_CERT": str(cert_file),
        "POSITION_STORE_TLS_KEY": str(key_file),
        "POSITION_STORE_TRANSFORM_PERIOD": "0.05",
    }
    running = HttpsService(
        root / "services" / "PositionStore", "position_store_service", env, context=context
    )
    running.start()
    try:
        frames = Frames(
            f"wss://127.0.0.1:{running.port}/PositionStore/records",
            {"Accept": "application/json"},
            ssl=context,
        )
        status, created = running.call(
            "POST",
            "/PositionStore/records",
            {"robot": "secure", "timestamp": 5.0, "data": {"lat": 3600.0, "lon": 0.0}},
        )
        assert status == 201
        assert running.call("GET", created["href"]) == (200, frames.json(1)[0])
        frames.close()
        plain = http.client.HTTPConnection("127.0.0.1", running.port, timeout=5)
        with pytest.raises((http.client.HTTPException, ConnectionError)):
            plain.request("GET", "/")
            plain.getresponse()
        plain.close()
        untrusted = http.client.HTTPSConnection(
            "127.0.0.1", running.port, timeout=5, context=ssl.create_default_context()
        )
        with pytest.raises(ssl.SSLError):
            untrusted.request("GET", "/")
        untrusted.close()
    finally:
        running.stop()


def test_a_certificate_without_its_key_is_refused(tmp_path: Path) -> None:
    root = write_files(service.generate(product()), tmp_path / "bundle")
    cert_file, _ = self_signed(tmp_path)
    env = {"POSITION_STORE_TOKEN": TOKEN, "POSITION_STORE_TLS_CERT": str(cert_file)}
    running = RunningService(root / "services" / "PositionStore", "position_store_service", env)
    with pytest.raises(
        RuntimeError, match="HTTPS needs both POSITION_STORE_TLS_CERT and POSITION_STORE_TLS_KEY"
    ):
        running.start()
