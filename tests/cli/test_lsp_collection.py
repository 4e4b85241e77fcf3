"""The language server collects a check's garbage after the check's findings are sent,
not before: the editor sees them a collection sooner (docs/editors.md)."""

from __future__ import annotations

import asyncio
import gc
import threading
import weakref

import pytest

from spl.lsp.server import collected_once_sent


class Node:
    """A model element pointing at itself: garbage only the cyclic collector frees."""

    def __init__(self) -> None:
        self.me = self


@pytest.fixture
def loop():
    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    yield loop
    loop.call_soon_threadsafe(loop.stop)
    thread.join(5)
    loop.close()


def test_garbage_of_a_check_is_collected_once_its_findings_are_sent(loop) -> None:
    assert gc.isenabled()
    seen: list[tuple[str, bool]] = []
    with collected_once_sent(loop):
        assert not gc.isenabled()
        cycle = weakref.ref(Node())  # the check's model, garbage when the check ends
        loop.call_soon_threadsafe(lambda: seen.append(("sent", cycle() is not None)))
    seen.append(("after", cycle() is not None))
    assert seen == [("sent", True), ("after", False)]
    assert gc.isenabled()


def test_a_caller_that_paused_collection_keeps_it_paused(loop) -> None:
    gc.disable()
    try:
        with collected_once_sent(loop):
            cycle = weakref.ref(Node())
        assert not gc.isenabled() and cycle() is not None
    finally:
        gc.enable()
