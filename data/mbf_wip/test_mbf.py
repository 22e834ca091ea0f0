"""Tests of mbf.py against PC-BASIC 2.0.8 (black box).

Differential tests: hypothesis draws batches of operations on singles given
as MBF bytes; each batch is ONE BASIC program that reads the operands with
CVS, computes, and writes MKS$ bytes, WRITE # text and PRINT # text of every
result, while the screen collects the soft error messages.  The model must
agree byte for byte.  MBF_SAMPLES (default 6000, about a minute) is the
number of operations in a run; MBF_OPS restricts the operations (comma
separated names).
"""
import os
import random

import pytest
from hypothesis import HealthCheck, Phase, given, settings, strategies as st

import mbf
from basic_run import run_basic

HERE = os.path.dirname(os.path.abspath(__file__))
BATCH = 250

# name: (BASIC expression on X and Y, model function)
OPS = {
    "add": ("X+Y", mbf.add),
    "sub": ("X-Y", mbf.sub),
    "mul": ("X*Y", mbf.mul),
    "div": ("X/Y", mbf.div),
    "neg": ("-X", lambda x, y, err: mbf.neg(x)),
    "int": ("INT(X)", lambda x, y, err: mbf.int_(x)),
    "sq": ("X^2", lambda x, y, err: mbf.ipower(x, 2, err)),
    "cube": ("X^3", lambda x, y, err: mbf.ipower(x, 3, err)),
    "inv2": ("X^-2", lambda x, y, err: mbf.ipower(x, -2, err)),
    "ipow": ("X^Y", mbf.power),                       # Y whole, 0..40
    "npow": ("X^Y", mbf.power),                       # Y whole, -40..-1
    "fpow": ("ABS(X)^Y", lambda x, y, err: mbf.power(abs(x), y, err)),
    "half": ("ABS(X)^.5", lambda x, y, err: mbf.power(abs(x), 0.5, err)),
    "sqr": ("SQR(ABS(X))", lambda x, y, err: mbf.sqr(abs(x), err)),
    "exp": ("EXP(X)", lambda x, y, err: mbf.exp_(x, err)),
    "log": ("LOG(ABS(X))", lambda x, y, err: mbf.log_(abs(x), err)),
    "sin": ("SIN(X)", lambda x, y, err: mbf.sin_(x, err)),
    "cos": ("COS(X)", lambda x, y, err: mbf.cos_(x, err)),
    "tan": ("TAN(X)", lambda x, y, err: mbf.tan_(x, err)),
    "atn": ("ATN(X)", lambda x, y, err: mbf.atn(x, err)),
}


def _b(m, e, neg):
    """MBF bytes from a 24-bit mantissa (top bit set), exponent byte, sign."""
    return bytes((m & 255, (m >> 8) & 255, ((m >> 16) & 0x7F) | (0x80 if neg else 0), e))


mantissas = st.one_of(
    st.integers(0x800000, 0xFFFFFF),
    st.sampled_from([0x800000, 0x800001, 0xFFFFFF, 0xFFFFFE, 0xC00000, 0xAAAAAA]),
    st.integers(0x8000, 0xFFFF).map(lambda h: h << 8 | 0x80),        # boundary bits
    st.integers(0x8000, 0xFFFF).map(lambda h: h << 8 | 0x7F),
)
exponents = st.one_of(st.integers(100, 160), st.integers(1, 255),
                      st.sampled_from([1, 2, 3, 127, 128, 129, 250, 253, 254, 255]))
singles = st.one_of(
    st.builds(_b, mantissas, exponents, st.booleans()),
    st.sampled_from([bytes(4), _b(0x800000, 1, False), _b(0xFFFFFF, 255, False),
                     _b(0xFFFFFF, 255, True), _b(0x800000, 129, False)]),
)
# near multiples of pi/2 (TAN poles), near +-88 (EXP overflow), angles
near_pole = st.builds(lambda me, d, n: _b(me[0] + d, me[1], n),
                      st.sampled_from([(0xC90FDB, 0x81), (0x96CBE4, 0x83), (0xFB53D1, 0x83)]),
                      st.integers(-40, 40), st.booleans())
near_88 = st.builds(lambda d, n: _b(0xB00000 + d, 0x87, n), st.integers(-0x8000, 0x8000), st.booleans())
angles = st.builds(_b, st.integers(0x800000, 0xFFFFFF), st.integers(0x70, 0x88), st.booleans())


@st.composite
def operations(draw, names):
    """One operation: name and two operands; Y is sometimes X nudged, so that
    sums cancel and quotients come near 1."""
    name = draw(st.sampled_from(names))
    x = draw(singles)
    if x[3] and draw(st.booleans()) and name in ("add", "sub", "div"):
        m = (x[0] | x[1] << 8 | x[2] << 16 | 0x800000) & 0xFFFFFF | 0x800000
        m = min(0xFFFFFF, max(0x800000, m + draw(st.integers(-300, 300))))
        y = _b(m, max(1, min(255, x[3] + draw(st.integers(-2, 2)))),
               draw(st.booleans()))
    else:
        y = draw(singles)
    if name == "ipow":                                  # whole exponents
        y = mbf.to_bytes(float(draw(st.integers(0, 40))))
    if name == "npow":
        y = mbf.to_bytes(float(draw(st.integers(-40, -1))))
    if name == "fpow":
        y = draw(st.one_of(singles, st.sampled_from([mbf.to_bytes(v) for v in (.5, -.5, 1.5, 1 / 3, 2.5, -2.5)])))
    if name in ("sin", "cos", "tan") and draw(st.booleans()):
        x = draw(st.one_of(angles, near_pole))
    if name == "exp" and draw(st.booleans()):
        x = draw(st.one_of(angles, near_88))
    if name == "log" and not x[3]:                      # LOG(0) is a hard error
        x = _b(0x800000, 129, False)
    return name, x, y


def basic_program(names):
    """The BASIC program for a batch: operands from IN.DAT, results to
    B.DAT (MKS$ bytes, then the WRITE # text) and P.DAT (PRINT #).  (Three
    files is PC-BASIC's default limit.)"""
    lines = ['10 OPEN "I",#1,"IN.DAT":OPEN "O",#2,"B.DAT":OPEN "O",#3,"P.DAT"',
             '20 IF EOF(1) THEN 90',
             '30 INPUT #1,O%,B0%,B1%,B2%,B3%,C0%,C1%,C2%,C3%',
             '40 X=CVS(CHR$(B0%)+CHR$(B1%)+CHR$(B2%)+CHR$(B3%)):Y=CVS(CHR$(C0%)+CHR$(C1%)+CHR$(C2%)+CHR$(C3%))',
             '50 ON O% GOSUB ' + ",".join(str(1000 + 10 * i) for i in range(len(names))),
             '60 R$=MKS$(Z):WRITE #2,ASC(R$),ASC(MID$(R$,2)),ASC(MID$(R$,3)),ASC(MID$(R$,4)),Z',
             '70 PRINT #3,Z',
             '80 GOTO 20',
             '90 CLOSE:END']
    for i, name in enumerate(names):
        lines.append("%d Z=%s:RETURN" % (1000 + 10 * i, OPS[name][0]))
    return lines


def run_batch(batch):
    """Run a batch in PC-BASIC; return (per-op results, screen messages)."""
    names = sorted(set(n for n, _, _ in batch))
    text = "".join("%d,%s,%s\r\n" % (names.index(n) + 1, ",".join(map(str, x)), ",".join(map(str, y)))
                   for n, x, y in batch)
    out, files = run_basic(basic_program(names), inputs={"IN.DAT": text.encode()})
    assert "P.DAT" in files, "PC-BASIC stopped: " + out[-300:]

    def lines(name):
        return files[name].decode("latin-1").rstrip("\x1a").split("\r\n")[:len(batch)]
    got = []
    for line, p in zip(lines("B.DAT"), lines("P.DAT")):
        fields = line.split(",", 4)
        got.append((bytes(map(int, fields[:4])), fields[4], p))
    messages = [l.strip() for l in out.splitlines() if l.strip()]
    return got, messages


def model_batch(batch):
    """The same batch through the model."""
    messages = []
    got = []
    for name, x, y in batch:
        z = OPS[name][1](mbf.from_bytes(x), mbf.from_bytes(y), messages.append)
        got.append((mbf.to_bytes(z), mbf.fmt_write(z), mbf.fmt_print(z)))
    return got, messages


def _zero_bytes(r):
    """A result whose exponent byte is 0 is zero; PC-BASIC may leave the
    sign and mantissa bytes of an underflowed result behind (NOTES.md fact
    11), which only MKS$ shows, so all such results compare as 00 00 00 00."""
    return (bytes(4),) + r[1:] if r[0][3] == 0 else r


def compare(batch):
    """List of differences between PC-BASIC and the model for a batch."""
    real, real_msgs = run_batch(batch)
    model, model_msgs = model_batch(batch)
    diffs = [(op[0], op[1].hex(), op[2].hex(), r, m)
             for op, r, m in zip(batch, real, model) if _zero_bytes(r) != _zero_bytes(m)]
    if real_msgs != model_msgs:
        diffs.append(("messages", real_msgs[:5], model_msgs[:5]))
    return diffs


def _samples():
    return int(os.environ.get("MBF_SAMPLES", "6000"))


def _names(default):
    chosen = os.environ.get("MBF_OPS")
    return sorted(chosen.split(",")) if chosen else sorted(default)


def _differential(names):
    @settings(max_examples=max(1, _samples() // BATCH), deadline=None, derandomize=True,
              phases=(Phase.generate,), suppress_health_check=list(HealthCheck))
    @given(st.lists(operations(names), min_size=BATCH, max_size=BATCH))
    def check(batch):
        diffs = compare(batch)
        assert not diffs, "%d differences, first: %r" % (len(diffs), diffs[:3])
    check()


def test_operations_match_pcbasic():
    """Every operation and function: MKS$ bytes, WRITE # and PRINT # text
    of the result and the order of the soft error messages."""
    _differential(_names(OPS))


# ---------------------------------------------------------------------------
# text forms against the table PC-BASIC produced (gen_format_table.py)

def _table():
    with open(os.path.join(HERE, "data", "format_table.tsv")) as f:
        rows = [l.rstrip("\n").split("\t") for l in f if not l.startswith("#")]
    return [(bytes.fromhex(h), w, p[1:-1]) for h, w, p in rows]


# rows the output model gets wrong (|x| >= 1E9 near a rounding boundary;
# the division-by-ten step is not exactly reproduced, see NOTES.md)
KNOWN_TEXT_MISSES = {"01d8ccf1", "2ba882c6", "940f75b6", "f6c13bae", "0c4506ab",
                     "2e4357a1", "f0b671b1", "4f190aaa", "44a92caf"}


def test_write_and_print_text_match_table():
    misses = []
    for b, w, p in _table():
        x = mbf.from_bytes(b)
        if (mbf.fmt_write(x), mbf.fmt_print(x)) != (w, p):
            misses.append(b.hex())
    assert set(misses) <= KNOWN_TEXT_MISSES, sorted(set(misses) - KNOWN_TEXT_MISSES)[:10]
    assert len(_table()) > 4000


def test_write_text_matches_rounding_edge_table():
    """18,000 values chosen within 1/50 ulp of a rounding boundary of the
    decimal scaling (data/format_edges.tsv, made by PC-BASIC in exp/e27,
    e29, e33, e36, e37)."""
    with open(os.path.join(HERE, "data", "format_edges.tsv")) as f:
        rows = [l.rstrip("\n").split("\t") for l in f if not l.startswith("#")]
    misses = {h for h, w in rows if mbf.fmt_write(mbf.from_bytes(bytes.fromhex(h))) != w}
    assert misses <= KNOWN_TEXT_MISSES, sorted(misses - KNOWN_TEXT_MISSES)[:10]
    assert len(rows) > 17000


def test_bytes_round_trip():
    rng = random.Random(1)
    for _ in range(2000):
        b = bytes((rng.getrandbits(8), rng.getrandbits(8), rng.getrandbits(8), rng.randint(1, 255)))
        assert mbf.to_bytes(mbf.from_bytes(b)) == b


def test_literals_and_input_match_pcbasic():
    """Program literals and INPUT text: MKS$ bytes as PC-BASIC stores them."""
    literals = [".5", "180!", "2!", "2", "4", "3.141592654#", ".1", "1E-20", "123456789",
                "1.5E+3", "-7.25", "0.001", "65536", "1E38", "2.5E-39"]
    typed = ["6", "-0.5", "1e3", "  12  ", ".333", "1E+07", "9999999", "0"]
    lines = ['10 OPEN "O",#1,"L.DAT"']
    for i, t in enumerate(literals):
        lines.append('%d A=%s:R$=MKS$(A):WRITE #1,ASC(R$),ASC(MID$(R$,2)),ASC(MID$(R$,3)),ASC(MID$(R$,4))'
                     % (100 + i, t))
    for i, t in enumerate(typed):
        lines.append('%d INPUT "",A:R$=MKS$(A):WRITE #1,ASC(R$),ASC(MID$(R$,2)),ASC(MID$(R$,3)),ASC(MID$(R$,4))'
                     % (500 + i))
    lines.append("900 CLOSE:END")
    _, files = run_basic(lines, keys="".join(t + "\r" for t in typed))
    got = [bytes(map(int, l.split(","))) for l in
           files["L.DAT"].decode("latin-1").rstrip("\x1a").split("\r\n") if l]
    assert got == [mbf.to_bytes(mbf.parse(t)) for t in literals + typed]


def test_for_loops_match_pcbasic():
    """Iteration counts and final values of single FOR loops."""
    loops = [("0", "1", ".1"), ("1", "0", "-.25"), ("1", "0", "1"), ("0", "6.283185", ".0174533"),
             ("-1", "1", "1/3"), ("0", "360", "7.5"), ("5", "5", "1"), ("0", "1", "0")]
    lines = ['10 OPEN "O",#1,"L.DAT"']
    for i, (a, b, s) in enumerate(loops):
        n = 100 + 10 * i
        lines.append('%d N=0:S=%s:FOR P=%s TO %s STEP S:N=N+1:IF N>1000 THEN %d' % (n, s, a, b, n + 2))
        lines.append('%d NEXT' % (n + 1))
        lines.append('%d WRITE #1,N,P' % (n + 2))
    lines.append("900 CLOSE:END")
    _, files = run_basic(lines)
    got = files["L.DAT"].decode("latin-1").rstrip("\x1a").split("\r\n")[:len(loops)]
    want = []
    for a, b, s in loops:
        a, b = mbf.parse(a), mbf.parse(b)
        s = mbf.div(1.0, 3.0) if s == "1/3" else mbf.parse(s)
        n = sum(1 for _ in mbf.for_values(a, b, s))
        want.append("%d,%s" % (n, mbf.fmt_write(mbf.for_final(a, b, s))))
    assert got == want
