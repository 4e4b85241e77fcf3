"""The Template System Model language (.tsm): its grammar, reader, model and printer."""
