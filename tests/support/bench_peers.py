"""The engine beside other programs: the numpy path against a C loop of the same formulas
(C_SWEEP, built with cc -O2 and loaded with ctypes), against a plain C loop of the same
half-tangent formula (C_PLAIN: libm's hypot, no correctly rounded copy) and against pylinkage
(with numba where it is installed). Not part of the shipped program (`python3 linkage.py
bench` measures the program itself); run from the repository's root as the other studies are,
with an interpreter that has numba to time pylinkage as its users run it:

    PYTHONPATH=tests python3 -m support.bench_peers [--quick] [c] [plain] [pylinkage]

It prints its numbers and how they were taken; tests/test_fast.py runs it on tiny sizes."""

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


def median_rates(points: int, runs: list[Callable[[], object]], calls: int) -> list[float]:
    """Points per second of CPU time (process time) of each of `runs`, called in turn `calls`
    times (alternated, so that a change of the machine's speed falls on all alike): medians."""
    times: list[list[float]] = [[] for _ in runs]
    for _ in range(calls):
        for run, spent in zip(runs, times):
            start = time.process_time()
            run()
            spent.append(time.process_time() - start)
    return [points / sorted(spent)[len(spent) // 2] for spent in times]


def pylinkage_runs(points: int) -> dict[str, Any] | str:
    """pylinkage on the plane four-bar and slider-crank of BENCH_LINKAGES, `points` steps a call,
    with numba where it is installed (NUMBA_DISABLE_JIT=1: without), or why it cannot be run.
    The four-bar by its fast ways, numba's where it has it: Mechanism.step_fast (positions) and
    step_fast_with_kinematics (and velocity and acceleration, the input at 1 rad/s), each
    called once before, so that numba's compiling is not timed; the four-bar with a coupler
    point (add_point_tracker) by step, the one way that moves the point (coupler_still); the
    slider-crank positions only (Mechanism.step): pylinkage 1.3.0 gives no slider velocity
    (step_with_derivatives leaves it None, and step_fast_with_kinematics does not move the
    slider; tests/test_pylinkage.py)."""
    try:
        import pylinkage
        from pylinkage import _numba_compat
        from pylinkage.mechanism import fourbar, slider_crank
    except ImportError:
        return "not installed (pip install pylinkage)"
    step = math.radians(360.0 / (points - 1))
    four_bar = fourbar(crank=2.0, coupler=7.0, rocker=9.0, ground=6.0, omega=step)
    four_bar.set_input_velocity(four_bar._driver_links[0], 1.0, 0.0)
    traced = pylinkage_coupler(step)
    slider = slider_crank(crank=2.0, rod=7.0, omega=step, slide_through=(0.0, 1.5))
    jit = _numba_compat.HAS_NUMBA and os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")
    four_bar.step_fast(3)                          # numba compiles here, not in the timing
    four_bar.step_fast_with_kinematics(3)
    return {"version": f"pylinkage {pylinkage.__version__}, "
                       + ("with numba (its solver compiled before the timing: the compile time "
                          "is not in the rates)" if jit else "without numba (not installed, "
                          "or NUMBA_DISABLE_JIT=1: its solver runs as plain Python)"),
            "positions": lambda: four_bar.step_fast(points),
            "kinematics": lambda: four_bar.step_fast_with_kinematics(points),
            "coupler": lambda: list(traced.step(points)),
            "slider": lambda: list(slider.step(points))}


def pylinkage_coupler(step: float) -> Any:
    """pylinkage's four-bar of BENCH_LINKAGES with a coupler point (a point tracker 3.5 from the
    crank pin along the coupler, turned 0.3 rad), `step` radians a step."""
    from pylinkage.mechanism.builder import MechanismBuilder
    builder = MechanismBuilder(name="four-bar with a coupler point")
    builder.add_ground_link("ground", ports={"A": (0.0, 0.0), "D": (6.0, 0.0)})
    builder.add_driver_link("crank", length=2.0, motor_port="A", omega=step)
    builder.add_link("coupler", length=7.0)
    builder.add_link("rocker", length=9.0)
    builder.connect("crank.tip", "coupler.0")
    builder.connect("coupler.1", "rocker.0")
    builder.connect("rocker.1", "ground.D")
    builder.set_branch("coupler.1", 1)
    builder.add_point_tracker("P", "coupler.0", "coupler.1", distance=3.5, angle=0.3)
    return builder.build()


def coupler_still(steps: int = 36) -> dict[str, list[int]] | str:
    """How many of pylinkage's joints each way moves over `steps` steps of 10 degrees on the
    four-bar with a coupler point (pylinkage_coupler: five joints, three of them moving with the
    crank): {way: [joints that move, joints]}; or why it cannot be run."""
    try:
        import numpy
        pylinkage_coupler(0.0)
    except ImportError:
        return "not installed (pip install pylinkage)"
    moved = {}
    for way in ("step", "step_fast", "step_fast_with_kinematics"):
        mechanism = pylinkage_coupler(math.radians(10.0))
        frames = (numpy.array(list(mechanism.step(steps)), dtype=float) if way == "step"
                  else getattr(mechanism, way)(steps))
        frames = frames[0] if isinstance(frames, tuple) else frames      # (positions, v, a)
        span = numpy.abs(frames - frames[:1]).max(axis=(0, 2))          # a joint's largest move
        moved[way] = [int((span > 1e-9).sum()), len(span)]
    return moved


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


def built(source: str) -> Any:
    """The C `source` built with the C compiler (cc, or $CC) -O2 in a temporary folder and loaded
    with ctypes (a ctypes.CDLL), or why it cannot be (a str)."""
    import ctypes
    import subprocess
    import tempfile
    compiler = os.environ.get("CC") or shutil.which("cc")
    if not compiler:
        return "no C compiler (cc) found"
    with tempfile.TemporaryDirectory() as folder:
        path, library = os.path.join(folder, "loop.c"), os.path.join(folder, "loop.so")
        with open(path, "w", encoding="ascii") as f:
            f.write(source)
        try:
            subprocess.run([compiler, "-O2", "-shared", "-fPIC", "-o", library, path, "-lm"],
                           check=True, capture_output=True, timeout=120)
            return ctypes.CDLL(library)           # mapped: the file may go with its folder
        except (OSError, subprocess.SubprocessError) as e:
            return f"{compiler} -O2 failed: {getattr(e, 'stderr', b'').decode(errors='replace')[:200] or e}"


def c_loop() -> Callable[..., list[Any]] | str:
    """C_SWEEP built with the C compiler (cc, or $CC) -O2 in a temporary folder and loaded with
    ctypes: a function (linkage, angles, branch) -> (phi, output, velocity, acceleration,
    status) arrays; or why it cannot be built (a str)."""
    import ctypes
    library = built(C_SWEEP)
    if isinstance(library, str):
        return library
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
        args = [n, angles, np.array(link.constants), 1.0 if branch == 1 else -1.0,
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


C_PLAIN = r"""
/* The plane four-bar's output angle as anyone would write the engine's half-tangent formula in C
   (the root of P cos psi + Q sin psi = -S that _sweep_four_bar takes): libm's cos, sin, hypot
   and atan2, the angle turned into radians without reduction, no point classified or handed
   over (NaN where not assembled, as sqrt gives it). angle: psi alone; motion: psi, psi', psi''. */
#include <math.h>

#define TERMS(k) double p0 = k[0], pc = k[1], ps = k[2], q0 = k[3], qc = k[4], qs = k[5], \
                        s0 = k[6], sc = k[7], ss = k[8]

void angle(long n, const double *phi, const double *k, double sign, double *out)
{
    TERMS(k);
    for (long i = 0; i < n; i++) {
        double t = phi[i] * (M_PI / 180.0), c = cos(t), s = sin(t);
        double p = p0 + pc * c + ps * s, q = q0 + qc * c + qs * s, sv = s0 + sc * c + ss * s;
        double rr = hypot(p, q), root = sqrt((rr - sv) * (rr + sv));
        out[i] = atan2(-q * sv - sign * p * root, -p * sv + sign * q * root) * (180.0 / M_PI);
    }
}

void motion(long n, const double *phi, const double *k, double sign, double *out, double *vel,
            double *acc)
{
    TERMS(k);
    for (long i = 0; i < n; i++) {
        double t = phi[i] * (M_PI / 180.0), c = cos(t), s = sin(t);
        double xp = pc * c + ps * s, xq = qc * c + qs * s, xs = sc * c + ss * s;
        double p = p0 + xp, q = q0 + xq, sv = s0 + xs;
        double rr = hypot(p, q), root = sqrt((rr - sv) * (rr + sv));
        double sn = -q * sv - sign * p * root, cn = -p * sv + sign * q * root;
        out[i] = atan2(sn, cn) * (180.0 / M_PI);
        double cp = cn / (rr * rr), sp = sn / (rr * rr);
        double dp = ps * c - pc * s, dq = qs * c - qc * s, ds = ss * c - sc * s;
        double v = -sign * (dp * cp + dq * sp + ds) / root;
        vel[i] = v;
        acc[i] = -sign * (-(xp * cp + xq * sp + xs) + 2.0 * (dq * cp - dp * sp) * v
                          + sv * v * v) / root;
    }
}
"""


def plain_loop() -> Callable[..., list[Any]] | str:
    """C_PLAIN built as C_SWEEP is: a function (linkage, angles, derivatives 0 or 2) -> its
    output arrays, made anew as sweep_arrays makes its own (psi; or psi, psi', psi''); or why it
    cannot be built (a str)."""
    import ctypes
    library = built(C_PLAIN)
    if isinstance(library, str):
        return library
    np = linkage.numpy_module()
    double_p = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
    common = [ctypes.c_long, double_p, double_p, ctypes.c_double]
    library.angle.argtypes = common + [double_p]
    library.motion.argtypes = common + [double_p] * 3

    def plain_sweep(link: linkage.Linkage, angles: Any, derivatives: int = 0,
                    branch: int = 1) -> list[Any]:
        """C_PLAIN's answer for the plane four-bar `link` at `angles` (a float64 array)."""
        n = len(angles)
        answer = [np.empty(n) for _ in range(1 if derivatives == 0 else 3)]
        (library.angle if derivatives == 0 else library.motion)(
            n, angles, np.array(link.constants), 1.0 if branch == 1 else -1.0, *answer)
        return answer
    return plain_sweep


PLAIN_TARGET = 0.8       # sweep_arrays' rate over C_PLAIN's, the angle alone, 1e4 points and more


def bench_plain_loop(out: TextIO, sizes: tuple[int, ...],
                     calls: int | None = None) -> dict[tuple[int, int], float]:
    """sweep_arrays against C_PLAIN on the plane four-bar of BENCH_LINKAGES, branch 1, the angle
    alone and with velocity and acceleration, at each of `sizes` points (0 to 360 degrees): the
    CPU time of every call (`calls` of each, or 5 to 201 by the size), the two alternated, and
    the ratio of their medians; the load average before and after each row. Returns the ratios
    by (derivatives, points)."""
    plain = plain_loop()
    if isinstance(plain, str):
        print(f"plain C loop: skipped ({plain})", file=out)
        return {}
    np = linkage.numpy_module()
    print("\nsweep_arrays against a plain C loop of the same half-tangent formula (C_PLAIN: libm's "
          "hypot and atan2, no reduction of the angle, nothing classified; cc -O2, called with "
          "ctypes), the plane four-bar, branch 1, angles 0 to 360; points per second of CPU time, "
          "medians of 5 to 201 calls each (more for fewer points), the two alternated; agree "
          "to: the largest difference of their numbers where both have them (degrees; the "
          "velocity and acceleration ratios); load: the load average before and after", file=out)
    print(f"{'points':>11} {'what':>11} {'numpy':>12} {'plain C':>12} {'numpy/C':>8} "
          f"{'agree to':>9} {'load':>9}", file=out)
    kind, dims = linkage.BENCH_LINKAGES[0]
    link = linkage.Linkage(kind, **dims)
    ratios = {}
    for level in (0, 2):
        for n in sizes:
            angles = np.linspace(0.0, 360.0, n)
            load = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
            fast, c = link.sweep_arrays(angles, 1, level), plain(link, angles, level)
            numpy_rate, c_rate = median_rates(n, [lambda: link.sweep_arrays(angles, 1, level),
                                                  lambda: plain(link, angles, level)],
                                              calls or max(5, min(201, 2_000_000 // n) | 1))
            both = (fast.status == 0) & np.isfinite(c[0])
            gaps = [np.abs(got - want)[both] for got, want in zip(c, fast[1:4])]
            gaps[0] = np.minimum(gaps[0], 360.0 - gaps[0])          # psi = 180 and -180
            agree = max(float(np.max(g, initial=0.0)) for g in gaps)
            ratios[level, n] = numpy_rate / c_rate
            after = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
            print(f"{n:11,} {('angle', '', '+vel., acc.')[level]:>11} {numpy_rate:12,.0f} "
                  f"{c_rate:12,.0f} {numpy_rate / c_rate:8.2f} {agree:9.1e} "
                  f"{load:4.1f}-{after:<4.1f}", file=out, flush=True)
    wide = [(level, n) for level, n in ratios if n >= 10_000 and level == 0]
    if wide:
        low = min(ratios[key] for key in wide)
        print(f"target: numpy >= {PLAIN_TARGET} of the plain C loop for the angle alone from "
              f"10,000 points to {max(sizes):,}: {'met' if low >= PLAIN_TARGET else 'NOT MET'}, "
              f"lowest {low:.2f}", file=out)
    return ratios


def bench_pylinkage(out: TextIO, points: int, calls: int = 5) -> None:
    """pylinkage beside us (the numpy path and the scalar engine) on the same angles, like with
    like: their four-bar positions (step_fast) against our output angle alone, with velocity
    and acceleration (step_fast_with_kinematics) against ours with them, its coupler point (step)
    against our coupler point, the slider-crank's positions (step) against our displacement;
    CPU time, medians of `calls` calls, theirs and ours alternated."""
    theirs = pylinkage_runs(points)
    if isinstance(theirs, str):
        print(f"pylinkage: {theirs}", file=out)
        return
    print(f"\n{theirs['version']}; {points:,} angles; points per second of CPU time, medians of "
          f"{calls} calls each, theirs and ours alternated", file=out)
    angles = linkage.evenly_spaced_angles(0.0, 360.0, 360.0 / (points - 1))
    try:
        array = linkage.angle_array(0.0, 360.0 / (points - 1), 0, points)
    except linkage.FastUnavailable:
        array = None
    u, v = 3.5 * math.cos(0.3), 3.5 * math.sin(0.3)
    rows: tuple[tuple[str, str, str, int], ...] = (
            (linkage.PLANE_FOUR_BAR, "positions", "positions (step_fast)", 0),
            (linkage.PLANE_FOUR_BAR, "kinematics", "with velocity and acceleration "
             "(step_fast_with_kinematics)", 2),
            (linkage.PLANE_FOUR_BAR, "coupler", "a coupler point's positions (step: "
             "step_fast leaves the point still)", 0),
            (linkage.PLANE_SLIDER_CRANK, "slider", "positions only (step; no slider velocity)",
             0))
    for kind, key, what, level in rows:
        link = linkage.Linkage(kind, **dict(linkage.BENCH_LINKAGES)[kind])
        ours: list[Callable[[], object]]
        if key == "coupler":
            ours = [lambda: link.coupler(angles, u, v, 1, level)] + (
                [lambda: link.coupler_arrays(array, u, v, 1, level)] if array is not None else [])
        else:
            ours = [lambda: link.sweep(angles, 1, level)] + (
                [lambda: link.sweep_arrays(array, 1, level)] if array is not None else [])
        rates = median_rates(points, [theirs[key]] + ours, calls)
        fast = f"numpy path {rates[2] / rates[0]:,.1f}x, " if len(rates) > 2 else ""
        print(f"{kind:12} {rates[0]:12,.0f} points/s {what}; ours/pylinkage: {fast}"
              f"scalar engine {rates[1] / rates[0]:,.2f}x", file=out, flush=True)
    moved = coupler_still()
    if not isinstance(moved, str):
        still = [way for way, (n, _) in moved.items() if n < moved["step"][0]]
        print(f"the coupler point, over 36 steps of 10 degrees: of the four-bar's "
              f"{moved['step'][1]} joints " + ", ".join(f"{way} moves {n}" for way, (n, _) in
                                                        moved.items())
              + (f": {' and '.join(still)} leave the coupler point where it was built" if still
                 else ""), file=out)


def main(argv: list[str] | None = None) -> int:
    """[--quick] [c] [plain] [pylinkage]: the benches named (all where none), tiny with --quick."""
    args = sys.argv[1:] if argv is None else argv
    quick, names = "--quick" in args, [a for a in args if a != "--quick"] or ["c", "plain",
                                                                               "pylinkage"]
    print(f"{linkage.machine()}; CPU time, this process; {sys.executable}", flush=True)
    sizes = C_SIZES[:2] if quick else C_SIZES
    try:
        linkage.numpy_module()
        if "c" in names:
            bench_c_loop(sys.stdout, sizes)
        if "plain" in names:
            bench_plain_loop(sys.stdout, sizes)
    except linkage.FastUnavailable as e:
        print(f"C loop: skipped ({e})")
    if "pylinkage" in names:
        bench_pylinkage(sys.stdout, 101 if quick else 100_001)
    return 0


if __name__ == "__main__":
    sys.exit(main())
