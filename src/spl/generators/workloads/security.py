"""What every generated workload runs with: the ``restricted`` Pod Security Standard,
its namespace, and the two scanner waivers (docs/kubernetes.md).

A platform team's admission controller and scanner (checkov) refuse pods that run as
root, may gain privileges, keep Linux capabilities, have no seccomp profile, write their
root filesystem or mount a service-account token they never use. None of spl's
workloads needs any of that: the ROS nodes, the Zenoh bridges and router, the data
services and their PostgreSQL all run here as one unprivileged high UID on a read-only
root filesystem, writing only to the ``emptyDir`` volumes :func:`scratch_volumes` gives
them (``/tmp``, where ``HOME`` and the ROS logs go) and to their data volumes.

Every object is placed in the namespace of its product or fleet (:func:`namespace_for`,
a DNS-1123 label), or in the one ``spl resolve --namespace`` chooses (the bundle's
options, :class:`spl.generators.bundle.options.BundleOptions`), which enforces the
``restricted`` level (:func:`namespace_document`), so a pod that would break it is
refused by the cluster itself, not only by a scanner.
"""

from __future__ import annotations

import hashlib
import re
from typing import cast

from spl.generators.json_text import Document
from spl.resolver.architecture.generated_names import kubernetes_label

# One UID and GID for every container: high (above 10000, apart from the host's users),
# the one the services' Dockerfile creates.
UID = 10001
DNS_1123_LABEL = re.compile(r"[a-z0-9]([-a-z0-9]*[a-z0-9])?")
MAX_LENGTH = 63
SCRATCH = "/tmp"  # the pod's own emptyDir, not the node's /tmp
# Pull by tag and the cluster's default pull policy: the images are named by tag so that
# kustomize `images:` can replace them; pinning digests and forcing pulls is the
# platform's choice. These two checks alone are waived, with the reason, in the objects.
WAIVERS = {
    "CKV_K8S_43": "images are named by tag so that the images field of kustomization.yaml "
    "can set them, digests included",
    "CKV_K8S_15": "the pull policy is the cluster's default; an image set by tag in "
    "kustomization.yaml is pulled when the tag changes",
}


def checked_namespace(name: str) -> str:
    """``name`` when it is a DNS-1123 label (what Kubernetes accepts as a namespace),
    else a ValueError saying what is wrong with it."""
    if len(name) > MAX_LENGTH or not DNS_1123_LABEL.fullmatch(name):
        raise ValueError(
            f"namespace {name!r} is not a DNS-1123 label: at most {MAX_LENGTH} lower-case "
            "letters, digits and '-', starting and ending with a letter or digit"
        )
    return name


def namespace_for(owner: str) -> str:
    """The namespace product (or fleet) ``owner`` is given when none is chosen: its name
    as a label (lower case, ``_`` -> ``-``), shortened with a digest past 63 characters,
    or ``spl-`` and a digest when it gives no label."""
    name = kubernetes_label(owner).strip("-")
    if DNS_1123_LABEL.fullmatch(name) and len(name) <= MAX_LENGTH:
        return name
    digest = hashlib.sha256(owner.encode("utf-8")).hexdigest()[:8]
    cleaned = re.sub(r"[^-a-z0-9]", "-", name)[:54].strip("-")
    return f"{cleaned}-{digest}" if cleaned else f"spl-{digest}"


def namespace_document(namespace: str, part_of: str) -> Document:
    """The Namespace, enforcing (and auditing, warning at) the restricted level."""
    labels = {"kubernetes.io/metadata.name": namespace, "app.kubernetes.io/part-of": part_of}
    for mode in ("enforce", "audit", "warn"):
        labels[f"pod-security.kubernetes.io/{mode}"] = "restricted"
        labels[f"pod-security.kubernetes.io/{mode}-version"] = "latest"
    return {
        "apiVersion": "v1",
        "kind": "Namespace",
        "metadata": {"name": namespace, "labels": labels},
    }


def waiver_annotations() -> dict[str, str]:
    """checkov's skip annotations for the two waived checks, each with its reason."""
    return {
        f"checkov.io/skip{index}": f"{check}={reason}"
        for index, (check, reason) in enumerate(WAIVERS.items(), start=1)
    }


def pod_security() -> Document:
    """The pod's securityContext: non-root, one high UID/GID, RuntimeDefault seccomp."""
    return {
        "runAsNonRoot": True,
        "runAsUser": UID,
        "runAsGroup": UID,
        "fsGroup": UID,
        "seccompProfile": {"type": "RuntimeDefault"},
    }


def container_security() -> Document:
    """A container's securityContext at the restricted level, read-only root included."""
    return {
        "allowPrivilegeEscalation": False,
        "privileged": False,
        "readOnlyRootFilesystem": True,
        "runAsNonRoot": True,
        "runAsUser": UID,
        "runAsGroup": UID,
        "capabilities": {"drop": ["ALL"]},
        "seccompProfile": {"type": "RuntimeDefault"},
    }


def scratch_mount() -> Document:
    """The writable ``/tmp`` every container gets (its own emptyDir)."""
    return {"name": "tmp", "mountPath": SCRATCH}


def scratch_volumes() -> list[Document]:
    """The pod's ``tmp`` emptyDir (bounded, so a runaway log cannot fill the node)."""
    return [{"name": "tmp", "emptyDir": {"sizeLimit": "256Mi"}}]


def ros_environment() -> list[dict[str, str]]:
    """Where a ROS 2 process writes on a read-only root: HOME and ROS_HOME (whence
    ``ROS_LOG_DIR``, the launch and node logs) under the pod's ``/tmp``."""
    return [
        {"name": "HOME", "value": SCRATCH},
        {"name": "ROS_HOME", "value": f"{SCRATCH}/ros"},
        {"name": "ROS_LOG_DIR", "value": f"{SCRATCH}/ros/log"},
    ]


def harden(pod_spec: Document) -> Document:
    """``pod_spec`` with the pod security context, no service-account token, and every
    container's security context and ``/tmp``: the restricted level for any workload."""
    containers = cast("list[Document]", pod_spec["containers"])
    for container in containers:
        container["securityContext"] = container_security()
        mounts = cast("list[Document]", container.setdefault("volumeMounts", []))
        if not any(mount["mountPath"] == SCRATCH for mount in mounts):
            mounts.append(scratch_mount())
    volumes = cast("list[Document]", pod_spec.setdefault("volumes", []))
    if not any(volume["name"] == "tmp" for volume in volumes):
        volumes.extend(scratch_volumes())
    return {
        "automountServiceAccountToken": False,
        "securityContext": pod_security(),
        **pod_spec,
    }
