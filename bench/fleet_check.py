"""Time of ``spl fleet check`` and ``spl fleet options`` on large mapping3d fleets.

A fleet of N robots (default 100, then 1000) of the shipped mapping3d line in ten groups:
in each group the robots explore the environment the group's first robot explores (so
they agree on the shared StrategyPlanner) and pick their base, camera and on-board PC
at random (a Roomba never carries a PC); every seventh robot keeps its map private and
explores anything, and one group shares the public map. Seeded, so every run times the
same fleet.

    python bench/fleet_check.py [--robots 100 1000] [--seed 7]

Prints, per size: robots, distinct products resolved, shared instances, seconds to read
the fleet file, to check it (resolutions included) and to compute one robot's options
with the SAT solver. The target is a fleet of 100 robots checked in seconds.
"""

from __future__ import annotations

import argparse
import random
import tempfile
import time
from pathlib import Path

from spl.resolver.fleets.fleet import check_fleet
from spl.resolver.fleets.fleet_file import load_fleet
from spl.resolver.fleets.options import fleet_options
from spl.resolver.resolution.product_line import load_product_line

LINE = Path(__file__).resolve().parents[1] / "product_lines" / "mapping3d"
GROUPS = 10


def fleet_text(robots: int, seed: int) -> str:
    rng = random.Random(seed)
    environment = {g: rng.choice(["Room", "Corridor"]) for g in range(GROUPS)}
    lines = ["fleet: bench", f"product_line: {LINE}", "robots:"]
    for i in range(robots):
        group = i % GROUPS
        base = rng.choice(["YouBot", "Roomba"])
        features = [base, rng.choice(["Stereo", "Depth"])]
        if base == "YouBot" and rng.random() < 0.5:
            features.append("AdditionalPC")
        sharing = ""
        if i % 7 == 3:
            features.append(rng.choice(["Room", "Corridor"]))
            sharing = ", sharing: {SharedMap: private}"
        elif group == 0:
            features.append("Room")
            sharing = ", sharing: {SharedMap: public}"
        else:
            features.append(environment[group])
        lines.append(
            f"  robot_{i}: {{group: g{group}, features: [{', '.join(features)}]{sharing}}}"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", type=int, nargs="+", default=[100, 1000])
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    line = load_product_line(LINE)
    line.formula  # parsed and encoded once, as the command does  # noqa: B018
    print("| robots | products resolved | shared instances | read s | check s | options s |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    with tempfile.TemporaryDirectory() as folder:
        for robots in args.robots:
            path = Path(folder) / f"fleet_{robots}.yaml"
            path.write_text(fleet_text(robots, args.seed))
            start = time.perf_counter()
            fleet = load_fleet(path)
            read = time.perf_counter() - start
            start = time.perf_counter()
            check = check_fleet(fleet, line)
            checked = time.perf_counter() - start
            assert check.ok, [str(d) for d in check.diagnostics[:3]]
            distinct = len({id(r.resolution) for r in check.robots})
            start = time.perf_counter()
            options = fleet_options(fleet, "newcomer", "g1")
            answered = time.perf_counter() - start
            assert options.joinable
            print(
                f"| {robots} | {distinct} | {len(check.instances())} | {read:.2f} | "
                f"{checked:.2f} | {answered:.2f} |"
            )


if __name__ == "__main__":
    main()
