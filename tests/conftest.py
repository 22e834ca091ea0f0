"""Hypothesis for the whole suite: no deadline (PC-BASIC runs are slow), and the same examples
every run (derandomized), so that the README's test command passes or fails the same way on
every machine and in CI, and a red run is reproducible. To explore new examples instead:

    LINKAGE_EXPLORE=1 python3 -m pytest

(every example exploration has found is kept as an @example in its test).

The quick subset, `python3 -m pytest -n auto --quick` (the README's "Tests"), is every test not
marked `slow` (`pytestmark = pytest.mark.slow` for a whole module: those that run PC-BASIC, build
and install the wheel, fuzz, fill disks or sweep thousands of random linkages; @pytest.mark.slow
on a test or a golden case), with at most QUICK_EXAMPLES examples a property. It needs only
pytest and hypothesis: the optional peers are imported where used (support/peers.py: a test that
needs a missing one is skipped, or failed where CI is set). pytest-xdist is optional too."""

import os
import signal
import sys

import pytest
from hypothesis import HealthCheck, settings

from support import program

settings.register_profile("explore", deadline=None,
                          suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
settings.register_profile("seeded", parent=settings.get_profile("explore"), derandomize=True,
                          database=None)
settings.load_profile("explore" if os.environ.get("LINKAGE_EXPLORE") else "seeded")

QUICK_EXAMPLES = 10
SLOW_MODULE = "\npytestmark = pytest.mark.slow"      # a module marked slow as a whole

# Modules whose tests start first, the longest (a test or a chain of them) first, so that the
# workers of `-n auto` end together on the many short tests of the other modules; test_fast and
# test_engine next to each other, so that one worker computes the 50-digit references of the hard
# catalogue (engine_harness.ref, cached) for both.
FIRST = ["test_install.py", "test_fast.py", "test_engine.py", "test_port.py",
         "test_differential.py", "test_bench.py", "test_fuzz.py", "test_mbf.py",
         "test_mbf_fast.py", "test_errata.py", "test_physics.py", "test_input.py",
         "test_analyse.py"]


def pytest_addoption(parser):
    parser.addoption("--quick", action="store_true",
                     help="the quick subset: no test marked slow, at most 10 examples a property")


def pytest_configure(config):
    """The markers; linkage.py's bytecode, once a run (by pytest-xdist's controller, before its
    workers)."""
    config.addinivalue_line("markers", "slow: left out by --quick (PC-BASIC, the wheel, fuzzing, "
                            "PNGs, big sweeps, the 50-digit reference on the hard catalogue)")
    if not hasattr(config, "workerinput"):
        program.compile_once()
    if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
        # started in the background of a shell (`cmd &`) or by nohup, SIGINT comes ignored and
        # every program the tests start would inherit that: the Ctrl-C tests would see a program
        # that cannot be interrupted. Python's own handler is reset to the default by exec.
        signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """`-n`'s tests spread by work stealing (a worker that runs out takes half of what the other
    has left), not in chunks that leave one worker running alone for the last ten seconds."""
    if config.getoption("dist") == "load":
        from xdist.scheduler import WorkStealingScheduling
        return WorkStealingScheduling(config, log)
    return None


@pytest.hookimpl(wrapper=True)
def pytest_collection(session):
    """The test modules' bytecode (their asserts rewritten by pytest) is kept in __pycache__ even
    where PYTHONDONTWRITEBYTECODE is set, as linkage.py's is (program.compile_once): each worker
    would otherwise rewrite and compile every module at every run (about 3 s of CPU a worker)."""
    kept = sys.dont_write_bytecode
    sys.dont_write_bytecode = False
    try:
        return (yield)
    finally:
        sys.dont_write_bytecode = kept


def pytest_ignore_collect(collection_path, config):
    """--quick: a module marked slow as a whole is not even imported (its line read from the
    file)."""
    if config.getoption("quick") and collection_path.suffix == ".py" \
            and collection_path.name.startswith("test_"):
        return SLOW_MODULE in collection_path.read_text(encoding="utf-8") or None
    return None


def pytest_collection_modifyitems(config, items):
    rank = {name: i for i, name in enumerate(FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(FIRST)))    # stable: order kept
    if not config.getoption("quick"):
        return
    slow = [item for item in items if item.get_closest_marker("slow")]
    config.hook.pytest_deselected(items=slow)
    kept = [item for item in items if not item.get_closest_marker("slow")]
    items[:] = kept
    for item in kept:              # hypothesis keeps a test's settings on the test function
        test = getattr(item, "obj", None)
        chosen = getattr(test, "_hypothesis_internal_use_settings", None)
        if chosen is not None and chosen.max_examples > QUICK_EXAMPLES:
            test._hypothesis_internal_use_settings = settings(chosen,
                                                              max_examples=QUICK_EXAMPLES)
