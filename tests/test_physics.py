"""Physical proof of the fixed listing: its formulas close each mechanism's loop.

For each of the five mechanisms the loop closure is written here from first principles, in the
geometry and sign conventions that the listing's coefficients imply (derived by expanding each
closure in t = tan(phi/2), u = tan(psi/2) and matching lines 540-930 term by term; the
derivation is summarised in each function's docstring). The listing itself is then run under
PC-BASIC in double precision (basic_runner.double_precision_variant: formula lines untouched) and
every point it writes must

  * close the loop to round-off (ANG.DAT), and
  * have the velocity (VEL.DAT) and acceleration (ACC.DAT) ratios of finite differences of the
    displacement it wrote: a 5-point central difference with h = 0.01 degree.

A wrong correction in legacy_basic/ERRATA.md makes one of these fail; test_errata.py reverts each
correction in turn and checks that one does.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import pytest

from support import basic_runner

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

H_DEG = 0.01          # finite-difference step, degrees
CLOSURE_TOL = 1e-12   # loop-closure residual, relative to the largest link (measured: 2.2e-15)
VEL_TOL = 1e-9        # |VEL - finite difference of ANG|, absolute (measured: 1.3e-11)
ACC_TOL = 1e-9        # |ACC - finite difference of VEL|, absolute (measured: 1.2e-11)
CLIP = 3.0            # the listing writes ratios clipped to +-3


def _rot_y(angle: float, v: tuple[float, float, float]) -> tuple[float, float, float]:
    """Rotate v by `angle` about the y axis (z turns toward +x)."""
    c, s = math.cos(angle), math.sin(angle)
    return (c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2])


def _dist(p, q) -> float:
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(p, q)))


def plane_four_bar(dims, phi, psi) -> float:
    """Crank pivot at the origin, output pivot at (a, 0); crank b at phi, output d at psi, both
    counter-clockwise from +x; coupler c joins the tips. |B - D|^2 - c^2, times
    (1 + t^2)(1 + u^2)/4, is exactly lines 880-930 (A1 = p7 p8, ..., A4 = -2bd, A5 = p5 p6)."""
    a, b, c, d = dims["a"], dims["b"], dims["c"], dims["d"]
    tip_b = (b * math.cos(phi), b * math.sin(phi))
    tip_d = (a + d * math.cos(psi), d * math.sin(psi))
    return (_dist(tip_b, tip_d) - c) / max(a, b, c, d)


def spherical_four_bar(dims, phi, psi) -> float:
    """Unit sphere; input axis z, output axis at arc a from it toward +x (rotation about y).
    Crank tip at polar arc b, azimuth phi about z; output tip at arc d from the output axis,
    azimuth psi in the output axis's frame (the image of x, y under the same rotation);
    closure B.D = cos c. (B.D - cos c) times -(1 + t^2)(1 + u^2)/2 is lines 810-860."""
    a, b, c, d = (math.radians(dims[k]) for k in "abcd")
    tip_b = (math.sin(b) * math.cos(phi), math.sin(b) * math.sin(phi), math.cos(b))
    tip_d = _rot_y(a, (math.sin(d) * math.cos(psi), math.sin(d) * math.sin(psi), math.cos(d)))
    return sum(x * y for x, y in zip(tip_b, tip_d)) - math.cos(c)


def skew_four_bar(dims, phi, psi) -> float:
    """Input axis z; crank b turns in the plane z = 0. The output axis has direction
    w = (0, -sin xi, cos xi): twisted by xi about the common perpendicular, which runs along x,
    has length a, and meets the input axis at z = f. The output crank d turns in the plane
    spanned by e1 = (1, 0, 0) and e2 = (0, cos xi, sin xi) about the centre Q lying g along -w
    from the perpendicular's foot: Q = (a, g sin xi, f - g cos xi), g = f / cos xi (line 420,
    which puts Q in the crank's plane z = 0). The coupler c is the real length typed in.
    Expanding |B - D|^2 - c^2 gives A4 = -2bd cos xi, A6 = -gb sin xi, A7 = fd sin xi and the
    effective coupler c^2 - f^2 - g^2 + 2fg cos xi of line 430 (lines 650-710)."""
    a, b, c, d, f = dims["a"], dims["b"], dims["c"], dims["d"], dims["f"]
    xi = math.radians(dims["ksi"])
    g = f / math.cos(xi)
    tip_b = (b * math.cos(phi), b * math.sin(phi), 0.0)
    centre = (a, g * math.sin(xi), f - g * math.cos(xi))
    e1, e2 = (1.0, 0.0, 0.0), (0.0, math.cos(xi), math.sin(xi))
    tip_d = tuple(q + d * (math.cos(psi) * x + math.sin(psi) * y)
                  for q, x, y in zip(centre, e1, e2))
    return (_dist(tip_b, tip_d) - c) / max(a, b, c, d, f)


def plane_slider_crank(dims, phi, x) -> float:
    """Crank b about the origin; the slider moves on the line y = e (the listing's sign:
    I1 = -4eb, where Table 1 prints +4eb); x is the slider's abscissa; rod length c (the c* of
    Fig. 2, line 450 forms c = sqrt(c*^2 - e^2)). |B - D|^2 - c^2 times (1 + t^2) is lines 740-790
    with a = d = 0 (neither is asked for)."""
    b, c, e = dims["b"], dims["c"], dims["e"]
    return (_dist((b * math.cos(phi), b * math.sin(phi)), (x, e)) - c) / max(b, c, abs(e))


def skew_slider_crank(dims, phi, x) -> float:
    """Crank b turns in the plane z = 0 about z; the slider's line passes through (a, 0, f), the
    foot of the common perpendicular of length a, with direction s = (0, sin xi, -cos xi); x is the
    slider's position along s. |B - D|^2 - c^2 times (1 + t^2) gives A4 = -4b sin xi,
    A8 = A10 = -2f cos xi and the effective coupler c^2 - f^2 of line 430 (G = 0, line 410)."""
    a, b, c, f = dims["a"], dims["b"], dims["c"], dims["f"]
    xi = math.radians(dims["ksi"])
    tip_b = (b * math.cos(phi), b * math.sin(phi), 0.0)
    slider = (a, x * math.sin(xi), f - x * math.cos(xi))
    return (_dist(tip_b, slider) - c) / max(a, b, c, abs(f))


@dataclasses.dataclass(frozen=True)
class Mechanism:
    key: str                       # menu key
    prompts: tuple[str, ...]       # dimensions in the order the listing asks for them
    closure: Callable[[dict, float, float], float]
    slider: bool                   # output is a length (ANG.DAT holds x), not an angle


MECHANISMS = {
    "plane": Mechanism("1", ("b", "c", "d", "a"), plane_four_bar, False),
    "spherical": Mechanism("2", ("b", "c", "d", "a"), spherical_four_bar, False),
    "skew": Mechanism("3", ("b", "c", "d", "a", "f", "ksi"), skew_four_bar, False),
    "slider": Mechanism("4", ("b", "c", "e"), plane_slider_crank, True),
    "skew-slider": Mechanism("5", ("b", "c", "a", "f", "ksi"), skew_slider_crank, True),
}

# Linkages that assemble over the whole sweep. "imaginary" has c^2 < f^2 tan^2 xi: the listing's
# CIM = 1 path (complex p's, lines 590-630).
CASES = {
    "plane-crank-rocker": ("plane", dict(a=6, b=2, c=7, d=9)),
    "plane-second": ("plane", dict(a=4, b=1, c=3.5, d=3)),
    "spherical": ("spherical", dict(a=80, b=20, c=75, d=60)),
    "spherical-wobble": ("spherical", dict(a=90, b=15, c=90, d=90)),
    "skew": ("skew", dict(a=6, b=2, c=7, d=9, f=1.5, ksi=25)),
    "skew-imaginary": ("skew", dict(a=3, b=0.5, c=1.5, d=3, f=3, ksi=30)),
    "slider": ("slider", dict(b=2, c=7, e=1.5)),
    "skew-slider": ("skew-slider", dict(a=6, b=1, c=7.5, f=3, ksi=45)),
}
# Typed before the first case's session so that the menu's other paths run too: an invalid key
# (the bell, line 240) and an illegal linkage (lines 500-510), then back to the menu.
DETOUR = b"x" + b"11\r1\r1\r20\r" + b" "
COARSE = (3.0, 357.0, 24.0)        # from, to, step (degrees): avoids t = tan(phi/2) infinite
STENCIL_CENTRES = (41.0, 233.0)


def _number(x: float) -> bytes:
    return repr(x).encode() if x != int(x) else b"%d" % int(x)


def session_keys(mechanism: Mechanism, dims: dict, start: float, stop: float, step: float,
                 branch: int) -> bytes:
    """The keystrokes of one session: menu key, dimensions, bounds, step, branch key."""
    values = [dims[name] for name in mechanism.prompts] + [start, stop, step]
    return mechanism.key.encode() + b"".join(_number(v) + b"\r" for v in values) + b"%d" % branch


@dataclasses.dataclass(frozen=True)
class Sweep:
    case: str
    branch: int
    kind: str          # "coarse" or "stencil"
    keys: bytes
    points: int = 5    # how many points the session writes


def sweeps(cases=tuple(CASES), centres=STENCIL_CENTRES, branches=(1, 2),
           coarse=COARSE, detour=True) -> list[Sweep]:
    """The sessions that check `cases`: a coarse sweep and a 5-point stencil per centre, for
    each branch; the very first session takes the DETOUR through the menu's other paths (a
    plane four-bar's: the variables it sets stay for the next session, and a slider-crank's
    sessions, which do not ask for a and d, would use them)."""
    out = []
    for case in cases:
        kind, dims = CASES[case]
        mech = MECHANISMS[kind]
        for branch in branches:
            start, stop, step = coarse
            points = int((stop - start) // step) + 1
            out.append(Sweep(case, branch, "coarse", session_keys(mech, dims, *coarse, branch),
                             points))
            for centre in centres:
                keys = session_keys(mech, dims, centre - 2 * H_DEG, centre + 2 * H_DEG, H_DEG,
                                    branch)
                out.append(Sweep(case, branch, "stencil", keys))
    if detour:
        out[0] = dataclasses.replace(out[0], keys=DETOUR + out[0].keys)
    return out


def _unwrap(values: list[float]) -> list[float]:
    out = [values[0]]
    for v in values[1:]:
        out.append(v + 360.0 * round((out[-1] - v) / 360.0))
    return out


def _derivative(phis: list[float], values: list[float]) -> float:
    """5-point central difference at the middle sample, per degree of input angle. The spacing
    is read from the file: INPUT gives the typed bounds and step single precision."""
    f0, f1, _, f3, f4 = values
    return (f0 - 8 * f1 + 8 * f3 - f4) / (3 * (phis[4] - phis[0]))


def check_sweep(sweep: Sweep, files: dict[str, bytes]) -> list[str]:
    """Everything wrong with one session's output, as readable lines (empty when it is right)."""
    kind, dims = CASES[sweep.case]
    mech = MECHANISMS[kind]
    where = f"{sweep.case} branch {sweep.branch} ({sweep.kind})"
    missing = [n for n in basic_runner.DAT_FILES if n not in files]
    if missing:
        return [f"{where}: the listing wrote no {', '.join(missing)}"]
    ang, vel, acc = (basic_runner.read_dat(files[n]) for n in basic_runner.DAT_FILES)
    expected = 5 if sweep.kind == "stencil" else sweep.points
    if not len(ang) == len(vel) == len(acc) == expected:
        return [f"{where}: {len(ang)}, {len(vel)}, {len(acc)} lines, expected {expected} each"]
    problems = []
    for phi_deg, out in ang:
        psi = out if mech.slider else math.radians(out)
        residual = mech.closure(dims, math.radians(phi_deg), psi)
        if not abs(residual) <= CLOSURE_TOL:
            problems.append(f"{where}: phi={phi_deg}: loop residual {residual:.3e}")
    if sweep.kind == "stencil":
        per_radian = math.degrees(1.0)
        outputs = [y for _, y in ang] if mech.slider else _unwrap([y for _, y in ang])
        phis = [x for x, _ in ang]
        velocity = _derivative(phis, outputs) * (per_radian if mech.slider else 1.0)
        acceleration = _derivative(phis, [y for _, y in vel]) * per_radian
        phi_mid, vel_mid, acc_mid = ang[2][0], vel[2][1], acc[2][1]
        # Lines 1200-1210 and 1290-1300 clip the ratios to +-3; a clipped stencil would check
        # nothing, so every stencil centre is chosen where the ratios are well inside.
        if not all(abs(v) < CLIP for _, v in vel + acc):
            problems.append(f"{where}: phi={phi_mid}: ratios clipped at +-3, nothing checked")
        if not abs(vel_mid - velocity) <= VEL_TOL:
            problems.append(f"{where}: phi={phi_mid}: VEL {vel_mid} but d/dphi of ANG is "
                            f"{velocity}")
        if not abs(acc_mid - acceleration) <= ACC_TOL:
            problems.append(f"{where}: phi={phi_mid}: ACC {acc_mid} but d/dphi of VEL is "
                            f"{acceleration}")
    return problems


def physics_problems(listing: bytes, plan: list[Sweep]) -> dict[Sweep, list[str]]:
    """Run every sweep of `plan` through `listing` in double precision, in one interpreter."""
    variant = basic_runner.double_precision_variant(listing)
    results = basic_runner.run_batch([s.keys for s in plan], variant, double=True)
    return {sweep: check_sweep(sweep, files) for sweep, files in zip(plan, results)}


@pytest.mark.parametrize("case", sorted(CASES))
def test_fixed_listing_closes_the_loop_and_differentiates_right(case):
    """(A PC-BASIC run a case, so that pytest -n spreads them over the cores.)"""
    plan = sweeps(cases=(case,), detour=case == next(iter(CASES)))
    results = physics_problems(basic_runner.LISTING.read_bytes(), plan)
    problems = [p for ps in results.values() for p in ps]
    assert not problems, "\n".join(problems)


def test_every_case_is_a_valid_linkage_for_its_closure():
    """The closures are not vacuous: a wrong output angle leaves a residual far above tolerance."""
    for case, (kind, dims) in CASES.items():
        mech = MECHANISMS[kind]
        wrong = 0.3 if mech.slider else 0.01
        assert abs(mech.closure(dims, 0.7, wrong)) > 1e-6 or abs(mech.closure(dims, 0.7, -wrong)) > 1e-6, case

