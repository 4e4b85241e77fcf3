"""The Resolution Model language (.rm): its grammar, reader, names and model."""
