"""The data-acquisition system of product_lines/data_acquisition, for the service tests:
data.tsm parsed with the .tsm language, wrapped in a ResolvedProduct as the Resolution
Engine would hand it to the generators."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from spl.dsl.tsm import language as tsm_language
from spl.resolver.architecture.product import ResolvedProduct

PRODUCT_LINE = Path(__file__).resolve().parents[2] / "product_lines" / "data_acquisition"


def data_acquisition_system() -> Any:
    return tsm_language.parse_file(PRODUCT_LINE / "data.tsm")


def product(
    name: str = "data_acquisition",
    features: tuple[str, ...] = ("DataAcquisition", "Embedded", "Follow", "Positions", "Storage"),
    attributes: dict[str, Any] | None = None,
    system: Any = None,
) -> ResolvedProduct:
    if attributes is None:
        attributes = {"Embedded.database": "sqlite", "Postgres.database": "postgresql"}
    return ResolvedProduct(
        name=name,
        system=system if system is not None else data_acquisition_system(),
        features=tuple(sorted(features)),
        attributes=attributes,
    )
