"""analyse against brute force (issue 34, item 8): random plane four-bars and slider-cranks of
every class, on both branches (crank-rockers, double-cranks, rocking cranks, two-circuit
linkages), each circuit's output range and swing against the motion sampled every 0.001 degree
and refined at 50 digits in mpmath, to 1e-9 (degrees; for the slider, of its size); the
transmission angle of the plane four-bar against eq. (1) at the angles where it is extreme.

Nothing here calls analyse's helpers or the engine: the loop closure is written below from the
geometry, the dead centres solved in closed form, and the circuits built from them.

  plane four-bar: crank pivot A at the origin, output pivot D at (a, 0), crank pin
    B = b (cos phi, sin phi), output pin C = D + d (cos psi, sin psi), |BC| = c. With r = |DB|
    and theta the direction from D to B, psi = theta +- alpha, cos alpha = (d^2 + r^2 - c^2) /
    (2 d r). The listing's branch 1 is the root where d|BC|^2/dpsi = 2 d r sin(psi - theta) > 0
    (the engine's section notes: dE/dpsi > 0), i.e. psi = theta + alpha; branch 2 theta - alpha.
    The crank can turn where |c - d| <= r <= c + d: its dead centres are where cos phi =
    (a^2 + b^2 - r^2) / 2ab for r = c + d and r = |c - d|.
  plane slider-crank: crank pin B = b (cos phi, sin phi), slider on the line y = e at
    x = b cos phi +- sqrt(c^2 - (e - b sin phi)^2), branch 1 the + root (the slider to the right
    of the crank pin); dead centres where e - b sin phi = +-c.

A circuit is the whole turn on the branch asked where the crank turns fully, else a crank
interval between two dead centres, out on branch 1 and back on branch 2 (a circuit has both).

The default run checks 60 linkages (stratified over the classes, one branch each, the two
explicit cases of the issue besides), and 80 more, 40 linkages on both branches (5 of each class);
LINKAGE_LONG=1 makes those 304, 152 linkages (19 of each class, the first 5 of each the default
run's). The module is marked slow (the full run's, not --quick's)."""

from __future__ import annotations

import math
import os
import random
import tomllib
from pathlib import Path

import mpmath
import numpy
import pytest

import linkage

pytestmark = pytest.mark.slow

DIGITS = 50
GRID = 0.001                    # degrees between samples of the brute force
TOLERANCE = 1e-9                # degrees (the slider: times max(1, its largest dimension))
PHI_TOLERANCE = 1e-6            # where an extreme is, when no other extreme is as far


def wrapped(x):
    return (x + 180.0) % 360.0 - 180.0


# == the loop closure, written from the geometry ================================================

class Model:
    """A plane four-bar (a, b, c, d) or slider-crank (b, c, e): dead centres, intervals and the
    output, in numpy (the samples) and in mpmath (the refinement)."""

    def __init__(self, kind, dims):
        self.kind, self.dims = kind, dict(dims)
        self.angular = kind == "plane"
        with mpmath.workdps(DIGITS):
            self.mp = {k: mpmath.mpf(v) for k, v in dims.items()}

    # -- dead centres and intervals
    def dead_centres(self):
        """The dead centres in [0, 360), mpf, sorted."""
        found = []
        with mpmath.workdps(DIGITS):
            m = self.mp
            if self.kind == "plane":
                for r in (m["c"] + m["d"], abs(m["c"] - m["d"])):
                    cos_phi = (m["a"] ** 2 + m["b"] ** 2 - r * r) / (2 * m["a"] * m["b"])
                    if abs(cos_phi) < 1:
                        x = mpmath.degrees(mpmath.acos(cos_phi))
                        found += [x, 360 - x]
            else:
                for sign in (1, -1):
                    sin_phi = (m["e"] - sign * m["c"]) / m["b"]
                    if abs(sin_phi) < 1:
                        x = mpmath.degrees(mpmath.asin(sin_phi))
                        found += [x % 360, (180 - x) % 360]
        return sorted(found)

    def assembles(self, phi):
        with mpmath.workdps(DIGITS):
            m, t = self.mp, mpmath.radians(mpmath.mpf(phi))
            if self.kind == "plane":
                r2 = m["a"] ** 2 + m["b"] ** 2 - 2 * m["a"] * m["b"] * mpmath.cos(t)
                return (m["c"] - m["d"]) ** 2 <= r2 <= (m["c"] + m["d"]) ** 2
            return abs(m["e"] - m["b"] * mpmath.sin(t)) <= m["c"]

    def intervals(self):
        """[(lo, hi)] mpf, hi > lo (hi may pass 360), the crank intervals; None where the crank
        turns fully; [] where it never assembles."""
        dead = self.dead_centres()
        if not dead:
            return None if self.assembles(0) else []
        ends = dead + [dead[0] + 360]
        return [(lo, hi) for lo, hi in zip(ends, ends[1:]) if self.assembles((lo + hi) / 2)]

    # -- the output
    def output_np(self, phi, branch):
        """psi (degrees) or x at phis (numpy array, degrees) on branch 1 or 2."""
        t = numpy.radians(phi)
        d = self.dims
        sign = 1.0 if branch == 1 else -1.0
        if self.kind == "plane":
            bx, by = d["b"] * numpy.cos(t) - d["a"], d["b"] * numpy.sin(t)
            r = numpy.hypot(bx, by)
            cos_alpha = numpy.clip((d["d"] ** 2 + r * r - d["c"] ** 2) / (2 * d["d"] * r), -1, 1)
            return numpy.degrees(numpy.arctan2(by, bx) + sign * numpy.arccos(cos_alpha))
        h = d["e"] - d["b"] * numpy.sin(t)
        return d["b"] * numpy.cos(t) + sign * numpy.sqrt(numpy.maximum(d["c"] ** 2 - h * h, 0.0))

    def output_mp(self, phi, branch):
        """The same in mpmath at DIGITS (phi an mpf, degrees); at a dead centre the double root."""
        with mpmath.workdps(DIGITS):
            m, t = self.mp, mpmath.radians(phi)
            sign = 1 if branch == 1 else -1
            if self.kind == "plane":
                bx, by = m["b"] * mpmath.cos(t) - m["a"], m["b"] * mpmath.sin(t)
                r = mpmath.hypot(bx, by)
                cos_alpha = (m["d"] ** 2 + r * r - m["c"] ** 2) / (2 * m["d"] * r)
                cos_alpha = min(max(cos_alpha, -1), 1)
                return mpmath.degrees(mpmath.atan2(by, bx) + sign * mpmath.acos(cos_alpha))
            h = m["e"] - m["b"] * mpmath.sin(t)
            return m["b"] * mpmath.cos(t) + sign * mpmath.sqrt(max(m["c"] ** 2 - h * h, 0))

    def mu(self, phi):
        """The plane four-bar's transmission angle, eq. (1) (degrees, mpmath)."""
        with mpmath.workdps(DIGITS):
            m, t = self.mp, mpmath.radians(mpmath.mpf(phi))
            r2 = m["a"] ** 2 + m["b"] ** 2 - 2 * m["a"] * m["b"] * mpmath.cos(t)
            cos_mu = (m["c"] ** 2 + m["d"] ** 2 - r2) / (2 * m["c"] * m["d"])
            return mpmath.degrees(mpmath.acos(min(max(cos_mu, -1), 1)))


# == brute force ================================================================================

def golden(f, lo, hi, maximum, iterations=70):
    """The best of f over [lo, hi] (mpf) by golden-section search, the ends included:
    (value, x)."""
    with mpmath.workdps(DIGITS):
        sign = 1 if maximum else -1
        g = (mpmath.sqrt(5) - 1) / 2
        best = max(((sign * f(lo), lo), (sign * f(hi), hi)))
        a, b = lo, hi
        x1, x2 = b - g * (b - a), a + g * (b - a)
        f1, f2 = sign * f(x1), sign * f(x2)
        for _ in range(iterations):
            if f1 > f2:
                b, x2, f2 = x2, x1, f1
                x1 = b - g * (b - a)
                f1 = sign * f(x1)
            else:
                a, x1, f1 = x1, x2, f2
                x2 = a + g * (b - a)
                f2 = sign * f(x2)
        best = max(best, (f1, x1), (f2, x2))
        return sign * best[0], best[1]


class Path_:
    """A circuit sampled: phi (float), branch (1, 2; 0 at a dead centre, its mpf in exact),
    values unwrapped along it."""

    def __init__(self, model, interval, branch):
        self.model = model
        if interval is None:                          # the whole turn on `branch`
            phis = numpy.arange(0, round(360 / GRID)) * GRID
            self.phi, self.branch = phis, numpy.full(len(phis), branch)
            self.exact = {}
            values = model.output_np(phis, branch)
        else:
            lo, hi = interval
            flo, fhi = float(lo), float(hi)
            inner = flo + GRID * numpy.arange(1, math.ceil((fhi - flo) / GRID))
            inner = inner[(inner > flo) & (inner < fhi)]
            with mpmath.workdps(DIGITS):
                at_lo, at_hi = model.output_mp(lo, 1), model.output_mp(hi, 1)
            self.phi = numpy.concatenate([[flo], inner, [fhi], inner[::-1]])
            self.branch = numpy.concatenate([[0], numpy.full(len(inner), 1), [0],
                                             numpy.full(len(inner), 2)])
            values = numpy.concatenate([[float(at_lo)], model.output_np(inner, 1), [float(at_hi)],
                                        model.output_np(inner[::-1], 2)])
            self.exact = {0: lo, len(inner) + 1: hi}
        self.turns = False
        if model.angular:
            values = numpy.unwrap(values, period=360.0)
            # the path closes on its first point (phi = 360 on the whole turn, the first dead
            # centre on a crank interval): the net change is 0, or a full turn of the output
            closing = float(model.output_np(numpy.array([360.0]), branch)[0]) if (
                interval is None) else values[0]
            closing += 360.0 * round((values[-1] - closing) / 360.0)
            self.turns = abs(closing - values[0]) > 180.0
        self.values = values

    def value_at(self, i, phi, branch):
        """The exact output at phi on branch, placed beside sample i's unwrapped value."""
        v = float(self.model.output_mp(phi, branch))
        if self.model.angular:
            v += 360.0 * round((self.values[i] - v) / 360.0)
        return v

    def extreme(self, maximum):
        """(value, phi, tie): the circuit's greatest (least) output, every sampled local extreme
        near the sampled best refined at 50 digits."""
        y = self.values if maximum else -self.values
        n = len(y)
        local = numpy.nonzero((y >= numpy.roll(y, 1)) & (y >= numpy.roll(y, -1)))[0]
        span = float(self.values.max() - self.values.min())
        near = [i for i in local if y[i] >= y.max() - max(0.05, 0.05 * span)]
        near = sorted(near, key=lambda i: -y[i])[:12]
        found = []
        for i in near:
            for phi, value in self._refined(i, n, maximum):
                found.append((value, phi))
        sign = 1.0 if maximum else -1.0
        found.sort(key=lambda e: -sign * e[0])
        value, phi = found[0]
        tie = any(abs(v - value) <= 1e-9 * self.scale() and abs(wrapped(p - phi)) > 1e-4
                  for v, p in found[1:])
        return value, phi, tie

    def scale(self):
        return 1.0 if self.model.angular else max(1.0, *map(abs, self.model.dims.values()))

    def _refined(self, i, n, maximum):
        """[(phi, value)] about sample i: at a dead centre its exact output and each side's
        bracket on its branch; else the bracket of its neighbours on its branch."""
        out = []
        before, after = (i - 1) % n, (i + 1) % n

        def side(j, end, branch):
            lo, hi = sorted((mpmath.mpf(self._phi(j)), mpmath.mpf(end)))
            value, x = golden(lambda p: self._signed(p, branch, i), lo, hi, maximum)
            out.append((float(x) % 360.0, float(value)))

        if self.branch[i] == 0:
            dead = self.exact[i]
            out.append((float(dead) % 360.0, self.value_at(i, dead, 1)))
            side(before, dead, int(self.branch[before]))
            side(after, dead, int(self.branch[after]))
        else:
            b = int(self.branch[i])
            ends = [self._phi(j) for j in (before, after)]
            if self.exact == {} and i in (0, n - 1):     # the turn's seam: 0 and 360 - GRID
                ends = [self.phi[i] - GRID, self.phi[i] + GRID]
            lo, hi = sorted(ends)
            value, x = golden(lambda p: self._signed(p, b, i), mpmath.mpf(lo), mpmath.mpf(hi),
                              maximum)
            out.append((float(x) % 360.0, float(value)))
        return out

    def _phi(self, j):
        return self.exact.get(j, self.phi[j])

    def _signed(self, phi, branch, i):
        v = self.model.output_mp(phi, branch)
        if self.model.angular:
            v += 360 * round((self.values[i] - float(v)) / 360.0)
        return v


def brute_circuits(model, branch):
    """[(interval or None, Path_)] of the linkage on `branch`."""
    intervals = model.intervals()
    if intervals is None:
        return [(None, Path_(model, None, branch))]
    return [(interval, Path_(model, interval, branch)) for interval in intervals]


# == the check ==================================================================================

def check(kind, dims, branch, report=None):
    """analyse(Linkage(kind, **dims), branch) against brute force; returns the worst
    differences {range, swing, phi} for the report."""
    model = Model(kind, dims)
    circuits = brute_circuits(model, branch)
    analysis = linkage.analyse(linkage.Linkage(kind, **dims), branch)
    where = (kind, dims, branch)
    got = getattr(analysis, "circuits", ()) or (analysis,)   # built without circuits: one
    assert len(got) == len(circuits), (where, [c.crank_range for c in got], circuits)
    # the top-level keys are circuit 1's
    assert analysis.output_min == got[0].output_min and analysis.output_max == got[0].output_max
    assert analysis.forward_stroke == got[0].forward_stroke
    assert analysis.mu_min == got[0].mu_min and analysis.mu_max == got[0].mu_max
    worst = {"range": 0.0, "swing": 0.0, "phi": 0.0}
    for circuit, (interval, path) in zip(got, circuits):
        if interval is None:
            assert circuit.crank_range is None and analysis.crank_range is None, where
        else:
            (lo, hi), = circuit.crank_range
            assert abs(wrapped(lo - float(interval[0]))) <= 1e-9, (where, lo, interval)
            assert abs(wrapped(hi - float(interval[1]))) <= 1e-9, (where, hi, interval)
        if path.turns:
            assert circuit.output_min is None and circuit.output_max is None, (where, circuit)
            continue
        assert circuit.output_min is not None and circuit.output_max is not None, (where, circuit)
        tol = TOLERANCE * path.scale()
        low, low_phi, low_tie = path.extreme(False)
        high, high_phi, high_tie = path.extreme(True)
        got_low, got_high = circuit.output_min.value, circuit.output_max.value
        diff = (wrapped if model.angular else (lambda x: x))
        d_low, d_high = abs(diff(got_low - low)), abs(diff(got_high - high))
        d_swing = abs((got_high - got_low) - (high - low))
        assert d_low <= tol and d_high <= tol, (where, circuit, (low, low_phi), (high, high_phi))
        assert d_swing <= tol, (where, circuit, high - low)
        worst["range"] = max(worst["range"], d_low / path.scale(), d_high / path.scale())
        worst["swing"] = max(worst["swing"], d_swing / path.scale())
        if not low_tie:
            d = abs(wrapped(circuit.output_min.phi - low_phi))
            assert d <= PHI_TOLERANCE, (where, circuit.output_min, low_phi)
            worst["phi"] = max(worst["phi"], d)
        if not high_tie:
            d = abs(wrapped(circuit.output_max.phi - high_phi))
            assert d <= PHI_TOLERANCE, (where, circuit.output_max, high_phi)
            worst["phi"] = max(worst["phi"], d)
        if interval is None and not (low_tie or high_tie):
            forward = (high_phi - low_phi) % 360.0
            back = 360.0 - forward
            assert abs(circuit.forward_stroke - forward) <= 1e-5, (where, circuit, forward)
            assert circuit.time_ratio == pytest.approx(max(forward, back) / min(forward, back),
                                                       rel=1e-6), where
            assert circuit.time_ratio >= 1.0
            assert circuit.time_ratio_review == pytest.approx(forward / back, rel=1e-6), where
            if abs(forward - back) > 1e-5:
                assert circuit.slower_stroke == ("forward" if forward > back else "return"), where
        elif interval is not None:
            assert circuit.time_ratio is None and circuit.forward_stroke is None, where
        if kind == "plane":
            check_mu(model, circuit, interval, where)
    return worst


def check_mu(model, circuit, interval, where):
    """The plane four-bar's mu depends on phi alone (eq. (1)), extreme at phi = 0 and 180 and at
    the dead centres (0 or 180 there): mu_min, mu_max and mu_worst against those, and the
    angle of a flat extreme (0 or 180) exact."""
    if interval is None:
        phis = [mpmath.mpf(0), mpmath.mpf(180)]
    else:
        lo, hi = interval
        phis = [lo, hi] + [mpmath.mpf(p) for p in (0, 180, 360, 540) if lo < p < hi]
    values = [(float(model.mu(p)), float(p) % 360.0) for p in phis]
    low, high = min(values), max(values)
    assert abs(circuit.mu_min.value - low[0]) <= 1e-9, (where, circuit.mu_min, values)
    assert abs(circuit.mu_max.value - high[0]) <= 1e-9, (where, circuit.mu_max, values)
    worst = max(abs(low[0] - 90.0), abs(high[0] - 90.0))
    assert abs(abs(circuit.mu_worst.value - 90.0) - worst) <= 1e-9, (where, circuit.mu_worst)
    for got, (value, _) in ((circuit.mu_min, low), (circuit.mu_max, high)):
        flat = [p for v, p in values if abs(v - value) <= 1e-9]
        if all(p in (0.0, 180.0) for p in flat):       # an interior (flat) extreme, not a dead centre
            assert got.phi in (0.0, 180.0), (where, got)


# == the linkages ===============================================================================

def plane_class(a, b, c, d):
    """The class the tests must cover: Grashof's type, the Grashof double-rocker (two circuits)
    and the non-Grashof one apart."""
    s, p, q, l = sorted((a, b, c, d))
    if s + l > p + q:
        return "non-grashof"
    shortest = min("abcd", key=dict(zip("abcd", (a, b, c, d))).__getitem__)
    return {"a": "double-crank", "b": "crank-rocker", "c": "two-circuit", "d": "rocker-crank"}[
        shortest]


def slider_class(b, c, e):
    if b + abs(e) < c:
        return "crank-slider"
    return "two-circuit" if b - abs(e) > c else "rocker-slider"


def drawn(seed, per_class, both_branches):
    """(kind, dims, branch): per_class linkages of each class, uniform lengths in (0.1, 10) (the
    slider's offset in (-5, 5)), the branch drawn, or both."""
    rng = random.Random(seed)
    wanted = {("plane", k): per_class for k in ("crank-rocker", "double-crank", "rocker-crank",
                                               "two-circuit", "non-grashof")}
    wanted.update({("slider", k): per_class for k in ("crank-slider", "rocker-slider",
                                                     "two-circuit")})
    out = []
    while any(wanted.values()):
        if rng.random() < 0.5:
            dims = {k: rng.uniform(0.1, 10.0) for k in "abcd"}
            key = ("plane", plane_class(*dims.values()))
        else:
            dims = dict(b=rng.uniform(0.1, 10.0), c=rng.uniform(0.1, 10.0),
                        e=rng.uniform(-5.0, 5.0))
            key = ("slider", slider_class(*dims.values()))
        if wanted[key] == 0 or Model(key[0], dims).intervals() == []:
            continue                                  # enough of its class, or no linkage
        wanted[key] -= 1
        branches = (1, 2) if both_branches else (rng.choice((1, 2)),)
        out += [(key[0], dims, branch, key[1]) for branch in branches]
    return out


DEFAULT = drawn("analyse-brute", 8, False)[:60]       # 8 classes, 60 linkages
# 40 linkages, both branches (the full run's; --quick leaves the module out); LINKAGE_LONG=1: 152,
# the number the full run had until 2026-11-28 (12 s of CPU)
SLOW = drawn("analyse-brute-slow", 19 if os.environ.get("LINKAGE_LONG") else 5, True)


def test_analyse_against_brute_force():
    worst = {"range": 0.0, "swing": 0.0, "phi": 0.0}
    classes = set()
    for kind, dims, branch, kind_class in DEFAULT:
        found = check(kind, dims, branch)
        classes.add((kind, kind_class))
        worst = {k: max(v, found[k]) for k, v in worst.items()}
    assert len(classes) == 8, classes
    print(f"\n{len(DEFAULT)} linkages: worst differences {worst}")


@pytest.mark.parametrize("kind, dims, branch, kind_class", SLOW,
                         ids=[f"{k}-{c}-{i // 2}-b{b}" for i, (k, _, b, c) in enumerate(SLOW)])
def test_analyse_against_brute_force_slow(kind, dims, branch, kind_class):
    check(kind, dims, branch)


# == the cases ==========================================================================

def test_an_extreme_beside_a_dead_centre_on_the_return_branch():
    """Issue 34: a = 0.47, b = 4.22, c = 0.75, d = 3.04 on branch 2 was given 25.20516802 (the
    dead centre's output) for its greatest output; the return branch reaches 25.538522 at
    phi = 22.190918, 0.3 degree before the dead centre at 22.4866: swing 51.077, not 50.744."""
    dims = dict(a=0.47, b=4.22, c=0.75, d=3.04)
    model = Model("plane", dims)
    (interval, path), = brute_circuits(model, 2)
    high, high_phi, _ = path.extreme(True)
    assert high == pytest.approx(25.538522, abs=1e-6) and high_phi == pytest.approx(22.190918,
                                                                                   abs=1e-6)
    analysis = linkage.analyse(linkage.Linkage("plane", **dims), 2)
    assert abs(analysis.output_max.value - high) <= TOLERANCE
    assert abs(analysis.output_max.phi - high_phi) <= PHI_TOLERANCE
    low, _, _ = path.extreme(False)
    assert abs((analysis.output_max.value - analysis.output_min.value) - (high - low)) <= TOLERANCE
    check("plane", dims, 2)
    check("plane", dims, 1)


def test_an_extreme_beside_a_dead_centre_found_by_the_slow_run():
    """One of the slow run's non-Grashof double-rockers: on branch 1 the least output,
    -132.905078 at phi = 230.601081, 0.125 degree from the dead centre at 230.476389, was given
    as the dead centre's -132.786660."""
    dims = dict(a=0.6960959151627366, b=8.974953816263472, c=0.6375931579288637,
                d=8.79564725071887)
    (interval, path), = brute_circuits(Model("plane", dims), 1)
    low, low_phi, _ = path.extreme(False)
    assert low == pytest.approx(-132.905078, abs=1e-6) and low_phi == pytest.approx(230.601081,
                                                                                    abs=1e-6)
    assert float(interval[0]) == pytest.approx(230.476389, abs=1e-6)
    check("plane", dims, 1)
    check("plane", dims, 2)


@pytest.mark.parametrize("kind, dims, swing", [
    ("plane", dict(a=3, b=2.5, c=1, d=3.2), 40.889),
    ("slider", dict(b=3, c=2, e=0.5), 4.109),
])
def test_a_linkage_with_two_circuits_is_analysed_a_circuit_at_a_time(kind, dims, swing):
    """Issue 34: one output range spanning both circuits (304.48 degrees, 9.95) was given; each
    circuit swings 40.889 degrees (4.109)."""
    model = Model(kind, dims)
    circuits = brute_circuits(model, 1)
    assert len(circuits) == 2
    analysis = linkage.analyse(linkage.Linkage(kind, **dims), 1)
    assert len(analysis.circuits) == 2
    for circuit, (interval, path) in zip(analysis.circuits, circuits):
        low, _, _ = path.extreme(False)
        high, _, _ = path.extreme(True)
        assert high - low == pytest.approx(swing, abs=1e-3)
        assert abs((circuit.output_max.value - circuit.output_min.value) - (high - low)) <= 1e-9
    top = analysis.output_max.value - analysis.output_min.value
    assert top == pytest.approx(swing, abs=1e-3)
    lines = linkage.analysis_lines(analysis)
    assert "circuits = 2" in lines
    assert any(line.startswith("circuit_2.swing = ") for line in lines)
    check(kind, dims, 1)
    check(kind, dims, 2)


def test_the_skew_scenes_worst_transmission_angle():
    """Issue 34: for the skew four-bar a = 4, b = 1.5, c = 3, d = 3, f = 1, ksi = 40 the
    transmission angle furthest from 90 degrees is mu = 141.6 at phi = 202.4 (51.6 from 90), not
    mu_min = 50.1: against the engine's mu at every 0.01 degree (Linkage.transmission), refined
    every 1e-6 degree about the worst. (Before issue 30 decided the skew kinds' mu by the forces,
    coupler-skew-four-bar.toml's linkage was this case; its mu_min is now the worst.)"""
    link = linkage.Linkage("skew", a=4, b=1.5, c=3, d=3, f=1, ksi=40)
    analysis = linkage.analyse(link, 1)
    phis = [0.01 * i for i in range(36000)]
    mus = link.transmission(phis, 1)
    i = max(range(len(phis)), key=lambda j: abs(mus[j] - 90.0))
    fine = [phis[i] + 1e-6 * k for k in range(-10000, 10001)]
    fine_mus = link.transmission(fine, 1)
    j = max(range(len(fine)), key=lambda k: abs(fine_mus[k] - 90.0))
    worst, at = fine_mus[j], fine[j]
    assert worst == pytest.approx(141.6, abs=0.1) and at == pytest.approx(202.4, abs=0.05)
    got = analysis.mu_worst
    assert abs(got.value - worst) <= 1e-9 and abs(got.phi - at) <= 1e-4, (got, worst, at)
    assert got != analysis.mu_min and analysis.mu_min.value == pytest.approx(50.1, abs=0.05)
    values = dict(line.split(" = ", 1) for line in linkage.analysis_lines(analysis))
    assert float(values["mu_worst"]) == pytest.approx(worst, abs=1e-7)
    assert float(values["mu_worst_deviation"]) == pytest.approx(worst - 90.0, abs=1e-7)
    assert float(values["mu_worst_at"]) == pytest.approx(at, abs=1e-4)


def test_the_time_ratio_is_the_slower_stroke_over_the_faster():
    """The skew scene's output rises while the crank turns 173.5 degrees and falls back in
    186.5: time ratio 1.0745 with the return the slower (the review's eq. (5), forward over
    return, 0.9307, kept as time_ratio_review); the strokes from the engine's outputs sampled
    every 0.01 degree."""
    scene = tomllib.loads((Path(linkage.__file__).parent / "data" / "scenes"
                           / "coupler-skew-four-bar.toml").read_text(encoding="utf-8"))
    link = linkage.Linkage(scene["kind"], **scene["dimensions"])
    phis = [0.01 * i for i in range(36000)]
    psi = numpy.unwrap(numpy.array([m.output for m in link.sweep(phis, 1, 0)]), period=360.0)
    forward = (phis[int(numpy.argmax(psi))] - phis[int(numpy.argmin(psi))]) % 360.0
    back = 360.0 - forward
    assert back > forward
    values = dict(line.split(" = ", 1) for line in linkage.analysis_lines(linkage.analyse(link)))
    assert float(values["time_ratio"]) == pytest.approx(back / forward, abs=2e-4)
    assert values["slower_stroke"] == "return"
    assert float(values["time_ratio_review"]) == pytest.approx(forward / back, abs=2e-4)


@pytest.mark.parametrize("kind, dims, branch, which, phi", [
    # formerly 1.811127163e-06
    ("plane", dict(a=0.47, b=4.22, c=0.75, d=3.04), 2, "mu_min", 0.0),
    # formerly 359.99999999998704, 179.9999999998424, 180.00000000049863, 3.412310434214305e-10
    ("plane", dict(a=4.008028898209531, b=5.082824894101982, c=0.3307582795319148,
                   d=1.1311763488888926), 2, "mu_min", 0.0),
    ("plane", dict(a=5.654342145036684, b=3.1013905291742563, c=8.344754444015251,
                   d=2.0506951191423513), 2, "mu_max", 180.0),
    ("plane", dict(a=8.390555758973122, b=5.5948713054037365, c=8.76515150094124,
                   d=7.0060849666151235), 2, "mu_max", 180.0),
    ("plane", dict(a=0.8901659151423407, b=9.673926332663036, c=6.140823464730407,
                   d=2.671976405398228), 2, "mu_min", 0.0),
    # formerly 89.99999999984249, 90.00000000005186
    ("slider", dict(b=8.02030105187808, c=8.90869172916406, e=2.985018415937625), 2, "mu_min",
     90.0),
    ("slider", dict(b=6.164106367952446, c=3.814876044758746, e=4.295043679355203), 1,
     "mu_min", 90.0),
])
def test_the_angle_of_a_flat_transmission_extreme_is_rounded(kind, dims, branch, which, phi):
    """The plane four-bar's mu depends on phi through cos phi alone (eq. (1)), the slider's
    through sin phi (the rod's slope): inside the crank's range their extremes are at phi = 0 or
    180 (90 or 270) exactly, where the old code gave angles a few 1e-10 off (found by sampling
    random linkages: 166 of 400)."""
    analysis = linkage.analyse(linkage.Linkage(kind, **dims), branch)
    got = getattr(analysis, which)
    assert got.phi == phi, got
    if kind == "plane":
        assert abs(got.value - float(Model(kind, dims).mu(phi))) <= 1e-9, got
    check(kind, dims, branch)
