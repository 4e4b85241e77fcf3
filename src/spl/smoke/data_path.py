"""The data path of a rehearsal: the bundle's own services, writers and readers, live.

For a bundle with stores, ``spl smoke`` starts each generated service (uvicorn on a
free loopback port, an embedded SQLite database in the run's folder, a random token in
its environment, the transformer's period shortened), and the ROS 1 launch files start
the **generated** writer and reader nodes (``clients/ros1/<package>``) against it; only
the robots' own nodes are stand-ins. The stand-in publishers on writers' topics send a
known run of values and the stand-in subscribers on readers' topics record what they
get. Each flow of data then gets its rows: the values sent, stored once each in order
(the store's raw records), refined as the model's transform says (computed here from
``resolved.tsm``, not taken from the service, so a transform changed by hand in the
generated service fails), and received by the reader's subscribers once each, in order.

A fault round comes with it: once a third of the values of the first store's writers
are stored, its service is killed (SIGKILL) and started again on the same database and
port; the writers' retries must bring every record in, and nothing may arrive twice
downstream.

The services run with this interpreter; when it lacks what the generated service
imports, the rehearsal says so in one line and stands in for the writers and readers
instead (:func:`missing`).
"""

from __future__ import annotations

import json
import os
import secrets
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from spl.generators.store_contract import StoreContext, client_settings, store_context
from spl.metamodels import tsm
from spl.resolver.architecture.product import ResolvedProduct
from spl.smoke.data_checks import (
    cloud_stores,
    compiled_transforms,
    difference,
    planned_to,
    refine,
    same,
    sent_to,
)
from spl.smoke.live import Row
from spl.smoke.plan import SmokePlan
from spl.smoke.processes import Processes, free_port

if TYPE_CHECKING:
    from spl.metamodels import tsm_types

TRANSFORM_PERIOD = "0.3"  # seconds: the rehearsal need not wait the model's period
START_TIMEOUT = 30.0
FAULT_SHARE = 3  # the service is killed once a third of the values are stored
DATA_ROWS = ("stored from ", "refined ", "fault round")  # the interface column of its rows


def missing(bundle: Path, system: Any) -> str | None:
    """Why this interpreter cannot run the bundle's services (None: it can)."""
    for _, store in cloud_stores(system):
        names = store_context(store, ResolvedProduct("smoke", system, ()))
        folder = bundle / "services" / names["name"]
        check = subprocess.run(
            [sys.executable, "-c", f"import {names['package']}.app"],
            cwd=folder,
            env={**os.environ, "PYTHONPATH": str(folder), names["token_env"]: "probe"},
            capture_output=True,
            text=True,
        )
        if check.returncode != 0:
            lines = check.stderr.strip().splitlines()
            reason = lines[-1] if lines else f"exit status {check.returncode}"
            return (
                f"data path not rehearsed: the generated {names['name']} service does not "
                f"start with {sys.executable} ({reason}); pip install 'spl-robotics[services]' "
                "to run it, its writers and readers are stood in for meanwhile"
            )
    return None


@dataclass
class Service:
    """One generated store service, as the rehearsal runs it."""

    container: str
    store: tsm_types.Store
    names: StoreContext
    folder: Path
    port: int
    database: Path
    token: str = field(default_factory=lambda: secrets.token_hex(16))
    process: subprocess.Popen[bytes] | None = None
    starts: int = 0

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def get(self, path: str) -> Any:
        request = urllib.request.Request(self.url + path, headers={"Accept": "application/json"})
        with urllib.request.urlopen(request, timeout=2.0) as answer:  # nosec B310: loopback
            return json.loads(answer.read())

    def records(self, collection: str) -> list[dict[str, Any]]:
        """Every record of a collection, in id order (following the pages by id)."""
        found: list[dict[str, Any]] = []
        while True:
            after = found[-1]["id"] if found else 0
            page = self.get(f"{self.names['prefix']}/{collection}?limit=1000&after_id={after}")
            found += page["items"]
            if not page.get("next"):
                return found


class DataPath:
    """The services of a bundle, started, watched, killed once and compared."""

    def __init__(self, bundle: Path, system: Any, processes: Processes, run_dir: Path) -> None:
        self.bundle, self.system, self.processes = bundle, system, processes
        self.product = ResolvedProduct("smoke", system, ())
        self.services: list[Service] = []
        for container, store in cloud_stores(system):
            names = store_context(store, self.product)
            self.services.append(
                Service(
                    container.name,
                    store,
                    names,
                    bundle / "services" / names["name"],
                    free_port(),
                    run_dir / "db" / f"{names['slug']}.db",
                )
            )
        self.transforms = compiled_transforms(system)
        self.fault: str | None = None  # what the fault round did, once done
        self.restarted_at = 0.0  # when the fault round's restart answered (monotonic)
        self.problems: list[str] = []

    # -- starting ------------------------------------------------------------------------
    def start(self) -> None:
        for service in self.services:
            service.database.parent.mkdir(parents=True, exist_ok=True)
            self._start(service)
        for service in self.services:
            self._wait_up(service)

    def _start(self, service: Service) -> None:
        names = service.names
        env = self.processes.environment(
            PYTHONPATH=str(service.folder),
            DATABASE_URL=f"sqlite:///{service.database}",
            HOST="127.0.0.1",
            PORT=str(service.port),
            **{names["token_env"]: service.token, names["period_env"]: TRANSFORM_PERIOD},
        )
        service.starts += 1
        label = f"service-{names['name']}-{service.starts}"
        argv = [sys.executable, "-m", names["package"]]
        service.process = self.processes.start(label, argv, env)

    def _wait_up(self, service: Service) -> None:
        deadline = time.monotonic() + START_TIMEOUT
        while time.monotonic() < deadline:
            try:
                service.get("/")
                return
            except (OSError, urllib.error.URLError, ValueError):
                if service.process is not None and service.process.poll() is not None:
                    break
                time.sleep(0.1)
        label = f"service-{service.names['name']}-{service.starts}"
        self.problems.append(f"{label} did not answer: {self.processes.output(label)[-300:]}")

    def launch_arguments(self) -> list[str]:
        """``<store>_url:=http://127.0.0.1:PORT`` for roslaunch, one per store."""
        return [f"{s.names['slug']}_url:={s.url}" for s in self.services]

    def environment(self) -> dict[str, str]:
        """The stores' tokens, for the generated nodes (read from the environment)."""
        return {s.names["token_env"]: s.token for s in self.services}

    # -- the fault round -------------------------------------------------------------------
    def step(self, expected: int) -> None:
        """Kill and restart the first service once a third of ``expected`` raw records
        (all its writers' values) are stored."""
        if self.fault is not None or not self.services or expected == 0:
            return
        service = self.services[0]
        try:
            stored = len(service.records("records"))
        except (OSError, urllib.error.URLError, ValueError, KeyError):
            return
        if stored * FAULT_SHARE < expected:
            return
        assert service.process is not None
        os.kill(service.process.pid, signal.SIGKILL)
        service.process.wait()
        self.processes.retire(service.process)
        self._start(service)
        self._wait_up(service)
        self.restarted_at = time.monotonic()
        self.fault = f"killed (SIGKILL) after {stored} of {expected} records, restarted"

    # -- comparing ---------------------------------------------------------------------------
    def rows(self, plan: SmokePlan, statuses: dict[str, dict[str, dict]]) -> dict[str, list[Row]]:
        """The data rows of every store, by container: a store's with its container, a
        reader's subscribers' with theirs."""
        rows: list[Row] = []
        T = tsm()
        for service in self.services:
            writers = [
                n
                for c in self.system.containers
                for n in c.nodes
                if isinstance(n, T.Writer) and n.store is service.store
            ]
            readers = [
                n
                for c in self.system.containers
                for n in c.nodes
                if isinstance(n, T.Reader) and n.store is service.store
            ]
            try:
                raw = service.records("records")
                refined = {
                    r.output.name: service.records(r.output.name) for r in service.store.refinements
                }
            except (OSError, urllib.error.URLError, ValueError, KeyError) as error:
                rows.append(
                    Row(
                        service.container,
                        service.names["name"],
                        "(service)",
                        service.names["prefix"],
                        "answering",
                        f"not answering: {error}",
                        False,
                    )
                )
                continue
            sent = {w.name: sent_to(plan, statuses, w) for w in writers}
            for writer in writers:
                rows.append(self._stored_row(service, writer, sent[writer.name], raw))
            for refinement in service.store.refinements:
                rows.append(self._refined_row(service, refinement, raw, refined))
            for reader in readers:
                rows += self._received_rows(plan, statuses, service, reader, refined)
            if service is self.services[0] and any(len(v) for v in sent.values()):
                rows.append(
                    Row(
                        service.container,
                        service.names["name"],
                        "fault round",
                        service.names["prefix"],
                        "killed and restarted mid-run",
                        self.fault or "not yet",
                        self.fault is not None,
                    )
                )
        found: dict[str, list[Row]] = {}
        for row in rows:
            found.setdefault(row.container, []).append(row)
        return found

    def expected_raw(self, plan: SmokePlan) -> int:
        """How many values the first store's writers' publishers will have sent."""
        if not self.services:
            return 0
        T = tsm()
        writers = [
            n
            for c in self.system.containers
            for n in c.nodes
            if isinstance(n, T.Writer) and n.store is self.services[0].store
        ]
        return sum(planned_to(plan, w) for w in writers)

    def _stored_row(
        self, service: Service, writer: Any, sent: list[list[Any]], raw: list[dict[str, Any]]
    ) -> Row:
        robot = client_settings(writer.eContainer(), writer, self.product)["robot_id"]
        fields = [f.name for f in writer.dataType.fields]
        stored = [[r["data"][f] for f in fields] for r in raw if r["robot"] == robot]
        ok = same(stored, sent) and len(sent) > 0
        seen = f"{len(stored)} stored" + ("" if ok else difference(stored, sent))
        return Row(
            service.container,
            service.names["name"],
            f"stored from {writer.name}",
            f"{service.names['prefix']}/records",
            f"the {len(sent)} values sent, once each, in order",
            seen,
            ok,
        )

    def _refined_row(
        self,
        service: Service,
        refinement: Any,
        raw: list[dict[str, Any]],
        refined: dict[str, list[dict[str, Any]]],
    ) -> Row:
        name = refinement.output.name
        fields = [f.name for f in refinement.output.fields]
        expected = refine(self.transforms, refinement, raw)
        rows = refined[name]
        got = {r["raw_id"]: [r[f] for f in fields] for r in rows}
        want = {raw_id: [values[f] for f in fields] for raw_id, values in expected.items()}
        ok = sorted(got) == sorted(want) and all(same([got[k]], [want[k]]) for k in want)
        ok = ok and len(rows) == len(got) and bool(want)  # once each, and something refined
        seen = f"{len(rows)} refined"
        if not ok:
            wrong = [k for k in want if k in got and not same([got[k]], [want[k]])]
            seen += f"; raw ids expected {sorted(want)}, refined {sorted(got)}" + (
                f"; raw {wrong[0]}: {got[wrong[0]]} not {want[wrong[0]]}" if wrong else ""
            )
        return Row(
            service.container,
            service.names["name"],
            f"refined {name}",
            f"{service.names['prefix']}/{name}",
            f"{refinement.transform.name} of each stored record ({len(want)})",
            seen,
            ok,
        )

    def _received_rows(
        self,
        plan: SmokePlan,
        statuses: dict[str, dict[str, dict]],
        service: Service,
        reader: Any,
        refined: dict[str, list[dict[str, Any]]],
    ) -> list[Row]:
        fields = [f.name for f in reader.dataType.fields]
        wanted = [[r[f] for f in fields] for r in refined.get(reader.dataType.name, [])]
        publisher = f"{reader.eContainer().name}.{reader.name}.records"
        rows = []
        for container in plan.containers:
            for node in container.nodes:
                if node.role == "endpoint":
                    continue
                for interface in node.interfaces:
                    if not interface.kind.subscribes or publisher not in interface.sources:
                        continue
                    entry = (
                        statuses.get(container.name, {})
                        .get(node.ros_name, {})
                        .get("interfaces", {})
                        .get(interface.name, {})
                    )
                    got = [v for source, v in entry.get("values", []) if source == publisher]
                    ok = same(got, wanted) and bool(wanted)
                    seen = f"{len(got)} received" + ("" if ok else difference(got, wanted))
                    rows.append(
                        Row(
                            container.name,
                            node.name,
                            interface.name,
                            interface.ros_name,
                            f"the {len(wanted)} {reader.dataType.name} records of "
                            f"{reader.name}, once each, in order",
                            seen,
                            ok,
                        )
                    )
        return rows
