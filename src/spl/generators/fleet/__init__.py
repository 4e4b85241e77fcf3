"""The deployment bundle of a fleet: each robot's files, each shared instance once
(docs/fleets.md)."""
