"""CI validation of product lines (docs/ci.md): derive products, check every artifact.

Each product is one test case: its selection is checked and resolved, every artifact of
its bundle is generated in memory and validated (launch XSDs, Rapyuta JSON Schema and
rules, Python compiled, YAML/XML parsed, resolved model re-parsed, manifest hashes).
A product fails with the located messages of whatever went wrong; it never stops the
run. The products are the line's own ``products/*.yaml`` (always, named by their
``product`` name) plus, on request, every product of the feature model or a t-wise
covering array of it (named by their non-core features).

The models of a line are parsed once. With ``jobs > 1`` the products run in forked
worker processes that inherit the parsed lines (and their SAT formulas) from the parent,
so nothing is parsed or pickled per product; results come back in submission order, so
the report does not depend on scheduling, and a worker that dies has its product run
again (:mod:`spl.validation.workers`).

A caller may add a check of the generated files (``rehearse``: ``spl validate --smoke``
passes the live ROS rehearsal); its problems fail the product like any other and its
summary line goes into the report. The check is handed in, so this module does not
depend on the application layer that implements it.
"""

from __future__ import annotations

import hashlib
import importlib
import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from spl import __version__
from spl.core.cyclic_gc import without_cyclic_gc
from spl.core.diagnostics import ModelError
from spl.core.lifetime import checkpointed, die_with_parent, raise_if_signalled, unwind_on_signals
from spl.pipeline import ProductWarning, load_line
from spl.resolver.resolution.product_line import ProductLine

if TYPE_CHECKING:
    from spl.generators.bundle.inputs import BundleMemo
    from spl.validation.bundle_changes import Version

Outcome = Literal["passed", "failed", "error", "skipped"]
LINE_CASE = "(product line)"  # the test case of a line whose models do not load


@dataclass(frozen=True)
class ProductCase:
    """One product to validate: a selection file, or a generated feature selection."""

    line: int  # index of the line in the run
    name: str
    selection_file: Path | None = None
    features: tuple[str, ...] = ()  # generated products: their non-core features


@dataclass(frozen=True)
class CaseResult:
    classname: str  # the product line's name
    name: str
    outcome: Outcome
    messages: tuple[str, ...] = ()  # located problems (failed) or the crash (error)
    warnings: tuple[ProductWarning, ...] = ()  # as the derivation gives them
    seconds: float = 0.0
    checked: str = ""  # the summary line of the caller's extra check (smoke rehearsal)

    @property
    def passed(self) -> bool:
        """Nothing failed: checked and found good, or skipped as its bundle is unchanged
        (``--changed-from``, whose ``messages`` say since when)."""
        return self.outcome in ("passed", "skipped")

    @property
    def product_warnings(self) -> tuple[str, ...]:
        """The warnings that are the product's: printed under its line, counted, and its
        failure with ``--strict`` (docs/ci.md, "A product's warnings")."""
        return tuple(w.text for w in self.warnings if not w.machine)

    @property
    def machine_warnings(self) -> tuple[str, ...]:
        """The warnings about the machine that ran it (a picture Graphviz is missing for):
        in its test case, said once for the run, never its failure."""
        return tuple(w.text for w in self.warnings if w.machine)


@dataclass
class LoadedLine:
    """A product line given on the command line: parsed, or the reason it is not."""

    directory: Path
    name: str
    line: ProductLine | None
    problems: tuple[str, ...] = ()
    # the version compared with (--changed-from, --since): its products whose bundles
    # are the same are skipped
    base: Version | None = None


def load_lines(directories: Iterable[Path]) -> list[LoadedLine]:
    """Parse each line once and build its SAT formula before any worker is forked."""
    loaded = []
    for directory in directories:
        name = Path(directory).resolve().name
        try:
            line = load_line(directory)
            line.formula.backbone()  # computed here, inherited by every worker
        except ModelError as exc:
            loaded.append(
                LoadedLine(Path(directory), name, None, tuple(str(d) for d in exc.diagnostics))
            )
            continue
        loaded.append(LoadedLine(Path(directory), name, line))
    return loaded


def plan_cases(lines: list[LoadedLine], mode: str = "listed", t: int = 2) -> list[ProductCase]:
    """The products to validate: every line's ``products/*.yaml``, then the generated
    ones (``mode`` ``all`` or ``sample``; ``listed`` adds none)."""
    from spl.resolver.analysis.sampling import covering_array, product_key

    # a line that did not load is one failing case, reported first
    cases = [ProductCase(i, LINE_CASE) for i, loaded in enumerate(lines) if loaded.line is None]
    for index, loaded in enumerate(lines):
        line = loaded.line
        if line is None:
            continue
        for path in line.product_files():
            cases.append(ProductCase(index, _listed_name(path), selection_file=path))
        if mode == "listed":
            continue
        formula = line.formula
        products: Iterable[frozenset[str]]
        if mode == "all":
            products = formula.products()
        elif mode == "sample":
            products = covering_array(formula, t).products
        else:
            raise ValueError(f"unknown mode {mode!r}")
        root = formula.cnf.names[0]
        for product in products:
            key = tuple(product_key(formula, product)) or (root,)
            cases.append(ProductCase(index, ",".join(key), features=key))
    return cases


@dataclass(frozen=True)
class Shard:
    """Part ``index`` of ``count`` of a run (``spl validate --shard K/N``, docs/ci.md).

    A shard is a contiguous block of the plan, the blocks differing by at most one case:
    shards 1..N in order are the whole run, each case in exactly one, so their JUnit
    reports merge back into the report of the unsharded run (``spl merge-junit``). The
    plan is a function of the models alone, so every CI job computes the same one."""

    index: int
    count: int

    @classmethod
    def parse(cls, text: str) -> Shard:
        """``K/N`` with 1 <= K <= N (ValueError saying what is wrong)."""
        k, slash, n = text.partition("/")
        if not (slash and k.isdigit() and n.isdigit() and k.isascii() and n.isascii()):
            raise ValueError(f"{text!r} is not K/N (for example 2/4)")
        index, count = int(k), int(n)
        if not 1 <= index <= count:
            raise ValueError(f"{text!r}: K must be between 1 and N")
        return cls(index, count)

    def of(self, cases: list[ProductCase]) -> list[ProductCase]:
        """This shard's block of the plan."""
        start = (self.index - 1) * len(cases) // self.count
        return cases[start : self.index * len(cases) // self.count]

    def __str__(self) -> str:
        return f"{self.index}/{self.count}"


def plan_digest(lines: list[LoadedLine], cases: list[ProductCase]) -> str:
    """What identifies a run's plan: the shards of one run carry the same digest, so a
    merge refuses reports of different runs (other models, options or spl versions)."""
    digest = hashlib.sha256(__version__.encode() + b"\0")
    for case in cases:
        digest.update(f"{lines[case.line].name}\0{case.name}\0".encode())
    return digest.hexdigest()[:16]


def _listed_name(path: Path) -> str:
    """The ``product`` name a selection file declares, or its file name; the file is
    parsed properly (and its errors reported) when the case runs."""
    import yaml

    if not path.is_file():  # a named pipe would block; the case reports what it is
        return path.stem
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (yaml.YAMLError, OSError, ValueError, TypeError, RecursionError):
        # ValueError: not UTF-8, or a tag that does not convert (`!!float x`)
        return path.stem
    name = data.get("product") if isinstance(data, dict) else None
    return name if isinstance(name, str) and name.isidentifier() else path.stem


# An extra check of a valid bundle's files: (problems, one summary line).
Rehearsal = Callable[[dict[str, bytes]], tuple[list[str], str]]


@dataclass(frozen=True)
class CaseChecks:
    """What a product's case checks besides its files: a live rehearsal of a valid
    bundle (``--smoke``), the rendered diagram (``--diagrams``: one Graphviz process per
    product, so off by default; the diagram's source is always generated and checked)."""

    rehearse: Rehearsal | None = None
    diagrams: bool = False
    # what the run's bundles share (bundle/inputs.py): one per run; None: a bundle its own
    memo: BundleMemo | None = None
    # the skip's reason for a product whose bundle its line's ``base`` derives alike
    unchanged: str = "bundle unchanged"


def run_case(
    line: ProductLine,
    classname: str,
    case: ProductCase,
    checks: CaseChecks = CaseChecks(),
    base: Version | None = None,
) -> CaseResult:
    """Resolve one product, generate its bundle in memory and validate every file;
    then, when the files are valid, run ``checks.rehearse`` on them. With the line's
    older version ``base``, a product whose bundle it derives alike is skipped."""
    from spl import pipeline
    from spl.generators.bundle.options import BundleOptions
    from spl.resolver.resolution.product_selection import load_selection_file, selection_from_list
    from spl.validation.bundle_changes import Version, unchanged

    start = time.perf_counter()
    try:
        if case.selection_file is not None:
            selection = load_selection_file(case.selection_file)
        else:
            selection = selection_from_list(",".join(case.features), name="_".join(case.features))
        options = BundleOptions(render_diagrams=checks.diagrams)
        derivation = pipeline.derive(line, selection, options, checks.memo)
        if base is not None and unchanged(
            base, Version(line.directory, line), case, derivation, options, checks.memo
        ):
            return CaseResult(classname, case.name, "skipped", (checks.unchanged,))
        problems = pipeline.validate(derivation)
        checked = ""
        if checks.rehearse is not None and not problems:
            found, checked = checks.rehearse(derivation.bundle.files)
            problems += found
    except ModelError as exc:
        return CaseResult(
            classname,
            case.name,
            "failed",
            tuple(str(d) for d in exc.diagnostics if d.severity == "error"),
            seconds=time.perf_counter() - start,
        )
    except Exception as exc:  # an spl bug: reported as this product's error, run goes on
        return CaseResult(
            classname,
            case.name,
            "error",
            (f"internal error: {type(exc).__name__}: {exc}",),
            seconds=time.perf_counter() - start,
        )
    outcome: Outcome = "failed" if problems else "passed"
    return CaseResult(
        classname,
        case.name,
        outcome,
        tuple(problems),
        derivation.warnings,
        time.perf_counter() - start,
        checked,
    )


# The lines of the current run, set before the pool forks: workers read them from here.
_LINES: list[LoadedLine] = []
_CHECKS = CaseChecks()


def run_planned(loaded: LoadedLine, case: ProductCase, checks: CaseChecks) -> CaseResult:
    """The result of one planned case: a product, or the line that did not load."""
    if loaded.line is None:
        return CaseResult(loaded.name, LINE_CASE, "failed", loaded.problems)
    with without_cyclic_gc("dropped"):  # one product built, used and dropped as a whole
        return run_case(loaded.line, loaded.name, case, checks, loaded.base)


def _run_in_worker(case: ProductCase) -> CaseResult:
    raise_if_signalled()
    return run_planned(_LINES[case.line], case, _CHECKS)


def _run_in_forked_worker(case: ProductCase) -> CaseResult:
    with checkpointed():  # a signal swallowed during the product unwinds at its end
        return _run_in_worker(case)


def _lost(case: ProductCase, why: str) -> CaseResult:
    return CaseResult(_LINES[case.line].name, case.name, "error", (f"lost: {why}",))


def run_cases(
    lines: list[LoadedLine],
    cases: list[ProductCase],
    jobs: int = 1,
    on_result: Callable[[CaseResult], None] | None = None,
    checks: CaseChecks = CaseChecks(),
) -> list[CaseResult]:
    """Every case's result, in the order of ``cases``. ``jobs > 1`` uses forked worker
    processes."""
    from spl.generators.bundle.inputs import BundleMemo

    results: list[CaseResult] = []
    global _LINES, _CHECKS
    _LINES, _CHECKS = lines, checks if checks.memo else replace(checks, memo=BundleMemo())
    try:
        for result in _results(cases, jobs):
            results.append(result)
            if on_result:
                on_result(result)
    finally:
        _LINES, _CHECKS = [], CaseChecks()
    return results


def _start_worker() -> None:
    """Workers end on Ctrl-C (SIGINT from the terminal) and on SIGTERM (an interrupted
    run stopping them) by unwinding quietly, so the task's own cleanup runs (a smoke rehearsal
    stops the processes it started), and end with a killed spl (a CI timeout)."""
    unwind_on_signals(pool_worker=True)
    die_with_parent()


def _import_product_modules() -> None:
    """Imports what deriving and validating any product uses (the generators, the
    resolver, the bundle checks) before the first product, with their objects moved to
    the oldest generation as they are not garbage: imported inside the first product,
    they are young objects that the collection after it walks (about 20 ms, more than a
    product takes)."""
    from spl.generators.bundle.writer import GENERATORS

    with without_cyclic_gc("kept"):
        warm = ("spl.resolver.resolution.engine", "spl.generators.bundle.validation")
        for module in (*GENERATORS, *warm):
            importlib.import_module(module)


def _results(cases: list[ProductCase], jobs: int) -> Iterator[CaseResult]:
    while cases and _LINES[cases[0].line].line is None:  # first in the plan: nothing to run
        yield _run_in_worker(cases[0])
        cases = cases[1:]
    if cases:
        _import_product_modules()
    if jobs <= 1 or len(cases) <= 1:
        yield from map(_run_in_worker, cases)
        return
    # The first product runs here: it loads the schemas, templates and grammars (the
    # generators are imported already), and every worker forked afterwards inherits them
    # warm (otherwise each worker pays that first-product cost again).
    yield _run_in_worker(cases[0])
    from spl.validation.workers import ForkedWorkers  # a run with one job does without

    rest = cases[1:]
    chunk = max(1, min(16, len(rest) // (jobs * 8)))  # products given to a worker at once
    workers = ForkedWorkers(rest, _run_in_forked_worker, _lost, jobs, _start_worker, chunk)
    yield from workers.results()
