"""pylinkage as an outside check of the engine on the two plane linkages it models.

pylinkage (https://github.com/HugoFara/pylinkage; MIT licence, pure Python; pinned to 1.3.0 in the
`test` extra) is an independent kinematics package: it solves each joint as a circle-circle or
circle-line intersection, step by step, keeping the intersection nearest the joint's previous
position. Its frames are the engine's (tests/test_physics.py): fourbar(crank=b, coupler=c,
rocker=d, ground=a) turns the crank about the origin and the rocker about (a, 0);
slider_crank(crank=b, rod=c, slide_through=(0, e)) runs the slider on the line y = e.

* Four-bar: Mechanism.step_with_derivatives, the crank at 1 rad/s and no angular acceleration,
  gives each joint's velocity and acceleration from pylinkage's own velocity and acceleration
  solvers (no differencing). With r = C - D the rocker, v_C = psi' k x r and
  a_C = psi'' k x r - psi'^2 r, so psi' = (r x v_C) / |r|^2 and psi'' = (r x a_C) / |r|^2.
  The output angle (degrees), velocity and acceleration (absolute below 1, relative above) must
  agree to 1e-9 where pylinkage's position is well determined. Its circle-circle intersection
  loses digits near a dead centre or change point (the rocker tip near the line of the circles'
  centres) and where the circles are nearly concentric (the crank tip near the rocker pivot of a
  rhombus or kite, where the output link is free): condition() is that intersection's condition
  number K, and the output is compared where K <= K_OUTPUT, velocity and acceleration where
  K <= K_DERIVATIVES (their errors grow as K^2 and K^3: 1.6e-9 in psi'' at K = 28 for the
  parallelogram 8, 7.25, 8, 7.25 near its change point). The engine's own numbers there are held
  to the 50-digit reference by test_engine.py. Measured, 2026-11-25, 2,714 sweeps of 240 points
  (`PYTHONPATH=tests python3 -m support.pylinkage_worst 1500 1` and `1500 2`; a fifth of them
  parallelograms): output compared at 511,062 points, worst 5.3e-11 degree; velocity and
  acceleration at 308,718, worst 1.6e-13 and 4.7e-12; no point where one assembles and the other
  not.
* Slider-crank: pylinkage 1.3.0 gives the slider's position but not its velocity:
  step_with_derivatives leaves the prismatic joint's velocity None ("until the mechanism model
  exposes a line constraint API"), and step_fast_with_kinematics leaves the slider where it
  started (test_pylinkage_gives_no_slider_velocity pins both, so that a pylinkage that learns
  them is noticed). So x' and x'' are differentiated from pylinkage's positions, taken H apart:
  central differences of order 8 on 9 points. Their error is truncation, about
  h^8 x^(9) / 630 (x'') and less for x', negligible for a rod that clears the crank and offset
  (c >= 1.1 (b + |e|): no dead centre, x analytic in a wide strip), plus rounding, the
  positions' error (measured 1e-15 of the size) times sum|w| / h (2.1 / h for x') and
  sum|w| / h^2 (6.3 / h^2 for x''): with h = 0.5 degree, 2e-13 and 8e-11 of the size. Hence
  SLIDER_TOL: 1e-9 for x and x', 1e-8 for x'' (over the linkage's size, or over the value where
  that is larger). Measured over 2 x 28,800 points (the same script, seeds 1 and 2): x 9.6e-16,
  x' 8.7e-14, x'' 2.7e-11.

Branches: the engine names them by the sign of dE/dpsi (the listing's A+B and A-B); pylinkage
keeps, at each step, the root nearest its previous position. Each pylinkage sweep is mapped to
the engine branch whose output equals pylinkage's at its first point; at each later point the
test applies pylinkage's own rule to the engine's two roots (nearest()) and follows it. So the
mapping changes only where pylinkage's does: near a change point, where the other root can be
nearer than the continuation, and at an indeterminate position, where pylinkage's previous
position is the circles' centre and both roots are equally near.

Where one assembles and the other does not: pylinkage's circle_intersect calls two circles
tangent when their distance is within eps = 1e-12 max(distance, r1, r2, 1) of r1 + r2 (or
|r1 - r2|) and returns the one point; the engine decides in 50-digit decimal (zero within 1e-33
of the scale). test_pylinkages_tangent_tolerance builds a four-bar stretched out by less than
that eps: pylinkage assembles it, the engine says not assembled. In the random sweeps every point
where they disagree is collected and must be such a point (within pylinkage's eps of tangency);
the failure message lists them. A sweep starts where K <= K_OUTPUT: started with the crank tip
on the rocker pivot of a rhombus, pylinkage puts the rocker tip on that pivot and cannot go on.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings, strategies as st

import linkage as engine
from support import engine_harness as harness
from support.peers import Peer

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

pl, pl_errors = Peer("pylinkage.mechanism"), Peer("pylinkage.exceptions")   # at their first use

STEP = 1.5                  # degrees between the four-bar's positions
STEPS = 240                 # a whole turn
TOL = 1e-9                  # four-bar: output (degrees), velocity, acceleration
K_OUTPUT = 1e3             # the output is compared where pylinkage's intersection's condition
K_DERIVATIVES = 10.0        # number (condition()) is at most this; velocity and acceleration
#                             where at most this (the errors grow as K, K^2, K^3)
H = 0.5                     # degrees between the slider's positions (the differences' step)
SLIDER_TOL = {"output": 1e-9, "velocity": 1e-9, "acceleration": 1e-8}
PYLINKAGE_EPS = 1e-12       # pylinkage's circle_intersect: tangent within eps * scale
FIRST_DERIVATIVE = (1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280)
SECOND_DERIVATIVE = (-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315,
                     -1 / 560)


def joint_index(mechanism, fragment):
    return next(i for i, j in enumerate(mechanism.joints) if fragment in j.id)


def angle_error(x, y):
    return harness.output_error("plane", {}, x, y)


def pylinkage_four_bar(a, b, c, d, phi0, pylinkage_branch, steps=STEPS):
    """pylinkage's sweep from phi0 by STEP: [(phi, psi, psi', psi'', rocker tip)] up to the first
    position it cannot build, and whether it stopped there."""
    mechanism = pl.fourbar(crank=b, coupler=c, rocker=d, ground=a, omega=math.radians(STEP),
                        initial_angle=math.radians(phi0), branch=pylinkage_branch)
    mechanism.set_input_velocity(mechanism._driver_links[0], 1.0, 0.0)
    tip, rocker = joint_index(mechanism, "crank.tip"), joint_index(mechanism, "rocker.0")
    points = []
    try:
        for positions, velocities, accelerations in mechanism.step_with_derivatives(steps):
            (bx, by), (cx, cy) = positions[tip], positions[rocker]
            rx, ry = cx - a, cy
            r2 = rx * rx + ry * ry
            velocity = acceleration = None          # pylinkage's, None where it has none
            if velocities[rocker] is not None and accelerations[rocker] is not None:
                (vx, vy), (ax, ay) = velocities[rocker], accelerations[rocker]
                velocity, acceleration = (rx * vy - ry * vx) / r2, (rx * ay - ry * ax) / r2
            points.append((math.degrees(math.atan2(by, bx)), math.degrees(math.atan2(ry, rx)),
                           velocity, acceleration, (cx, cy)))
    except pl_errors.UnbuildableError:
        return points, True
    return points, False


def four_bar_tangency(a, b, c, d, phi):
    """How far from tangent pylinkage's two circles are at phi, in units of its eps: the coupler
    circle about the crank tip and the rocker circle about (a, 0)."""
    bx, by = b * math.cos(math.radians(phi)), b * math.sin(math.radians(phi))
    distance = math.hypot(a - bx, by)
    eps = PYLINKAGE_EPS * max(distance, c, d, 1.0)
    return min(abs(distance - (c + d)), abs(distance - abs(c - d))) / eps


def rocker_tip(a, d, psi):
    return (a + d * math.cos(math.radians(psi)), d * math.sin(math.radians(psi)))


def condition(a, b, c, d, phi, psi):
    """The condition number of pylinkage's circle-circle intersection for the rocker tip C at
    (phi, psi): its position error is about eps L^2 / h, h the height of C over the line of the
    centres B and D, L the largest of c, d and |B - D|, and psi's is that over d; nearly
    concentric circles (|B - D| small) lose L / |B - D| besides. K = L^2 / (h d) + L / |B - D|."""
    bx, by = b * math.cos(math.radians(phi)), b * math.sin(math.radians(phi))
    cx, cy = rocker_tip(a, d, psi)
    distance = math.hypot(a - bx, by)
    if distance == 0.0:
        return math.inf
    height = abs((cx - bx) * (0.0 - by) - (cy - by) * (a - bx)) / distance
    size = max(c, d, distance)
    return math.inf if height == 0.0 else size * size / (height * d) + size / distance


def nearest(a, d, link, phi, previous):
    """The engine's branch whose rocker tip at phi is nearest pylinkage's previous one (previous):
    the root pylinkage keeps (its solve_revolute); None where the two are equally near to 1e-12.
    (pylinkage's previous tip need not be a position of the linkage: at an indeterminate
    position, concentric circles, its circle_intersect reports "the same circle" and
    solve_revolute puts the tip on the circles' centre.)"""
    px, py = previous
    gaps = {}
    for branch in (1, 2):
        psi = link.motion(phi, branch, 0).output
        if psi is not None:
            cx, cy = rocker_tip(a, d, psi)
            gaps[branch] = math.hypot(cx - px, cy - py)
    if len(gaps) < 2:
        return next(iter(gaps), None)
    if abs(gaps[1] - gaps[2]) <= 1e-12 * max(a, d, 1.0):
        return None
    return min(gaps, key=gaps.get)


def engine_branch(link, phi, output, slider=False):
    """The engine's branch whose output at phi is pylinkage's; None if neither or both."""
    matches = []
    for branch in (1, 2):
        m = link.motion(phi, branch)
        if m.output is not None:
            error = abs(m.output - output) if slider else angle_error(m.output, output)
            if error <= 1e-6:
                matches.append(branch)
    return matches[0] if len(matches) == 1 else None


length = st.floats(0.3, 10.0)


def startable(a, b, c, d, phi0):
    """Assembled at phi0 with the branches apart, and pylinkage's intersection well conditioned:
    a start pylinkage can make."""
    link = engine.Linkage("plane", a=a, b=b, c=c, d=d)
    m1, m2 = link.motion(phi0, 1), link.motion(phi0, 2)
    return (m1.status == engine.ASSEMBLED and angle_error(m1.output, m2.output) > 1.0
            and condition(a, b, c, d, phi0, m1.output) <= K_OUTPUT)


def compare_four_bar(a, b, c, d, phi0, pylinkage_branch):
    """pylinkage's sweep against the engine: ([(what, phi, error, K)] where compared,
    [(phi, what)] where one assembles and the other does not)."""
    link = engine.Linkage("plane", a=a, b=b, c=c, d=d)
    points, stopped = pylinkage_four_bar(a, b, c, d, phi0, pylinkage_branch)
    branch = engine_branch(link, *points[0][:2]) if points else 1   # (a status: both branches)
    assert branch is not None, points[0]
    compared, disagree, previous = [], [], points[0][4] if points else None
    for phi, psi, velocity, acceleration, tip in points:
        m = link.motion(phi, branch)
        if m.output is None:
            disagree.append((phi, f"pylinkage assembles, the engine says {m.status}"))
            continue
        kept = nearest(a, d, link, phi, previous) or engine_branch(link, phi, psi) or branch
        if kept != branch:                              # pylinkage's nearest root: the other
            branch, m = kept, link.motion(phi, kept)
        previous = tip
        k = condition(a, b, c, d, phi, m.output)
        if k <= K_OUTPUT:
            compared.append(("output", phi, angle_error(m.output, psi), k))
        if m.status == engine.ASSEMBLED and k <= K_DERIVATIVES and velocity is not None:
            compared.append(("velocity", phi, harness.ratio_error(velocity, m.velocity), k))
            compared.append(("acceleration", phi,
                             harness.ratio_error(acceleration, m.acceleration), k))
    if stopped:                         # the next angle, where pylinkage could not build
        phi = points[-1][0] + STEP if points else phi0 + STEP
        if link.motion(phi, branch).status != engine.NOT_ASSEMBLED:
            disagree.append((phi, "the engine assembles, pylinkage does not"))
    return compared, disagree


@settings(max_examples=60)
@given(length, length, length, length, st.floats(-180.0, 180.0), st.sampled_from((0, 1)))
def test_random_four_bars(a, b, c, d, phi0, pylinkage_branch):
    assume(startable(a, b, c, d, phi0))
    compared, disagree = compare_four_bar(a, b, c, d, phi0, pylinkage_branch)
    beyond = [point for point in compared if point[2] > TOL]
    assert not beyond, f"a={a} b={b} c={c} d={d}: {beyond[:5]}"
    unexplained = [(phi, what, four_bar_tangency(a, b, c, d, phi)) for phi, what in disagree
                   if four_bar_tangency(a, b, c, d, phi) > 1.0]
    assert not unexplained, f"a={a} b={b} c={c} d={d}: {unexplained}"


def test_pylinkages_tangent_tolerance():
    """A four-bar stretched out (coupler and rocker in line) at phi0 = 120 to within half of
    pylinkage's eps: pylinkage builds it (one point, its tangent case), the engine's 50 digits say
    it does not close (its discriminant is -1e-12 of the scale, far below -1e-33); a hair
    shorter still, 3 eps, pylinkage refuses too."""
    a, b, phi0 = 6.0, 2.0, 120.0
    reach = math.hypot(a - b * math.cos(math.radians(phi0)), b * math.sin(math.radians(phi0)))
    for shortfall, pylinkage_builds in ((0.5, True), (3.0, False)):
        c = 0.4 * reach
        d = reach - c - shortfall * PYLINKAGE_EPS * reach
        link = engine.Linkage("plane", a=a, b=b, c=c, d=d)
        assert link.motion(phi0, 1).status == engine.NOT_ASSEMBLED
        if pylinkage_builds:
            mechanism = pl.fourbar(crank=b, coupler=c, rocker=d, ground=a,
                                initial_angle=math.radians(phi0))
            tip = mechanism.joints[joint_index(mechanism, "rocker.0")].position
            psi = math.degrees(math.atan2(tip[1], tip[0] - a))
            crank = (b * math.cos(math.radians(phi0)), b * math.sin(math.radians(phi0)))
            assert psi == pytest.approx(math.degrees(math.atan2(crank[1], crank[0] - a)), abs=1e-5)
        else:
            with pytest.raises(pl_errors.UnbuildableError):
                pl.fourbar(crank=b, coupler=c, rocker=d, ground=a, initial_angle=math.radians(phi0))


# -- the slider-crank: positions, differentiated ---------------------------------------------------

def pylinkage_slider(b, c, e, phi0, steps):
    """pylinkage's slider positions from phi0 by H degrees: [(phi, x)]."""
    mechanism = pl.slider_crank(crank=b, rod=c, omega=math.radians(H),
                             initial_angle=math.radians(phi0), slide_through=(0.0, e))
    tip, slider = joint_index(mechanism, "crank.tip"), joint_index(mechanism, "rod.1")
    points = []
    for positions in mechanism.step(steps):
        (bx, by), (x, y) = positions[tip], positions[slider]
        assert abs(y - e) <= 1e-12 * max(1.0, abs(e))
        points.append((math.degrees(math.atan2(by, bx)), x))
    return points


def compare_slider(b, e, margin, phi0, steps=80):
    """pylinkage's slider positions against the engine, differentiated: [(what, phi, error)],
    the error over the linkage's size (or over the value, where larger)."""
    c = (b + abs(e)) * (1.0 + margin)
    link = engine.Linkage("slider", b=b, c=c, e=e)
    points = pylinkage_slider(b, c, e, phi0, steps)
    size = max(b, c, abs(e))
    branch = engine_branch(link, *points[0], slider=True)
    assert branch is not None, points[0]
    h, compared = math.radians(H), []
    for k in range(4, len(points) - 4):
        phi, x = points[k]
        m = link.motion(phi, branch)
        assert m.status == engine.ASSEMBLED
        xs = [p[1] for p in points[k - 4:k + 5]]
        velocity = sum(w * v for w, v in zip(FIRST_DERIVATIVE, xs)) / h
        acceleration = sum(w * v for w, v in zip(SECOND_DERIVATIVE, xs)) / (h * h)
        for what, got, want in (("output", x, m.output), ("velocity", velocity, m.velocity),
                                ("acceleration", acceleration, m.acceleration)):
            compared.append((what, phi, abs(got - want) / max(size, abs(want))))
    return compared


@settings(max_examples=40)
@given(length, st.floats(-5.0, 5.0), st.floats(0.1, 2.0), st.floats(-180.0, 180.0))
def test_random_slider_cranks(b, e, margin, phi0):
    """A rod that clears crank and offset, c = (b + |e|)(1 + margin): the crank turns fully, no
    dead centre within a strip of the real axis. x to 1e-9 of the size; x' and x'' from
    differences of pylinkage's positions (SLIDER_TOL)."""
    beyond = [p for p in compare_slider(b, e, margin, phi0) if p[2] > SLIDER_TOL[p[0]]]
    assert not beyond, beyond[:5]


def test_pylinkage_gives_no_slider_velocity():
    """Why the slider's derivatives are differentiated (the docstring): pylinkage 1.3.0's two
    kinematic paths give none. Should a later pylinkage give them, compare them directly."""
    mechanism = pl.slider_crank(crank=2.0, rod=7.0, omega=math.radians(1.0),
                             slide_through=(0.0, 1.5))
    mechanism.set_input_velocity(mechanism._driver_links[0], 1.0, 0.0)
    slider = joint_index(mechanism, "rod.1")
    _, velocities, _ = next(mechanism.step_with_derivatives(1))
    assert velocities[slider] is None
    positions = mechanism.step_fast_with_kinematics(3)[0]          # (steps, joints, 2)
    on_rail = [j for j in range(positions.shape[1])
               if (abs(positions[:, j, 1] - 1.5) < 1e-12).all()]
    assert on_rail and all((positions[:, j] == positions[0, j]).all() for j in on_rail)
