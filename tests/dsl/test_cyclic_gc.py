"""The one pause of the cyclic garbage collector (spl.core.cyclic_gc) and its three
endings: a model read is kept in the oldest generation, a validated product's objects
are collected once, the resolution's are left to the collector."""

from __future__ import annotations

import gc
from typing import ClassVar

import pytest

from spl.core.cyclic_gc import without_cyclic_gc


class Node:
    def __init__(self) -> None:
        self.me = self  # a cycle: only the cyclic collector frees it


@pytest.fixture
def collections():
    started: list[int] = []

    def count(phase: str, info: dict) -> None:
        if phase == "start":
            started.append(info["generation"])

    gc.collect()
    gc.callbacks.append(count)
    yield started
    gc.callbacks.remove(count)
    gc.enable()


def test_a_kept_model_moves_to_the_oldest_generation_unvisited(collections):
    with without_cyclic_gc():
        model = [Node() for _ in range(1000)]
        assert not gc.isenabled()
    assert gc.isenabled() and collections == []
    oldest = {id(o) for o in gc.get_objects(generation=2)}
    assert all(id(n) in oldest for n in model)


class Counted(Node):
    freed: ClassVar[list[int]] = [0]

    def __del__(self) -> None:
        Counted.freed[0] += 1


def test_a_dropped_block_is_collected_once_as_garbage(collections):
    Counted.freed[0] = 0
    with without_cyclic_gc("dropped"):
        for _ in range(2000):
            Counted()  # garbage at once, never collected while the block runs
        assert collections == [] and Counted.freed[0] == 0
    assert Counted.freed[0] == 2000  # freed on leaving, before anything else allocates
    assert gc.isenabled() and collections == [0]


def test_a_left_block_only_resumes_the_collector(collections):
    with without_cyclic_gc("left"):
        model = [Node() for _ in range(1000)]
        assert collections == []
    oldest = gc.get_objects(generation=2)  # the first thing after: nothing moved them there
    assert gc.isenabled()
    assert model and not any(type(o) is Node for o in oldest)


def test_a_pause_inside_a_pause_leaves_the_outer_one_in_charge(collections):
    with without_cyclic_gc("dropped"):
        with without_cyclic_gc("left"):
            pass
        assert not gc.isenabled()
    assert gc.isenabled() and collections == [0]
