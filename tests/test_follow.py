"""Change points and the followed motion: Linkage.sweep(phis, "follow", start=1|2),
`run ... --branch follow`, and velocity and acceleration at and near a change point.

A change point is where the discriminant has a double zero in phi and the two branches cross with
finite velocity (a + b = c + d and the like); the listing's labels 1 and 2 (the sign of dE/dpsi)
swap there, so a fixed branch jumps from one assembly to the other. The followed motion keeps to
the assembly it started in. Expected values come from the 50-digit reference
(tests/support/engine_reference.py, which solves the closure from the geometry and takes a change
point's limits by solving just past it), from closed forms, or from the engine's fixed
branches where only the choice of branch is under test.
"""

from __future__ import annotations

import math
import signal
import subprocess
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import assume, given, settings, strategies as st

import linkage as engine
from support import engine_harness as harness
from support import basic_runner
from support.program import PROGRAM

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

ROOT = Path(__file__).resolve().parent.parent
SLIDERS = ("slider", "skew-slider")
GRASHOF_BOUNDARY = dict(a=5.0, b=2.0, c=4.0, d=3.0)        # a + b = c + d: change point at 180
HALF_DEGREE = engine.evenly_spaced_angles(0.0, 360.0, 0.5)


def wrap(d):
    return (d + 180.0) % 360.0 - 180.0


def step_of(kind, m0, m1):
    """The output's change from m0 to m1: radians (wrapped) or length."""
    if kind in SLIDERS:
        return m1.output - m0.output
    return math.radians(wrap(m1.output - m0.output))


# -- the change point's derivatives: within 1e-9 at every distance ------------------------------

OFFSETS = [0.0] + [s * 10.0 ** -k for k in range(13, 5, -1) for s in (1, -1)]
CHANGE_POINTS = [("plane", GRASHOF_BOUNDARY, 180.0),
                 ("plane", dict(a=4.0, b=2.0, c=3.0, d=5.0), 0.0),
                 ("slider", dict(b=2.0, c=2.0, e=0.0), 90.0),
                 ("slider", dict(b=2.0, c=3.0, e=1.0), -90.0),
                 ("spherical", dict(a=70.0, b=30.0, c=60.0, d=40.0), 180.0),
                 ("skew-slider", dict(a=1.0, b=3.0, c=2.0, f=0.0, ksi=60.0), 0.0)]


@pytest.mark.parametrize("kind,dims,phi0", CHANGE_POINTS,
                         ids=[f"{k}-{phi0:g}" for k, _, phi0 in CHANGE_POINTS])
def test_derivatives_at_every_distance_from_a_change_point(kind, dims, phi0):
    """Velocity and acceleration within 1e-9 of the 50-digit reference (absolute below 1,
    relative above) from 1e-6 degree down to the change point itself, where both are the limits
    of the listing's branch from above."""
    link = engine.Linkage(kind, **dims)
    worst = 0.0
    for offset in OFFSETS:
        phi = phi0 + offset
        ref = harness.ref(kind, dims, phi)
        for branch in (1, 2):
            m, r = link.motion(phi, branch), ref[branch]
            want = "change-point" if offset == 0.0 else "assembled"
            assert m.status == r.status == want, (phi, branch, m, r.status)
            assert harness.output_error(kind, dims, m.output, r.output) <= 1e-12
            for got, exact in ((m.velocity, r.velocity), (m.acceleration, r.acceleration)):
                error = harness.ratio_error(got, exact)
                worst = max(worst, error)
                assert error <= 1e-9, (phi, branch, m, r)
    print(f"{kind} {dims} at {phi0}: worst velocity/acceleration error {worst:.1e}")


def test_the_issues_two_examples_against_closed_forms():
    """b = c, e = 0: the roots are x = 0 and x = 2b cos phi, so the second's acceleration at
    90 + delta is 2b sin(delta) (6.9e-15 at the double 90.0000000000001, where 50 digits gave
    9.8e-07). 5-2-4-3 at 180: each branch is symmetric about phi = 180 (the mirror image), so the
    accelerations at 180 are 0 and nearby about -1.4e-16 a 1e-13 degree (was +-3.96e-06, and
    branch 1's of the wrong sign)."""
    slider = engine.Linkage("slider", b=2, c=2, e=0)
    phi = 90.0000000000001
    m = slider.motion(phi, 2)
    exact = 4.0 * math.sin(math.radians(phi - 90.0))
    assert m.output == pytest.approx(-exact, rel=1e-12) and m.velocity == pytest.approx(-4.0)
    assert abs(m.acceleration - exact) <= 1e-20
    assert max(abs(v) for v in slider.motion(phi, 1)[1:4]) <= 1e-30      # x = 0 exactly
    plane = engine.Linkage("plane", **GRASHOF_BOUNDARY)
    for branch in (1, 2):
        at = plane.motion(180.0, branch)
        assert at.status == engine.CHANGE_POINT and at.acceleration == 0.0
        near = plane.motion(180.0000000000001, branch)
        assert -3e-16 < near.acceleration < 0.0, near


def test_a_change_point_is_told_from_a_dead_centre():
    """At a dead centre the velocity is infinite (no values); at an isolated position (the
    discriminant's double zero a maximum) no branch goes on (no values); at a change point
    both do."""
    dead = engine.Linkage("plane", a=3, b=4, c=2, d=3).motion(90.0)
    isolated = engine.Linkage("skew-slider", a=1, b=3, c=2, f=0, ksi=30).motion(0.0)
    crossing = engine.Linkage("skew-slider", a=1, b=3, c=2, f=0, ksi=60).motion(0.0)
    assert dead.status == isolated.status == engine.DEAD_CENTRE
    assert dead.velocity is None and isolated.velocity is None
    assert crossing.status == engine.CHANGE_POINT and crossing.velocity is not None


# -- following the motion -----------------------------------------------------------------------

def test_the_grashof_boundary_linkage_is_followed_through_180():
    """a=5 b=2 c=4 d=3, 0 to 360 by 0.5: branch 1's velocity jumps from -0.236 to 0.807 at 180;
    the followed motion stays smooth and is, past 180, the reference's branch 2."""
    link = engine.Linkage("plane", **GRASHOF_BOUNDARY)
    fixed = link.sweep(HALF_DEGREE, 1)
    followed = link.sweep(HALF_DEGREE, engine.FOLLOW, start=1)
    i = HALF_DEGREE.index(180.0)
    assert fixed[i - 1].velocity == pytest.approx(-0.2359, abs=1e-4)
    assert fixed[i + 1].velocity == pytest.approx(0.8074, abs=1e-4)
    assert followed[:i] == fixed[:i]
    assert followed[i].status == engine.CHANGE_POINT
    assert sum(f != x for f, x in zip(followed, fixed)) == 361
    assert max(abs(f.velocity - x.velocity) for f, x in zip(followed, fixed)) > 1.0
    h = math.radians(0.5)
    for m0, m1 in zip(followed, followed[1:]):
        bound = max(abs(m0.acceleration), abs(m1.acceleration)) * h + 1e-6
        assert abs(m1.velocity - m0.velocity) <= bound, (m0, m1)
    for phi in (180.0, 180.5, 181.0, 270.0, 359.5):
        m = followed[HALF_DEGREE.index(phi)]
        r = harness.ref("plane", GRASHOF_BOUNDARY, phi)[2]
        assert harness.output_error("plane", GRASHOF_BOUNDARY, m.output, r.output) <= 1e-12
        assert harness.ratio_error(m.velocity, r.velocity) <= 1e-12, (phi, m, r)
        assert harness.ratio_error(m.acceleration, r.acceleration) <= 1e-12, (phi, m, r)
    backwards = link.sweep(HALF_DEGREE[::-1], engine.FOLLOW, start=2)
    assert [m.velocity for m in backwards] == [m.velocity for m in followed[::-1]]


@pytest.mark.parametrize("start", (1, 2))
def test_a_crank_rocker_is_its_fixed_branch(start):
    link = engine.Linkage("plane", a=6, b=2, c=7, d=9)
    angles = engine.evenly_spaced_angles(-400.0, 400.0, 0.5)
    assert link.sweep(angles, engine.FOLLOW, start=start) == link.sweep(angles, start)
    assert (link.sweep(angles[::-1], engine.FOLLOW, start=start)
            == link.sweep(angles[::-1], start))


def test_a_dead_centre_ends_the_motion():
    """a=3 b=4 c=2 d=3: dead centre at phi = 90 (the linkage does not assemble beyond). On the
    grid the point itself is the dead centre, then STOPPED; stepped over, the first angle past
    it is STOPPED. Before it, the followed motion is the fixed branch it started in."""
    link = engine.Linkage("plane", a=3, b=4, c=2, d=3)
    angles = engine.evenly_spaced_angles(10.0, 120.0, 0.5)
    i = angles.index(90.0)
    for start in (1, 2):
        followed = link.sweep(angles, engine.FOLLOW, start=start)
        assert followed[:i] == link.sweep(angles[:i], start)
        assert followed[i] == link.motion(90.0, start)
        assert followed[i].status == engine.DEAD_CENTRE
        assert all(m == engine.Motion(m.phi, None, None, None, engine.STOPPED)
                   for m in followed[i + 1:])
    coarse = link.sweep([70.0, 77.0, 84.0, 91.0, 98.0], engine.FOLLOW)
    assert [m.status for m in coarse] == [engine.ASSEMBLED] * 3 + [engine.STOPPED] * 2


def test_a_gap_between_two_angles_ends_the_motion():
    """The double rocker a=5 b=4 c=2 d=3 assembles for |phi| <= 66.42 only: from 60 to 300
    (= -60) the crank would have to pass the dead centre, so the motion ends, though both
    angles assemble; from 60 down to -60 it passes the change point at 0 and goes on."""
    link = engine.Linkage("plane", a=5, b=4, c=2, d=3)
    assert link.motion(300.0).status == engine.ASSEMBLED
    assert [m.status for m in link.sweep([60.0, 300.0], engine.FOLLOW)] == [
        engine.ASSEMBLED, engine.STOPPED]
    down = link.sweep([60.0, -60.0], engine.FOLLOW)
    assert [m.status for m in down] == [engine.ASSEMBLED] * 2
    smooth = link.sweep(engine.evenly_spaced_angles(60.0, -60.0, -0.01), engine.FOLLOW)
    assert down[1] == smooth[-1]


@pytest.mark.parametrize("dims,start,step", [
    (dict(a=1.0, b=2.0, c=1.0, d=2.0), 1.0, 5.0),      # a parallelogram: crossing at 180
    (dict(a=2.00001, b=1.0, c=1.0, d=2.0), -4.0, 30.0),  # nearly a kite: close, not crossing
    (GRASHOF_BOUNDARY, 1.0, -15.0),
])
def test_long_steps_through_crossings_and_near_misses(dims, start, step):
    """Found by hypothesis: a step over a crossing that lands just past it, and a step over two
    branches passing within 1e-3 of each other, which from afar look alike. The followed motion
    at the long steps' angles is the one followed by steps 100 times shorter."""
    link = engine.Linkage("plane", **dims)
    count = round(360 / abs(step))
    long = link.sweep([start + i * step for i in range(count + 1)], engine.FOLLOW)
    short = link.sweep([start + j * step / 100 for j in range(100 * count + 1)], engine.FOLLOW)
    for x, y in zip(long, short[::100]):
        assert x.status == y.status, (x, y)
        if x.output is not None:
            assert step_of("plane", x, y) == pytest.approx(0, abs=1e-9), (x, y)
            assert x.velocity == pytest.approx(y.velocity, rel=1e-9, abs=1e-9), (x, y)


def test_a_motion_from_just_past_a_dead_centre_keeps_its_branch():
    """b = c = e = 1 assembles for 0 <= phi <= 180, dead centres at both ends (the labels never
    swap in between). From 2.2e-16 degree, where the roots are 5.6e-9 apart with velocities of
    +-3.6e8, 5-degree steps are the fixed branch up to the dead centre at 180: the roots meet at
    a dead centre as they do at a crossing, but there the velocity cannot choose (found by
    hypothesis)."""
    link = engine.Linkage("slider", b=1, c=1, e=1)
    angles = [2.220446049250313e-16 + 5.0 * i for i in range(73)]
    followed = link.sweep(angles, engine.FOLLOW, start=1)
    fixed = link.sweep(angles, 1)
    assert followed[:37] == fixed[:37] and followed[36].status == engine.DEAD_CENTRE
    assert {m.status for m in followed[37:]} == {engine.STOPPED}


def test_the_motion_starts_where_the_linkage_first_assembles():
    """b=1 c=1 e=1.5 assembles for 30 <= phi <= 150, dead centres at both ends: before the
    motion starts each angle has its own status (the dead centre at 30 too), the motion ends at
    the one at 150."""
    link = engine.Linkage("slider", b=1, c=1, e=1.5)
    angles = engine.evenly_spaced_angles(0.0, 180.0, 1.0)
    followed = link.sweep(angles, engine.FOLLOW, start=2)
    fixed = link.sweep(angles, 2)
    assert all(m.status == engine.NOT_ASSEMBLED for m in followed[:30])
    assert followed[30] == fixed[30] and followed[30].status == engine.DEAD_CENTRE
    assert followed[31:150] == fixed[31:150]
    assert followed[150] == fixed[150] and followed[150].status == engine.DEAD_CENTRE
    assert {m.status for m in followed[151:]} == {engine.STOPPED}


def test_what_is_asked_and_bad_arguments():
    link = engine.Linkage("plane", **GRASHOF_BOUNDARY)
    full = link.sweep(HALF_DEGREE, engine.FOLLOW)
    for level in (0, 1):
        part = link.sweep(HALF_DEGREE, engine.FOLLOW, level)
        assert [m.output for m in part] == [m.output for m in full]
        assert all(m.acceleration is None and (m.velocity is None) == (level == 0)
                   for m in part)
    with pytest.raises(ValueError, match="start"):
        link.sweep([0.0], engine.FOLLOW, start=3)
    with pytest.raises(ValueError, match="follow"):
        link.sweep([0.0], 1, start=2)
    with pytest.raises(ValueError, match="follow"):
        link.sweep([0.0], "folow")


# -- hypothesis ---------------------------------------------------------------------------------

length = st.floats(0.2, 10.0)


@st.composite
def generic_linkages(draw):
    kind = draw(st.sampled_from(("plane", "spherical", "slider")))
    if kind == "plane":
        dims = {k: draw(length) for k in "abcd"}
    elif kind == "spherical":
        dims = {k: draw(st.floats(2.0, 178.0)) for k in "abcd"}
    else:
        dims = dict(b=draw(length), c=draw(length), e=draw(st.floats(-5.0, 5.0)))
    return kind, dims


def near_a_change_point(kind, dims, within=1e-9):
    """Grashof's boundary to within `within` of the size, not exactly, in the binary values
    (plane and spherical: a + b = c + d and the other two pairings; slider: c = b - e or
    b + e). Exact fractions: 0.5 + 1.9 and 0.4 + 2.0 round to the same double, yet differ."""
    if kind == "slider":
        b, c, e = (Fraction(dims[k]) for k in "bce")
        sums = [(c, b - e), (c, b + e)]
    else:
        a, b, c, d = (Fraction(dims[k]) for k in "abcd")
        sums = [(a + b, c + d), (a + c, b + d), (a + d, b + c)]
    size = max(abs(v) for v in dims.values())
    return any(0 < abs(x - y) <= within * size for x, y in sums)


def closest_approach(kind, link, lo, hi):
    """(How close the two branches come from lo to hi, whether the linkage assembles at every
    angle there), as far as 200 samples tell, zooming eight times onto the sample where the
    branches are closest: they meet there at a crossing, and a gap where the linkage does not
    assemble opens there (it may be 1e-6 degree wide)."""
    closest = math.inf
    for _ in range(9):
        angles = [lo + (hi - lo) * k / 200 for k in range(201)]
        pairs = list(zip(link.sweep(angles, 1, 0), link.sweep(angles, 2, 0)))   # motion's, each
        if any(m.status in (engine.NOT_ASSEMBLED, engine.INDETERMINATE)
               for pair in pairs for m in pair):
            return closest, False
        gaps = [abs(step_of(kind, m1, m2)) for m1, m2 in pairs]
        k = min(range(201), key=gaps.__getitem__)
        closest = min(closest, gaps[k])
        lo, hi = angles[max(k - 1, 0)], angles[min(k + 1, 200)]
    return closest, True


@given(generic_linkages(), st.floats(-360.0, 360.0), st.sampled_from((0.25, -0.25, 2.0)),
       st.sampled_from((1, 2)))
@settings(max_examples=150, deadline=None)
def test_the_followed_motion_changes_label_only_where_the_branches_meet(linkage, phi0, step,
                                                                       start):
    """From the first assembled angle on, the followed motion is, at each angle, one of the two
    fixed branches - `start` first; it changes label only between angles where the two branches
    meet (a change point: for random dimensions a rare exact equality such as b = c, e = 0,
    which hypothesis does find); and it ends only where, on the way to the next angle, the
    linkage does not assemble. After that, every angle is STOPPED."""
    kind, dims = linkage
    # a = b and c = d: the crank tip passes over the output pivot, where the output link is free
    # and the labels swap without the branches meeting (test_engine.output_link_held)
    assume(kind == "slider" or not (dims["a"] == dims["b"] and dims["c"] == dims["d"]))
    link = engine.Linkage(kind, **dims)
    angles = engine.evenly_spaced_angles(phi0, phi0 + 120.0 * math.copysign(1, step), step)
    followed = link.sweep(angles, engine.FOLLOW, start=start)
    fixed = {br: link.sweep(angles, br) for br in (1, 2)}
    label, started = start, False
    for i, f in enumerate(followed):
        if not started:
            assert f == fixed[start][i]
            started = f.status in (engine.ASSEMBLED, engine.CHANGE_POINT)
            continue
        if f.status == engine.STOPPED:
            assert not closest_approach(kind, link, angles[i - 1], angles[i])[1], f
            assert all(m.status == engine.STOPPED for m in followed[i:])
            return
        if f != fixed[label][i]:
            assert f == fixed[3 - label][i], (f, fixed[label][i])
            closest = closest_approach(kind, link, angles[i - 1], angles[i])[0]
            scale = harness.size(kind, dims) if kind in SLIDERS else 1.0     # length or radian
            assert closest <= 1e-6 * scale, (f, closest)
            label = 3 - label
        if f.status == engine.DEAD_CENTRE:
            assert all(m.status == engine.STOPPED for m in followed[i + 1:])
            return


@given(generic_linkages(), st.floats(-360.0, 360.0), st.sampled_from((5.0, -15.0, 30.0)),
       st.sampled_from((1, 2)), st.booleans())
@settings(max_examples=60, deadline=None)
def test_long_steps_follow_the_same_motion_as_short_ones(linkage, phi0, step, start, boundary):
    """From an angle where the linkage assembles, a sweep by 5 to 30 degrees gives, at its
    angles, what a sweep 20 times finer gives: the long steps are halved where they must be,
    and a dead centre between two angles is found. With `boundary`, a plane linkage on
    Grashof's boundary (quarters, a + b = c + d), whose change point the long steps jump.
    Linkages within rounding of a change point are left out: a + d = b + c typed as 0.5, 0.4,
    2, 1.9 misses it by 1e-16 in binary, which opens a gap 4e-6 degree wide where the branches
    meet; a long step that agrees with the smooth crossing passes it, the fine sweep lands in
    it and stops."""
    kind, dims = linkage
    assume(boundary or not near_a_change_point(kind, dims))
    if boundary:
        kind, d = "plane", dims.get("a", 3.0) + dims["b"] - dims["c"]
        dims = {k: round(4 * v) / 4 for k, v in
                dict(a=dims.get("a", 3.0), b=dims["b"], c=dims["c"], d=d).items()}
        dims["d"] = dims["a"] + dims["b"] - dims["c"]
        assume(dims["d"] > 0.1 and min(dims.values()) > 0.1)
    # (a = b, c = d: an angle exactly where the output link is free ends the motion, and the
    # fine sweep may land on it where the long one does not)
    assume(kind == "slider" or not (dims["a"] == dims["b"] and dims["c"] == dims["d"]))
    link = engine.Linkage(kind, **dims)
    assume(link.motion(phi0, start).status == engine.ASSEMBLED)
    count = round(360 / abs(step))
    coarse = [phi0 + i * step for i in range(count + 1)]
    # the fine sweep 20 times finer (0.25 to 1.5 degrees): 100 times cost 1.6 s more of CPU and
    # caught no mutation of _follow_step more (11 tried: 6 caught by both, 5 by neither)
    fine = [phi0 + j * step / 20 for j in range(20 * count + 1)]
    long = link.sweep(coarse, engine.FOLLOW, start=start)
    short = link.sweep(fine, engine.FOLLOW, start=start)[::20]
    for x, y in zip(long, short):
        assert x.status == y.status, (x, y)
        if x.output is not None:
            assert step_of(kind, x, y) == pytest.approx(0.0, abs=1e-9), (x, y)


@given(st.integers(1, 40), st.integers(1, 40), st.integers(1, 40), st.sampled_from((1, 2)),
       st.sampled_from((0.5, 0.1)))
@settings(max_examples=100, deadline=None)
def test_a_grashof_boundary_linkage_is_smooth_through_its_change_point(a, b, c, start, step):
    """a + b = c + d exactly (quarters): the branches cross at phi = 180 with finite velocities.
    The followed motion goes through with psi and psi' continuous - consecutive points' psi
    differ by what |psi'| bounds, psi' by what |psi''| bounds - and past 180 it is the other
    label's (the listing's labels swap at the change point)."""
    a, b, c = a / 4.0, b / 4.0, c / 4.0
    d = a + b - c
    assume(d > 0.1 and abs(c - d) < a + b - 0.3)       # assembles around 180; not folded
    link = engine.Linkage("plane", a=a, b=b, c=c, d=d)
    assert link.motion(180.0).status == engine.CHANGE_POINT
    angles = engine.evenly_spaced_angles(170.0, 190.0, step)
    fixed = {br: link.sweep(angles, br) for br in (1, 2)}
    assume(all(m.status != engine.NOT_ASSEMBLED for br in (1, 2) for m in fixed[br]))
    v1, v2 = (link.motion(180.0, br).velocity for br in (1, 2))
    assume(abs(v1 - v2) > 1e-3)                               # two distinct crossings
    followed = link.sweep(angles, engine.FOLLOW, start=start)
    i = angles.index(180.0)
    assert followed[:i] == fixed[start][:i]
    assert followed[i + 1:] == fixed[3 - start][i + 1:]
    h = math.radians(step)
    for m0, m1 in zip(followed, followed[1:]):
        vmax = max(abs(m0.velocity), abs(m1.velocity))
        amax = max(abs(m0.acceleration), abs(m1.acceleration))
        assert abs(step_of("plane", m0, m1)) <= vmax * h + amax * h * h + 1e-12, (m0, m1)
        assert abs(m1.velocity - m0.velocity) <= amax * h * 1.5 + 1e-3 * h, (m0, m1)


# -- the command line ---------------------------------------------------------------------------

def run(*args, cwd=None):
    return subprocess.run(PROGRAM + ["run", *args], capture_output=True, text=True, cwd=cwd)


PLANE_5243 = ["plane", "--b", "2", "--c", "4", "--d", "3", "--a", "5"]


def test_run_branch_follow_writes_the_followed_motion(tmp_path):
    done = run(*PLANE_5243, "--from", "0", "--to", "360", "--step", "0.5", "--branch", "follow",
               "--precision", "double", "--dir", str(tmp_path))
    assert done.returncode == 0 and "wrote ANG.DAT, VEL.DAT, ACC.DAT" in done.stderr
    followed = engine.Linkage("plane", **GRASHOF_BOUNDARY).sweep(HALF_DEGREE, engine.FOLLOW)
    for name, column in (("ANG.DAT", 1), ("VEL.DAT", 2), ("ACC.DAT", 3)):
        rows = basic_runner.read_dat((tmp_path / name).read_bytes())
        assert rows == [(m.phi, m[column]) for m in followed]
    again = run(*PLANE_5243, "--from", "0", "--to", "360", "--step", "0.5", "--branch", "follow",
                "--start-branch", "2", "--precision", "double", "--dir", str(tmp_path))
    assert again.returncode == 0
    vel = basic_runner.read_dat((tmp_path / "VEL.DAT").read_bytes())
    assert vel[0][1] == engine.Linkage("plane", **GRASHOF_BOUNDARY).motion(0.0, 2).velocity


def test_run_branch_follow_stops_at_a_dead_centre(tmp_path):
    done = run("plane", "--b", "4", "--c", "2", "--d", "3", "--a", "3", "--from", "80", "--to",
               "100", "--step", "5", "--branch", "follow", "--precision", "double",
               "--dir", str(tmp_path))
    assert done.returncode == 0
    assert [p for p, _ in basic_runner.read_dat((tmp_path / "ANG.DAT").read_bytes())] == [
        80.0, 85.0, 90.0]
    assert [p for p, _ in basic_runner.read_dat((tmp_path / "VEL.DAT").read_bytes())] == [
        80.0, 85.0]


@pytest.mark.parametrize("args,message", [
    (["--branch", "follow"], "--branch follow goes with --precision double"),
    (["--branch", "follow", "--precision", "basic"], "the original program has branches 1 and 2"),
    (["--branch", "1", "--start-branch", "2", "--precision", "double"],
     "--start-branch goes with --branch follow"),
    (["--branch", "follow", "--start-branch", "3", "--precision", "double"], "invalid choice"),
    (["--branch", "folow", "--precision", "double"], "invalid choice"),
])
def test_run_refuses_follow_where_it_has_no_meaning(tmp_path, args, message):
    done = run(*PLANE_5243, "--from", "0", "--to", "10", "--step", "5", *args,
               "--dir", str(tmp_path))
    assert done.returncode == 2 and message in done.stderr, done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "ANG.DAT").exists()


# -- scenes ---------------------------------------------------------------------------------------

SCENE = ROOT / "data" / "scenes" / "hard-follow-change-point.toml"


def test_the_follow_scene_writes_the_followed_motion(tmp_path):
    """branches = [1, "follow"]: one folder each; the followed series is Linkage.sweep's."""
    scene = engine.load_scene(str(SCENE))
    assert scene.branches == (1, engine.FOLLOW)
    series = engine.compute_scene(scene, str(tmp_path))
    assert [(s.name, s.branch) for s in series] == [("double-branch1", 1),
                                                    ("double-branchfollow", engine.FOLLOW)]
    assert [(s.name, s.branch) for s in engine.dat_series(str(tmp_path))] == [
        ("double-branch1", 1), ("double-branchfollow", engine.FOLLOW)]
    followed = engine.Linkage("plane", **GRASHOF_BOUNDARY).sweep(scene.angles(), engine.FOLLOW)
    vel = basic_runner.read_dat((tmp_path / "double-branchfollow" / "VEL.DAT").read_bytes())
    assert vel == [(m.phi, m.velocity) for m in followed]
    text = engine.text_figure(engine.scene_figure(scene, series))
    assert "follow (the motion followed from branch 1)" in text and "o followed" in text


@pytest.mark.parametrize("change,message", [
    (('precision = "double"', 'precision = "both"'), "\"follow\" is the accurate engine's"),
    (('precision = "double"', 'precision = "basic"'), "the original program has branches 1 and 2"),
    (('branches = [1, "follow"]', 'branches = ["folow"]'), "\"follow\" among them"),
    (('branches = [1, "follow"]', 'branches = [[1]]'), "\"follow\" among them"),
    (('[[panels]]\nquantities = ["displacement"]\n\n[[panels]]\nquantities = ["velocity"]',
      '[[panels]]\nquantities = ["mechanism"]'), "a mechanism scene draws one of the listing's"),
])
def test_a_scene_refuses_follow_where_it_has_no_meaning(tmp_path, change, message):
    text = SCENE.read_text()
    assert change[0] in text
    path = tmp_path / "s.toml"
    path.write_text(text.replace(*change))
    with pytest.raises(engine.SceneError, match="key 'branches'") as refused:
        engine.load_scene(str(path))
    assert message in str(refused.value)
    done = subprocess.run(PROGRAM + ["scene", str(path), "--dir", str(tmp_path)],
                          capture_output=True, text=True)
    assert done.returncode != 0 and message in done.stderr and "Traceback" not in done.stderr


def test_a_motion_that_never_agrees_with_its_neighbours_ends_its_halvings():
    """Lengths of 1e308 beside lengths of 1 leave the output angle to rounding (180 degrees
    everywhere, the velocity not zero): no step is smooth, and halving both halves of every
    step made 2^50 of them (a hang). The halvings between two angles are bounded; the sweep
    answers, every angle with a position (a hang guard of 60 s, not a speed limit)."""
    def hung(signum, frame):
        raise TimeoutError("the followed sweep hangs")
    previous = signal.signal(signal.SIGALRM, hung)
    signal.alarm(60)
    try:
        motions = engine.Linkage("plane", a=6, b=1.7e308, c=1.7e308, d=9).sweep(
            [10.0 * i for i in range(37)], engine.FOLLOW)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert len(motions) == 37 and all(m.status == "assembled" for m in motions)


# -- a long followed motion: the numpy path of the files (issue 35, item 2) ------------------------

DEAD_CENTRE_4324 = ["plane", "--a", "4", "--b", "3", "--c", "4", "--d", "2"]


def test_a_long_followed_motion_that_stops_is_written_where_numpy_takes_over(tmp_path):
    """Issue 35, item 2: a followed motion of 16,384 points or more (a full block: the files'
    numbers formatted by numpy) that stops at a dead centre ended in KeyError: 'stopped', as the
    numpy path knew every status but STOPPED. Now its files are Linkage.sweep's, the CSV's
    status column too (stopped included)."""
    assert engine.NUMBER_ROWS <= 36001
    done = run(*DEAD_CENTRE_4324, "--from", "0", "--to", "360", "--step", "0.01", "--branch",
               "follow", "--precision", "double", "--dir", str(tmp_path), "--csv",
               str(tmp_path / "out.csv"))
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    angles = [0.0 + i * 0.01 for i in range(36001)]
    followed = engine.Linkage("plane", a=4.0, b=3.0, c=4.0, d=2.0).sweep(angles, engine.FOLLOW)
    rows = (tmp_path / "out.csv").read_text().splitlines()[1:]
    assert [r.split(",")[4] for r in rows] == [m.status for m in followed]
    assert "stopped" in {m.status for m in followed}
    ang = basic_runner.read_dat((tmp_path / "ANG.DAT").read_bytes())
    assert ang == [(m.phi, m.output) for m in followed if m.output is not None]


def test_a_long_follow_scene_that_stops_is_written(tmp_path):
    """Issue 35, item 2, a scene: branches = ["follow"] on 36,001 angles with a dead centre."""
    path = tmp_path / "s.toml"
    path.write_text('title = "stops"\nmechanism = "plane"\n'
                    "dimensions = { a = 4, b = 3, c = 4, d = 2 }\n"
                    "input = { from = 0, to = 360, step = 0.01 }\n"
                    'branches = ["follow"]\nprecision = "double"\n\n'
                    '[[panels]]\nquantities = ["displacement"]\n')
    done = subprocess.run(PROGRAM + ["scene", str(path), "--dir", str(tmp_path / "out")],
                          capture_output=True, text=True)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    angles = [0.0 + i * 0.01 for i in range(36001)]
    followed = engine.Linkage("plane", a=4.0, b=3.0, c=4.0, d=2.0).sweep(angles, engine.FOLLOW)
    ang = basic_runner.read_dat((tmp_path / "out" / "ANG.DAT").read_bytes())
    assert ang == [(m.phi, m.output) for m in followed if m.output is not None]
