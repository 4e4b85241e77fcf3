"""`spl validate` runs each product with the cyclic collector paused and collects once
after it: the product's models do not outlive its case, the collector is on again
afterwards, and a run makes one collection per product instead of several."""

from __future__ import annotations

import gc
import subprocess
import sys
from pathlib import Path

from spl.validation.line import load_lines, plan_cases, run_cases

MAPPING = Path(__file__).resolve().parents[2] / "product_lines" / "mapping3d"


def _systems(kind: type) -> int:
    return sum(1 for o in gc.get_objects() if type(o) is kind)


def test_each_product_is_collected_once_and_does_not_outlive_its_case():
    lines = load_lines([MAPPING])
    cases = plan_cases(lines, "all")[:4]
    system_class = type(lines[0].line.tsm)
    run_cases(lines, cases[:1])  # imports and caches warm
    gc.collect()
    before = _systems(system_class)
    collections = []

    def count(phase: str, info: dict) -> None:
        if phase == "start":
            collections.append(info["generation"])

    gc.callbacks.append(count)
    try:
        results = run_cases(lines, cases)
    finally:
        gc.callbacks.remove(count)
    assert [r.outcome for r in results] == ["passed"] * len(cases)
    assert gc.isenabled()
    assert collections == [0] * len(cases)  # one per product, none while it ran
    assert _systems(system_class) == before  # every resolved model already freed


def test_what_every_product_imports_is_in_the_oldest_generation_before_the_first():
    """Imported inside the first product, the generators' and checks' objects were young,
    and the collection after that product walked them all; imported before it, they are
    in the oldest generation, which a young collection does not walk. A fresh
    interpreter, so nothing is imported yet."""
    probe = (
        "import gc, sys\n"
        "import spl.validation.line as lv\n"
        "from spl.generators.bundle.writer import GENERATORS\n"
        "lv._import_product_modules()\n"
        "assert set(GENERATORS) <= set(sys.modules), 'a generator is not imported'\n"
        "young = {id(o) for g in (0, 1) for o in gc.get_objects(generation=g)}\n"
        "functions = [m.generate for m in map(sys.modules.get, GENERATORS)]\n"
        "assert not any(id(f) in young for f in functions), 'a generator is young'\n"
        "print(len(young), len(gc.get_objects(generation=2)))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    young, old = map(int, done.stdout.split())
    assert young < old / 50
