"""The deployment bundle: every generator's files plus the manifest, written atomically.

All files are produced in memory first, so a failing generator leaves nothing on disk;
then they are written to a temporary sibling folder that is renamed into place. The
manifest records the sha256 of every file, so bundles can be compared and cached.

A generator may hand back :class:`Skipped` instead of a file's bytes when it cannot
write an output: the product is one the output cannot carry (``zenoh/`` when no choice
of namespaces gives its architecture), or an optional system program it needs is missing
(Graphviz's ``dot`` for ``architecture.svg``). The bundle is complete without it, the
manifest's ``skipped`` lists it with the reason, and every command reporting the product
warns (docs/ci.md, "A product's warnings"). Nothing else in the job depends on such a
program.
"""

from __future__ import annotations

import errno
import hashlib
import importlib
import json
import os
import shutil
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from spl import __version__
from spl.dsl.tsm.printer import print_model
from spl.generators.bundle.inputs import BundleInputs, BundleMemo
from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.paths import BundleFiles, BundlePathClash, Skipped, check_paths
from spl.generators.bundle.resolved_xmi import resolved_xmi
from spl.generators.json_text import indented
from spl.resolver.architecture.product import ResolvedProduct, node_keys

# Each output target and its generator modules; each module offers
# generate(product, ...) -> {bundle path: bytes}, taking by keyword what READS gives it.
# `spl resolve --target` picks targets by name; resolved.tsm, resolved.xmi and
# manifest.json are in every bundle.
TARGETS = {
    "ros1": ("spl.generators.ros1.launch_files",),
    "ros2": ("spl.generators.ros2.launch_files",),
    "rapyuta": ("spl.generators.rapyuta.configurations",),
    "diagrams": ("spl.generators.diagrams.architecture",),
    "services": (
        "spl.generators.service.generator",
        "spl.generators.clients.generator",
        "spl.generators.deploy.generator",
    ),
    "kubernetes": ("spl.generators.kubernetes.manifests",),
    "zenoh": ("spl.generators.zenoh.configurations",),
}
GENERATORS = tuple(module for modules in TARGETS.values() for module in modules)


def choose_targets(text: str | None) -> tuple[str, ...]:
    """The targets named in ``--target a,b`` (all of them when ``text`` is None), in
    TARGETS order; an unknown name is a ValueError naming the known ones."""
    if text is None:
        return tuple(TARGETS)
    wanted = [name.strip() for name in text.split(",") if name.strip()]
    unknown = [name for name in wanted if name not in TARGETS]
    if unknown or not wanted:
        shown = ", ".join(unknown) if unknown else "none"
        raise ValueError(f"unknown target {shown}; targets: {', '.join(TARGETS)}")
    return tuple(name for name in TARGETS if name in wanted)


@dataclass(frozen=True)
class Bundle:
    """The files of one bundle (path -> bytes, manifest included) and the files skipped."""

    files: dict[str, bytes]
    skipped: dict[str, str]  # bundle path -> reason
    # the skipped paths a program missing on this machine left out (a picture not
    # rendered), which another machine writes: warned about, never the product's fault
    machine_skipped: frozenset[str]
    # the memo it was written with: its validation reuses it (the Rapyuta sets it found
    # clean are not checked again)
    memo: BundleMemo = field(default_factory=BundleMemo, compare=False)


# Generators that run an external program to render a picture; ``render_diagrams=False``
# asks them for the source only (their ``generate`` takes ``render``).
RENDERING = frozenset({"spl.generators.diagrams.architecture"})

# What a generator reads beside the product, as keyword arguments of its ``generate``,
# taken from the bundle's inputs when it runs: the options the bundle is written with,
# the product's Zenoh transport, computed once for kubernetes/ and zenoh/ together, and
# the memo of the bundles written with this one.
READS: dict[str, Callable[[BundleInputs], dict[str, object]]] = {
    "spl.generators.rapyuta.configurations": lambda inputs: {"clean": inputs.memo.clean},
    "spl.generators.diagrams.architecture": lambda inputs: {
        "render": inputs.options.render_diagrams,
        "quoted": inputs.memo.quoted,
    },
    "spl.generators.deploy.generator": lambda inputs: {"options": inputs.options},
    "spl.generators.kubernetes.manifests": lambda inputs: {
        "options": inputs.options,
        "wiring": inputs.transport,
        "plain": inputs.memo.plain,
    },
    "spl.generators.zenoh.configurations": lambda inputs: {"wiring": inputs.transport},
}


def build_bundle(
    product: ResolvedProduct,
    options: BundleOptions | None = None,
    memo: BundleMemo | None = None,
) -> Bundle:
    """Every file of the product's bundle (of the ``options``' targets, default all), in
    memory, and the files that were skipped; without ``render_diagrams`` no picture is
    rendered. ``memo``: the one of the bundles written with it (a run over many
    products), else the bundle's own."""
    options = BundleOptions() if options is None else options
    targets = tuple(TARGETS) if options.targets is None else options.targets
    inputs = BundleInputs(product, options, memo)  # the transport dies with this bundle
    files = BundleFiles(
        {
            "resolved.tsm": print_model(product.system).encode("utf-8"),
            "resolved.xmi": resolved_xmi(product.system, inputs.memo.xmi),
        }
    )
    skipped: dict[str, str] = {}
    machine_skipped: set[str] = set()
    for module_name in (m for target in targets for m in TARGETS[target]):
        generate = importlib.import_module(module_name).generate
        reads = READS.get(module_name)
        generated = generate(product, **reads(inputs)) if reads else generate(product)
        clash = (files.keys() | skipped.keys()) & generated.keys()
        if clash:
            raise BundlePathClash(f"{module_name} writes {sorted(clash)} already written")
        for path, data in generated.items():
            if isinstance(data, Skipped):
                skipped[path] = data.reason
                if module_name in RENDERING:  # only a missing program stops a picture
                    machine_skipped.add(path)
            else:
                files[path] = data
    skipped = dict(sorted(skipped.items()))
    check_paths([*files, "manifest.json"])
    files["manifest.json"] = manifest(product, files, skipped, targets)
    return Bundle(dict(sorted(files.items())), skipped, frozenset(machine_skipped), inputs.memo)


def bundle_files(product: ResolvedProduct) -> dict[str, bytes]:
    """The bundle's files (path -> bytes), for callers that do not report skipped files."""
    return build_bundle(product).files


def manifest(
    product: ResolvedProduct,
    files: dict[str, bytes],
    skipped: dict[str, str] | None = None,
    targets: tuple[str, ...] | None = None,
) -> bytes:
    """``manifest.json``: one key set for every product (docs/outputs.md), so a tool
    reading ``warnings``, ``skipped`` or ``left_out`` finds it empty, never absent."""
    system = product.system
    keys = node_keys(system)
    document = {
        "product": product.name,
        "features": list(product.features),
        "attributes": product.attributes,
        "sharing": {
            keys[id(node)]: node.sharing.name
            for container in system.containers
            for node in container.nodes
        },
        "placement": {
            keys[id(node)]: container.name
            for container in system.containers
            for node in container.nodes
        },
        "migrations": [
            {"node": m.node, "from": m.source, "to": m.target} for m in product.migrations
        ],
        "warnings": [str(w) for w in product.warnings],
        "skipped": dict(skipped or {}),
        "left_out": dict(product.left_out),
        "targets": list(TARGETS if targets is None else targets),
        "toolchain": {"name": "spl-robotics", "version": __version__},
        "files": {path: hashlib.sha256(data).hexdigest() for path, data in sorted(files.items())},
    }
    return (indented(document, sort_keys=True) + "\n").encode("utf-8")


def write_bundle(files: dict[str, bytes], out: Path) -> None:
    """Write ``files`` as the folder ``out``, all or nothing; paths that would land on
    one file are refused before anything is written (:func:`check_paths`). ``out`` may
    be new, an empty folder or an earlier bundle (which the new one replaces); anything
    else there (a file, the product line's own folder, a user's folder) is refused with
    FileExistsError before anything is written, since replacing it would delete it."""
    check_paths(files)
    out = Path(out)
    if out.exists() or out.is_symlink():
        _check_replaceable(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = out.parent / f".{out.name}.tmp-{os.getpid()}"
    retired = out.parent / f".{out.name}.old-{os.getpid()}"
    try:
        for relative, data in files.items():
            target = staging / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        if out.exists():
            out.rename(retired)
        staging.rename(out)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
        shutil.rmtree(retired, ignore_errors=True)


# The files by which a folder is known as a bundle spl wrote: a product's manifest or a
# fleet's, each naming spl's toolchain.
BUNDLE_MANIFESTS = ("manifest.json", "fleet.json")


def _check_replaceable(out: Path) -> None:
    """FileExistsError unless ``out`` is an empty folder or a bundle spl wrote."""
    if out.is_dir() and not out.is_symlink():
        if not any(out.iterdir()) or any(_written_by_spl(out / name) for name in BUNDLE_MANIFESTS):
            return
        reason = "exists and is not a bundle written by spl (no spl manifest.json in it)"
    elif out.is_symlink():
        reason = "is a symbolic link"
    else:
        reason = "exists and is not a folder"
    raise FileExistsError(errno.EEXIST, f"{reason}; give another -o or remove it", str(out))


def _written_by_spl(manifest: Path) -> bool:
    try:
        document = json.loads(manifest.read_bytes())
    except (OSError, ValueError):
        return False
    toolchain = document.get("toolchain") if isinstance(document, dict) else None
    return isinstance(toolchain, dict) and toolchain.get("name") == "spl-robotics"
