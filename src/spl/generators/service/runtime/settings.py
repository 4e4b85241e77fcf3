"""Run-time settings of a generated service, read from the environment when it starts.

The variables' names are the product's (``<STORE>_TOKEN``, ...: the generated
``settings.py`` names them, docs/services.md lists them); what they mean is the same in
every service. Secrets are never written in generated files: the write token is only
ever read when the service starts, from the file ``<token variable>_FILE`` names (a
read-only secret volume in a cluster) or else from the variable itself (a local run);
the database URL likewise from DATABASE_URL_FILE or DATABASE_URL.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass

from .callback_targets import AllowList, allow_list


@dataclass(frozen=True)
class EnvironmentNames:
    """The names a product gives its service's variables, and its default database."""

    token: str
    protect_reads: str
    period: str
    tls_cert: str
    tls_key: str
    callback_hosts: str
    default_database_url: str


@dataclass(frozen=True)
class Settings:
    database_url: str
    token: str
    protect_reads: bool
    max_batch: int
    transformer: str  # "embedded": a thread in the web process; "off": run the worker
    period_override: float | None
    host: str
    port: int
    tls_cert: str | None  # PEM files: HTTPS when both are set
    tls_key: str | None
    callback_hosts: AllowList  # hosts callbacks may post to although internal
    max_body: int  # bytes of a posted body (413 beyond)

    def period(self, model_period: float) -> float:
        return self.period_override if self.period_override is not None else model_period


def _flag(value: str | None) -> bool:
    return (value or "").strip().lower() in ("1", "true", "yes", "on")


def secret(name: str, environ: Mapping[str, str] = os.environ) -> str | None:
    """The secret ``name``: the contents of the file ``<name>_FILE`` names (its last line
    break dropped), else the variable ``name`` itself, else None. A named file that cannot
    be read stops the service with a message naming it."""
    path = environ.get(f"{name}_FILE")
    if not path:
        return environ.get(name)
    try:
        with open(path, encoding="utf-8") as file:
            return file.read().removesuffix("\n").removesuffix("\r")
    except (OSError, UnicodeDecodeError) as error:
        raise SystemExit(f"{name}_FILE={path!r}: cannot read the secret: {error}") from None


def load(names: EnvironmentNames, environ: Mapping[str, str] = os.environ) -> Settings:
    """The settings ``environ`` gives a service whose variables are ``names``."""
    period = environ.get(names.period)
    max_batch = int(environ.get("MAX_BATCH", "1000"))
    return Settings(
        database_url=secret("DATABASE_URL", environ) or names.default_database_url,
        token=secret(names.token, environ) or "",
        protect_reads=_flag(environ.get(names.protect_reads)),
        max_batch=max_batch,
        transformer=environ.get("TRANSFORMER", "embedded"),
        period_override=float(period) if period else None,
        host=environ.get("HOST", "127.0.0.1"),
        port=int(environ.get("PORT", "8000")),
        tls_cert=environ.get(names.tls_cert) or None,
        tls_key=environ.get(names.tls_key) or None,
        callback_hosts=allow_list(names.callback_hosts, environ.get(names.callback_hosts)),
        # a full batch of records of up to 16 KiB each, and never less than 1 MiB
        max_body=int(environ.get("MAX_BODY", str(max(2**20, max_batch * 2**14)))),
    )
