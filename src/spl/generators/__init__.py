"""Model-to-text generators: one module and one template set per deployment target."""
