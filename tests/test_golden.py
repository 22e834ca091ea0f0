"""The golden corpus is what PC-BASIC writes today: re-run it and compare bytes.

A sample of the cases runs in every test run; LINKAGE_GOLDEN=all runs every case (the 3601-point
sweep alone takes about two minutes).
"""

from __future__ import annotations

import os
import subprocess

import pytest

from support import basic_runner
from support import make_golden

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

CASES = make_golden.load_cases()
SAMPLE = {
    "plane-spike-180", "plane-change-point", "plane-reversed-range",
    "spherical-illegal-then-spherical", "skew-imaginary-coupler",
    "slider-rod-shorter-than-offset", "skew-slider-b2", "illegal-slider-then-plane",
    "menu-invalid-keys", "branch-invalid-keys", "redo-from-start", "exit",
}
CHOSEN = CASES if os.environ.get("LINKAGE_GOLDEN") == "all" else [
    c for c in CASES if c["name"] in SAMPLE]


def first_difference(name: str, want: bytes, got: bytes) -> str:
    want_lines, got_lines = want.split(b"\r\n"), got.split(b"\r\n")
    for i, (w, g) in enumerate(zip(want_lines, got_lines), 1):
        if w != g:
            return f"{name} line {i}: expected {w!r}, got {g!r}"
    return f"{name}: {len(want_lines)} lines expected, got {len(got_lines)}"


@pytest.mark.parametrize("case", CHOSEN, ids=[c["name"] for c in CHOSEN])
def test_pcbasic_still_writes_the_golden_bytes(case):
    folder = make_golden.GOLDEN / case["name"]
    want = {p.name: p.read_bytes() for p in folder.iterdir() if p.name != "keys.txt"}
    run = basic_runner.run_listing((folder / "keys.txt").read_bytes())
    got = dict(run.files, **{"SCREEN.TXT": run.screen})
    assert sorted(got) == sorted(want), f"{case['name']}: files written differ"
    for name in sorted(want):
        assert got[name] == want[name], first_difference(f"{case['name']}/{name}", want[name],
                                                         got[name])


def test_the_corpus_is_complete_and_consistent():
    assert len(CASES) >= 40
    assert SAMPLE <= {c["name"] for c in CASES}
    folders = {p.name for p in make_golden.GOLDEN.iterdir() if p.is_dir()}
    assert folders == {c["name"] for c in CASES}
    readme = (make_golden.GOLDEN / "README.md").read_text()
    for case in CASES:
        folder = make_golden.GOLDEN / case["name"]
        assert (folder / "keys.txt").read_bytes() == make_golden.case_keys(case), case["name"]
        assert (folder / "SCREEN.TXT").exists(), case["name"]
        assert f"| `{case['name']}` |" in readme, case["name"]
        for dat in basic_runner.DAT_FILES:
            if (folder / dat).exists():
                data = (folder / dat).read_bytes()
                assert data.endswith(b"\x1a") and b"\n" not in data.replace(b"\r\n", b""), dat


def test_the_corpus_was_made_by_the_pcbasic_in_use():
    recorded = (make_golden.GOLDEN / "PCBASIC_VERSION").read_text().strip()
    assert recorded == make_golden.REQUIRED_VERSION == basic_runner.pcbasic_version()


def test_the_corpus_covers_what_the_issue_asks():
    """Spot checks that the named behaviours really are in the corpus, read from its bytes."""
    def screen(name):
        return (make_golden.GOLDEN / name / "SCREEN.TXT").read_bytes()

    def rows(name, dat):
        return basic_runner.read_dat((make_golden.GOLDEN / name / dat).read_bytes())

    assert len(rows("plane-3601-points", "ANG.DAT")) >= 3600
    assert b"Division by zero" in screen("plane-change-point")
    assert b"Overflow" in screen("plane-change-point")
    assert (0.0, 0.0) in [(a, v) for (_, a), (_, v) in zip(rows("plane-double-rocker", "ANG.DAT"),
                                                           rows("plane-double-rocker", "VEL.DAT"))]
    assert {3.0, -3.0} & {v for _, v in rows("plane-dead-centre-clip", "VEL.DAT")}
    assert {3.0, -3.0} & {v for _, v in rows("plane-dead-centre-clip", "ACC.DAT")}
    assert b"Illegal linkage" in screen("illegal-then-plane")
    assert rows("plane-reversed-range", "ANG.DAT") == []
    assert not any(n.endswith(".DAT") for n in os.listdir(make_golden.GOLDEN / "exit"))
    assert [round(v, 4) for _, v in rows("plane-spike-180", "VEL.DAT")][1:4] == [.2545, .545, .2448]


# A program that leaves behind all it can: variables, an array, a function, a file open, the
# screen's width and colours, the key bar, memory poked, the random numbers' seed, keys not read.
LEAVER = (b'10 A=42:B$="LEFT":DIM C(20):C(5)=7:DEF FNQ(X)=2*X\r\n'
          b'20 OPEN "O",#1,"LEFT.DAT":PRINT #1,"open"\r\n'
          b'30 KEY ON:WIDTH 40:COLOR 2,1:LOCATE 10,10:DEF SEG=&H1000:POKE 5,99\r\n'
          b'40 RANDOMIZE 77:R=RND(1):INPUT X:STOP\r\n')
# ... and one that prints what it finds (FNQ is "Undefined user function", error 18, when new).
FINDER = (b'10 ON ERROR GOTO 100:DEF SEG=&H1000\r\n'
          b'20 PRINT A;B$;C(5);X;FRE(0);RND(1);PEEK(5);CSRLIN;POS(0);INKEY$\r\n'
          b'30 OPEN "O",#1,"F.DAT":PRINT #1,"f":CLOSE:PRINT FNQ(1):END\r\n'
          b'100 PRINT "error";ERR;"in";ERL:RESUME NEXT\r\n')


def test_a_run_leaves_nothing_to_the_next():
    """The runs share a PC-BASIC server process (support/basic_runner.py). The finder run after
    the leaver, in the same process, prints and writes what it does in a process of its own,
    started as `pcbasic` is; the leaver's file stays in its own folder."""
    left = basic_runner.run_program(LEAVER, b"5\rLEFTOVER KEYS")
    assert b"Break in 40" in left.screen and left.files == {"LEFT.DAT": b"open\r\n\x1a"}
    found = basic_runner.run_program(FINDER)
    if found.server != left.server:              # the leaver's server had made its last run
        left = basic_runner.run_program(LEAVER, b"5\rLEFTOVER KEYS")
        found = basic_runner.run_program(FINDER)
    assert found.server == left.server != 0
    assert found == basic_runner.run_program(FINDER, alone=True)
    assert b"error 18 in 30" in found.screen and list(found.files) == ["F.DAT"]


def test_a_run_that_hangs_is_stopped_and_the_next_one_runs():
    with pytest.raises(subprocess.TimeoutExpired):
        basic_runner.run_program(b"10 GOTO 10\r\n", timeout=0.3)
    assert basic_runner.run_program(b'10 PRINT "next"\r\n').screen == b"next\r\n"
