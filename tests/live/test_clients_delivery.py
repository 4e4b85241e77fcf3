"""A generated ROS 1 reader delivers every record of its store to a subscriber that
comes up after it, in order, the first one included, once each, on a loaded machine
(docs/services.md, "Robot-side writers and readers"): a ROS topic keeps no history, so
a reader that published the records it found at once lost them to a subscriber that
was not connected yet (seen under load as ``seen 11 received; #1 is [record 2]``).

The real things run: the generated service (uvicorn, SQLite, its transformer), Debian's
roscore, the generated reader's own script with rospy, and a rospy subscriber; three
processes spin the CPUs all the while. The records are refined in the store before the
subscriber starts, and more come while it listens."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from spl.smoke.live import Master
from spl.smoke.planning import load_plan
from spl.smoke.processes import Processes, find_ros, free_port, write_messages

from support.cpu_load import busy_processes
from support.service_runtime import TOKEN, RunningService, load_module, wait_for
from support.smoke_runs import ROOT, write_product

DATA = ROOT / "product_lines" / "data_acquisition"
LISTENER = Path(__file__).resolve().parents[1] / "support" / "record_listener.py"
BATCH = 6  # raw records posted before the subscriber starts, and again while it listens
PATIENCE = 120.0  # seconds: a generous bound on a loaded machine, never a pace


# (reader package, topic, message type, store, its service's slug, writer package, raw
# values of the i-th sample, refined records per batch of raw ones: a command's
# duration waits for the next velocity)
READERS = {
    "subscribing": (
        "command_reader", "/ev3/command", "ev3_msgs/Command", "FollowStore", "follow_store",
        "velocity_writer", lambda i: {"vx": float(i), "vy": 0.5, "va": -float(i)}, BATCH - 1,
    ),
    "polling": (
        "position_reader", "/gps/deg", "rover_msgs/PositionInDEG", "PositionStore",
        "position_store", "position_writer", lambda i: {"lat": 3600.0 * i, "lon": 7.25 * i},
        BATCH,
    ),
}  # fmt: skip


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_product(DATA, "Positions,Follow,Embedded", tmp_path_factory.mktemp("d") / "b")


def received(processes: Processes, label: str, fields: list[str]) -> list[list[Any]]:
    """The listener's messages so far, each as its values of ``fields``."""
    lines = processes.output(label).splitlines()
    records = [json.loads(line[len("record ") :]) for line in lines if line.startswith("record ")]
    return [[record[f] for f in fields] for record in records]


@pytest.mark.parametrize("kind", sorted(READERS))
def test_a_subscriber_started_after_the_reader_gets_every_record_under_load(
    bundle: Path, tmp_path: Path, kind: str
) -> None:
    package, topic, type_name, store, slug, writer_package, sample, refined = READERS[kind]
    ros = find_ros()
    token_env = f"{slug.upper()}_TOKEN"
    messages = tmp_path / "messages"
    write_messages(messages, load_plan(bundle).messages)
    client_root = bundle / "clients" / "ros1"
    writer = load_module(
        client_root / writer_package / "src" / writer_package / "store_client.py",
        f"delivery_writer_{kind}",
    )
    reader = load_module(
        client_root / package / "src" / package / "store_client.py", f"delivery_reader_{kind}"
    )
    fields = list(reader.FIELDS)
    service = RunningService(
        bundle / "services" / store,
        f"{slug}_service",
        {token_env: TOKEN, f"{slug.upper()}_TRANSFORM_PERIOD": "0.1"},
    )
    store_client = reader.StoreClient("http://127.0.0.1", token=TOKEN)

    def post(first: int) -> None:
        batching = writer.BatchingWriter(
            writer.StoreClient(service.url, token=TOKEN), "robot_1", batch_size=BATCH
        )
        for index in range(first, first + BATCH):
            assert batching.submit(1000.0 + index, sample(index))
        assert batching.flush(PATIENCE)
        batching.close()

    def stored() -> list[list[Any]]:
        return [[record[f] for f in fields] for record in store_client.read(limit=1000)]

    with busy_processes(3), Processes(tmp_path / "run") as processes:
        service.start()
        try:
            store_client.base = f"{service.url}/{store}"
            port = free_port()
            uri = f"http://127.0.0.1:{port}/"
            env = processes.environment(
                ROS_MASTER_URI=uri, ROS_HOME=str(tmp_path / "ros"), ROS_IP="127.0.0.1"
            )
            processes.start("roscore", [ros.roscore, "-p", str(port)], env)
            master = Master(uri)
            wait_for(lambda: master.pid() is not None, PATIENCE)
            script = client_root / package / "scripts" / package
            pythonpath = f"{messages}:{client_root / package / 'src'}"
            processes.start(
                "reader",
                [ros.python, str(script), f"records:={topic}", f"_store_url:={service.url}",
                 "_period:=0.2"],
                {**env, "PYTHONPATH": pythonpath, token_env: TOKEN},
            )  # fmt: skip
            wait_for(lambda: topic in master.graph().publishers, PATIENCE)
            # the first records are refined in the store (the reader has them at once)
            post(0)
            wait_for(lambda: len(stored()) == refined, PATIENCE)
            # ... and only then does a subscriber come up
            processes.start(
                "listener",
                [ros.python, str(LISTENER), topic, type_name],
                {**env, "PYTHONPATH": str(messages)},
            )
            wait_for(lambda: topic in master.graph().subscribers, PATIENCE)
            post(BATCH)  # more records while it listens
            total = refined + BATCH
            wait_for(lambda: len(stored()) == total, PATIENCE)
            expected = stored()

            def delivered() -> bool:
                """The last record has come (what is missing before it never will), or
                a process ended."""
                got = received(processes, "listener", fields)
                return expected[-1] in got or len(got) >= total or bool(processes.exited())

            wait_for(delivered, PATIENCE)
            got = received(processes, "listener", fields)
        finally:
            service.stop()
        ended = [label for label, _, _ in processes.exited()]
    assert not ended, [processes.output(label)[-2000:] for label in ended]
    assert got[:1] == expected[:1], f"seen {len(got)} received; #1 is {got[:1]}"
    assert got == expected  # every record, once each, in the store's order
    assert len(expected) == total and len({json.dumps(v) for v in expected}) == total
