"""kill -9 while the transformer works: after a restart, every raw record is transformed
exactly once (the output and the watermark are written in one transaction)."""

from __future__ import annotations

import sqlite3
from pathlib import Path

from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import (
    TOKEN,
    RunningService,
    crash_during_transformation,
    post_in_batches,
    write_files,
)

TOTAL = 12000
ROBOTS = ("ev3_a", "ev3_b", "ev3_c")


def test_kill_9_during_transformation_loses_and_duplicates_nothing(tmp_path: Path) -> None:
    write_files(service.generate(product()), tmp_path)
    directory = tmp_path / "services" / "FollowStore"
    env = {
        "FOLLOW_STORE_TOKEN": TOKEN,
        "FOLLOW_STORE_TRANSFORM_PERIOD": "0.02",
        "TRANSFORMER": "off",
    }
    running = RunningService(directory, "follow_store_service", env).start()
    per_robot = TOTAL // len(ROBOTS)
    records = [
        {
            "robot": robot,
            "timestamp": 100.0 + i * 0.25,
            "data": {"vx": float(i), "vy": 0.0, "va": float(n)},
        }
        for i in range(per_robot + 1)  # + 1: the newest of each robot waits for a next one
        for n, robot in enumerate(ROBOTS)
    ]
    post_in_batches(f"{running.url}/FollowStore/records/batch", records)
    running.kill()

    database = directory / "follow_store.db"

    def count_refined() -> int:
        with sqlite3.connect(f"file:{database}?mode=ro", uri=True, timeout=30) as conn:
            return conn.execute("SELECT count(*) FROM follow_store_command").fetchone()[0]

    running.env["TRANSFORMER"] = "embedded"
    try:
        crash_during_transformation(running, count_refined, TOTAL)
    finally:
        running.stop()
    with sqlite3.connect(database) as conn:
        rows = conn.execute(
            "SELECT c.raw_id, c.duration, c.vx, r.document FROM follow_store_command c "
            "JOIN follow_store_raw r ON r.id = c.raw_id"
        ).fetchall()
        errors = conn.execute("SELECT count(*) FROM follow_store_errors").fetchone()[0]
    assert len(rows) == TOTAL and len({row[0] for row in rows}) == TOTAL
    assert all(duration == 0.25 for _, duration, _, _ in rows)
    assert errors == 0
