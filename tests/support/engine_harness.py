"""Shared by test_engine.py and the accuracy bench (python3 linkage.py bench accuracy): the
hard-case catalogue, the ordinary sweep, and how an answer is scored against the 50-digit
reference (engine_reference.py, imported at the first use: the bench runs without mpmath)."""

from __future__ import annotations

import functools
import tomllib
from pathlib import Path

import test_physics
from support.peers import need

DATA = Path(__file__).resolve().parents[2] / "data"
SLIDERS = ("slider", "skew-slider")
KINDS = ("plane", "spherical", "skew", "slider", "skew-slider")

# Within this margin (closure's extreme over the linkage's squared size) a position is a
# dead-centre to rounding: the reference may call it not assembled, or two roots 1e-8 apart,
# where the engine reports DEAD_CENTRE.
ROUNDING_MARGIN = 1e-40

# The ordinary sweep: the linkages of tests/test_physics.py, both branches, phi = 3, 11, ..., 355.
ORDINARY_CASES = test_physics.CASES
ORDINARY_PHIS = [3.0 + 8.0 * i for i in range(45)]


def load_hard_cases():
    with open(DATA / "hard_cases.toml", "rb") as fh:
        return tomllib.load(fh)["case"]


def size(kind, dims):
    """The linkage's size: the largest length (sliders' position errors are relative to it)."""
    return max(abs(v) for k, v in dims.items() if k != "ksi")


@functools.lru_cache(maxsize=None)
def _ref_cached(kind, dims_items, phi, dps):
    reference = need("support.engine_reference")
    return reference.solve(kind, dict(dims_items), phi, dps)


def ref(kind, dims, phi, dps=50):
    """reference.solve (50 digits, 10 guard digits), cached: several tests use the same points."""
    return _ref_cached(kind, tuple(sorted((k, float(v)) for k, v in dims.items())), float(phi), dps)


def output_error(kind, dims, got, want):
    """Output error: degrees (wrapped) for the four-bars; relative to the size for sliders."""
    if kind in SLIDERS:
        return abs(float(got - want)) / size(kind, dims)
    d = float(got - want)
    # exact for |d| < 180 ((d + 180) % 360 - 180 would round d to a multiple of 180's ulp, 2.8e-14)
    return abs(d - 360.0 * round(d / 360.0))


def ratio_error(got, want):
    """Velocity/acceleration error: absolute below 1, relative above."""
    return abs(float(got - want)) / max(1.0, abs(float(want)))


def points():
    """Every (case, phi, branch) of the hard catalogue."""
    for case in load_hard_cases():
        for phi in case["phis"]:
            for branch in (1, 2):
                yield case, float(phi), branch


VALUED = ("assembled", "change-point")   # statuses that give velocity and acceleration


def score(kind, dims, phi, branch, status, output, velocity, acceleration, r):
    """Compare one computed answer with the reference point r.

    Returns (verdict, errors): verdict "ok" when the status is consistent with the reference
    (a dead-centre or missing assembly within ROUNDING_MARGIN may be called either way; at a
    reference change point the answer must give values; a change point called within rounding
    of one is scored as the values it gives), else a message; errors maps "output", "velocity",
    "acceleration" to the error where both exist.
    """
    errors = {}
    near = r.extreme is not None and abs(float(r.extreme)) <= ROUNDING_MARGIN
    if r.status == "not-assembled":
        if status == "not-assembled" or (near and status in ("dead-centre", "assembled",
                                                             "change-point")):
            return "ok", errors
        return f"reference: not assembled; got {status}", errors
    if status == "not-assembled":
        if near and r.status != "change-point":
            return "ok", errors
        return f"reference: {r.status}; got not assembled", errors
    if status not in ("assembled", "dead-centre", "change-point"):
        return f"reference: {r.status}; got {status}", errors
    if r.status == "change-point" and status not in VALUED:
        return f"reference: change-point; got {status}", errors
    if r.status == "dead-centre" and status != "dead-centre" and not near:
        return f"reference: dead-centre; got {status}", errors
    errors["output"] = output_error(kind, dims, output, r.output)
    if status in VALUED and r.status in VALUED:
        if velocity is not None:
            errors["velocity"] = ratio_error(velocity, r.velocity)
        if acceleration is not None:
            errors["acceleration"] = ratio_error(acceleration, r.acceleration)
    return "ok", errors
