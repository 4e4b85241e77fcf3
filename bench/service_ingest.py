"""Ingestion throughput of a generated data-acquisition service vs a bare FastAPI app.

The generated PositionStore service (SQLite, transformer running) and a bare FastAPI
endpoint that only parses the posted JSON and returns it run under the same uvicorn on
this machine; one httpx client (keep-alive) posts the same records to both, one run.
Target: generated / bare >= 0.5 for single-record posts.

    /tmp/venv/bin/python bench/service_ingest.py [--records 2000] [--batch 100] [--clients 1]
"""

from __future__ import annotations

import argparse
import os
import socket
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from service_models import product  # noqa: E402

from spl.generators import service  # noqa: E402

TOKEN = "bench-token"
BARE_APP = '''
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
'''


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(command: list[str], cwd: Path, env: dict[str, str], port: int) -> subprocess.Popen:
    process = subprocess.Popen(command, cwd=cwd, env={**os.environ, **env},
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        try:
            httpx.get(f"http://127.0.0.1:{port}/", timeout=1)
            return process
        except httpx.HTTPError:
            time.sleep(0.05)
    process.kill()
    raise SystemExit("server did not start")


def record(robot: str, i: int) -> dict:
    return {"robot": robot, "timestamp": 1e9 + i, "data": {"lat": 128520.0 + i, "lon": 502200.0}}


def post_singles(base: str, robot: str, records: int) -> None:
    headers = {"Authorization": f"Bearer {TOKEN}"}
    with httpx.Client(base_url=base, headers=headers, timeout=30) as client:
        for i in range(records):
            client.post("/PositionStore/records", json=record(robot, i)).raise_for_status()


def post_batches(base: str, robot: str, records: int, batch: int) -> None:
    headers = {"Authorization": f"Bearer {TOKEN}"}
    with httpx.Client(base_url=base, headers=headers, timeout=30) as client:
        for first in range(0, records, batch):
            body = {"records": [record(robot, first + i) for i in range(batch)]}
            client.post("/PositionStore/records/batch", json=body).raise_for_status()


def timed(clients: int, work, *args) -> float:  # type: ignore[no-untyped-def]
    """Seconds for ``clients`` robots (threads, one connection each) doing ``work``."""
    started = time.perf_counter()
    with ThreadPoolExecutor(clients) as pool:
        for future in [pool.submit(work, *args[:1], f"robot_{n}", *args[1:])
                       for n in range(clients)]:
            future.result()
    return time.perf_counter() - started


def measure(base: str, records: int, batch: int, clients: int) -> tuple[float, float]:
    """(single posts per second, records per second in batches)."""
    post_singles(base, "warmup", 50)
    single = records * clients / timed(clients, post_singles, base, records)
    batched = records * 10 * clients / timed(clients, post_batches, base, records * 10, batch)
    return single, batched


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=2000)
    parser.add_argument("--batch", type=int, default=100)
    parser.add_argument("--clients", type=int, default=1, help="concurrent robots")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for relative, data in service.generate(product()).items():
            path = work / relative
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        (work / "bare_app.py").write_text(BARE_APP)
        results = {}
        for name, command, cwd in [
            ("bare FastAPI", [sys.executable, "-m", "uvicorn", "bare_app:app"], work),
            ("generated service", [sys.executable, "-m", "position_store_service"],
             work / "services" / "PositionStore"),
        ]:
            port = free_port()
            env = {"HOST": "127.0.0.1", "PORT": str(port), "POSITION_STORE_TOKEN": TOKEN}
            if name == "bare FastAPI":
                command = [*command, "--port", str(port), "--no-access-log"]
            process = start(command, cwd, env, port)
            try:
                results[name] = measure(f"http://127.0.0.1:{port}", args.records, args.batch,
                                        args.clients)
            finally:
                process.terminate()
                process.wait(10)
    for name, (single, batched) in results.items():
        print(f"{name:18s} {single:8.0f} single posts/s {batched:9.0f} records/s "
              f"in batches of {args.batch} ({args.clients} client(s))")
    bare, generated = results["bare FastAPI"], results["generated service"]
    print(f"ratio generated/bare: single {generated[0] / bare[0]:.2f}, "
          f"batched {generated[1] / bare[1]:.2f} (target single >= 0.5)")


if __name__ == "__main__":
    main()
