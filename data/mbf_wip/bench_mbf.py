"""Time the MBF operations and one sweep point of LINKAGE.BAS lines 1060-1330
(plane four-bar, b=2, c=7, d=9, a=6, solution 1).  Run: python3 bench_mbf.py"""
import timeit

import mbf
from mbf import add, sub, mul, div, power, ipower, tan_, atn, neg, fmt_write, parse

P = parse
PI = P("3.141592654#")
A, B, C, D = P("6"), P("2"), P("7"), P("9")
HALF, ONE, TWO, FOUR, THREE, K180 = P(".5"), 1.0, P("2"), P("4"), P("3"), P("180!")


def coefficients():
    """Lines 540-570 and 880-930."""
    p = [None] * 9
    p[1] = div(sub(add(sub(A, B), C), D), P("2!"))
    p[2] = div(sub(sub(sub(A, B), C), D), P("2!"))
    p[3] = div(sub(add(add(A, B), C), D), P("2!"))
    p[4] = div(sub(sub(add(A, B), C), D), P("2!"))
    p[5] = div(add(add(sub(A, B), C), D), P("2!"))
    p[6] = div(add(sub(sub(A, B), C), D), P("2!"))
    p[7] = div(add(add(add(A, B), C), D), P("2!"))
    p[8] = div(add(sub(add(A, B), C), D), P("2!"))
    return (mul(p[7], p[8]), mul(p[1], p[2]), mul(p[3], p[4]), mul(mul(neg(TWO), B), D),
            mul(p[5], p[6]), 0.0, 0.0, 0.0, 0.0, 0.0)


COEF = coefficients()


def sweep_point(phi, sol=1, err=mbf._ignore):
    """Lines 1060-1330 for one PHI: returns the three WRITE # lines."""
    a1, b1, c1, d1, e1, f1, g1, h1, i1, j1 = COEF
    t = tan_(mul(HALF, phi), err)
    t2 = ipower(t, 2, err)
    gj, gh = add(g1, j1, err), add(g1, h1, err)
    den = add(add(b1, mul(c1, t2, err), err), mul(f1, t, err), err)
    num = add(add(mul(d1, t, err), mul(gj, t2, err), err), gh, err)
    u11 = div(neg(num), mul(TWO, den, err), err)
    q = add(add(add(mul(a1, t2, err), e1, err), mul(f1, t, err), err), mul(i1, t, err), err)
    disc_l = ipower(num, 2, err)
    disc_r = mul(mul(FOUR, den, err), q, err)
    uim = disc_l < disc_r
    if uim:
        u11 = u12 = 0.0
    else:
        u12 = div(power(sub(disc_l, disc_r, err), HALF, err), mul(TWO, den, err), err)
    u = [None, add(u11, u12, err), sub(u11, u12, err)]
    psi = [None] + [mul(div(mul(TWO, atn(u[i], err), err), PI, err), K180, err) for i in (1, 2)]
    deg = mul(div(phi, PI, err), K180, err)
    m11, m22 = [None, 0, 0], [None, 0, 0]
    for lop in (1, 2):
        ul = u[lop]
        ul2 = ipower(ul, 2, err)
        s1 = mul(TWO, add(add(add(add(add(mul(b1, ul, err), mul(mul(c1, ul, err), t2, err), err),
                                      mul(mul(HALF, d1, err), t, err), err),
                                  mul(mul(f1, ul, err), t, err), err),
                              mul(mul(HALF, gj, err), t2, err), err),
                          mul(HALF, gh, err), err), err)
        m1n = add(add(add(add(add(mul(a1, t, err), mul(mul(c1, t, err), ul2, err), err),
                              mul(mul(HALF, d1, err), ul, err), err),
                          mul(mul(HALF, f1, err), add(ul2, ONE, err), err), err),
                      mul(mul(gj, t, err), ul, err), err), mul(HALF, i1, err), err)
        m1d = mul(add(ONE, ul2, err), div(s1, TWO, err), err)
        m1 = div(mul(neg(add(ONE, t2, err)), m1n, err), m1d, err)
        m11[lop] = 0.0 if uim else max(-THREE, min(THREE, m1))
        m1 = 0.0 if uim else m1
        p1 = add(mul(add(mul(THREE, ul2, err), ONE, err), add(add(b1, mul(c1, t2, err), err), mul(f1, t, err), err), err),
                 mul(ul, add(add(add(mul(gj, t2, err), mul(d1, t, err), err), g1, err), h1, err), err), err)
        q1 = mul(mul(TWO, add(ONE, t2, err), err),
                 add(add(add(mul(mul(mul(TWO, c1, err), t, err), ul, err), mul(HALF, d1, err), err),
                         mul(f1, ul, err), err), mul(gj, t, err), err), err)
        r1 = mul(div(add(ONE, t2, err), add(ONE, ul2, err), err),
                 add(mul(add(mul(THREE, t2, err), ONE, err), add(add(a1, mul(c1, ul2, err), err), mul(gj, ul, err), err), err),
                     mul(t, add(add(mul(f1, add(ul2, ONE, err), err), mul(d1, ul, err), err), i1, err), err), err), err)
        m2 = neg(div(add(add(mul(p1, ipower(m1, 2, err), err), mul(q1, m1, err), err), r1, err), s1, err))
        m22[lop] = 0.0 if uim else max(-THREE, min(THREE, m2))
    return ("%s,%s" % (fmt_write(deg), fmt_write(psi[sol])),
            "%s,%s" % (fmt_write(deg), fmt_write(m11[sol])),
            "%s,%s" % (fmt_write(deg), fmt_write(m22[sol])))


def main():
    x, y = P("1.234567"), P("7.654321")
    n = 200000
    for name, stmt in (("add", lambda: add(x, y)), ("sub", lambda: sub(x, y)),
                       ("mul", lambda: mul(x, y)), ("div", lambda: div(x, y)),
                       ("x^2", lambda: ipower(x, 2)), ("x^.5", lambda: power(x, HALF)),
                       ("tan", lambda: tan_(x)), ("atn", lambda: atn(x)),
                       ("write text", lambda: fmt_write(x))):
        t = timeit.timeit(stmt, number=n if name in ("add", "sub", "mul", "div") else n // 10)
        print("%-10s %7.2f us" % (name, t / (n if name in ("add", "sub", "mul", "div") else n // 10) * 1e6))
    phi = P("1.2345")
    reps = 2000
    t = timeit.timeit(lambda: sweep_point(phi), number=reps)
    print("sweep point with WRITE text %7.3f ms" % (t / reps * 1e3))


if __name__ == "__main__":
    main()
