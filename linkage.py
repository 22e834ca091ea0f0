"""linkage: Freudenstein and Mohammad Beigi's microcomputer kinematic analysis of the basic
linkage mechanisms, ported from the IBM-PC BASIC program of their paper ("On a computationally
efficient microcomputer kinematic analysis of the basic linkage mechanisms", Mechanism and
Machine Theory, 1980s).

    python3 linkage.py                  the original program: menu 1-6, prompts, ANG/VEL/ACC.DAT
    python3 linkage.py run TYPE ...     the same program driven by options (see --help)

Fidelity: ANG.DAT, VEL.DAT and ACC.DAT are byte-identical to those legacy_basic/LINKAGE.BAS
writes under PC-BASIC 2.0.8 given the same keystrokes (tests/test_port.py holds the port to
every case of data/golden/). The arithmetic is GW-BASIC's own single precision. Deviations from
the original, all where it would hang or lose data, are marked `# ERRATA Pn` here and listed in
legacy_basic/ERRATA.md, Part 3.

Sections: GW-BASIC single precision; the listing's computation; the original program
(screen, keys, INPUT, the menu session, files); the command line.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import shutil
import sys

__version__ = "0.2.0"


# ---- GW-BASIC single precision --------------------------------------------------------------
# GW-BASIC single precision (Microsoft Binary Format) as PC-BASIC 2.0.8 computes it.
#
# A single is held as a plain Python float whose value is exactly representable
# in MBF: a 24-bit mantissa 0.1xxx (binary) times 2**(E-128) with the exponent
# byte E in 1..255, or 0.0.  Every such value is an exact IEEE double, so
# comparisons, negation, INT and the FOR test need no emulation; the arithmetic
# functions below reproduce the interpreter's own rounding bit for bit.
#
# Soft errors ("Overflow", "Division by zero") do not stop the computation:
# the function returns +-MAX and calls the `err` callable it was given with the
# message, in the order the interpreter prints them.
MBF_MAX = math.ldexp(0xFFFFFF, 127 - 24)      # 1.701412E+38, the overflow value
OVERFLOW = "Overflow"
DIV_ZERO = "Division by zero"
_T24 = 16777216.0                        # 2**24


def _ignore(message):
    """Default soft-error sink: drop the message."""


# --------------------------------------------------------------------------
# representation helpers

def _split(x):
    """Return (negative, mantissa, exponent byte) of a nonzero single."""
    f, e = math.frexp(x)
    if f < 0:
        return True, int(-f * _T24), e + 128
    return False, int(f * _T24), e + 128


def _make(mbf_neg, m, eb, err):
    """Build a single from a 24-bit mantissa (possibly 2**24 after a rounding
    carry) and an exponent byte; handles overflow and underflow to zero."""
    if m >> 24:
        m >>= 1
        eb += 1
    if eb > 255:
        err(OVERFLOW)
        return -MBF_MAX if mbf_neg else MBF_MAX
    if eb <= 0 or m == 0:
        return 0.0
    v = math.ldexp(m, eb - 152)
    return -v if mbf_neg else v


def _round3(m, ah):
    """GW $ROUNS: keep the top 3 bits of the guard byte `ah`, round half to
    even on them.  Returns the rounded mantissa (may be 2**24)."""
    ah &= 0xE0
    if ah & 0x80:
        m += 1
        if ah == 0x80:
            m &= ~1
    return m


def mbf_from_bytes(b):
    """CVS: the single stored in 4 MBF bytes (exponent byte 0 means zero)."""
    if b[3] == 0:
        return 0.0
    m = b[0] | b[1] << 8 | (b[2] | 0x80) << 16
    v = math.ldexp(m, b[3] - 152)
    return -v if b[2] & 0x80 else v


def mbf_to_bytes(x):
    """MKS$: the 4 MBF bytes of a single (-0.0, made by unary minus of a
    zero, keeps its sign bit as in PC-BASIC)."""
    if x == 0:
        return b"\0\0\x80\0" if math.copysign(1.0, x) < 0 else bytes(4)
    mbf_neg, m, eb = _split(x)
    return bytes((m & 255, (m >> 8) & 255, ((m >> 16) & 0x7F) | (0x80 if mbf_neg else 0), eb))


# --------------------------------------------------------------------------
# the four operations

def mbf_add(x, y, err=_ignore):
    """X+Y as GW $FADDS: align the smaller operand right keeping a guard byte
    whose bit 5 is sticky, mbf_add or subtract, normalise, round ($ROUNS)."""
    if x == 0:
        return y
    if y == 0:
        return x
    nx, mx, ex = _split(x)
    ny, my, ey = _split(y)
    if ex < ey or (ex == ey and mx < my):
        x, nx, mx, ex, ny, my, ey = y, ny, my, ey, nx, mx, ex
    c = ex - ey
    if c >= 25:
        return x
    ah = _guard(my, c)
    small = my >> c
    if nx == ny:
        m = mx + small
        if m >> 24:
            ah = (m & 1) << 7 | ah >> 1
            m >>= 1
            ex += 1
            if ex > 255:
                err(OVERFLOW)
                return -MBF_MAX if nx else MBF_MAX
        return _make(nx, _round3(m, ah), ex, err)
    v = (mx << 8) - ((small << 8) | ah)
    if v == 0:
        return 0.0
    shift = 32 - v.bit_length()
    v <<= shift
    ex -= shift
    if ex <= 0:
        return 0.0
    return _make(nx, _round3(v >> 8, v & 0xFF), ex, err)


def _guard(m, c):
    """Guard byte left by GW's right shift of mantissa m by c (0..24) bits:
    the exact bits, with bit 5 (and the bits it has since been shifted into)
    set when any lower or lost bit was set."""
    if c == 0:
        return 0
    k, j = divmod(c, 8)
    if k:
        b = (m >> (8 * k - 8)) & 0xFF
        if b & 0x1F or m & ((1 << (8 * k - 8)) - 1):
            b |= 0x20
        w = ((m >> 8 * k) << 8) | b
    else:
        w = m << 8
    ah = (w >> j) & 0xFF
    if j and w:
        low = (w & -w).bit_length() - 1          # lowest set bit of w
        if low <= 5 + j:
            p0 = max(0, 5 - j, low - j)
            ah |= (0x3F >> p0 << p0) & 0x3F      # fill bits p0..5
    return ah


def mbf_sub(x, y, err=_ignore):
    """X-Y: GW returns X when Y is zero, else flips the sign of Y and adds."""
    if y == 0:
        return x
    return mbf_add(x, -y, err)


def mbf_mul(x, y, err=_ignore):
    """X*Y as GW $FMULS: the 48-bit product truncated to 24+3 bits, then
    rounded half to even on those 3 bits."""
    p = x * y                     # exact: 24x24 bits fit a double
    if p == 0:
        return 0.0
    f, e = math.frexp(p)
    mbf_neg = f < 0
    t = int((-f if mbf_neg else f) * 134217728.0)  # 27 bits, truncated
    m = t >> 3
    g = t & 7
    if g > 4 or (g == 4 and m & 1):
        m += 1
    return _make(mbf_neg, m, e + 128, err)


def mbf_div(x, y, err=_ignore):
    """X/Y rounded to nearest, ties to even (GW $SDIV).  Division by zero
    reports the error and gives +-MBF_MAX with the sign of X."""
    if y == 0:
        err(DIV_ZERO)
        return -MBF_MAX if x < 0 else MBF_MAX
    if x == 0:
        return 0.0
    q = x / y                     # double rounding 53->24 is innocuous for /
    f, e = math.frexp(q)
    mbf_neg = f < 0
    return _make(mbf_neg, round((-f if mbf_neg else f) * _T24), e + 128, err)


def mbf_neg(x):
    """Unary minus: flips the sign bit, also of a zero (MKS$ shows it)."""
    return -x


def mbf_int(x):
    """INT: the largest integer not above X (always exact in MBF)."""
    return float(math.floor(x))


# --------------------------------------------------------------------------
# double precision helpers (56-bit mantissa) used by number <-> text

def _rne_bits(n, bits):
    """Round the positive integer n to `bits` significant bits, ties to even.
    Returns (mantissa, shift) with n ~= mantissa * 2**shift."""
    sh = n.bit_length() - bits
    if sh <= 0:
        return n << -sh, sh
    m = n >> sh
    rest = n & ((1 << sh) - 1)
    half = 1 << (sh - 1)
    if rest > half or (rest == half and m & 1):
        m += 1
        if m >> bits:
            m >>= 1
            sh += 1
    return m, sh


def _dp_to_single(m56, sh, mbf_neg, err):
    """GW $CSD: double (56-bit mantissa m56 * 2**sh) to single, rounding half
    up on the 25th bit only."""
    m = ((m56 >> 31) + 1) >> 1
    eb = sh + 32 + 152
    return _make(mbf_neg, m, eb, err)


def _pow10_dp(k):
    """10**k (k >= 0) as the interpreter's double constant: (mantissa, shift)."""
    return _rne_bits(10 ** k, 56)


def _scale10(x, k, err=_ignore):
    """GW MDPTEN on a single: x * 10**k (k > 0) or x / 10**-k (k < 0) in
    double precision, then back to single with $CSD."""
    mbf_neg, m, eb = _split(x)
    e2 = eb - 152
    if k > 0:
        pm, psh = _pow10_dp(k)
        m56, sh = _rne_bits(m * pm, 56)
        return _dp_to_single(m56, sh + psh + e2, mbf_neg, err)
    d = 10 ** -k
    s = 60 + d.bit_length()
    q, r = divmod(m << s, d)
    q = q << 1 | (r != 0)                       # sticky bit
    m56, sh = _rne_bits(q, 56)
    return _dp_to_single(m56, sh - s - 1 + e2, mbf_neg, err)


def _digits(x):
    """Seven decimal digits and the decimal exponent k of |x| (x != 0), so
    that |x| ~ 0.ddddddd * 10**k: scale by the one mbf_power of ten that brings
    |x| into [1e6, 1e7) in double precision, round to single ($CSD), mbf_add .5
    if not whole, truncate (observed PC-BASIC behaviour, see NOTES.md)."""
    x = abs(x)
    _, m, eb = _split(x)
    e2 = eb - 152                      # x = m * 2**e2 exactly
    k = 6 - math.floor(math.log10(x))
    while _cmp_pow10(m, e2, k, 7) >= 0:
        k -= 1
    while _cmp_pow10(m, e2, k, 6) < 0:
        k += 1
    y = _scale10(x, k) if k else x
    if y != math.floor(y):
        y = mbf_add(y, 0.5)
    s = str(int(y))
    return s, len(s) - k


def _cmp_pow10(m, e2, k, p):
    """Sign of m * 2**e2 * 10**k - 10**p, in exact integer arithmetic."""
    a, b = m, 10 ** p
    if k >= 0:
        a *= 10 ** k
    else:
        b *= 10 ** -k
    if e2 >= 0:
        a <<= e2
    else:
        b <<= -e2
    return (a > b) - (a < b)


def _text(x):
    """The digits of x without sign or padding, as PRINT and WRITE show them."""
    if x == 0:
        return "0"
    d, k = _digits(x)
    d = d.rstrip("0")
    nd = len(d)
    if 0 < k <= 7:
        if nd <= k:
            return d + "0" * (k - nd)
        return d[:k] + "." + d[k:]
    if k <= 0 and nd - k <= 7:
        return "." + "0" * -k + d
    e = k - 1
    return "%s%sE%s%02d" % (d[0], "." + d[1:] if nd > 1 else "", "-" if e < 0 else "+", abs(e))


def mbf_write_text(x):
    """Number as WRITE # writes it: '-' for negatives, no padding."""
    return ("-" if x < 0 else "") + _text(x)


def mbf_print_text(x):
    """Number as PRINT shows it: sign or space in front, a space after."""
    return ("-" if x < 0 else " ") + _text(x) + " "


# --------------------------------------------------------------------------
# functions: GW-BASIC's single precision Hart polynomials ($POLY), with the
# double precision range reduction of SIN/COS.  Constants are the
# interpreter's MBF bytes.

def _c(*b):
    """A single constant from its MBF bytes."""
    return mbf_from_bytes(bytes(b))


_SINCN = (_c(0xFB, 0xD7, 0x1E, 0x86), _c(0x65, 0x26, 0x99, 0x87), _c(0x58, 0x34, 0x23, 0x87),
          _c(0xE1, 0x5D, 0xA5, 0x86), _c(0xDB, 0x0F, 0x49, 0x83))
_ATNC1 = (_c(0xD7, 0xB3, 0x5D, 0x81), _c(0x00, 0x00, 0x80, 0x81))
_ATNC2 = (_c(0x62, 0x35, 0x83, 0x7E), _c(0x50, 0x24, 0x4C, 0x7E), _c(0x79, 0xA9, 0xAA, 0x7F), 1.0)
_EXPCN = (_c(0x7C, 0x88, 0x59, 0x74), _c(0xE0, 0x97, 0x26, 0x77), _c(0xC4, 0x1D, 0x1E, 0x7A),
          _c(0x5E, 0x50, 0x63, 0x7C), _c(0x1A, 0xFE, 0x75, 0x7E), _c(0x18, 0x72, 0x31, 0x80), 1.0)
_LOGP = (_c(0x9A, 0xF7, 0x19, 0x83), _c(0x24, 0x63, 0x43, 0x83), _c(0x75, 0xCD, 0x8D, 0x84),
         _c(0xA9, 0x7F, 0x83, 0x82))
_LOGQ = (1.0, _c(0xE2, 0xB0, 0x4D, 0x83), _c(0x0A, 0x72, 0x11, 0x83), _c(0xF4, 0x04, 0x35, 0x7F))
_TWO_PI = _c(0xDB, 0x0F, 0x49, 0x83)
_HALF_PI = _c(0xDB, 0x0F, 0x49, 0x81)
_SIXTH_PI = _c(0x92, 0x0A, 0x06, 0x80)
_TAN_PI12 = _c(0xA2, 0x30, 0x09, 0x7F)
_SQR3 = _c(0xD7, 0xB3, 0x5D, 0x81)
_LOG2E = _c(0x3B, 0xAA, 0x38, 0x81)
_LN2 = _c(0x18, 0x72, 0x31, 0x80)
# 1/(2*pi) as the interpreter's double: 56-bit mantissa, value = _IN2PI_M * 2**-58
_IN2PI_M = 0xA2F9836E4E440B


def _poly(x, coeffs, err=_ignore):
    """$POLY: Horner's rule, highest coefficient first."""
    r = coeffs[0]
    for c in coeffs[1:]:
        r = mbf_add(mbf_mul(r, x, err), c, err)
    return r


def _polyx(x, coeffs, err=_ignore):
    """$POLYX: x * P(x*x)."""
    return mbf_mul(_poly(mbf_mul(x, x, err), coeffs, err), x, err)


def _quadrant_sin(turns, shift_quarter):
    """Shared SIN/COS core.  `turns` is the exact reduced angle in turns as
    (numerator, shift): value = numerator * 2**shift, 0 <= value < 1.
    Returns the single result before the final sign."""
    n, sh = turns
    if shift_quarter:                      # COS: mbf_add a quarter turn, reduce
        n, sh = _dp_add(n, sh, 1, -2)
        n, sh = _frac(n, sh)
    if n == 0:
        return 0.0, False
    q4n, q4sh = n, sh + 2                   # times 4: quadrant in integer part
    quad = q4n >> -q4sh if q4sh < 0 else q4n << q4sh
    fn, fsh = _frac(q4n, q4sh)
    if quad & 1:                            # quadrants 1 and 3: 1 - fraction
        fn, fsh = _dp_add(1, 0, -fn, fsh)
    negate = quad >= 2
    if fn == 0:
        return 0.0, negate
    m56, s56 = _rne_bits(fn, 56)
    y = _dp_to_single(m56, s56 + fsh - 2, False, _ignore)   # divide by 4
    if y == 0:
        return 0.0, negate
    if _split(y)[2] < 0x74:
        return mbf_mul(y, _TWO_PI), negate
    return _polyx(y, _SINCN), negate


def _dp_add(an, ash, bn, bsh):
    """Sum of a*2**ash and b*2**bsh rounded to 56 bits (GW $FADDD)."""
    s = min(ash, bsh)
    v = (an << (ash - s)) + (bn << (bsh - s))
    if v == 0:
        return 0, 0
    mbf_neg = v < 0
    m, sh = _rne_bits(-v if mbf_neg else v, 56)
    return (-m if mbf_neg else m), sh + s


def _frac(n, sh):
    """Fractional part of the nonnegative n * 2**sh (exact)."""
    if sh >= 0:
        return 0, 0
    return n & ((1 << -sh) - 1), sh


def _turns(x):
    """|x| / (2*pi) reduced to [0, 1) as GW does: double precision product
    with the double constant 1/(2*pi), rounded to 56 bits, minus its INT."""
    _, m, eb = _split(x)
    p, sh = _rne_bits(m * _IN2PI_M, 56)
    return _frac(p, sh + eb - 152 - 58)


def mbf_sin(x, err=_ignore):
    """SIN as GW-BASIC: tiny arguments returned as they are, otherwise
    double precision reduction to a quarter turn and Hart 3341."""
    if x == 0:
        return 0.0
    neg_in, _, eb = _split(x)
    if eb < 0x77:
        return x
    y, negate = _quadrant_sin(_turns(x), False)
    return -y if negate != neg_in else y


def mbf_cos(x, err=_ignore):
    """COS as GW-BASIC: SIN of the reduced angle plus a quarter turn."""
    if x == 0:
        return 1.0
    y, negate = _quadrant_sin(_turns(x), True)
    return -y if negate else y


def mbf_tan(x, err=_ignore):
    """TAN as GW-BASIC: SIN(X)/COS(X) with single precision division."""
    return mbf_div(mbf_sin(x), mbf_cos(x), err)


def mbf_atn(x, err=_ignore):
    """ATN as GW-BASIC: reduce by 1/x and by pi/6, then Hart 4940."""
    if x == 0:
        return 0.0
    negative = x < 0
    x = -x if negative else x
    invert = _split(x)[2] >= 0x81
    if invert:
        x = mbf_div(1.0, x, err)
    shift = x > _TAN_PI12
    if shift:
        s = mbf_add(x, _SQR3, err)
        x = mbf_div(_poly(x, _ATNC1, err), s, err)
    r = _polyx(x, _ATNC2, err)
    if shift:
        r = mbf_add(r, _SIXTH_PI, err)
    if invert:
        r = mbf_sub(_HALF_PI, r, err)
    return -r if negative else r


def mbf_exp(x, err=_ignore):
    """EXP as GW-BASIC: 2**(x*log2 e) split into 2**INT and Hart 1302."""
    y = mbf_mul(x, _LOG2E, err)
    if y == 0:
        return 1.0
    eb = _split(y)[2]
    if eb >= 0x88:
        if y < 0:
            return 0.0
        err(OVERFLOW)
        return MBF_MAX
    if eb < 0x68:
        return 1.0
    n = math.floor(y)
    if n + 0x81 > 255:
        err(OVERFLOW)
        return MBF_MAX
    f = mbf_sub(y, float(n), err)
    return mbf_mul(_poly(f, _EXPCN, err), math.ldexp(1.0, n), err)


def mbf_log(x, err=_ignore):
    """LOG as GW-BASIC (x > 0): Hart 2524 on the mantissa plus the
    exponent, times ln 2."""
    if x == 1.0:
        return 0.0
    _, m, eb = _split(x)
    f = math.ldexp(m, -24)
    r = mbf_div(_poly(f, _LOGP, err), _poly(f, _LOGQ, err), err)
    return mbf_mul(mbf_add(r, float(eb - 0x80), err), _LN2, err)


def mbf_power(x, y, err=_ignore):
    """X^Y as GW $FPWR: whole Y below 32768 by repeated squaring
    (T^2 is exactly T*T), otherwise EXP(Y*LOG(X)); negative Y inverts the
    result.  Overflow inside one ^ is reported once.  A negative X with a
    fractional Y is an Illegal function call (ValueError)."""
    seen = []

    def once(message):
        if not seen:
            seen.append(message)
            err(message)
    if y == 0:
        return 1.0
    if x == 0:
        if y < 0:
            err(DIV_ZERO)
            return MBF_MAX
        return 0.0
    whole = y == math.floor(y)
    if x < 0 and not whole:
        raise ValueError("Illegal function call")
    if y < 0:
        r = _power_pos(x, -y, whole, once)
        if r == 0:
            once(OVERFLOW)
            odd = whole and x < 0 and abs(y) < 32768 and int(-y) & 1
            return -MBF_MAX if odd else MBF_MAX
        return mbf_div(1.0, r, once)
    return _power_pos(x, y, whole, once)


def _power_pos(x, y, whole, err):
    """X^Y for Y > 0 (the FP30A part of $FPWR)."""
    if whole and y < 32768:
        n = int(y)
        r, z = 1.0, x
        while True:
            if n & 1:
                r = mbf_mul(r, z, err)
            n >>= 1
            if not n or abs(r) == MBF_MAX or abs(z) == MBF_MAX:
                return MBF_MAX if abs(r) == MBF_MAX or abs(z) == MBF_MAX else r
            z = mbf_mul(z, z, err)
    r = mbf_exp(mbf_mul(y, mbf_log(abs(x), err), err), err)
    if x < 0 and whole and int(y) & 1:
        return -r
    return r


# --------------------------------------------------------------------------
# text to number, FOR loops

def mbf_parse(text, err=_ignore):
    """A number typed at INPUT or written as a program literal (`.5`, `180!`,
    `2`, `1e3`, `3.141592654#`, `  -12  `) as the single it becomes: the
    decimal value rounded to a 56-bit double, then to single rounding half up
    on the 25th bit ($CSD).  Integers and up to 7 digits are exact."""
    s = text.strip().upper().rstrip("!#%")
    mbf_neg = s.startswith("-")
    s = s.lstrip("+-")
    mant, _, ex = s.replace("D", "E").partition("E")
    whole, _, frac = mant.partition(".")
    digits = (whole + frac).lstrip("0") or "0"
    k = (int(ex) if ex.strip("+-") else 0) - len(frac)
    n = int(digits)
    if n == 0:
        return 0.0
    if k >= 0:
        m56, sh = _rne_bits(n * 10 ** k, 56)
    else:
        d = 10 ** -k
        s2 = 60 + d.bit_length()
        q, r = divmod(n << s2, d)
        m56, sh = _rne_bits(q << 1 | (r != 0), 56)
        sh -= s2 + 1
    return _dp_to_single(m56, sh, mbf_neg, err)


def mbf_for_values(start, stop, step, err=_ignore):
    """The values a single FOR variable takes: FOR V=start TO stop STEP step
    runs the body with V=start unless start is already past stop, then adds
    step in single precision after each pass and goes on while V has not
    passed stop (STEP 0 runs the body once).  The last value yielded is not
    the variable's value after the loop: see mbf_for_final()."""
    v = start
    if (step > 0 and v > stop) or (step < 0 and v < stop):
        return
    while True:
        yield v
        v = mbf_add(v, step, err)
        if not ((step > 0 and v <= stop) or (step < 0 and v >= stop)):
            return


def mbf_for_final(start, stop, step, err=_ignore):
    """The FOR variable's value after the loop has ended (start+step when
    the body never ran)."""
    last = start
    for last in mbf_for_values(start, stop, step, err):
        pass
    return mbf_add(last, step, err)


# ---- The listing's computation: lines 110, 250-930 and 1050-1340 ----------------------------
#
# The listing's variables keep their BASIC names here, so that this section can be read beside
# legacy_basic/LINKAGE.BAS line by line. In the paper's symbols (eqs. (1)-(3), Table 1):
#
#   listing          paper                     listing         paper
#   A B C D          a b c d (fixed link,      P(1..8)         p1..p8, real parts
#                    crank, coupler, output)   PIM(1..8)       p1..p8, imaginary parts
#   E                e (slider offset)         A1 B1 C1 D1 E1  A1 A2 A3 A4 A5
#   F, KSI, G        f, xi, g = f / cos xi     F1 G1 H1 I1 J1  A6 A7 A8 A9 A10
#   S                s (1 for slider-cranks)   T, U(1..2)      t = tan(phi/2), u (or x)
#   BT CT DT DIAG    b c d a for the check     M1, M11         m1 (dpsi/dphi), m1' (sliders)
#   CIM              1: coupler imaginary      M2, M22         m2, m2' (eqs. (5)-(7))
#
# Arithmetic is GW-BASIC's: a `Single` rounds every + - * / ^ as PC-BASIC does, and Python's
# operator precedence is BASIC's (^ first, then unary minus, then * /, then + -, each left to
# right), so an expression below evaluates in the listing's order when written as the listing
# writes it. Literals (2, .5, 180 for 180!) are exact singles. Soft errors ("Overflow",
# "Division by zero") collect in Single.errors, in order, for the screen to show.


class Single:
    """A GW-BASIC single-precision value; arithmetic rounds as PC-BASIC 2.0.8 does."""

    __slots__ = ("v",)
    errors: list[str] = []

    def __init__(self, v: float = 0.0):
        self.v = v

    def __repr__(self) -> str:
        return f"Single({mbf_write_text(self.v)})"

    def __add__(self, other): return Single(mbf_add(self.v, _value(other), _soft_error))
    def __radd__(self, other): return Single(mbf_add(_value(other), self.v, _soft_error))
    def __sub__(self, other): return Single(mbf_sub(self.v, _value(other), _soft_error))
    def __rsub__(self, other): return Single(mbf_sub(_value(other), self.v, _soft_error))
    def __mul__(self, other): return Single(mbf_mul(self.v, _value(other), _soft_error))
    def __rmul__(self, other): return Single(mbf_mul(_value(other), self.v, _soft_error))
    def __truediv__(self, other): return Single(mbf_div(self.v, _value(other), _soft_error))
    def __rtruediv__(self, other): return Single(mbf_div(_value(other), self.v, _soft_error))
    def __pow__(self, other): return Single(mbf_power(self.v, _value(other), _soft_error))
    def __rpow__(self, other): return Single(mbf_power(_value(other), self.v, _soft_error))
    def __neg__(self): return Single(mbf_neg(self.v))
    def __lt__(self, other): return self.v < _value(other)
    def __le__(self, other): return self.v <= _value(other)
    def __gt__(self, other): return self.v > _value(other)
    def __ge__(self, other): return self.v >= _value(other)
    def __eq__(self, other): return self.v == _value(other)
    def __hash__(self): return hash(self.v)


def _value(x) -> float:
    return x.v if isinstance(x, Single) else float(x)


def _soft_error(message: str) -> None:
    Single.errors.append(message)


def SIN(x: Single) -> Single: return Single(mbf_sin(x.v, _soft_error))
def COS(x: Single) -> Single: return Single(mbf_cos(x.v, _soft_error))
def TAN(x: Single) -> Single: return Single(mbf_tan(x.v, _soft_error))
def ATN(x: Single) -> Single: return Single(mbf_atn(x.v, _soft_error))
def INT(x: Single) -> Single: return Single(mbf_int(x.v))


ZERO = Single(0.0)
PI = Single(mbf_parse("3.141592654#"))                                  # 110


@dataclasses.dataclass
class Variables:
    """The listing's variables that matter between passes through the menu: "Illegal linkage"
    goes back with GOTO 130, not RUN, so every one keeps its value (ERRATA K1-K3)."""

    A: Single = ZERO
    B: Single = ZERO
    C: Single = ZERO
    D: Single = ZERO
    E: Single = ZERO
    F: Single = ZERO
    G: Single = ZERO
    KSI: Single = ZERO
    S: Single = ZERO
    CIM: Single = ZERO
    BT: Single = ZERO
    CT: Single = ZERO
    DT: Single = ZERO
    DIAG: Single = ZERO


PROMPTS = {
    "b": "Please enter the input crank length: ",
    "c": "       enter the connecting rod length: ",
    "d": "       enter the output crank length: ",
    "a": "       enter the fixed link length: ",
    "a-skew": "       enter the horizontal sector of the fixed link length: ",
    "e": "       enter the center offset: ",
    "f": "       enter the vertical sector of the fixed link: ",
    "ksi": "       enter the skew angle: ",
    "from": "Enter the first bound of the input angle: ",
    "to": "Enter the second bound of the input angle: ",
    "step": "Enter increment: ",
}


def dimensions(v: Variables, bartype: int, ask) -> bool:
    """Lines 250-480: ask for linkage `bartype`'s dimensions (ask(prompt) is INPUT), convert
    them and run the assembly check. True when the linkage passes it."""
    if bartype >= 4:                                                        # 250
        v.S = Single(1.0)
    v.B = ask(PROMPTS["b"]); v.BT = v.B                                     # 260
    v.C = ask(PROMPTS["c"]); v.CT = v.C                                     # 270
    if not v.S == 1:                                                        # 280
        v.D = ask(PROMPTS["d"]); v.DT = v.D                                 # 290
    if bartype <= 2:                                                        # 300
        v.A = ask(PROMPTS["a"]); v.DIAG = v.A
    if bartype in (3, 5):                                                   # 310
        v.A = ask(PROMPTS["a-skew"])
    if bartype == 4:                                                        # 320
        v.E = ask(PROMPTS["e"])
        v.C = (v.C**2 - v.E**2)                                             # 450
    else:
        if bartype == 2:                                                    # 330
            v.A = (v.A / 180) * PI; v.DIAG = v.A - (INT(v.A / PI) * PI)     # 340
            v.B = (v.B / 180) * PI; v.BT = v.B - (INT(v.B / PI) * PI)       # 350
            v.C = (v.C / 180) * PI; v.CT = v.C - (INT(v.C / PI) * PI)       # 360
            v.D = (v.D / 180) * PI; v.DT = v.D - (INT(v.D / PI) * PI)       # 370
        if bartype not in (3, 5):                                           # 380
            return _assembles(v, bartype)
        v.F = ask(PROMPTS["f"])                                             # 390
        v.KSI = ask(PROMPTS["ksi"]); v.KSI = (v.KSI / 180) * PI             # 400
        v.DIAG = (v.A**2 + (v.F * TAN(v.KSI))**2)**.5
        if bartype == 5:                                                    # 410
            v.G = ZERO
        else:
            v.G = v.F / COS(v.KSI)                                          # 420
        v.C = (v.C**2 - v.F**2 - v.G**2 + 2 * v.F * v.G * COS(v.KSI))       # 430
    if v.C >= 0:                                                            # 460
        v.C = v.C**.5; v.CIM = ZERO
    if v.C < 0:                                                             # 470
        v.CIM = Single(1.0); v.C = (-v.C)**.5
    return _assembles(v, bartype)


def _assembles(v: Variables, bartype: int) -> bool:
    """Line 480, the assembly check (none for the plane slider-crank; see ERRATA K4)."""
    DIAG, BT, CT, DT = v.DIAG, v.BT, v.CT, v.DT
    return not (bartype != 4 and (DIAG > BT + CT + DT or BT > DIAG + CT + DT
                                  or CT > DIAG + BT + DT or DT > DIAG + BT + CT))


def coefficients(v: Variables, bartype: int) -> tuple[Single, ...]:
    """Lines 520-930: the coefficients A1..J1 of the half-tangent equation (2)."""
    A, B, C, D, E, F, G, KSI, S = v.A, v.B, v.C, v.D, v.E, v.F, v.G, v.KSI, v.S
    P, PIM = [ZERO] * 9, [ZERO] * 9                     # P(1..8), PIM(1..8); index 0 unused
    if v.CIM == 0:                                                          # 520
        P[1] = (A - B + C - D) / 2; P[2] = (A - B - C - D) / 2              # 540
        P[3] = (A + B + C - D) / 2; P[4] = (A + B - C - D) / 2              # 550
        P[5] = (A - B + C + D) / 2; P[6] = (A - B - C + D) / 2              # 560
        P[7] = (A + B + C + D) / 2; P[8] = (A + B - C + D) / 2              # 570
    else:
        for LOP in range(1, 9):                                             # 590
            PIM[LOP] = ((-Single(1.0))**(Single(float(LOP)) + 1)) * C / 2
        P[1] = (A - B - D) / 2; P[2] = P[1]                                 # 600
        P[3] = (A + B - D) / 2; P[4] = P[3]                                 # 610
        P[5] = (A - B + D) / 2; P[6] = P[5]                                 # 620
        P[7] = (A + B + D) / 2; P[8] = P[7]                                 # 630
    if bartype == 3:                                                        # 640
        A1 = (P[7] * P[8]) - (PIM[7] * PIM[8])                              # 650
        B1 = (P[1] * P[2]) - (PIM[1] * PIM[2])                              # 660
        C1 = (P[3] * P[4]) - (PIM[3] * PIM[4])                              # 670
        D1 = -2 * COS(KSI) * B * D                                          # 680
        E1 = (P[5] * P[6]) - (PIM[5] * PIM[6])                              # 690
        F1 = -G * B * SIN(KSI)                                              # 700
        G1 = F * D * SIN(KSI); H1 = I1 = J1 = ZERO                          # 710
    elif bartype >= 4:                                                      # 730
        A1 = 4 * ((P[7] * P[8]) - (PIM[7] * PIM[8])); B1 = S; C1 = S        # 740
        D1 = -4 * B * SIN(KSI)                                              # 750
        if bartype == 4:
            D1 = ZERO
        E1 = 4 * ((P[5] * P[6]) - (PIM[5] * PIM[6]))                        # 760
        F1 = G1 = I1 = ZERO                                                 # 770
        if bartype == 4:
            I1 = -4 * v.E * B
        H1 = -2 * F * COS(KSI)                                              # 780
        if bartype == 4:
            H1 = -2 * B
        J1 = -2 * F * COS(KSI)                                              # 790
        if bartype == 4:
            J1 = 2 * B
    elif bartype == 2:                                                      # 800
        A1 = SIN(P[7]) * SIN(P[8])                                          # 810
        B1 = SIN(P[1]) * SIN(P[2])                                          # 820
        C1 = SIN(P[3]) * SIN(P[4])                                          # 830
        D1 = -2 * SIN(B) * SIN(D)                                           # 840
        E1 = SIN(P[5]) * SIN(P[6])                                          # 850
        F1 = G1 = H1 = I1 = J1 = ZERO                                       # 860
    else:                                                                   # 870
        A1 = P[7] * P[8]                                                    # 880
        B1 = P[1] * P[2]                                                    # 890
        C1 = P[3] * P[4]                                                    # 900
        D1 = -2 * B * D                                                     # 910
        E1 = P[5] * P[6]                                                    # 920
        F1 = G1 = H1 = I1 = J1 = ZERO                                       # 930
    return A1, B1, C1, D1, E1, F1, G1, H1, I1, J1


def degrees_to_radians(x: Single) -> Single:
    """Lines 960, 1000, 1010: (X/180!)*PI."""
    return (x / 180) * PI


def sweep_angles(PHI1: Single, PHI2: Single, INC: Single):
    """Line 1050, FOR PHI=PHIB(1) TO PHIB(2) STEP INC: the values PHI takes."""
    for phi in mbf_for_values(PHI1.v, PHI2.v, INC.v, _soft_error):
        yield Single(phi)


def sweep_point(co: tuple[Single, ...], PHI: Single, SOL: int, S: Single) -> tuple[str, str, str]:
    """Lines 1060-1330 at one input angle: the lines WRITE # puts in ANG.DAT, VEL.DAT, ACC.DAT
    for solution SOL (1 is (A+B), 2 is (A-B))."""
    A1, B1, C1, D1, E1, F1, G1, H1, I1, J1 = co
    T = TAN(.5 * PHI)                                                                    # 1060
    U11 = -(D1*T + (G1+J1)*T**2 + (G1+H1)) / (2*(B1 + C1*(T**2) + F1*T))                # 1070
    if ((D1*T + (G1+J1)*T**2 + (G1+H1))**2) < 4*(B1 + C1*(T**2) + F1*T)*(A1*(T**2) + E1 + F1*T + I1*T):  # 1080
        U11 = U12 = ZERO
        UIM = True
    else:
        UIM = False
        U12 = ((((D1*T + (G1+J1)*T**2 + (G1+H1))**2) - 4*(B1 + C1*(T**2) + F1*T)*(A1*(T**2) + E1 + F1*T + I1*T))**.5) / (2*(B1 + C1*(T**2) + F1*T))  # 1090
    U = (U11 + U12, U11 - U12)                                                           # 1100-1110
    PSI = U                                                                              # 1120
    if S == 0:                                                                           # 1130-1140
        PSI = tuple((2*ATN(u)/PI)*180 for u in U)
    angle = mbf_write_text(((PHI/PI)*180).v)
    ang = f"{angle},{mbf_write_text(PSI[SOL - 1].v)}\r\n"                               # 1150
    M11, M22 = [ZERO, ZERO], [ZERO, ZERO]
    for k, u in enumerate(U):                                                            # 1160
        M1 = -(1 + T**2)*(A1*T + C1*T*u**2 + .5*D1*u + .5*F1*(u**2 + 1) + (G1+J1)*T*u + .5*I1) / ((1 + u**2)*(B1*u + C1*u*T**2 + .5*D1*T + F1*u*T + .5*(G1+J1)*T**2 + .5*(G1+H1)))  # 1170
        M11[k] = M1                                                                      # 1172
        if S == 1:                                                                       # 1175
            M11[k] = (1 + u**2)*M1/2
        if UIM:                                                                          # 1180
            M11[k] = M1 = ZERO
        if M11[k] > 3:                                                                   # 1200
            M11[k] = Single(3.0)
        if M11[k] < -3:                                                                  # 1210
            M11[k] = Single(-3.0)
        P1 = (3*u**2 + 1)*(B1 + C1*T**2 + F1*T) + u*((G1+J1)*T**2 + D1*T + G1 + H1)      # 1220
        Q1 = 2*(1 + T**2)*(2*C1*T*u + .5*D1 + F1*u + (G1+J1)*T)                          # 1230
        R1 = ((1 + T**2)/(1 + u**2))*((3*T**2 + 1)*(A1 + C1*u**2 + (G1+J1)*u) + T*(F1*(u**2 + 1) + D1*u + I1))  # 1240
        S1 = 2*(B1*u + C1*u*T**2 + .5*D1*T + F1*u*T + .5*(G1+J1)*T**2 + .5*(G1+H1))      # 1250
        M2 = -(P1*M1**2 + Q1*M1 + R1)/S1                                                 # 1260
        M22[k] = M2                                                                      # 1262
        if S == 1:                                                                       # 1265
            M22[k] = ((M1**2)*u + M2)*(1 + u**2)/2
        if UIM:                                                                          # 1270
            M2 = M22[k] = ZERO
        if M22[k] > 3:                                                                   # 1290
            M22[k] = Single(3.0)
        if M22[k] < -3:                                                                  # 1300
            M22[k] = Single(-3.0)
    vel = f"{angle},{mbf_write_text(M11[SOL - 1].v)}\r\n"                               # 1320
    acc = f"{angle},{mbf_write_text(M22[SOL - 1].v)}\r\n"                               # 1330
    return ang, vel, acc

# ---- The original program: keys, screen, INPUT, the session, the files ---------------------


class EndOfKeys(Exception):
    """The keystrokes ran out while the program waited for one (ERRATA P4)."""


class ProgramStop(Exception):
    """The port stops where the original would hang or lose data; the message says why."""


class Keys:
    """Keystrokes one at a time from a byte stream, as PC-BASIC reads its --input file:
    CR LF is one Enter, NUL and the byte after it are one extended key."""

    def __init__(self, read_byte, fold_crlf: bool):
        self._read = read_byte
        self._fold = fold_crlf
        self._pending = b""

    def _byte(self) -> bytes:
        if self._pending:
            byte, self._pending = self._pending, b""
            return byte
        byte = self._read()
        if not byte:
            raise EndOfKeys
        return byte

    def get(self) -> str:
        byte = self._byte()
        if byte == b"\0":
            return "\0" + self._byte().decode("latin-1")
        if byte == b"\r" and self._fold:
            try:
                after = self._byte()
            except EndOfKeys:
                after = b""
            if after != b"\n":
                self._pending = after
        return byte.decode("latin-1")


class Screen:
    """PRINT, CLS, LOCATE and SOUND. On a terminal they draw with ANSI codes; redirected, the
    output is PC-BASIC's own transcript (--output=STDOUT): lines ended by CR LF, no positions."""

    def __init__(self, write, terminal: bool, soft_errors=None):
        self._write = write
        self._write_soft_error = write if soft_errors is None else soft_errors
        self.terminal = terminal

    def text(self, s: str) -> None:
        self.show_soft_errors()
        self._write(s)

    def line(self, s: str = "") -> None:
        self.text(s + "\r\n")

    def cls(self) -> None:
        if self.terminal:
            self.text("\x1b[2J\x1b[H")

    def locate(self, row: int, column: int) -> None:
        if self.terminal:
            self.text(f"\x1b[{row};{column}H")

    def beep(self) -> None:
        """SOUND 1500,1: the terminal's bell (PC-BASIC run with --sound=False prints nothing)."""
        if self.terminal:
            self._write("\a")

    def show_soft_errors(self) -> None:
        while Single.errors:
            self._write_soft_error(Single.errors.pop(0) + "\r\n")


def input_number(screen: Screen, keys: Keys, prompt: str) -> Single:
    """INPUT "prompt",X: read a line with GW-BASIC's editing keys and convert it as INPUT does;
    "?Redo from start" and the prompt again when it is not one number."""
    while True:
        screen.text(prompt)
        typed, echo = _read_line(screen, keys, column=len(prompt))
        if not screen.terminal:
            screen.text(echo)
        screen.line()
        value = input_value(typed)
        if value is not None:
            return value
        screen.line("?Redo from start")


def _read_line(screen: Screen, keys: Keys, column: int) -> tuple[str, str]:
    """The line typed up to Enter, and its echo. Backspace deletes, Esc clears, Tab moves to the
    next of GW-BASIC's 8-column stops, a line feed only breaks the echo (PC-BASIC's behaviour);
    other control keys and extended keys are ignored (ERRATA P5)."""
    typed, echo = "", ""
    while True:
        key = keys.get()
        if key == "\r":
            return typed, echo
        if key == "\b" or (key == "\x7f" and screen.terminal):
            if typed:
                typed, echo = typed[:-1], echo[:-1]
                if screen.terminal:
                    screen.text("\b \b")
            continue
        if key == "\x1b":
            if screen.terminal:
                screen.text("\b \b" * len(typed))
            typed, echo = "", ""
            continue
        if key == "\t":
            key = " " * (8 - (column + len(typed)) % 8)
        elif key == "\n":
            echo += "\n"
            continue
        elif len(key) != 1 or key < " " or key == "\x7f":
            continue
        typed, echo = typed + key, echo + key
        if screen.terminal:
            screen.text(key)


def input_value(typed: str) -> Single | None:
    """What INPUT makes of an answer for one numeric variable, or None for "?Redo from start".
    Spaces are ignored; empty is 0; &H and &O (or &) are 16-bit integers; a decimal number may
    have a sign, a point, an exponent (E or D, whose digits may be missing) and a ! or # after
    which anything is ignored. Overflow prints "Overflow" and gives 1.701412E+38."""
    s = typed.replace(" ", "").upper()
    if s.startswith("&"):
        return _input_integer(s[1:])
    number, suffix = s, ""
    for mark in "!#":
        if mark in number:
            number, suffix = number.split(mark, 1)
    sign = ""
    if number[:1] in "+-" and number:
        sign, number = number[0], number[1:]
    mantissa, exponent = number, ""
    for mark in "ED":
        if mark in mantissa:
            mantissa, exponent = mantissa.split(mark, 1)
    whole, _, fraction = mantissa.partition(".")
    fraction = fraction.replace(".", "")
    exp_sign = exponent[:1] if exponent[:1] in ("+", "-") else ""
    exp_digits = exponent[len(exp_sign):]
    if not (whole + fraction + exp_digits).isdigit() and (whole + fraction + exp_digits):
        return None
    if not mantissa.strip(".") and exponent:
        return None                                     # "E5": PC-BASIC's own oddity (P5)
    text = f"{sign}{whole or '0'}.{fraction or '0'}E{exp_sign}{exp_digits or '0'}"
    return Single(mbf_parse(text, _soft_error))


def _input_integer(digits: str) -> Single | None:
    """&Hxxxx, &Oooo or &ooo: a 16-bit two's-complement integer."""
    base = 8
    if digits[:1] == "H":
        base, digits = 16, digits[1:]
    elif digits[:1] == "O":
        digits = digits[1:]
    try:
        n = int(digits, base) if digits else 0
    except ValueError:
        return None
    if n > 0xFFFF:
        return None
    return Single(float(n - 0x10000 if n >= 0x8000 else n))


def key_value(key: str) -> int:
    """VAL of a one-key string: its digit, or 0."""
    return "0123456789".find(key) if len(key) == 1 and key in "0123456789" else 0


class DatFiles:
    """ANG.DAT, VEL.DAT and ACC.DAT written as GW-BASIC's sequential files (CR LF lines, the
    end-of-file byte 1A on CLOSE). They are written under temporary names and renamed on CLOSE,
    so an interrupted sweep leaves no file that looks complete (ERRATA P3)."""

    NAMES = ("ANG.DAT", "VEL.DAT", "ACC.DAT")

    def __init__(self, directory: str):
        self._final = [os.path.join(directory, n) for n in self.NAMES]
        self._partial = [os.path.join(directory, f".{n}.partial") for n in self.NAMES]
        self._files = []
        try:
            for path in self._partial:
                self._files.append(open(path, "w", encoding="ascii", newline=""))
        except OSError as e:
            self.discard()
            raise ProgramStop(f"cannot write the DAT files in {directory!r}: {e.strerror}")
        except BaseException:                   # Ctrl-C between two of the three
            self.discard()
            raise

    def write(self, lines: tuple[str, str, str]) -> None:
        for f, line in zip(self._files, lines):
            f.write(line)

    def close(self) -> None:
        """CLOSE (line 1350): the end-of-file byte, then the files get their names."""
        for f in self._files:
            f.write("\x1a")
            f.close()
        for partial, final in zip(self._partial, self._final):
            os.replace(partial, final)

    def discard(self) -> None:
        for f in self._files:
            f.close()
        for path in self._partial:
            if os.path.exists(path):
                os.remove(path)


MENU = ((6, "1. Plane Four Bar"), (8, "2. Spherical Four Bar"), (10, "3. Skew Four Bar"),
        (12, "4. Plane Slider Crank"), (14, "5. Skew Slider Crank"), (16, "6. Exit"))
BYTES_PER_POINT = 3 * len("-1.234567E+38,-1.234567E+38\r\n")


def run_session(screen: Screen, keys: Keys, directory: str = ".",
                stop_if_illegal: bool = False) -> None:
    """The whole program, lines 100-1360, driven by `keys`: the menu until a linkage assembles
    (or 6), its sweep, the three files. `stop_if_illegal` turns "Illegal linkage" into a
    ProgramStop instead of a return to the menu (for the run command)."""
    v = Variables()
    while True:
        screen.cls()                                                        # 130-190
        for row, item in MENU:
            screen.locate(row, 25)
            screen.line(item)
        screen.locate(23, 25)
        screen.line("Enter Option: _")
        while True:                                                         # 200-240
            key = keys.get()
            if 1 <= key_value(key) <= 5:
                bartype = key_value(key)
                break
            if key == "6":
                return                                                      # 1360
            screen.beep()
        screen.cls()                                                        # 260
        if dimensions(v, bartype, lambda prompt: input_number(screen, keys, prompt)):
            break
        if stop_if_illegal:
            raise ProgramStop("Illegal linkage (impossible to assemble)")
        screen.cls()                                                        # 500
        screen.locate(12, 20)
        screen.line("Illegal linkage (impossible to assemble)")
        screen.locate(23, 25)
        screen.line("Hit any key to continue")
        keys.get()                                                          # 510
    co = coefficients(v, bartype)
    PHI1 = input_number(screen, keys, PROMPTS["from"])                      # 940
    PHI2 = input_number(screen, keys, PROMPTS["to"])                        # 950
    INC = degrees_to_radians(input_number(screen, keys, PROMPTS["step"]))   # 960
    screen.line("Which solution do you need? 1. (A+B)     2. (A-B)")       # 970
    while True:                                                             # 980-990
        SOL = key_value(keys.get())
        if 1 <= SOL <= 2:
            break
        screen.beep()
    sweep(screen, co, degrees_to_radians(PHI1), degrees_to_radians(PHI2), INC, SOL, v.S,
          directory)                                                        # 1000-1350


def sweep(screen: Screen, co, PHI1: Single, PHI2: Single, INC: Single, SOL: int, S: Single,
          directory: str) -> None:
    """Lines 1020-1350: open the files, sweep PHI, close."""
    files = DatFiles(directory)                                             # 1020-1040
    try:
        check_sweep(PHI1, PHI2, INC, directory)
        for PHI in sweep_angles(PHI1, PHI2, INC):                           # 1050, 1340
            files.write(sweep_point(co, PHI, SOL, S))
            screen.show_soft_errors()
    except BaseException:
        files.discard()
        raise
    files.close()                                                           # 1350


def check_sweep(PHI1: Single, PHI2: Single, INC: Single, directory: str) -> None:
    """Refuse the sweeps the original would never finish (ERRATA P1, P2)."""
    if INC == 0:
        raise ProgramStop("the increment is 0: the original would write points for ever "
                          "(GW-BASIC's FOR never ends with STEP 0)")
    if (INC > 0 and PHI1 > PHI2) or (INC < 0 and PHI1 < PHI2):
        return
    far = PHI1 if abs(PHI1.v) > abs(PHI2.v) else PHI2
    if mbf_add(far.v, INC.v) == far.v:
        raise ProgramStop("the increment is too small for single precision: the input angle "
                          "would stop advancing and the original would loop for ever")
    points = (PHI2.v - PHI1.v) / INC.v + 1
    free = shutil.disk_usage(directory).free
    if points * BYTES_PER_POINT > free:
        raise ProgramStop(f"the sweep has about {points:,.0f} points, up to "
                          f"{points * BYTES_PER_POINT:,.0f} bytes of DAT files, and only "
                          f"{free:,} bytes are free in {directory!r}")

# ---- The command line ---------------------------------------------------------------------

MECHANISM_TYPES = {  # name: (menu key, the dimensions in the order the listing asks for them)
    "plane": ("1", ("b", "c", "d", "a")),
    "spherical": ("2", ("b", "c", "d", "a")),
    "skew": ("3", ("b", "c", "d", "a", "f", "skew")),
    "slider": ("4", ("b", "c", "e")),
    "skew-slider": ("5", ("b", "c", "a", "f", "skew")),
}
DIMENSION_HELP = {
    "a": "fixed link (skew linkages: its horizontal sector); degrees for the spherical linkage",
    "b": "input crank", "c": "connecting rod (coupler)", "d": "output crank",
    "e": "slider offset", "f": "vertical sector of the fixed link", "skew": "skew angle, degrees",
}


def menu_program(stdin=None, stdout=None, directory: str = ".") -> int:
    """`python3 linkage.py`: the original program on this terminal, or driven by the keys on
    standard input (`python3 linkage.py < keys.txt`) with PC-BASIC's screen transcript."""
    stdin = sys.stdin if stdin is None else stdin
    stdout = sys.stdout if stdout is None else stdout
    if not (stdin.isatty() and stdout.isatty()):
        return redirected_program(stdin.buffer, stdout.buffer, directory)
    import termios
    fd = stdin.fileno()
    saved = termios.tcgetattr(fd)
    mode = termios.tcgetattr(fd)
    mode[0] &= ~termios.ICRNL                      # Enter arrives as CR, as on the PC
    mode[3] &= ~(termios.ICANON | termios.ECHO)    # single keys, no echo; Ctrl-C still breaks
    mode[6][termios.VMIN], mode[6][termios.VTIME] = 1, 0
    try:
        termios.tcsetattr(fd, termios.TCSAFLUSH, mode)

        def write(s: str) -> None:
            stdout.write(s)
            stdout.flush()
        keys = Keys(lambda: os.read(fd, 1), fold_crlf=False)
        return _run_guarded(Screen(write, terminal=True), keys, directory)
    finally:
        termios.tcsetattr(fd, termios.TCSAFLUSH, saved)


def redirected_program(keys_in, screen_out, directory: str = ".") -> int:
    """The menu program reading its keys from the byte stream `keys_in` and writing PC-BASIC's
    screen transcript (CR LF lines) to the byte stream `screen_out`."""
    keys = Keys(lambda: keys_in.read(1), fold_crlf=True)
    screen = Screen(lambda s: screen_out.write(s.encode("utf-8")), terminal=False)
    try:
        return _run_guarded(screen, keys, directory)
    finally:
        screen_out.flush()


def _run_guarded(screen: Screen, keys: Keys, directory: str) -> int:
    """Run the session; turn the ways it can stop into a message and an exit status."""
    try:
        run_session(screen, keys, directory)
        screen.show_soft_errors()
        return 0
    except EndOfKeys:
        error, status = "the keystrokes ended before the program did; no DAT file was written", 1
    except ProgramStop as stop:
        error, status = str(stop), 1
    except KeyboardInterrupt:
        error, status = "interrupted; no DAT file was written", 130
    finally:
        if screen.terminal:
            screen.line()
    print(f"linkage.py: {error}", file=sys.stderr)
    return status


def run_command(args: argparse.Namespace, parser: argparse.ArgumentParser) -> int:
    """`python3 linkage.py run TYPE ...`: the menu program given these answers."""
    key, needed = MECHANISM_TYPES[args.type]
    given = {name for name in DIMENSION_HELP if getattr(args, name) is not None}
    missing = [f"--{n}" for n in needed if n not in given]
    extra = [f"--{n}" for n in sorted(given - set(needed))]
    if missing or extra:
        what = ("missing " + " ".join(missing)) if missing else ("no use for " + " ".join(extra))
        parser.error(f"{args.type} needs {' '.join('--' + n for n in needed)}: {what}")
    answers = [getattr(args, n) for n in needed] + [args.start, args.stop, args.step]
    for name, text in zip(list(needed) + ["from", "to", "step"], answers):
        if input_value(text) is None:
            parser.error(f"--{name} {text!r} is not a number")
    keystrokes = (key + "".join(a + "\r" for a in answers) + args.branch).encode("latin-1")
    stream = iter(keystrokes[i:i + 1] for i in range(len(keystrokes)))
    keys = Keys(lambda: next(stream, b""), fold_crlf=True)
    screen = Screen(lambda s: None, terminal=False,
                    soft_errors=lambda s: sys.stderr.write(s.replace("\r\n", "\n")))
    if not os.path.isdir(args.dir):
        parser.error(f"--dir {args.dir!r} is not a directory")
    try:
        run_session(screen, keys, args.dir, stop_if_illegal=True)
    except ProgramStop as stop:
        print(f"linkage.py: {stop}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("linkage.py: interrupted; no DAT file was written", file=sys.stderr)
        return 130
    screen.show_soft_errors()
    return 0


def _mechanism_type(text: str) -> str:
    by_number = {key: name for name, (key, _) in MECHANISM_TYPES.items()}
    name = by_number.get(text, text)
    if name not in MECHANISM_TYPES:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not one of {', '.join(MECHANISM_TYPES)} (or 1-5)")
    return name


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="linkage.py", description=__doc__.split("\n\n")[0],
        epilog="With no command: the original menu program.")
    commands = parser.add_subparsers(dest="command")
    run = commands.add_parser(
        "run", help="the original program driven by options",
        description="The original program given these answers: writes ANG.DAT, VEL.DAT and "
                    "ACC.DAT exactly as the menu would. Dimensions are typed as in the menu "
                    "(degrees for the spherical linkage's arcs). "
                    + "; ".join(f"{name}: {' '.join('--' + d for d in dims)}"
                                for name, (_, dims) in MECHANISM_TYPES.items()) + ".")
    run.add_argument("type", type=_mechanism_type, metavar="TYPE",
                     help="plane, spherical, skew, slider, skew-slider (or 1-5)")
    for name, text in DIMENSION_HELP.items():
        run.add_argument(f"--{name}", metavar="X", help=text)
    run.add_argument("--from", dest="start", required=True, metavar="P1",
                     help="first bound of the input angle, degrees")
    run.add_argument("--to", dest="stop", required=True, metavar="P2",
                     help="second bound of the input angle, degrees")
    run.add_argument("--step", required=True, metavar="INC", help="increment, degrees")
    run.add_argument("--branch", required=True, choices=("1", "2"),
                     help="1: the (A+B) solution, 2: the (A-B) solution")
    run.add_argument("--dir", default=".", metavar="OUT", help="where to write the DAT files")
    run.set_defaults(handler=run_command, parser=run)
    return parser


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        return menu_program()
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.error("give a command, or none for the menu program")
    return args.handler(args, args.parser)


if __name__ == "__main__":
    sys.exit(main())
