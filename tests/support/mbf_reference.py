"""The reference for linkage.py's fast single-precision paths: GW-BASIC's addition,
multiplication, division and number-to-text as linkage.py computed them before they were made
fast (commit 2df59f2), each operation spelled out step by step, as data/PCBASIC_NOTES.md
describes it and tests/test_mbf.py held it to PC-BASIC. tests/test_mbf_fast.py holds the
program's operations to these; the program never imports this file."""

import math

MBF_MAX = math.ldexp(0xFFFFFF, 127 - 24)      # 1.701412E+38, the overflow value
OVERFLOW = "Overflow"
DIV_ZERO = "Division by zero"
_T24 = 16777216.0                        # 2**24
_TOP = 2.0 ** 127                        # the first magnitude beyond the single range
_BOTTOM = 2.0 ** -128                    # the smallest magnitude in it


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


# --------------------------------------------------------------------------
# the four operations

def mbf_add(x, y, err=_ignore):
    """X+Y as PC-BASIC computes it (observed; data/PCBASIC_NOTES.md).
    Equal signs: the exact sum rounded to nearest, ties to even.
    Opposite signs: the smaller operand is aligned keeping one guard byte
    (bits below it are dropped; bit 5 of the guard is set when any of its
    bits 0-4 is), subtracted, normalised and rounded by GW's $ROUNS.  Two
    quirks: a one-bit normalisation whose guard reads as a tie (100xxxxx,
    not exactly 80h) on an even mantissa drops the guard first; and a small
    operand of exactly half an ulp 24 places down leaves X unchanged."""
    if x == 0:
        return y if y != 0 else 0.0          # a sum of zeros is +0, whatever their signs
    if y == 0:
        return x
    if (x > 0) is (y > 0):
        # The double sum is exact while the exponents are at most 28 apart; further apart,
        # it rounds to within an eighth of X's last place, and the single sum is X anyway.
        f, e = math.frexp(x + y)
        v = math.ldexp(round(f * _T24), e - 24)
        if -_TOP < v < _TOP:
            return v
        err(OVERFLOW)
        return math.copysign(MBF_MAX, x)
    if -3 <= math.frexp(x)[1] - math.frexp(y)[1] <= 3:
        # Exponents at most 3 apart: no bit reaches the guard byte's low 5, so the guard
        # arithmetic below rounds the exact difference half to even.
        d = x + y
        if d == 0:
            return 0.0
        f, e = math.frexp(d)
        v = math.ldexp(round(f * _T24), e - 24)
        return v if not -_BOTTOM < v < _BOTTOM else 0.0
    nx, mx, ex = _split(x)
    ny, my, ey = _split(y)
    if ex < ey or (ex == ey and mx < my):
        x, nx, mx, ex, ny, my, ey = y, ny, my, ey, nx, mx, ex
    c = ex - ey
    if c >= 25 or (c == 24 and my == 1 << 23):
        return x
    v = (my << 8) >> c
    d = (mx << 8) - ((v >> 8) << 8 | _sticky(v & 0xFF))
    if d == 0:
        return 0.0
    m, g = d >> 8, d & 0xFF
    if m < 1 << 23:
        if g & 0xE0 == 0x80 and g != 0x80 and not m & 1:
            g = 0
        while m < 1 << 23:
            m = m << 1 | g >> 7
            g = _sticky((g << 1) & 0xFF)
            ex -= 1
    if ex <= 0:
        return 0.0
    return _make(nx, _round3(m, g), ex, err)


def _sticky(g):
    """Guard byte with its sticky bit 5 set when any of bits 0-4 is set."""
    return g | 0x20 if g & 0x1F else g


def mbf_sub(x, y, err=_ignore):
    """X-Y: X when Y is zero (+0 for a zero X), else X plus the negated Y."""
    if y == 0:
        return x if x != 0 else 0.0
    return mbf_add(x, -y, err)


def mbf_mul(x, y, err=_ignore):
    """X*Y as GW $FMULS: the 48-bit product truncated to 24+3 bits, then
    rounded half to even on those 3 bits."""
    p = x * y                     # exact: 24x24 bits fit a double
    if p == 0:
        return 0.0
    f, e = math.frexp(p)
    t = int(abs(f) * 134217728.0)                  # 27 bits, truncated
    m, g = t >> 3, t & 7
    if g > 4 or (g == 4 and m & 1):
        m += 1
    v = math.ldexp(m, e - 24)
    if v >= _TOP:
        err(OVERFLOW)
        return math.copysign(MBF_MAX, p)
    if v < _BOTTOM:
        return 0.0
    return v if p > 0 else -v


def mbf_div(x, y, err=_ignore):
    """X/Y as PC-BASIC computes it (observed; data/PCBASIC_NOTES.md): restoring long
    division of the mantissas held with a guard byte (m << 8), where the
    divisor register is shifted right after each of the 24 quotient bits so
    that its low bits fall off (the quotient comes out a little too large
    for divisors with many low 1-bits); it starts one place lower when the
    dividend mantissa is the smaller.  Rounding compares the remainder with
    H = (next divisor) + 1: above rounds up, equal rounds to even.  Division
    by zero reports the error and gives +-MBF_MAX with the sign bit of X (so -0/0 is
    -MBF_MAX; the sign of a zero Y does not matter)."""
    if y == 0:
        err(DIV_ZERO)
        return math.copysign(MBF_MAX, x)
    if x == 0:
        return 0.0
    nx, mx, ex = _split(x)
    ny, my, ey = _split(y)
    rem = mx << 8
    dv = my << 8
    eb = ex - ey + 129
    if mx < my:
        dv >>= 1
        eb -= 1
    # The first 8 quotient bits in one division: dv >> i is exact for i < 8 (dv has at least
    # 7 low zero bits), so they are the exact quotient's; the other 16 follow the register.
    q, rem = divmod(rem << 7, dv)
    rem >>= 7
    dv >>= 8
    for _ in range(16):
        q <<= 1
        if rem >= dv:
            rem -= dv
            q |= 1
        dv >>= 1
    if rem > dv + 1 or (rem == dv + 1 and q & 1):
        q += 1
    return _make(nx != ny, q, eb, err)


# --------------------------------------------------------------------------
# decimal scaling: the register PC-BASIC multiplies and divides by ten in
#
# Numbers are turned into text and text into numbers by scaling a mantissa register by ten
# (observed; data/PCBASIC_NOTES.md, "The decimal register"). The register holds a single's 24
# bits and a guard byte (32 bits), or a double's 56 bits and a guard byte (64 bits); a value
# is (m, e) with m * 2**e, m normalised to the register's width.

def _times_ten(m, e, width):
    """x*4 + x: the aligned x loses its two low bits, which survive as a sticky low bit; a
    carry out of the register shifts the sum right, dropping its low bit."""
    s = m + (m >> 2)
    e += 3
    if s >> width:
        s >>= 1
        e += 1
    return s | (m & 3 != 0), e


def _tenth(m, e, width):
    """x/10: the quotient of m*8 by ten, one unit low when that is exact, cut to the
    register's width; when m is below ten's mantissa (0xA0...) the quotient has one bit
    fewer and the register is filled with a zero bit."""
    q = ((m << 3) - 1) // 10
    sh = q.bit_length() - width
    return (q >> sh if sh > 0 else q << -sh), e - 3 + sh


def _digits(x):
    """Seven decimal digits and the decimal exponent k of |x| (x != 0), so
    that |x| ~ 0.ddddddd * 10**k, as PC-BASIC makes them (observed; see
    data/PCBASIC_NOTES.md, "Numbers to text").  The mantissa goes into the
    32-bit decimal register; a value above 9999999 is divided by ten while it
    stays above 9999999, any other value is multiplied by ten while it is
    below 999999.9375 (so a single just below a power of ten, such as
    .99999994, can print as that power: "1").  The register is rounded half
    up to 24 bits and the single is rounded like WRITE does it: mbf_add .5 in
    single if not whole, truncate."""
    _, m, eb = _split(abs(x))
    m <<= 8
    e = eb - 160                       # |x| = m * 2**e; ldexp(m, e) is exact (m < 2**32)
    k = 0
    if math.ldexp(m, e) > 9999999:
        while math.ldexp(m, e) > 9999999:
            m, e = _tenth(m, e, 32)
            k += 1
    else:
        while math.ldexp(m, e) < 999999.9375:
            m, e = _times_ten(m, e, 32)
            k -= 1
    q = (m >> 8) + ((m & 0xFF) >= 0x80)
    y = math.ldexp(q, e + 8)
    if y != math.floor(y):
        y = mbf_add(y, 0.5)
    s = str(int(y))
    return s, len(s) + k


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
