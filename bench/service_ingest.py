"""Ingestion throughput of a generated data-acquisition service vs a bare FastAPI app.

    .venv/bin/python bench/service_ingest.py [--runs 5] [--concurrency 8] [--records 2000]
                                              [--slices 10] [--batch 100] [--profile FILE]

The generated PositionStore service (SQLite, transformer running) and a bare FastAPI
endpoint that only parses the posted JSON and returns it run under the same uvicorn on
this machine. One client keeps ``--concurrency`` keep-alive connections busy (each sends
its next request when the previous answer arrived) and posts the same single records to
both, side by side: a run posts ``--records`` to each server in ``--slices`` slices
that alternate between the two servers (and which of them goes first), so a change of
machine load hits both alike, and takes the ratio generated/bare of the run's rates.
Printed: every run, then the min and the median ratio over the runs. Target (issue
17): min >= 0.5 at concurrency 8 over 5 runs. Each run also gives the server
processes' CPU time per post (all threads, from /proc): on a loaded machine the
rates follow the CPU each server is given, the CPU per post much less.

The client speaks HTTP/1.1 on raw asyncio streams with the requests built beforehand,
so it costs little CPU: on a 2-core machine a heavy client would take the server's core
and flatter the ratio by slowing the bare endpoint most. Every answer is checked (status
201, a body of the announced length). ``--batch N`` also measures batches of N records
(sliced the same way; printed, not judged). ``--profile FILE`` runs the generated service
under cProfile and writes its statistics to FILE when it stops.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from spl.generators.service import generator as service  # noqa: E402

from support.service_models import product  # noqa: E402

TOKEN = "bench-token"
# docs/performance.md, "Targets": generated / bare at concurrency 8, reliably (the min of
# 5 runs)
TARGET = 0.5
STORE = "/PositionStore"
BARE_APP = """
from fastapi import FastAPI, Request
from fastapi.responses import Response

app = FastAPI()


@app.post("/PositionStore/records")
async def post(request: Request) -> Response:
    body = await request.body()
    import json
    document = json.loads(body)
    return Response(json.dumps(document), status_code=201, media_type="application/json")


@app.post("/PositionStore/records/batch")
async def batch(request: Request) -> Response:
    return await post(request)


@app.get("/")
def root() -> dict:
    return {}
"""
PROFILED = """
import cProfile, signal, sys
import uvicorn
profiler = cProfile.Profile()
signal.signal(signal.SIGTERM, lambda *_: (_ for _ in ()).throw(KeyboardInterrupt()))
profiler.enable()
try:
    uvicorn.run("position_store_service.app:app", host="127.0.0.1", port=int(sys.argv[1]),
                log_level="warning", access_log=False)
finally:
    profiler.disable()
    profiler.dump_stats(sys.argv[2])
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(command: list[str], cwd: Path, env: dict[str, str], port: int) -> subprocess.Popen:
    process = subprocess.Popen(
        command,
        cwd=cwd,
        env={**os.environ, **env},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise SystemExit(f"{command} exited with {process.returncode}")
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=1):
                return process
        except (urllib.error.URLError, OSError):
            time.sleep(0.05)
    process.kill()
    raise SystemExit("server did not start")


def record(robot: str, i: int) -> dict:
    return {"robot": robot, "timestamp": 1e9 + i, "data": {"lat": 128520.0 + i, "lon": 502200.0}}


def http_post(path: str, document: dict) -> bytes:
    body = json.dumps(document).encode()
    head = (
        f"POST {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer {TOKEN}\r\n"
        f"Content-Type: application/json\r\nContent-Length: {len(body)}\r\n\r\n"
    )
    return head.encode() + body


async def _connection(port: int, requests: list[bytes]) -> None:
    """Send ``requests`` one after the other on one keep-alive connection."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    try:
        for data in requests:
            writer.write(data)
            head = await reader.readuntil(b"\r\n\r\n")
            status_line, *lines = head.decode("latin-1").split("\r\n")
            if status_line.split(" ", 2)[1] != "201":
                raise SystemExit(f"unexpected answer: {head!r}")
            length = next(
                int(v)
                for k, _, v in (line.partition(":") for line in lines)
                if k.lower() == "content-length"
            )
            await reader.readexactly(length)
    finally:
        writer.close()
        await writer.wait_closed()


async def _load(port: int, per_connection: list[list[bytes]]) -> float:
    started = time.perf_counter()
    await asyncio.gather(*(_connection(port, requests) for requests in per_connection))
    return time.perf_counter() - started


def posts(robots: int, count: int, batch: int, seed: int) -> list[list[bytes]]:
    """``count`` requests split over ``robots`` connections, one robot per connection;
    timestamps from ``seed`` on (each call its own seed: no two records alike)."""
    result = []
    for n in range(robots):
        robot, base = f"robot_{n}", seed * 10**6
        if batch == 1:
            result.append(
                [
                    http_post(f"{STORE}/records", record(robot, base + i))
                    for i in range(count // robots)
                ]
            )
        else:
            result.append(
                [
                    http_post(
                        f"{STORE}/records/batch",
                        {"records": [record(robot, base + i * batch + j) for j in range(batch)]},
                    )
                    for i in range(count // robots)
                ]
            )
    return result


@dataclass
class Server:
    name: str
    port: int
    process: subprocess.Popen
    singles: list[float] = field(default_factory=list)  # posts per second, one per run
    batched: list[float] = field(default_factory=list)  # records per second, one per run
    cpu: list[float] = field(default_factory=list)  # server CPU microseconds per single post

    def cpu_seconds(self) -> float:
        """User + system CPU of the server process so far (all its threads)."""
        fields = Path(f"/proc/{self.process.pid}/stat").read_text().rpartition(")")[2].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def measure(servers: list[Server], args: argparse.Namespace, run: int) -> None:
    """One run: ``--slices`` slices per server, alternating between the two servers (and
    which goes first), so that a change of machine load between slices hits both; a
    server's rate is its posts over its summed time."""
    kinds = [("singles", 1, args.records)]
    if args.batch:
        kinds.append(("batched", args.batch, args.records // args.batch * 4))
    for kind, batch, count in kinds:
        seconds = {server.name: 0.0 for server in servers}
        cpu = {server.name: 0.0 for server in servers}
        records = {server.name: 0 for server in servers}
        for piece in range(args.slices):
            seed = run * args.slices + piece + (0 if batch == 1 else 10**4)
            for server in servers if (run + piece) % 2 == 0 else servers[::-1]:
                requests = posts(args.concurrency, count // args.slices, batch, seed)
                before = server.cpu_seconds()
                seconds[server.name] += asyncio.run(_load(server.port, requests))
                cpu[server.name] += server.cpu_seconds() - before
                records[server.name] += sum(len(r) for r in requests) * batch
        for server in servers:
            getattr(server, kind).append(records[server.name] / seconds[server.name])
            if kind == "singles":
                server.cpu.append(cpu[server.name] / records[server.name] * 1e6)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--concurrency", type=int, default=8, help="connections kept busy")
    parser.add_argument("--records", type=int, default=2000, help="single posts per run")
    parser.add_argument("--slices", type=int, default=10, help="alternations per run")
    parser.add_argument("--batch", type=int, default=0, help="also post batches of N")
    parser.add_argument("--profile", type=Path, help="cProfile statistics of the service")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for relative, data in service.generate(product()).items():
            path = work / relative
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        (work / "bare_app.py").write_text(BARE_APP)
        directory = work / "services" / "PositionStore"
        bare_port, generated_port = free_port(), free_port()
        generated_command = [sys.executable, "-m", "position_store_service"]
        if args.profile:
            generated_command = [
                sys.executable,
                "-c",
                PROFILED,
                str(generated_port),
                str(args.profile.resolve()),
            ]
        env = {"HOST": "127.0.0.1", "POSITION_STORE_TOKEN": TOKEN}
        servers = [
            Server(
                "bare FastAPI",
                bare_port,
                start(
                    [
                        sys.executable,
                        "-m",
                        "uvicorn",
                        "bare_app:app",
                        "--port",
                        str(bare_port),
                        "--no-access-log",
                    ],
                    work,
                    env,
                    bare_port,
                ),
            ),
            Server(
                "generated service",
                generated_port,
                start(
                    generated_command,
                    directory,
                    {**env, "PORT": str(generated_port)},
                    generated_port,
                ),
            ),
        ]
        try:
            for server in servers:  # warm up: imports, connection pools, first pages
                asyncio.run(_load(server.port, posts(args.concurrency, 200, 1, -1)))
            for run in range(args.runs):
                measure(servers, args, run)
        finally:
            for server in servers:
                server.process.terminate()
                server.process.wait(30)
    report(servers, args)


def report(servers: list[Server], args: argparse.Namespace) -> None:
    bare, generated = servers
    ratios = [g / b for g, b in zip(generated.singles, bare.singles, strict=True)]
    print(f"single posts, concurrency {args.concurrency}, {args.records} posts per run")
    print("run  bare posts/s  generated posts/s  ratio  bare CPU us/post  generated CPU us/post")
    rows = zip(bare.singles, generated.singles, ratios, bare.cpu, generated.cpu, strict=True)
    for run, (b, g, r, bc, gc) in enumerate(rows):
        print(f"{run + 1:3d}  {b:12.0f}  {g:17.0f}  {r:5.2f}  {bc:16.0f}  {gc:21.0f}")
    cpu_ratio = statistics.median(bare.cpu) / statistics.median(generated.cpu)
    print(
        f"server CPU per post (median): bare {statistics.median(bare.cpu):.0f} us, "
        f"generated {statistics.median(generated.cpu):.0f} us (bare/generated {cpu_ratio:.2f})"
    )
    print(
        f"ratio generated/bare over {args.runs} runs: min {min(ratios):.2f}, "
        f"median {statistics.median(ratios):.2f} (target min >= {TARGET})"
    )
    if args.batch:
        batch_ratios = [g / b for g, b in zip(generated.batched, bare.batched, strict=True)]
        print(
            f"batches of {args.batch}: bare {statistics.median(bare.batched):.0f}, "
            f"generated {statistics.median(generated.batched):.0f} records/s (median); "
            f"ratio min {min(batch_ratios):.2f}, median {statistics.median(batch_ratios):.2f}"
        )


if __name__ == "__main__":
    main()
