"""The Ecore metamodels of spl, loaded once with pyecore.

The Python classes of every model element come from the ``.ecore`` files next to this
module, so the metamodel an Eclipse EMF user opens and the classes the toolchain
instantiates cannot drift apart. The files are read by :mod:`.ecore_files` (the
standard library's XML parser and pyecore's constructors: pyecore's XMI resource layer
and its imports are paid only by code that saves or loads XMI models).
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any, cast

from pyecore.ecore import EClass, EEnum, EPackage

from spl.metamodels.ecore_files import read_packages

if TYPE_CHECKING:  # the model classes for the type checker (scripts/ecore_types.py)
    from spl.metamodels import fm_types, rm_types, tsm_types

__all__ = ["fm", "load", "packages", "resource_set", "rm", "tsm"]

NAMES = ("tsm", "fm", "rm")


@cache
def packages() -> dict[str, EPackage]:
    """Every metamodel package by name, cross-metamodel references resolved."""
    folder = Path(__file__).parent  # not importlib.resources: it imports zipfile, tempfile...
    found = read_packages([folder / f"{name}.ecore" for name in NAMES])
    return {package.name: package for package in found.values()}


@cache
def resource_set() -> Any:
    """A pyecore ResourceSet whose metamodel registry holds the metamodels (for XMI)."""
    from pyecore.resources import ResourceSet

    rset = ResourceSet()
    for package in packages().values():
        rset.metamodel_registry[package.nsURI] = package
    return rset


@cache
def load(name: str) -> SimpleNamespace:
    """The metamodel ``name`` as a namespace of its classes and enums (``load('tsm').Node``)."""
    package = packages().get(name)
    if package is None:
        raise KeyError(f"no metamodel named {name!r}")
    members = {
        c.name: (c.python_class if isinstance(c, EClass) else c)
        for c in package.eClassifiers
        if isinstance(c, (EClass, EEnum))
    }
    return SimpleNamespace(package=package, **members)


def tsm() -> tsm_types.Metamodel:
    return cast("tsm_types.Metamodel", load("tsm"))


def fm() -> fm_types.Metamodel:
    return cast("fm_types.Metamodel", load("fm"))


def rm() -> rm_types.Metamodel:
    return cast("rm_types.Metamodel", load("rm"))
