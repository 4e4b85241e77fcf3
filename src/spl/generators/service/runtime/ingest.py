"""Storing posted records: every request of one turn of the event loop in one
transaction (group commit).

Requests hand their validated rows to the ``RecordWriter`` and wait (asynchronously)
for the ids. Once per turn of the event loop, the writer inserts the rows of every
request that arrived in that turn in one transaction: at concurrency 8 a commit
carries several requests, and no request holds a thread of its own. A request is
answered only after the commit that holds its rows has returned, so a record
answered 201 is in the database, also after a crash of the process (on SQLite, WAL
with synchronous=NORMAL: a commit survives the process, not a power failure).

On SQLite the turn's transaction runs right in the event loop: with WAL it is a
few tens of microseconds of CPU, and it waits neither for a disk (its connection
leaves checkpoints, which sync the disk, to the writer thread, once a second) nor
for the write lock (busy timeout 0, BEGIN IMMEDIATE). When another connection holds
the lock (the transformer, another process), nothing was written and the group
goes to the writer thread, which waits for the lock; this process's transformer
lets it in between two of its steps (database.py's WriteTurns). PostgreSQL is across a
socket, so there every group goes to the writer thread.

A request's rows stay together in one transaction (a batch is all or nothing). In
the writer thread, when the database refuses a row (integrity or data error),
nothing was written and each request of the group is tried again on its own, so
only the request at fault is refused. Any other failure (a lock wait timed out, the
connection broke, the commit failed) answers every request of the group with it.

The INSERT is SQLAlchemy's, compiled once for the engine's dialect, and runs on the
connection's DBAPI cursor: SQLAlchemy's per-statement work cost several times the
insert itself. Values pass through the columns' own bind processors (the JSON
document is serialised as SQLAlchemy would), so the rows are the ones SQLAlchemy
writes.

A record with a ``key`` is inserted with ``ON CONFLICT (robot, key) DO NOTHING``: when
its robot and key are stored already (by an earlier post, an earlier record of the same
group, or another replica), nothing is inserted and the stored record's id is read back
in the same transaction, so a writer that sends a batch again after a lost answer gets
the ids of the first time. On PostgreSQL each transaction takes the raw table's
transaction lock before its ids (database.py's ordered_inserts), so ids become visible in
increasing order for the subscribers; SQLite has one writer at a time anyway. After
each commit the subscriptions' feeds are woken (``on_commit``).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import queue
import sqlite3
import threading
import time
from collections.abc import Callable
from typing import Any, cast

from sqlalchemy import ColumnElement, Connection, Engine, Table, bindparam, select
from sqlalchemy.dialects import postgresql, sqlite

from .database import ORDERED_INSERTS, WriteTurns, ordered_inserts_key

log = logging.getLogger(__name__)
# Rows per transaction in the writer thread: several full batches, yet short enough
# that a transaction never holds SQLite's write lock for long.
MAX_GROUP_ROWS = 5000
# SQLite: how often the writer thread checkpoints the log the event loop wrote.
CHECKPOINT_SECONDS = 1.0
COLUMNS = ("robot", "source_ts", "received_ts", "document", "key")
STOP = None

Request = tuple[list[dict[str, Any]], asyncio.Future]


class NotWritten(Exception):
    """The transaction was rolled back before its commit: nothing of it is stored."""


class RawInsert:
    """``INSERT INTO <raw table> ... RETURNING id`` for one dialect, on a DBAPI cursor
    (``key_where``: the rows the idempotency key's unique index covers)."""

    def __init__(self, engine: Engine, raw_records: Table, key_where: ColumnElement[bool]) -> None:
        self.table = raw_records.name
        dialect = engine.dialect
        insert = postgresql.insert if dialect.name == "postgresql" else sqlite.insert
        statement = insert(raw_records).on_conflict_do_nothing(
            index_elements=[raw_records.c.robot, raw_records.c.key], index_where=key_where
        )
        compiled = statement.returning(raw_records.c.id).compile(
            dialect=dialect, column_keys=list(COLUMNS)
        )
        self.sql = compiled.string
        self.names = tuple(compiled.positiontup or ()) if compiled.positional else None
        self.processors = [
            (name, processor)
            for name in COLUMNS
            if (processor := raw_records.c[name].type.dialect_impl(dialect).bind_processor(dialect))
            is not None
        ]
        # psycopg sends all rows in one pipeline and reads their ids back in order;
        # sqlite3's executemany returns no rows, so SQLite inserts row by row (in
        # process, no round trip).
        self.pipelined = dialect.driver == "psycopg"
        self.postgres = dialect.name == "postgresql"
        found = (
            select(raw_records.c.id)
            .where(raw_records.c.robot == bindparam("robot"), raw_records.c.key == bindparam("key"))
            .compile(dialect=dialect)
        )
        self.lookup_sql = found.string
        self.lookup_names = tuple(found.positiontup or ()) if found.positional else None

    def parameters(self, row: dict[str, Any]) -> tuple | dict[str, Any]:
        values = {"key": None, **row}  # a row may come without a key
        for name, processor in self.processors:
            values[name] = processor(values[name])
        return tuple(values[n] for n in self.names) if self.names else values

    def run(self, cursor: Any, rows: list[dict[str, Any]]) -> list[int]:
        """The ids of ``rows``, in their order: a row whose robot and key are stored
        already gets the stored record's id."""
        if self.postgres:
            cursor.execute(ORDERED_INSERTS, (ordered_inserts_key(self.table),))
        parameters = [self.parameters(row) for row in rows]
        ids: list[int | None] = []
        if self.pipelined:
            cursor.executemany(self.sql, parameters, returning=True)
            while True:
                found = cursor.fetchone()
                ids.append(found[0] if found is not None else None)
                if not cursor.nextset():
                    break
        else:
            for values in parameters:
                cursor.execute(self.sql, values)
                found = cursor.fetchone()
                ids.append(found[0] if found is not None else None)
        for index, record_id in enumerate(ids):
            if record_id is None:  # a key stored before: its record's id
                ids[index] = self.stored_id(cursor, rows[index])
        return ids  # type: ignore[return-value]

    def stored_id(self, cursor: Any, row: dict[str, Any]) -> int:
        values = {"robot": row["robot"], "key": row["key"]}
        parameters = tuple(values[n] for n in self.lookup_names) if self.lookup_names else values
        cursor.execute(self.lookup_sql, parameters)
        return cursor.fetchone()[0]


class RecordWriter:
    """Created and started in the event loop that serves the requests; ``turns`` are
    this process's turns to write (shared with its transformer)."""

    def __init__(
        self,
        engine: Engine,
        turns: WriteTurns,
        raw_records: Table,
        key_where: ColumnElement[bool],
        on_commit: Callable[[], None] | None = None,
    ) -> None:
        self.engine = engine
        self.turns = turns
        self.on_commit = on_commit or (lambda: None)
        self.statement = RawInsert(engine, raw_records, key_where)
        dbapi = engine.dialect.loaded_dbapi
        self.data_errors = (dbapi.IntegrityError, dbapi.DataError)
        self.sqlite = engine.dialect.name == "sqlite"  # written in the loop
        self.connections: dict[bool, Connection] = {}  # by in_loop: one each, held
        self.loop = asyncio.get_running_loop()
        self.waiting: list[Request] = []
        self.pending: queue.SimpleQueue = queue.SimpleQueue()
        self.thread = threading.Thread(target=self._run, name="record-writer", daemon=True)

    def start(self) -> RecordWriter:
        self.thread.start()
        return self

    def close(self) -> None:
        """Write what was handed over, then stop."""
        self._hand_over()
        self.pending.put(STOP)
        self.thread.join()
        if connection := self.connections.pop(True, None):
            connection.close()

    async def store(self, rows: list[dict[str, Any]]) -> list[int]:
        """The ids of ``rows``, in order, once their transaction is committed."""
        future = self.loop.create_future()
        if not self.waiting:  # the first request of this turn of the loop
            self.loop.call_soon(self._hand_over)
        self.waiting.append((rows, future))
        return await future

    def _hand_over(self) -> None:
        """Store the requests of one turn: here on SQLite when its write lock is free,
        else in the writer thread (one wake-up per turn, not per request)."""
        if not self.waiting:
            return
        group, self.waiting = self.waiting, []
        if self.sqlite:
            try:
                ids = self._insert(True, [row for rows, _ in group for row in rows])
            except NotWritten:
                pass  # the lock is taken (or a row refused): the writer thread sorts it out
            except Exception as exc:  # the commit failed: unknown outcome for all
                log.exception("commit of %d requests failed", len(group))
                _resolve(_outcomes(group, exc))
                return
            else:
                self.on_commit()
                _resolve(_outcomes(group, ids))
                return
        self.pending.put(group)

    def _run(self) -> None:
        stopping = False
        checkpointed = time.monotonic()
        while not stopping:
            if self.sqlite and time.monotonic() - checkpointed >= CHECKPOINT_SECONDS:
                self._checkpoint()
                checkpointed = time.monotonic()
            try:
                group = self.pending.get(timeout=CHECKPOINT_SECONDS if self.sqlite else None)
            except queue.Empty:
                continue
            if group is STOP:
                break
            group = list(group)
            size = sum(len(rows) for rows, _ in group)
            while size < MAX_GROUP_ROWS:
                try:
                    more = self.pending.get_nowait()
                except queue.Empty:
                    break
                if more is STOP:
                    stopping = True
                    break
                group.extend(more)
                size += sum(len(rows) for rows, _ in more)
            try:
                self._write(group)
            except BaseException as exc:  # never leave a request waiting for ever
                log.exception("storing %d requests failed", len(group))
                self._settle(_outcomes(group, exc))
        if connection := self.connections.pop(False, None):
            connection.close()

    def _write(self, group: list[Request]) -> None:
        """In the writer thread: the group in one transaction, or each request alone."""
        try:
            ids = self._insert(False, [row for rows, _ in group for row in rows])
        except NotWritten as exc:
            if isinstance(exc.__cause__, self.data_errors) and len(group) > 1:
                for request in group:
                    self._write([request])
                return
            self._settle(_outcomes(group, exc.__cause__ or exc))
        except Exception as exc:  # the commit failed: unknown outcome for all
            log.exception("commit of %d requests failed", len(group))
            self._settle(_outcomes(group, exc))
        else:
            self.on_commit()
            self._settle(_outcomes(group, ids))

    def _checkpoint(self) -> None:
        """Copy SQLite's log into the database file, here and not in the event loop: a
        checkpoint syncs the disk. PASSIVE: it waits for no reader and no writer."""
        try:
            dbapi_connection = _sqlite(self._connection(False))
            dbapi_connection.execute("PRAGMA wal_checkpoint(PASSIVE)").fetchall()
        except Exception:  # the next period tries again; the log only grows meanwhile
            log.exception("checkpoint failed")
            self._discard(False)

    def _connection(self, in_loop: bool) -> Connection:
        connection = self.connections.get(in_loop)
        if connection is None:
            # SQLite: take the write lock up front; no effect on PostgreSQL.
            connection = self.engine.connect().execution_options(sqlite_begin="immediate")
            if in_loop:  # never wait for the lock, nor for the disk, in the event loop
                connection.detach()  # its settings stay out of the pool
                dbapi_connection = _sqlite(connection)
                dbapi_connection.execute("PRAGMA busy_timeout = 0")
                dbapi_connection.execute("PRAGMA wal_autocheckpoint = 0")  # _checkpoint's
            self.connections[in_loop] = connection
        return connection

    def _insert(self, in_loop: bool, rows: list[dict[str, Any]]) -> list[int]:
        """The ids of ``rows`` once committed. ``NotWritten`` when nothing was written
        (the transaction was rolled back, or the event loop's turn is taken); any other
        exception: the commit failed, outcome unknown."""
        if not self.sqlite:
            return self._transaction(False, rows)
        if not in_loop:
            with self.turns.posts():
                return self._transaction(False, rows)
        if not self.turns.try_posts():
            raise NotWritten("the transformer of this process is writing")
        try:
            return self._transaction(True, rows)
        finally:
            self.turns.release()

    def _transaction(self, in_loop: bool, rows: list[dict[str, Any]]) -> list[int]:
        connection = self._connection(in_loop)
        try:
            transaction = connection.begin()
            cursor = connection.connection.cursor()
            try:
                ids = self.statement.run(cursor, rows)
            finally:
                cursor.close()
        except Exception as exc:
            try:
                connection.rollback()
            except Exception:
                self._discard(in_loop)
            if not _lock_taken(exc):
                log.warning("insert of %d rows failed: %s", len(rows), exc)
            raise NotWritten from exc
        try:
            transaction.commit()
        except BaseException:
            self._discard(in_loop)
            raise
        return ids

    def _discard(self, in_loop: bool) -> None:
        """A connection that failed may be broken: the next transaction takes a new one."""
        connection = self.connections.pop(in_loop, None)
        if connection is not None:
            connection.invalidate()

    def _settle(self, outcomes: list[tuple[asyncio.Future, Any]]) -> None:
        # a closed loop (RuntimeError) has nobody waiting for these answers
        with contextlib.suppress(RuntimeError):
            self.loop.call_soon_threadsafe(_resolve, outcomes)


def _sqlite(connection: Connection) -> sqlite3.Connection:
    """sqlite3's own connection under ``connection`` (written to only on SQLite)."""
    return cast(sqlite3.Connection, connection.connection.dbapi_connection)


def _lock_taken(exc: BaseException) -> bool:
    """SQLite's write lock is held elsewhere (SQLAlchemy wraps the driver's error)."""
    error = getattr(exc, "orig", exc)
    return (
        isinstance(error, sqlite3.OperationalError)
        and error.sqlite_errorcode & 0xFF == sqlite3.SQLITE_BUSY
    )


def _outcomes(
    group: list[Request], result: list[int] | BaseException
) -> list[tuple[asyncio.Future, Any]]:
    """Each request's future with its ids (sliced from ``result``) or the exception."""
    if isinstance(result, BaseException):
        return [(future, result) for _, future in group]
    outcomes, start = [], 0
    for rows, future in group:
        outcomes.append((future, result[start : start + len(rows)]))
        start += len(rows)
    return outcomes


def _resolve(outcomes: list[tuple[asyncio.Future, Any]]) -> None:
    for future, result in outcomes:
        if future.done():  # the request was cancelled (client gone); its rows are stored
            continue
        if isinstance(result, BaseException):
            future.set_exception(result)
        else:
            future.set_result(result)
