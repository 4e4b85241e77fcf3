"""The generated clients against the real generated service, beyond the happy path: a
subscribing reader's WebSocket feed (the standard-library client of store_client.py
against uvicorn) that falls back to polling while the service is down and delivers each
record once, in order; writers' idempotency keys; TLS verification of the store's
certificate; only http(s) URLs."""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from spl.generators.clients import generator as clients
from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import TOKEN, RunningService, load_module, wait_for, write_files
from support.tls import self_signed


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Path:
    resolved = product()
    files = {**service.generate(resolved), **clients.generate(resolved)}
    return write_files(files, tmp_path_factory.mktemp("bundle"))


def follow_store(bundle: Path, **env: str) -> RunningService:
    settings = {"FOLLOW_STORE_TOKEN": TOKEN, "FOLLOW_STORE_TRANSFORM_PERIOD": "0.1", **env}
    return RunningService(bundle / "services" / "FollowStore", "follow_store_service", settings)


def module(bundle: Path, package: str, name: str):  # type: ignore[no-untyped-def]
    path = bundle / "clients" / "ros1" / package / "src" / package / "store_client.py"
    return load_module(path, name)


def post(writer_module, url: str, robot: str, count: int, first: int = 0) -> None:  # type: ignore[no-untyped-def]
    writer = writer_module.BatchingWriter(
        writer_module.StoreClient(url, token=TOKEN), robot, batch_size=3
    )
    for index in range(first, first + count):
        assert writer.submit(100.0 + index, {"vx": float(index), "vy": 0.0, "va": 0.0})
    assert writer.flush(20)
    writer.close()


def test_a_subscribed_reader_gets_every_record_once_through_a_restart(bundle: Path) -> None:
    running = follow_store(bundle).start()
    writer = module(bundle, "velocity_writer", "feed_writer")
    reader = module(bundle, "command_reader", "feed_reader")
    assert hasattr(reader, "Feed") and not hasattr(writer, "Feed")  # only `subscribe` readers
    received: list[dict] = []
    stop = threading.Event()
    polling = reader.PollingReader(reader.StoreClient(running.url))
    feed = reader.Feed(polling, received.append, 0.2, stop)
    thread = threading.Thread(target=feed.run, daemon=True)
    thread.start()
    try:
        post(writer, running.url, "ev3_a", 6)
        wait_for(lambda: len(received) >= 5)  # the last velocity waits for a next one
        running.kill()  # the WebSocket drops: the feed polls, and subscribes again later
        running.start()
        post(writer, running.url, "ev3_a", 6, first=6)
        wait_for(lambda: len(received) >= 11)
    finally:
        stop.set()
        running.stop()
    thread.join(5)
    ids = [record["id"] for record in received]
    assert ids == sorted(set(ids)) and len(ids) == 11  # once each, in order
    assert [record["vx"] for record in received] == [float(i) for i in range(11)]
    assert [record["duration"] for record in received] == [1.0] * 11  # next.timestamp - timestamp


def test_a_batch_sent_again_is_stored_once(bundle: Path) -> None:
    running = follow_store(bundle).start()
    try:
        writer = module(bundle, "velocity_writer", "key_writer")
        client = writer.StoreClient(running.url, token=TOKEN)
        batch = [writer.to_record("ev3_key", 1.0 + i, {"vx": 1.0, "vy": 2.0, "va": 3.0}, f"s-{i}")
                 for i in range(3)]  # fmt: skip
        first = client.post(batch)
        again = client.post(batch)  # an answer lost, the batch retried
        assert first == again
        assert len(client.read(robot="ev3_key")) == 3  # a writer's collection: raw records
    finally:
        running.stop()


def test_an_https_store_is_verified_against_the_named_authority(bundle: Path, tmp_path) -> None:
    import ssl

    cert, key = self_signed(tmp_path)
    running = follow_store(bundle, FOLLOW_STORE_TLS_CERT=str(cert), FOLLOW_STORE_TLS_KEY=str(key))
    running.context = ssl.create_default_context(cafile=str(cert))
    running.start()
    writer = module(bundle, "velocity_writer", "tls_writer")
    try:
        assert running.url.startswith("https://")
        os.environ.pop(writer.CA_ENV, None)
        untrusted = writer.StoreClient(running.url, token=TOKEN)
        with pytest.raises(writer.StoreError, match="CERTIFICATE_VERIFY_FAILED"):
            untrusted.post([writer.to_record("ev3_a", 1.0, {"vx": 0.0, "vy": 0.0, "va": 0.0})])
        os.environ[writer.CA_ENV] = str(cert)
        trusted = writer.StoreClient(running.url, token=TOKEN)
        assert trusted.post([writer.to_record("ev3_a", 1.0, {"vx": 0.0, "vy": 0.0, "va": 0.0})])
    finally:
        os.environ.pop(writer.CA_ENV, None)
        running.stop()


def test_only_http_and_https_urls_are_used(bundle: Path) -> None:
    writer = module(bundle, "velocity_writer", "scheme_writer")
    for url in ("file:///etc/passwd", "ftp://store.example.org", "store.example.org:8000"):
        with pytest.raises(ValueError, match="only http and https are used"):
            writer.StoreClient(url)


def test_a_node_given_another_scheme_stops_at_start_with_a_clear_message(bundle: Path) -> None:
    reader = module(bundle, "command_reader", "scheme_reader")
    assert reader.client_for("https://store.example.org").base.startswith("https://")
    for url in ("file:///etc/passwd", "ftp://store.example.org"):
        with pytest.raises(SystemExit) as stopped:
            reader.client_for(url)
        assert str(stopped.value) == (
            f"store URL {url!r}: only http and https are used; set the store_url parameter "
            "to the http:// or https:// URL of the FollowStore service"
        )
