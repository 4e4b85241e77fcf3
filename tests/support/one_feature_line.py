"""A product line of one .tsm, one optional feature X and no resolution element: for tests
whose question is about an architecture alone (its checks, its deployment, a fleet of it)."""

from __future__ import annotations

from pathlib import Path

# A robot calling the protected MapServer; a public FleetManager calling it too.
MAP_SERVER_TSM = """system M
robot container R {
    endpoint robot_id "r" url "wss://x.example.org:9000/" user "u" password env "P"
    node Drv { implementation a/drv calls get : nav_msgs/GetMap }
}
cloud container C group "g" {
    node MapServer sharing protected { implementation a/map
        provides get_map : nav_msgs/GetMap name "/static_map" }
    node FleetManager sharing public { implementation a/fleet
        calls map -> MapServer.get_map }
}
"""
MAP_SERVER_BRIDGE = "bridge R.Drv.get -> C.MapServer.get_map\n"


def one_feature_line(directory: Path, tsm: str) -> Path:
    """``directory`` holding m.tsm (``tsm``), m.fm (root M, optional X) and an empty m.rm."""
    directory.mkdir(parents=True)
    (directory / "m.tsm").write_text(tsm)
    (directory / "m.fm").write_text("feature model M\nroot M { optional X }\n")
    (directory / "m.rm").write_text('resolution model M\ntsm "m.tsm"\nfm "m.fm"\n')
    return directory
