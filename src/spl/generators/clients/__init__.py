"""The robot-side writer and reader nodes of the stores (docs/services.md)."""
