"""The resolved architecture and the facts every output reads: flows, placement, wiring, ROS
names, stores (docs/semantics.md, docs/deployment.md)."""
