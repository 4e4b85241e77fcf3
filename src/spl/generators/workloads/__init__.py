"""What every generated workload runs with, on Kubernetes (the kubernetes target) and in the
services' own deployment (the deploy target): names, hardening, resources and probes,
network policies (docs/kubernetes.md)."""
