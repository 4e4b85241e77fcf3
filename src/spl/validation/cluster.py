"""``spl validate --scheduler``: the products of a run on a Dask cluster (docs/ci.md).

Dask distributed schedules the products; spl only says what a product's task is. The
client packs each product line's files (the models, ``products/*.yaml``, capability
files) and sends them to the workers, which parse a line once and keep it for every
later product of the same content: nothing is read from a shared disk. A worker writes
the files under a temporary folder of its own and loads them there; the messages it
returns name the folder the user gave, so verdicts, the JUnit report and the exit code
are those of ``--jobs 1``, byte for byte.

A product whose worker dies (killed, out of memory, its machine gone) is run again on
another worker by the scheduler; its result is taken once, from the run that finished.
Results are reported in the order of the plan whatever order they finish in. Each
rehearsal (``--smoke``) takes free ports for its ROS master and nodes, so several on one
host never collide.
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import logging
import os
import shutil
import tempfile
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import urlsplit

from spl import __version__
from spl.validation.line import (
    CaseChecks,
    CaseResult,
    LoadedLine,
    ProductCase,
    load_lines,
    run_planned,
)
from spl.validation.workers import ATTEMPTS  # as many tries as on this machine's workers

if TYPE_CHECKING:
    from distributed import Client, Future

INSTALL = "pip install 'spl-robotics[cluster]'"
# How long a separately started scheduler may take to have a worker.
WORKER_WAIT = 60.0
LOCAL_WORKERS_PER_CPU = 4  # local:N at most, per CPU of the machine


class ClusterProblem(Exception):
    """The cluster cannot run the products (no Dask, no scheduler, no worker, another
    spl on the workers); the message says what to do."""


@dataclass(frozen=True)
class LineFiles:
    """What the workers get of a product line: its files, by path in its folder."""

    key: str  # a digest of the contents: a worker loads each content once
    name: str  # the line's name in the report
    folder: str  # the folder as the user gave it: messages name it
    files: tuple[tuple[str, bytes], ...]


def pack(loaded: LoadedLine) -> LineFiles:
    """Every regular file of the line's folder but hidden and cache folders'."""
    root = Path(loaded.directory)
    files = []
    for path in sorted(root.rglob("*")):
        parts = path.relative_to(root).parts
        if any(p.startswith(".") or p == "__pycache__" for p in parts) or not path.is_file():
            continue
        files.append((path.relative_to(root).as_posix(), path.read_bytes()))
    digest = hashlib.sha256(__version__.encode())
    for name, data in files:
        digest.update(name.encode() + b"\0" + hashlib.sha256(data).digest())
    return LineFiles(digest.hexdigest(), loaded.name, str(root), tuple(files))


@contextlib.contextmanager
def connect(address: str) -> Iterator[Client]:
    """A client of the scheduler at ``address`` (``tcp://HOST:PORT``, ``tls://...``), or
    of a LocalCluster of N single-threaded worker processes (``local:N``)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ClusterProblem(f"--scheduler needs Dask distributed: {INSTALL}") from None
    workers = _local_workers(address)
    logging.getLogger("distributed").setLevel(logging.ERROR)
    with contextlib.ExitStack() as stack:
        if workers is not None:
            cluster = stack.enter_context(
                LocalCluster(
                    n_workers=workers,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    silence_logs=logging.ERROR,
                )
            )
            client = stack.enter_context(Client(cluster))
        else:
            try:
                client = stack.enter_context(Client(address, timeout="10s"))
            except (OSError, TimeoutError) as exc:
                raise ClusterProblem(f"no Dask scheduler answers at {address}: {exc}") from None
            try:
                client.wait_for_workers(1, timeout=WORKER_WAIT)
            except TimeoutError:
                raise ClusterProblem(
                    f"the scheduler at {address} has had no worker for {WORKER_WAIT:.0f} s: "
                    f"start some with 'dask worker {address} --nthreads 1'"
                ) from None
        _check_versions(client)
        yield client


def _local_workers(address: str) -> int | None:
    """N of ``local:N``, None for a scheduler's ``tcp://HOST:PORT`` (or ``tls://``); a
    ClusterProblem for anything else, before anything is started. N is at most four
    per CPU: a rehearsal mostly waits on its ROS masters, but a LocalCluster of
    thousands of processes would only bring the machine down."""
    if address.startswith("local:"):
        count, most = address.removeprefix("local:"), LOCAL_WORKERS_PER_CPU * (os.cpu_count() or 1)
        if not (count.isascii() and count.isdigit() and len(count) < 7 and 1 <= int(count) <= most):
            raise ClusterProblem(
                f"--scheduler {address}: local:N takes 1 to {most} workers "
                f"({LOCAL_WORKERS_PER_CPU} per CPU of this machine)"
            )
        return int(count)
    if not address.startswith(("tcp://", "tls://")):
        raise ClusterProblem(
            f"--scheduler {address}: give tcp://HOST:PORT (a running scheduler) or "
            "local:N (N workers on this machine)"
        )
    try:
        parts = urlsplit(address)
        complete = bool(parts.hostname and parts.port) and not (parts.path or parts.query)
    except ValueError:  # a port out of range or not a number
        complete = False
    if not complete:
        raise ClusterProblem(
            f"--scheduler {address}: give the scheduler's host and port, as tcp://HOST:PORT"
        )
    return None


def _check_versions(client: Client) -> None:
    versions = client.run(_spl_version)
    other = {worker: v for worker, v in versions.items() if v != __version__}
    if other:
        worker, version = sorted(other.items())[0]
        raise ClusterProblem(
            f"worker {worker} runs spl {version}, this is spl {__version__}: install the "
            "same spl on every worker"
        )


def _spl_version() -> str:
    """Run on each worker: the spl that worker imports."""
    return __version__


def run_on_cluster(
    client: Client,
    lines: list[LoadedLine],
    cases: list[ProductCase],
    checks: CaseChecks,
    smoke: bool,
    on_result: Callable[[CaseResult], None] | None = None,
) -> list[CaseResult]:
    """Every case's result, in the order of ``cases``."""
    from distributed import KilledWorker, as_completed

    packed = {i: pack(loaded) for i, loaded in enumerate(lines) if loaded.line is not None}
    shipped = {i: client.scatter(files, broadcast=True, hash=True) for i, files in packed.items()}
    futures = {}
    for index, case in enumerate(cases):
        if lines[case.line].line is None:  # nothing to send: its problems are here
            continue
        futures[index] = _submit(client, shipped[case.line], case, checks.diagrams, smoke)
    done: dict[int, CaseResult] = {}
    attempts = dict.fromkeys(futures, 1)
    pending = as_completed(list(futures.values()))
    position = {future.key: index for index, future in futures.items()}
    results: list[CaseResult] = []

    def report_ready() -> None:
        while len(results) < len(cases):
            index = len(results)
            case = cases[index]
            if lines[case.line].line is None:
                result = run_planned(lines[case.line], case, checks)
            elif index in done:
                result = done.pop(index)
            else:
                return
            results.append(result)
            if on_result:
                on_result(result)

    report_ready()
    for future in pending:
        index = position.pop(future.key)
        lost = future.status != "finished" and isinstance(future.exception(), KilledWorker)
        if future.status == "finished":
            done[index] = future.result()
        elif lost and attempts[index] < ATTEMPTS:  # its workers died: once more
            attempts[index] += 1
            case = cases[index]
            again = _submit(client, shipped[case.line], case, checks.diagrams, smoke)
            position[again.key] = index
            pending.add(again)
        else:
            why = (
                f"lost: the workers running it kept ending ({future.exception()})"
                if lost
                else f"internal error: {type(future.exception()).__name__}: {future.exception()}"
            )
            done[index] = CaseResult(
                lines[cases[index].line].name, cases[index].name, "error", (why,)
            )
        report_ready()
    return results


def _submit(client: Client, line: object, case: ProductCase, diagrams: bool, smoke: bool) -> Future:
    """One product as a task of its own (``pure=False``: a product run twice, after its
    worker died, is a new task, not the lost one's result)."""
    return client.submit(run_remote, line, case, diagrams, smoke, pure=False)


# -- on a worker ----------------------------------------------------------------------------
def run_remote(line: LineFiles, case: ProductCase, diagrams: bool, smoke: bool) -> CaseResult:
    """One product on a worker, from the line's files: the result names the user's
    folder, never the worker's copy."""
    folder, loaded = _unpacked(line)
    if case.selection_file is not None:
        relative = Path(case.selection_file).relative_to(line.folder)
        case = replace(case, selection_file=folder / relative)
    rehearse = _rehearsal() if smoke else None
    if isinstance(rehearse, str):  # no ROS 1 on this worker
        return CaseResult(line.name, case.name, "error", (rehearse,))
    result = run_planned(loaded, case, CaseChecks(rehearse, diagrams))
    return _relocated(result, str(folder), line.folder)


# The lines this worker has loaded, by content; the lock keeps a worker with several
# threads from loading one twice.
_LOADED: dict[str, tuple[Path, LoadedLine]] = {}
_LOADING = threading.Lock()


def _unpacked(line: LineFiles) -> tuple[Path, LoadedLine]:
    """The line written to a folder of this worker and loaded, once per content (the
    folder lives as long as the worker process)."""
    with _LOADING:
        if line.key not in _LOADED:
            folder = Path(tempfile.mkdtemp(prefix="spl-line-")) / Path(line.folder).name
            atexit.register(shutil.rmtree, folder.parent, ignore_errors=True)
            for name, data in line.files:
                path = folder / name
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_bytes(data)
            [loaded] = load_lines([folder])
            _LOADED[line.key] = folder, replace(loaded, name=line.name)
        return _LOADED[line.key]


@cache
def _rehearsal() -> Callable[[dict[str, bytes]], tuple[list[str], str]] | str:
    """This worker's live check, bound to its own ROS 1; the reason when it has none."""
    from functools import partial

    from spl.smoke.processes import RosMissing, find_ros
    from spl.smoke.rehearsal import rehearse_files

    try:
        return partial(rehearse_files, ros=find_ros())
    except RosMissing as exc:
        return f"this worker cannot rehearse: {exc}"


def _relocated(result: CaseResult, worker_folder: str, folder: str) -> CaseResult:
    def moved(texts: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(text.replace(worker_folder, folder) for text in texts)

    return replace(
        result,
        messages=moved(result.messages),
        warnings=tuple(
            replace(warning, text=warning.text.replace(worker_folder, folder))
            for warning in result.warnings
        ),
        checked=result.checked.replace(worker_folder, folder),
    )
