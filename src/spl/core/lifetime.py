"""How spl's processes end: children that follow a killed parent, and processes that
unwind on a signal even when Python loses the exception the signal handler raised.

A forked `spl validate` worker or a smoke rehearsal's roscore must not outlive spl when
spl itself is killed (SIGKILL from a CI timeout cannot be caught, so nothing in spl gets
to clean up): Linux's parent-death signal tells the child instead.

A signal handler that raises is fragile: when the signal lands while a finaliser, an
at-fork hook or ``sys.unraisablehook`` runs, Python prints "Exception ignored" and
carries on, and a worker would rehearse on while its pool waits for it. So the handler
also records the signal, and every loop that waits (the rehearsal's poll) calls
:func:`raise_if_signalled`.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
from collections.abc import Iterator

_PR_SET_PDEATHSIG = 1
_signalled: int | None = None
_owner: int | None = None  # the process that installed the handlers
_keyboard = False
_end_when_swallowed = False  # a pool worker between tasks: nothing reaches a checkpoint


def die_with_parent() -> None:
    """Ask for SIGTERM when the parent ends (Linux; elsewhere a no-op). Safe between fork
    and exec, and in a pool worker's initializer."""
    import ctypes  # here: only a process that starts children loads it

    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)


def _unwinding(signum: int) -> BaseException:
    if signum == signal.SIGINT and _keyboard:
        return KeyboardInterrupt()
    return SystemExit(128 + signum)


def _leave(signum: int, _frame: object) -> None:
    global _signalled
    if os.getpid() != _owner:
        # a forked child running with this handler inherited, before handlers of its own
        # (subprocess's child in at-fork hooks before exec, a pool worker before its
        # initializer): raising there may be swallowed ("Exception ignored"), and a pool
        # worker terminated while it starts would then wait for work for ever, its pool
        # waiting for it. The signal's own default action ends it, as without spl.
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    if _signalled is not None:
        return  # already unwinding (Ctrl-C, then the pool's SIGTERM): let cleanup finish
    _signalled = signum
    raise _unwinding(signum)


def _quiet_unraisable(unraisable: sys.UnraisableHookArgs) -> None:
    if _signalled is not None and isinstance(unraisable.exc_value, SystemExit | KeyboardInterrupt):
        if _end_when_swallowed:
            # a pool worker waits for its next products in a loop that has no
            # checkpoint: it would wait for ever, and its pool for it (a hang seen in the
            # suite: the pool's SIGTERM landed in a weakref callback after a product). The
            # signal's default action ends it; its children have die_with_parent.
            signal.signal(_signalled, signal.SIG_DFL)
            os.kill(os.getpid(), _signalled)
        return  # a signal's unwinding Python could not deliver there: the next checkpoint does
    sys.__unraisablehook__(unraisable)


def unwind_on_signals(keyboard_interrupt: bool = False, pool_worker: bool = False) -> None:
    """SIGINT and SIGTERM end this process by unwinding quietly (SystemExit 128+signal,
    or KeyboardInterrupt for SIGINT when ``keyboard_interrupt``), so ``with`` blocks stop
    what they started and no traceback is printed; a second signal does not interrupt
    that cleanup. A ``pool_worker`` whose unwinding Python swallows ends by the signal."""
    global _signalled, _owner, _keyboard, _end_when_swallowed
    _signalled, _owner, _keyboard = None, os.getpid(), keyboard_interrupt
    _end_when_swallowed = pool_worker
    signal.signal(signal.SIGINT, _leave)
    signal.signal(signal.SIGTERM, _leave)
    sys.unraisablehook = _quiet_unraisable


@contextlib.contextmanager
def checkpointed() -> Iterator[None]:
    """A pool worker's task: its own checkpoints (a rehearsal's poll, each case's start)
    unwind a swallowed signal through its cleanup, so it is not ended abruptly inside;
    the task's end is one more checkpoint, before the worker waits for work again."""
    global _end_when_swallowed
    ending, _end_when_swallowed = _end_when_swallowed, False
    try:
        yield
    finally:
        _end_when_swallowed = ending
    raise_if_signalled()


def raise_if_signalled() -> None:
    """Unwind now if a signal arrived whose exception Python swallowed."""
    if _signalled is not None and os.getpid() == _owner:
        raise _unwinding(_signalled)
