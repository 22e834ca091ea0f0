"""Hypothesis for the whole suite: no deadline (PC-BASIC runs are slow), and the same examples
every run (derandomized), so that the README's test command passes or fails the same way on
every machine and in CI, and a red run is reproducible. To explore new examples instead:

    LINKAGE_EXPLORE=1 python3 -m pytest

(every example exploration has found is kept as an @example in its test)."""

import os

from hypothesis import HealthCheck, settings

settings.register_profile("explore", deadline=None,
                          suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
settings.register_profile("seeded", parent=settings.get_profile("explore"), derandomize=True,
                          database=None)
settings.load_profile("explore" if os.environ.get("LINKAGE_EXPLORE") else "seeded")
