"""What every store's records are made of, whatever its data types: the value types a
posted record may hold, the base of the record models, a field, a refinement.

A product's ``model.py`` builds its tables, record models and refinements from these
(docs/services.md, "Records and refinements").
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field
from sqlalchemy import BigInteger, Integer, Table

# SQLite only auto-increments INTEGER PRIMARY KEY; PostgreSQL gets BIGINT identities.
RecordId = BigInteger().with_variant(Integer(), "sqlite")

# What the columns hold: 64-bit integers (SQLite and PostgreSQL), text without NUL
# (PostgreSQL refuses it); a record outside them is refused when posted, not when stored.
Int64 = Annotated[int, Field(ge=-(2**63), le=2**63 - 1)]
StoredText = Annotated[str, Field(pattern=r"^[^\x00]*$")]
# Source timestamps a date can be given for (xsd:dateTime in the Turtle representation,
# years 1 to 9999): 0001-01-01T00:00:00Z <= timestamp <= 9999-12-31T23:59:59Z.
FIRST_TIMESTAMP = -62135596800.0
LAST_TIMESTAMP = 253402300799.0
KEY_PATTERN = r"^[A-Za-z0-9_.:\-]{1,128}$"

# a compiled transform: (record, previous, next) -> the refined record's fields
Transform = Callable[[dict[str, Any], dict[str, Any] | None, dict[str, Any] | None], dict[str, Any]]


class RecordModel(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)


@dataclass(frozen=True)
class FieldSpec:
    name: str
    type: str  # the model's type: double, int, string or bool


@dataclass(frozen=True)
class Refinement:
    name: str  # the refined data type, also the collection name under the store's path
    table: Table
    fields: tuple[FieldSpec, ...]
    transform: Transform
    period: float
    uses_prev: bool
    uses_next: bool
