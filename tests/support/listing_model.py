"""A straight Python transcription of LINKAGE.BAS's arithmetic (for tests and the benchmark).

coefficients(): lines 250-930 (a fresh run: every variable starts at 0, as after RUN);
point(): lines 1060-1330 for one input angle, returning what lines 1150, 1320 and 1330 write
(unclipped unless clip=True). `m` is the arithmetic: the math module (double precision, as the
double-precision variant of tests/support/basic_runner.py runs it) or mpmath (any precision).
Division by zero, which GW-BASIC reports and carries on past (K7), returns status "division".
"""

from __future__ import annotations

import math

ORDER = {  # dimensions in the order the listing asks for them
    "plane": ("b", "c", "d", "a"), "spherical": ("b", "c", "d", "a"),
    "skew": ("b", "c", "d", "a", "f", "ksi"), "slider": ("b", "c", "e"),
    "skew-slider": ("b", "c", "a", "f", "ksi"),
}
BARTYPE = {"plane": 1, "spherical": 2, "skew": 3, "slider": 4, "skew-slider": 5}


def coefficients(kind: str, dims: dict, m=math):
    """(A1, B1, C1, D1, E1, F1, G1, H1, I1, J1, S, PI): lines 250-930 for a fresh run."""
    bartype = BARTYPE[kind]
    num = (lambda v: m.mpf(v)) if m is not math else float
    PI = 4 * m.atan(num(1))
    A = B = C = D = E = F = G = KSI = num(0)
    S = 1 if bartype >= 4 else 0
    B, C = num(dims["b"]), num(dims["c"])
    if S != 1:
        D = num(dims["d"])
    if bartype <= 2:
        A = num(dims["a"])
    if bartype in (3, 5):
        A = num(dims["a"])
    if bartype == 4:
        E = num(dims["e"])
        C = C ** 2 - E ** 2
    else:
        if bartype == 2:
            A, B, C, D = (x / 180 * PI for x in (A, B, C, D))
        if bartype in (3, 5):
            F = num(dims["f"])
            KSI = num(dims["ksi"]) / 180 * PI
            G = num(0) if bartype == 5 else F / m.cos(KSI)
            C = C ** 2 - F ** 2 - G ** 2 + 2 * F * G * m.cos(KSI)
    cim = 0
    if bartype >= 3:
        if C >= 0:
            C = C ** 0.5 if m is math else m.sqrt(C)
        else:
            cim = 1
            C = (-C) ** 0.5 if m is math else m.sqrt(-C)
    P = [None] * 9
    PIM = [num(0)] * 9
    if cim == 0:
        P[1], P[2] = (A - B + C - D) / 2, (A - B - C - D) / 2
        P[3], P[4] = (A + B + C - D) / 2, (A + B - C - D) / 2
        P[5], P[6] = (A - B + C + D) / 2, (A - B - C + D) / 2
        P[7], P[8] = (A + B + C + D) / 2, (A + B - C + D) / 2
    else:
        for lop in range(1, 9):
            PIM[lop] = ((-1) ** (lop + 1)) * C / 2
        P[1] = P[2] = (A - B - D) / 2
        P[3] = P[4] = (A + B - D) / 2
        P[5] = P[6] = (A - B + D) / 2
        P[7] = P[8] = (A + B + D) / 2
    z = num(0)
    if bartype == 3:
        A1 = P[7] * P[8] - PIM[7] * PIM[8]
        B1 = P[1] * P[2] - PIM[1] * PIM[2]
        C1 = P[3] * P[4] - PIM[3] * PIM[4]
        D1 = -2 * m.cos(KSI) * B * D
        E1 = P[5] * P[6] - PIM[5] * PIM[6]
        F1 = -G * B * m.sin(KSI)
        G1, H1, I1, J1 = F * D * m.sin(KSI), z, z, z
    elif bartype >= 4:
        A1 = 4 * (P[7] * P[8] - PIM[7] * PIM[8])
        B1 = C1 = num(S)
        D1 = z if bartype == 4 else -4 * B * m.sin(KSI)
        E1 = 4 * (P[5] * P[6] - PIM[5] * PIM[6])
        F1 = G1 = z
        I1 = -4 * E * B if bartype == 4 else z
        H1 = -2 * B if bartype == 4 else -2 * F * m.cos(KSI)
        J1 = 2 * B if bartype == 4 else -2 * F * m.cos(KSI)
    elif bartype == 2:
        A1 = m.sin(P[7]) * m.sin(P[8])
        B1 = m.sin(P[1]) * m.sin(P[2])
        C1 = m.sin(P[3]) * m.sin(P[4])
        D1 = -2 * m.sin(B) * m.sin(D)
        E1 = m.sin(P[5]) * m.sin(P[6])
        F1 = G1 = H1 = I1 = J1 = z
    else:
        A1, B1, C1 = P[7] * P[8], P[1] * P[2], P[3] * P[4]
        D1 = -2 * B * D
        E1 = P[5] * P[6]
        F1 = G1 = H1 = I1 = J1 = z
    return (A1, B1, C1, D1, E1, F1, G1, H1, I1, J1, S, PI)


def point(co, phi_deg, sol: int, m=math, clip: bool = False):
    """Lines 1060-1330 at input angle phi_deg: (status, ANG value, VEL value, ACC value).

    status: "ok"; "uim" (negative discriminant: the listing writes 0, 0, 0, K8);
    "division" (a division by zero, or overflow, where GW-BASIC prints an error and goes on).
    """
    A1, B1, C1, D1, E1, F1, G1, H1, I1, J1, S, PI = co
    num = (lambda v: m.mpf(v)) if m is not math else float
    PHI = num(phi_deg) / 180 * PI
    try:
        T = m.tan(0.5 * PHI) if m is math else m.tan(PHI / 2)
        U11 = -(D1 * T + (G1 + J1) * T ** 2 + (G1 + H1)) / (2 * (B1 + C1 * (T ** 2) + F1 * T))
        uim = 0
        disc = ((D1 * T + (G1 + J1) * T ** 2 + (G1 + H1)) ** 2) - 4 * (B1 + C1 * (T ** 2) + F1 * T) * (A1 * (T ** 2) + E1 + F1 * T + I1 * T)
        if disc < 0:
            U11 = U12 = num(0)
            uim = 1
        else:
            U12 = (disc ** 0.5 if m is math else m.sqrt(disc)) / (2 * (B1 + C1 * (T ** 2) + F1 * T))
        U = {1: U11 + U12, 2: U11 - U12}
        PSI = {k: (2 * m.atan(U[k]) / PI * 180 if S == 0 else U[k]) for k in (1, 2)}
        M11, M22 = {}, {}
        for lop in (1, 2):
            u = U[lop]
            M1 = -(1 + T ** 2) * (A1 * T + C1 * T * u ** 2 + .5 * D1 * u + .5 * F1 * (u ** 2 + 1) + (G1 + J1) * T * u + .5 * I1) / ((1 + u ** 2) * (B1 * u + C1 * u * T ** 2 + .5 * D1 * T + F1 * u * T + .5 * (G1 + J1) * T ** 2 + .5 * (G1 + H1)))
            M11[lop] = M1 if S != 1 else (1 + u ** 2) * M1 / 2
            if uim:
                M11[lop] = M1 = num(0)
            if clip:
                M11[lop] = max(-3, min(3, M11[lop]))
            P1 = (3 * u ** 2 + 1) * (B1 + C1 * T ** 2 + F1 * T) + u * ((G1 + J1) * T ** 2 + D1 * T + G1 + H1)
            Q1 = 2 * (1 + T ** 2) * (2 * C1 * T * u + .5 * D1 + F1 * u + (G1 + J1) * T)
            R1 = ((1 + T ** 2) / (1 + u ** 2)) * ((3 * T ** 2 + 1) * (A1 + C1 * u ** 2 + (G1 + J1) * u) + T * (F1 * (u ** 2 + 1) + D1 * u + I1))
            S1 = 2 * (B1 * u + C1 * u * T ** 2 + .5 * D1 * T + F1 * u * T + .5 * (G1 + J1) * T ** 2 + .5 * (G1 + H1))
            M2 = -(P1 * M1 ** 2 + Q1 * M1 + R1) / S1
            M22[lop] = M2 if S != 1 else ((M1 ** 2) * u + M2) * (1 + u ** 2) / 2
            if uim:
                M22[lop] = num(0)
            if clip:
                M22[lop] = max(-3, min(3, M22[lop]))
    except (ZeroDivisionError, OverflowError):
        return ("division", None, None, None)
    return ("uim" if uim else "ok", PSI[sol], M11[sol], M22[sol])
