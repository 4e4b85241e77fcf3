"""How model identifiers become the names of what is generated from a product.

The Resolution Engine binds a product's writer and reader nodes to the client packages
the generators write, so the resolved architecture and the generated files must name
them alike; the data-acquisition services, their deployment files and the Kubernetes
objects derive their names the same way. The rules live here, below both.

Model names are unique only inside their container: two cloud containers may each hold
a store ``PositionStore``, two robot containers a writer ``PositionWriter``. What is
generated from them shares one bundle (one ``services/`` folder, one PostgreSQL
database, one Kubernetes namespace), so :func:`unique_names` gives each element a name
of its own, qualified with its container only where the plain name would be shared.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Callable, Sequence
from typing import TypeVar

# a model name that may reach generated code (Python, YAML, shell) as it is
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
DNS_LIMIT = 63  # an RFC 1035 label (a Kubernetes Service name)
T = TypeVar("T")
_LOWER_UPPER = re.compile(r"([a-z0-9])([A-Z])")  # positionStore -> position_Store
_ACRONYM_WORD = re.compile(r"([A-Z]+)([A-Z][a-z])")  # EV3Writer -> EV3_Writer
_UNDERSCORES = re.compile(r"_+")


def snake_case(name: str) -> str:
    """``PositionStore`` -> ``position_store``; ``EV3Writer`` -> ``ev3_writer``."""
    if not IDENTIFIER.match(name):
        raise ValueError(f"not an identifier: {name!r}")
    words = _LOWER_UPPER.sub(r"\1_\2", name)
    words = _ACRONYM_WORD.sub(r"\1_\2", words)
    return _UNDERSCORES.sub("_", words).strip("_").lower() or "x"


def lower_identifier(name: str, lead: str) -> str:
    """``snake_case(name)``, starting with a letter as Python packages, ROS packages and
    environment variables must: ``_1Store`` -> ``<lead>_1_store``."""
    slug = snake_case(name)
    return slug if slug[0].isalpha() else f"{lead}_{slug}"


def dns_name(name: str) -> str:
    """A Kubernetes/compose-safe name (RFC 1035 label: a letter first, at most 63
    characters) for a validated identifier; a longer one keeps its start and a digest
    of the whole, so two long names stay apart."""
    label = lower_identifier(name, "x").replace("_", "-")
    if len(label) <= DNS_LIMIT:
        return label
    digest = hashlib.sha256(name.encode("utf-8")).hexdigest()[:8]
    return f"{label[: DNS_LIMIT - 9].rstrip('-')}-{digest}"


ZENOH_ROUTER = "zenoh-router"  # the Kubernetes objects of the product's Zenoh router


def kubernetes_label(text: str) -> str:
    """The DNS-1035 label a model name or placement tag maps to by Kubernetes' rule:
    lower case, ``_`` -> ``-``, no leading or trailing ``-`` (may still be invalid: the
    Kubernetes generator checks)."""
    return text.lower().replace("_", "-").strip("-")


def unique_names(
    elements: Sequence[tuple[T, str, str]],
    forms: Callable[[T, str], set[str]],
    reserved: frozenset[str] = frozenset(),
) -> list[str]:
    """One name per ``(element, container, name)``, in order: ``name`` itself when no
    other element's name gives one of the same ``forms(element, name)`` (the folder,
    package, table, DNS names... derived from it) and none is ``reserved``, else
    ``<container>_<name>``; a name that still meets one given before gets ``_2``,
    ``_3``... So the names are unique by construction, deterministic, and unchanged
    wherever nothing is shared."""
    plain = [forms(element, name) for element, _, name in elements]
    seen: dict[str, int] = {}
    for derived in plain:
        for form in derived:
            seen[form] = seen.get(form, 0) + 1
    taken = set(reserved)
    names = []
    for (element, container, name), derived in zip(elements, plain, strict=True):
        if derived & taken or any(seen[form] > 1 for form in derived):
            base = f"{container}_{name}"
            candidate, number, derived = base, 1, forms(element, base)
            while derived & taken:
                number += 1
                candidate = f"{base}_{number}"
                derived = forms(element, candidate)
        else:
            candidate = name
        taken |= derived
        names.append(candidate)
    return names
