"""The faithful program: `python3 linkage.py` writes what legacy_basic/LINKAGE.BAS writes under
PC-BASIC 2.0.8, byte for byte, and stops cleanly where the original would hang or lose data.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess
import threading
import typing

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import linkage
from support import make_golden
from support.program import PROGRAM, SCRIPT
from support.terminal import Terminal

CASES = make_golden.load_cases()


class FreeSpace(typing.NamedTuple):
    free: int


def run_port(keys: bytes, directory, program=PROGRAM) -> subprocess.CompletedProcess:
    return subprocess.run(program, input=keys, cwd=directory, capture_output=True, timeout=300)


def dat_files(directory) -> dict[str, bytes]:
    return {n: (directory / n).read_bytes() for n in sorted(os.listdir(directory))
            if n.endswith(".DAT")}


def first_difference(name: str, want: bytes, got: bytes) -> str:
    for i, (w, g) in enumerate(zip(want.split(b"\r\n"), got.split(b"\r\n")), 1):
        if w != g:
            return f"{name} line {i}: expected {w!r}, got {g!r}"
    return f"{name}: lengths differ ({len(want)} and {len(got)} bytes)"


# ---- the golden corpus ---------------------------------------------------------------------

@pytest.fixture(scope="module")
def golden_runs() -> dict:
    """The golden cases' runs made so far in this process, by case name."""
    return {}


# The golden cases --quick keeps: a short session of each mechanism and the menu's wrong keys;
# the others are marked slow. These run as programs (`python3 linkage.py < keys.txt`, by
# PROGRAM); the others by the function the program hands redirected keys to (menu_program's
# redirected_program), in this process: the same bytes, without a start of Python a case.
QUICK_CASES = {"plane-b1", "spherical-b1", "skew-b1", "slider-b1", "skew-slider-b1",
               "menu-invalid-keys"}


def run_in_process(keys: bytes, directory) -> subprocess.CompletedProcess:
    """The menu program on keys in this process, as run_port's program runs it."""
    screen, said = io.BytesIO(), io.StringIO()
    with contextlib.redirect_stderr(said):
        status = linkage.redirected_program(io.BytesIO(keys), screen, str(directory))
    return subprocess.CompletedProcess(PROGRAM, status, screen.getvalue(),
                                       said.getvalue().encode())


@pytest.fixture
def golden_run(request, golden_runs, tmp_path_factory):
    """(case, the port's run of its keys, the DAT files it wrote): one run a case, which the
    case's tests below share. (A module-scoped fixture parametrized by each test's own list of
    cases was made again for every test, its parameters told apart by their index in the list:
    92 runs of the 44 cases.)"""
    case = request.param
    if case["name"] not in golden_runs:
        folder = tmp_path_factory.mktemp(case["name"])
        start = run_port if case["name"] in QUICK_CASES else run_in_process
        result = start((make_golden.GOLDEN / case["name"] / "keys.txt").read_bytes(), folder)
        golden_runs[case["name"]] = case, result, dat_files(folder)
    return golden_runs[case["name"]]


def golden(cases):
    """Parametrize a test by golden case, sharing each case's run (golden_run)."""
    return pytest.mark.parametrize("golden_run", [
        pytest.param(c, id=c["name"], marks=() if c["name"] in QUICK_CASES else pytest.mark.slow)
        for c in cases], indirect=True)


@golden(CASES)
def test_the_port_writes_the_golden_bytes(golden_run):
    case, result, got = golden_run
    folder = make_golden.GOLDEN / case["name"]
    assert result.returncode == 0, result.stderr.decode()
    want = {p.name: p.read_bytes() for p in folder.iterdir() if p.name.endswith(".DAT")}
    assert sorted(got) == sorted(want)
    for name in want:
        assert got[name] == want[name], first_difference(f"{case['name']}/{name}", want[name],
                                                         got[name])
    screen = (folder / "SCREEN.TXT").read_bytes()
    assert result.stdout == screen, first_difference(f"{case['name']}/SCREEN.TXT", screen,
                                                     result.stdout)


@golden([c for c in CASES if c["name"] not in ("plane-change-point", "plane-double-rocker")])
def test_the_port_shows_the_golden_screen(golden_run):
    """The screen transcript, apart from the two cases whose "Overflow" messages depend on the
    unfinished arithmetic, is already PC-BASIC's byte for byte."""
    case, result, _ = golden_run
    folder = make_golden.GOLDEN / case["name"]
    screen = (folder / "SCREEN.TXT").read_bytes()
    assert result.stdout == screen, first_difference(f"{case['name']}/SCREEN.TXT", screen,
                                                     result.stdout)


# ---- the run command -------------------------------------------------------------------------

STRAIGHT = re.compile(rb"^([1-5])((?:[0-9.Ee+-]+\r)+)([12])$")


def run_options(keys: bytes) -> list[str] | None:
    """The `run` options that type the same answers as a straight golden session, if it is one."""
    match = STRAIGHT.match(keys)
    if not match:
        return None
    key, answers, branch = match[1].decode(), match[2].decode().split("\r")[:-1], match[3]
    name, (_, dims) = next((n, m) for n, m in linkage.KIND_MENU.items() if m[0] == key)
    if len(answers) != len(dims) + 3:
        return None
    options = [name]
    for option, answer in zip([f"--{d}" for d in dims] + ["--from", "--to", "--step"], answers):
        options += [option, answer]
    return options + ["--branch", branch.decode()]


RUN_CASES = [c for c in CASES
             if run_options((make_golden.GOLDEN / c["name"] / "keys.txt").read_bytes())]


@golden(RUN_CASES)
def test_run_writes_what_the_menu_writes(golden_run, tmp_path):
    case, menu, menu_files = golden_run
    keys = (make_golden.GOLDEN / case["name"] / "keys.txt").read_bytes()
    assert menu.returncode == 0
    argv = ["run"] + run_options(keys) + ["--dir", str(tmp_path)]
    if case["name"] in QUICK_CASES:            # as a program; the others by main in this process
        result = subprocess.run(PROGRAM + argv, capture_output=True, timeout=300)
    else:
        said = io.StringIO()
        with contextlib.redirect_stderr(said):
            status = linkage.main(argv)
        result = subprocess.CompletedProcess(argv, status, b"", said.getvalue().encode())
    if menu_files["ANG.DAT"] == b"\x1a":      # the menu's empty sweep (K14): run refuses
        assert result.returncode == 1 and b"has no point" in result.stderr
        assert os.listdir(tmp_path) == []
        return
    assert result.returncode == 0, result.stderr.decode()
    assert dat_files(tmp_path) == menu_files


def test_run_covers_every_mechanism():
    kinds = {run_options((make_golden.GOLDEN / c["name"] / "keys.txt").read_bytes())[0]
             for c in RUN_CASES}
    assert kinds == set(linkage.KIND_MENU)


@pytest.mark.parametrize("options, message", [
    (["plane", "--b", "2", "--c", "7", "--d", "9"], "plane needs --b --c --d --a: missing --a"),
    (["slider", "--b", "2", "--c", "7", "--e", "1", "--d", "3"], "no use for --d"),
    (["skew", "--b", "2"], "skew needs --b --c --d --a --f --ksi"),
    (["plane", "--b", "two", "--c", "7", "--d", "9", "--a", "6"], "--b: 'two' is not a number"),
    (["hexagon"], "'hexagon' is not one of plane, spherical, skew, slider, skew-slider"),
])
def test_run_rejects_meaningless_options(options, message, tmp_path):
    base = ["--from", "0", "--to", "10", "--step", "5", "--branch", "1"]
    result = subprocess.run(PROGRAM + ["run"] + options + base, capture_output=True, cwd=tmp_path)
    assert result.returncode == 2
    assert message in result.stderr.decode()
    assert "Traceback" not in result.stderr.decode()
    assert os.listdir(tmp_path) == []


def test_run_reports_an_illegal_linkage(tmp_path):
    result = subprocess.run(PROGRAM + ["run", "plane", "--a", "20", "--b", "1", "--c", "1",
                                       "--d", "1", "--from", "0", "--to", "90", "--step", "15",
                                       "--branch", "1", "--dir", str(tmp_path)],
                            capture_output=True)
    assert result.returncode == 1
    assert "Illegal linkage (impossible to assemble)" in result.stderr.decode()
    assert os.listdir(tmp_path) == []


# ---- where the original would hang or lose data (ERRATA Part 3) ------------------------------

@pytest.mark.parametrize("keys, message", [
    (b"12\r7\r9\r6\r0\r90\r0\r1", "the increment is 0"),
    (b"12\r7\r9\r6\r0\r1e30\r1\r1", "too small for single precision"),
    (b"12\r7\r9\r6\r0\r90", "the keystrokes ended before the program did"),
    (b"x", "the keystrokes ended before the program did"),
    (b"11\r1\r1\r20\r", "the keystrokes ended before the program did"),
])
def test_the_port_stops_cleanly(keys, message, tmp_path):
    """(The first started as the user starts it, `python3 linkage.py`; the others by PROGRAM,
    which test_command_line shows the same without compiling the script at each start.)"""
    result = run_port(keys, tmp_path, SCRIPT if keys == b"12\r7\r9\r6\r0\r90\r0\r1" else PROGRAM)
    assert result.returncode == 1
    assert message in result.stderr.decode()
    assert "Traceback" not in result.stderr.decode()
    assert os.listdir(tmp_path) == []


def test_a_directory_it_cannot_write():
    """/proc takes no new files, even from root (CI runs as root, so chmod would not do)."""
    result = subprocess.run(SCRIPT, input=b"12\r7\r9\r6\r0\r90\r10\r1", cwd="/proc",
                            capture_output=True, timeout=60)
    assert result.returncode == 1
    assert "cannot write the DAT files in '.'" in result.stderr.decode()
    assert "Traceback" not in result.stderr.decode()


def test_run_into_a_directory_it_cannot_write():
    result = subprocess.run(PROGRAM + ["run", "slider", "--b", "2", "--c", "7", "--e", "1",
                                       "--from", "0", "--to", "90", "--step", "10",
                                       "--branch", "1", "--dir", "/proc"], capture_output=True)
    assert result.returncode == 1
    assert "cannot write the DAT files in '/proc'" in result.stderr.decode()


def test_a_sweep_larger_than_the_disk(tmp_path, monkeypatch):
    monkeypatch.setattr(linkage.shutil, "disk_usage", lambda d: FreeSpace(10_000))
    out = io.BytesIO()
    status = linkage.redirected_program(io.BytesIO(b"12\r7\r9\r6\r0\r360\r1\r1"), out,
                                        str(tmp_path))
    assert status == 1
    assert os.listdir(tmp_path) == []


# Ctrl-C, SIGTERM and SIGHUP mid-sweep: tests/test_hardening.py.


# ---- two sessions in one process ----------------------------------------------------------------

def test_two_interleaved_blocks_each_get_their_own_soft_errors():
    """Soft errors go to the soft_errors() block they happen in: two threads taking turns (a
    barrier between each operation), each dividing by zero or overflowing in its own block,
    each gets its own messages, in its own order, and none of the other's."""
    turns = threading.Barrier(2)
    got = {}

    def work(name, operation, times):
        with linkage.soft_errors() as errors:
            for _ in range(times):
                turns.wait()
                operation()
                turns.wait()
        got[name] = list(errors)
    big = linkage.Single(linkage.MBF_MAX)
    threads = [threading.Thread(target=work, args=("divides", lambda: linkage.Single(1.0) / 0, 3)),
               threading.Thread(target=work, args=("overflows", lambda: big * big, 3))]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)
    assert got == {"divides": ["Division by zero"] * 3, "overflows": ["Overflow"] * 3}


@pytest.mark.parametrize("cases", [("plane-double-rocker", "empty-answers")])
def test_two_sessions_at_once_show_each_its_own_soft_errors(cases, tmp_path):
    """Two menu sessions whose sweeps divide by zero, run at once in two threads of one process,
    several times: each screen is its golden screen (its own soft errors, none of the other's)."""
    screens = {}

    def session(case, round_):
        folder = tmp_path / f"{case}-{round_}"
        folder.mkdir()
        out = io.BytesIO()
        keys = (make_golden.GOLDEN / case / "keys.txt").read_bytes()
        linkage.redirected_program(io.BytesIO(keys), out, str(folder))
        screens[case, round_] = out.getvalue()
    threads = [threading.Thread(target=session, args=(case, r)) for r in range(4) for case in cases]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=300)
    for (case, _), screen in screens.items():
        assert screen == (make_golden.GOLDEN / case / "SCREEN.TXT").read_bytes(), case
    assert len(screens) == 8


# ---- any keys at all -------------------------------------------------------------------------

@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(keys=st.binary(max_size=60) | st.lists(
    st.sampled_from([b"1", b"2", b"3", b"4", b"5", b"6", b"0", b"\r", b"\n", b"\x08", b"\x1b",
                     b"\t", b"\0", b"x", b" ", b"-", b".", b"e", b"&H", b"9", b"1e30", b"360\r",
                     b"-90\r", b".5\r", b"\x03", b"\x7f", b"\xff"]), max_size=40).map(b"".join))
def test_random_keys_never_give_a_traceback(keys, tmp_path_factory, monkeypatch):
    directory = tmp_path_factory.mktemp("fuzz")
    monkeypatch.setattr(linkage.shutil, "disk_usage",
                        lambda d: FreeSpace(200_000))     # sweeps over ~2000 points: refused
    out = io.BytesIO()
    status = linkage.redirected_program(io.BytesIO(keys), out, str(directory))
    assert status in (0, 1)
    assert not [n for n in os.listdir(directory) if n.endswith(".partial")]


# ---- on a real terminal ----------------------------------------------------------------------

def test_the_terminal_program_takes_single_keys_and_rings_the_bell(tmp_path):
    term = Terminal(PROGRAM, tmp_path)
    try:
        term.wait_for(b"Enter Option: _")
        assert b"\x1b[2J" in term.seen and b"\x1b[6;25H1. Plane Four Bar" in term.seen
        term.press(b"x")
        term.wait_for(b"\a")
        term.press(b"1")                                   # no Enter: INKEY$
        term.wait_for(b"Please enter the input crank length: ")
        term.press(b"\x1b[A3\x7f2\r")                     # an arrow key is ignored; Backspace edits
        term.wait_for(b"enter the connecting rod length: ")
        for answer, prompt in ((b"7", b"output crank"), (b"9", b"fixed link"),
                               (b"6", b"first bound"), (b"0", b"second bound"),
                               (b"360", b"increment"), (b"10", b"Which solution")):
            term.press(answer + b"\r")
            term.wait_for(prompt)
        term.press(b"1")                                   # no Enter: INPUT$(1)
        assert term.proc.wait(timeout=60) == 0
        assert term.modes() == term.modes_before
    finally:
        term.close()
    redirected = tmp_path / "redirected"
    redirected.mkdir()
    run_port((make_golden.GOLDEN / "plane-b1" / "keys.txt").read_bytes(), redirected)
    assert dat_files(tmp_path) == dat_files(redirected)


def test_ctrl_c_restores_the_terminal(tmp_path):
    term = Terminal(PROGRAM, tmp_path)
    try:
        term.wait_for(b"Enter Option: _")
        assert term.modes() != term.modes_before           # single keys, no echo
        term.press(b"\x03")
        assert term.proc.wait(timeout=30) == 130
        assert term.modes() == term.modes_before
    finally:
        term.close()
    assert os.listdir(tmp_path) == []


# ---- the sweep point with each repeated subexpression computed once ------------------------

coefficient = st.one_of(
    st.just(0.0),
    st.floats(-100, 100).map(lambda x: linkage.mbf_parse(f"{x:.5g}")),
    st.floats(-1e30, 1e30).map(lambda x: linkage.mbf_parse(f"{x:.3g}")),
    # singles, as every coefficient the program makes (1e-30 and 1.7e38 as doubles are not)
    st.sampled_from(["1", "-1", ".5", "2", "1e-30", "1.7e38"]).map(linkage.mbf_parse),
)


# 500 seeded examples in the default run (3,000 until 2026-11-28); LINKAGE_FUZZ=N draws N.
@settings(max_examples=int(os.environ.get("LINKAGE_FUZZ", "0")) or 500, deadline=None,
          suppress_health_check=list(HealthCheck))
@given(st.tuples(*[coefficient] * 10), st.floats(-7, 7), st.sampled_from([0.0, 1.0]),
       st.sampled_from([1, 2]), st.sampled_from([0, 1, 2]))
def test_the_fast_sweep_point_is_the_listed_one(co, phi, s, sol, derivatives):
    """sweep_point (each repeated subexpression once; the listing's own order when a soft error
    occurs) writes the lines and the messages of lines 1060-1330 evaluated as listed."""
    co = tuple(linkage.Single(c) for c in co)
    PHI, S = linkage.Single(linkage.mbf_parse(f"{phi:.6g}")), linkage.Single(s)
    with linkage.soft_errors() as listed_errors:
        listed = linkage.sweep_point_as_listed(co, PHI, sol, S, derivatives)
    with linkage.soft_errors() as fast_errors:
        fast = linkage.sweep_point(co, PHI, sol, S, derivatives)
    assert (fast, fast_errors) == (listed, listed_errors)
    if not listed_errors:                  # no fallback was needed: the fast path alone
        with linkage.soft_errors() as errors:
            assert linkage.sweep_point_fast(co, PHI, sol, S, derivatives) == listed
        assert not errors


# Found by a search of 200,000 random points: the root not written (U(2), SOL = 1) overflows
# while the written one does not; its "Overflow"s are on the original's screen all the same.
QUIET_WRITTEN_ROOT = ((0.0, 0.0, 1e-30, 2.0, 99.514, 1e-30, 42.399, 0.0, 0.5, -96.646), -6.16222)


@pytest.mark.parametrize("s", [0.0, 1.0])
@pytest.mark.parametrize("derivatives", [1, 2])
def test_the_root_not_written_still_says_overflow(s, derivatives):
    """sweep_point leaves out the root it does not write only where that root can say nothing:
    here it says "Overflow" (4 to 12 times) and the written root alone would say none."""
    co = tuple(linkage.Single(linkage.mbf_parse(repr(c))) for c in QUIET_WRITTEN_ROOT[0])
    PHI, S = linkage.Single(linkage.mbf_parse(repr(QUIET_WRITTEN_ROOT[1]))), linkage.Single(s)
    with linkage.soft_errors() as listed_errors:
        listed = linkage.sweep_point_as_listed(co, PHI, 1, S, derivatives)
    with linkage.soft_errors() as errors:
        assert linkage.sweep_point(co, PHI, 1, S, derivatives) == listed
    assert errors == listed_errors and len(errors) >= 4
    assert set(errors) == {"Overflow"}
