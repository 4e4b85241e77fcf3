"""Names that reach Kubernetes, derived from model names and checked before use.

Kubernetes object names used here (Deployments, Services, ConfigMaps) are DNS-1035
labels: lower case letters, digits and ``-``, starting with a letter, ending with a
letter or digit, at most 63 characters (a Service name must be one; the others follow
it so one name serves all objects of an instance). A model name maps to one by a fixed
rule: lower case, ``_`` becomes ``-``, leading and trailing ``-`` are dropped. Two
names that map to one (``Cloud_A`` and ``cloud-a``), a name that maps to nothing
usable, or one too long once the longest suffix is added, are located errors: a
manifest is never emitted with a name Kubernetes refuses or that two objects share.

Label values (product, container, placement) may hold upper case and ``_`` but at
most 63 characters; a longer value keeps its first 54 characters and a digest of the
whole, so it stays deterministic and distinct, and the full text goes in an
annotation.
"""

from __future__ import annotations

import hashlib
import re
from typing import TYPE_CHECKING

from spl.core.diagnostics import Diagnostic, Location, location_of
from spl.resolver.architecture.generated_names import ZENOH_ROUTER, kubernetes_label

if TYPE_CHECKING:
    from spl.resolver.architecture.placement import Instance

DNS_LABEL = re.compile(r"[a-z]([-a-z0-9]*[a-z0-9])?")
LABEL_VALUE = re.compile(r"([A-Za-z0-9]([-A-Za-z0-9_.]*[A-Za-z0-9])?)?")
MAX_LENGTH = 63


dns_label = kubernetes_label  # a model name's label (may be invalid: check with DNS_LABEL)


def label_value(text: str) -> str:
    """``text`` as a Kubernetes label value: as is when it fits, else shortened with a
    digest of the whole (deterministic, never two texts to one value in practice)."""
    if len(text) <= MAX_LENGTH and LABEL_VALUE.fullmatch(text):
        return text
    cleaned = re.sub(r"[^-A-Za-z0-9_.]", "_", text)[:54].strip("-_.")
    digest = hashlib.sha256(text.encode("utf-8")).hexdigest()[:8]
    return f"{cleaned}-{digest}" if cleaned else digest


class ObjectNames:
    """Assigns each instance one object name, refusing what Kubernetes would refuse.

    ``room`` is the length of the longest suffix appended to a name (``-launch``);
    ``reserved`` are names the generator itself uses for other objects.
    """

    def __init__(self, errors: list[Diagnostic], room: int, reserved: tuple[str, ...]) -> None:
        self.errors = errors
        self.room = room
        self.taken: dict[str, str] = {name: "a generated object" for name in reserved}

    def name(self, text: str, where: Location | None, what: str) -> str:
        """The object name for ``text`` (``what`` names it in messages; errors are
        located at ``where``); an unusable name is reported and a placeholder returned."""
        name = dns_label(text)
        problem = None
        if not DNS_LABEL.fullmatch(name):
            problem = (
                f"{what} {text!r} gives no Kubernetes name (after lower-casing and "
                "'_' -> '-', it must start with a letter and hold only letters, digits and '-')"
            )
        elif len(name) + self.room > MAX_LENGTH:
            problem = (
                f"{what} {text!r} gives the Kubernetes name {name!r}, longer than "
                f"{MAX_LENGTH - self.room} characters (63 with its suffixes): shorten it"
            )
        elif name in self.taken:
            problem = (
                f"{what} {text!r} and {self.taken[name]} both give the Kubernetes name "
                f"{name!r}: rename one of them"
            )
        if problem:
            self.errors.append(Diagnostic(where, problem))
            return "invalid"
        self.taken[name] = f"{what} {text!r}"
        return name


ROUTER = ZENOH_ROUTER  # the Zenoh router's objects
CONFIG_SUFFIX = "-config"  # an instance's ConfigMap: <name>-config


def instance_names(instances: list[Instance], errors: list[Diagnostic]) -> dict[str, str]:
    """The object name of every cloud instance (``resolver.placement.Instance``), by its
    placement tag: the Deployment, the Service the Zenoh router connects to and, with
    ``-config``, the ConfigMap. Problems are located at the instance's container."""
    names = ObjectNames(errors, len(CONFIG_SUFFIX), (ROUTER,))
    return {
        instance.place.tag: names.name(
            instance.place.tag, location_of(instance.container), "cloud instance"
        )
        for instance in instances
    }
