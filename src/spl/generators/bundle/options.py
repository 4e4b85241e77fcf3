"""How a bundle is written, as its command was told (docs/outputs.md, docs/kubernetes.md).

``spl resolve``, ``spl fleet resolve`` and ``spl validate`` make one
:class:`BundleOptions` from their command line and hand it down through
``spl.pipeline.derive`` and :func:`spl.generators.bundle.writer.build_bundle` to the generators
that read it, so a reader of a generator sees every input it depends on in its
signature. What a bundle's generators read beside the product and its options is in
:mod:`spl.generators.bundle.inputs`.
"""

from __future__ import annotations

from dataclasses import dataclass

from spl.generators.workloads.security import checked_namespace, namespace_for


@dataclass(frozen=True)
class BundleOptions:
    """The choices a bundle is written with; the defaults are ``spl resolve``'s.

    ``targets``: the output targets written (``--target``), None for all of them.
    ``render_diagrams``: whether ``architecture.svg`` is rendered (``spl validate``
    without ``--diagrams`` skips the ``dot`` process; the source is always written).
    ``namespace``: the Kubernetes namespace of every object (``--namespace``, a
    DNS-1123 label, checked here), None for the one named from the product or fleet.
    """

    targets: tuple[str, ...] | None = None
    render_diagrams: bool = True
    namespace: str | None = None

    def __post_init__(self) -> None:
        if self.namespace is not None:
            checked_namespace(self.namespace)  # ValueError saying what is wrong

    def namespace_of(self, owner: str) -> str:
        """The namespace of product (or fleet) ``owner``'s objects: the one chosen, else
        its own (:func:`namespace_for`)."""
        return self.namespace if self.namespace is not None else namespace_for(owner)
