"""The kubernetes target: least-privilege manifests (docs/kubernetes.md)."""
