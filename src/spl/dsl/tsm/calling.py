"""Whether a client may call a server, in the one wording of every place that binds them.

A .tsm client names its server (``calls action goal -> M.move_base``), a .tsm bridge and
an .rm ``connect`` bind a client to a server of another container or of a product: all
three refuse the same pairs with the same words (docs/tsm.md, "Actions";
docs/rm.md), naming both ends with where each is declared, since the mistake may be
in either statement. The kinds are asked of the registry (docs/architecture.md,
"Interface kinds"), so a new kind of a calling family is refused alike.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from spl.core.diagnostics import location_of
from spl.metamodels.interface_kinds import calling_titles, kind_of, side


@dataclass(frozen=True)
class CallProblem:
    """Why a client may not call a server: the message, and whether the server's side of
    the statement is the one at fault (a reference is refused at its own column)."""

    message: str
    at_server: bool


def declared_name(interface: Any) -> str:
    """``CONTAINER.NODE.INTERFACE`` of a node's interface, as a statement may name it."""
    node = interface.eContainer()
    return f"{node.eContainer().name}.{node.name}.{interface.name}"


def end(interface: Any) -> str:
    """One end of a refused binding: its qualified name and where it is declared."""
    where = location_of(interface)
    return f"{declared_name(interface)} ({where})" if where else declared_name(interface)


def call_problem(
    client: Any, server: Any, written: str | None = None, verb: str = "bridged"
) -> CallProblem | None:
    """Why ``client`` may not call ``server``, or None where it may.

    ``written`` is how the statement reads with its two ends in their order,
    ``"bridge {client} -> {server}"``: a statement naming a server first and its client
    second carries the calls against the way they run, and is told so (``verb``: how the
    statement carries them) with the statement to write instead. Without it (a client's
    own ``->``), the first end is a client by its statement."""
    client_kind, server_kind = kind_of(client), kind_of(server)
    if not client_kind.calls:
        if (
            written is not None
            and server_kind.calls
            and side(server_kind.family, True) is client_kind
        ):
            family = server_kind.family.name
            fixed = written.format(client=declared_name(server), server=declared_name(client))
            return CallProblem(
                f"{family} {verb} the wrong way: {end(client)} is {client_kind.a_title} and "
                f"{end(server)} is {server_kind.a_title}; calls run from the client to its "
                f"server: write '{fixed}'",
                at_server=False,
            )
        named = f"{client.eContainer().name}.{client.name}"
        return CallProblem(f"{named} is {client_kind.a_class}, not a {calling_titles()}", False)
    provider = side(client_kind.family, True)
    if server_kind is not provider:
        return CallProblem(
            f"kind mismatch: {end(client)} is {client_kind.a_title}, {end(server)} is "
            f"{server_kind.a_title}, not {provider.a_title}",
            at_server=True,
        )
    if client.type and server.type and client.type != server.type:
        return CallProblem(
            f"type mismatch: {end(client)} is {client.type}, {end(server)} is {server.type}",
            at_server=True,
        )
    return None
