"""The coupler point and the transmission angle (Linkage.coupler, .transmission and their numpy
forms), checked against definitions written here, not against the engine's own formulas.

1. Geometry: along the motion the point keeps its distances (arcs on the sphere) from the crank
   pin A and the output pin P (B, or the slider C) that its definition implies, on the side v
   says, from joint_positions' joints; a linkage scaled by 2^-600 .. 2^600 moves its point
   scaled; at a dead centre the point stands (no velocity) and mu is 0 or 180.
2. Velocity and acceleration: positions solved here in mpmath at 40 digits from the joint frames
   of joint_positions' docstring (the closure |P(q) - A(phi)| = c, or A.B = cos c on the unit
   sphere, by findroot), the point built from its definition, differentiated by 7-point central
   differences in phi (radians).
3. pylinkage 1.3.0 as an outside implementation: its TrackerJoint (a point at `distance` and
   `angle` from the coupler's first joint, the angle from the direction to its second joint) on
   random plane four-bars and slider-cranks.
4. The transmission angle: the review's eq. (1) (plane four-bar, both branches), eq. (3)
   corrected (slider-crank), the spherical law of cosines, skew with f = ksi = 0 as plane, every
   kind (the skew ones above all) from the definition (dP/dq from differences of the mpmath
   positions), and the review's worked examples of eqs. (2a), (2b).
5. coupler_arrays and transmission_arrays against the scalar forms, on random linkages and at
   dead centres and change points.
6. branch="follow" through change points (fixed ones, random Grashof-boundary four-bars): the
   coupler curve and its velocity are continuous.
7. Refusals: each reason check_coupler_point gives.
"""

from __future__ import annotations

import functools
import math
import os
from pathlib import Path

import pytest
from hypothesis import assume, given, settings, strategies as st

import linkage as engine
from support.peers import Peer, need
from test_engine import linkages
from test_follow import CHANGE_POINTS
from test_pylinkage import condition, startable

mpmath, np = Peer("mpmath"), Peer("numpy")                     # imported at their first use
pl_builder, pl_errors = Peer("pylinkage.mechanism.builder"), Peer("pylinkage.exceptions")

KINDS = tuple(engine.LINKAGE_DIMENSIONS)
SLIDERS = ("slider", "skew-slider")
LINE_KINDS = ("skew", "skew-slider")          # only v = 0
DPS = 40
# Random linkages a kind for the two properties against 40-digit positions (velocity and
# acceleration, transmission), each at up to 4 angles: 16 in the default run (80 a property; the
# 150 drawn over all kinds before issue 36 gave the spherical four-bar 7 and 10); LINKAGE_LONG=1:
# 40 (200 a property).
MP_EXAMPLES = 40 if os.environ.get("LINKAGE_LONG") else 16


# -- small vector helpers (floats or mpf alike) ------------------------------------------------

def sub(p, q):
    return tuple(x - y for x, y in zip(p, q))


def add(*terms):
    """Sum of (coefficient, vector) pairs."""
    return tuple(sum(k * v[i] for k, v in terms) for i in range(3))


def dot(p, q):
    return sum(x * y for x, y in zip(p, q))


def cross(p, q):
    return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])


def norm(p):
    return math.sqrt(sum(float(x) ** 2 for x in p))


def size_of(kind, dims):
    """The linkage's size: its largest length (1, the sphere's radius, for the spherical)."""
    if kind == "spherical":
        return 1.0
    return max(abs(v) for k, v in dims.items() if k != "ksi")


def point_scale(kind, dims, u, v):
    """The size of the coupler point's numbers: the linkage's, or the point's reach from A."""
    return 1.0 if kind == "spherical" else max(size_of(kind, dims), math.hypot(u, v))


# -- random linkages and coupler points -------------------------------------------------------

@st.composite
def points_on(draw, kind, dims):
    """A coupler point (u, v): lengths up to twice the linkage's size, degrees on the sphere
    (beyond a turn, too), v = 0 on the skew kinds."""
    if kind == "spherical":
        u, v = draw(st.floats(-720.0, 720.0)), draw(st.floats(-360.0, 360.0))
    else:
        size = size_of(kind, dims)
        u, v = draw(st.floats(-2.0, 2.0)) * size, draw(st.floats(-2.0, 2.0)) * size
    return u, 0.0 if kind in LINE_KINDS else v


@st.composite
def linkages_with_points(draw, kinds=KINDS):
    kind, dims = draw(linkages(kinds))
    return kind, dims, draw(points_on(kind, dims))


def assembled_angles(link, start, branch, count=8):
    """The angles of start + 45 k (k < count) where the linkage is assembled on the branch."""
    phis = [start + 45.0 * k for k in range(count)]
    return [m.phi for m in link.sweep(phis, branch, 0) if m.status == engine.ASSEMBLED]


# -- 1. geometry ------------------------------------------------------------------------------

def geometry_problems(kind, dims, link, phi, branch, u, v, coupler):
    """What is wrong with one coupler position against joint_positions' pins."""
    pose = engine.joint_positions(link, phi, branch)
    a, p = pose.joints["A"], pose.joints["C" if kind in SLIDERS else "B"]
    q = coupler.position
    out = []
    if kind == "spherical":
        c, ur, vr = (math.radians(x) for x in (dims["c"], u, v))
        checks = [(norm(q) - 1.0, "|Q| = 1"),
                  (dot(q, a) - math.cos(ur) * math.cos(vr), "cos QA = cos u cos v"),
                  (dot(q, p) - math.cos(vr) * math.cos(c - ur), "cos QB = cos v cos(c - u)"),
                  (dot(cross(a, p), q) - math.sin(c) * math.sin(vr),
                   "det[A, B, Q] = sin c sin v (the side)")]
        tol = 1e-9
    else:
        c = dims["c"]
        scale = point_scale(kind, dims, u, v)
        checks = [(norm(sub(q, a)) - math.hypot(u, v), "|QA| = hypot(u, v)"),
                  (norm(sub(q, p)) - math.hypot(c - u, v), "|QP| = hypot(c - u, v)"),
                  ((dot(sub(p, a), sub(q, a)) - c * u) / scale, "(P - A).(Q - A) = c u"),
                  (norm(sub(cross(sub(p, a), sub(q, a)), (0.0, 0.0, c * v))) / scale,
                   "(P - A) x (Q - A) = c v z (the side)")]
        tol = 1e-9 * scale
    out += [f"{what}: off by {err!r}" for err, what in checks if not abs(err) <= tol]
    return out


@given(linkages_with_points(), st.floats(-360.0, 360.0), st.sampled_from((1, 2)))
@settings(max_examples=250)
def test_the_point_keeps_its_place_on_the_coupler(drawn, start, branch):
    """At every assembled angle (8 spread over a turn) the point is where (u, v) puts it:
    at the distances (arcs) from A and P its definition implies, on the side v says."""
    kind, dims, (u, v) = drawn
    link = engine.Linkage(kind, **dims)
    phis = assembled_angles(link, start, branch)
    assume(phis)
    for cm in link.coupler(phis, u, v, branch):
        assert cm.status == engine.ASSEMBLED and cm.position is not None
        found = geometry_problems(kind, dims, link, cm.phi, branch, u, v, cm)
        assert not found, f"{kind} {dims} (u, v) = ({u!r}, {v!r}) phi={cm.phi!r} " \
                          f"branch {branch}: {found}"


def test_the_point_is_none_where_the_linkage_does_not_assemble():
    """No position, no point: a four-bar whose crank and links cannot reach across its frame."""
    link = engine.Linkage("plane", a=10.0, b=1.0, c=2.0, d=2.0)
    [cm] = link.coupler([0.0], 0.5, 0.5)
    assert cm.status == engine.NOT_ASSEMBLED
    assert (cm.position, cm.velocity, cm.acceleration) == (None, None, None)
    assert link.transmission([0.0]) == [None]


SCALES = (2.0 ** -600, 2.0 ** -30, 2.0 ** 40, 2.0 ** 600)


@given(linkages(("plane", "slider", "skew", "skew-slider")), st.floats(-360.0, 360.0),
       st.sampled_from((1, 2)), st.floats(-2.0, 2.0), st.floats(-2.0, 2.0),
       st.sampled_from(SCALES))
@settings(max_examples=80)
def test_a_linkage_scaled_moves_its_point_scaled(drawn, start, branch, fu, fv, scale):
    """Every length (and u, v) times a power of two from 2^-600 to 2^600: the point, its
    velocity and acceleration scale with them (to 1e-13), the transmission angle stays."""
    kind, dims = drawn
    size = size_of(kind, dims)
    u, v = fu * size, 0.0 if kind in LINE_KINDS else fv * size
    big = {k: x if k == "ksi" else x * scale for k, x in dims.items()}
    phis = [start + 45.0 * k for k in range(8)]
    base, other = engine.Linkage(kind, **dims), engine.Linkage(kind, **big)
    scaled = other.coupler(phis, u * scale, v * scale, branch)
    reach = point_scale(kind, dims, u, v)
    for was, now in zip(base.coupler(phis, u, v, branch), scaled):
        assert now.status == was.status, (kind, dims, scale, now, was)
        for x, y in zip(was[1:4], now[1:4]):
            assert (x is None) == (y is None), (was, now)
            if x is not None:
                error = norm(sub(tuple(c / scale for c in y), x)) / max(reach, norm(x))
                assert error <= 1e-13, (kind, dims, scale, was, now)
    for x, y in zip(base.transmission(phis, branch), other.transmission(phis, branch)):
        assert (x is None) == (y is None) and (x is None or abs(x - y) <= 1e-9), (x, y)


DEAD_CENTRES = [("plane", dict(a=3.0, b=4.0, c=2.0, d=3.0), 90.0, 180.0),     # stretched
                ("plane", dict(a=3.0, b=4.0, c=4.0, d=9.0), 90.0, 0.0),       # folded
                ("slider", dict(b=2.0, c=1.0, e=0.0), 30.0, 0.0),             # rod square
                ("slider", dict(b=2.0, c=1.0, e=0.0), 150.0, 0.0),            # to the guide
                ("slider", dict(b=2.0, c=1.0, e=0.0), 210.0, 180.0),
                ("spherical", dict(a=90.0, b=30.0, c=50.0, d=40.0), 90.0, 180.0),
                ("spherical", dict(a=90.0, b=30.0, c=130.0, d=40.0), 90.0, 0.0),
                ("spherical", dict(a=90.0, b=30.0, c=20.0, d=110.0), 90.0, 0.0)]


@pytest.mark.parametrize("kind, dims, phi, mu", DEAD_CENTRES,
                         ids=[f"{k}-{phi:g}-{d['c']:g}" for k, d, phi, _ in DEAD_CENTRES])
def test_at_a_dead_centre_the_point_stands_and_mu_is_0_or_180(kind, dims, phi, mu):
    """Coupler and output crank in line (the rod square to the guide; on the sphere |AB0| =
    c + d or |c - d|): the point is there, with no velocity (infinite), and mu is 180 (stretched)
    or 0 (folded)."""
    link = engine.Linkage(kind, **dims)
    u, v = (20.0, 10.0) if kind == "spherical" else (0.5, 0.25)
    for branch in (1, 2):
        [cm] = link.coupler([phi], u, v, branch)
        assert cm.status == engine.DEAD_CENTRE, cm
        assert cm.position is not None and cm.velocity is None and cm.acceleration is None
        assert not geometry_problems(kind, dims, link, phi, branch, u, v, cm)
        [got] = link.transmission([phi], branch)
        assert got == pytest.approx(mu, abs=1e-6), (branch, got)


# -- 2. velocity and acceleration against 40-digit differences --------------------------------

reference = Peer("support.engine_reference")     # the 50-digit reference needs mpmath


@functools.cache
def _trig():
    """mpmath's cos and sin at the working precision, the last 4,096 remembered (the
    reference's remembered_trig): the stencil's solves take those of the same link angles and
    input angle at every step."""
    return reference.remembered_trig(4096)


def mp_cos(x):
    return _trig()[0](x)


def mp_sin(x):
    return _trig()[1](x)


def mp_rad(x):
    return mpmath.mpf(x) * mpmath.pi / 180


def mp_crank_pin(kind, dims, phi):
    """A at phi radians (mpf), from joint_positions' frames: the crank about z from x."""
    if kind == "spherical":
        b = mp_rad(dims["b"])
        return (mp_sin(b) * mp_cos(phi), mp_sin(b) * mp_sin(phi), mp_cos(b))
    b = mpmath.mpf(dims["b"])
    return (b * mp_cos(phi), b * mp_sin(phi), mpmath.mpf(0))


def mp_output_pin(kind, dims, q):
    """P at the output q (radians, or the slider's x), from joint_positions' frames."""
    zero = mpmath.mpf(0)
    if kind == "plane":
        a, d = mpmath.mpf(dims["a"]), mpmath.mpf(dims["d"])
        return (a + d * mp_cos(q), d * mp_sin(q), zero)
    if kind == "spherical":
        # B0 = (sin a, 0, cos a); the output crank, arc d about B0, turns from the fixed link's
        # plane (e1, toward A0's side rotated as B0 is) toward +y
        a, d = mp_rad(dims["a"]), mp_rad(dims["d"])
        b0 = (mp_sin(a), zero, mp_cos(a))
        e1 = (mp_cos(a), zero, -mp_sin(a))
        e2 = (zero, mpmath.mpf(1), zero)
        return add((mp_cos(d), b0), (mp_sin(d) * mp_cos(q), e1),
                   (mp_sin(d) * mp_sin(q), e2))
    if kind == "skew":
        # the output crank's circle about B0 = (a, f tan ksi, 0), square to the output shaft
        # w = (0, -sin ksi, cos ksi), from x toward w x x = (0, cos ksi, sin ksi)
        a, d, f, ksi = (mpmath.mpf(dims["a"]), mpmath.mpf(dims["d"]), mpmath.mpf(dims["f"]),
                        mp_rad(dims["ksi"]))
        b0 = (a, f * mpmath.tan(ksi), zero)
        return add((1, b0), (d * mp_cos(q), (1, 0, 0)),
                   (d * mp_sin(q), (zero, mp_cos(ksi), mp_sin(ksi))))
    if kind == "slider":
        return (q, mpmath.mpf(dims["e"]), zero)
    a, f, ksi = mpmath.mpf(dims["a"]), mpmath.mpf(dims["f"]), mp_rad(dims["ksi"])
    return (a, q * mp_sin(ksi), f - q * mp_cos(ksi))


def mp_closure(kind, dims, phi, q):
    a, p = mp_crank_pin(kind, dims, phi), mp_output_pin(kind, dims, q)
    if kind == "spherical":
        return dot(a, p) - mp_cos(mp_rad(dims["c"]))
    c = mpmath.mpf(dims["c"])
    return (dot(sub(p, a), sub(p, a)) - c * c) / (c * c)


def mp_solve(kind, dims, phi, guess):
    """The output q at phi (radians) next to the guess (to 1e-6; the engine's output, or its
    Taylor step): 40 digits. The secant starts from two points 1e-9 apart (mpmath's default
    second point, a quarter further, can reach the other branch's root)."""
    guess = mpmath.mpf(guess)
    step = mpmath.mpf("1e-9") * (1 + abs(guess))
    q = mpmath.findroot(lambda x: mp_closure(kind, dims, phi, x), (guess, guess + step))
    assert abs(mp_closure(kind, dims, phi, q)) < mpmath.mpf(10) ** (8 - DPS), (kind, dims, phi)
    assert abs(q - guess) <= 1e-6 * (1 + abs(guess)), \
        f"{kind} {dims}: no root next to {float(guess)!r} at phi = {float(phi)!r} rad"
    return q


def mp_coupler(kind, dims, a, p, u, v):
    """The coupler point from its definition, in mpmath."""
    if kind == "spherical":
        ur, vr = mp_rad(u), mp_rad(v)
        w = sub(p, tuple(dot(a, p) * x for x in a))
        t = tuple(x / mpmath.sqrt(dot(w, w)) for x in w)
        return add((mpmath.cos(vr) * mpmath.cos(ur), a), (mpmath.cos(vr) * mpmath.sin(ur), t),
                   (mpmath.sin(vr), cross(a, t)))
    w = sub(p, a)
    e = tuple(x / mpmath.sqrt(dot(w, w)) for x in w)
    n = (-e[1], e[0], mpmath.mpf(0))
    return add((1, a), (mpmath.mpf(u), e), (mpmath.mpf(v), n))


H = "1e-4"                      # radians between the differences' positions (an mpf in use)
D1 = (-1, 9, -45, 0, 45, -9, 1)                 # / 60 h
D2 = (2, -27, 270, -490, 270, -27, 2)           # / 180 h^2


def mp_stencil(kind, dims, m):
    """[(phi, A, P, q)] at phi + k H (k = -3..3), the output solved at each, started from the
    engine's Taylor step (a guess only; the root is the geometry's)."""
    with mpmath.workdps(DPS):
        h = mpmath.mpf(H)
        phi0 = mp_rad(m.phi)
        q0 = mpmath.mpf(m.output) if kind in SLIDERS else mp_rad(m.output)
        out = []
        for k in range(-3, 4):
            phi = phi0 + k * h
            guess = q0 + m.velocity * (k * h) + m.acceleration * (k * h) ** 2 / 2
            q = mp_solve(kind, dims, phi, guess)
            out.append((phi, mp_crank_pin(kind, dims, phi), mp_output_pin(kind, dims, q), q))
        return out


def differences(values):
    """(value, first, second derivative) of the 7 vectors (or numbers) at k H."""
    scalar = not isinstance(values[0], tuple)
    vs = [(x,) for x in values] if scalar else values
    h = mpmath.mpf(H)
    first = tuple(sum(w * x[i] for w, x in zip(D1, vs)) / (60 * h) for i in range(len(vs[0])))
    second = tuple(sum(w * x[i] for w, x in zip(D2, vs)) / (180 * h * h)
                   for i in range(len(vs[0])))
    if scalar:
        return values[3], first[0], second[0]
    return values[3], first, second


def well_conditioned(m, vmax=20.0, amax=200.0):
    return (m.status == engine.ASSEMBLED and abs(m.velocity) <= vmax
            and abs(m.acceleration) <= amax)


def vector_error(got, want, scale):
    return norm(sub(got, tuple(float(x) for x in want))) / max(scale, norm(want))


@pytest.mark.parametrize("kind", KINDS)
@given(data=st.data(), start=st.floats(-360.0, 360.0), branch=st.sampled_from((1, 2)))
@settings(max_examples=MP_EXAMPLES)
def test_velocity_and_acceleration_are_the_40_digit_differences(kind, data, start, branch):
    """Position to 1e-10, velocity and acceleration to 1e-7 (of the point's scale, or of the
    vector where larger) against central differences of positions solved in mpmath."""
    kind, dims, (u, v) = data.draw(linkages_with_points((kind,)))
    size = size_of(kind, dims)
    if kind in SLIDERS:
        motion_ok = lambda m: well_conditioned(m, 20.0 * size, 200.0 * size)   # noqa: E731
    else:
        motion_ok = well_conditioned
    link = engine.Linkage(kind, **dims)
    phis = assembled_angles(link, start, branch, 4)
    motions = [m for m in link.sweep(phis, branch) if motion_ok(m)]
    assume(motions)
    scale = point_scale(kind, dims, u, v)
    got = {cm.phi: cm for cm in link.coupler([m.phi for m in motions], u, v, branch)}
    for m in motions:
        with mpmath.workdps(DPS):
            points = [mp_coupler(kind, dims, a, p, u, v)
                      for _, a, p, _ in mp_stencil(kind, dims, m)]
            want = differences(points)
        cm = got[m.phi]
        errors = [vector_error(g, w, scale) for g, w in zip(cm[1:4], want)]
        where = f"{kind} {dims} (u, v) = ({u!r}, {v!r}) phi={m.phi!r} branch {branch}"
        assert errors[0] <= 1e-10, (where, cm.position, want[0])
        assert errors[1] <= 1e-7, (where, cm.velocity, want[1])
        assert errors[2] <= 1e-7, (where, cm.acceleration, want[2])


def test_derivatives_follow_what_is_asked():
    """derivatives 0, 1, 2: the point alone, with its velocity, and its acceleration; the same
    numbers as the full answer."""
    link = engine.Linkage("plane", a=4.0, b=1.5, c=3.5, d=3.0)
    full = link.coupler([10.0, 70.0], 1.0, 0.5)
    for level in (0, 1):
        for cm, whole in zip(link.coupler([10.0, 70.0], 1.0, 0.5, derivatives=level), full):
            assert cm.position == whole.position
            assert cm.acceleration is None
            assert (cm.velocity is None) == (level == 0)
            if level == 1:
                assert cm.velocity == whole.velocity


# -- 3. pylinkage's tracker -------------------------------------------------------------------

PYLINKAGE_STEP = 6.0            # degrees between pylinkage's positions
PYLINKAGE_STEPS = 60
PYLINKAGE_TOL = 1e-9            # of the point's scale


def tracked_four_bar(a, b, c, d, phi0, branch, u, v):
    """pylinkage's fourbar factory (the same joints) with a tracker at (u, v) on the coupler."""
    builder = pl_builder.MechanismBuilder(name="fourbar")
    builder.add_ground_link("ground", ports={"A": (0.0, 0.0), "D": (a, 0.0)})
    builder.add_driver_link("crank", length=b, motor_port="A",
                            omega=math.radians(PYLINKAGE_STEP), initial_angle=math.radians(phi0))
    builder.add_link("coupler", length=c)
    builder.add_link("rocker", length=d)
    builder.connect("crank.tip", "coupler.0")
    builder.connect("coupler.1", "rocker.0")
    builder.connect("rocker.1", "ground.D")
    builder.set_branch("coupler.1", branch)
    builder.add_point_tracker("point", "coupler.0", "coupler.1", distance=math.hypot(u, v),
                              angle=math.atan2(v, u))
    return builder.build()


def tracked_slider(b, c, e, phi0, u, v):
    """pylinkage's slider_crank factory with a tracker at (u, v) on the rod."""
    builder = pl_builder.MechanismBuilder(name="slider-crank")
    builder.add_ground_link("ground", ports={"O": (0.0, 0.0)})
    builder.add_driver_link("crank", length=b, motor_port="O",
                            omega=math.radians(PYLINKAGE_STEP), initial_angle=math.radians(phi0))
    builder.add_link("rod", length=c)
    builder.add_slide_axis("rail", through=(0.0, e), direction=(1.0, 0.0))
    builder.connect("crank.tip", "rod.0")
    builder.connect_prismatic("rod.1", "rail")
    builder.add_point_tracker("point", "rod.0", "rod.1", distance=math.hypot(u, v),
                              angle=math.atan2(v, u))
    return builder.build()


def joint(mechanism, fragment):
    return next(i for i, j in enumerate(mechanism.joints) if fragment in j.id)


def pylinkage_points(mechanism, tip_name, pin_name):
    """[(phi, crank tip, output pin, tracked point)] until pylinkage cannot build."""
    tip, pin, point = (joint(mechanism, n) for n in (tip_name, pin_name, "point"))
    out = []
    try:
        for positions in mechanism.step(PYLINKAGE_STEPS):
            t = positions[tip]
            out.append((math.degrees(math.atan2(t[1], t[0])), t, positions[pin],
                        positions[point]))
    except (pl_errors.UnbuildableError, pl_errors.UnderconstrainedError):
        pass
    return out


def compare_with_pylinkage(kind, dims, link, points, u, v, well_determined):
    """Each pylinkage position against the engine's coupler point on the branch whose output
    pin is pylinkage's (skipped where both or neither are, near a dead centre): the worst
    error over the point's scale, and how many were compared."""
    scale = point_scale(kind, dims, u, v)
    worst, compared = 0.0, 0
    for phi, _, pin, tracked in points:
        matches = []
        for branch in (1, 2):
            pose = engine.joint_positions(link, phi, branch)
            mine = pose.joints.get("C" if kind in SLIDERS else "B")
            if mine is not None and norm(sub(mine[:2], pin)) <= 1e-7 * scale:
                matches.append((branch, pose))
        if len(matches) != 1 or not well_determined(phi, matches[0][1]):
            continue
        [cm] = link.coupler([phi], u, v, matches[0][0], 0)
        worst = max(worst, norm(sub(cm.position[:2], tracked)) / scale)
        assert cm.position[2] == 0.0
        compared += 1
    return worst, compared


length = st.floats(0.3, 10.0)


@given(length, length, length, length, st.floats(-180.0, 180.0), st.sampled_from((0, 1)),
       st.floats(-2.0, 2.0), st.floats(-2.0, 2.0))
@settings(max_examples=40)
def test_pylinkage_traces_the_same_four_bar_coupler_curve(a, b, c, d, phi0, branch, fu, fv):
    """pylinkage's tracker at distance hypot(u, v) and angle atan2(v, u) from the coupler's
    direction is the point (u, v): the same curve to 1e-9 of the point's scale, where
    pylinkage's circle intersection is well conditioned (test_pylinkage.condition <= 1e3)."""
    assume(startable(a, b, c, d, phi0))
    size = max(a, b, c, d)
    u, v = fu * size, fv * size
    mechanism = tracked_four_bar(a, b, c, d, phi0, branch, u, v)
    points = pylinkage_points(mechanism, "crank.tip", "rocker.0")
    link = engine.Linkage("plane", a=a, b=b, c=c, d=d)

    def well_determined(phi, pose):
        return condition(a, b, c, d, phi, pose.output) <= 1e3
    worst, compared = compare_with_pylinkage("plane", dict(a=a, b=b, c=c, d=d), link, points,
                                             u, v, well_determined)
    assume(compared)
    assert worst <= PYLINKAGE_TOL, (a, b, c, d, phi0, branch, u, v, worst)


@given(length, st.floats(-5.0, 5.0), st.floats(0.1, 2.0), st.floats(-180.0, 180.0),
       st.floats(-2.0, 2.0), st.floats(-2.0, 2.0))
@settings(max_examples=30)
def test_pylinkage_traces_the_same_slider_crank_coupler_curve(b, e, margin, phi0, fu, fv):
    """The same on slider-cranks whose rod clears crank and offset (c = (b + |e|)(1 + margin):
    no dead centre), the tracker on the rod."""
    c = (b + abs(e)) * (1.0 + margin)
    dims = dict(b=b, c=c, e=e)
    size = max(b, c, abs(e))
    u, v = fu * size, fv * size
    points = pylinkage_points(tracked_slider(b, c, e, phi0, u, v), "crank.tip", "rod.1")
    link = engine.Linkage("slider", **dims)
    worst, compared = compare_with_pylinkage("slider", dims, link, points, u, v,
                                             lambda phi, pose: True)
    assert compared >= PYLINKAGE_STEPS // 2, compared
    assert worst <= PYLINKAGE_TOL, (b, c, e, phi0, u, v, worst)


def test_pylinkage_tracker_example():
    """One point by hand: 4-1.5-3.5-3 at phi = 30 with (1, 0.5), pylinkage's lower branch."""
    mechanism = tracked_four_bar(4.0, 1.5, 3.5, 3.0, 30.0 - PYLINKAGE_STEP, 0, 1.0, 0.5)
    phi, _, pin, tracked = pylinkage_points(mechanism, "crank.tip", "rocker.0")[0]
    assert phi == pytest.approx(30.0)
    link = engine.Linkage("plane", a=4.0, b=1.5, c=3.5, d=3.0)
    branch = next(br for br in (1, 2)
                  if norm(sub(engine.joint_positions(link, 30.0, br).joints["B"][:2], pin))
                  < 1e-9)
    [cm] = link.coupler([30.0], 1.0, 0.5, branch)
    assert cm.position[:2] == pytest.approx(tracked, abs=1e-12)


# -- 4. the transmission angle ----------------------------------------------------------------

def cos_close(mu, cos_want, scale, tol=1e-12):
    """mu (degrees) in [0, 180] and its cosine cos_want, to tol of the formula's terms' scale."""
    return 0.0 <= mu <= 180.0 and abs(math.cos(math.radians(mu)) - cos_want) <= tol * scale


def eq1(a, b, c, d, phi):
    """Review eq. (1) in the project's letters: cos mu and the scale of its terms."""
    cp = math.cos(math.radians(phi))
    return ((c * c + d * d - a * a - b * b + 2 * a * b * cp) / (2 * c * d),
            (c * c + d * d + a * a + b * b + 2 * a * b) / (2 * c * d))


@given(linkages(("plane",)), st.floats(-360.0, 360.0))
@settings(max_examples=150)
def test_plane_four_bar_transmission_is_eq_1_on_both_branches(drawn, start):
    _, dims = drawn
    link = engine.Linkage("plane", **dims)
    phis = [start + 30.0 * k for k in range(12)]
    checked = 0
    for branch in (1, 2):
        for phi, m, mu in zip(phis, link.sweep(phis, branch, 0), link.transmission(phis, branch)):
            assert (mu is None) == (m.output is None)
            if mu is None:
                continue
            cos_mu, scale = eq1(dims["a"], dims["b"], dims["c"], dims["d"], phi)
            assert cos_close(mu, cos_mu, scale), (dims, phi, branch, mu, cos_mu)
            checked += 1
    assume(checked)


@given(linkages(("slider",)), st.floats(-360.0, 360.0))
@settings(max_examples=100)
def test_slider_crank_transmission_is_eq_3_corrected(drawn, start):
    """cos mu = (b sin phi - e) / c: the review's eq. (3), corrected (errata S9), with its offset
    epsilon = -e, mu = 90 - arctan[(epsilon + r sin theta) / sqrt(l^2 - (...)^2)], signed."""
    _, dims = drawn
    b, c, e = dims["b"], dims["c"], dims["e"]
    link = engine.Linkage("slider", **dims)
    phis = [start + 30.0 * k for k in range(12)]
    checked = 0
    for branch in (1, 2):
        for phi, mu in zip(phis, link.transmission(phis, branch)):
            if mu is None:
                continue
            epsilon, r, l = -e, b, c
            h = epsilon + r * math.sin(math.radians(phi))
            scale = (b + abs(e)) / c
            assert cos_close(mu, (b * math.sin(math.radians(phi)) - e) / c, scale), \
                (dims, phi, branch, mu)
            if l * l - h * h > 1e-6 * l * l:
                review = 90.0 - math.degrees(math.atan(h / math.sqrt(l * l - h * h)))
                assert mu == pytest.approx(review, abs=1e-6), (dims, phi, branch, mu, review)
            checked += 1
    assume(checked)


@given(linkages(("spherical",)), st.floats(-360.0, 360.0))
@settings(max_examples=150)
def test_spherical_transmission_is_the_inner_angle_at_b(drawn, start):
    """cos mu = (cos|AB0| - cos c cos d) / (sin c sin d), |AB0| from the fixed triangle
    A0 A B0: cos|AB0| = cos a cos b + sin a sin b cos phi."""
    _, dims = drawn
    a, b, c, d = (math.radians(dims[k]) for k in "abcd")
    link = engine.Linkage("spherical", **dims)
    phis = [start + 30.0 * k for k in range(12)]
    checked = 0
    for branch in (1, 2):
        for phi, mu in zip(phis, link.transmission(phis, branch)):
            if mu is None:
                continue
            cos_ab0 = (math.cos(a) * math.cos(b)
                       + math.sin(a) * math.sin(b) * math.cos(math.radians(phi)))
            sc_sd = math.sin(c) * math.sin(d)
            cos_mu = (cos_ab0 - math.cos(c) * math.cos(d)) / sc_sd
            assert cos_close(mu, cos_mu, 3.0 / sc_sd), (dims, phi, branch, mu, cos_mu)
            checked += 1
    assume(checked)


@given(linkages(("plane",)), st.floats(-360.0, 360.0))
@settings(max_examples=60)
def test_a_plane_skew_linkage_has_the_plane_transmission(drawn, start):
    """f = 0, ksi = 0: the skew linkage is the plane four-bar, and so is its mu (eq. (1))."""
    _, dims = drawn
    link = engine.Linkage("skew", **dims, f=0.0, ksi=0.0)
    phis = [start + 30.0 * k for k in range(12)]
    for branch in (1, 2):
        for phi, mu in zip(phis, link.transmission(phis, branch)):
            if mu is not None:
                cos_mu, scale = eq1(dims["a"], dims["b"], dims["c"], dims["d"], phi)
                assert cos_close(mu, cos_mu, scale), (dims, phi, branch, mu, cos_mu)


def mp_angle(x, y):
    return float(mpmath.atan2(mpmath.sqrt(dot(cross(x, y), cross(x, y))), dot(x, y))
                 * 180 / mpmath.pi)


@pytest.mark.parametrize("kind", KINDS)
@given(data=st.data(), start=st.floats(-360.0, 360.0), branch=st.sampled_from((1, 2)))
@settings(max_examples=MP_EXAMPLES)
def test_transmission_is_the_angle_of_the_output_pins_motion(kind, data, start, branch):
    """The definition, every kind: the angle between t_a = dP/dq, the output pin's motion per
    unit positive output (dP/dphi, by differences of the mpmath positions, times the sign of
    q' = dq/dphi), and t_r = axis x (P - A), the axis z (OA on the sphere); the skew kinds'
    ball-jointed coupler: 90 degrees less the angle between the line P - A and t_a (its size:
    what the forces transmit, tests/test_forces_scenes.py), on t_r's side of 90. To 1e-7
    degree."""
    kind, dims = data.draw(linkages((kind,)))
    link = engine.Linkage(kind, **dims)
    size = size_of(kind, dims) if kind in SLIDERS else 1.0
    phis = assembled_angles(link, start, branch, 4)
    motions = [m for m in link.sweep(phis, branch)
               if well_conditioned(m, 20.0 * size, 200.0 * size)]
    assume(motions)
    mus = link.transmission([m.phi for m in motions], branch)
    for m, mu in zip(motions, mus):
        with mpmath.workdps(DPS):
            stencil = mp_stencil(kind, dims, m)
            _, dq, _ = differences([q for *_, q in stencil])
            if abs(dq) < 1e-3 * size:
                continue                    # the output at rest: dP/dphi tells no direction
            _, a, p, _ = stencil[3]
            _, dp, _ = differences([pin for _, _, pin, _ in stencil])
            t_a = tuple(mpmath.sign(dq) * x for x in dp)
            axis = a if kind == "spherical" else (0, 0, 1)
            t_r = cross(axis, sub(p, a))
            want = mp_angle(t_a, t_r)
            if kind in ("skew", "skew-slider"):
                off_line = abs(90 - mp_angle(t_a, sub(p, a)))
                want = off_line if dot(t_a, t_r) >= 0 else 180 - off_line
        assert mu == pytest.approx(want, abs=1e-7), (kind, dims, m.phi, branch, mu, want)


# the review's worked examples, in its letters (a crank, b coupler, c rocker, d = 1 frame), with
# the printed extremes (FOURB-CR-1's 47.022 is cut, not rounded: errata S2)
# (the digit each is printed to: 1e-3 where cut, 5e-4 where rounded; the review's lengths are
# themselves rounded to 6 digits, which moves mu by about 1e-5 degree)
REVIEW_EXAMPLES = [
    ("FOURB-CR-1", dict(a=0.257961, b=1.012188, c=0.642896), (47.022, 1e-3), (96.380, 5.1e-4)),
    ("FOURB-CR-2", dict(a=0.585014, b=1.009510, c=0.946189), (24.223, 5.1e-4), (108.238, 5.1e-4)),
]


@pytest.mark.parametrize("name, review, mu_min, mu_max", REVIEW_EXAMPLES,
                         ids=[row[0] for row in REVIEW_EXAMPLES])
def test_the_reviews_worked_examples_eqs_2a_2b(name, review, mu_min, mu_max):
    """mu at phi = 0 is eq. (2a)'s mu_min, at 180 eq. (2b)'s mu_max, on both branches; they are
    the printed numbers to their last digit, and the least and greatest over the turn."""
    a, b, c = review["a"], review["b"], review["c"]
    eq2a = math.degrees(math.acos((b * b + c * c - (1 - a) ** 2) / (2 * b * c)))
    eq2b = math.degrees(math.acos((b * b + c * c - (1 + a) ** 2) / (2 * b * c)))
    link = engine.Linkage("plane", a=1.0, b=a, c=b, d=c)
    for branch in (1, 2):
        at_0, at_180 = link.transmission([0.0, 180.0], branch)
        assert at_0 == pytest.approx(eq2a, abs=1e-9), (branch, at_0, eq2a)
        assert at_180 == pytest.approx(eq2b, abs=1e-9), (branch, at_180, eq2b)
        assert abs(at_0 - mu_min[0]) <= mu_min[1], (at_0, mu_min)
        assert abs(at_180 - mu_max[0]) <= mu_max[1], (at_180, mu_max)
        turn = link.transmission([float(p) for p in range(0, 360, 5)], branch)
        assert at_0 - 1e-9 <= min(turn) and max(turn) <= at_180 + 1e-9, (min(turn), max(turn))


# -- 5. the numpy forms -------------------------------------------------------------------------

def same_vectors(array, vectors, scale, tol=1e-12):
    """Rows of array against the scalar vectors (None -> a NaN row): [(i, why)] wrong."""
    wrong = []
    for i, want in enumerate(vectors):
        row = array[i]
        if want is None:
            if not np.isnan(row).all():
                wrong.append((i, f"{row} where the scalar form has None"))
            continue
        error = norm(sub(tuple(row), want)) / max(scale, norm(want))
        if not error <= tol:
            wrong.append((i, f"{row} against {want}: {error:.1e}"))
    return wrong


@given(linkages_with_points(), st.floats(-360.0, 360.0), st.sampled_from((1, 2)),
       st.sampled_from((0, 1, 2)))
@settings(max_examples=150)
def test_the_numpy_forms_are_the_scalar_ones(drawn, start, branch, derivatives):
    """coupler_arrays and transmission_arrays: the scalar numbers to 1e-12 (of the point's
    scale or of the vector, degrees for mu), NaN where the scalar is None; 24 angles a turn."""
    kind, dims, (u, v) = drawn
    link = engine.Linkage(kind, **dims)
    phis = [start + 15.0 * k for k in range(24)]
    scalar = link.coupler(phis, u, v, branch, derivatives)
    arrays = link.coupler_arrays(np.array(phis), u, v, branch, derivatives)
    scale = point_scale(kind, dims, u, v)
    assert arrays.position.shape == (24, 3)
    wrong = same_vectors(arrays.position, [cm.position for cm in scalar], scale)
    for level, name in ((1, "velocity"), (2, "acceleration")):
        got = getattr(arrays, name)
        if derivatives < level:
            assert got is None
        else:
            wrong += same_vectors(got, [getattr(cm, name) for cm in scalar], scale)
    mu_scalar = link.transmission(phis, branch)
    mu_array = link.transmission_arrays(np.array(phis), branch)
    assert mu_array.dtype == np.float64 and mu_array.shape == (24,)
    for i, (x, y) in enumerate(zip(mu_array, mu_scalar)):
        if y is None:
            if not math.isnan(x):
                wrong.append((i, f"mu {x} where the scalar is None"))
        elif not abs(x - y) <= 1e-12 * max(abs(y), 1.0):
            wrong.append((i, f"mu {x} against {y}"))
    assert not wrong, (kind, dims, u, v, branch, [(phis[i], why) for i, why in wrong[:4]])


SINGULAR = [(k, d, phi) for k, d, phi, _ in DEAD_CENTRES] + list(CHANGE_POINTS)


@pytest.mark.parametrize("kind, dims, phi0", SINGULAR,
                         ids=[f"{k}-{phi:g}-{d['c']:g}" for k, d, phi in SINGULAR])
def test_the_numpy_forms_at_dead_centres_and_change_points(kind, dims, phi0):
    """On and 1e-9, 1e-3 degree either side of a dead centre or change point (where
    sweep_arrays hands points to sweep): the scalar numbers, NaN where there are none."""
    link = engine.Linkage(kind, **dims)
    phis = [phi0 + x for x in (-1e-3, -1e-9, 0.0, 1e-9, 1e-3)]
    u, v = (20.0, 10.0) if kind == "spherical" else (0.5, 0.0 if kind in LINE_KINDS else 0.25)
    for branch in (1, 2):
        scalar = link.coupler(phis, u, v, branch)
        arrays = link.coupler_arrays(np.array(phis), u, v, branch)
        wrong = [(name, same_vectors(getattr(arrays, name), [getattr(cm, name) for cm in scalar],
                                     1.0)) for name in ("position", "velocity", "acceleration")]
        mus = zip(link.transmission_arrays(np.array(phis), branch),
                  link.transmission(phis, branch))
        wrong.append(("mu", [(x, y) for x, y in mus if not (
            math.isnan(x) if y is None else abs(x - y) <= 1e-12 * max(abs(y), 1.0))]))
        assert not [w for w in wrong if w[1]], (branch, [cm.status for cm in scalar], wrong)


# -- 6. followed through change points ---------------------------------------------------------

FOLLOW_STEP = 0.01          # degrees
FOLLOW_COUNT = 200          # the sweep: the change point +- 1 degree


FOLLOWED = [("plane", dict(a=3.0, b=1.0, c=2.0, d=2.0), 180.0)] + CHANGE_POINTS


@pytest.mark.parametrize("kind, dims, phi0", FOLLOWED,
                         ids=[f"{k}-{'-'.join(f'{x:g}' for x in d.values())}-{phi0:g}"
                              for k, d, phi0 in FOLLOWED])
@pytest.mark.parametrize("start", (1, 2))
def test_the_followed_coupler_curve_is_smooth_through_a_change_point(kind, dims, phi0, start):
    """branch="follow" across a change point: consecutive points differ by at most the fastest
    speed the point reaches nearby (either branch) times the step, and the curve has no kink:
    its second differences are O(step^2), and the velocity it reports changes by O(step).
    A fixed branch label that swaps there (the listing's) shows the kink the check looks for."""
    link = engine.Linkage(kind, **dims)
    u, v = (0.7, 0.0) if kind in LINE_KINDS else ((30.0, 20.0) if kind == "spherical"
                                                  else (0.7, 0.4))
    phis = [phi0 - 1.0 + FOLLOW_STEP * k for k in range(FOLLOW_COUNT + 1)]
    h = math.radians(FOLLOW_STEP)
    fixed = {br: link.coupler(phis, u, v, br) for br in (1, 2)}
    speed = max(norm(cm.velocity) for br in (1, 2) for cm in fixed[br]
                if cm.velocity is not None)
    accel = max(norm(cm.acceleration) for br in (1, 2) for cm in fixed[br]
                if cm.acceleration is not None)
    followed = link.coupler(phis, u, v, engine.FOLLOW, start=start)
    assert all(cm.status in (engine.ASSEMBLED, engine.CHANGE_POINT) for cm in followed), \
        [cm.status for cm in followed]
    assert any(cm.status == engine.CHANGE_POINT for cm in followed)

    def kinks(curve):
        ps = [cm.position for cm in curve]
        steps = [norm(sub(q, p)) for p, q in zip(ps, ps[1:])]
        seconds = [norm(add((1, r), (-2, q), (1, p))) for p, q, r in zip(ps, ps[1:], ps[2:])]
        turns = [norm(sub(y.velocity, x.velocity)) for x, y in zip(curve, curve[1:])]
        return max(steps), max(seconds), max(turns)

    step, second, turn = kinks(followed)
    assert step <= 1.01 * speed * h, (step, speed * h)
    assert second <= 2.0 * accel * h * h, (second, accel * h * h)
    assert turn <= 2.0 * accel * h, (turn, accel * h)
    fixed_mu = {br: link.transmission(phis, br) for br in (1, 2)}
    followed_mu = link.transmission(phis, engine.FOLLOW, start=start)
    for i, cm in enumerate(followed):   # each followed point is one of the fixed branches'
        gaps = {br: norm(sub(cm.position, fixed[br][i].position)) for br in (1, 2)}
        br = min(gaps, key=gaps.get)
        assert gaps[br] <= 1e-12 * (1 + speed), cm
        assert abs(followed_mu[i] - fixed_mu[br][i]) <= 1e-9 or \
            abs(followed_mu[i] - fixed_mu[3 - br][i]) <= 1e-9, (cm, followed_mu[i])
    if kind == "plane":         # the listing's labels swap at these change points: a kink
        assert max(kinks(fixed[start])[1:]) > 10 * max(second, turn)


@given(st.integers(1, 40), st.integers(1, 40), st.integers(1, 40), st.sampled_from((1, 2)),
       st.floats(-2.0, 2.0), st.floats(-2.0, 2.0))
@settings(max_examples=40)
def test_a_random_grashof_boundary_coupler_curve_is_smooth(a, b, c, start, fu, fv):
    """a + b = c + d exactly (quarters, test_follow's draw): followed from 170 to 190 degrees by
    0.1, the point moves by at most its speed times the step (plus its acceleration's share),
    and its velocity by at most its acceleration times the step."""
    a, b, c = a / 4.0, b / 4.0, c / 4.0
    d = a + b - c
    assume(d > 0.1 and abs(c - d) < a + b - 0.3)
    link = engine.Linkage("plane", a=a, b=b, c=c, d=d)
    v1, v2 = (link.motion(180.0, br).velocity for br in (1, 2))
    assume(v1 is not None and v2 is not None and abs(v1 - v2) > 1e-3)
    size = max(a, b, c, d)
    u, v = fu * size, fv * size
    phis = engine.evenly_spaced_angles(170.0, 190.0, 0.1)
    curve = link.coupler(phis, u, v, engine.FOLLOW, start=start)
    assume(all(cm.velocity is not None for cm in curve))
    h = math.radians(0.1)
    for m0, m1 in zip(curve, curve[1:]):
        vmax = max(norm(m0.velocity), norm(m1.velocity))
        amax = max(norm(m0.acceleration), norm(m1.acceleration))
        assert norm(sub(m1.position, m0.position)) <= vmax * h + amax * h * h + 1e-12 * size, \
            (a, b, c, d, u, v, m0, m1)
        assert norm(sub(m1.velocity, m0.velocity)) <= 1.5 * amax * h + 1e-3 * h * size, \
            (a, b, c, d, u, v, m0, m1)


# -- 7. refusals ---------------------------------------------------------------------------------

EXAMPLE = {"plane": dict(a=4.0, b=1.5, c=3.5, d=3.0),
           "spherical": dict(a=70.0, b=30.0, c=60.0, d=40.0),
           "skew": dict(a=4.0, b=1.5, c=3.5, d=3.0, f=1.0, ksi=30.0),
           "slider": dict(b=1.5, c=4.0, e=0.5),
           "skew-slider": dict(a=1.0, b=1.5, c=4.0, f=0.5, ksi=30.0)}


def refusals(link, u, v):
    """The message of each entry point's refusal of (u, v) (they must all refuse)."""
    messages = []
    for call in (lambda: engine.check_coupler_point(link, u, v),
                 lambda: link.coupler([0.0], u, v),
                 lambda: link.coupler_arrays(np.array([0.0]), u, v),
                 lambda: engine.coupler_of(link, link.sweep([0.0]), u, v)):
        with pytest.raises(ValueError) as caught:
            call()
        messages.append(str(caught.value))
    return messages


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("u, v", [(math.nan, 0.0), (0.0, math.nan), (math.inf, 0.0),
                                  (0.0, -math.inf)])
def test_a_point_not_finite_is_refused(kind, u, v):
    for message in refusals(engine.Linkage(kind, **EXAMPLE[kind]), u, v):
        assert "finite" in message


@pytest.mark.parametrize("kind", KINDS)
def test_a_point_too_far_is_refused(kind):
    """Beyond 1e9 times the size (the largest length; 360 degrees on the sphere) from A; at
    1e9 times it is a point."""
    dims = EXAMPLE[kind]
    reach = 360.0 if kind == "spherical" else size_of(kind, dims)
    link = engine.Linkage(kind, **dims)
    far = 1e9 * reach * (1 + 1e-12)
    for u, v in ((far, 0.0), (-far, 0.0)) + (() if kind in LINE_KINDS else ((0.0, far),)):
        for message in refusals(link, u, v):
            assert "size" in message and "1e+09" in message, message
    engine.check_coupler_point(link, 1e9 * reach, 0.0)


@pytest.mark.parametrize("kind", LINE_KINDS)
def test_a_point_off_the_line_of_a_ball_jointed_coupler_is_refused(kind):
    link = engine.Linkage(kind, **EXAMPLE[kind])
    for v in (1e-300, -1.0):
        for message in refusals(link, 0.5, v):
            assert "ball joints" in message and "v must be 0" in message, message
    assert link.coupler([0.0], 0.5, 0.0)[0].position is not None
    assert link.coupler([0.0], 0.5, -0.0)[0].position is not None


@pytest.mark.parametrize("kind", ("plane", "slider", "skew", "skew-slider"))
def test_a_coupler_of_no_length_is_refused(kind):
    dims = dict(EXAMPLE[kind], c=0.0)
    for message in refusals(engine.Linkage(kind, **dims), 0.5, 0.0):
        assert "c = 0" in message, message


@pytest.mark.parametrize("c", (0.0, 180.0, 360.0, -180.0))
def test_a_spherical_coupler_of_no_great_circle_is_refused(c):
    dims = dict(EXAMPLE["spherical"], c=c)
    for message in refusals(engine.Linkage("spherical", **dims), 10.0, 0.0):
        assert f"c = {c:g}" in message and "great circle" in message, message


@pytest.mark.parametrize("u, v", [("abc", 0.0), (0.0, None), ([1.0], 0.0)])
def test_a_point_that_is_not_two_numbers_is_refused(u, v):
    for message in refusals(engine.Linkage("plane", **EXAMPLE["plane"]), u, v):
        assert "two numbers" in message, message


# -- what a drawing, a scene or a run that asks for neither pays: nothing ------------------------

@pytest.fixture
def coupler_calls(monkeypatch):
    """Every call of the coupler point's and the transmission angle's computations."""
    calls = []
    for name in ("coupler_of", "transmission_of", "coupler_of_arrays", "transmission_of_arrays"):
        function = getattr(engine, name)

        def counted(*args, function=function, name=name):
            calls.append(name)
            return function(*args)
        monkeypatch.setattr(engine, name, counted)
    return calls


@pytest.mark.parametrize("argv", [
    ["scene", "{scenes}/fig1a-plane-four-bar.toml", "--frames", "2"],
    ["scene", "{scenes}/fig3-plane-four-bar.toml", "--dir", "{tmp}"],
    ["run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9", "--from", "0", "--to",
     "360", "--step", "10", "--branch", "1", "--precision", "double", "--dir", "{tmp}"],
    ["run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9", "--from", "0", "--to",
     "360", "--step", "10", "--branch", "1", "--precision", "double", "--dir", "{tmp}",
     "--fast"],
])
def test_what_asks_for_neither_computes_neither(argv, coupler_calls, tmp_path, capsys):
    if "--fast" in argv:
        need("numpy", load=False)
    scenes = Path(engine.__file__).parent / "data" / "scenes"
    argv = [a.format(scenes=scenes, tmp=tmp_path) for a in argv]
    assert engine.main(argv) == 0
    assert coupler_calls == []


def test_a_csv_without_a_coupler_point_computes_only_mu(coupler_calls, tmp_path, capsys):
    argv = ["run", "slider", "--b", "2", "--c", "7", "--e", "1.5", "--from", "0", "--to", "360",
            "--step", "10", "--branch", "1", "--precision", "double", "--dir", str(tmp_path),
            "--csv", str(tmp_path / "out.csv")]
    assert engine.main(argv) == 0
    assert set(coupler_calls) == {"transmission_of"}
    assert engine.main(argv + ["--coupler", "3"]) == 0
    assert set(coupler_calls) == {"transmission_of", "coupler_of"}
