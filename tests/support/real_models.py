"""Where the tests find the community's real feature models (copies in tests/data)."""

from pathlib import Path

REAL_MODELS = Path(__file__).resolve().parents[1] / "data" / "feature-models"
