"""Hypothesis for the whole suite: no deadline (PC-BASIC runs are slow), and the same examples
every run (derandomized), so that the README's test command passes or fails the same way on
every machine and in CI, and a red run is reproducible. To explore new examples instead:

    LINKAGE_EXPLORE=1 python3 -m pytest

(every example exploration has found is kept as an @example in its test)."""

import os

import pytest
from hypothesis import HealthCheck, settings

import program

settings.register_profile("explore", deadline=None,
                          suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
settings.register_profile("seeded", parent=settings.get_profile("explore"), derandomize=True,
                          database=None)
settings.load_profile("explore" if os.environ.get("LINKAGE_EXPLORE") else "seeded")


# The quick subset for contributors, `python3 -m pytest -n auto --quick` (the README's "Tests"):
# every module but these, which run PC-BASIC, build and install the wheel, fuzz, fill disks or
# sweep thousands of random linkages; and at most QUICK_EXAMPLES examples a property.
SLOW = {"test_errata.py", "test_physics.py", "test_mbf.py", "test_input.py",
        "test_differential.py", "test_golden.py", "test_install.py",
        "test_readme.py", "test_fuzz.py", "test_hardening.py", "test_mechanism_labels.py",
        "test_bench.py", "test_analyse.py", "test_analyse_brute.py", "test_follow.py",
        "test_mechanism_geometry.py", "test_fast.py", "test_pylinkage.py"}
QUICK_EXAMPLES = 10


def pytest_addoption(parser):
    parser.addoption("--quick", action="store_true",
                     help="the quick subset: no slow module, at most 10 examples a property")


# and these tests of the quick modules, the slowest (their fixtures run the listing's model or
# PC-BASIC, they render PNGs, or they hold the engine to the 50-digit reference on the hard
# catalogue);
SLOW_TESTS = {"test_agrees_with_the_listing_in_double_precision",
              "test_the_listings_spike_at_180_is_absent", "test_png_size_and_dpi",
              "test_draglink_2_misses_near_dpsi_equal_dphi_are_rounding_limited",
              "test_the_type_checker_finds_nothing", "test_the_png_overlays_the_positions",
              "test_hard_case", "test_hard_catalogue_covers_the_singularities",
              "test_worst_errors_over_the_catalogue", "test_reference_is_converged"}
# and of the port's golden cases (tests/test_port.py) only a short session of each mechanism and
# the menu's wrong keys.
QUICK_CASES = {"plane-b1", "spherical-b1", "skew-b1", "slider-b1", "skew-slider-b1",
               "menu-invalid-keys"}

# Modules whose tests start first, the longest (a test or a chain of them) first, so that the
# workers of `-n auto` end together on the many short tests of the other modules; test_fast and
# test_engine next to each other, so that one worker computes the 50-digit references of the hard
# catalogue (engine_harness.ref, cached) for both.
FIRST = ["test_install.py", "test_fast.py", "test_engine.py", "test_port.py",
         "test_differential.py", "test_bench.py", "test_fuzz.py", "test_mbf.py",
         "test_mbf_fast.py", "test_errata.py", "test_physics.py", "test_input.py",
         "test_analyse.py"]


def pytest_configure(config):
    """linkage.py's bytecode, once a run (by pytest-xdist's controller, before its workers)."""
    if not hasattr(config, "workerinput"):
        program.compile_once()


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """`-n`'s tests spread by work stealing (a worker that runs out takes half of what the other
    has left), not in chunks that leave one worker running alone for the last ten seconds."""
    if config.getoption("dist") == "load":
        from xdist.scheduler import WorkStealingScheduling
        return WorkStealingScheduling(config, log)
    return None


def pytest_ignore_collect(collection_path, config):
    """--quick: the slow modules are not even imported."""
    return True if config.getoption("quick") and collection_path.name in SLOW else None


def _left_out_of_quick(item) -> bool:
    if item.originalname in SLOW_TESTS:
        return True
    return "golden_run" in item.fixturenames and item.callspec.id not in QUICK_CASES


def pytest_collection_modifyitems(config, items):
    rank = {name: i for i, name in enumerate(FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(FIRST)))    # stable: order kept
    if not config.getoption("quick"):
        return
    slow = [item for item in items if _left_out_of_quick(item)]
    config.hook.pytest_deselected(items=slow)
    kept = [item for item in items if not _left_out_of_quick(item)]
    items[:] = kept
    for item in kept:              # hypothesis keeps a test's settings on the test function
        test = getattr(item, "obj", None)
        chosen = getattr(test, "_hypothesis_internal_use_settings", None)
        if chosen is not None and chosen.max_examples > QUICK_EXAMPLES:
            test._hypothesis_internal_use_settings = settings(chosen,
                                                              max_examples=QUICK_EXAMPLES)
