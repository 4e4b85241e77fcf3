"""The Jinja2 environment of the template sets each target ships in its ``templates/``.

The data-acquisition service, its robot-side clients and its deployment files are
templates; each generator builds a context from the resolved model and renders here,
with one configuration: undefined names fail, whitespace is controlled and nothing is
auto-escaped (the output is Python, YAML and Markdown: values are validated and then
``repr()``-ed for Python or passed through the ``yaml`` filter for YAML: a validated
identifier such as ``no`` or ``null`` is still read by YAML as a boolean or nothing).
"""

from __future__ import annotations

from functools import cache

import yaml
from jinja2 import Environment, PackageLoader, PrefixLoader, StrictUndefined

TEMPLATED = ("service", "clients", "deploy")  # the targets written from templates


@cache
def environment() -> Environment:
    env = Environment(
        # each target's templates beside its generator, named "<target>/<path>"
        loader=PrefixLoader(
            {t: PackageLoader(f"spl.generators.{t}", "templates") for t in TEMPLATED}
        ),
        undefined=StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,  # Python, YAML and Markdown: values are validated or repr()-ed
    )
    env.filters["pyrepr"] = repr
    env.filters["yaml"] = yaml_scalar
    return env


def yaml_scalar(text: str) -> str:
    """``text`` as a YAML scalar that reads back as that very text: plain where YAML
    reads it so (``position-store``), quoted where it would not (``'no'``, ``'null'``,
    ``'1e3'``), as PyYAML writes a string."""
    dumped = yaml.safe_dump(str(text), width=2**16)
    return dumped.removesuffix("\n...\n").removesuffix("\n")


def render(template: str, **context: object) -> bytes:
    """The UTF-8 text of ``template`` (``<target>/<path under its templates/>``) in
    ``context``."""
    return environment().get_template(template).render(**context).encode("utf-8")
