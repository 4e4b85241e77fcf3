"""What the generators of one bundle read beside the product and its
:class:`~spl.generators.bundle.options.BundleOptions` (docs/outputs.md).

:class:`BundleInputs` is what a product's generators read beside the product: the
options, and the product's Zenoh transport, which both ``kubernetes/`` and ``zenoh/``
need. It is made by the one call that builds the bundle and dies with it, so the
transport is computed at most once per bundle and never outlives the product it was
computed from. :class:`FleetInputs` is the same for a fleet bundle, whose transport is
computed over all robots together.

:class:`BundleMemo` is what writing bundles learns that holds for every bundle (how
Graphviz quotes a text, whether YAML writes a string plain, which Rapyuta file sets
pass, what ``resolved.xmi`` asks of the metamodel): an application writing many
bundles (``spl validate``'s run over a line, a fleet's robots) makes one and passes it
in, so the products share it; a bundle written without one makes its own, which dies
with it. The bundle writer hands each target its part (``READS`` in
:mod:`spl.generators.bundle.writer`): no target reads another's.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.resolved_xmi import MetamodelRoles
from spl.generators.rapyuta.rules import CleanSets
from spl.generators.transport.bridge import Transport, transport
from spl.resolver.architecture.product import ResolvedProduct
from spl.resolver.fleets.deployment import FleetDeployment


@dataclass
class BundleMemo:
    """Answers that depend on a text alone, kept while bundles are written with it
    (docs/performance.md: the products of a line repeat most of their ids, labels and
    files). Each is the memo of one pure function, so sharing one changes no byte."""

    quoted: dict[tuple[type, str], str] = field(default_factory=dict)  # Graphviz's quoting
    plain: dict[str, bool] = field(default_factory=dict)  # a YAML string written plain
    clean: CleanSets = field(default_factory=CleanSets)  # Rapyuta file sets found clean
    xmi: MetamodelRoles = field(default_factory=MetamodelRoles)  # resolved.xmi's look-ups

    def bounded(self) -> BundleMemo:
        """This memo, its tables emptied when they have grown past what a long run
        (thousands of products) should hold."""
        if len(self.quoted) > MEMO_TEXTS:
            self.quoted.clear()
        if len(self.plain) > MEMO_TEXTS:
            self.plain.clear()
        return self


MEMO_TEXTS = 65_536


class BundleInputs:
    """What the generators of one product's bundle read beside the product."""

    def __init__(
        self, product: ResolvedProduct, options: BundleOptions, memo: BundleMemo | None = None
    ) -> None:
        self.product = product
        self.options = options
        self.memo = (BundleMemo() if memo is None else memo).bounded()

    @cached_property
    def transport(self) -> Transport:
        """The product's Zenoh transport, computed when first read (a bundle without
        ``kubernetes/`` and ``zenoh/`` never computes it). Read-only for its readers."""
        return transport(self.product)


class FleetInputs:
    """What the generators of one fleet bundle read beside its deployment; its robots'
    bundles share its memo."""

    def __init__(
        self,
        deployment: FleetDeployment,
        options: BundleOptions,
        memo: BundleMemo | None = None,
    ) -> None:
        self.deployment = deployment
        self.options = options
        self.memo = BundleMemo() if memo is None else memo

    @cached_property
    def transport(self) -> Transport:
        """The fleet's Zenoh transport: every robot's product together, computed when
        first read. Read-only for its readers."""
        return transport(*(entry.product for entry in self.deployment.robots))

    @property
    def skipped(self) -> dict[str, str]:
        """What the fleet bundle leaves out and why: ``zenoh/`` when Zenoh cannot carry
        the fleet, whose instances then run without bridges."""
        wiring = self.transport
        if wiring.carried:
            return {}
        return {"zenoh/": f"Zenoh cannot carry this fleet: {wiring.reason}"}
