"""The Jinja2 environment of the template sets shipped in ``templates/``.

The data-acquisition service, its robot-side clients and its deployment files are
templates; each generator builds a context from the resolved model and renders here,
with one configuration: undefined names fail, whitespace is controlled and nothing is
auto-escaped (the output is Python, YAML and Markdown: values are validated or
``repr()``-ed by the context builders).
"""

from __future__ import annotations

from functools import cache
from typing import Any

from jinja2 import Environment, PackageLoader, StrictUndefined


@cache
def environment() -> Environment:
    env = Environment(
        loader=PackageLoader("spl.generators", "templates"),
        undefined=StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,  # Python, YAML and Markdown: values are validated or repr()-ed
    )
    env.filters["pyrepr"] = repr
    return env


def render(template: str, **context: Any) -> bytes:
    """The UTF-8 text of ``template`` (a path under ``templates/``) in ``context``."""
    return environment().get_template(template).render(**context).encode("utf-8")
