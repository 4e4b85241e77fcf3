"""The ros2 target: ``ros2/<container>.launch.xml`` for every container of a product
(the launch XML itself is built by :mod:`spl.generators.launch.ros2_launch`)."""

from __future__ import annotations

from spl.generators.launch.ros2_launch import launch_file
from spl.resolver.architecture.product import ResolvedProduct


def generate(product: ResolvedProduct) -> dict[str, bytes]:
    """``ros2/<container>.launch.xml`` for every robot and cloud container."""
    return {
        f"ros2/{container.name}.launch.xml": launch_file(product, container)
        for container in product.system.containers
    }
