"""Subscriptions to the collections of a store (R0.12-R0.17 and R1.8 of "Requirements
and Specifications for Robots, Linked Data and all the REST"): ``GET``
with ``Upgrade: websocket`` opens a WebSocket, ``GET`` with ``Upgrade: callback`` and
``Callback: <URI>`` stores a callback subscription; both push every new record of the
collection, one at a time and in id order, as JSON or Turtle (``Accept``).

Each collection has a feed: a thread reads the records after the feed's cursor as soon
as a record was committed in this process (the writer and the transformer wake it) and
every ``FEED_POLL`` seconds for records other processes committed (a transformer of its
own, other replicas), and hands them to the subscribers in the event loop. A
subscriber keeps the id of the last record it sent (``position``); whatever it missed
(it subscribed with ``after_id``, it fell behind, a batch came in between) it reads
from the database itself, so it sends each record once and in id order. Ids are
committed in increasing order: SQLite has one writer at a time, and on PostgreSQL the
inserts into a collection take a transaction lock first (database.ordered_inserts).

Callback subscriptions are rows of their own table, so they survive a restart. The
replica holding a subscription's lease delivers it: it posts each record to the
callback URI, retrying with exponential back-off (0.1 s doubling to 30 s) until the
receiver answers 2xx (410 Gone cancels the subscription), and stores its position as
it goes; after a crash the records since the stored position are posted again. Before
every post the callback's host is resolved and checked again, and the post goes to a
checked address (callback_targets); a redirect is an answer like any other non-2xx
one, never followed, and no proxy of the environment is used.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
import uuid
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import httpx
from sqlalchemy import Table

from . import callback_targets
from .turtle import JSON, TURTLE, Links

if TYPE_CHECKING:
    from .hub import Hub

log = logging.getLogger(__name__)
FEED_POLL = 0.02  # seconds between two reads of a feed that has subscribers
PAGE = 500  # records per read
QUEUE_LIMIT = 64  # batches waiting for a slow subscriber before it reads them itself
LEASE = 5.0  # seconds a replica holds the callback subscriptions it delivers
RENEW = 1.0
FIRST_BACKOFF = 0.1
MAX_BACKOFF = 30.0
CALLBACK_TIMEOUT = 10.0


@dataclass(frozen=True)
class Collection:
    """A collection one can subscribe to: raw ``records`` or a refined type."""

    name: str
    path: str
    table: Table
    json_text: Callable[[Any], str]  # a record as the JSON text a GET of it answers
    turtle: Callable[[Links, Any], str]  # its statements
    document: Callable[[str], str]  # statements as a whole Turtle document

    def text(self, media: str, links: Links, row: Any) -> str:
        if media == "json":
            return self.json_text(row)
        return self.document(self.turtle(links, row))


class Subscriber:
    """One subscription of this process: sends the records after ``position``."""

    kind = ""

    def __init__(
        self,
        hub: Hub,
        collection: Collection,
        media: str,
        links: Links,
        position: int,
        identifier: str | None = None,
        created: float | None = None,
    ) -> None:
        self.hub = hub
        self.collection = collection
        self.media = media
        self.links = links
        self.position = position
        self.id = identifier or str(uuid.uuid4())
        self.created = created if created is not None else time.time()
        self.queue: asyncio.Queue = asyncio.Queue()
        self.behind = False
        self.task: asyncio.Task | None = None

    def describe(self) -> dict[str, Any]:
        return {
            "id": self.id,
            "type": self.kind,
            "resource": self.collection.path,
            "media_type": TURTLE if self.media == "turtle" else JSON,
            "callback": None,
            "created": self.created,
        }

    def offer(self, low: int, rows: Sequence[Any]) -> None:
        """In the event loop: records after ``low`` the feed read."""
        if self.behind:
            return
        if self.queue.qsize() >= QUEUE_LIMIT:  # read them from the database later
            self.behind = True
            self.queue.put_nowait((low, None))
        else:
            self.queue.put_nowait((low, rows))

    async def run(self) -> None:
        await self.catch_up()
        while True:
            low, rows = await self.queue.get()
            if rows is None:
                self.behind = False
                await self.catch_up()
                continue
            if self.position < low:  # records in between came before this subscriber
                await self.catch_up()
            for row in rows:
                if row.id > self.position:
                    await self.send(row)

    async def catch_up(self) -> None:
        """Send every stored record after ``position``, read from the database."""
        while True:
            rows = await asyncio.to_thread(self.hub.read, self.collection, self.position)
            for row in rows:
                if row.id > self.position:
                    await self.send(row)
            if len(rows) < PAGE:
                return

    async def send(self, row: Any) -> None:
        await self.deliver(self.collection.text(self.media, self.links, row))
        self.position = row.id

    async def deliver(self, text: str) -> None:
        raise NotImplementedError

    async def stop(self) -> None:
        if self.task is not None:
            self.task.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await self.task


class WebSocketSubscriber(Subscriber):
    kind = "websocket"

    def __init__(self, websocket: Any, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.websocket = websocket

    async def deliver(self, text: str) -> None:
        await self.websocket.send_text(text)

    async def serve(self) -> None:
        """Push records until the client goes away (or the subscription is cancelled)."""
        self.hub.add(self)
        self.task = asyncio.create_task(self.run())
        receiver = asyncio.create_task(self._drain())
        try:
            await asyncio.wait({self.task, receiver}, return_when=asyncio.FIRST_COMPLETED)
        finally:
            self.hub.remove(self)
            for task in (self.task, receiver):
                task.cancel()
            for task in (self.task, receiver):
                with contextlib.suppress(asyncio.CancelledError, Exception):
                    await task

    async def _drain(self) -> None:
        """Read (and ignore) what the client sends, until it disconnects."""
        while True:
            message = await self.websocket.receive()
            if message["type"] == "websocket.disconnect":
                return

    async def cancel(self) -> None:
        """Close the connection (code 1000); ``serve`` then ends."""
        if self.task is not None:
            self.task.cancel()
        with contextlib.suppress(Exception):
            await self.websocket.close(code=1000, reason="subscription cancelled")


class CallbackSubscriber(Subscriber):
    kind = "callback"

    def __init__(self, callback: str, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.callback = callback
        self.stored = self.position
        self.stored_at = time.monotonic()

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "callback": self.callback}

    async def run(self) -> None:
        try:
            await super().run()
        finally:
            await self._store_position()

    async def send(self, row: Any) -> None:
        await super().send(row)
        if self.queue.empty() or time.monotonic() - self.stored_at > 0.5:
            await self._store_position()

    async def _store_position(self) -> None:
        if self.position == self.stored:
            return
        position = self.position
        still = await asyncio.to_thread(self.hub.store_position, self.id, position)
        self.stored, self.stored_at = position, time.monotonic()
        if not still:  # cancelled, or another replica took it over
            raise asyncio.CancelledError

    async def deliver(self, text: str) -> None:
        media_type = TURTLE if self.media == "turtle" else JSON
        headers = {
            "Content-Type": f"{media_type}; charset=utf-8",
            "Link": f'<{self.links.url(self.collection.path)}>; rel="related", '
            f"<{self.links.url(self.hub.subscription_path(self.id))}>; "
            'rel="self"',
        }
        delay = FIRST_BACKOFF
        while True:
            try:
                answer = await self._post(text.encode(), headers)
                if 200 <= answer.status_code < 300:
                    return
                if answer.status_code == 410:  # the receiver is gone for good (RestHooks)
                    log.info(
                        "callback %s answered 410: subscription %s cancelled",
                        self.callback,
                        self.id,
                    )
                    await asyncio.to_thread(self.hub.delete_callback, self.id)
                    raise asyncio.CancelledError
                problem = f"answered {answer.status_code}"
            except callback_targets.CallbackRefused as exc:
                problem = f"not posted: {exc}"
            except httpx.HTTPError as exc:
                problem = f"{type(exc).__name__}: {exc}"
            log.warning(
                "callback %s of subscription %s %s; again in %.1f s",
                self.callback,
                self.id,
                problem,
                delay,
            )
            await asyncio.sleep(delay)
            delay = min(delay * 2, MAX_BACKOFF)

    async def _post(self, body: bytes, headers: dict[str, str]) -> httpx.Response:
        """Post to the first checked address of the callback's host that connects (the
        host resolved and checked now: DNS cannot point it elsewhere in between)."""
        _, targets = await asyncio.to_thread(
            callback_targets.destinations, self.callback, self.hub.allow
        )
        for index, target in enumerate(targets):
            extensions = {"sni_hostname": target.server_name} if target.server_name else {}
            try:
                return await self.hub.client().post(
                    target.url,
                    content=body,
                    extensions=extensions,
                    headers={**headers, "Host": target.host_header},
                )
            except (httpx.ConnectError, httpx.ConnectTimeout):
                if index == len(targets) - 1:
                    raise
        raise callback_targets.CallbackRefused(f"{self.callback}: no address to post to")
