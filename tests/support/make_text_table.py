"""Make data/mbf/text_table.tsv with PC-BASIC: singles (as MBF bytes) and the text WRITE # and
PRINT # give them. Never edit the table by hand; run, from the repository's root,
`PYTHONPATH=tests python3 -m support.make_text_table`.

The values: the edges (zero, the extremes), random singles over the whole range, and the
hard places of the decimal conversion: the neighbours of every power of ten and of numbers
whose seventh digit is followed by exactly 5.
"""

from __future__ import annotations

import random

import linkage
from support import basic_runner

TABLE = basic_runner.ROOT / "data" / "mbf" / "text_table.tsv"
PROGRAM = b"\r\n".join([
    b'10 OPEN "R",#1,"IN.DAT",4:FIELD #1,4 AS X$:OPEN "O",#2,"W.DAT":OPEN "O",#3,"P.DAT"',
    b'20 FOR I=1 TO LOF(1)/4:GET #1,I:X=CVS(X$):WRITE #2,X:PRINT #3,X:NEXT',
    b'30 CLOSE:END',
]) + b"\r\n"


def neighbours(value: float, reach: int) -> list[bytes]:
    """The singles within `reach` units of the last place of the single nearest `value`."""
    if not 3e-39 < value < 1.7e38:
        return []
    b = linkage.mbf_to_bytes(linkage.mbf_parse(repr(value)))
    m = b[0] | b[1] << 8 | (b[2] | 0x80) << 16
    return [bytes((n & 255, (n >> 8) & 255, (n >> 16) & 0x7F, b[3]))
            for n in range(m - reach, m + reach + 1) if 0x800000 <= n <= 0xFFFFFF]


def sample(seed: int = 7) -> list[bytes]:
    rng = random.Random(seed)
    values = [bytes(4), bytes((255, 255, 127, 255)), bytes((255, 255, 255, 255)),
              bytes((0, 0, 0, 1)), bytes((0, 0, 128, 1))]
    for _ in range(4000):
        e = rng.choice([rng.randint(100, 160), rng.randint(1, 255), rng.randint(120, 152)])
        values.append(bytes((rng.getrandbits(8), rng.getrandbits(8), rng.getrandbits(8), e)))
    for n in range(-38, 39):
        values += neighbours(10.0 ** n, 3)
    for _ in range(1500):
        digits = rng.randint(1000000, 9999999) + 0.5
        values += neighbours(digits * 10.0 ** rng.randint(-44, 31), 1)
    return list(dict.fromkeys(values))


def main() -> None:
    values = sample()
    run = basic_runner.run_program(PROGRAM, inputs={"IN.DAT": b"".join(values)}, alone=True)
    write = run.files["W.DAT"].decode("ascii").rstrip("\x1a").split("\r\n")
    printed = run.files["P.DAT"].decode("ascii").rstrip("\x1a").split("\r\n")
    TABLE.parent.mkdir(parents=True, exist_ok=True)
    with open(TABLE, "w", encoding="ascii", newline="\n") as f:
        f.write(f"# made by tests/support/make_text_table.py with "
                f"{basic_runner.pcbasic_version()}\n")
        f.write("# MBF bytes (hex)\tWRITE # text\tPRINT # text (between quotes)\n")
        for b, w, p in zip(values, write, printed):
            f.write(f'{b.hex()}\t{w}\t"{p}"\n')
    print(len(values), "rows written to", TABLE)


if __name__ == "__main__":
    main()
