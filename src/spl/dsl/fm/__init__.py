"""The extended Feature Model language (.fm): its grammar, reader, model and printer."""
