"""How model identifiers become the names of what is generated from a product.

The Resolution Engine binds a product's writer and reader nodes to the client packages
the generators write, so the resolved architecture and the generated files must name
them alike; the data-acquisition services, their deployment files and the Kubernetes
objects derive their names the same way. The rules live here, below both.
"""

from __future__ import annotations

import re

# a model name that may reach generated code (Python, YAML, shell) as it is
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def snake_case(name: str) -> str:
    """``PositionStore`` -> ``position_store``; ``EV3Writer`` -> ``ev3_writer``."""
    if not IDENTIFIER.match(name):
        raise ValueError(f"not an identifier: {name!r}")
    words = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", name)
    words = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1_\2", words)
    return re.sub(r"_+", "_", words).strip("_").lower() or "x"


def dns_name(name: str) -> str:
    """A Kubernetes/compose-safe name (RFC 1123 label) for a validated identifier."""
    return snake_case(name).replace("_", "-").strip("-")[:63] or "x"
