"""``spl smoke``: start a bundle's ROS graph with the real ROS 1 and compare it live.

For every container of the bundle: a private ``roscore`` on a free port; the bundle's
own ``ros1/<container>.launch`` started by the real ``roslaunch`` with stand-ins in
place of the executables (:func:`spl.smoke.processes.write_sandbox`), except the
generated writers and readers, which run as they are when the bundle's services can
run (:mod:`spl.smoke.data_path`: the services are started first, and the data they
move is checked end to end); and the container's endpoint relaying along the resolved
architecture's flow table. Then the graph is read from each
master and from the stand-ins until every expectation of the plan holds, until
every stand-in is up and no check has changed for ``settle`` seconds (or half the
time the stand-ins took to come up, when that is longer), or until ``timeout``. All
processes are ended whatever happens (success, failure, an exception, Ctrl-C).
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from lxml import etree

from spl.core.lifetime import raise_if_signalled
from spl.pipeline import read_bundle
from spl.smoke.data_path import DATA_ROWS, DataPath, cloud_stores, missing
from spl.smoke.live import Master, Row, compare, read_statuses
from spl.smoke.plan import ContainerPlan, SmokePlan
from spl.smoke.planning import actions_of, load_plan
from spl.smoke.processes import (
    STANDIN,
    Processes,
    RosInstall,
    actionlib_missing,
    find_ros,
    free_port,
    marked_processes,
    script_command,
    standin_command,
    write_messages,
    write_sandbox,
)
from spl.smoke.report import Progress, SmokeResult

DEFAULT_TIMEOUT = 30.0
DEFAULT_SETTLE = 5.0
# after the data path's fault round a writer retries with a backoff that has grown while
# the service restarted (up to ~10 s on a loaded machine): wait that long before calling
# the counts settled (a run that passes ends as soon as every check is ok)
WRITER_RETRY = 15.0
POLL = 0.25
# roslaunch's line for a node process that ended: "[ns/Name-1] process has died [...]"
NODE_DIED = re.compile(r"\[([^\]\s]+)-\d+\] process has (?:died|finished)")
MASTER_RETRIES = 3  # roscores started again, in all, when one loses its port


def run_smoke(
    bundle: Path,
    timeout: float = DEFAULT_TIMEOUT,
    settle: float = DEFAULT_SETTLE,
    progress: Callable[[Progress], None] | None = None,
    ros: RosInstall | None = None,
) -> SmokeResult:
    """Rehearse the bundle in folder ``bundle``, given in any form (relative to the
    current directory, with ``..``, a trailing slash, through a symlink). Raises
    RosMissing without ROS 1 and ModelError when the bundle's model does not parse.

    The path is made absolute here, once, before anything reads it: roslaunch, the
    services and the generated nodes run in other working directories, so a path
    relative to ours would name another folder there (docs/smoke.md, "How it runs")."""
    bundle = bundle.resolve()
    start = time.monotonic()
    system, _ = read_bundle(bundle)
    ros = ros or find_ros()
    stores = bool(cloud_stores(system))
    skipped = missing(bundle, system) if stores else None
    actions = actions_of(system)
    unplayed = actionlib_missing(ros.python) if actions else None
    plan = load_plan(bundle, generated=stores and skipped is None, actions=unplayed is None)
    run_dir = Path(tempfile.mkdtemp(prefix="spl-smoke-"))
    try:
        with Processes(run_dir) as processes:
            data = DataPath(bundle, system, processes, run_dir) if plan.runs_data else None
            rehearsal = _Rehearsal(bundle, plan, ros, processes, run_dir, data)
            rehearsal.start()
            rows, problems = rehearsal.watch(start + timeout, settle, start, progress)
    finally:
        shutil.rmtree(run_dir, ignore_errors=True)
    result = SmokeResult(plan.product, str(bundle), time.monotonic() - start, rows, problems)
    result.skipped = skipped
    if unplayed is not None:
        result.actions_skipped = (
            f"actions not rehearsed, no goal, feedback or result of {', '.join(actions)} "
            f"is checked: {unplayed}"
        )
    return result


def rehearse_files(
    files: dict[str, bytes], ros: RosInstall, timeout: float = DEFAULT_TIMEOUT
) -> tuple[list[str], str]:
    """The check ``spl validate --smoke`` runs on every valid bundle: the bundle is
    written to a temporary folder and rehearsed. Returns the failures (``smoke: ...``)
    and the verdict line."""
    from spl.generators.bundle.writer import write_bundle

    with tempfile.TemporaryDirectory(prefix="spl-validate-smoke-") as folder:
        write_bundle(files, Path(folder) / "bundle")
        result = run_smoke(Path(folder) / "bundle", timeout=timeout, ros=ros)
    checks = sum(len(rows) for rows in result.rows.values())
    warning = f"; warning: {result.actions_skipped}" if result.actions_skipped else ""
    if result.passed:
        return [], f"smoke: all {checks} checks ok in {result.seconds:.1f} s{warning}"
    failures = [f"smoke: {failure}" for failure in result.failures()]
    return failures, (
        f"smoke: FAILED, {len(failures)} of {checks} checks in {result.seconds:.1f} s{warning}"
    )


class _Rehearsal:
    def __init__(
        self,
        bundle: Path,
        plan: SmokePlan,
        ros: RosInstall,
        processes: Processes,
        run_dir: Path,
        data: DataPath | None,
    ) -> None:
        self.bundle, self.plan, self.ros, self.data = bundle, plan, ros, data
        self.processes, self.run_dir = processes, run_dir
        self.status_dir = run_dir / "status"
        self.plan_file = run_dir / "plan.json"
        self.masters: dict[str, Master] = {}
        self.cores: dict[str, subprocess.Popen[bytes]] = {}
        self.core_starts = 0
        self.environments: dict[str, dict[str, str]] = {}
        self.launched: set[str] = set()
        self.labels: dict[str, tuple[str, str | None]] = {}  # label -> (container, node)

    def start(self) -> None:
        """Start every container's roscore, then (as the masters come up) its endpoint,
        data clients and roslaunch."""
        description = self.plan.stand_in_description(self.status_dir)
        self.plan_file.write_text(json.dumps(description, indent=1), encoding="utf-8")
        messages = self.run_dir / "messages"
        write_messages(messages, self.plan.messages)
        generated = {(n.container, n.name) for c in self.plan.containers for n in c.nodes
                     if n.role == "generated"}  # fmt: skip
        stand_in = standin_command(self.ros.python)
        executables = []
        for container in self.plan.containers:
            launch = self.bundle / "ros1" / f"{container.name}.launch"
            for package, executable, name in _launch_executables(launch):
                command = stand_in
                if (container.name, name) in generated:
                    root = self.bundle / "clients" / "ros1" / package
                    command = script_command(self.ros.python, root / "scripts" / executable,
                                             [messages, root / "src"])  # fmt: skip
                executables.append((package, executable, command))
        write_sandbox(self.run_dir / "sandbox", executables)
        (self.run_dir / "tmp").mkdir()
        if self.data is not None:
            self.data.start()
        for container in self.plan.containers:
            self._start_master(container)

    def _start_master(self, container: ContainerPlan) -> None:
        """roscore on a free port; started again on another port when it dies before it
        answers (another program took the port between the probe and roscore)."""
        port = free_port()
        uri = f"http://127.0.0.1:{port}/"
        home = self.run_dir / "home" / container.name
        env = self.processes.environment(
            ROS_MASTER_URI=uri, ROS_IP="127.0.0.1", ROS_HOME=str(home),
            ROS_LOG_DIR=str(home / "log"), TMPDIR=str(self.run_dir / "tmp"),
            SPL_SMOKE_PLAN=str(self.plan_file), SPL_SMOKE_CONTAINER=container.name,
        )  # fmt: skip
        self.environments[container.name] = env
        self.masters[container.name] = Master(uri)
        argv = [self.ros.roscore, "-p", str(port), "--sigint-timeout=1", "--sigterm-timeout=1"]
        self.cores[container.name] = self.processes.start(_core_label(container.name), argv, env)

    def _launch(self, container: ContainerPlan) -> None:
        env = self.environments[container.name]
        python = [self.ros.python, "-I", str(STANDIN)]
        for node in container.nodes:
            namespace = {"ROS_NAMESPACE": node.ros_name.rsplit("/", 1)[0] or "/"}
            if node.role == "endpoint":
                label = f"endpoint-{container.name}"
                self.processes.start(label, [*python, "endpoint"], {**env, **namespace})
            elif node.role == "probe":
                label = f"probe-{container.name}-{node.name}"
                remaps = [f"{i.name}:={i.ros_name}" for i in node.interfaces]
                argv = [*python, "node", f"__name:={node.name}", *remaps]
                self.processes.start(label, argv, {**env, **namespace})
            else:
                continue
            self.labels[label] = (container.name, node.ros_name)
        sandbox = str(self.run_dir / "sandbox")
        launch = self.bundle / "ros1" / f"{container.name}.launch"
        argv = [self.ros.roslaunch, "--wait", "--skip-log-check", "--disable-title",
                "--sigint-timeout=1", "--sigterm-timeout=1", str(launch)]  # fmt: skip
        label = f"roslaunch-{container.name}"
        self.labels[label] = (container.name, None)
        launch_env = {**env, "ROS_PACKAGE_PATH": f"{sandbox}/share", "CMAKE_PREFIX_PATH": sandbox}
        if self.data is not None:  # the stores' addresses and tokens, for the generated nodes
            argv += self.data.launch_arguments()
            launch_env |= self.data.environment()
        self.processes.start(label, argv, launch_env)
        self.launched.add(container.name)

    def watch(
        self,
        deadline: float,
        settle: float,
        start: float,
        progress: Callable[[Progress], None] | None,
    ) -> tuple[dict[str, list[Row]], list[str]]:
        """Poll until every check passes, the graph has settled, or the deadline."""
        last_change, before, up_after = start, None, None
        while True:
            now = time.monotonic()
            lost = False  # a master that ended with no restart left: nothing more to see
            for container in self.plan.containers:
                name = container.name
                if name in self.launched:
                    continue
                pid = self.masters[name].pid()
                if pid is not None and pid in marked_processes(self.processes.token):
                    self._launch(container)
                elif (
                    pid is not None or self.cores[name].poll() is not None
                ) and self.core_starts < MASTER_RETRIES:
                    # another program's master holds the port (ours refuses to start
                    # next to it), or ours died: never use it, start ours elsewhere
                    self.core_starts += 1
                    self.processes.retire(self.cores[name])
                    self._start_master(container)
                else:
                    lost = lost or self.cores[name].poll() is not None
            if self.data is not None:
                self.data.step(self.data.expected_raw(self.plan))
                # the restart's own time is no quiet spell: the writers were waiting on it
                last_change = max(last_change, self.data.restarted_at)
            rows, ready, stand_ins, given_up = self._snapshot()
            problems = self._process_problems()
            if self.data is not None:
                problems += self.data.problems
            # the data path's counts grow until it is done: a quiet spell waits for them
            state = (ready, [(r.ok, r.seen if r.interface.startswith(DATA_ROWS) else "")
                             for rs in rows.values() for r in rs])  # fmt: skip
            if state != before:  # settling waits for a quiet spell, not a fixed time
                before, last_change = state, now
            if progress:
                progress(Progress(now - start, len(self.launched), len(self.plan.containers),
                                  ready, stand_ins, sum(r.ok for rs in rows.values() for r in rs),
                                  sum(len(rs) for rs in rows.values())))  # fmt: skip
            everything_ok = all(r.ok for rs in rows.values() for r in rs) and not problems
            all_up = len(self.launched) == len(self.plan.containers)
            up = all_up and ready + given_up >= stand_ins
            if up and up_after is None:
                up_after = now - start
            # a loaded machine that was slow to start is given a longer quiet spell too
            quiet = max(settle, (up_after or 0.0) / 2)
            if self.data is not None and self.data.fault is not None:
                quiet = max(quiet, WRITER_RETRY)
            settled = up and now - last_change >= quiet
            passed = all_up and everything_ok and ready >= stand_ins
            if passed or settled or lost or now >= deadline:
                break
            time.sleep(POLL)
            raise_if_signalled()
        if not all_up:
            down = [c.name for c in self.plan.containers if c.name not in self.launched]
            problems.append(f"roscore did not come up for {', '.join(down)}")
        elif not everything_ok and now >= deadline:
            problems.append(f"timed out after {now - start:.1f} s")
        return rows, problems

    def _snapshot(self) -> tuple[dict[str, list[Row]], int, int, int]:
        rows, ready, stand_ins, given_up = {}, 0, 0, 0
        ended = {label for label, _, _ in self.processes.exited()}
        dead = {self.labels[label] for label in ended if label in self.labels}
        # a master that ended after its roslaunch started takes every node with it; one
        # that ended before is started again by :meth:`watch` (or reported there)
        lost_masters = {c for c in self.launched if _core_label(c) in ended}
        dead |= {(container, node) for container, node, _ in self._died_in_roslaunch()}
        every_status = {
            c.name: read_statuses(self.status_dir / c.name) for c in self.plan.containers
        }
        for container in self.plan.containers:
            statuses = every_status[container.name]
            master = self.masters[container.name]
            graph, params = None, {}
            if container.name in self.launched:
                try:
                    graph = master.graph()
                    params = {p.ros_name: master.param(p.ros_name)
                              for n in container.nodes for p in n.parameters}  # fmt: skip
                except (OSError, LookupError):
                    graph = None
            rows[container.name] = compare(container, graph, statuses, params)
            for node in container.nodes:
                stand_ins += 1
                registered = graph is not None and node.ros_name in graph.nodes()
                if statuses.get(node.ros_name, {}).get("ready") or (
                    node.role == "generated" and registered
                ):
                    ready += 1
                elif (
                    (container.name, node.ros_name) in dead
                    or container.name in lost_masters
                    or (node.role in ("launched", "generated") and (container.name, None) in dead)
                ):
                    given_up += 1  # its process (or its roslaunch) ended: it never will be
        if self.data is not None:
            for name, extra in self.data.rows(self.plan, every_status).items():
                rows[name] = rows.get(name, []) + extra
        return rows, ready, stand_ins, given_up

    def _died_in_roslaunch(self) -> list[tuple[str, str, str]]:
        """``(container, node ROS name, roslaunch's line)`` for every node whose process
        roslaunch reported dead (a stand-in never ends by itself)."""
        died = []
        for label, (container, node) in self.labels.items():
            if node is not None:
                continue  # not a roslaunch
            output = self.processes.output(label)
            for name in dict.fromkeys(m.group(1) for m in NODE_DIED.finditer(output)):
                died.append((container, f"/{name}", f"node {name} ended, roslaunch reports"))
        return died

    def _process_problems(self) -> list[str]:
        """Processes that ended on their own: a rehearsal's processes run until the end,
        except a roslaunch with no node to run (it exits 0 at once)."""
        idle = {
            (c.name, None) for c in self.plan.containers if not any(
                n.role in ("launched", "generated") for n in c.nodes)
        }  # fmt: skip
        ended = [
            f"{label} exited with status {status}: {output}".strip()
            for label, status, output in self.processes.exited()
            if not (status == 0 and self.labels.get(label) in idle)
        ]
        return ended + [f"roslaunch-{c}: {line}" for c, _, line in self._died_in_roslaunch()]


def _core_label(container: str) -> str:
    return f"roscore-{container}"


def _launch_executables(launch: Path) -> list[tuple[str, str, str]]:
    """``(pkg, type, name)`` of every ``<node>`` of a roslaunch file (roslaunch itself
    reports a file it cannot read)."""
    try:
        root = etree.parse(str(launch), etree.XMLParser(resolve_entities=False)).getroot()
    except (OSError, etree.XMLSyntaxError):
        return []
    return [
        (node.get("pkg", ""), node.get("type", ""), node.get("name", ""))
        for node in root.iter("node")
        if node.get("pkg") and node.get("type")
    ]
