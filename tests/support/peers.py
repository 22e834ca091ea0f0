"""The tests' optional peers - pylinkage, mpmath, numpy, matplotlib, ezdxf, PC-BASIC - imported
where a test uses them, so that the quick subset collects and runs with pytest and hypothesis
alone.

need("mpmath") imports it; where it is missing, a running test is skipped saying what to install
(locally), or failed (where the environment's CI is set: in CI no test is skipped because a
dependency is missing); outside a test (a generator, a study, collection) Missing is raised.
Peer("numpy") at a module's top is the module, imported by need() at its first use."""

from __future__ import annotations

import importlib
import importlib.util
import os


class Missing(ImportError):
    """An optional peer is not installed, outside a running test."""


def _in_ci() -> bool:
    return os.environ.get("CI", "").lower() not in ("", "0", "false", "no")


def need(name: str, load: bool = True):
    """The module `name` (load=False: only found, not imported; None returned)."""
    try:
        if not load:
            if importlib.util.find_spec(name) is None:
                raise ImportError(f"No module named {name!r}", name=name)
            return None
        return importlib.import_module(name)
    except ImportError as e:
        lack(f"needs {e.name or name}, which is not installed (python3 -m pip install -e "
             "'.[test]')", e.name or name)


def lack(said: str, name: str | None = None):
    """What a test needs is missing: in a running test, skipped saying `said` (failed where CI is
    set); elsewhere Missing."""
    if os.environ.get("PYTEST_CURRENT_TEST"):
        import pytest
        if _in_ci():
            pytest.fail(f"{said}; in CI every test dependency is installed", pytrace=False)
        pytest.skip(said)
    raise Missing(said, name=name)


class Peer:
    """A module imported at its first use: `numpy = Peer("numpy")`, then numpy.loadtxt(...)."""

    def __init__(self, name: str):
        self._name = name

    def __getattr__(self, attr: str):
        return getattr(need(self._name), attr)
