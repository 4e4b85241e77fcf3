"""``spl validate --jobs N``: the products of a run in N forked worker processes that
survive the loss of a worker (docs/ci.md).

A worker that ends in the middle of a product (killed by the out-of-memory killer or by
hand, a crash in a native library) must neither hang the run nor lose a product. A
``multiprocessing.Pool`` does both: it starts a new worker but never hands the lost task
to anyone, and waits for its result for ever. So each worker here is a process of its
own with a pipe, told which products to run a few at a time, and it sends each result
as soon as it has it. The run then knows exactly which product a dead worker was on:
that one is run again by a new worker, the ones queued behind it go back to the queue,
and a product whose workers end :data:`ATTEMPTS` times is reported as an error. Results
are handed on in the order of the plan, whatever order they arrive in.

The workers are forked after the lines are loaded, so they inherit the parsed models
(and their SAT formulas) and receive only the positions of their products in the plan.
"""

from __future__ import annotations

import contextlib
import signal
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from multiprocessing import get_context
from multiprocessing.connection import Connection, wait
from typing import TYPE_CHECKING, Generic, TypeVar

from spl.core.lifetime import raise_if_signalled

if TYPE_CHECKING:
    from multiprocessing.context import ForkContext, ForkProcess

# A product whose workers end this many times is reported as an error, not run again.
ATTEMPTS = 3
# How long the run waits between two checks for a Ctrl-C that Python swallowed.
TICK = 0.2

Task = TypeVar("Task")
Result = TypeVar("Result")


@dataclass(eq=False)  # each worker is itself: kept in sets and dicts by identity
class _Worker:
    process: ForkProcess
    connection: Connection
    assigned: deque[int] = field(default_factory=deque)  # sent, not yet answered


class ForkedWorkers(Generic[Task, Result]):
    """``work`` over ``tasks`` in ``jobs`` forked processes, each result yielded in
    task order by :meth:`results`; ``lost(task, why)`` stands for the result of a task
    whose workers kept ending."""

    def __init__(
        self,
        tasks: Sequence[Task],
        work: Callable[[Task], Result],
        lost: Callable[[Task, str], Result],
        jobs: int,
        start: Callable[[], None],
        chunk: int = 1,
    ) -> None:
        self.tasks, self.work, self.lost, self.start = tasks, work, lost, start
        self.jobs, self.chunk = max(1, min(jobs, len(tasks))), max(1, chunk)
        self.queue: deque[int] = deque(range(len(tasks)))
        self.attempts = [0] * len(tasks)
        self.done: dict[int, Result] = {}
        self.workers: list[_Worker] = []

    def results(self) -> Iterator[Result]:
        """Every task's result, in task order, as soon as it and those before it are in."""
        context = get_context("fork")
        following = 0
        try:
            while following < len(self.tasks):
                self._fill(context)
                self._receive()
                while following in self.done:
                    yield self.done.pop(following)
                    following += 1
        finally:
            self._stop()

    def _fill(self, context: ForkContext) -> None:
        """Start workers up to ``jobs`` while there is work, and give idle ones a chunk."""
        while self.queue and len(self.workers) < self.jobs:
            self.workers.append(self._spawn(context))
        for worker in list(self.workers):
            if self.queue and not worker.assigned:
                chunk = [self.queue.popleft() for _ in range(min(self.chunk, len(self.queue)))]
                try:
                    worker.connection.send(chunk)
                except OSError:  # it ended while idle: the chunk goes back, uncounted
                    self.queue.extendleft(reversed(chunk))
                    self._bury(worker)
                else:
                    worker.assigned.extend(chunk)

    def _spawn(self, context: ForkContext) -> _Worker:
        ours, theirs = context.Pipe()
        process = context.Process(
            target=_serve, args=(theirs, self.tasks, self.work, self.start), daemon=True
        )
        process.start()
        theirs.close()
        return _Worker(process, ours)

    def _receive(self) -> None:
        """Results that came in, and the work of workers that ended given out again."""
        busy = [w for w in self.workers if w.assigned]
        waiting: dict[object, _Worker] = {w.connection: w for w in busy}
        waiting |= {w.process.sentinel: w for w in busy}
        ready = wait([w.connection for w in busy] + [w.process.sentinel for w in busy], TICK)
        raise_if_signalled()  # a Ctrl-C that Python swallowed ends the wait too
        for worker in dict.fromkeys(waiting[r] for r in ready):
            if not self._read(worker):
                self._bury(worker)

    def _read(self, worker: _Worker) -> bool:
        """Every result the worker has sent; False when it has ended."""
        try:
            while worker.connection.poll():
                index, result = worker.connection.recv()
                worker.assigned.remove(index)
                self.done[index] = result
        except (EOFError, OSError):
            return False
        return worker.process.exitcode is None

    def _bury(self, worker: _Worker) -> None:
        """The worker ended: the task it was on counts an attempt, its others go back."""
        worker.process.join()
        worker.connection.close()
        self.workers.remove(worker)
        if not worker.assigned:
            return
        current, *queued = worker.assigned
        self.queue.extendleft(reversed(queued))
        self.attempts[current] += 1
        if self.attempts[current] < ATTEMPTS:
            self.queue.appendleft(current)
        else:
            why = f"the worker process running it ended {ATTEMPTS} times ({_ending(worker)})"
            self.done[current] = self.lost(self.tasks[current], why)

    def _stop(self) -> None:
        """The workers end: idle ones when told to (None: the pipe's closing is not
        enough, as workers forked later hold copies of its end here), busy ones (the run
        was interrupted: Ctrl-C, an error) on SIGTERM, which they unwind through their
        own cleanup; SIGKILL after 30 s."""
        for worker in self.workers:
            if worker.assigned and worker.process.exitcode is None:
                worker.process.terminate()
            else:
                with contextlib.suppress(OSError):
                    worker.connection.send(None)
        for worker in self.workers:
            worker.process.join(30)
            if worker.process.exitcode is None:
                worker.process.kill()
                worker.process.join()
            worker.connection.close()
        self.workers = []


def _ending(worker: _Worker) -> str:
    code = worker.process.exitcode
    if code is not None and code < 0:
        return f"last: killed by {signal.Signals(-code).name}"
    return f"last: exit status {code}"


def _serve(
    connection: Connection,
    tasks: Sequence[Task],
    work: Callable[[Task], Result],
    start: Callable[[], None],
) -> None:
    """A worker: runs the tasks it is given, sending each result at once, until told to
    end (None)."""
    start()
    while True:
        try:
            chunk = connection.recv()
        except EOFError:  # the run has gone without a word
            return
        if chunk is None:
            return
        for index in chunk:
            connection.send((index, work(tasks[index])))
