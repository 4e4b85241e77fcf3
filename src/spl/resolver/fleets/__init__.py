"""Fleets: robots of one line sharing cloud instances (docs/fleets.md)."""
