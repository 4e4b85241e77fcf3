"""The three languages registered with textX (entry-point group ``textx_languages``).

So that ``textx check mapping.tsm`` (and any textX-based tool) sees the same language as
``spl check``: each registered metamodel is the language's grammar plus a model
processor running every check of spl's builder, reporting the first problem as a
located textX error and all of them in its message.
"""

from __future__ import annotations

import importlib
from typing import Any

from textx import language
from textx.exceptions import TextXSemanticError

from spl.core.diagnostics import ModelError


def _checked_metamodel(module_name: str) -> Any:
    module = importlib.import_module(module_name)
    # a fresh instance: the processor must not run inside spl's own parsing
    metamodel = module._grammar.__wrapped__()

    def run_spl_checks(model: Any, _metamodel: Any) -> None:
        filename = getattr(model, "_tx_filename", None)
        if filename is None:
            return  # a model parsed from a string has no file for the cross-file checks
        try:
            module.parse_file(filename)
        except ModelError as exc:
            head, *rest = exc.diagnostics
            first = head.location
            raise TextXSemanticError(
                "\n".join([head.message, *(str(d) for d in rest)]),
                line=first.line if first else None,
                col=first.col if first else None,
                filename=first.file if first else filename,
            ) from None

    metamodel.register_model_processor(run_spl_checks)
    return metamodel


@language("spl-tsm", "*.tsm")
def tsm_language() -> Any:
    """spl Template System Model: robot/cloud containers, ROS nodes, topics, bridges, stores"""
    return _checked_metamodel("spl.dsl.tsm.language")


@language("spl-fm", "*.fm")
def fm_language() -> Any:
    """spl extended Feature Model: feature tree, groups, attributes, sharing, constraints"""
    return _checked_metamodel("spl.dsl.fm.language")


@language("spl-rm", "*.rm")
def rm_language() -> Any:
    """spl Resolution Model: features bound to required elements and transformations"""
    return _checked_metamodel("spl.dsl.rm.language")
