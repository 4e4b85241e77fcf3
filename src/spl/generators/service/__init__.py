"""The data-acquisition services: one web service per store (docs/services.md)."""
