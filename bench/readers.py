"""Benchmark: does each fast reader (src/spl/dsl/*/reader.py) pay against textX?

    .venv/bin/python bench/readers.py [--sizes 1000 10000] [--folder-sizes 1000]
        [--repeat 3] [--runs 5] [--each] [--no-in-process] [--limit-gb 4]

The readers exist only for speed (textX parses whatever they leave, and must give the
same tree: tests/dsl/test_*_reader.py). For each grammar, in process (CPU seconds):

* **metamodel**: importing textX, and textX building the grammar's metamodel, which every
  process that parses with textX pays once (the readers need neither);
* **parse tree**, least CPU time of ``--repeat``: textX's ``model_from_str`` against
  the reader's ``read`` on every shipped model of the language (product_lines/, summed)
  and on the synthetic line of bench/tsm_scale.py (``--sizes`` nodes: its .tsm, .fm and
  .rm).

Then whole ``spl check`` processes, ``--runs`` each, interleaved, median CPU time (user
+ system: on a loaded machine the wall time also measures waiting for a core): with the
readers, and with them switched off (each ``read`` returning None, so textX reads
everything, as it would without the reader; ``--each``: also one reader at a time): on
the shipped mapping3d line, on the synthetic line's .tsm, and on its folder at the
``--folder-sizes`` (default 1,000 nodes only: a 10,000-node folder's check is minutes of
the line checks' witness resolutions, which no reader touches, so its rows would take
hours and measure the resolver, docs/performance.md "Large product lines"). The processes
keep cached bytecode, as an installed spl does; each may take ``--limit-gb`` of address
space, and one that needs more is reported as over it instead of timed.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from tsm_scale import synthetic_line  # the same synthetic line, run as a script

from spl.dsl.fm import language as fm, reader as fm_reader
from spl.dsl.rm import language as rm, reader as rm_reader
from spl.dsl.tsm import language as tsm, reader as tsm_reader

ROOT = Path(__file__).resolve().parents[1]
LANGUAGES = {
    "tsm": (tsm._grammar, tsm_reader.read),
    "fm": (fm._grammar, fm_reader.read),
    "rm": (rm._grammar, rm_reader.read),
}
ENVIRONMENT = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
# `spl` with the readers named in its first argument switched off
WITHOUT_READERS = (
    "import importlib, sys\n"
    "for name in sys.argv.pop(1).split(','):\n"
    "    importlib.import_module(f'spl.dsl.{name}.reader').read = lambda text: None\n"
    "from spl.cli import main\n"
    "sys.argv[0] = 'spl'\n"
    "main()\n"
)


def best(repeat: int, action) -> float:
    """The least CPU time (of this process) of ``repeat`` runs of ``action``: on a shared,
    loaded machine the wall time also measures waiting for a core."""
    times = []
    for _ in range(repeat):
        start = time.process_time()
        action()
        times.append(time.process_time() - start)
    return min(times)


def parse_all(parse, texts: list[str]) -> None:
    for text in texts:
        parse(text)


def in_process(texts: dict[str, dict[str, list[str]]], repeat: int) -> None:
    start = time.process_time()
    import textx  # noqa: F401  (what a process parsing with textX imports first)

    print(f"importing textX: {time.process_time() - start:.3f} s (the readers need none)")
    print()
    print("| grammar | texts | KB | textX metamodel s | textX tree s | reader tree s | ratio |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: |")
    for language, (grammar, read) in LANGUAGES.items():
        grammar.cache_clear()
        start = time.process_time()
        metamodel = grammar()
        built = time.process_time() - start
        for label, group in texts[language].items():
            assert all(read(t) is not None for t in group), f"{label}: the reader refuses one"
            size = sum(len(t) for t in group) / 1024
            slow = best(repeat, lambda g=group, m=metamodel: parse_all(m.model_from_str, g))
            fast = best(repeat, lambda g=group, r=read: parse_all(r, g))
            print(
                f"| {language}.tx | {label} | {size:.0f} | {built:.3f} | {slow:.3f} "
                f"| {fast:.4f} | {slow / fast:.0f} x |"
            )


def process(arguments: list[str], off: tuple[str, ...], limit: int) -> float | None:
    """The CPU seconds (user + system) of one process ``spl ARGUMENTS`` with the readers
    of the languages ``off`` switched off: on a shared, loaded machine the wall time
    also measures waiting for a core. None where the process needed more than ``limit``
    bytes of address space (it is stopped there rather than take a shared machine's
    memory: the 10,000-node line folder grew to 20 GB, docs/performance.md).

    The child's stderr goes to a file, not a pipe: ``spl check`` of a large line warns
    more than a pipe holds (64 KiB), and a pipe nobody reads stops the child."""
    command = [sys.executable, "-m", "spl", *arguments]
    if off:
        command = [sys.executable, "-c", WITHOUT_READERS, ",".join(off), *arguments]

    def capped() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    with tempfile.TemporaryFile() as stderr:
        child = subprocess.Popen(
            command,
            cwd=ROOT,
            env=ENVIRONMENT,
            stdout=subprocess.DEVNULL,
            stderr=stderr,
            preexec_fn=capped,
        )
        _, status, usage = os.wait4(child.pid, 0)
        if os.waitstatus_to_exitcode(status) != 0:
            stderr.seek(0)
            said = stderr.read().decode(errors="replace")
            if "MemoryError" in said:
                return None
            raise SystemExit(f"{' '.join(command)} failed:\n{said[-4000:]}")
    return usage.ru_utime + usage.ru_stime


def whole_processes(targets: dict[str, Path], runs: int, each: bool, limit: int) -> None:
    ways = {"with readers": ()}
    if each:
        ways |= {f"no {language} reader": (language,) for language in LANGUAGES}
    ways["textX only"] = tuple(LANGUAGES)
    over = f"over {limit / 2**30:g} GB"
    print(f"median CPU s of {runs} processes each (interleaved; {over}: stopped there):")
    print()
    print(f"| spl check | {' | '.join(ways)} |")
    print(f"| --- | {' | '.join('---:' for _ in ways)} |")
    for label, target in targets.items():
        arguments = ["check", str(target)]
        # writes the bytecode a first run lacks; a target over the limit is not run again
        if process(arguments, (), limit) is None:
            print(f"| {label} | {' | '.join(over for _ in ways)} |", flush=True)
            continue
        samples: dict[str, list[float | None]] = {way: [] for way in ways}
        for _ in range(runs):  # interleaved, so a change of load hits every way alike
            for way, off in ways.items():
                if None not in samples[way]:
                    samples[way].append(process(arguments, off, limit))
        medians = {
            way: None if None in times else statistics.median(times)  # type: ignore[type-var]
            for way, times in samples.items()
        }
        on = medians["with readers"]
        cells = [over if on is None else f"{on:.3f}"]
        for way in list(ways)[1:]:
            slower = medians[way]
            if slower is None:
                cells.append(over)
            elif on is None:
                cells.append(f"{slower:.3f}")
            else:
                cells.append(f"{slower:.3f} ({slower / on:.1f} x)")
        print(f"| {label} | {' | '.join(cells)} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000])
    parser.add_argument(
        "--folder-sizes",
        type=int,
        nargs="*",
        default=[1000],
        help="the --sizes whose line folder is also checked whole (default 1000)",
    )
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--each", action="store_true", help="also switch off one reader at a time")
    parser.add_argument("--no-in-process", action="store_true", help="time whole processes only")
    parser.add_argument(
        "--limit-gb",
        type=float,
        default=4.0,
        help="address space each spl process may take (default 4; over it, it is stopped)",
    )
    options = parser.parse_args()
    texts: dict[str, dict[str, list[str]]] = {}
    for language in LANGUAGES:
        shipped = sorted((ROOT / "product_lines").rglob(f"*.{language}"))
        texts[language] = {
            f"{len(shipped)} shipped": [p.read_text(encoding="utf-8") for p in shipped]
        }
    targets = {"product_lines/mapping3d": ROOT / "product_lines" / "mapping3d"}
    with tempfile.TemporaryDirectory() as tmp:
        for size in options.sizes:
            folder = Path(tmp) / f"n{size}"
            folder.mkdir()
            synthetic_line(folder, size)
            for language in LANGUAGES:
                text = (folder / f"synthetic.{language}").read_text(encoding="utf-8")
                texts[language][f"synthetic {size}"] = [text]
            targets[f"synthetic {size}: .tsm"] = folder / "synthetic.tsm"
            if size in options.folder_sizes:
                targets[f"synthetic {size}: folder"] = folder
        if not options.no_in_process:
            in_process(texts, options.repeat)
            print()
        whole_processes(targets, options.runs, options.each, int(options.limit_gb * 2**30))


if __name__ == "__main__":
    main()
