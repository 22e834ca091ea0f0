"""linkage.forces held to what it must satisfy, never to its own formulas: the driving torque
against the energy balance of the reference (tests/support/forces_reference.py: the loop closed
in mpmath by its own roots, energies by their definitions, differentiated in time); every body's
Newton-Euler equations recomputed here from the reported reactions and the reference's
accelerations; virtual work for a static linkage; a balanced crank, a massless skew coupler and
the slider-crank's textbook piston force; bad input refused."""

from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings, strategies as st

import linkage
from linkage import Bodies, Body, Effects, Linkage
from support import forces_reference as ref

PLANE_KINDS = ("plane", "slider")
LINE_COUPLERS = ("skew", "skew-slider")
KINDS = ("plane", "spherical", "skew", "slider", "skew-slider")


def between(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


DIMENSIONS = {
    "plane": st.fixed_dictionaries({"a": between(1, 5), "b": between(0.2, 2), "c": between(1, 5),
                                    "d": between(1, 5)}),
    "spherical": st.fixed_dictionaries({"a": between(20, 160), "b": between(10, 80),
                                        "c": between(20, 160), "d": between(20, 160)}),
    "skew": st.fixed_dictionaries({"a": between(0.5, 3), "b": between(0.2, 1.5),
                                   "c": between(0.5, 3), "d": between(0.5, 3),
                                   "f": between(-1, 1), "ksi": between(-60, 60)}),
    "slider": st.fixed_dictionaries({"b": between(0.2, 2), "c": between(1, 5),
                                     "e": between(-1, 1)}),
    "skew-slider": st.fixed_dictionaries({"a": between(0.2, 3), "b": between(0.2, 1.5),
                                          "c": between(1, 4), "f": between(-1, 1),
                                          "ksi": between(-60, 60)}),
}


@st.composite
def tensors(draw):
    """A symmetric positive semi-definite 3 x 3 tensor (M M^T)."""
    m = [[draw(between(-1, 1)) for _ in range(3)] for _ in range(3)]
    return tuple(tuple(sum(m[i][k] * m[j][k] for k in range(3)) for j in range(3))
                 for i in range(3))


@st.composite
def bodies(draw, kind, explicit=None):
    """Three bodies of `kind`: each a rod of its mass or (explicit) a centre and inertia."""
    out = []
    for role in ("crank", "coupler", "output"):
        mass = draw(st.floats(0, 10, allow_subnormal=False))   # 5e-324 kg: a product of
        #                      it underflows in one form's order of operations, not the other's
        if not (draw(st.booleans()) if explicit is None else explicit):
            out.append(Body(mass))
        elif kind in PLANE_KINDS:
            centre = (draw(between(-1, 2)), draw(between(-1, 1))) if role == "coupler" \
                else draw(between(-1, 2))
            out.append(Body(mass, centre, draw(between(0, 2))))
        elif kind in LINE_COUPLERS and role == "coupler":
            side = draw(between(0, 2))
            out.append(Body(mass, (draw(between(-1, 2)), 0.0, 0.0),
                            ((draw(between(0, 2)), 0, 0), (0, side, 0), (0, 0, side))))
        else:
            out.append(Body(mass, tuple(draw(between(-1, 1)) for _ in range(3)),
                            draw(tensors())))
    return Bodies(*out)


@st.composite
def effects(draw, kind, speed=True):
    sliding = kind in linkage.SLIDER_CRANKS
    gravity = draw(st.sampled_from([None, 9.81, "vector"]))
    if gravity == "vector":
        gravity = (draw(between(-10, 10)), draw(between(-10, 10)),
                   0.0 if kind in PLANE_KINDS else draw(between(-10, 10)))
    coupler_force = None
    if draw(st.booleans()):
        u = draw(between(-1, 2)) if kind != "spherical" else draw(between(-60, 60))
        v = 0.0 if kind in LINE_COUPLERS else draw(between(-1, 1)) if kind != "spherical" \
            else draw(between(-40, 40))
        coupler_force = ((u, v), (draw(between(-50, 50)), draw(between(-50, 50)),
                                  0.0 if kind in PLANE_KINDS else draw(between(-50, 50))))
    return Effects(
        speed_rpm=draw(between(10, 600)) if speed else 0.0,
        crank_acceleration=draw(st.sampled_from([0.0, draw(between(-200, 200))]))
        if speed else 0.0,
        gravity=gravity,
        output_torque=0.0 if sliding else draw(between(-50, 50)),
        output_force=draw(between(-50, 50)) if sliding else 0.0,
        coupler_force=coupler_force)


@st.composite
def cases(draw, kind, speed=True, explicit=None):
    """A linkage of `kind` well away from its dead centres, an angle, branch, bodies, effects."""
    lk = Linkage(kind, **draw(DIMENSIONS[kind]))
    phi, branch = draw(between(0, 360)), draw(st.sampled_from([1, 2]))
    m = lk.motion(phi, branch)
    assume(m.status == linkage.ASSEMBLED and abs(m.velocity) < 20)
    mu = lk.transmission([phi], branch)[0]
    assume(mu is not None and 15 < mu < 165)
    return lk, phi, branch, draw(bodies(kind, explicit)), draw(effects(kind, speed))


def radius_of(kind):
    return 0.7 if kind == "spherical" else 1.0


def forces_at(lk, phi, branch, b, e):
    (out,) = linkage.forces(lk, [phi], branch, b, e, radius=radius_of(lk.kind))
    assert out.status == linkage.ASSEMBLED, out
    return out


# -- two methods, one answer ----------------------------------------------------------------------

def check_energy(case):
    lk, phi, branch, b, e = case
    torque, scale = ref.energy_torque(lk, phi, branch, b, e, radius_of(lk.kind))
    got = forces_at(lk, phi, branch, b, e)
    assert abs(got.torque - torque) <= 1e-9 * scale + 1e-12, (lk, phi, branch, b, e, got.torque,
                                                              torque)
    assert got.power == pytest.approx(got.torque * 2 * math.pi * e.speed_rpm / 60, rel=1e-15)


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_the_torque_is_the_energy_balances(kind, data):
    check_energy(data.draw(cases(kind)))


def test_the_arcs_means_are_the_quadratures():
    """The reference's uniform rod on the sphere: its means along the arc in closed form are
    mpmath.quad's integrals over the arc, at 50 digits, from a 1e-8 arc to a half circle."""
    mpmath = ref.mpmath
    with ref.mp.workdps(ref.DIGITS):
        functions = {"cc": lambda t: mpmath.cos(t) ** 2, "ss": lambda t: mpmath.sin(t) ** 2,
                     "cs": lambda t: mpmath.cos(t) * mpmath.sin(t), "c": mpmath.cos,
                     "s": mpmath.sin}
        for arc in (mpmath.mpf("1e-8"), mpmath.mpf("0.3"), mpmath.mpf(2), mpmath.pi):
            means = ref.arc_means(arc)
            for name, f in functions.items():
                assert abs(means[name] - mpmath.quad(f, [0, arc]) / arc) <= 1e-40, (arc, name)


# -- every body in equilibrium --------------------------------------------------------------------

# joint: (the body before it, the body after it: None the frame, 0 crank, 1 coupler, 2 output)
TOPOLOGY = {"A0": (None, 0), "A": (0, 1), "B": (1, 2), "C": (1, 2), "B0": (None, 2),
            "guide": (None, 2)}


def joint_point(kind, name, a, p, lk):
    if name == "A0" or kind == "spherical":     # the spherical joints' moments are about O
        return [0, 0, 0]
    if name == "A":
        return a
    if name == "B0" and kind == "plane":
        return [lk.dims["a"], 0, 0]
    if name == "B0":
        ksi = math.radians(lk.dims["ksi"])
        return [lk.dims["a"], lk.dims["f"] * math.tan(ksi), 0]
    return p            # B, C and the guide (at C)


def wrench_sums(kind, got, lk, b, e, phi, branch):
    """Per body: the terms of its force and moment (about the origin) equations, each a list of
    vectors whose sum must vanish; and the reference's bodies (for the frame's check)."""
    bodies_now, a, p, motion = ref.states(lk, phi, branch, b, e, radius_of(kind))
    g = ref.gravity_vector(kind, e.gravity)
    forces = [[], [], []]
    moments = [[], [], []]
    for name, reaction in got.joints.items():
        before, after = TOPOLOGY[name]
        at = joint_point(kind, name, a, p, lk)
        f = ref.vec(*reaction.force) if reaction.force is not None else None
        mo = ref.vec(*reaction.moment) if reaction.moment is not None else ref.vec(0, 0, 0)
        for body, sign in ((after, 1), (before, -1)):
            if body is None:
                continue
            if f is not None:
                forces[body].append([sign * x for x in f])
                moments[body].append([sign * x for x in ref.crossp(at, f)])
            moments[body].append([sign * x for x in mo])
    moments[0].append(ref.vec(0, 0, got.torque))
    for body, role in enumerate(("crank", "coupler", "output")):
        m, centre, inertia = ref.local_body(kind, role, getattr(b, role))
        state = bodies_now[body]
        weight = [m * x for x in g]
        forces[body] += [weight, [-m * x for x in state.acceleration]]
        moments[body] += [ref.crossp(state.centre, weight),
                          [-m * x for x in ref.crossp(state.centre, state.acceleration)]]
        world = [[sum(state.axes[k][i] * inertia[k][l] * state.axes[l][j]
                      for k in range(3) for l in range(3)) for j in range(3)] for i in range(3)]

        def times(w, world=world):
            return [sum(world[i][j] * w[j] for j in range(3)) for i in range(3)]
        moments[body] += [[-x for x in times(state.spin_rate)],
                          [-x for x in ref.crossp(state.spin, times(state.spin))]]
    if e.output_torque:
        axis = motion.g.axis
        moments[2].append([e.output_torque * x for x in axis])
    if e.output_force:
        load = [e.output_force * x for x in motion.g.guide]
        forces[2].append(load)
        moments[2].append(ref.crossp(p, load))
    if e.coupler_force is not None:
        at, force = e.coupler_force
        point = motion.body_point(1, ref.coupler_local(kind, radius_of(kind), at))(
            motion.poses[4])
        forces[1].append(ref.vec(*force))
        moments[1].append(ref.crossp(point, ref.vec(*force)))
    return forces, moments, bodies_now, p


def residual(terms, plane):
    """|sum| over the largest term, over the components that count (x, y in the plane)."""
    total = [sum(t[i] for t in terms) for i in range(3)]
    largest = max(max(abs(x) for x in t) for t in terms)
    if plane is not None:
        total = [total[i] for i in plane]
    return float(max(abs(x) for x in total) / largest) if largest else 0.0


def check_equilibrium(case):
    lk, phi, branch, b, e = case
    kind = lk.kind
    got = forces_at(lk, phi, branch, b, e)
    with ref.mp.workdps(ref.DIGITS):
        forces, moments, bodies_now, p = wrench_sums(kind, got, lk, b, e, phi, branch)
        plane_f, plane_m = ((0, 1), (2,)) if kind in PLANE_KINDS else (None, None)
        worst = 0.0
        for body in range(3):
            if kind != "spherical":
                worst = max(worst, residual(forces[body], plane_f))
            worst = max(worst, residual(moments[body], plane_m))
        # the frame: minus the ground joints' reactions and the driver's torque
        ground = [(n, r) for n, r in got.joints.items() if TOPOLOGY[n][0] is None]
        shaking_m = [ref.vec(*got.shaking_moment), ref.vec(0, 0, got.torque)]
        for name, r in ground:
            if r.force is not None:
                shaking_m.append(ref.crossp(joint_point(kind, name, None, p, lk),
                                            ref.vec(*r.force)))
            if r.moment is not None:
                shaking_m.append(ref.vec(*r.moment))
        worst = max(worst, residual(shaking_m, None))
        if kind == "spherical":     # the whole linkage's Newton
            g = ref.gravity_vector(kind, e.gravity)
            terms = [[-x for x in got.shaking_force]]
            for body, role in enumerate(("crank", "coupler", "output")):
                m = ref.mpf(getattr(b, role).mass)
                terms += [[m * x for x in g], [-m * x for x in bodies_now[body].acceleration]]
            if e.coupler_force is not None:
                terms.append(ref.vec(*e.coupler_force[1]))
        else:
            terms = [ref.vec(*got.shaking_force)] + [ref.vec(*r.force) for _, r in ground]
        worst = max(worst, residual(terms, None))
    assert worst <= 1e-10, (lk, phi, branch, b, e, worst)
    return worst


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=25, deadline=None)
@given(data=st.data())
def test_every_body_is_in_equilibrium(kind, data):
    check_equilibrium(data.draw(cases(kind, explicit=True)))


# -- closed forms ---------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=20, deadline=None)
@given(data=st.data())
def test_a_static_linkage_obeys_virtual_work(kind, data):
    """Speed 0: T = -(the loads' and weights' generalised forces), from the reference's velocity
    ratios (the motion at one radian per second)."""
    lk, phi, branch, b, e = data.draw(cases(kind, speed=False, explicit=True))
    got = forces_at(lk, phi, branch, b, e)
    with ref.mp.workdps(ref.DIGITS):
        motion = ref.ratios(lk, phi, branch, radius_of(kind))
        g = ref.gravity_vector(kind, e.gravity)
        terms = [ref.loads_power(motion, kind, e, radius_of(kind))]
        for body, role in enumerate(("crank", "coupler", "output")):
            spec = getattr(b, role)
            _, centre, _ = ref.local_body(kind, role, spec)
            rate = motion.velocities(motion.body_point(body, centre))[2]
            terms.append(ref.mpf(spec.mass) * ref.dotp(g, rate))
        expected = float(-sum(terms))
        scale = float(max(abs(t) for t in terms))
    assert abs(got.torque - expected) <= 1e-9 * scale + 1e-12, (got.torque, expected)
    assert got.power == 0.0


def perpendicular(force, along):
    """|force x along| / (|force| |along|)."""
    c = linkage.cross(force, along)
    return math.sqrt(linkage.dot(c, c)) / math.sqrt(linkage.dot(force, force)
                                                    * linkage.dot(along, along))


@pytest.mark.parametrize("kind", LINE_COUPLERS)
@settings(max_examples=20, deadline=None)
@given(data=st.data())
def test_a_massless_skew_coupler_is_a_two_force_member(kind, data):
    lk, phi, branch, b, e = data.draw(cases(kind))
    b = b._replace(coupler=Body(0.0))
    e = e._replace(coupler_force=None)
    got = forces_at(lk, phi, branch, b, e)
    pose = linkage.joint_positions(lk, phi, branch)
    out = linkage.PINS[kind].output_joint
    along = [q - p for p, q in zip(pose.joints["A"], pose.joints[out])]
    for name in ("A", out):
        force = got.joints[name].force
        assume(linkage.dot(force, force) > 1e-12)
        assert perpendicular(force, along) < 1e-10, (name, force, along)
    # and the crank's push at A is what the coupler passes on at its output pin
    assert got.joints["A"].force == pytest.approx(got.joints[out].force,
                                                  abs=1e-10 * max(map(abs, got.joints["A"].force)))


@pytest.mark.parametrize("kind", ("plane", "skew"))
@settings(max_examples=20, deadline=None)
@given(data=st.data())
def test_a_balanced_crank_changes_nothing_else(kind, data):
    """A crank whose centre is on its axis (any mass and inertia) at constant speed: the torque
    and every joint but A0 as with no crank mass; A0 carries its weight."""
    lk, phi, branch, b, e = data.draw(cases(kind))
    e = e._replace(crank_acceleration=0.0)
    mass = data.draw(between(0.1, 50))
    inertia = data.draw(between(0, 5))
    crank = (Body(mass, 0.0, inertia) if kind == "plane" else
             Body(mass, (0.0, 0.0, data.draw(between(-1, 1))),
                  ((inertia, 0, 0), (0, inertia, 0), (0, 0, 2 * inertia))))
    light = forces_at(lk, phi, branch, b._replace(crank=Body(0.0)), e)
    heavy = forces_at(lk, phi, branch, b._replace(crank=crank), e)
    size = max(abs(light.torque), max(abs(x) for r in light.joints.values() for x in r.force))
    assert heavy.torque == pytest.approx(light.torque, abs=1e-11 * size)
    for name in ("A", "B", "B0"):
        assert heavy.joints[name].force == pytest.approx(light.joints[name].force,
                                                         abs=1e-11 * size)
    weight = [mass * x for x in ref.gravity_vector(kind, e.gravity)]
    assert [x - y for x, y in zip(heavy.joints["A0"].force, light.joints["A0"].force)] == \
        pytest.approx([-float(w) for w in weight], abs=1e-11 * (size + mass * 10))


@settings(max_examples=40, deadline=None)
@given(r=between(0.05, 0.5), ratio=between(2.5, 6), m=between(0.1, 20), rpm=between(100, 6000),
       phi=between(0, 360))
def test_the_piston_force_and_torque_are_the_textbooks(r, ratio, m, rpm, phi):
    """Crank r, rod l, no offset, piston mass m, massless crank and rod: F = m x'' omega^2 with
    x = r cos phi + sqrt(l^2 - r^2 sin^2 phi), and T = F dx/dphi."""
    l = r * ratio
    w = 2 * math.pi * rpm / 60
    got = forces_at(Linkage("slider", b=r, c=l, e=0.0), phi, 1,
                    Bodies(Body(0.0), Body(0.0), Body(m)), Effects(speed_rpm=rpm))
    c, s = math.cos(math.radians(phi)), math.sin(math.radians(phi))
    root = math.sqrt(l * l - r * r * s * s)
    x1 = -r * s - r * r * s * c / root
    x2 = -r * c - r * r * (c * c - s * s) / root - r ** 4 * s * s * c * c / root ** 3
    force = m * x2 * w * w
    assert got.joints["C"].force[0] == pytest.approx(force, rel=1e-10, abs=1e-9 * m * r * w * w)
    assert got.torque == pytest.approx(force * x1, rel=1e-10, abs=1e-9 * m * r * r * w * w)
    assert got.joints["guide"].force[1] == pytest.approx(-got.joints["C"].force[1],
                                                         abs=1e-9 * m * r * w * w)


# -- what does not exist, what is unbounded -------------------------------------------------------

def test_no_position_no_forces_and_a_change_point_is_unbounded():
    lk = Linkage("plane", a=4.0, b=1.0, c=2.0, d=3.0)      # a + b = c + d: change point at 180
    bodies = Bodies(Body(1.0), Body(2.0), Body(3.0))
    out = linkage.forces(lk, [180.0, 90.0], 1, bodies, Effects(speed_rpm=100, gravity=9.81))
    assert out[0].status == linkage.UNBOUNDED and out[0].torque is None
    assert out[1].status == linkage.ASSEMBLED
    apart = Linkage("plane", a=10.0, b=1.0, c=2.0, d=3.0)    # never assembles
    (none,) = linkage.forces(apart, [30.0], 1, bodies, Effects())
    assert none.status == linkage.NOT_ASSEMBLED
    assert none[1:6] == (None,) * 5


def test_forces_at_a_dead_centre_are_unbounded_and_finite_near_it():
    """a = 3, b = 4, c = 2, d = 3: at phi = 90 the crank pin is c + d = 5 from B0 (coupler and
    output in line, mu = 0): UNBOUNDED, None. Approaching it every number is finite and the
    torque grows without bound (as psi' psi'', ~ 1 / distance^2)."""
    lk = Linkage("plane", a=3.0, b=4.0, c=2.0, d=3.0)
    phis = [90.0] + [90.0 - 10.0 ** -n for n in range(1, 14)]
    out = linkage.forces(lk, phis, 1, Bodies(Body(1.0), Body(1.0), Body(1.0)),
                         Effects(speed_rpm=60, gravity=9.81))
    assert out[0].status == linkage.UNBOUNDED and out[0][1:6] == (None,) * 5
    torques = []
    for r in out[1:]:
        assert r.status == linkage.ASSEMBLED, r
        values = [r.torque, *r.shaking_force, *r.shaking_moment] + [
            x for j in r.joints.values() for x in j.force]
        assert all(math.isfinite(x) for x in values), r
        torques.append(abs(r.torque))
    assert all(later > 10 * earlier for earlier, later in zip(torques, torques[1:]))


# -- the summary ----------------------------------------------------------------------------------

def test_the_summary_of_a_sine_torque():
    """T = T0 + A sin phi over a turn: peak T0 + A at 90, RMS sqrt(T0^2 + A^2 / 2), the energy
    integral A (1 - cos phi) swings 2 A: flywheel 2 A / (cs omega^2)."""
    t0, amp, rpm, cs = 3.0, 5.0, 120.0, 0.05
    w = 2 * math.pi * rpm / 60
    phis = [i * 0.25 for i in range(1441)]
    results = [linkage.Forces(p, t0 + amp * math.sin(math.radians(p)),
                              (t0 + amp * math.sin(math.radians(p))) * w,
                              {"A0": linkage.Reaction((p, 0.0, 0.0), None)},
                              (0.0, p / 10, 0.0), (0.0, 0.0, -p), linkage.ASSEMBLED, rpm)
               for p in phis]
    got = linkage.forces_summary(results, cs=cs)
    assert got.peak_torque == (pytest.approx(t0 + amp), 90.0)
    assert got.rms_torque == pytest.approx(math.sqrt(t0 ** 2 + amp ** 2 / 2), rel=1e-6)
    assert got.mean_power == pytest.approx(t0 * w, rel=1e-9)
    assert got.peak_joints == {"A0": (360.0, 360.0)}
    assert got.peak_shaking_force == (36.0, 360.0)
    assert got.peak_shaking_moment == (360.0, 360.0)
    assert got.flywheel_inertia == pytest.approx(2 * amp / (cs * w * w), rel=1e-5)


# -- bad input -------------------------------------------------------------------------------------

PLANE = Linkage("plane", a=4.0, b=1.0, c=3.5, d=3.0)
SKEW = Linkage("skew", a=2.0, b=1.0, c=2.5, d=2.0, f=0.5, ksi=30.0)
SPHERE = Linkage("spherical", a=60.0, b=30.0, c=60.0, d=50.0)
ROD = ((0.0, 0, 0), (0, 1.0, 0), (0, 0, 1.0))


@pytest.mark.parametrize("lk, bodies, effects, said", [
    (PLANE, Bodies(crank=Body(-1.0)), Effects(), "crank's mass must not be negative"),
    (PLANE, Bodies(coupler=Body(math.nan)), Effects(), "coupler's mass must be finite"),
    (PLANE, Bodies(output=Body(1.0, 0.5, -0.1)), Effects(), "inertia must not be negative"),
    (PLANE, Bodies(output=Body(1.0, math.inf, 0.1)), Effects(), "centre must be finite"),
    (PLANE, Bodies(crank=Body(1.0, 0.5)), Effects(), "give both its centre and its inertia"),
    (SKEW, Bodies(crank=Body(1.0, (0, 0, 0), ((1, 0, 0), (0, -1, 0), (0, 0, 1)))), Effects(),
     "positive semi-definite"),
    (SKEW, Bodies(crank=Body(1.0, (0, 0, 0), ((1, 2, 0), (0, 1, 0), (0, 0, 1)))), Effects(),
     "symmetric"),
    (SKEW, Bodies(coupler=Body(1.0, (0.5, 0.1, 0), ROD)), Effects(), "centre must lie on it"),
    (SKEW, Bodies(coupler=Body(1.0, (0.5, 0, 0), ((0.0, 0, 0), (0, 1.0, 0), (0, 0, 2.0)))),
     Effects(), "axisymmetric"),
    (SKEW, Bodies(), Effects(coupler_force=((0.5, 0.2), (1, 0, 0))), "v must be 0"),
    (PLANE, Bodies(), Effects(gravity=(0, -9.8, 1.0)), "no z component"),
    (PLANE, Bodies(), Effects(speed_rpm=math.inf), "speed (rpm) must be finite"),
    (PLANE, Bodies(), Effects(output_force=1.0), "load it with output_torque"),
    (SPHERE, Bodies(crank=Body(1.0, (0, 0, 0.5), ((1, 0, 0), (0, 1, 0), (0, 0, math.nan)))),
     Effects(), "inertia must be finite"),
])
def test_bad_input_is_refused_with_a_reason(lk, bodies, effects, said):
    with pytest.raises(ValueError, match=said.replace("(", r"\(").replace(")", r"\)")):
        linkage.forces(lk, [30.0], 1, bodies, effects)
