"""The one place the order of spl's work is written down (SPEC section 1):

    load the line (parse .rm, .tsm, .fm; build the feature formula)
      -> check the selection and resolve it (M2M: the resolved architecture)
      -> emit the bundle (M2T: every target's files, in memory)
      -> validate or write it.

The commands (`resolve`, `validate`, `check`, `render`, `explain`), the validation
workers, the smoke rehearsal and the language server call these functions instead of
spelling the sequence out again, so a new step (a new target, a new check) is added
here once. Each step lives in its own layer (spl.dsl, spl.resolver, spl.generators);
this module only orders them.
"""

from __future__ import annotations

import contextlib
import importlib
import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from spl.diagnostics import Diagnostic, Location, ModelError

if TYPE_CHECKING:
    from spl.generators.bundle import Bundle
    from spl.resolver.engine import Resolution
    from spl.resolver.product_line import ProductLine
    from spl.resolver.product_selection import ProductSelection

# The language module of each model file kind: ``parse_file(path)`` raises ModelError
# with every problem found; ``summary(model)`` is its one-line description.
LANGUAGES = {".tsm": "spl.dsl.tsm", ".fm": "spl.dsl.fm", ".rm": "spl.dsl.rm"}


@dataclass(frozen=True)
class Derivation:
    """One product derived from a line: the resolution (with its trace and summary) and
    the bundle generated from it, not yet written anywhere."""

    resolution: Resolution
    bundle: Bundle


def load_line(directory: Path) -> ProductLine:
    """Parse the line's three models and build its feature formula (ModelError)."""
    from spl.resolver.product_line import load_product_line

    return load_product_line(directory)


def resolve_product(line: ProductLine, selection: ProductSelection) -> Resolution:
    """Check the selection against the feature model and resolve it (ModelError)."""
    from spl.resolver.engine import resolve

    return resolve(line, selection)


def derive(line: ProductLine, selection: ProductSelection) -> Derivation:
    """Resolve the selection and generate every file of its bundle in memory."""
    from spl.generators.bundle import build_bundle

    resolution = resolve_product(line, selection)
    return Derivation(resolution, build_bundle(resolution.product))


def validate(derivation: Derivation) -> list[str]:
    """Every problem of the bundle's files, checked by their consumers' rules (launch
    XSDs, Rapyuta schema and rules, Python compiled, resolved model re-parsed, ...)."""
    from spl.bundle_validation import validate_bundle

    return validate_bundle(derivation.bundle.files)


def write(derivation: Derivation, out: Path) -> None:
    """Write the bundle atomically: on any error nothing is left at ``out``."""
    from spl.generators.bundle import write_bundle

    write_bundle(derivation.bundle.files, out)


def read_bundle(bundle: Path) -> tuple[Any, str]:
    """A written bundle's resolved architecture (its ``resolved.tsm``, parsed by spl's
    own .tsm language, so the rehearsal sees what a user could edit and re-read) and its
    product name (from the manifest, else the system's). ModelError when it is none."""
    from spl.dsl.tsm import parse_text

    model = bundle / "resolved.tsm"
    if not model.is_file():
        raise ModelError([Diagnostic(None, f"{bundle} is not an spl bundle: no resolved.tsm")])
    system = parse_text(model.read_text(encoding="utf-8"), str(model))
    product = system.name
    manifest = bundle / "manifest.json"
    if manifest.is_file():
        with contextlib.suppress(ValueError, AttributeError):  # a damaged one hides nothing
            product = json.loads(manifest.read_text(encoding="utf-8")).get("product", product)
    return system, product


def parse_model(path: Path) -> tuple[Any, Any]:
    """One model file parsed by the language its suffix names: ``(language, model)``."""
    module_name = LANGUAGES.get(path.suffix)
    if module_name is None:
        known = ", ".join(sorted(LANGUAGES))
        raise ModelError(
            [Diagnostic(Location(str(path), 1, 1), f"unknown model kind (expected {known})")]
        )
    language = importlib.import_module(module_name)
    return language, language.parse_file(path)


def model_summary(path: Path) -> str:
    """Parse one model file; its one-line summary (ModelError with every problem)."""
    language, model = parse_model(path)
    return language.summary(model)


def line_summaries(line: ProductLine) -> dict[Path, str]:
    """The summaries of the files a loaded line parsed, by resolved path."""
    from spl.dsl import fm, rm, tsm

    base = line.models.path.parent
    return {
        line.models.path.resolve(): rm.summary(line.rm),
        (base / line.rm.tsmPath).resolve(): tsm.summary(line.tsm),
        (base / line.rm.fmPath).resolve(): fm.summary(line.fm),
    }


def check_line(line: ProductLine) -> list[Diagnostic]:
    """The product-line checks (SPEC section 8) of a line whose models load."""
    from spl.resolver.line_checks import check_product_line

    return check_product_line(line)
