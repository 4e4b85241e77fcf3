"""The Ecore metamodels of spl, loaded once with pyecore.

The Python classes of every model element come from the ``.ecore`` files next to this
module, so the metamodel an Eclipse EMF user opens and the classes the toolchain
instantiates cannot drift apart.
"""

from __future__ import annotations

from functools import cache
from importlib.resources import files
from types import SimpleNamespace

from pyecore.ecore import EClass, EEnum, EPackage
from pyecore.resources import URI, ResourceSet

__all__ = ["fm", "load", "resource_set", "rm", "tsm"]


@cache
def resource_set() -> ResourceSet:
    """One resource set holding every metamodel, so cross-metamodel references resolve."""
    rset = ResourceSet()
    for name in ("tsm", "fm", "rm"):
        path = files(__name__).joinpath(f"{name}.ecore")
        if not path.is_file():
            continue
        resource = rset.get_resource(URI(str(path)))
        package: EPackage = resource.contents[0]
        rset.metamodel_registry[package.nsURI] = package
    return rset


@cache
def load(name: str) -> SimpleNamespace:
    """The metamodel ``name`` as a namespace of its classes and enums (``load('tsm').Node``)."""
    for package in resource_set().metamodel_registry.values():
        if isinstance(package, EPackage) and package.name == name:
            members = {
                c.name: (c.python_class if isinstance(c, EClass) else c)
                for c in package.eClassifiers
                if isinstance(c, (EClass, EEnum))
            }
            return SimpleNamespace(package=package, **members)
    raise KeyError(f"no metamodel named {name!r}")


def tsm() -> SimpleNamespace:
    return load("tsm")


def fm() -> SimpleNamespace:
    return load("fm")


def rm() -> SimpleNamespace:
    return load("rm")
