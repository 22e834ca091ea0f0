"""Linkage.forces_arrays (the forces on numpy arrays, the chain eliminated body by body) held to
Linkage.forces (the whole system solved by Gaussian elimination) on hypothesis-drawn linkages,
bodies, loads and speeds of all five kinds: the same statuses everywhere, the same numbers to
1e-10 of each position's largest where the transmission angle is well away from 0 and 180, in
blocks made small here so that every sweep crosses several; through a dead centre and a change
point; and what forces_summary now takes from the results (their speed) rather than from its
caller."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import linkage
from linkage import Bodies, Body, Effects, Linkage
from test_forces import DIMENSIONS, KINDS, between, bodies, effects, radius_of


def numbers_of(f):
    """A Forces' numbers in one flat list: torque, power, the joints', the shaking."""
    return [f.torque, f.power] + [x for r in f.joints.values() for part in r
                                  if part is not None for x in part] + [
        *f.shaking_force, *f.shaking_moment]


def check_alike(lk, phis, branch, b, e, well=(5.0, 175.0)):
    """forces_arrays, and forces_of_arrays on the sweep made whole first, against forces at
    `phis`: statuses identical; numbers to 1e-10 of each position's largest where mu is inside
    `well` (1e-6 elsewhere: near a dead centre both are the same ill-conditioned answer, each
    to its own rounding)."""
    radius = radius_of(lk.kind)
    scalar = linkage.forces(lk, phis, branch, b, e, radius=radius)
    arrays = lk.forces_arrays(np.array(phis), branch, b, e, radius=radius)
    trig = {}
    apart = linkage.forces_of_arrays(lk, linkage.motion_arrays_of(lk, phis, branch, 2, trig),
                                     branch, b, e, radius=radius, trig=trig)
    mus = lk.transmission(phis, branch)
    for answer in (arrays, apart):
        assert answer.speed_rpm == e.speed_rpm
        for s, a, mu in zip(scalar, answer.forces(), mus):
            assert a.status == s.status, (s.phi, s.status, a.status)
            assert a.phi == s.phi and a.speed_rpm == s.speed_rpm
            if s.torque is None:
                assert a[1:6] == (None,) * 5, a
                continue
            assert list(a.joints) == list(s.joints)
            assert [[p is None for p in r] for r in a.joints.values()] == \
                [[p is None for p in r] for r in s.joints.values()]
            want, got = numbers_of(s), numbers_of(a)
            scale = max(map(abs, want)) or 1.0
            tolerance = 1e-10 if mu is not None and well[0] < mu < well[1] else 1e-6
            worst = max(abs(x - y) for x, y in zip(want, got)) / scale
            assert worst <= tolerance, (s.phi, mu, worst)
    return scalar, arrays


@pytest.fixture(autouse=True)
def small_blocks(monkeypatch):
    """Blocks of 7 angles: every sweep here crosses several, as a long sweep crosses 16384s."""
    monkeypatch.setattr(linkage, "FAST_BLOCK", 7)


@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=25, deadline=None)
@given(data=st.data())
def test_the_arrays_are_the_scalar_forces(kind, data):
    lk = Linkage(kind, **data.draw(DIMENSIONS[kind]))
    branch = data.draw(st.sampled_from([1, 2]))
    start = data.draw(between(0, 360))
    phis = [start + 360.0 * i / 23 for i in range(24)] + data.draw(
        st.lists(between(-720, 720), max_size=6))
    assume(any(m.status == linkage.ASSEMBLED for m in lk.sweep(phis, branch, 0)))
    check_alike(lk, phis, branch, data.draw(bodies(kind)), data.draw(effects(kind)))


def test_through_a_dead_centre_and_a_change_point():
    """The dead centre of test_forces (a = 3, b = 4, c = 2, d = 3, phi = 90) approached to 1e-13
    and reached (there forces() hands the position back: UNBOUNDED), a change point (a + b =
    c + d, phi = 180), and a linkage that never assembles: the statuses are forces()'."""
    heavy = Bodies(Body(1.0), Body(1.0), Body(1.0))
    effects_ = Effects(speed_rpm=60, gravity=9.81)
    dead = Linkage("plane", a=3.0, b=4.0, c=2.0, d=3.0)
    phis = [90.0] + [90.0 - 10.0 ** -n for n in range(1, 14)] + [60.0, 120.0]
    scalar, arrays = check_alike(dead, phis, 1, heavy, effects_)
    assert scalar[0].status == linkage.UNBOUNDED
    assert linkage.FORCES_STATUS_CODES[arrays.status[0]] == linkage.UNBOUNDED
    assert math.isnan(arrays.torque[0]) and np.isnan(arrays.joints["B"].force[0]).all()
    change = Linkage("plane", a=4.0, b=1.0, c=2.0, d=3.0)
    scalar, _ = check_alike(change, [170.0, 180.0, 190.0], 1, heavy, effects_)
    assert scalar[1].status == linkage.UNBOUNDED
    apart = Linkage("plane", a=10.0, b=1.0, c=2.0, d=3.0)
    scalar, arrays = check_alike(apart, [0.0, 30.0], 1, heavy, effects_)
    assert {f.status for f in scalar} == {linkage.NOT_ASSEMBLED}
    assert np.isnan(arrays.shaking_moment).all()


ROCKERS = {"plane": dict(a=3.0, b=2.5, c=2.0, d=2.0),
           "spherical": dict(a=60.0, b=50.0, c=55.0, d=40.0),
           "skew": dict(a=2.0, b=1.5, c=2.0, d=1.5, f=0.3, ksi=20.0),
           "slider": dict(b=2.0, c=1.5, e=0.2),
           "skew-slider": dict(a=1.0, b=1.5, c=1.2, f=0.3, ksi=30.0)}


def limit_of_assembly(lk):
    """An input angle where the linkage stops assembling (bisected to the last bit): there the
    output is at a dead centre, mu = 0 or 180, and its forces grow without bound."""
    phis = [i * 1.0 for i in range(361)]
    ok = [m.status == linkage.ASSEMBLED for m in lk.sweep(phis, 1, 0)]
    i = next(i for i in range(360) if ok[i] and not ok[i + 1])
    low, high = phis[i], phis[i + 1]
    while low < (middle := (low + high) / 2) < high:
        low, high = (middle, high) if lk.motion(middle, 1, 0).status == linkage.ASSEMBLED \
            else (low, middle)
    return low


@pytest.mark.parametrize("kind", KINDS)
def test_toward_a_limit_of_assembly(kind, monkeypatch):
    """Each kind's crank driven toward the angle where it stops assembling, to 1e-13 and onto
    it: where the elimination's divisor is small the numpy path hands the position to forces()
    (seen here), and the statuses are forces()' all the way."""
    lk = Linkage(kind, **ROCKERS[kind])
    limit = limit_of_assembly(lk)
    phis = [limit - 10.0 ** -n for n in range(1, 14)] + [limit, limit + 1e-9, limit - 30.0]
    masses, load = Bodies(Body(1.0), Body(2.0), Body(0.5)), Effects(speed_rpm=120, gravity=9.81)
    scalar, _ = check_alike(lk, phis, 1, masses, load)
    assert scalar[-1].status == linkage.ASSEMBLED
    handed = []
    forces = linkage.forces
    monkeypatch.setattr(linkage, "forces", lambda lk, phis, *a, **k: (
        handed.extend(phis), forces(lk, phis, *a, **k))[1])
    lk.forces_arrays(np.array(phis), 1, masses, load, radius=radius_of(kind))
    assert handed and limit - 30.0 not in handed and limit - 0.1 not in handed, handed


@pytest.mark.parametrize("kind", KINDS)
def test_from_rest_the_crank_accelerating(kind):
    """At speed 0 with the crank accelerating (the output's rates then its acceleration's alone:
    the skew kinds' closed form takes them from psi' times alpha, not psi'' times w^2), under
    gravity, with an output load: the numbers are forces()'."""
    lk = Linkage(kind, **ROCKERS[kind])
    load = dict(output_force=3.0) if kind in linkage.SLIDER_CRANKS else dict(output_torque=2.0)
    scalar, _ = check_alike(lk, [7.0 + 10.0 * i for i in range(36)], 1,
                            Bodies(Body(1.0), Body(2.0), Body(0.5)),
                            Effects(speed_rpm=0.0, crank_acceleration=50.0, gravity=9.81, **load))
    assert any(f.status == linkage.ASSEMBLED and f.torque for f in scalar)


@pytest.mark.parametrize("kind", KINDS)
def test_a_power_beyond_the_floats_is_the_scalar_forms_overflow(kind):
    """At 1e150 rpm the torque is a number but the power (torque times the speed) is not: forces()
    says overflow there, and so must forces_arrays (it said assembled, its power an inf, and
    numpy warned), its numbers forces()' (none)."""
    lk = Linkage(kind, **ROCKERS[kind])
    scalar, arrays = check_alike(lk, [7.0 + 10.0 * i for i in range(36)], 1,
                                 Bodies(Body(1.0), Body(2.0), Body(0.5)),
                                 Effects(1e150, gravity=9.81))
    statuses = {f.status for f in scalar}
    assert linkage.OUT_OF_RANGE in statuses <= {linkage.OUT_OF_RANGE, linkage.NOT_ASSEMBLED}
    assert np.isnan(arrays.power).all()


@pytest.mark.parametrize("kind", KINDS)
def test_numbers_beyond_the_floats_are_the_scalar_forms_overflow(kind):
    """Bodies of 1e306 kg: at some angles a reaction or the shaking is beyond the floats' range
    (the torque and power not always), and forces() says overflow there; forces_arrays must say
    it at the same angles (its plan's numbers checked a block at a time)."""
    lk = Linkage(kind, **dict(linkage.BENCH_LINKAGES)[kind])
    heavy = Bodies(Body(1e306), Body(1e306), Body(1e306))
    scalar, _ = check_alike(lk, [7.0 + 5.0 * i for i in range(72)], 1, heavy,
                            Effects(60.0, gravity=1.0))
    if kind != "spherical":             # its numbers stay in range at these masses
        assert {f.status for f in scalar} == {linkage.ASSEMBLED, linkage.OUT_OF_RANGE}


def test_the_plane_slider_s_guide_pushes_across_it_only():
    """The plane slider-crank's guide (along x) carries no force along itself nor out of the
    plane: those parts of its reaction are 0 exactly, as in forces(), not 0 to rounding."""
    lk = Linkage("slider", **ROCKERS["slider"])
    arrays = lk.forces_arrays(np.linspace(0.0, 360.0, 37), 1, Bodies(Body(1.0), Body(2.0),
                                                                    Body(0.5)),
                              Effects(120.0, gravity=9.81, output_force=3.0))
    assembled = arrays.status == linkage.FORCES_STATUS_CODES.index(linkage.ASSEMBLED)
    force = arrays.joints["guide"].force[assembled]
    assert len(force) and (force[:, [0, 2]] == 0.0).all() and (force[:, 1] != 0.0).all()


def test_a_kept_plan_is_the_one_for_its_call():
    """forces_of_arrays keeps the traced formulas per linkage object, bodies, effects and
    radius: calls on one linkage alternating two sets of bodies and two speeds each agree with
    forces(), and bodies given as lists (not to be kept) are taken all the same."""
    lk = Linkage("skew", a=2.0, b=1.5, c=2.0, d=1.5, f=0.3, ksi=20.0)
    light, heavy = Bodies(Body(1.0), Body(2.0), Body(0.5)), Bodies(Body(3.0), Body(0.1), Body(1.0))
    listed = Bodies(Body(1.0, [0.5, 0.1, 0.0], [[0.1, 0, 0], [0, 0.2, 0], [0, 0, 0.3]]))
    phis = [0.0, 40.0, 80.0, 200.0]
    for b, e in [(light, Effects(60.0)), (heavy, Effects(60.0)), (light, Effects(90.0)),
                 (light, Effects(60.0)), (listed, Effects(60.0, gravity=9.81))]:
        scalar, _ = check_alike(lk, phis, 1, b, e)
        assert all(f.status == linkage.ASSEMBLED for f in scalar)


def test_bad_input_is_refused_as_forces_refuses_it():
    lk = Linkage("plane", a=4.0, b=1.0, c=3.5, d=3.0)
    with pytest.raises(ValueError, match="mass must not be negative"):
        lk.forces_arrays([10.0], 1, Bodies(Body(-1.0)))
    with pytest.raises(ValueError, match="velocity and acceleration"):
        linkage.forces_of_arrays(lk, lk.sweep_arrays([10.0], 1, 0))


# -- the summary takes the speed the forces were computed at ----------------------------------------

def test_the_summary_s_speed_is_the_results():
    """The flywheel is ΔE / (cs ω²) at the speed the forces carry: the same torque curve at
    twice the speed (inertia forces alone, so four times the torque) needs the same flywheel;
    forces at two speeds have no one summary; the speed is no argument of forces_summary."""
    lk = Linkage("plane", a=0.3, b=0.1, c=0.35, d=0.45)
    masses = Bodies(Body(0.5), Body(1.2), Body(1.5))
    slow = lk.forces(range(0, 361, 5), 1, masses, Effects(speed_rpm=100))
    fast = lk.forces(range(0, 361, 5), 1, masses, Effects(speed_rpm=200))
    assert fast[7].torque == pytest.approx(4 * slow[7].torque, rel=1e-12)
    assert linkage.forces_summary(fast).flywheel_inertia == pytest.approx(
        linkage.forces_summary(slow).flywheel_inertia, rel=1e-9)
    with pytest.raises(ValueError, match="different speeds"):
        linkage.forces_summary(slow + fast)
    with pytest.raises(TypeError):
        linkage.forces_summary(slow, 100.0)       # type: ignore[misc]
    arrays = lk.forces_arrays(np.arange(0.0, 361.0, 5.0), 1, masses, Effects(speed_rpm=100))
    assert linkage.forces_summary(arrays.forces()).flywheel_inertia == pytest.approx(
        linkage.forces_summary(slow).flywheel_inertia, rel=1e-9)
