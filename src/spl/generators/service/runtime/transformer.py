"""The transformer of a store: first-order records -> second-order (refined) tables.

Per refinement and robot, a watermark (source timestamp, raw id) marks the last raw
record transformed. Each step reads the records after it in source-timestamp order,
writes their refined rows (or a per-record error), and moves the watermark, all in
one database transaction: a crash at any moment rolls the whole step back, so after
a restart every record is transformed exactly once. The refined tables' unique
``raw_id`` makes a second concurrent transformer fail instead of duplicating rows.

A transform that reads ``next`` holds back each robot's newest record until its
successor exists. A record that arrives with a source timestamp older than its
robot's watermark is behind the transformer and is reported in the error table.

On PostgreSQL a step takes the refined table's transaction lock before it inserts
(database.ordered_inserts): ids become visible in increasing order, which the
subscriptions rely on, also with several replicas each running a transformer. After
each step that committed records, ``on_commit`` wakes the subscriptions of this process
(another process's are woken by their own polling).

Runs as a thread inside the web process (TRANSFORMER=embedded, the default) or as
its own process (the service's ``transformer`` module; then the web process runs with
TRANSFORMER=off).
"""

from __future__ import annotations

import contextlib
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from sqlalchemy import Engine, Row, Table, and_, func, insert, or_, select, update

from .database import WriteTurns, ordered_inserts
from .records import Refinement

log = logging.getLogger(__name__)
BATCH = 500


@dataclass(frozen=True)
class TransformedStore:
    """What a store's transformer reads and writes: its raw records, watermarks and
    errors, its refinements, and the exception a transform raises for one record."""

    raw_records: Table
    watermarks: Table
    transform_errors: Table
    refinements: tuple[Refinement, ...]
    record_error: type[Exception]


def _record(row: Row[Any]) -> dict[str, Any]:
    values = dict(row.document)
    values["timestamp"] = row.source_ts
    return values


class Transformer:
    def __init__(
        self,
        engine: Engine,
        store: TransformedStore,
        turns: WriteTurns,
        on_commit: Callable[[], None] | None = None,
    ) -> None:
        self.engine = engine
        self.store = store
        self.on_commit = on_commit or (lambda: None)
        # SQLite: take the write lock up front (no effect on PostgreSQL), and take turns
        # with the posts of this process, which go first (database.py's WriteTurns).
        self.writer = engine.execution_options(sqlite_begin="immediate")
        sqlite = engine.dialect.name == "sqlite"
        self.turn = turns.transformer if sqlite else contextlib.nullcontext
        self.late_checked: dict[str, int] = {}  # raw ids up to this were checked for lateness

    def robots(self) -> list[str]:
        with self.engine.connect() as conn:
            return list(conn.scalars(select(self.store.raw_records.c.robot).distinct()))

    def run_refinement(self, refinement: Refinement) -> int:
        """Transform everything that is ready; returns the number of records consumed."""
        done = 0
        for robot in self.robots():
            while True:
                consumed, more = self.step(refinement, robot)
                if consumed:
                    self.on_commit()
                done += consumed
                if not more:
                    break
        return done

    def step(self, refinement: Refinement, robot: str) -> tuple[int, bool]:
        """One transaction: up to BATCH records of one robot, their output, the watermark."""
        store = self.store
        raw_records, watermarks = store.raw_records, store.watermarks
        with self.turn(), self.writer.begin() as conn:
            mark = conn.execute(
                select(watermarks)
                .where(watermarks.c.refinement == refinement.name, watermarks.c.robot == robot)
                .with_for_update()
            ).first()
            condition = raw_records.c.robot == robot
            if mark is not None:
                condition = and_(
                    condition,
                    or_(
                        raw_records.c.source_ts > mark.source_ts,
                        and_(
                            raw_records.c.source_ts == mark.source_ts,
                            raw_records.c.id > mark.raw_id,
                        ),
                    ),
                )
            rows = conn.execute(
                select(raw_records)
                .where(condition)
                .order_by(raw_records.c.source_ts, raw_records.c.id)
                .limit(BATCH + 1)
            ).all()
            if refinement.uses_next:
                ready, more = rows[:-1], len(rows) == BATCH + 1
            else:
                ready, more = rows[:BATCH], len(rows) > BATCH
            if not ready:
                return 0, False
            previous = None
            if refinement.uses_prev and mark is not None:
                previous = conn.execute(
                    select(raw_records).where(raw_records.c.id == mark.raw_id)
                ).first()
            outputs, failures = [], []
            for index, row in enumerate(ready):
                current = _record(row)
                following = _record(rows[index + 1]) if index + 1 < len(rows) else None
                before = _record(previous) if previous is not None else None
                try:
                    values = refinement.transform(current, before, following)
                except store.record_error as exc:
                    failures.append(
                        {"refinement": refinement.name, "raw_id": row.id, "message": str(exc)}
                    )
                else:
                    values.update(raw_id=row.id, robot=row.robot, timestamp=row.source_ts)
                    outputs.append(values)
                previous = row
            if outputs:
                ordered_inserts(conn, refinement.table.name)
                conn.execute(insert(refinement.table), outputs)
            if failures:
                conn.execute(insert(store.transform_errors), failures)
            last = ready[-1]
            if mark is None:
                conn.execute(
                    insert(watermarks).values(
                        refinement=refinement.name,
                        robot=robot,
                        source_ts=last.source_ts,
                        raw_id=last.id,
                    )
                )
            else:
                conn.execute(
                    update(watermarks)
                    .where(watermarks.c.refinement == refinement.name, watermarks.c.robot == robot)
                    .values(source_ts=last.source_ts, raw_id=last.id)
                )
            return len(ready), more

    def report_late(self, refinement: Refinement) -> int:
        """Record raw records that arrived behind their robot's watermark as errors."""
        store = self.store
        raw_records, watermarks = store.raw_records, store.watermarks
        transform_errors = store.transform_errors
        with self.turn(), self.writer.begin() as conn:
            newest = conn.scalar(select(func.max(raw_records.c.id))) or 0
            checked = self.late_checked.get(refinement.name, 0)
            behind = (
                select(raw_records.c.id)
                .join(
                    watermarks,
                    and_(
                        watermarks.c.robot == raw_records.c.robot,
                        watermarks.c.refinement == refinement.name,
                    ),
                )
                .where(raw_records.c.id > checked, raw_records.c.id <= newest)
                .where(
                    or_(
                        raw_records.c.source_ts < watermarks.c.source_ts,
                        and_(
                            raw_records.c.source_ts == watermarks.c.source_ts,
                            raw_records.c.id < watermarks.c.raw_id,
                        ),
                    )
                )
                .where(
                    ~select(refinement.table.c.raw_id)
                    .where(refinement.table.c.raw_id == raw_records.c.id)
                    .exists()
                )
                .where(
                    ~select(transform_errors.c.id)
                    .where(
                        transform_errors.c.raw_id == raw_records.c.id,
                        transform_errors.c.refinement == refinement.name,
                    )
                    .exists()
                )
            )
            ids = list(conn.scalars(behind))
            if ids:
                conn.execute(
                    insert(transform_errors),
                    [
                        {
                            "refinement": refinement.name,
                            "raw_id": i,
                            "message": "arrived after later records of its robot were transformed",
                        }
                        for i in ids
                    ],
                )
        self.late_checked[refinement.name] = newest
        return len(ids)


def run_forever(
    engine: Engine,
    store: TransformedStore,
    turns: WriteTurns,
    stop: threading.Event,
    on_commit: Callable[[], None] | None = None,
) -> None:
    """Every refinement on its own period until ``stop`` is set."""
    transformer = Transformer(engine, store, turns, on_commit)
    due = {r.name: 0.0 for r in store.refinements}
    while not stop.is_set():
        now = time.monotonic()
        for refinement in store.refinements:
            if now < due[refinement.name]:
                continue
            try:
                count = transformer.run_refinement(refinement)
                transformer.report_late(refinement)
                if count:
                    log.info("%s: transformed %d records", refinement.name, count)
            except Exception:  # the next period retries; nothing was committed
                log.exception("%s: transformation step failed", refinement.name)
            due[refinement.name] = time.monotonic() + refinement.period
        wait = min(due.values()) - time.monotonic() if due else 1.0
        stop.wait(max(0.01, wait))


def start_thread(
    engine: Engine,
    store: TransformedStore,
    turns: WriteTurns,
    on_commit: Callable[[], None] | None = None,
) -> tuple[threading.Thread, threading.Event]:
    stop = threading.Event()
    thread = threading.Thread(
        target=run_forever,
        args=(engine, store, turns, stop, on_commit),
        name="transformer",
        daemon=True,
    )
    thread.start()
    return thread, stop
