"""The Resolution Engine: one product from the line, with its transformation kinds, pruning,
rewiring and trace (docs/resolution.md)."""
