"""A high-precision reference for the five linkages, written from the geometry alone.

Independent of engine.py's formulas: each closure is the vector loop of tests/test_physics.py
(crank tip B, output tip D; squared distance |B - D|^2 - c^2, or B.D - cos c on the sphere)
evaluated in mpmath; the output is found by bracketed root finding on that closure (between
consecutive extrema of the closure in psi, where it is monotonic), and the velocity and
acceleration by implicit differentiation with partial derivatives taken numerically by mpmath
(mp.diff) at the working precision.

Branch labels follow the listing's rule, read off its lines 1070-1110 (U = (-B +- sqrt(D)) / 2A,
so dF/du = 2Au + B = +-sqrt(D)): branch 1 is the root where the listing's polynomial F
increases with the output. F is a positive multiple of |B - D|^2 - c^2 for the plane and skew
linkages and both slider-cranks, and of -(B.D - cos c) for the spherical one (the factors are
stated in tests/test_physics.py's docstrings), hence KAPPA.

At a change point (a double root where the closure's phi-derivative vanishes too, the branches
crossing) the values are limits: each branch's from above, the root solved 10^-dps degree
past the point in 4 dps digits - no formula of the engine's second-order expansion is used.
"""

from __future__ import annotations

import dataclasses
import functools

from mpmath import mp
from mpmath.libmp import mpf_cos_sin

KAPPA = {"plane": 1, "spherical": -1, "skew": 1, "slider": 1, "skew-slider": 1}
SLIDERS = ("slider", "skew-slider")


def remembered_trig(size: int | None = None):
    """cos and sin at the working precision, remembered by argument and precision in a table of
    their own (the last `size` pairs, or all): the values mp.cos and mp.sin give there (libmp's
    cos and sin of one argument at once), each computed once. A closure's link angles and input
    angle recur at every step of its root finding (mp.diff raises the precision, so each of its
    precisions is a value of its own); tests/test_coupler.py's 40-digit positions likewise."""
    @functools.lru_cache(maxsize=size)
    def pair(x, prec):
        return tuple(mp.make_mpf(v) for v in mpf_cos_sin(x, prec, "n"))

    def cos(x):
        return pair(mp.convert(x)._mpf_, mp.prec)[0]

    def sin(x):
        return pair(mp.convert(x)._mpf_, mp.prec)[1]
    return cos, sin


def _closure(kind: str, dims: dict):
    """The loop closure g(phi, y) in mpmath (phi radians; y = psi radians, or the slider's x),
    its cosines and sines remembered (remembered_trig)."""
    D = {k: mp.mpf(v) for k, v in dims.items()}
    rad = mp.pi / 180
    cos, sin = remembered_trig()
    if kind == "plane":
        a, b, c, d = D["a"], D["b"], D["c"], D["d"]

        def g(phi, psi):
            bx, by = b * cos(phi), b * sin(phi)
            dx, dy = a + d * cos(psi), d * sin(psi)
            return (bx - dx) ** 2 + (by - dy) ** 2 - c ** 2
        scale = max(abs(a), abs(b), abs(c), abs(d)) ** 2
    elif kind == "spherical":
        a, b, c, d = (D[k] * rad for k in "abcd")
        ca, sa = cos(a), sin(a)

        def g(phi, psi):
            tb = (sin(b) * cos(phi), sin(b) * sin(phi), cos(b))
            v = (sin(d) * cos(psi), sin(d) * sin(psi), cos(d))
            td = (ca * v[0] + sa * v[2], v[1], -sa * v[0] + ca * v[2])   # rotation about y by a
            return tb[0] * td[0] + tb[1] * td[1] + tb[2] * td[2] - cos(c)
        scale = mp.mpf(1)
    elif kind == "skew":
        a, b, c, d, f = D["a"], D["b"], D["c"], D["d"], D["f"]
        xi = D["ksi"] * rad
        gg = f / cos(xi)
        q = (a, gg * sin(xi), f - gg * cos(xi))
        e1, e2 = (1, 0, 0), (0, cos(xi), sin(xi))

        def g(phi, psi):
            tb = (b * cos(phi), b * sin(phi), 0)
            td = [q[i] + d * (cos(psi) * e1[i] + sin(psi) * e2[i]) for i in range(3)]
            return sum((tb[i] - td[i]) ** 2 for i in range(3)) - c ** 2
        scale = max(abs(a), abs(b), abs(c), abs(d), abs(f), abs(q[1])) ** 2
    elif kind == "slider":
        b, c, e = D["b"], D["c"], D["e"]

        def g(phi, x):
            return (b * cos(phi) - x) ** 2 + (b * sin(phi) - e) ** 2 - c ** 2
        scale = max(abs(b), abs(c), abs(e)) ** 2
    elif kind == "skew-slider":
        a, b, c, f = D["a"], D["b"], D["c"], D["f"]
        xi = D["ksi"] * rad
        s = (0, sin(xi), -cos(xi))

        def g(phi, x):
            tb = (b * cos(phi), b * sin(phi), 0)
            td = (a, x * s[1], f + x * s[2])
            return sum((tb[i] - td[i]) ** 2 for i in range(3)) - c ** 2
        scale = max(abs(a), abs(b), abs(c), abs(f)) ** 2
    else:
        raise ValueError(kind)
    return g, scale


@dataclasses.dataclass
class RefPoint:
    """The reference at one input angle on one branch (status as engine.py's)."""
    status: str                 # "assembled", "dead-centre", "change-point", "not-assembled"
    output: object = None       # mpf: psi in degrees in (-180, 180], or x
    velocity: object = None
    acceleration: object = None
    extreme: object = None      # closure at its extremum nearest zero, over scale (the margin)


def _bracket_root(f, lo, hi):
    """The root of f in [lo, hi] (f(lo), f(hi) of opposite signs), to full working precision."""
    flo, fhi = f(lo), f(hi)
    if flo == 0:
        return lo
    if fhi == 0:
        return hi
    # a few bisections for safety, then the Anderson-Bjorck bracketing solver
    for _ in range(8):
        mid = (lo + hi) / 2
        fm = f(mid)
        if fm == 0:
            return mid
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi, fhi = mid, fm
    try:
        return mp.findroot(f, (lo, hi), solver="anderson", tol=mp.mpf(10) ** (-2 * mp.dps))
    except (ValueError, ZeroDivisionError):
        pass
    while hi - lo > mp.mpf(2) ** (-mp.prec + 8) * (1 + abs(lo)):   # plain bisection
        mid = (lo + hi) / 2
        fm = f(mid)
        if fm == 0:
            return mid
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return (lo + hi) / 2


def _extrema_periodic(gp, samples=48):
    """The zeros of gp (the closure's derivative in psi) on one turn, by bracketing. The grid is
    offset from 0 and 180 degrees, where symmetric positions put extrema exactly (a zero of gp
    on a grid point would be seen twice or not at all)."""
    pts = [-mp.pi + mp.mpf("0.0123456789") + 2 * mp.pi * i / samples for i in range(samples)]
    vals = [gp(p) for p in pts]
    out = []
    for i in range(samples):
        lo, hi = pts[i], pts[i + 1] if i + 1 < samples else pts[0] + 2 * mp.pi
        vlo, vhi = vals[i], vals[(i + 1) % samples]
        if vlo == 0:
            out.append(lo)
        elif vlo * vhi < 0:
            out.append(_bracket_root(gp, lo, hi))
    return out


def solve(kind: str, dims: dict, phi_deg: float, dps: int = 50,
          guard: int = 10) -> dict[int, RefPoint]:
    """Both branches at input angle phi_deg (degrees, the float as given), to `dps` digits:
    computed with `guard` more; a double root within 10^-(dps-8) of the scale is a dead-centre,
    or a change point where the closure's phi-derivative vanishes there too (within 10^-(dps/2)
    of the scale): then velocity and acceleration are each branch's limit from above, phi ->
    phi_deg+ (_limit_from_above), the engine's convention."""
    tiny_digits = dps - 8
    with mp.workdps(dps + guard):
        g, scale = _closure(kind, dims)
        phi = mp.mpf(phi_deg) * mp.pi / 180
        kappa = KAPPA[kind]
        tiny = scale * mp.mpf(10) ** (-tiny_digits)

        def gy(y):
            return mp.diff(lambda t: g(phi, t), y)

        def gy_of(y):
            return g(phi, y)

        roots = []        # (y, is_double)
        margin = None
        if kind in SLIDERS:
            # one minimum on the line: g is convex in x (|B - D|^2 with D linear in x)
            xc = mp.findroot(gy, mp.mpf(0))
            gmin = g(phi, xc)
            margin = gmin / scale
            if abs(gmin) <= tiny:
                roots.append((xc, True))
            elif gmin < 0:
                for direction in (1, -1):
                    step = mp.sqrt(-gmin) + 1
                    while g(phi, xc + direction * step) <= 0:
                        step *= 2
                    lo, hi = sorted((xc, xc + direction * step))
                    roots.append((_bracket_root(gy_of, lo, hi), False))
        else:
            crit = sorted(_extrema_periodic(gy))
            if not crit:
                raise ArithmeticError("closure constant in psi: indeterminate")
            ext = [(c, g(phi, c)) for c in crit]
            margin = min((v for _, v in ext), key=abs) / scale
            n = len(ext)
            for i in range(n):
                c1, v1 = ext[i]
                c2, v2 = ext[(i + 1) % n]
                if i + 1 == n:
                    c2 = c2 + 2 * mp.pi
                if abs(v1) <= tiny:
                    roots.append((c1, True))
                elif abs(v2) > tiny and v1 * v2 < 0:
                    roots.append((_bracket_root(gy_of, c1, c2), False))
        result = {}
        for y, double in roots:
            if double:
                limit = None
                if abs(mp.diff(g, (phi, y), (1, 0))) <= scale * mp.mpf(10) ** (-(dps // 2)):
                    # the closure's gradient vanishes too: a change point, where the branches
                    # cross with finite velocities (each branch gets the limit from above), or
                    # an isolated position (no assembly on either side: a dead-centre)
                    limit = _limit_from_above(kind, dims, phi_deg, dps, guard)
                if limit is not None:
                    for br in (1, 2):
                        result[br] = RefPoint("change-point", _out(kind, y),
                                              limit[br].velocity, limit[br].acceleration, margin)
                    continue
                for br in (1, 2):
                    result[br] = RefPoint("dead-centre", _out(kind, y), extreme=margin)
                continue
            g_y = mp.diff(g, (phi, y), (0, 1))
            br = 1 if kappa * g_y > 0 else 2
            g_f = mp.diff(g, (phi, y), (1, 0))
            g_ff = mp.diff(g, (phi, y), (2, 0))
            g_fy = mp.diff(g, (phi, y), (1, 1))
            g_yy = mp.diff(g, (phi, y), (0, 2))
            v = -g_f / g_y
            acc = -(g_ff + 2 * g_fy * v + g_yy * v * v) / g_y
            result[br] = RefPoint("assembled", _out(kind, y), v, acc, margin)
        for br in (1, 2):
            result.setdefault(br, RefPoint("not-assembled", extreme=margin))
        return result


def _limit_from_above(kind, dims, phi_deg, dps, guard):
    """Both branches' values at phi_deg + 10^-dps degrees, solved with 4 dps digits: the limits
    phi -> phi_deg+ to dps digits (the error is that step times the next derivative; the
    acceleration loses 3 digits per digit of the step, hence the 4 dps). None if the linkage
    does not assemble there (an isolated position)."""
    with mp.workdps(4 * dps + guard):
        above = mp.mpf(phi_deg) + mp.mpf(10) ** -dps
    limit = solve(kind, dims, above, 4 * dps, guard)
    return limit if all(limit[br].status == "assembled" for br in (1, 2)) else None


def _out(kind, y):
    if kind in SLIDERS:
        return y
    deg = y * 180 / mp.pi
    deg = deg - 360 * mp.floor((deg + 180) / 360)      # [-180, 180)
    if deg <= -180 + mp.mpf(10) ** (-mp.dps + 10):
        deg += 360                                     # (-180, 180]
    return deg
