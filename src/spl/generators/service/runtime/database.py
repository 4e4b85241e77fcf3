"""Database engine of a store: SQLite by default, PostgreSQL when DATABASE_URL says so.

The schema is created from the SQLAlchemy metadata on start (create_all), never by
hand. On SQLite, the transformer's transactions start with BEGIN IMMEDIATE so its
read of the watermark and its writes form one serialised unit next to the API's
inserts; WAL lets readers continue meanwhile.
"""

from __future__ import annotations

import contextlib
import hashlib
import threading
from collections.abc import Iterator
from typing import Any

from sqlalchemy import (
    Connection,
    Engine,
    Index,
    MetaData,
    Table,
    create_engine,
    event,
    inspect,
    text,
)
from sqlalchemy.engine import make_url

SQLITE_BEGIN = {"immediate": "BEGIN IMMEDIATE", "deferred": "BEGIN"}


class WriteTurns:
    """Whose turn it is to write to SQLite in this process, posts first.

    SQLite lets one connection write at a time, and a connection that finds the lock
    taken polls for it (its busy handler sleeps up to 100 ms between tries), so the
    posts waiting for a transformer run found the lock free only by chance between
    two steps. Here the transformer takes a turn per step and lets waiting posts go
    first; the event loop only ever tries for a turn, never waits. Other processes
    (a transformer of its own, more workers) still meet at SQLite's lock.
    """

    def __init__(self) -> None:
        self.changed = threading.Condition()
        self.taken = False
        self.posts_waiting = 0

    def try_posts(self) -> bool:
        """A turn for the event loop's posts if nobody writes now; ``release()`` it."""
        with self.changed:
            if self.taken:
                return False
            self.taken = True
            return True

    @contextlib.contextmanager
    def posts(self) -> Iterator[None]:
        with self.changed:
            self.posts_waiting += 1
            self.changed.wait_for(lambda: not self.taken)
            self.posts_waiting -= 1
            self.taken = True
        try:
            yield
        finally:
            self.release()

    @contextlib.contextmanager
    def transformer(self) -> Iterator[None]:
        with self.changed:
            self.changed.wait_for(lambda: not self.taken and not self.posts_waiting)
            self.taken = True
        try:
            yield
        finally:
            self.release()

    def release(self) -> None:
        with self.changed:
            self.taken = False
            self.changed.notify_all()


def ordered_inserts_key(table: str) -> int:
    """The transaction lock (PostgreSQL advisory lock) of inserts into ``table``."""
    return int.from_bytes(hashlib.sha256(table.encode()).digest()[:8], "big", signed=True)


ORDERED_INSERTS = "SELECT pg_advisory_xact_lock(%s)"


def ordered_inserts(conn: Any, table: str) -> None:
    """On PostgreSQL: wait for the other transactions inserting into ``table`` to end
    before this one takes ids, so ids become visible in increasing order, as they do on
    SQLite (one writer at a time): a subscriber reading the records after the last id it
    saw never skips one committed late (the service's subscriptions.py). A no-op on SQLite."""
    if conn.dialect.name == "postgresql":
        conn.execute(
            text("SELECT pg_advisory_xact_lock(:key)"), {"key": ordered_inserts_key(table)}
        )


def _upgrade(engine: Engine, raw_records: Table, raw_key_index: Index) -> None:
    """Columns and indexes a database made by an earlier version of the service lacks
    (create_all makes only missing tables): the raw records' idempotency key."""
    columns = {c["name"] for c in inspect(engine).get_columns(raw_records.name)}
    if "key" not in columns:
        with engine.begin() as conn:
            conn.execute(text(f'ALTER TABLE "{raw_records.name}" ADD COLUMN "key" VARCHAR(128)'))
    raw_key_index.create(engine, checkfirst=True)


def _postgres_url(url: str) -> str:
    """Plain postgresql:// URLs use psycopg 3, the driver this service ships with."""
    parsed = make_url(url)
    if parsed.drivername in ("postgresql", "postgres"):
        parsed = parsed.set(drivername="postgresql+psycopg")
    return parsed.render_as_string(hide_password=False)


def create(url: str, metadata: MetaData, raw_records: Table, raw_key_index: Index) -> Engine:
    """The engine of the database ``url``, its tables (``metadata``) made or upgraded."""
    if make_url(url).get_backend_name() == "sqlite":
        engine = create_engine(url, connect_args={"check_same_thread": False, "timeout": 30})

        @event.listens_for(engine, "connect")
        def _configure(dbapi_connection: Any, _record: Any) -> None:
            dbapi_connection.isolation_level = None  # SQLAlchemy emits BEGIN itself
            cursor = dbapi_connection.cursor()
            cursor.execute("PRAGMA journal_mode=WAL")
            cursor.execute("PRAGMA synchronous=NORMAL")
            cursor.execute("PRAGMA foreign_keys=ON")
            cursor.close()

        @event.listens_for(engine, "begin")
        def _begin(connection: Connection) -> None:
            mode = connection.get_execution_options().get("sqlite_begin", "deferred")
            connection.exec_driver_sql(SQLITE_BEGIN[mode])
    else:
        engine = create_engine(_postgres_url(url), pool_pre_ping=True, pool_size=10)
    metadata.create_all(engine)
    _upgrade(engine, raw_records, raw_key_index)
    return engine
