"""The rapyuta target: rce-ros configurations and the Cloud Engine's own rules
(docs/outputs.md)."""
