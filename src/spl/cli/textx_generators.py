"""The emitters registered with textX (entry-point group ``textx_generators``).

``textx generate mapping.rm --target ros1 --features YouBot,Stereo,AdditionalPC,Room``
resolves the product line of the resolution model for those features (a list or a
product YAML file) and writes that target's files, as ``spl resolve`` would. It loads
and resolves, so it belongs with the commands, above the generators it calls.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import Any

from textx import generator
from textx.exceptions import TextXError
from textx.registration import GeneratorParam

from spl.core.diagnostics import ModelError

FEATURES = [GeneratorParam("features", "selected features: A,B,C or a product YAML file")]


def _emit(
    module_name: str, model: Any, output_path: str | None, overwrite: bool, features: str
) -> None:
    from spl.cli.commands.selection_options import selection_from_options
    from spl.dsl.rm import language as rm
    from spl.pipeline import resolve_product
    from spl.resolver.resolution.product_line import ProductLine

    rm_file = Path(model._tx_filename)
    try:
        line = ProductLine(rm_file.parent, rm.load(rm_file))
        product = resolve_product(line, selection_from_options(features, (), ())).product
    except ModelError as exc:
        raise TextXError("\n".join(str(d) for d in exc.diagnostics)) from None
    out = Path(output_path) if output_path else rm_file.parent / "build" / product.name
    for relative, data in importlib.import_module(module_name).generate(product).items():
        target = out / relative
        if target.exists() and not overwrite:
            continue
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)


@generator("spl-rm", "ros1", FEATURES)
def ros1_generator(metamodel, model, output_path, overwrite, debug, features: str) -> None:
    """roslaunch XML per container of the product selected with --features"""
    _emit("spl.generators.ros1.launch_files", model, output_path, overwrite, features)


@generator("spl-rm", "ros2", FEATURES)
def ros2_generator(metamodel, model, output_path, overwrite, debug, features: str) -> None:
    """ROS 2 launch XML per container of the product selected with --features"""
    _emit("spl.generators.ros2.launch_files", model, output_path, overwrite, features)


@generator("spl-rm", "rapyuta", FEATURES)
def rapyuta_generator(metamodel, model, output_path, overwrite, debug, features: str) -> None:
    """Rapyuta (rce-ros) configuration per robot of the product selected with --features"""
    _emit("spl.generators.rapyuta.configurations", model, output_path, overwrite, features)
