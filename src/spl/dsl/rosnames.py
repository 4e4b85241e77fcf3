"""ROS naming rules, and the conservative character sets of deployment settings.

Every name a model gives ends up in a generated file (launch XML, Rapyuta JSON,
Python, shell); checking it against the ROS rules here, once, means the generators
never have to escape their way out of a hostile name. Each ``problem_*`` function
returns ``None`` for a valid value or a short sentence saying what is wrong, so the
languages (.tsm, .rm, product selections) can report it at the right location.

Rules (ROS 1 wiki "Names", REP 144 for packages):
- base name: a letter, then letters, digits, underscores;
- graph name: base names joined by ``/``, optionally absolute (leading ``/``); no
  trailing or double slash. Private names (``~x``) are refused: a model's topics,
  services and namespaces are shared between nodes, never private to one;
- package name: lower case letter, then lower case letters, digits, underscores;
- message/service type: ``package/Type`` with ``Type`` a base name;
- executable: a file name made of letters, digits, ``_ . -``, not starting with
  ``-`` or ``.`` (so it can never be read as an option or a relative path).
"""

from __future__ import annotations

import keyword
import re

BASE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
GRAPH_NAME = re.compile(r"/?[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*")
PACKAGE = re.compile(r"[a-z][a-z0-9_]*")
TYPE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
EXECUTABLE = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.\-]*")
# Rapyuta endpoint settings; the same patterns as product selections' `deployment`.
ROBOT_ID = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,63}")
USER = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,63}")
URL = re.compile(r"wss?://[A-Za-z0-9.-]+(:[0-9]{1,5})?(/[A-Za-z0-9._~/-]*)?")
ENV_VAR = re.compile(r"[A-Z_][A-Z0-9_]*")
GROUP = re.compile(r"[A-Za-z][A-Za-z0-9_-]{0,63}")
# Command-line arguments of a node: no quoting, expansion, redirection or separators.
ARGS = re.compile(r"[A-Za-z0-9_ ./:=,+@%-]*")

_MAX = 255


def _shown(value: str) -> str:
    return repr(value if len(value) <= 60 else value[:57] + "...")


def problem_base_name(name: str, what: str = "name") -> str | None:
    if len(name) <= _MAX and BASE_NAME.fullmatch(name):
        return None
    return (
        f"{what} {_shown(name)} is not a valid ROS base name "
        f"(a letter, then letters, digits or underscores; at most {_MAX} characters)"
    )


def problem_graph_name(name: str, what: str = "ROS name") -> str | None:
    if len(name) <= _MAX and GRAPH_NAME.fullmatch(name):
        return None
    return (
        f"{what} {_shown(name)} is not a valid ROS graph name "
        "(names of a letter then letters, digits, underscores, separated by '/'; at most "
        f"{_MAX} characters)"
    )


def problem_package(name: str) -> str | None:
    if len(name) <= _MAX and PACKAGE.fullmatch(name):
        return None
    return (
        f"{_shown(name)} is not a valid ROS package name "
        "(a lower case letter, then lower case letters, digits or underscores; at most "
        f"{_MAX} characters)"
    )


def problem_type(text: str, what: str = "type") -> str | None:
    """``pkg/Type`` as message and service types are written in ROS."""
    package, slash, name = text.partition("/")
    if not slash:
        return f"{what} {_shown(text)} must be written package/Type"
    problem = problem_package(package) or (
        None
        if len(name) <= _MAX and TYPE_NAME.fullmatch(name)
        else f"{what} name {_shown(name)} is not valid (a letter, then letters, digits, "
        f"underscores; at most {_MAX} characters)"
    )
    keywords = [part for part in (package, name) if keyword.iskeyword(part)]
    if problem is None and keywords:  # `from import.msg import Scan` does not parse
        return (
            f"{what} {text}: {keywords[0]} is a Python keyword, so rospy code (the generated "
            f"writers and readers, spl smoke) cannot import it"
        )
    return problem


def problem_executable(name: str) -> str | None:
    if len(name) <= _MAX and EXECUTABLE.fullmatch(name) and name not in (".", ".."):
        return None
    return (
        f"executable {_shown(name)} is not valid "
        "(letters, digits, '_', '.', '-', not starting with '-' or '.'; at most "
        f"{_MAX} characters)"
    )


def problem_implementation(text: str) -> str | None:
    """``package/executable`` of a node."""
    package, slash, executable = text.partition("/")
    if not slash:
        return f"implementation {_shown(text)} must be written package/executable"
    return problem_package(package) or problem_executable(executable)


def problem_args(text: str) -> str | None:
    if len(text) <= 1000 and ARGS.fullmatch(text):
        return None
    return (
        "args may only contain letters, digits, spaces and _ . / : = , + @ % - "
        "(no quotes, $, backticks, ; & | < > or line breaks)"
    )


def problem_robot_id(text: str) -> str | None:
    if ROBOT_ID.fullmatch(text):
        return None
    return f"robot_id {_shown(text)} is not valid (a letter, then letters, digits, _ or -)"


def problem_user(text: str) -> str | None:
    if USER.fullmatch(text):
        return None
    return f"user {_shown(text)} is not valid (a letter, then letters, digits, _ or -)"


def problem_url(text: str) -> str | None:
    if len(text) <= 2000 and URL.fullmatch(text):
        return None
    return (
        f"url {_shown(text)} is not valid "
        "(ws:// or wss://, a host name, an optional :port and a plain path)"
    )


def problem_env_var(text: str) -> str | None:
    if ENV_VAR.fullmatch(text):
        return None
    return (
        f"environment variable {_shown(text)} is not valid "
        "(upper case letters, digits and underscores, not starting with a digit)"
    )


def problem_group(text: str) -> str | None:
    if GROUP.fullmatch(text):
        return None
    return f"group {_shown(text)} is not valid (a letter, then letters, digits, _ or -)"


def is_graph_name(name: str) -> bool:
    return problem_graph_name(name) is None


def is_type(text: str) -> bool:
    return problem_type(text) is None


def is_package(name: str) -> bool:
    return problem_package(name) is None
