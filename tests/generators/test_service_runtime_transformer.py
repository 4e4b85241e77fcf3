"""The runtime's database and transformer on a real SQLite file, imported directly
(docs/services.md, "The service"): the tables are made on start, each raw record is
refined once, in source-timestamp order, with its neighbours when the transform reads
them; a record its transform refuses becomes an error row, and one that arrives behind
its robot's watermark is reported late. The live tests run the same code in services
(tests/live/test_service_end_to_end.py, test_service_crash.py, test_service_postgres.py)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

from sqlalchemy import (
    JSON,
    Column,
    Double,
    ForeignKey,
    Index,
    MetaData,
    String,
    Table,
    Text,
    UniqueConstraint,
    create_engine,
    insert,
    inspect,
    select,
)

from spl.generators.service.runtime.database import WriteTurns, create
from spl.generators.service.runtime.records import FieldSpec, RecordId, Refinement
from spl.generators.service.runtime.transformer import TransformedStore, Transformer


class RecordError(Exception):
    """What a compiled transform raises for a record it cannot refine."""


metadata = MetaData()
raw = Table(
    "shop_raw",
    metadata,
    Column("id", RecordId, primary_key=True, autoincrement=True),
    Column("robot", String(64), nullable=False),
    Column("source_ts", Double(), nullable=False),
    Column("received_ts", Double(), nullable=False),
    Column("document", JSON(), nullable=False),
    Column("key", String(128), nullable=True),
)
KEY_WHERE = raw.c.key.isnot(None)
key_index = Index("shop_raw_key", raw.c.robot, raw.c.key, unique=True, sqlite_where=KEY_WHERE)
marks = Table(
    "shop_watermarks",
    metadata,
    Column("refinement", String(128), primary_key=True),
    Column("robot", String(64), primary_key=True),
    Column("source_ts", Double(), nullable=False),
    Column("raw_id", RecordId, nullable=False),
)
errors = Table(
    "shop_errors",
    metadata,
    Column("id", RecordId, primary_key=True, autoincrement=True),
    Column("refinement", String(128), nullable=False),
    Column("raw_id", RecordId, ForeignKey("shop_raw.id"), nullable=False),
    Column("message", Text(), nullable=False),
    UniqueConstraint("refinement", "raw_id"),
)
deltas = Table(
    "shop_delta",
    metadata,
    Column("id", RecordId, primary_key=True, autoincrement=True),
    Column("raw_id", RecordId, ForeignKey("shop_raw.id"), nullable=False, unique=True),
    Column("robot", String(64), nullable=False),
    Column("timestamp", Double(), nullable=False),
    Column("delta", Double(), nullable=False),
)


def _delta(current: dict[str, Any], prev: dict[str, Any] | None, _next: Any) -> dict[str, Any]:
    if current["price"] < 0:
        raise RecordError("a negative price")
    return {"delta": current["price"] - (prev["price"] if prev is not None else 0.0)}


DELTA = Refinement("Delta", deltas, (FieldSpec("delta", "double"),), _delta, 5.0, True, False)
STORE = TransformedStore(raw, marks, errors, (DELTA,), RecordError)


def _post(engine: Any, robot: str, *prices_at: tuple[float, float]) -> None:
    rows = [
        {"robot": robot, "source_ts": ts, "received_ts": time.time(), "document": {"price": p}}
        for p, ts in prices_at
    ]
    with engine.begin() as conn:
        conn.execute(insert(raw), rows)


def test_each_record_is_refined_once_in_order_with_its_predecessor(tmp_path: Path) -> None:
    engine = create(f"sqlite:///{tmp_path}/shop.db", metadata, raw, key_index)
    transformer = Transformer(engine, STORE, WriteTurns())
    _post(engine, "r1", (3.0, 20.0), (1.0, 10.0))  # posted out of order
    _post(engine, "r2", (-1.0, 5.0))
    assert transformer.run_refinement(DELTA) == 3
    assert transformer.run_refinement(DELTA) == 0  # nothing twice
    _post(engine, "r1", (4.5, 30.0))
    assert transformer.run_refinement(DELTA) == 1
    with engine.connect() as conn:
        refined = conn.execute(select(deltas.c.robot, deltas.c.timestamp, deltas.c.delta)).all()
        failed = conn.execute(select(errors.c.refinement, errors.c.message)).all()
    assert sorted(refined) == [("r1", 10.0, 1.0), ("r1", 20.0, 2.0), ("r1", 30.0, 1.5)]
    assert failed == [("Delta", "a negative price")]


def test_a_record_behind_its_robot_s_watermark_is_reported_late(tmp_path: Path) -> None:
    engine = create(f"sqlite:///{tmp_path}/shop.db", metadata, raw, key_index)
    transformer = Transformer(engine, STORE, WriteTurns())
    _post(engine, "r1", (1.0, 10.0), (2.0, 20.0))
    transformer.run_refinement(DELTA)
    _post(engine, "r1", (9.0, 15.0))  # older than the watermark (20.0)
    assert transformer.run_refinement(DELTA) == 0
    assert transformer.report_late(DELTA) == 1
    assert transformer.report_late(DELTA) == 0  # reported once
    with engine.connect() as conn:
        (message,) = conn.execute(select(errors.c.message)).scalars()
    assert message == "arrived after later records of its robot were transformed"


def test_the_tables_are_made_on_start_and_an_old_raw_table_gets_its_key(tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path}/old.db"
    old = MetaData()
    Table("shop_raw", old, *(Column(c.name, c.type, primary_key=c.primary_key)
                             for c in raw.columns if c.name != "key"))  # fmt: skip
    old.create_all(create_engine(url))  # a database of a service without keys
    engine = create(url, metadata, raw, key_index)
    assert "key" in {c["name"] for c in inspect(engine).get_columns("shop_raw")}
    assert {i["name"] for i in inspect(engine).get_indexes("shop_raw")} == {"shop_raw_key"}
    assert set(inspect(engine).get_table_names()) == {
        "shop_raw", "shop_watermarks", "shop_errors", "shop_delta",
    }  # fmt: skip
    with engine.connect() as conn:
        assert conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
