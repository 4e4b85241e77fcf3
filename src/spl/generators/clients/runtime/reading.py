"""A reader node's side of its store (docs/services.md, "Robot-side writers and
readers"): the refined records that appeared since the last poll, each once, and the
wait for the subscribers a record must reach before it is published.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any

from .transport import StoreClient

log = logging.getLogger(__name__)


class Listeners:
    """Holds a reader's records back until ``wanted`` subscribers are connected to its
    publisher (``connected()`` counts them). A ROS topic keeps no history: a record
    published before a subscriber is connected never reaches it, so a reader that
    published the store's records at once lost the first ones to the subscribers that
    came up a moment after it. Each record waits here, in order, in the thread that
    fetched it, which fetches nothing more meanwhile: what is not published yet stays in
    the store, and nothing is dropped or published twice.

    ``changed()`` wakes the wait at once (rospy reports every connection made or lost);
    without it the count is read again every ``recheck`` seconds."""

    def __init__(
        self,
        connected: Callable[[], int],
        wanted: int,
        stop: threading.Event,
        say: Callable[[str], Any] = log.info,
        recheck: float = 0.1,
    ) -> None:
        self.connected, self.wanted, self.stop = connected, max(0, wanted), stop
        self.say, self.recheck = say, recheck
        self._condition = threading.Condition()

    def changed(self) -> None:
        with self._condition:
            self._condition.notify_all()

    def wait(self) -> bool:
        """True once ``wanted`` subscribers are connected; False if the node stops first."""
        said = False
        with self._condition:
            while not self.stop.is_set():
                count = self.connected()
                if count >= self.wanted:
                    return True
                if not said:
                    self.say(
                        f"holding records until {self.wanted} subscribers are "
                        f"connected ({count} now)"
                    )
                    said = True
                self._condition.wait(self.recheck)
        return False


class PollingReader:
    """Fetches the refined records that appeared since the last poll, each once."""

    def __init__(
        self, client: StoreClient, robot: str | None = None, start: float | None = None
    ) -> None:
        self.client = client
        self.robot = robot
        self.start = start
        self.last_id = 0

    def poll(self) -> list[dict[str, Any]]:
        items = self.client.read(
            start=self.start, robot=self.robot, after_id=self.last_id, limit=1000
        )
        if items:
            self.last_id = max(item["id"] for item in items)
        return items
