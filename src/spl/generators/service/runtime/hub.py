"""The feeds and callback subscriptions of one service process (subscriptions.py: what
a subscription sends): a thread reads each collection after its cursor and hands the
records to the subscribers in the event loop; the callback subscriptions are rows of
the store's own table, delivered by the replica holding their lease.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
import time
import uuid
from collections.abc import Iterator, Sequence
from typing import Any

import httpx
from sqlalchemy import Connection, Engine, Table, delete, func, insert, or_, select, update

from . import callback_targets
from .callback_targets import AllowList
from .database import WriteTurns
from .subscriptions import (
    CALLBACK_TIMEOUT,
    FEED_POLL,
    LEASE,
    PAGE,
    RENEW,
    CallbackSubscriber,
    Collection,
    Subscriber,
    WebSocketSubscriber,
)
from .turtle import JSON, TURTLE, Links

log = logging.getLogger(__name__)


class Feed:
    def __init__(self, collection: Collection) -> None:
        self.collection = collection
        self.members: tuple[Subscriber, ...] = ()  # replaced, never changed (read by the thread)
        self.cursor = 0  # the thread's: records up to here were handed over

    def dispatch(self, low: int, rows: Sequence[Any]) -> None:
        for subscriber in self.members:
            subscriber.offer(low, rows)


class Hub:
    """The feeds and subscriptions of this process; created in the event loop. The
    callback subscriptions are rows of ``table``, their paths under ``prefix``; a write
    takes this process's ``turns``; callbacks go where ``allow`` lets them."""

    def __init__(
        self,
        engine: Engine,
        collections: list[Collection],
        table: Table,
        prefix: str,
        turns: WriteTurns,
        allow: AllowList,
    ) -> None:
        self.engine = engine
        self.table = table
        self.prefix = prefix
        self.turns = turns
        self.allow = allow
        self.owner = str(uuid.uuid4())  # this process, as the holder of callback leases
        self.collections = {c.name: c for c in collections}
        self.feeds = {c.name: Feed(c) for c in collections}
        self.loop = asyncio.get_running_loop()
        self.wakeup = threading.Event()
        self.stopping = threading.Event()
        self.thread = threading.Thread(target=self._run, name="subscription-feeds", daemon=True)
        self.subscribers: dict[str, Subscriber] = {}
        self.leases: asyncio.Task | None = None
        self._client: httpx.AsyncClient | None = None
        self.writer = engine.execution_options(sqlite_begin="immediate")
        self.sqlite = engine.dialect.name == "sqlite"

    def start(self) -> Hub:
        self.thread.start()
        self.leases = self.loop.create_task(self._keep_leases())
        return self

    async def close(self) -> None:
        if self.leases is not None:
            self.leases.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await self.leases
        for subscriber in list(self.subscribers.values()):
            if isinstance(subscriber, WebSocketSubscriber):
                await subscriber.cancel()
            else:
                await subscriber.stop()
        with contextlib.suppress(Exception):
            await asyncio.to_thread(self._release_leases)
        self.stopping.set()
        self.wakeup.set()
        self.thread.join(timeout=5)
        if self._client is not None:
            await self._client.aclose()

    def wake(self) -> None:
        """A record was committed (any thread): read the feeds now."""
        self.wakeup.set()

    def subscription_path(self, identifier: str) -> str:
        return f"{self.prefix}/subscriptions/{identifier}"

    def client(self) -> httpx.AsyncClient:
        if self._client is None:
            # no redirects followed, no proxy from the environment (it would resolve the
            # host itself, past the check): docs/services.md
            self._client = httpx.AsyncClient(
                timeout=CALLBACK_TIMEOUT,
                follow_redirects=False,
                trust_env=False,
                verify=callback_targets.authorities(),
            )
        return self._client

    # --- in the event loop ------------------------------------------------------

    def add(self, subscriber: Subscriber) -> None:
        self.subscribers[subscriber.id] = subscriber
        feed = self.feeds[subscriber.collection.name]
        feed.members = (*feed.members, subscriber)
        self.wake()

    def remove(self, subscriber: Subscriber) -> None:
        self.subscribers.pop(subscriber.id, None)
        feed = self.feeds[subscriber.collection.name]
        feed.members = tuple(s for s in feed.members if s is not subscriber)

    async def newest(self, collection: Collection) -> int:
        return await asyncio.to_thread(self.max_id, collection)

    async def create_callback(
        self, collection: Collection, callback: str, media: str, links: Links
    ) -> dict[str, Any]:
        now = time.time()
        row = {
            "id": str(uuid.uuid4()),
            "collection": collection.name,
            "callback": callback,
            "media_type": TURTLE if media == "turtle" else JSON,
            "base": links.base,
            "created": now,
            "position": await self.newest(collection),
            "owner": self.owner,
            "lease_until": now + LEASE,
        }
        await asyncio.to_thread(self._insert_callback, row)
        return self._start_callback(row).describe()

    def _start_callback(self, row: Any) -> CallbackSubscriber:
        mapping = dict(row._mapping) if hasattr(row, "_mapping") else dict(row)
        subscriber = CallbackSubscriber(
            mapping["callback"],
            self,
            self.collections[mapping["collection"]],
            "turtle" if mapping["media_type"] == TURTLE else "json",
            Links(mapping["base"]),
            mapping["position"],
            mapping["id"],
            mapping["created"],
        )
        self.add(subscriber)
        subscriber.task = self.loop.create_task(self._deliver(subscriber))
        return subscriber

    async def _deliver(self, subscriber: CallbackSubscriber) -> None:
        try:
            await subscriber.run()
        except asyncio.CancelledError:
            pass
        except Exception:
            log.exception("callback subscription %s stopped", subscriber.id)
        finally:
            if self.subscribers.get(subscriber.id) is subscriber:
                self.remove(subscriber)

    async def describe_all(self) -> list[dict[str, Any]]:
        rows = await asyncio.to_thread(self._callbacks)
        items = [self._describe_row(row) for row in rows]
        items += [
            s.describe() for s in self.subscribers.values() if isinstance(s, WebSocketSubscriber)
        ]
        return sorted(items, key=lambda item: (item["created"], item["id"]))

    async def describe(self, identifier: str) -> dict[str, Any] | None:
        subscriber = self.subscribers.get(identifier)
        if isinstance(subscriber, WebSocketSubscriber):
            return subscriber.describe()
        row = await asyncio.to_thread(self._callback, identifier)
        return self._describe_row(row) if row is not None else None

    async def cancel(self, identifier: str) -> bool:
        subscriber = self.subscribers.get(identifier)
        if isinstance(subscriber, WebSocketSubscriber):
            await subscriber.cancel()
            return True
        deleted = await asyncio.to_thread(self.delete_callback, identifier)
        if subscriber is not None:
            self.remove(subscriber)
            await subscriber.stop()
        return deleted

    def _describe_row(self, row: Any) -> dict[str, Any]:
        return {
            "id": row.id,
            "type": "callback",
            "resource": self.collections[row.collection].path,
            "media_type": row.media_type,
            "callback": row.callback,
            "created": row.created,
        }

    async def _keep_leases(self) -> None:
        """Deliver the callback subscriptions whose lease this process holds or takes
        over (every ``RENEW`` seconds); stop those cancelled or taken over."""
        while True:
            try:
                rows = await asyncio.to_thread(self._claim)
                owned = {row.id: row for row in rows}
                for identifier, row in owned.items():
                    if identifier not in self.subscribers and row.collection in self.collections:
                        self._start_callback(row)
                for identifier, subscriber in list(self.subscribers.items()):
                    if isinstance(subscriber, CallbackSubscriber) and identifier not in owned:
                        self.remove(subscriber)
                        await subscriber.stop()
            except asyncio.CancelledError:
                raise
            except Exception:
                log.exception("renewing the callback subscriptions failed")
            await asyncio.sleep(RENEW)

    # --- in threads -------------------------------------------------------------

    def _run(self) -> None:
        while not self.stopping.is_set():
            self.wakeup.wait(FEED_POLL)
            self.wakeup.clear()
            for feed in self.feeds.values():
                members = feed.members
                if not members:
                    continue
                low = max(feed.cursor, min(s.position for s in members))
                try:
                    rows = self.read(feed.collection, low)
                except Exception:
                    log.exception("reading %s for its subscribers failed", feed.collection.path)
                    continue
                if rows:
                    feed.cursor = rows[-1].id
                    try:
                        self.loop.call_soon_threadsafe(feed.dispatch, low, rows)
                    except RuntimeError:  # the loop is closed: the service stops
                        return
                    if len(rows) == PAGE:
                        self.wakeup.set()

    def read(self, collection: Collection, after: int, limit: int = PAGE) -> Sequence[Any]:
        table = collection.table
        with self.engine.connect() as conn:
            return conn.execute(
                select(table).where(table.c.id > after).order_by(table.c.id).limit(limit)
            ).all()

    def max_id(self, collection: Collection) -> int:
        with self.engine.connect() as conn:
            return conn.scalar(select(func.max(collection.table.c.id))) or 0

    @contextlib.contextmanager
    def _write(self) -> Iterator[Connection]:
        turn = self.turns.transformer() if self.sqlite else contextlib.nullcontext()
        with turn, self.writer.begin() as conn:
            yield conn

    def _insert_callback(self, row: dict[str, Any]) -> None:
        with self._write() as conn:
            conn.execute(insert(self.table).values(**row))

    def _callbacks(self) -> Sequence[Any]:
        with self.engine.connect() as conn:
            return conn.execute(select(self.table)).all()

    def _callback(self, identifier: str) -> Any:
        with self.engine.connect() as conn:
            return conn.execute(select(self.table).where(self.table.c.id == identifier)).first()

    def delete_callback(self, identifier: str) -> bool:
        with self._write() as conn:
            result = conn.execute(delete(self.table).where(self.table.c.id == identifier))
            return result.rowcount > 0

    def store_position(self, identifier: str, position: int) -> bool:
        """False when this process no longer holds the subscription."""
        table = self.table
        with self._write() as conn:
            result = conn.execute(
                update(table)
                .where(table.c.id == identifier, table.c.owner == self.owner)
                .values(position=position)
            )
            return result.rowcount > 0

    def _claim(self) -> Sequence[Any]:
        table = self.table
        with self.engine.connect() as conn:
            if not conn.scalar(select(func.count()).select_from(table)):
                return []
        now = time.time()
        with self._write() as conn:
            conn.execute(
                update(table)
                .where(or_(table.c.owner == self.owner, table.c.lease_until < now))
                .values(owner=self.owner, lease_until=now + LEASE)
            )
            return conn.execute(select(table).where(table.c.owner == self.owner)).all()

    def _release_leases(self) -> None:
        table = self.table
        with self._write() as conn:
            conn.execute(
                update(table).where(table.c.owner == self.owner).values(owner=None, lease_until=0.0)
            )
