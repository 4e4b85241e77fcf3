"""How spl processes end on a signal (spl.core.lifetime), in a fresh interpreter each time:
the cases are races in real runs (a Ctrl-C landing in a finaliser or in a child between
fork and exec), made certain here by signalling from exactly that place."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap

import pytest


def run(script: str) -> subprocess.CompletedProcess[str]:
    code = (
        "import os, signal\nfrom spl.core.lifetime import raise_if_signalled, unwind_on_signals\n"
    )
    return subprocess.run(
        [sys.executable, "-c", code + textwrap.dedent(script)],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip


@pytest.mark.parametrize("signum, status", [("SIGINT", 130), ("SIGTERM", 143)])
def test_a_signal_swallowed_in_a_finaliser_still_ends_the_process_quietly(signum, status):
    result = run(f"""
        unwind_on_signals()
        class Finaliser:
            def __del__(self):
                os.kill(os.getpid(), signal.{signum})
                sum(range(1000))  # the handler runs here, where Python cannot raise
        Finaliser()
        print("carried on")
        raise_if_signalled()
        print("not reached")
    """)
    assert result.returncode == status
    assert result.stdout == "carried on\n"
    assert result.stderr == ""  # no "Exception ignored" for a signal's unwinding


def test_ctrl_c_is_a_keyboard_interrupt_where_the_command_asks_for_it():
    result = run("""
        unwind_on_signals(keyboard_interrupt=True)
        try:
            os.kill(os.getpid(), signal.SIGINT)
            sum(range(1000))
        except KeyboardInterrupt:
            print("interrupted")
    """)
    assert (result.returncode, result.stdout, result.stderr) == (0, "interrupted\n", "")


def test_a_second_signal_does_not_interrupt_the_cleanup_of_the_first():
    result = run("""
        unwind_on_signals()
        try:
            os.kill(os.getpid(), signal.SIGINT)
            sum(range(1000))
        finally:
            os.kill(os.getpid(), signal.SIGTERM)  # the pool's terminate, during cleanup
            sum(range(1000))
            print("cleaned up")
    """)
    assert (result.returncode, result.stdout, result.stderr) == (130, "cleaned up\n", "")


@pytest.mark.parametrize("signum", ["SIGINT", "SIGTERM"])
def test_a_forked_child_without_handlers_of_its_own_ends_by_the_signal_quietly(signum):
    """Like subprocess's child running at-fork hooks before exec, or a validate pool
    worker terminated before its initializer ran (it then waited for work for ever and
    its pool for it: a hang seen in the suite under load)."""
    result = run(f"""
        unwind_on_signals()
        pid = os.fork()
        if pid == 0:
            os.kill(os.getpid(), signal.{signum})
            sum(range(1000))
            os._exit(7)
        print(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]))
    """)
    expected = f"{-getattr(signal, signum)}\n"
    assert (result.returncode, result.stdout, result.stderr) == (0, expected, "")


@pytest.mark.parametrize("pool_worker", [True, False])
def test_a_pool_worker_whose_unwinding_is_swallowed_ends_by_the_signal(pool_worker):
    """The pool's SIGTERM landing in a weakref callback after a product: the worker's
    SystemExit was swallowed, it went back to wait for work on a lock its pool held, and
    the pool waited for it for ever (a hang seen in the suite). Any other process carries
    on to its next checkpoint, as before."""
    result = run(f"""
        import threading, weakref
        unwind_on_signals(pool_worker={pool_worker})
        class Model:
            pass
        def callback(_):
            os.kill(os.getpid(), signal.SIGTERM)
            sum(range(1000))  # the handler runs here, where Python cannot raise
        model = Model()
        watch = weakref.ref(model, callback)
        del model
        print("waiting for work", flush=True)
        held = threading.Lock()
        held.acquire()
        held.acquire(timeout=1)  # as the worker waits for the pool's queue lock
        raise_if_signalled()
    """)
    if pool_worker:
        assert (result.returncode, result.stdout) == (-signal.SIGTERM, "")
    else:
        assert (result.returncode, result.stdout) == (143, "waiting for work\n")
    assert result.stderr == ""


def test_a_pool_workers_task_unwinds_a_swallowed_signal_through_its_cleanup():
    """Inside a task the worker is not ended abruptly (a rehearsal would leave its
    processes and temporary folder): the task's end is a checkpoint that unwinds."""
    result = run("""
        import weakref
        from spl.core.lifetime import checkpointed
        unwind_on_signals(pool_worker=True)
        class Model:
            pass
        def callback(_):
            os.kill(os.getpid(), signal.SIGTERM)
            sum(range(1000))  # the handler runs here, where Python cannot raise
        try:
            with checkpointed():
                model = Model()
                watch = weakref.ref(model, callback)
                del model
                print("task goes on", flush=True)
        finally:
            print("cleaned up", flush=True)
    """)
    assert (result.returncode, result.stdout) == (143, "task goes on\ncleaned up\n")
    assert result.stderr == ""
