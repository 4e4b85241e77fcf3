"""Pausing Python's cyclic garbage collector while a model is built.

Reading, encoding, resolving and validating build large graphs of objects that all stay
alive while the work runs. The collector's passes over them free nothing and, as the
graph grows, make the work superlinear in its size. Pausing it is the same move
everywhere; what differs is what becomes of the objects once collection resumes, so that
is the one choice :func:`without_cyclic_gc` asks for. What a paused block is done with
early can go at once by :func:`release`.
"""

from __future__ import annotations

import gc
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from typing import Literal

Afterwards = Literal["kept", "dropped", "left"]


@contextmanager
def without_cyclic_gc(
    afterwards: Afterwards = "kept", first: Callable[[], None] | None = None
) -> Iterator[None]:
    """Cyclic garbage collection paused for the block, then resumed with what the block
    allocated treated as ``afterwards`` says:

    - ``"kept"``: the block built a model that lives on (a model just read). It is moved
      to the oldest generation (a freeze and unfreeze: no object is visited); the first
      young collection would otherwise walk all of it (about a second after reading a
      10,000-node .tsm). Skipped when something else holds objects frozen.
    - ``"dropped"``: the block's objects are garbage once it is done (one validated
      product: its models, bundle and reports). One collection of the youngest
      generation scans each of them once, as garbage, instead of two or three times
      while still in use, and moves on what stays (the result, the caches).
    - ``"left"``: the collector takes them up as usual (the resolution's cycles).

    ``first``, when given, runs after the block with collection still paused: what must
    not wait for a collection (the editor sending a check's findings).
    """
    collecting = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if collecting:
            if first is not None:
                first()
            if afterwards == "kept" and gc.get_freeze_count() == 0:
                gc.freeze()
                gc.unfreeze()
            elif afterwards == "dropped":
                gc.collect(0)
            gc.enable()


def release(objects: Iterable[object]) -> None:
    """Forget the state of each of ``objects``, which nothing reads again: the cycles
    among them (a model's containers and contents, pyecore's slots and their owners)
    are broken, and they go as their last reference does, without waiting for the
    collector, which a block paused for them does not run (a line check resolves dozens
    of witness products one after the other: 700 MB of copies on a 1,000-node line,
    kept until the check ended)."""
    for found in objects:
        state = getattr(found, "__dict__", None)
        if state is not None:
            state.clear()


def collect_young() -> None:
    """Collect the cycles among what was allocated since the last collection (one pass
    over the youngest generation only, even while collection is paused). For a caller
    that dropped a block of work whose remains still hold cycles past :func:`release`
    (a networkx graph and its cached views, a recursive closure): a line check resolving
    hundreds of witness products one after the other would otherwise keep every one's
    remains until it ends (3.8 GB on a 10,000-node line). Objects that survive move to
    an older generation, so the next pass reads only what came after."""
    gc.collect(0)
