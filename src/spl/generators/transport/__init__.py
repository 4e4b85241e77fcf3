"""Which bridge carries which crossing flow under which Zenoh key: read by the zenoh and
kubernetes targets alike (docs/deployment.md)."""
