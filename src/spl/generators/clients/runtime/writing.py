"""A writer node's side of its store (docs/services.md, "Robot-side writers and
readers"): samples converted to the store's data type, queued without blocking the
robot, posted in batches, retried with back-off and keyed so that a retried batch is
never stored twice.
"""

from __future__ import annotations

import itertools
import logging
import queue
import random
import threading
import time
import uuid
from typing import Any

from .transport import StoreClient, StoreError

log = logging.getLogger(__name__)
CONVERT = {"double": float, "int": int, "string": str, "bool": bool}


def to_record(
    fields: dict[str, str],
    robot: str,
    timestamp: float,
    values: dict[str, Any],
    key: str | None = None,
) -> dict[str, Any]:
    """The posted form of one sample; values converted to the types of ``fields`` (the
    model's data type). ``key`` makes a post idempotent: the store keeps one record per
    robot and key, so a batch sent again after a lost answer is not stored twice."""
    data = {name: CONVERT[kind](values[name]) for name, kind in fields.items()}
    record: dict[str, Any] = {"robot": robot, "timestamp": float(timestamp), "data": data}
    if key is not None:
        record["key"] = key
    return record


class BatchingWriter:
    """Queue + background thread: ``submit`` never blocks the caller (a ROS callback).

    Records are sent in batches; transport errors and 5xx answers are retried with
    exponential backoff (the batch stays first in line), 4xx answers are logged and
    the batch dropped, since sending it again cannot succeed. Every record carries a key
    of its own (this writer's session and a counter), so a batch the store took before
    its answer was lost is not stored twice when sent again. When the queue is full,
    new samples are dropped and counted rather than blocking the robot.
    """

    def __init__(
        self,
        client: StoreClient,
        robot: str,
        batch_size: int = 100,
        max_queue: int = 10000,
        linger: float = 0.2,
        max_backoff: float = 30.0,
    ) -> None:
        self.client = client
        self.robot = robot
        self.batch_size = batch_size
        self.linger = linger
        self.max_backoff = max_backoff
        self.queue: queue.Queue[dict[str, Any]] = queue.Queue(maxsize=max_queue)
        self.dropped = 0
        self.rejected = 0
        self.sent = 0
        self.session = uuid.uuid4().hex[:16]
        self._numbers = itertools.count()
        self._stop = threading.Event()
        name = f"{client.access.name}-writer"
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def submit(self, timestamp: float, values: dict[str, Any]) -> bool:
        try:
            key = f"{self.session}-{next(self._numbers)}"
            record = to_record(self.client.access.fields, self.robot, timestamp, values, key)
        except (KeyError, TypeError, ValueError) as error:
            log.error("sample not sent, it does not fit the data type: %s", error)
            self.rejected += 1
            return False
        try:
            self.queue.put_nowait(record)
            return True
        except queue.Full:
            self.dropped += 1
            return False

    def _take_batch(self) -> list[dict[str, Any]]:
        try:
            batch = [self.queue.get(timeout=self.linger)]
        except queue.Empty:
            return []
        deadline = time.monotonic() + self.linger
        while len(batch) < self.batch_size:
            try:
                batch.append(self.queue.get(timeout=max(0.0, deadline - time.monotonic())))
            except queue.Empty:
                break
        return batch

    def _send(self, batch: list[dict[str, Any]]) -> None:
        delay = 0.1
        while not self._stop.is_set():
            try:
                self.client.post(batch)
                self.sent += len(batch)
                return
            except StoreError as error:
                if not error.retryable:
                    log.error("batch of %d records refused: %s", len(batch), error)
                    self.rejected += len(batch)
                    return
                log.warning("store unavailable (%s), retrying in %.1f s", error, delay)
                self._stop.wait(delay * (1.0 + random.random() / 2))
                delay = min(self.max_backoff, delay * 2)

    def _run(self) -> None:
        while not self._stop.is_set():
            batch = self._take_batch()
            if batch:
                self._send(batch)
                for _ in batch:
                    self.queue.task_done()

    def flush(self, timeout: float = 10.0) -> bool:
        """Wait until everything submitted so far was sent (or refused)."""
        deadline = time.monotonic() + timeout
        while self.queue.unfinished_tasks:
            if time.monotonic() > deadline:
                return False
            time.sleep(0.01)
        return True

    def close(self, timeout: float = 10.0) -> None:
        self.flush(timeout)
        self._stop.set()
        self._thread.join(timeout)
