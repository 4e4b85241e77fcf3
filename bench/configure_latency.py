"""Benchmark: how fast ``spl configure`` answers (docs/configure.md, "Speed").

    .venv/bin/python bench/configure_latency.py [--decisions 100] [--clicks 50] [--no-browser]

On automotive01 (2,513 features, tests/data/feature-models):

* **load**: reading the model, encoding it, its backbone, and the first page rendered
  (all 2,513 rows), in this process; target under 2 s. With Chromium, also the page
  loaded in the browser until it is idle.
* **server**: a seeded random walk of decisions (an open feature selected or deselected
  at random; undo when none is open), each answered with every state recomputed; the
  time is the server's own (its ``Server-Timing`` header), p50/p95/max; target p95
  under 50 ms.
* **click to page**: the same kind of walk in headless Chromium against a real
  ``spl configure`` process: the page's own timing from the click event until the
  changed rows are patched and the next frame is drawn (``window.splConfigure.timings``);
  target p95 under 150 ms.

Then the server time of a walk on every shipped product line; target p95 under 10 ms.
The figures depend on the machine and its load: run it on an otherwise idle machine
for the figures of docs/configure.md; ``uptime``'s load is printed with them.
"""

from __future__ import annotations

import argparse
import os
import random
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
AUTOMOTIVE = ROOT / "tests" / "data" / "feature-models" / "automotive01.uvl"
TARGETS = {"load": 2.0, "server": 50.0, "click": 150.0, "shipped": 10.0}


def percentile(values: list[float], share: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(share * len(ordered)) - 1))]


def summary(values: list[float]) -> str:
    return (
        f"p50 {statistics.median(values):.1f} ms, p95 {percentile(values, 0.95):.1f} ms, "
        f"max {max(values):.1f} ms over {len(values)}"
    )


def server_walk(source: Path, decisions: int, seed: int) -> tuple[float, list[float]]:
    """(load seconds, server milliseconds per decision) of a walk through the API."""
    from fastapi.testclient import TestClient

    from spl.configure.app import create_app
    from spl.configure.workspace import load_workspace

    started = time.perf_counter()
    api = TestClient(create_app(load_workspace(source)))
    page = api.get("/")
    load = time.perf_counter() - started
    assert page.status_code == 200, page.text
    states = api.get("/api/state").json()["states"]
    rng = random.Random(seed)
    times: list[float] = []
    while len(times) < decisions:
        opens = sorted(name for name, state in states.items() if state == "open")
        if not opens:
            answer = api.post("/api/undo")
            if answer.status_code != 200:
                break
            states.update(answer.json()["states"])
            continue
        answer = api.post(
            "/api/decide",
            json={"feature": rng.choice(opens), "action": rng.choice(["select", "deselect"])},
        )
        times.append(float(answer.headers["Server-Timing"].split("dur=")[1]))
        if answer.status_code == 200:
            states.update(answer.json()["states"])
    return load, times


def browser_walk(source: Path, clicks: int, seed: int) -> tuple[float, list[float]]:
    """(page load seconds, click-to-page milliseconds) in headless Chromium."""
    sys.path.insert(0, str(ROOT / "tests"))
    from support.configure_runs import chromium, configurator, settled, states

    with configurator(str(source)) as url:
        driver = chromium()
        try:
            started = time.perf_counter()
            driver.get(url)
            settled(driver, timeout=60)
            load = time.perf_counter() - started
            rng = random.Random(seed)
            done = 0
            while done < clicks:
                current = states(driver)
                opens = sorted(name for name, state in current.items() if state == "open")
                if not opens:
                    driver.find_element("css selector", '[data-action="undo"]').click()
                    settled(driver)
                    continue
                name = rng.choice(opens)
                action = rng.choice(["select", "deselect"])
                driver.execute_script(
                    'document.querySelector(`[data-feature="${arguments[0]}"] '
                    '[data-action="${arguments[1]}"]`).click();',
                    name,
                    action,
                )
                deadline = time.monotonic() + 30
                while driver.execute_script("return window.splConfigure.timings.length") <= done:
                    if time.monotonic() > deadline:
                        raise SystemExit("the page did not answer a click within 30 s")
                    time.sleep(0.005)
                done += 1
                settled(driver)  # the count's follow-up, if any, before the next click
            timings = driver.execute_script("return window.splConfigure.timings")
            server = driver.execute_script("return window.splConfigure.server")
        finally:
            driver.quit()
    print(f"  (the server's part of those clicks: {summary([float(t) for t in server])})")
    return load, [float(t) for t in timings]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--decisions", type=int, default=100)
    parser.add_argument("--clicks", type=int, default=50)
    parser.add_argument("--seed", type=int, default=31)
    parser.add_argument("--no-browser", action="store_true", help="skip the Chromium part")
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    ok = True
    load, times = server_walk(AUTOMOTIVE, args.decisions, args.seed)
    p95 = percentile(times, 0.95)
    ok &= load < TARGETS["load"] and p95 < TARGETS["server"]
    print(f"automotive01 load + first page: {load:.2f} s (target < {TARGETS['load']:g} s)")
    print(f"automotive01 server per decision: {summary(times)} (target p95 < 50 ms)")
    if not args.no_browser:
        page_load, clicks = browser_walk(AUTOMOTIVE, args.clicks, args.seed)
        ok &= percentile(clicks, 0.95) < TARGETS["click"]
        print(f"automotive01 page loaded in Chromium: {page_load:.2f} s")
        print(f"automotive01 click to page: {summary(clicks)} (target p95 < 150 ms)")
    for line in sorted((ROOT / "product_lines").iterdir()):
        _, shipped = server_walk(line, 40, args.seed)
        ok &= percentile(shipped, 0.95) < TARGETS["shipped"]
        print(f"{line.name} server per decision: {summary(shipped)} (target p95 < 10 ms)")
    print("all targets met" if ok else "some target missed")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
