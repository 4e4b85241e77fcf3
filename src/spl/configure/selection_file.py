"""A session's selection as a ``products/*.yaml`` file, written and read back
(docs/resolution.md, "Selections"; docs/configure.md, "Import and export").

Export writes the keys in the reader's order, so the same choices give the same bytes.
Import goes through the selection file's own reader (:func:`load_selection_file`, which
keeps the line and column of every name) and then the feature model's check, so an
unknown feature is reported at its place, every one of them, with the same message
``spl resolve`` gives; nothing of the file is taken unless all of it is right.
"""

from __future__ import annotations

import dataclasses
import tempfile
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import yaml

from spl.configure.session import Choices, InputError
from spl.core.diagnostics import Diagnostic, ModelError
from spl.resolver.resolution.product_selection import load_selection_file
from spl.resolver.resolution.selection import check_selection

if TYPE_CHECKING:
    from spl.configure.session import Session
    from spl.resolver.resolution.capabilities import RobotCapabilities
    from spl.resolver.resolution.product_selection import ProductSelection


def selection_text(selection: ProductSelection) -> str:
    """The YAML of a selection, keys in the file format's order, empty ones left out."""
    data: dict[str, object] = {"product": selection.name, "features": selection.features}
    if selection.deselected:
        data["deselected"] = selection.deselected
    if selection.sharing:
        data["sharing"] = dict(selection.sharing)
    if selection.attributes:
        data["attributes"] = dict(selection.attributes)
    if selection.deployment:
        data["deployment"] = {c: dict(s) for c, s in selection.deployment.items()}
    header = "# written by spl configure (docs/configure.md)\n"
    return header + yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=100)


def read_selection_text(session: Session, text: str, filename: str) -> Choices:
    """The choices a selection file's text makes; ModelError with every problem located
    in ``filename`` (unknown features, bad values), Impossible when it has no product."""
    name = Path(filename).name or "selection.yaml"
    with tempfile.TemporaryDirectory(prefix="spl-configure-") as folder:
        path = Path(folder) / name
        path.write_text(text, encoding="utf-8")
        try:
            selection = _checked(session, path)
        except ModelError as exc:
            raise ModelError([_renamed(d, str(path), name) for d in exc.diagnostics]) from None
    choices = Choices()
    for feature in selection.features:
        choices.decisions[feature] = True
    for feature in selection.deselected:
        choices.decisions[feature] = False
    problems = []
    for feature in choices.decisions:
        fixed_by = session.fixed_by(feature)
        if fixed_by and session.assumptions().get(feature) != choices.decisions[feature]:
            where = selection.location(feature)
            problems.append(f"{where.file}:{where.line}:{where.col}: {feature} is decided "
                            f"by {fixed_by}: {session.lock_text(feature)}")  # fmt: skip
    if problems:
        raise InputError("; ".join(problems).replace(str(path), name))
    for feature in list(choices.decisions):
        if session.fixed_by(feature):
            del choices.decisions[feature]
    choices.capabilities = dict(session.choices.capabilities)
    choices.capability_reasons = dict(session.choices.capability_reasons)
    choices.capability_file = session.choices.capability_file
    trial = _trial(session)
    for key, value in selection.attributes.items():
        shown = "true" if value is True else "false" if value is False else str(value)
        _apply(partial(trial.set_attribute, key, shown), selection.location(key), path, name)
    for feature, mode in selection.sharing.items():
        where = selection.location(f"sharing:{feature}")
        _apply(partial(trial.set_sharing, feature, mode), where, path, name)
    for container, settings in selection.deployment.items():
        where = selection.location(f"deployment:{container}")
        for key, value in settings.items():
            _apply(partial(trial.set_deployment, container, key, value), where, path, name)
    choices.attributes = trial.choices.attributes
    choices.sharing = trial.choices.sharing
    choices.deployment = trial.choices.deployment
    return choices


def read_capabilities_text(text: str, filename: str) -> RobotCapabilities:
    """A robot capability file's text read as ``spl resolve --capabilities`` reads the
    file; ModelError with its problems located in ``filename``."""
    from spl.resolver.resolution.capabilities import load_capabilities

    name = Path(filename).name or "robot.yaml"
    with tempfile.TemporaryDirectory(prefix="spl-configure-") as folder:
        path = Path(folder) / name
        path.write_text(text, encoding="utf-8")
        try:
            capabilities = load_capabilities(path)
        except ModelError as exc:
            raise ModelError([_renamed(d, str(path), name) for d in exc.diagnostics]) from None
    capabilities.source = name
    capabilities.locations = {
        key: dataclasses.replace(where, file=name) for key, where in capabilities.locations.items()
    }
    return capabilities


def _checked(session: Session, path: Path) -> ProductSelection:
    selection = load_selection_file(path)
    if selection.capabilities is not None:
        raise ModelError(
            [Diagnostic(selection.location("capabilities"),
                        "capabilities: import the robot capability file itself")]
        )  # fmt: skip
    formula = session.workspace.formula
    # unknown names and contradictions, each at its place (ModelError)
    check_selection(formula, selection.features, selection.deselected, selection.locations)
    return selection


def _trial(session: Session) -> Session:
    from spl.configure.session import Session as Fresh

    return Fresh(session.workspace)


def _apply(change, where, path: Path, name: str) -> None:
    try:
        change()
    except InputError as exc:
        raise InputError(f"{name}:{where.line}:{where.col}: {exc}") from None


def _renamed(diagnostic: Diagnostic, temporary: str, name: str) -> Diagnostic:
    """A diagnostic about the uploaded file, named as the user named it."""
    location = diagnostic.location
    if location is not None and location.file == temporary:
        location = dataclasses.replace(location, file=name)
    message = diagnostic.message.replace(temporary, name)
    return dataclasses.replace(diagnostic, location=location, message=message)
