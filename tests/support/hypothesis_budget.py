"""How many examples a property test runs: a small, fixed number in the suite (the
``ci`` hypothesis profile, see conftest.py), ten times as many when exploring."""

import os


def examples(count: int) -> int:
    return count * 10 if os.environ.get("HYPOTHESIS_PROFILE") == "explore" else count
