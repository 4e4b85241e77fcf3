"""``spl configure DIR_OR_MODEL [--port N] [--host H] [--no-browser]``: a web configurator
(docs/configure.md), or ``spl configure --fleet FLEET.yaml --robot NAME`` for a robot
joining a fleet."""

from __future__ import annotations

import errno
import socket
import threading
import time
import webbrowser
from pathlib import Path

import click

DEFAULT_PORT = 8765


@click.command("configure")
@click.argument(
    "source", metavar="DIR_OR_MODEL", required=False, type=click.Path(exists=True, path_type=Path)
)
@click.option("--port", type=click.IntRange(0, 65535), default=DEFAULT_PORT, show_default=True,
              help="port to listen on (0: any free port)")  # fmt: skip
@click.option("--host", default="127.0.0.1", show_default=True,
              help="address to listen on; the default serves this machine only")  # fmt: skip
@click.option("--no-browser", is_flag=True, help="do not open a browser; only print the URL")
@click.option(
    "--fleet",
    "fleet_file",
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
    metavar="FLEET.yaml",
    help="configure a robot joining this fleet: only options its shared instances allow",
)
@click.option("--robot", help="with --fleet: the robot to add or change")
@click.option("--group", help="with --fleet: its group (default: its entry's, else 'default')")
def command(
    source: Path | None,
    port: int,
    host: str,
    no_browser: bool,
    fleet_file: Path | None,
    robot: str | None,
    group: str | None,
) -> None:
    """Serve a configurator for a product line (or a bare .fm, .uvl or FeatureIDE .xml
    feature model, analysis only) and open it in the browser: every decision's
    consequences and why, the products left, and once complete the architecture and its
    bundle. Stops on Ctrl-C; writes nothing into the line unless a selection is saved."""
    from spl.configure.workspace import load_fleet_workspace, load_workspace

    if fleet_file is not None:
        if robot is None:
            raise click.UsageError("--fleet needs --robot NAME")
        if source is not None:
            raise click.UsageError("give DIR_OR_MODEL or --fleet, not both")
        workspace = load_fleet_workspace(fleet_file, robot, group)
    elif source is None:
        raise click.UsageError("give a product-line folder, a feature model or --fleet")
    elif robot is not None or group is not None:
        raise click.UsageError("--robot and --group go with --fleet")
    else:
        try:
            workspace = load_workspace(source)
        except ValueError as exc:
            raise click.BadParameter(str(exc), param_hint="DIR_OR_MODEL") from None
    serve(workspace, host, port, not no_browser)


def serve(workspace, host: str, port: int, open_browser: bool) -> None:
    """Listen (a port taken or an address not this machine's is a one-line error),
    print the URL, serve until Ctrl-C."""
    import uvicorn

    from spl.configure.app import create_app

    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    listener = socket.socket(family, socket.SOCK_STREAM)
    listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        listener.bind((host, port))
        listener.listen(64)
    except OSError as exc:
        listener.close()
        taken = exc.errno in (errno.EADDRINUSE, errno.EACCES)
        advice = (
            "choose another --port" if taken else "give one of this machine's addresses as --host"
        )
        raise click.ClickException(
            f"cannot listen on {host}:{port}: {exc.strerror or exc} ({advice})"
        ) from None
    bound = listener.getsockname()[1]
    shown = f"[{host}]" if family == socket.AF_INET6 else host
    url = f"http://{shown}:{bound}/"
    # on this machine only, the page answers only to this machine's names
    loopback = {"127.0.0.1": ["127.0.0.1", "localhost"], "localhost": ["127.0.0.1", "localhost"]}
    app = create_app(workspace, loopback.get(host))
    config = uvicorn.Config(app, log_level="warning", lifespan="off")
    server = uvicorn.Server(config)
    click.echo(f"spl configure: {workspace.title} at {url} (Ctrl-C stops)", err=False)
    if open_browser:

        def opener() -> None:
            while not server.started and not server.should_exit:
                time.sleep(0.05)
            if server.started:
                webbrowser.open(url)

        threading.Thread(target=opener, daemon=True).start()
    try:
        server.run(sockets=[listener])
    except KeyboardInterrupt:  # a second Ctrl-C while shutting down
        pass
    finally:
        listener.close()
    click.echo("spl configure: stopped")
