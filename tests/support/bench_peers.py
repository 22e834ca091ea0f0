"""The engine beside other programs: the numpy path against a C loop of the same formulas
(C_SWEEP, built with cc -O2 and loaded with ctypes) and against pylinkage (with numba where it is
installed). Not part of the shipped program (`python3 linkage.py bench` measures the program
itself); run from the repository's root as the other studies are:

    PYTHONPATH=tests python3 -m support.bench_peers [--quick]

It prints its numbers and how they were taken; tests/test_bench.py runs it on tiny sizes."""

from __future__ import annotations

import math
import os
import shutil
import sys
import time
from collections.abc import Callable
from typing import Any, TextIO

import linkage


def best_of(repeats: int, function: Callable[[], object]) -> float:
    """The least CPU time of `repeats` calls of function (process time, seconds)."""
    best = math.inf
    for _ in range(repeats):
        start = time.process_time()
        function()
        best = min(best, time.process_time() - start)
    return best


def pylinkage_rates(points: int) -> dict[str, Any] | str:
    """pylinkage's points per second on the plane four-bar and slider-crank of BENCH_LINKAGES,
    with numba where it is installed (NUMBA_DISABLE_JIT=1: without), or why it cannot be
    measured. The four-bar with velocity and acceleration (its fastest way,
    Mechanism.step_fast_with_kinematics, the input at 1 rad/s); the slider-crank positions only
    (Mechanism.step): pylinkage 1.3.0 gives no slider velocity (step_with_derivatives leaves it
    None, and step_fast_with_kinematics does not move the slider; tests/test_pylinkage.py)."""
    try:
        import pylinkage
        from pylinkage import _numba_compat
        from pylinkage.mechanism import fourbar, slider_crank
    except ImportError:
        return "not installed (pip install pylinkage)"
    step = math.radians(360.0 / (points - 1))
    four_bar = fourbar(crank=2.0, coupler=7.0, rocker=9.0, ground=6.0, omega=step)
    four_bar.set_input_velocity(four_bar._driver_links[0], 1.0, 0.0)
    slider = slider_crank(crank=2.0, rod=7.0, omega=step, slide_through=(0.0, 1.5))
    jit = _numba_compat.HAS_NUMBA and os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")
    if jit:
        four_bar.step_fast_with_kinematics(3)          # compiled here, not in the timing
    return {"version": f"pylinkage {pylinkage.__version__}, "
                       + ("with numba (its solver compiled)" if jit else "without numba (not "
                          "installed, or NUMBA_DISABLE_JIT=1: its solver runs as plain Python)"),
            linkage.PLANE_FOUR_BAR: points / best_of(
                3, lambda: four_bar.step_fast_with_kinematics(points)),
            linkage.PLANE_SLIDER_CRANK: points / best_of(3, lambda: list(slider.step(points)))}


C_SWEEP = r"""
/* The numpy path's formulas (linkage.py, _fast_cos_sin, _fast_hypot, _fast_four_bar,
   _fast_slider and _sweep_arrays' classification) as one C loop a point: bench engine times it
   beside sweep_arrays. Status 2 where not assembled, 5 where sweep_arrays would hand the point to
   the scalar engine (not redone here). */
#include <math.h>

static void cos_sin(double phi, int reduce, double *c, double *s)
{
    double r = reduce ? fmod(phi, 360.0) : phi, n = rint(r / 90.0);
    double y = (r - n * 90.0) * (M_PI / 180.0), cy = cos(y), sy = sin(y);
    switch ((long)n & 3) {
    case 0: *c = cy; *s = sy; break;
    case 1: *c = -sy; *s = cy; break;
    case 2: *c = -cy; *s = -sy; break;
    default: *c = sy; *s = -cy;
    }
}

static void square(double x, double *hi, double *lo)   /* x^2 = hi + lo exactly (Dekker) */
{
    double t = x * 134217729.0, xh = t - (t - x), xl = x - xh;
    *hi = x * x;
    *lo = ((xh * xh - *hi) + 2.0 * xh * xl) + xl * xl;
}

static double hypot_exact(double x, double y)           /* CPython 3.11's, as _fast_hypot */
{
    int e;
    double ax = fabs(x), ay = fabs(y), hi, lo, f1, f2, csum, t, h, r;
    frexp(ax > ay ? ax : ay, &e);
    ax = ldexp(ax, -e);
    ay = ldexp(ay, -e);
    square(ax, &hi, &f1);
    csum = hi + 1.0;
    f2 = (1.0 - csum) + hi;
    square(ay, &hi, &lo);
    f1 += lo;
    t = csum + hi;
    f2 += (csum - t) + hi;
    csum = t;
    h = sqrt((csum - 1.0) + (f1 + f2));
    square(h, &hi, &lo);
    r = csum - hi;
    f2 += (csum - r) - hi;
    f1 -= lo;
    r = (r - 1.0) + (f1 + f2);
    return ldexp(h + r / (h * 2.0), e);
}

static signed char status_of(double disc, double last, double line)
{
    return disc < -line ? 2 : (fabs(disc) <= line || !isfinite(last)) ? 5 : 0;
}

void four_bar(long n, const double *phi, const double *k, double sign, int reduce, double line,
              double *out, double *vel, double *acc, signed char *status)
{
    double p0 = k[0], pc = k[1], ps = k[2], q0 = k[3], qc = k[4], qs = k[5];
    double s0 = k[6], sc = k[7], ss = k[8];
    for (long i = 0; i < n; i++) {
        double c, s;
        cos_sin(phi[i], reduce, &c, &s);
        double xp = pc * c + ps * s, xq = qc * c + qs * s, xs = sc * c + ss * s;
        double p = p0 + xp, q = q0 + xq, sv = s0 + xs, rr = hypot_exact(p, q);
        double disc = (rr - sv) * (rr + sv), root = sqrt(disc);
        double sn = -(q * sv + sign * (p * root)), cn = -(p * sv - sign * (q * root));
        double psi = atan2(sn, cn) * (180.0 / M_PI);
        out[i] = psi == -180.0 ? 180.0 : psi;
        double r2 = rr * rr, cp = cn / r2, sp = sn / r2;
        double dp = ps * c - pc * s, dq = qs * c - qc * s, ds = ss * c - sc * s;
        double v = -sign * (((dp * cp + dq * sp) + ds) / root);
        double e = (xp * cp + xq * sp) + xs, fp = (dq * cp - dp * sp) * 2.0 * v;
        vel[i] = v;
        acc[i] = -sign * (((fp - e) + sv * v * v) / root);
        status[i] = status_of(disc, acc[i], line);
    }
}

void slider(long n, const double *phi, const double *k, double sign, int reduce, double line,
            double unit, double *out, double *vel, double *acc, signed char *status)
{
    double m0 = k[0], mc = k[1], ms = k[2], k0 = k[3], kc = k[4], ks = k[5], u0 = k[6];
    double uc = k[7], us = k[8], v0 = k[9], vc = k[10], vs = k[11], rod = k[12];
    int offset = v0 != 0.0 || vc != 0.0 || vs != 0.0;
    for (long i = 0; i < n; i++) {
        double c, s;
        cos_sin(phi[i], reduce, &c, &s);
        double xm = mc * c + ms * s, xk = kc * c + ks * s, m = m0 + xm, q = k0 + xk;
        double u = (u0 + uc * c) + us * s;
        double dist = offset ? hypot_exact(u, (v0 + vc * c) + vs * s) : fabs(u);
        double disc = (rod - dist) * (dist + rod), root = sqrt(disc);
        double big = m + (m < 0.0 ? -root : root), x = q / big;
        if ((sign < 0.0) == (m < 0.0))
            x = big;
        double dm = ms * c - mc * s, dk = ks * c - kc * s;
        double v = sign * ((dm * x - dk * 0.5) / root);
        double a = sign * ((((xk * 0.5 - xm * x) + dm * 2.0 * v) - v * v) / root);
        status[i] = status_of(disc, a, line);
        out[i] = x * unit;
        vel[i] = v * unit;
        acc[i] = a * unit;
    }
}
"""


def c_loop() -> Callable[..., list[Any]] | str:
    """C_SWEEP built with the C compiler (cc, or $CC) -O2 in a temporary folder and loaded with
    ctypes: a function (linkage, angles, branch) -> (phi, output, velocity, acceleration,
    status) arrays; or why it cannot be built (a str)."""
    import ctypes
    import subprocess
    import tempfile
    compiler = os.environ.get("CC") or shutil.which("cc")
    if not compiler:
        return "no C compiler (cc) found"
    with tempfile.TemporaryDirectory() as folder:
        source, built = os.path.join(folder, "sweep.c"), os.path.join(folder, "sweep.so")
        with open(source, "w", encoding="ascii") as f:
            f.write(C_SWEEP)
        try:
            subprocess.run([compiler, "-O2", "-shared", "-fPIC", "-o", built, source, "-lm"],
                           check=True, capture_output=True, timeout=120)
            library = ctypes.CDLL(built)          # mapped: the file may go with its folder
        except (OSError, subprocess.SubprocessError) as e:
            return f"{compiler} -O2 failed: {getattr(e, 'stderr', b'').decode(errors='replace')[:200] or e}"
    np = linkage.numpy_module()
    double_p, status_p = (np.ctypeslib.ndpointer(dtype=t, flags="C_CONTIGUOUS")
                          for t in (np.float64, np.int8))
    common = [ctypes.c_long, double_p, double_p, ctypes.c_double, ctypes.c_int, ctypes.c_double]
    library.four_bar.argtypes = common + [double_p, double_p, double_p, status_p]
    library.slider.argtypes = common + [ctypes.c_double, double_p, double_p, double_p, status_p]

    def c_sweep(link: linkage.Linkage, angles: Any, branch: int = 1) -> list[Any]:
        """sweep_arrays' answer (its five arrays, new, as it makes them) by C_SWEEP."""
        n = len(angles)
        answer = [np.empty(n) for _ in range(3)] + [np.empty(n, dtype=np.int8)]
        args = [n, angles, np.array(link._constants), 1.0 if branch == 1 else -1.0,
                int(not max(-angles.min(), angles.max()) < 360.0),
                linkage.FAST_MARGIN * link.precise_below]
        if link.is_slider:
            library.slider(*args, link.unit, *answer)
        else:
            library.four_bar(*args, *answer)
        return [np.array(angles)] + answer
    return c_sweep


C_SIZES = (1_000, 10_000, 100_000, 1_000_000, 10_000_000)
C_TARGET = 0.7           # sweep_arrays' rate over the C loop's, at 1e4 points and more


def bench_c_loop(out: TextIO, sizes: tuple[int, ...]) -> None:
    """sweep_arrays against C_SWEEP at each of `sizes` points, plane four-bar and slider-crank,
    velocity and acceleration: rates and their ratio, the two alternated."""
    c_sweep = c_loop()
    if isinstance(c_sweep, str):
        print(f"C loop: skipped ({c_sweep})", file=out)
        return
    print("\nsweep_arrays against a C loop of the same formulas (C_SWEEP, cc -O2, called with "
          "ctypes; its points for the scalar engine not redone), branch 1, velocity and "
          "acceleration; points per second, best of 3 to 300 (more for fewer points), the two "
          "alternated; agree to: the largest difference of their outputs", file=out)
    print(f"{'points':>11} {'linkage':12} {'numpy':>12} {'C':>12} {'numpy/C':>8} {'agree to':>9}",
          file=out)
    np = linkage.numpy_module()
    ratios, fixed = {}, {}
    for kind, dims in (linkage.BENCH_LINKAGES[0], linkage.BENCH_LINKAGES[3]):
        link = linkage.Linkage(kind, **dims)
        rates = {}
        for n in sizes:
            angles = np.linspace(0.0, 360.0, n)
            repeats = max(3, min(300, 3_000_000 // n))
            best = [math.inf, math.inf]
            for _ in range(repeats):
                for i, run in enumerate((lambda: link.sweep_arrays(angles, 1),
                                         lambda: c_sweep(link, angles))):
                    best[i] = min(best[i], best_of(1, run))
            fast, c = link.sweep_arrays(angles, 1), c_sweep(link, angles)
            usual = (fast.status == 0) & (c[4] == 0)
            agree = float(np.max(np.abs(fast.output - c[1])[usual], initial=0.0))
            rates[n] = (n / best[0], n / best[1])
            ratios[kind, n] = best[1] / best[0]
            print(f"{n:11,} {kind:12} {n / best[0]:12,.0f} {n / best[1]:12,.0f} "
                  f"{best[1] / best[0]:8.2f} {agree:9.1e}", file=out)
        (n1, (r1, _)), (n2, (r2, _)) = list(rates.items())[:2]
        fixed[kind] = (n1 / r1 - n1 * (n2 / r2 - n1 / r1) / (n2 - n1)) * 1e6
    print("fixed cost of a sweep_arrays call: " + ", ".join(
        f"{kind} {us:,.0f} us" for kind, us in fixed.items())
        + f" (its time at {sizes[0]:,} points less {sizes[0]:,} points at the cost of a point "
        f"from {sizes[0]:,} to {sizes[1]:,})", file=out)
    if max(sizes) >= 10_000:
        short = [f"{k} at {n:,}" for (k, n), r in ratios.items() if n >= 10_000 and r < C_TARGET]
        print(f"target: numpy >= {C_TARGET} of the C loop from 10,000 points to {max(sizes):,}: "
              + (f"NOT MET ({', '.join(short)})" if short else "met")
              + f", lowest {min(r for (k, n), r in ratios.items() if n >= 10_000):.2f}",
              file=out)


def bench_pylinkage(out: TextIO, points: int) -> None:
    """pylinkage's rates beside ours (the scalar engine and the numpy path) on the same angles."""
    theirs = pylinkage_rates(points)
    if isinstance(theirs, str):
        print(f"pylinkage: {theirs}", file=out)
        return
    print(f"\n{theirs['version']}; {points:,} angles; ours/pylinkage compares like with like "
          "(the slider: our displacement-only rates)", file=out)
    angles = linkage.evenly_spaced_angles(0.0, 360.0, 360.0 / (points - 1))
    for kind, what in ((linkage.PLANE_FOUR_BAR, "with velocity and acceleration "
                        "(step_fast_with_kinematics)"),
                       (linkage.PLANE_SLIDER_CRANK, "positions only (step; no slider velocity)")):
        level = 2 if kind == linkage.PLANE_FOUR_BAR else 0
        link = linkage.Linkage(kind, **dict(linkage.BENCH_LINKAGES)[kind])
        scalar = points / best_of(3, lambda: link.sweep(angles, 1, level))
        try:
            array = linkage.angle_array(0.0, 360.0 / (points - 1), 0, points)
            fast = points / best_of(3, lambda: link.sweep_arrays(array, 1, level))
            ours = f"numpy path {fast / theirs[kind]:,.0f}x, "
        except linkage.FastUnavailable:
            ours = ""
        print(f"{kind:12} {theirs[kind]:12,.0f} points/s {what}; ours/pylinkage: {ours}"
              f"scalar engine {scalar / theirs[kind]:,.1f}x", file=out)


def main(argv: list[str] | None = None) -> int:
    quick = "--quick" in (sys.argv[1:] if argv is None else argv)
    print(f"{linkage.machine()}; CPU time, this process", flush=True)
    try:
        linkage.numpy_module()
        bench_c_loop(sys.stdout, C_SIZES[:2] if quick else C_SIZES)
    except linkage.FastUnavailable as e:
        print(f"C loop: skipped ({e})")
    bench_pylinkage(sys.stdout, 101 if quick else 100_001)
    return 0


if __name__ == "__main__":
    sys.exit(main())
