"""spl: model-driven software product lines for cloud robotics."""

__version__ = "0.1.0"
