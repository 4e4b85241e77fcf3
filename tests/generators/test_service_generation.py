"""The service generator's output without running it: complete, deterministic, every
Python file compiles, hostile names are refused before any code is written."""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

from spl.core.diagnostics import ModelError
from spl.generators.service import generator as service, runtime as service_runtime
from spl.metamodels import tsm

from support.service_models import product

T = tsm()
RUNTIME = Path(service_runtime.__file__).parent


@pytest.fixture(scope="module")
def files() -> dict[str, bytes]:
    return service.generate(product())


def test_one_runnable_package_per_store(files) -> None:
    for store, package in [
        ("PositionStore", "position_store_service"),
        ("FollowStore", "follow_store_service"),
    ]:
        names = {p for p in files if p.startswith(f"services/{store}/")}
        assert {
            f"services/{store}/{n}" for n in ("README.md", "pyproject.toml", "requirements.txt")
        } <= names
        for module in (
            "__main__",
            "app",
            "access",
            "linked",
            "model",
            "transforms",
            "transformer",
            "database",
            "settings",
        ):
            path = f"services/{store}/{package}/{module}.py"
            compile(files[path], path, "exec")
        readme = files[f"services/{store}/README.md"].decode()
        for word in (
            "FastAPI",
            "SQLAlchemy 2",
            "uvicorn",
            f"python -m {package}",
            "DATABASE_URL",
            f"{store.upper()[:-5]}_STORE_TOKEN",
        ):
            assert word in readme


def test_every_service_ships_the_runtime_byte_for_byte(files) -> None:
    """docs/services.md, "The runtime package": the service's runtime/ is spl's own
    service_runtime, each module as it is in spl, and the distribution installs it."""
    shipped = sorted(RUNTIME.glob("*.py"))
    assert {p.name for p in shipped} >= {"__init__.py", "callback_targets.py", "access.py"}
    for store, package in [
        ("PositionStore", "position_store_service"),
        ("FollowStore", "follow_store_service"),
    ]:
        runtime = {
            path.removeprefix(f"services/{store}/{package}/runtime/"): data
            for path, data in files.items()
            if path.startswith(f"services/{store}/{package}/runtime/")
        }
        assert runtime == {p.name: p.read_bytes() for p in shipped}
        pyproject = files[f"services/{store}/pyproject.toml"].decode()
        assert f'packages = ["{package}", "{package}.runtime"]' in pyproject


def test_the_runtime_imports_only_itself_and_the_services_libraries(files) -> None:
    """Copied into a service, the runtime finds no spl: its own modules are imported
    relatively, anything else must be the standard library or requirements.txt's."""
    required = files["services/PositionStore/requirements.txt"].decode()
    libraries = {line.split(">")[0].split("[")[0].lower() for line in required.splitlines()}
    libraries |= {"starlette", "pydantic"}  # FastAPI's own, which the runtime names
    for path in sorted(RUNTIME.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module or ""]
            else:
                continue
            for name in names:
                top = name.split(".")[0]
                assert top in sys.stdlib_module_names or top.lower() in libraries, (
                    f"{path.name}: imports {name}"
                )


def test_generation_is_deterministic(files) -> None:
    assert service.generate(product()) == files


def test_model_text_reaches_code_only_as_literals(files) -> None:
    model = ast.parse(files["services/FollowStore/follow_store_service/model.py"])
    strings = {n.value for n in ast.walk(model) if isinstance(n, ast.Constant)}
    assert {"FollowStore", "Velocity", "vx", "duration", "follow_store_command"} <= strings
    classes = {n.name for n in ast.walk(model) if isinstance(n, ast.ClassDef)}
    assert "VelocityRecord" in classes
    fields = {
        t.id
        for n in ast.walk(model)
        if isinstance(n, ast.AnnAssign)
        for t in [n.target]
        if isinstance(t, ast.Name)
    }
    assert not fields & {"vx", "vy", "va"}  # attributes are f0, f1...; names are aliases


@pytest.mark.parametrize(
    ("where", "name"),
    [
        ("store", "Store'); import os; ('"),
        ("field", "lat\nimport os"),
        ("datatype", "Position In"),
        ("system", "Acquisition> . <urn:x"),  # the Turtle vocabulary is named after it
    ],
)
def test_hostile_names_are_refused(where: str, name: str) -> None:
    resolved = product()
    store = next(s for c in resolved.system.containers for s in c.stores)
    if where == "store":
        store.name = name
    elif where == "system":
        resolved.system.name = name
    elif where == "field":
        store.raw.fields[0].name = name
    else:
        store.raw.name = name
    with pytest.raises(ModelError, match="invalid"):
        service.generate(resolved)


def test_ill_typed_transforms_stop_generation() -> None:
    resolved = product()
    transform = next(t for t in resolved.system.transforms if t.name == "SecondToDEG")
    transform.assignments[0].expression = T.BooleanLiteral(value=True)
    with pytest.raises(ModelError, match=r"cannot assign bool to PositionInDEG\.lat"):
        service.generate(resolved)


def test_database_default_follows_the_storage_feature() -> None:
    embedded = service.generate(product())
    postgres = service.generate(
        product(
            features=("DataAcquisition", "Follow", "Positions", "Postgres", "Storage"),
            attributes={"Postgres.database": "postgresql"},
        )
    )
    path = "services/PositionStore/position_store_service/settings.py"
    assert b"sqlite:///./position_store.db" in embedded[path]
    assert b"postgresql://spl@localhost:5432/spl" in postgres[path]


@pytest.mark.parametrize(
    "name",
    ["subscriptions", "blueprint", "properties", "actions", "records", "errors", "Subscriptions"],
)
def test_refined_types_named_like_the_store_s_own_resources_are_refused(name: str) -> None:
    """``/<Store>/subscriptions`` and the rest are the service's own resources; a refined
    type of that name would be served there too (``Subscriptions`` would also take the
    table of the callback subscriptions)."""
    resolved = product()
    store = next(s for c in resolved.system.containers for s in c.stores if s.refinements)
    store.refinements[0].output.name = name
    with pytest.raises(ModelError, match="rename the refined type"):
        service.generate(resolved)


def test_a_model_without_a_system_name_gets_the_plain_vocabulary() -> None:
    resolved = product()
    resolved.system.name = None
    files = service.generate(resolved)
    model = files["services/PositionStore/position_store_service/model.py"].decode()
    assert "SYSTEM = None" in model
