"""analyse, crank_limits and analysis_lines checked against what they summarise, never against
themselves: the type against Grashof's rule typed here (exact in the lengths) and against a dense
sweep of the engine; the dead centres where the engine's status switches; the output's extremes,
swing and time ratio against a brute-force sweep refined locally; the transmission angle's
extremes of the plane crank-rocker against the review's eqs. (2a), (2b) evaluated in mpmath; the
change points of linkages built to have one; the review's worked examples through
`design ... --analyze` against the review's printed numbers; and the command line's refusals
(one line, no traceback, no file written) and its CSV columns.

Letters are the project's: a the fixed link, b the crank, c the coupler, d the output crank,
e the slider's offset (the review's a, b, c, d are the project's b, c, d, a)."""

from __future__ import annotations

import csv
import math
import os
import random
from fractions import Fraction
from pathlib import Path

import mpmath
import numpy
import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings, strategies as st

import linkage
from test_mechanism_geometry import LINKAGES     # the random linkages of every kind

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

NOT = linkage.NOT_ASSEMBLED
ALL_HEALTH = list(HealthCheck)

# Uniform draws from a seeded generator, for the tests that must see enough linkages of each
# class (crank-rocker and rocking crank, ...): hypothesis' floats favour the ends of a range and
# the numbers written in the code under test, so how many of each class it draws changed with
# any edit of linkage.py. These are the ranges of LINKAGES (test_mechanism_geometry).
LENGTH, OFFSET, ARC, KSI = (0.1, 10.0), (-5.0, 5.0), (5.0, 175.0), (-75.0, 75.0)
RANGES = {
    "plane": dict(a=LENGTH, b=LENGTH, c=LENGTH, d=LENGTH),
    "spherical": dict(a=ARC, b=ARC, c=ARC, d=ARC),
    "skew": dict(a=LENGTH, b=LENGTH, c=LENGTH, d=LENGTH, f=OFFSET, ksi=KSI),
    "slider": dict(b=LENGTH, c=LENGTH, e=OFFSET),
    "skew-slider": dict(a=LENGTH, b=LENGTH, c=LENGTH, f=OFFSET, ksi=KSI),
}


def uniform_linkages(ranges: dict, n: int, seed: str) -> list[tuple[dict, int]]:
    """n (dimensions, branch), each dimension uniform in its range, from random.Random(seed)."""
    rng = random.Random(seed)
    return [({k: rng.uniform(lo, hi) for k, (lo, hi) in ranges.items()}, rng.choice((1, 2)))
            for _ in range(n)]


def examples(n, shrink=True):
    """n examples; shrink=False for the costly tests (a failure is reported as found: shrinking
    one of them takes minutes)."""
    phases = list(Phase) if shrink else [Phase.explicit, Phase.reuse, Phase.generate]
    return settings(max_examples=n, deadline=None, suppress_health_check=ALL_HEALTH,
                    phases=phases)


def wrapped(x):
    """x - y for angles: the difference in [-180, 180)."""
    return (x + 180.0) % 360.0 - 180.0


def grashof(a, b, c, d):
    """(type, crank turns fully) by Grashof's rule in the typed lengths, exactly (Fractions);
    None for the type when the shortest link is not unique."""
    lengths = {n: Fraction(abs(v)) for n, v in zip("abcd", (a, b, c, d))}
    ordered = sorted(lengths.values())
    s, p, q, l = ordered
    if s + l == p + q:
        return "change-point", None
    if s + l > p + q:
        return "double-rocker", False
    shortest = [n for n, v in lengths.items() if v == s]
    if len(shortest) > 1:
        return None, "a" in shortest or "b" in shortest
    kind = {"b": "crank-rocker", "a": "double-crank", "d": "rocker-crank",
            "c": "double-rocker"}[shortest[0]]
    return kind, shortest[0] in "ab"


def grashof_margin(a, b, c, d):
    s, p, q, l = sorted(abs(v) for v in (a, b, c, d))
    return abs((s + l) - (p + q))


def main(argv, capsys):
    """linkage.main(argv) in this process: (status, stdout, stderr)."""
    try:
        status = linkage.main(argv)
    except SystemExit as e:                       # argparse's refusals
        status = e.code
    except Exception as e:                        # noqa: BLE001 - what a user would see
        out, err = capsys.readouterr()
        return None, out, err + f"Traceback (in process): {e!r}\n"
    out, err = capsys.readouterr()
    return status, out, err


# == 1. Grashof's rule against the sampled motion (plane four-bar) ==============================

GRID = [0.25 * i for i in range(1441)]          # 0 to 360 by 0.25, both ends
LENGTH = st.floats(0.2, 10.0)


@examples(100)
@given(a=LENGTH, b=LENGTH, c=LENGTH, d=LENGTH, branch=st.sampled_from([1, 2]))
def test_grashof_says_what_the_sampled_motion_does(a, b, c, d, branch):
    """The plane four-bar's D is least at phi = 0 or 180 (it is a concave quadratic in cos phi),
    both on the grid: the grid sees every angle where the linkage does not assemble."""
    assume(grashof_margin(a, b, c, d) >= 1e-6)
    expected, crank_full = grashof(a, b, c, d)
    assume(expected is not None)
    link = linkage.Linkage("plane", a=a, b=b, c=c, d=d)
    swept = link.sweep(GRID, branch, 0)
    sampled_full = all(m.status != NOT for m in swept)
    assert sampled_full == crank_full, (a, b, c, d, expected)
    if all(m.output is None for m in swept):
        with pytest.raises(ValueError, match="assembles at no input angle"):
            linkage.analyse(link, branch)
        return
    analysis = linkage.analyse(link, branch)
    assert (analysis.crank_range is None) == sampled_full, (a, b, c, d, analysis.crank_range)
    assert analysis.linkage_class == expected, (a, b, c, d, analysis.criterion)
    assert analysis.change_points == ()


# == 2. the crank's range and its dead centres, every kind ======================================

FINE = [0.25 * i for i in range(1440)]           # [0, 360) by 0.25
PROBE = 1e-6
# Random linkages a kind: 100 in the default run, at least 11 of each kind whose crank turns
# fully and 53 that rock (the 150 before issue 36: 18 and 79); six mutations of crank_limits
# tried for issue 36 were caught, or missed, alike by the 100 and the 150. LINKAGE_LONG=1: the
# 150, the default's 100 first (the same seeded draws).
CRANK_LINKAGES = 150 if os.environ.get("LINKAGE_LONG") else 100


def assembles(m):
    return m.output is not None


@pytest.mark.parametrize("kind", list(LINKAGES))
def test_the_crank_range_and_dead_centres_are_where_the_engine_stops_assembling(kind,
                                                                                 monkeypatch):
    """Linkages the engine finds degenerate at a grid angle (a change point or a free output
    link exactly there: equal lengths, s + l = p + q) are left to the fixed tests below; any
    exception but ValueError from analyse is collected and reported at the end (as the
    remaining examples are still checked). crank_limits is computed once a linkage: the test's
    call is given what analyse's own call found (the same linkage, the same answer), not
    searched again (a sixth of this test's CPU)."""
    seen = {"rocking": 0, "full": 0}
    crashes = []
    found, crank_limits = {}, linkage.crank_limits

    def crank_limits_once(link):
        if id(link) in found:
            return tuple(list(limits) for limits in found[id(link)][1])
        answer = crank_limits(link)
        found[id(link)] = link, tuple(tuple(limits) for limits in answer)   # the linkage kept:
        return answer                                                         # its id unused
    monkeypatch.setattr(linkage, "crank_limits", crank_limits_once)

    def check(dims, branch):
        link = linkage.Linkage(kind, **dims)
        swept = link.sweep(FINE, 1, 0)
        if any(m.status in (linkage.CHANGE_POINT, linkage.INDETERMINATE) for m in swept):
            return
        try:
            analysis = linkage.analyse(link, branch)
        except ValueError as e:
            assert "assembles at no input angle" in str(e), e
            assert not any(assembles(m) for m in swept), (dims, "assembles but analyse says not")
            return
        except Exception as e:                    # noqa: BLE001 - reported below
            crashes.append((kind, dims, branch, repr(e)))
            return
        dead = analysis.dead_centres
        limits = linkage.crank_limits(link)
        assert (tuple(limits[0]), tuple(limits[1])) == (dead, analysis.change_points), dims
        probes = []
        for j, dc in enumerate(dead):
            assert 0.0 <= dc < 360.0, (dims, dc)
            # within a quarter of the way to the next dead centre (a gap may be 1e-11 wide)
            near = min([PROBE] + [abs(wrapped(dc - other)) / 4 for other in dead if other != dc])
            below, above = link.motion(dc - near, 1, 0), link.motion(dc + near, 1, 0)
            assert {below.status == NOT, above.status == NOT} == {True, False}, \
                (kind, dims, dc, below.status, above.status)
            assert assembles(below) != assembles(above), (kind, dims, dc)
            probes += [below, above]
        gap = any(m.status == NOT for m in swept + probes)
        assert (analysis.crank_range is None) == (not gap), (kind, dims, analysis.crank_range, dead)
        # every switch between neighbours of the grid holds a dead centre
        for i in range(len(FINE)):
            m0, m1 = swept[i], swept[(i + 1) % len(FINE)]
            if assembles(m0) != assembles(m1):
                lo, hi = FINE[i], FINE[i] + 0.25
                assert any(lo - 1e-9 <= x <= hi + 1e-9 or lo - 1e-9 <= x + 360.0 <= hi + 1e-9
                           for x in dead), (kind, dims, lo, hi, dead)
        if analysis.crank_range is not None:
            seen["rocking"] += 1
            assert len(dead) % 2 == 0 and dead, (kind, dims, dead)
            for lo, hi in analysis.crank_range:
                for end in (lo, hi):
                    assert any(abs(wrapped(end - x)) <= 1e-9 for x in dead), (kind, dims, end)
                middle = lo + ((hi - lo) % 360.0) / 2
                assert assembles(link.motion(middle, 1, 0)), (kind, dims, lo, hi)
        else:
            seen["full"] += 1
            assert dead == (), (kind, dims, dead)

    for dims, branch in uniform_linkages(RANGES[kind], CRANK_LINKAGES, kind):
        check(dims, branch)
    assert not crashes, f"analyse raised on {len(crashes)} linkages, e.g. {crashes[:3]}"
    assert seen["rocking"] >= 10 and seen["full"] >= 10, seen


# == 3. output range, swing and time ratio against a brute-force sweep ==========================

STEP = 0.01
COARSE = [STEP * i for i in range(36000)]       # [0, 360) by 0.01


def _values(link, phis, branch, reference=None):
    """The outputs at phis on branch (None if any does not assemble), unwrapped for the
    four-bars and placed beside `reference`. Sampled by the numpy path: the scalar engine's
    statuses exactly and its numbers to 1e-13 (tests/test_fast.py), 20 times as fast (the
    scalar sweeps were 6 of this test's 8 s of CPU)."""
    swept = link.sweep_arrays(phis, branch, 0)
    if (swept.status != linkage.STATUS_CODES.index(linkage.ASSEMBLED)).any():
        return None
    if link.is_slider:
        return swept.output
    values = numpy.unwrap(swept.output, period=360.0)
    if reference is not None:
        values += 360.0 * round((reference - values[len(values) // 2]) / 360.0)
    return values


def _refined(link, branch, coarse, which):
    """Brute force: every coarse local extreme near the global one re-sampled every 1e-5 degree
    within +-0.011 degree; [(value, phi)] sorted best first."""
    sign = 1.0 if which == "min" else -1.0
    ys = sign * coarse
    best = ys.min()
    found = []
    candidates = numpy.nonzero((ys <= numpy.roll(ys, 1)) & (ys <= numpy.roll(ys, -1))
                               & (ys <= best + 1e-3))[0]
    for i in sorted(candidates, key=lambda i: ys[i])[:8]:
        phis = [COARSE[i] + k * 1e-5 for k in range(-1100, 1101)]
        local = _values(link, phis, branch, coarse[i])
        if local is None:
            continue
        j = int(numpy.argmin(sign * local))
        found.append((float(local[j]), phis[j] % 360.0))
    return sorted(found, key=lambda e: sign * e[0])


def brute_force(link, branch):
    """(min, max) as (value, phi), or None where the crank does not turn fully on the grid or the
    output turns fully (not a crank-rocker); location None when two extremes tie."""
    coarse = _values(link, COARSE, branch)
    if coarse is None:
        return None
    if not link.is_slider:
        steps = numpy.abs(numpy.diff(numpy.append(coarse, coarse[0] + 360.0 * round(
            (coarse[-1] - coarse[0]) / 360.0))))
        if abs(coarse[-1] - coarse[0]) > 180.0 or steps.max() > 5.0:
            return None                           # the output turns (or the branch jumps)
    if coarse.max() - coarse.min() < 1e-2:
        return None                               # the output barely moves
    ends = []
    for which in ("min", "max"):
        found = _refined(link, branch, coarse, which)
        value, phi = found[0]
        tie = [p for v, p in found[1:] if abs(v - value) < 1e-9 and abs(wrapped(p - phi)) > 0.02]
        ends.append((value, None if tie else phi))
    return ends


CRANK_ROCKER_RANGES = {
    "plane": dict(a=(1.5, 10.0), b=(0.2, 1.0), c=(1.5, 10.0), d=(1.5, 10.0)),
    "spherical": dict(a=(30.0, 150.0), b=(5.0, 25.0), c=(30.0, 150.0), d=(30.0, 150.0)),
    "skew": dict(a=(1.5, 10.0), b=(0.2, 1.0), c=(1.5, 10.0), d=(1.5, 10.0), f=(-2.0, 2.0),
                 ksi=(-60.0, 60.0)),
    "slider": dict(b=(0.2, 2.0), c=(0.5, 10.0), e=(-3.0, 3.0)),
    "skew-slider": dict(a=(-3.0, 3.0), b=(0.2, 2.0), c=(0.5, 10.0), f=(-2.0, 2.0),
                        ksi=(-60.0, 60.0)),
}
CRANK_ROCKERS = {
    "plane": st.fixed_dictionaries(dict(a=st.floats(1.5, 10.0), b=st.floats(0.2, 1.0),
                                        c=st.floats(1.5, 10.0), d=st.floats(1.5, 10.0))),
    "spherical": st.fixed_dictionaries(dict(a=st.floats(30.0, 150.0), b=st.floats(5.0, 25.0),
                                            c=st.floats(30.0, 150.0), d=st.floats(30.0, 150.0))),
    "skew": st.fixed_dictionaries(dict(a=st.floats(1.5, 10.0), b=st.floats(0.2, 1.0),
                                       c=st.floats(1.5, 10.0), d=st.floats(1.5, 10.0),
                                       f=st.floats(-2.0, 2.0), ksi=st.floats(-60.0, 60.0))),
    "slider": st.fixed_dictionaries(dict(b=st.floats(0.2, 2.0), c=st.floats(0.5, 10.0),
                                         e=st.floats(-3.0, 3.0))),
    "skew-slider": st.fixed_dictionaries(dict(a=st.floats(-3.0, 3.0), b=st.floats(0.2, 2.0),
                                              c=st.floats(0.5, 10.0), f=st.floats(-2.0, 2.0),
                                              ksi=st.floats(-60.0, 60.0))),
}


def check_extremes_against_brute_force(link, branch):
    """The analysis' output extremes, swing, strokes and time ratio against brute_force; False
    where the linkage is no crank-rocker (crank-slider) on the grid."""
    brute = brute_force(link, branch)
    if brute is None:
        return False
    (low, low_phi), (high, high_phi) = brute
    analysis = linkage.analyse(link, branch)
    where = (link, branch, analysis)
    assert analysis.crank_range is None, where
    assert analysis.output_min is not None and analysis.output_max is not None, where
    tol = 1e-6 * (1.0 if not link.is_slider else max(1.0, max(abs(v) for v in link.dims.values())))
    got_low, got_high = analysis.output_min.value, analysis.output_max.value
    if link.is_slider:
        assert abs(got_low - low) <= tol and abs(got_high - high) <= tol, (where, low, high)
    else:
        assert abs(wrapped(got_low - low)) <= tol, (where, low, high)
        assert abs(wrapped(got_high - high)) <= tol, (where, low, high)
    assert abs((got_high - got_low) - (high - low)) <= 2 * tol, (where, high - low)
    assert analysis.linkage_class == ("crank-slider" if link.is_slider else "crank-rocker"), where
    if low_phi is None or high_phi is None:
        return True                               # two extremes alike: where is not defined
    assert abs(wrapped(analysis.output_min.phi - low_phi)) <= 1e-3, (where, low_phi)
    assert abs(wrapped(analysis.output_max.phi - high_phi)) <= 1e-3, (where, high_phi)
    forward = (high_phi - low_phi) % 360.0
    assert analysis.forward_stroke is not None, where
    assert abs(wrapped(analysis.forward_stroke - forward)) <= 1e-3, (where, forward)
    assert abs(analysis.forward_stroke + analysis.return_stroke - 360.0) <= 1e-9, where
    # the review's eq. (5), forward over return, and the ratio as engineers quote it: the slower
    # stroke over the faster (>= 1), with which stroke is the slower
    assert analysis.time_ratio_review == pytest.approx(
        analysis.forward_stroke / analysis.return_stroke, rel=1e-12)
    slower, faster = sorted((analysis.forward_stroke, analysis.return_stroke), reverse=True)
    assert analysis.time_ratio == pytest.approx(slower / faster, rel=1e-12)
    assert analysis.time_ratio >= 1.0
    if abs(analysis.forward_stroke - analysis.return_stroke) > 1e-6:
        assert analysis.slower_stroke == ("forward" if analysis.forward_stroke > analysis.return_stroke
                                          else "return"), where
    return True


@pytest.mark.parametrize("kind", list(CRANK_ROCKERS))
def test_output_range_swing_and_time_ratio_against_a_brute_force_sweep(kind):
    checked = [check_extremes_against_brute_force(linkage.Linkage(kind, **dims), branch)
               for dims, branch in uniform_linkages(CRANK_ROCKER_RANGES[kind], 25, kind)]
    assert sum(checked) >= 10, (kind, sum(checked), len(checked))


def test_an_output_extreme_on_a_sample_where_the_velocity_is_exactly_zero():
    """The review's FOURB-CR-1 example (theta 10, psi 50, theta0 30) as synthesis designs it: on
    branch 2 the engine's velocity at phi = 220, one of analyse's half-degree samples, is 0.0
    exactly; the rocker's maximum is there (the rocker swings 50 degrees while the crank turns
    190)."""
    link = linkage.Linkage("plane", a=1.0, b=0.2579608173397918, c=1.0121877901475418,
                           d=0.64289623095107)
    assert check_extremes_against_brute_force(link, 2)


# == 4. the transmission angle's extremes of the plane crank-rocker: eqs. (2a), (2b) =============

def mu_review(a, b, c, d, phi):
    """Eq. (2a) (phi = 0) and (2b) (phi = 180) in the project's letters, in mpmath, degrees."""
    with mpmath.workdps(40):
        a, b, c, d = (mpmath.mpf(v) for v in (a, b, c, d))
        diagonal = a - b if phi == 0 else a + b
        return float(mpmath.degrees(mpmath.acos((c * c + d * d - diagonal ** 2) / (2 * c * d))))


@examples(150)
@given(CRANK_ROCKERS["plane"], st.sampled_from([1, 2]))
def test_mu_extremes_of_a_plane_crank_rocker_are_the_reviews_eq_2(dims, branch):
    a, b, c, d = (dims[k] for k in "abcd")
    assume(grashof(a, b, c, d)[0] == "crank-rocker" and grashof_margin(a, b, c, d) >= 1e-6)
    analysis = linkage.analyse(linkage.Linkage("plane", **dims), branch)
    at = {0.0: mu_review(a, b, c, d, 0), 180.0: mu_review(a, b, c, d, 180)}
    (low_phi, low), (high_phi, high) = sorted(at.items(), key=lambda e: e[1])
    where = (dims, branch, analysis.mu_min, analysis.mu_max, at)
    assert abs(analysis.mu_min.value - low) <= 1e-9, where
    assert abs(analysis.mu_max.value - high) <= 1e-9, where
    assert abs(wrapped(analysis.mu_min.phi - low_phi)) <= 1e-6, where
    assert abs(wrapped(analysis.mu_max.phi - high_phi)) <= 1e-6, where


# == 5. change points ===========================================================================

def test_a_plane_four_bar_with_s_plus_l_equal_to_p_plus_q_has_a_change_point_at_180():
    """a = 3, b = 1, c = 2, d = 2: at phi = 180 the crank tip is 4 = c + d from the output
    pivot, all four links on one line (D touches zero there and nowhere else)."""
    analysis = linkage.analyse(linkage.Linkage("plane", a=3, b=1, c=2, d=2))
    assert analysis.linkage_class == "change-point"
    assert len(analysis.change_points) == 1 and abs(analysis.change_points[0] - 180.0) <= 1e-9
    assert analysis.dead_centres == () and analysis.crank_range is None
    dead, changes = linkage.crank_limits(linkage.Linkage("plane", a=3, b=1, c=2, d=2))
    assert list(dead) == [] and len(changes) == 1 and abs(changes[0] - 180.0) <= 1e-9


def test_a_slider_crank_with_b_plus_e_equal_to_c_has_a_change_point():
    """b = 2, e = 1, c = 3: the crank tip (2 cos phi, 2 sin phi) is 1 - 2 sin phi from the
    slider's line y = 1, which is c = 3 at phi = 270 only."""
    analysis = linkage.analyse(linkage.Linkage("slider", b=2, c=3, e=1))
    assert analysis.linkage_class == "change-point"
    assert len(analysis.change_points) == 1 and abs(analysis.change_points[0] - 270.0) <= 1e-9
    assert analysis.dead_centres == () and analysis.crank_range is None


def law_of_cosines_phi(a, b, distance):
    """The crank angle (degrees, in [0, 180]) at which the crank tip is `distance` from the
    output pivot: a^2 + b^2 - 2ab cos phi = distance^2."""
    with mpmath.workdps(40):
        a, b, distance = (mpmath.mpf(v) for v in (a, b, distance))
        return float(mpmath.degrees(mpmath.acos((a * a + b * b - distance ** 2) / (2 * a * b))))


@pytest.mark.parametrize("kind, dims, changes, dead", [
    # a parallelogram: flat at phi = 0 (the crank tip 2 = c - d from the output pivot) and at
    # 180 (4 = c + d); the crank turns fully, through both
    ("plane", dict(a=3, b=1, c=3, d=1), [0.0, 180.0], []),
    # a - b = c - d = 2: flat at phi = 0; the crank tip reaches c + d = 3 at cos phi = 1/6
    ("plane", dict(a=3, b=1, c=2.5, d=0.5), [0.0], [law_of_cosines_phi(3, 1, 3), 360.0 - law_of_cosines_phi(
        3, 1, 3)]),
    # a rhombus: at phi = 0 the crank tip is on the output pivot (the output is free there, the
    # branches cross); at 180 all four links lie on a line
    ("plane", dict(a=1, b=1, c=1, d=1), [0.0, 180.0], []),
    # the spherical rhombus, the same on the sphere
    ("spherical", dict(a=5, b=5, c=5, d=5), [0.0, 180.0], []),
])
def test_a_change_point_at_phi_0_is_no_dead_centre(kind, dims, changes, dead):
    """D touches zero at phi = 0 without changing sign: the engine assembles the linkage on both
    sides (checked here), so the crank passes 0: a change point, not a dead centre, and the
    crank's range is not cut at 0."""
    link = linkage.Linkage(kind, **dims)
    for phi in (-1e-6, 1e-6):
        assert link.motion(phi, 1, 0).output is not None
    analysis = linkage.analyse(link)
    assert analysis.linkage_class == "change-point", analysis
    got = (list(analysis.change_points), list(analysis.dead_centres))
    assert len(got[0]) == len(changes) and len(got[1]) == len(dead), (got, changes, dead)
    assert all(abs(x - y) <= 1e-9 for x, y in zip(got[0] + got[1], changes + dead)), got
    if dead:
        (lo, hi), = analysis.crank_range
        assert (lo, hi) == (pytest.approx(dead[1], abs=1e-9), pytest.approx(dead[0], abs=1e-9))
    else:
        assert analysis.crank_range is None


@pytest.mark.parametrize("kind, dims, expected", [
    # b + |e| = c + 1e-13: D dips 2e-13 of its scale below zero around phi = 270, where the
    # engine does not assemble the linkage (a gap 5e-5 degree wide)
    ("slider", dict(b=1.0, c=1.0, e=1e-13), "rocker-slider"),
    # the rhombus made skew by 1e-130 degree: the output link is free at phi = 0
    ("skew", dict(a=1.0, b=1.0, c=1.0, d=1.0, f=1.0, ksi=1e-130), None),
], ids=["slider-touching", "skew-rhombus"])
def test_a_linkage_at_the_edge_of_a_change_point_is_analysed(kind, dims, expected, capsys):
    """analyse gives an Analysis (or a ValueError), never another exception, and the command
    line no traceback."""
    analysis = linkage.analyse(linkage.Linkage(kind, **dims))
    if expected:
        assert analysis.linkage_class == expected
    if kind == "slider":
        # x = cos phi +- |cos phi| (b = c = 1, e ~ 0): 2 at phi = 0 and 0 at 180 on branch 1
        # (and -2 at 0 on branch 2, if the circuit comes back on it): the output moves by 2 at
        # least
        assert analysis.output_min is not None, analysis
        assert analysis.output_max.value - analysis.output_min.value >= 2.0 - 1e-6, analysis
    argv = ["analyse", kind] + [w for n, v in dims.items() for w in (f"--{n}", repr(v))]
    status, out, err = main(argv, capsys)
    assert "Traceback" not in err and status == 0, err[-300:]


@pytest.mark.parametrize("kind, dims, expected", [
    ("plane", dict(a=3, b=1, c=2, d=2 + 1e-6), "crank-rocker"),      # s + l < p + q
    ("plane", dict(a=3, b=1, c=2, d=2 - 1e-6), "double-rocker"),     # s + l > p + q
    ("slider", dict(b=2, c=3, e=1 - 1e-6), "crank-slider"),
    ("slider", dict(b=2, c=3, e=1 + 1e-6), "rocker-slider"),
])
def test_near_a_change_point_is_not_one(kind, dims, expected):
    analysis = linkage.analyse(linkage.Linkage(kind, **dims))
    assert analysis.linkage_class == expected
    assert analysis.change_points == ()
    assert (analysis.crank_range is None) == expected.startswith("crank-")
    assert len(analysis.dead_centres) == (0 if expected.startswith("crank-") else 2)


# == 6. the review's worked examples, designed and analysed =====================================

def analysis_values(out):
    lines = [line for line in out.splitlines() if line.startswith("analysis.")]
    values = dict(line.removeprefix("analysis.").split(" = ", 1) for line in lines)
    return values


def number(text):
    return float(text.split()[0])


def designed(capsys, *argv):
    status, out, err = main(["design", *argv, "--analyze"], capsys)
    assert status == 0 and "Traceback" not in err, (argv, status, err)
    values = analysis_values(out)
    assert values, out
    return values


def test_fourb_cr_4_psi_60_mu_40_is_analysed_as_designed(capsys):
    values = designed(capsys, "fourb-cr-4", "--psi", "60", "--mu-min", "40")
    assert values["class"] == "crank-rocker" and values["crank_range"] == "full"
    assert number(values["swing"]) == pytest.approx(60, abs=1e-7)
    assert number(values["time_ratio"]) == pytest.approx(1, abs=1e-9)
    assert number(values["mu_min"]) == pytest.approx(40, abs=1e-7)
    assert number(values["mu_max"]) == pytest.approx(140, abs=1e-7)


def test_fourb_cr_4_review_example_psi_50_mu_30(capsys):
    """The review's FOURB-CR-4 example: crank 0.407014, coupler 0.487998, rocker 0.963078, frame
    1 (the project's b, c, d, a); centric (time ratio 1), swing 50, mu 30 to 150 (the review's
    'Delta = 149.99' is erratum S2: 150.00)."""
    values = designed(capsys, "fourb-cr-4", "--psi", "50", "--mu-min", "30")
    assert [f"{number(values[k]):.6f}" for k in "abcd"] == [
        "1.000000", "0.407014", "0.487998", "0.963078"]
    assert values["class"] == "crank-rocker"
    assert number(values["swing"]) == pytest.approx(50, abs=1e-7)
    assert number(values["time_ratio"]) == pytest.approx(1, abs=1e-9)
    assert number(values["mu_min"]) == pytest.approx(30, abs=1e-7)
    assert f"{number(values['mu_max']):.2f}" == "150.00"


def test_fourb_cr_1_review_example_theta_10_psi_50_theta0_30(capsys):
    """The review's FOURB-CR-1 example: the rocker swings psi = 50 while the crank turns
    180 + theta = 190 (and back in 170: time ratio 19/17), from the extended dead centre at
    theta0 = 30; printed mu_min = 47.022 (truncated, erratum S2) and mu_max = 96.380."""
    values = designed(capsys, "fourb-cr-1", "--theta", "10", "--psi", "50", "--theta0", "30")
    assert values["class"] == "crank-rocker" and values["crank_range"] == "full"
    assert f"{math.trunc(number(values['mu_min']) * 1000) / 1000:.3f}" == "47.022"
    assert f"{number(values['mu_max']):.3f}" == "96.380"
    assert number(values["swing"]) == pytest.approx(50, abs=1e-7), values
    assert number(values["output_min_phi"]) == pytest.approx(30, abs=1e-6), values
    assert number(values["forward_stroke"]) == pytest.approx(190, abs=1e-6), values
    assert number(values["return_stroke"]) == pytest.approx(170, abs=1e-6), values
    assert number(values["time_ratio"]) == pytest.approx(19 / 17, rel=1e-9), values


# == 7. the command line ========================================================================

def one_error_line(err):
    """The one line of stderr that says what is wrong (argparse prints its usage before it)."""
    assert "Traceback" not in err, err
    said = [line for line in err.splitlines() if not line.startswith(("usage:", " "))]
    assert len(said) == 1, err
    return said[0]


def test_analyse_prints_the_analysis_lines(capsys):
    status, out, err = main(["analyse", "plane", "--a", "3", "--b", "1", "--c", "2.5",
                             "--d", "2.2"], capsys)
    assert status == 0 and err == ""
    expected = linkage.analysis_lines(linkage.analyse(linkage.Linkage(
        "plane", a=3.0, b=1.0, c=2.5, d=2.2)))
    assert out.splitlines() == expected
    values = dict(line.split(" = ", 1) for line in out.splitlines())
    assert values["class"] == "crank-rocker" and values["branch"] == "1"
    # eq. (2a) and (2b) again, through the printed text (10 significant digits)
    assert number(values["mu_min"]) == pytest.approx(mu_review(3, 1, 2.5, 2.2, 0), abs=1e-7)
    assert number(values["mu_max"]) == pytest.approx(mu_review(3, 1, 2.5, 2.2, 180), abs=1e-7)


def test_analyse_refuses_a_linkage_that_never_assembles(capsys):
    status, out, err = main(["analyse", "plane", "--a", "10", "--b", "1", "--c", "1",
                             "--d", "1"], capsys)
    assert status == 1 and out == ""
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("linkage.py: Illegal linkage (impossible to assemble): ")


@pytest.mark.parametrize("dims, message", [
    (["--a", "nan", "--b", "1", "--c", "1", "--d", "1"], "--a"),
    (["--a", "1", "--b", "1e999", "--c", "1", "--d", "1"], "--b"),
    (["--a", "1", "--b", "1", "--c", "1"], "missing --d"),
])
def test_analyse_refuses_bad_dimensions(capsys, dims, message):
    status, out, err = main(["analyse", "plane", *dims], capsys)
    assert status == 2 and out == ""
    line = one_error_line(err)
    assert "error" in line and message in line, err


SKEW = ["skew", "--a", "3", "--b", "1", "--c", "3", "--d", "2", "--f", "0.5", "--ksi", "20"]
SKEW_SLIDER = ["skew-slider", "--a", "1", "--b", "1", "--c", "3", "--f", "0.5", "--ksi", "30"]
PLANE = ["plane", "--a", "3", "--b", "1", "--c", "2.5", "--d", "2.2"]
SWEEP = ["--from", "0", "--to", "360", "--step", "7.5", "--branch", "1"]


@pytest.mark.parametrize("argv, status", [
    (PLANE + ["--coupler", "1"], 2),                                   # basic precision
    (PLANE + ["--precision", "double", "--coupler", "1", "NOCSV"], 2),  # no --csv
    (PLANE + ["--precision", "double", "--coupler", "nan"], None),
    (PLANE + ["--precision", "double", "--coupler", "0.5", "nan"], None),
    (PLANE + ["--precision", "double", "--coupler", "1e300"], None),
    (SKEW + ["--precision", "double", "--coupler", "1", "0.5"], None),
    (SKEW_SLIDER + ["--precision", "double", "--coupler", "1", "-0.25"], None),
    (SKEW + ["--precision", "double", "--fast", "--coupler", "1", "0.5"], None),
    (SKEW_SLIDER + ["--precision", "double", "--fast", "--coupler", "1e300"], None),
], ids=["basic", "no-csv", "nan", "v-nan", "1e300", "skew-v", "skew-slider-v", "skew-v-fast",
        "skew-slider-1e300-fast"])
def test_run_refuses_a_bad_coupler_point_and_writes_nothing(tmp_path, capsys, argv,
                                                            status):
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    csv_args = [] if "NOCSV" in argv else ["--csv", str(out_dir / "x.csv")]
    argv = [a for a in argv if a != "NOCSV"]
    got, out, err = main(["run", *argv[:1], *SWEEP, *argv[1:], *csv_args, "--dir", str(out_dir)],
                         capsys)
    assert got != 0 and (status is None or got == status), (argv, got, err)
    assert "coupler" in one_error_line(err), err
    assert sorted(p.name for p in out_dir.iterdir()) == [], "written though refused"
    assert list(tmp_path.iterdir()) == [out_dir]


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def run_csv(tmp_path, capsys, name, argv):
    folder = tmp_path / name
    folder.mkdir()
    status, _, err = main(["run", *argv[:1], *SWEEP, *argv[1:], "--precision", "double",
                           "--csv", str(folder / "out.csv"), "--dir", str(folder)], capsys)
    assert status == 0, err
    return read_csv(folder / "out.csv")


def test_run_csv_columns_in_double_with_and_without_a_coupler_point(tmp_path, capsys):
    plain = run_csv(tmp_path, capsys, "plain", PLANE)
    assert plain[0] == ["phi", "output", "velocity", "acceleration", "status", "transmission"]
    with_point = run_csv(tmp_path, capsys, "point", PLANE + ["--coupler", "0.5", "0.3"])
    assert with_point[0] == plain[0] + [f"coupler_{q}{axis}" for q in ("", "v", "a")
                                        for axis in "xyz"]
    assert len(with_point) == len(plain) == 49 + 1
    assert [row[:6] for row in with_point] == plain
    # the transmission column is eq. (1): cos mu = (c^2 + d^2 - a^2 - b^2 + 2ab cos phi) / 2cd
    for row in plain[1:]:
        phi, mu = float(row[0]), float(row[5])
        cos_mu = (2.5 ** 2 + 2.2 ** 2 - 9 - 1 + 6 * math.cos(math.radians(phi))) / (2 * 2.5 * 2.2)
        assert mu == pytest.approx(math.degrees(math.acos(cos_mu)), abs=1e-9), row


def same_table(one, other):
    """The same CSV text, or the same numbers to 1e-12 (relative to each column's largest)."""
    if one == other:
        return True
    assert one[0] == other[0] and len(one) == len(other)
    for column in range(len(one[0])):
        x = [row[column] for row in one[1:]]
        y = [row[column] for row in other[1:]]
        if one[0][column] == "status":
            assert x == y
            continue
        x, y = numpy.array(x, dtype=float), numpy.array(y, dtype=float)
        assert (numpy.isnan(x) == numpy.isnan(y)).all(), one[0][column]
        scale = max(1.0, numpy.nanmax(numpy.abs(x)) if not numpy.isnan(x).all() else 1.0)
        assert numpy.allclose(x, y, rtol=1e-12, atol=1e-12 * scale, equal_nan=True), one[0][column]
    return True


@pytest.mark.parametrize("point", [[], ["--coupler", "0.5", "0.3"]], ids=["output", "coupler"])
def test_run_fast_gives_the_same_csv(tmp_path, capsys, point):
    scalar = run_csv(tmp_path, capsys, "scalar", PLANE + point)
    fast = run_csv(tmp_path, capsys, "fast", PLANE + point + ["--fast"])
    assert same_table(scalar, fast)


def test_the_readmes_analysis_is_what_the_program_prints(capsys):
    """README's `analyse` of Fig. 3's linkage is the program's output now."""
    readme = (Path(linkage.__file__).parent / "README.md").read_text(encoding="utf-8")
    command = "    $ python3 linkage.py analyse plane --a 6 --b 2 --c 7 --d 9\n"
    block = readme[readme.index(command) + len(command):].split("\n\n")[0]
    shown = [line.removeprefix("    ") for line in block.splitlines()]
    assert linkage.main(["analyse", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9"]) == 0
    assert capsys.readouterr().out.splitlines() == shown


# == degenerate linkages (issue 35, item 6) =====================================================

@pytest.mark.parametrize("argv, named", [
    (["skew-slider", "--a", "0", "--b", "2", "--c", "2", "--f", "0", "--ksi", "0"], "a = 0"),
    (["plane", "--a", "0", "--b", "2", "--c", "7", "--d", "9"], "a = 0"),
    (["plane", "--a", "0", "--b", "2", "--c", "7", "--d", "8"], "a = 0"),   # turns rigidly
    (["plane", "--a", "6", "--b", "0", "--c", "7", "--d", "9"], "b = 0"),
    (["slider", "--b", "2", "--c", "0", "--e", "1"], "c = 0"),
    (["spherical", "--a", "40", "--b", "20", "--c", "30", "--d", "0"], "d = 0"),
    (["skew", "--a", "0", "--b", "2", "--c", "7", "--d", "9", "--f", "0", "--ksi", "30"],
     "a = 0 and f = 0"),
])
def test_a_degenerate_linkage_is_said_to_be_so_at_once(capsys, argv, named):
    """Issue 35, item 6: a zero link made analyse search a linkage at a dead centre at every
    angle (12 s of CPU for the skew slider-crank) and print `type = rocker-slider` with 160
    "dead centres" at its grid points. It is degenerate, said in one line (exit 1) at once: a
    bound of 0.5 s of CPU that the search took 10 to 25 times over (a guard, not a benchmark)."""
    import time
    started = time.process_time()
    status, out, err = main(["analyse", *argv], capsys)
    spent = time.process_time() - started
    assert status == 1 and out == ""
    line = one_error_line(err)
    assert "degenerate" in line and named in line, line
    assert spent < 0.5, spent


def test_a_linkage_at_a_dead_centre_at_every_angle_is_degenerate():
    """No link of zero length, yet at a dead centre at every angle: the plane four-bar with
    b + c = d and a fixed link of 1e-300 (nothing beside 2, 7 and 9 in the engine's numbers), its
    statuses checked at 33 angles here. Ordinary linkages, one with a change point among them,
    and a skew slider-crank whose fixed link is its vertical part f alone, are not degenerate."""
    link = linkage.Linkage("plane", a=1e-300, b=2, c=7, d=9)
    assert all(m.status == linkage.DEAD_CENTRE for m in link.sweep([0.5 + 11 * i for i in
                                                                   range(33)], 1, 0))
    assert "dead centre" in linkage.degenerate(link)
    for kind, dims in (("plane", dict(a=6, b=2, c=7, d=9)), ("plane", dict(a=5, b=2, c=4, d=3)),
                       ("slider", dict(b=2, c=3, e=1)),
                       ("skew-slider", dict(a=0, b=1, c=3, f=0.5, ksi=30))):
        assert linkage.degenerate(linkage.Linkage(kind, **dims)) is None, (kind, dims)
