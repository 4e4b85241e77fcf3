"""The deployment bundle: every target's files, the manifest, the resolved model, written
atomically."""
