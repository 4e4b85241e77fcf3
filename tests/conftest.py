"""Hypothesis profiles for the fuzz and property tests.

``ci`` (the default) is reproducible: examples are derived from each test's name
(``derandomize``), nothing is read from or written to an example database, and there
is no per-example deadline (a shared 2-core machine has slow moments). Example counts
are set per test and stay small so the suite keeps its time budget.
``explore`` searches with fresh random examples and ten times as many of them, for a
developer hunting new counterexamples: ``HYPOTHESIS_PROFILE=explore pytest
tests/cli/test_fuzz_*.py``.
"""

import os

from hypothesis import HealthCheck, settings

_QUIET = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much]

settings.register_profile(
    "ci",
    derandomize=True,
    database=None,
    deadline=None,
    print_blob=True,
    suppress_health_check=_QUIET,
)
settings.register_profile(
    "explore",
    derandomize=False,
    database=None,
    deadline=None,
    print_blob=True,
    suppress_health_check=_QUIET,
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
