"""Diagrams of architectures and feature models, drawn with Graphviz."""
