"""Write the typed metamodel modules: one static class per metaclass of each ``.ecore``.

    .venv/bin/python scripts/ecore_types.py          # (re)write src/spl/metamodels/*_types.py
    .venv/bin/python scripts/ecore_types.py --check  # exit 1 when one is stale

spl's model classes are made from ``src/spl/metamodels/{tsm,fm,rm}.ecore`` at run time, so a type
checker cannot see them; ``src/spl/metamodels/tsm_types.py``, ``fm_types.py`` and
``rm_types.py`` declare them for it (imported under ``if TYPE_CHECKING:`` only, they cost
nothing at run time). Each metaclass becomes a class with its supertypes, its features
typed from the metamodel (an ``EString`` is ``str``, an ``EIntegerObject`` ``int | None``,
an enum its literal class, a reference its class, ``| None`` when its lower bound is 0, a
many-valued feature ``Many[...]``), a keyword constructor, and ``eContainer()`` answering
the classes that may contain it. Each module ends with ``Metamodel``, the namespace
``spl.metamodels.tsm()`` (and ``fm()``, ``rm()``) returns. ``tests/cli/test_ecore_types.py``
fails when a module differs from what this script writes from the ``.ecore`` files.
"""

from __future__ import annotations

import argparse
import keyword
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FOLDER = ROOT / "src" / "spl" / "metamodels"
NAMES = ("tsm", "fm", "rm")
DOCUMENTATION = "http://www.eclipse.org/emf/2002/GenModel"
DATA_TYPES = {
    "EString": "str",
    "EInt": "int",
    "EBoolean": "bool",
    "EDouble": "float",
    "EIntegerObject": "int | None",
}
WIDTH = 100


def _packages() -> dict:
    from spl.metamodels import packages  # spl installed (the venv): its metamodel reader

    return packages()


def _documentation(element) -> str:
    for annotation in element.eAnnotations:
        if annotation.source == DOCUMENTATION and "documentation" in annotation.details:
            return " ".join(annotation.details["documentation"].split())
    return ""


def _docstring(text: str, indent: str) -> list[str]:
    text = text.replace("\\", "\\\\").replace('"""', "'''")
    if len(indent) + 6 + len(text) <= WIDTH:
        return [f'{indent}"""{text}"""']
    lines = textwrap.wrap(text, WIDTH - len(indent) - 3, break_on_hyphens=False)
    lines[0] = '"""' + lines[0]
    return [f"{indent}{line}" for line in lines] + [f'{indent}"""']


def _comment(text: str, indent: str) -> list[str]:
    width = WIDTH - len(indent) - 3
    return [f"{indent}#: {line}" for line in textwrap.wrap(text, width, break_on_hyphens=False)]


class _Writer:
    """The module of one package: names of classes of another package are qualified by
    that package's module (``tsm.Node`` in ``rm_types``)."""

    def __init__(self, package, all_packages: dict) -> None:
        self.package = package
        self.all_packages = all_packages
        self.imported: set[str] = set()
        self.bases: set[str] = {"EPackage"}  # of model_types; EPackage: the namespace's

    def name(self, classifier) -> str:
        owner = classifier.ePackage.name
        if owner == self.package.name:
            return classifier.name
        self.imported.add(owner)
        return f"{owner}.{classifier.name}"

    def type_of(self, feature) -> str:
        from pyecore.ecore import EEnum, EReference

        etype = feature.eType
        if isinstance(feature, EReference) or isinstance(etype, EEnum):
            single = self.name(etype)
        else:
            single = DATA_TYPES[etype.name]
        if feature.many:
            self.bases.add("Many")
            return f"Many[{single}]"
        if isinstance(feature, EReference) and feature.lowerBound < 1:
            return f"{single} | None"
        return single

    def containers(self, eclass) -> list[str]:
        """The classes with a containment whose type is ``eclass`` or one of its
        supertypes (in the order of the packages, then of their classes)."""
        from pyecore.ecore import EClass, EReference

        accepted = {id(eclass)} | {id(s) for s in eclass.eAllSuperTypes()}
        found: list[str] = []
        for package in self.all_packages.values():
            for owner in package.eClassifiers:
                if not isinstance(owner, EClass):
                    continue
                for feature in owner.eStructuralFeatures:
                    if (
                        isinstance(feature, EReference)
                        and feature.containment
                        and id(feature.eType) in accepted
                        and self.name(owner) not in found
                    ):
                        found.append(self.name(owner))
        return found

    def enum(self, eenum) -> list[str]:
        literals = [literal.name for literal in eenum.eLiterals]
        self.bases |= {"EnumLiteral", "EnumType"}
        lines = ["", "", f"class {eenum.name}(EnumLiteral):"]
        lines += _docstring(f"A literal of the enum {eenum.name}.", "    ")
        choices = ", ".join(f'"{name}"' for name in literals)
        lines += ["", f"    name: Literal[{choices}]"]
        lines += ["", "", f"class {eenum.name}Enum(EnumType):"]
        lines += _docstring(f"The enum {eenum.name}: its literals by name.", "    ")
        lines.append("")
        for name in literals:
            if keyword.iskeyword(name):
                lines.append(f"    # {name}: a keyword, reached through getEEnumLiteral({name!r})")
            else:
                lines.append(f"    {name}: {eenum.name}")
        lookup = f"def getEEnumLiteral(self, name: builtins.str) -> {eenum.name} | None: ..."
        lines += ["", f"    {lookup}"]
        return lines

    def eclass(self, eclass) -> list[str]:
        bases = ", ".join(self.name(s) for s in eclass.eSuperTypes)
        if not bases:
            bases = "EObject"
            self.bases.add(bases)
        lines = ["", "", f"class {eclass.name}({bases}):"]
        documentation = _documentation(eclass)
        body: list[str] = []
        if documentation:
            body += _docstring(documentation, "    ")
        if eclass.abstract:
            if body:
                body.append("")
            body.append("    # abstract: only its subclasses have instances")
        features = list(eclass.eStructuralFeatures)
        if features and body:
            body.append("")
        for feature in features:
            text = _documentation(feature)
            if text:
                body += _comment(text, "    ")
            body.append(f"    {feature.name}: {self.type_of(feature)}")
        if not eclass.abstract:
            if body:
                body.append("")
            body += self.constructor(eclass)
        containers = self.containers(eclass)
        if containers:
            if body:
                body.append("")
            body.append(f"    def eContainer(self) -> {' | '.join(containers)}: ...")
        return lines + (body or ["    pass"])

    def constructor(self, eclass) -> list[str]:
        parameters = []
        for feature in eclass.eAllStructuralFeatures():
            kind = self.type_of(feature)
            if kind.startswith("Many["):
                kind = "Iterable[" + kind[len("Many[") :]
            parameters.append(f"{feature.name}: {kind} = ...")
        one_line = f"    def __init__(self, *, {', '.join(parameters)}) -> None: ..."
        if len(one_line) <= WIDTH:
            return [one_line]
        return [
            "    def __init__(",
            "        self,",
            "        *,",
            *(f"        {parameter}," for parameter in parameters),
            "    ) -> None: ...",
        ]

    def namespace(self) -> list[str]:
        from pyecore.ecore import EClass, EEnum

        own = self.package.name
        lines = ["", "", "class Metamodel:"]
        lines += _docstring(
            f"The {own} metamodel as its classes and enums, as ``spl.metamodels.{own}()`` "
            "gives it (and the plain twins, for the tsm).",
            "    ",
        )
        lines += ["", "    package: EPackage"]
        if own == "tsm":
            lines.append("    located_later: bool  # the plain twins only (spl.dsl.tsm.plain)")
        for classifier in self.package.eClassifiers:
            if isinstance(classifier, EEnum):
                lines.append(f"    {classifier.name}: {own}.{classifier.name}Enum")
            elif isinstance(classifier, EClass):
                lines.append(f"    {classifier.name}: type[{own}.{classifier.name}]")
        return lines

    def module(self) -> str:
        from pyecore.ecore import EClass, EEnum

        own = self.package.name
        body: list[str] = []
        for classifier in self.package.eClassifiers:
            if isinstance(classifier, EEnum):
                body += self.enum(classifier)
        for classifier in self.package.eClassifiers:
            if isinstance(classifier, EClass):
                body += self.eclass(classifier)
        body += self.namespace()
        self.imported.add(own)
        head = [f'"""The {own} metamodel (src/spl/metamodels/{own}.ecore) for the type checker.']
        documentation = _documentation(self.package)
        if documentation:
            head += ["", *textwrap.wrap(documentation, WIDTH, break_on_hyphens=False)]
        head += [
            "",
            "Written by scripts/ecore_types.py from the .ecore file: do not edit (the test",
            "tests/cli/test_ecore_types.py fails when it is stale). Import it under",
            "``if TYPE_CHECKING:`` only.",
            '"""',
            "",
            "from __future__ import annotations",
            "",
        ]
        if "EnumType" in self.bases:
            head.append("import builtins")
        uses_iterable = any("Iterable[" in line for line in body)
        if uses_iterable:
            head.append("from collections.abc import Iterable")
        literal = ", Literal" if any("Literal[" in line for line in body) else ""
        head.append(f"from typing import TYPE_CHECKING{literal}")
        head.append("")
        modules = sorted(self.imported)
        bases = ", ".join(sorted(self.bases, key=str.lower))
        head.append(f"from spl.metamodels.model_types import {bases}")
        # the metamodels refer to each other (an rm statement holds a tsm topic): for the
        # type checker only, so that importing one never runs another
        head += ["", "if TYPE_CHECKING:"]
        head += [f"    from spl.metamodels import {name}_types as {name}" for name in modules]
        return "\n".join(head + body) + "\n"


def modules() -> dict[Path, str]:
    """Each typed module's path and the text this script writes for it."""
    found = _packages()
    return {FOLDER / f"{name}_types.py": _Writer(found[name], found).module() for name in NAMES}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 when a module is stale")
    options = parser.parse_args(argv)
    stale = []
    for path, text in modules().items():
        if path.exists() and path.read_text(encoding="utf-8") == text:
            continue
        stale.append(path)
        if not options.check:
            path.write_text(text, encoding="utf-8")
    for path in stale:
        verb = "is stale" if options.check else "written"
        shown = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
        print(f"{shown} {verb}", file=sys.stderr)
    return 1 if options.check and stale else 0


if __name__ == "__main__":
    sys.exit(main())
