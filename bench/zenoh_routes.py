"""Time of the Zenoh routing (``spl.generators.transport.routes.routes``, docs/deployment.md,
"How the bridges' namespaces are chosen"): every product of each shipped line and of the
offshore test line, mapping3d fleets of N robots (bench/fleet_check.py's, whose usual
namespaces are exact), then offshore fleets of N teams whose usual namespaces are not.

In the fleets every team is a crawler and a drone using the vessel's protected detector,
the farm's reports and the team's repair planner onshore; every other team's crawler
sends its own ultrasonic defects to the vessel. With one team per group the search
carries the fleet; with two teams per group no namespaces can (a team's defects would
reach the other team's crawler) and the search says so.

    python bench/zenoh_routes.py [--robots 100 1000] [--teams 10 40 100]

Prints, per line: products, seconds of routing in all, products that needed the search;
per fleet: robots, links, seconds, choices tried, and whether Zenoh carries it.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from fleet_check import fleet_text as mapping_fleet  # run as bench/zenoh_routes.py

from spl.generators.transport.namespaces import Choice
from spl.generators.transport.routes import links, routes
from spl.resolver.analysis.formula import enumerate_products
from spl.resolver.architecture.placement import Placement
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.architecture.wiring import Wiring
from spl.resolver.fleets.deployment import deploy
from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import ProductSelection

ROOT = Path(__file__).resolve().parents[1]
OFFSHORE = ROOT / "tests" / "models" / "offshore"
LINES = [*sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir()), OFFSHORE]


def wirings(products: list[ResolvedProduct]) -> list[Wiring]:
    return [Wiring(p.flows, Placement(p.system, []), []) for p in products]


def fleet_text(teams: int, per_group: int) -> str:
    rows = ["fleet: bench", f"product_line: {OFFSHORE}", "robots:"]
    for i in range(teams):
        own = "Thickness, WallDefects, LogOnVessel" if i % 2 == 0 else "Marking"
        features = f"DetectionOnVessel, Reporting, RepairPlanning, {own}"
        rows.append(f"  team{i}: {{group: g{i // per_group}, features: [{features}]}}")
    return "\n".join(rows) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", type=int, nargs="+", default=[100, 1000])
    parser.add_argument("--teams", type=int, nargs="+", default=[10, 40, 100])
    args = parser.parse_args()
    print("| line | products | routing s | searched |")
    print("| --- | ---: | ---: | ---: |")
    for folder in LINES:
        line = load_product_line(folder)
        placed = [
            wirings([resolve(line, ProductSelection("p", sorted(features))).product])
            for features in enumerate_products(line.fm)
        ]
        start = time.perf_counter()
        for one in placed:
            routes(one)
        elapsed = time.perf_counter() - start
        searched = 0
        for one in placed:
            choice = Choice(*links(one))
            choice.choose()
            searched += choice.tries > 0
        print(f"| {folder.name} | {len(placed)} | {elapsed:.2f} | {searched} |")
    print()
    print("| fleet | robots | links | routing s | choices tried | carried |")
    print("| --- | ---: | ---: | ---: | ---: | --- |")
    with tempfile.TemporaryDirectory() as scratch:
        fleets = [(f"mapping3d, {n} robots", mapping_fleet(n, 7)) for n in args.robots]
        for teams in args.teams:
            for per_group in (1, 2):
                name = f"offshore, {teams} teams, {per_group} per group"
                fleets.append((name, fleet_text(teams, per_group)))
        for k, (name, text) in enumerate(fleets):
            path = Path(scratch) / f"fleet_{k}.yaml"
            path.write_text(text)
            products = [e.product for e in deploy(check_fleet(load_fleet(path))).robots]
            placed = wirings(products)
            start = time.perf_counter()
            found = routes(placed)
            elapsed = time.perf_counter() - start
            choice = Choice(*links(placed))
            choice.choose()
            print(
                f"| {name} | {len(choice.robots)} | {len(choice.links)} | "
                f"{elapsed:.2f} | {choice.tries} | {'no' if found.problems else 'yes'} |"
            )


if __name__ == "__main__":
    main()
