"""Hypothesis for the whole suite: no deadline (PC-BASIC runs are slow), and in CI (CI=true)
the same examples every run, so that a red CI is reproducible; elsewhere new examples each run
(HYPOTHESIS_PROFILE=ci to reproduce CI's)."""

import os

from hypothesis import HealthCheck, settings

settings.register_profile("dev", deadline=None,
                          suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
settings.register_profile("ci", parent=settings.get_profile("dev"), derandomize=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE",
                                     "ci" if os.environ.get("CI") == "true" else "dev"))
