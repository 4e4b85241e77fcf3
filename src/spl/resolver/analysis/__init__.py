"""Feature-model analysis with a SAT solver: the formula, its operations, sampling and the
configurator's propagation (docs/analysis.md)."""
