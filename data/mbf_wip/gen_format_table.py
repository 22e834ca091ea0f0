"""Generate data/format_table.tsv with PC-BASIC: for a set of singles (given as
MBF bytes) the text WRITE # and PRINT # produce.  Run: python3 gen_format_table.py"""
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from basic_run import run_basic

PROG = ['10 OPEN "I",#1,"IN.DAT":OPEN "O",#2,"W.DAT":OPEN "O",#3,"P.DAT"',
        '20 IF EOF(1) THEN 90',
        '30 INPUT #1,B0%,B1%,B2%,B3%',
        '40 X=CVS(CHR$(B0%)+CHR$(B1%)+CHR$(B2%)+CHR$(B3%))',
        '50 WRITE #2,X:PRINT #3,X',
        '60 GOTO 20',
        '90 CLOSE:END']


def sample(n, seed=7):
    """MBF byte strings: edges, round decimals, integers and random values."""
    rng = random.Random(seed)
    out = [bytes(4), bytes((255, 255, 127, 255)), bytes((255, 255, 255, 255)),
           bytes((0, 0, 0, 1)), bytes((0, 0, 128, 1))]
    for _ in range(n):
        kind = rng.random()
        if kind < 0.6:
            e = rng.randint(100, 160)
        elif kind < 0.8:
            e = rng.randint(1, 255)
        else:
            e = rng.randint(120, 152)
        out.append(bytes((rng.getrandbits(8), rng.getrandbits(8), rng.getrandbits(8), e)))
    return out


def main():
    values = sample(int(sys.argv[1]) if len(sys.argv) > 1 else 4000)
    text = "".join("%d,%d,%d,%d\r\n" % tuple(b) for b in values)
    _, files = run_basic(PROG, inputs={"IN.DAT": text.encode()})
    w = files["W.DAT"].decode("latin-1").rstrip("\x1a").split("\r\n")
    p = files["P.DAT"].decode("latin-1").rstrip("\x1a").split("\r\n")
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "format_table.tsv")
    with open(path, "w") as f:
        f.write("# bytes(hex)\tWRITE # text\tPRINT # text (between quotes)\n")
        for b, wt, pt in zip(values, w, p):
            f.write('%s\t%s\t"%s"\n' % (b.hex(), wt, pt))
    print(len(values), "rows written to", path)


if __name__ == "__main__":
    main()
