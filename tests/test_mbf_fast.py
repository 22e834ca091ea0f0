"""linkage.py's single-precision operations against tests/support/mbf_reference.py, the
step-by-step versions they were made fast from: X+Y and X-Y (IEEE single rounding where it is the
same), X/Y (the register's last 16 quotient bits found by one division where they are certain), the
digits of PRINT and WRITE # (the times-ten loop inline, WRITE's rounding of the register as floor(y
+ .5)), and mbf_scaled, the listing's .5*X, 2*X and 4*X, against mbf_mul. Every result is compared
with its sign bit and its soft errors, on hypothesis's operands, on a seeded sweep of random ones,
and on the edges each fast path decides by: the ends of IEEE's normal range, overflow, underflow,
cancellation, ties, divisors full of low 1-bits, remainders beside the certain margins."""

from __future__ import annotations

import math
import os
import random

import pytest
from hypothesis import HealthCheck, example, given, settings, strategies as st

import linkage as L
from support import mbf_reference as R

# The number of examples a property: MBF_FAST_SCALE times the default run's (the default keeps the
# suite quick: a hypothesis example costs about 2 ms, 50 times an operation of the seeded sweep;
# MBF_FAST_SCALE=4 is the default run before 2026-11-28, MBF_FAST_SCALE=20 the run the port's
# speed-up was checked with, 160,000 random pairs and 20,000 hypothesis examples of the operations).
SCALE = float(os.environ.get("MBF_FAST_SCALE", "1"))


def examples(n: int) -> int:
    return max(1, round(n * SCALE))

BINARY = ("mbf_add", "mbf_sub", "mbf_mul", "mbf_div")


def single(m: int, eb: int, negative: bool = False) -> float:
    """The single with 24-bit mantissa m (top bit set) and exponent byte eb (1..255)."""
    v = math.ldexp(m, eb - 152)
    return -v if negative else v


def outcome(function, *args):
    """Value, sign bit and soft errors of one operation."""
    errors = []
    v = function(*args, errors.append)
    return v, math.copysign(1.0, v), errors


def assert_same(name: str, x: float, y: float) -> None:
    assert outcome(getattr(L, name), x, y) == outcome(getattr(R, name), x, y), \
        (name, x.hex(), y.hex())


def assert_same_text(x: float) -> None:
    if x != 0:
        assert L._digits(x) == R._digits(x), x.hex()
    assert L._text(x) == R._text(x), x.hex()


mantissas = st.one_of(
    st.integers(0x800000, 0xFFFFFF),
    st.sampled_from([0x800000, 0x800001, 0xFFFFFF, 0xFFFFFE, 0xC00000, 0xAAAAAA, 0x800080,
                     0xFFFF00, 0x80FFFF, 0xBFFFFF]),
    st.integers(0, 15).map(lambda k: 0xFFFFFF ^ k),          # many low 1-bits
    st.integers(0, 255).map(lambda k: 0x800000 | k),
)
exponents = st.one_of(st.integers(1, 255), st.integers(118, 140),
                      st.sampled_from([1, 2, 3, 4, 254, 255]))
singles = st.one_of(
    st.just(0.0), st.just(-0.0),
    st.builds(single, mantissas, exponents, st.booleans()),
)


@st.composite
def near(draw):
    """X and a Y of the opposite sign (or the same) a few units or exponents away: the
    cancelling sums, and the operands 3 and 4 exponents apart where X+Y changes method."""
    m, eb, neg = draw(mantissas), draw(st.integers(1, 255)), draw(st.booleans())
    shift = draw(st.integers(0, 26))
    m2 = min(max(m + draw(st.integers(-4, 4)), 0x800000), 0xFFFFFF)
    eb2 = min(max(eb - shift, 1), 255)
    return single(m, eb, neg), single(m2, eb2, neg != draw(st.booleans()))


@settings(max_examples=examples(1000), deadline=None, suppress_health_check=list(HealthCheck))
@given(st.tuples(singles, singles) | near(), st.sampled_from(BINARY))
@example((single(0x800000, 3), single(0xFFFFFF, 2, True)), "mbf_add")   # below 2**-126
@example((single(0xFFFFFF, 255), single(0xFFFFFF, 255)), "mbf_add")     # overflow
@example((single(0xFFFFFF, 255), single(0x800000, 231)), "mbf_add")     # rounds to 2**127
@example((single(0x800000, 1), single(0x800001, 1, True)), "mbf_add")   # underflow
def test_the_operations_are_the_reference(operands, name):
    assert_same(name, *operands)


@settings(max_examples=examples(500), deadline=None, suppress_health_check=list(HealthCheck))
@given(singles)
@example(single(0xFFFFFF, 128))                     # .99999994, printed as 1
@example(999999.9375)
@example(9999999.0)
@example(single(0xFFFFFF, 1))
@example(single(0xFFFFFF, 255))
def test_the_digits_are_the_reference(x):
    assert_same_text(x)


def test_a_seeded_sweep_of_random_operands():
    rng = random.Random(24)
    for _ in range(examples(8000)):
        x = single(rng.randint(0x800000, 0xFFFFFF), rng.randint(100, 156), rng.random() < .5)
        y = single(rng.randint(0x800000, 0xFFFFFF), rng.randint(100, 156), rng.random() < .5)
        for name in BINARY:
            assert_same(name, x, y)
        assert_same_text(x)


def test_division_beside_the_certain_margins():
    """Dividends whose remainder by the 16-bit register's divisor falls right at, just inside
    and just outside the margins the quotient is certain within, for divisors full of low
    1-bits (where the register's quotient is not the exact one)."""
    rng = random.Random(7)
    divisors = [0xFFFFFF, 0xFFFFFE, 0x800001, 0xBFFFFF, 0xAAAAAB, 0xFFFF7F, 0x9FFFFF] + [
        0xFFFFFF ^ rng.getrandbits(6) for _ in range(20)] + [
        rng.randint(0x800000, 0xFFFFFF) for _ in range(20)]
    checked = 0
    for my in divisors:
        for small in (False, True):           # the dividend mantissa below the divisor's or not
            dv = (my << 7 if small else my << 8) >> 8
            h = ((dv >> 16) + 1) << 15
            for target in (h, h - 524288, dv - 524288):
                for delta in range(-3, 4):
                    # a dividend mantissa whose r = (rem << 8) mod dv lands near target
                    for _ in range(4):
                        mx = rng.randint(0x800000, my - 1) if small else rng.randint(my, 0xFFFFFF)
                        dvf = my << 7 if small else my << 8
                        rem = (mx << 15) % dvf
                        r = (rem << 8) % dv
                        step = (dv >> 8) or 1
                        mx2 = mx + ((target + delta * 32768 - r) // step) % 4096 - 2048
                        for m in (mx, mx2):
                            if 0x800000 <= m <= 0xFFFFFF:
                                for ebx, eby in ((129, 129), (200, 60), (60, 200), (255, 1)):
                                    assert_same("mbf_div", single(m, ebx), single(my, eby))
                                    checked += 1
    assert checked > 5000


@pytest.mark.parametrize("eb", [1, 2, 3, 4, 5, 126, 127, 128, 129, 253, 254, 255])
def test_sums_at_the_ends_of_the_ranges(eb):
    """Sums and differences of neighbours at each exponent near the ends of the single's range
    and of IEEE's normal one (2**-126), where the fast path hands over to the exact one."""
    rng = random.Random(eb)
    for _ in range(2000):
        m1, m2 = rng.randint(0x800000, 0xFFFFFF), rng.randint(0x800000, 0xFFFFFF)
        e2 = max(1, min(255, eb - rng.randint(-2, 5)))
        for n1, n2 in ((False, False), (False, True), (True, False), (True, True)):
            x, y = single(m1, eb, n1), single(m2, e2, n2)
            for name in BINARY:
                assert_same(name, x, y)


@settings(max_examples=examples(250), deadline=None, suppress_health_check=list(HealthCheck))
@given(singles, st.sampled_from([0.5, 2.0, 4.0]))
@example(single(0x800000, 1), 0.5)                                       # underflows to 0
@example(single(0xFFFFFF, 255), 2.0)                                     # overflows
@example(single(0x800000, 254, True), 4.0)
def test_scaling_by_a_power_of_two_is_the_product(x, k):
    assert outcome(L.mbf_scaled, k, x) == outcome(R.mbf_mul, k, x), (k, x.hex())
