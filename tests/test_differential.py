"""Sessions drawn at random run in PC-BASIC and in the port: the same bytes come out.

Hypothesis draws whole sessions: any of the five mechanisms, dimensions that assemble or not
(and skew couplers that are imaginary), answers PC-BASIC must refuse ("?Redo from start"), stray
menu and branch keys, bounds, steps and branches. Each session is run by PC-BASIC in a run of
its own (two at a time) and by the port in-process; files and screen must be identical.
LINKAGE_DIFFERENTIAL=N draws N sessions per example instead of 8.
"""

from __future__ import annotations

import concurrent.futures
import io
import math
import os
import tempfile

import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings, strategies as st

from support import basic_runner
import linkage

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

SESSIONS = int(os.environ.get("LINKAGE_DIFFERENTIAL", "8"))
DIMENSIONS = {1: "bcda", 2: "bcda", 3: "bcdafk", 4: "bce", 5: "bcafk"}


def _text(x: float) -> str:
    return repr(round(x, 3)).removesuffix(".0")


lengths = st.floats(0.1, 12).map(_text)
arcs = st.floats(1, 179).map(_text)                   # degrees, spherical linkage
skew_angles = st.floats(0, 75).map(_text)
junk = st.sampled_from(["abc", "1,2", "5x", "--1", "\"3\""])
stray_menu_keys = st.lists(st.sampled_from(["0", "7", "8", "9", "x", " ", "\r"]), max_size=3)
stray_branch_keys = st.lists(st.sampled_from(["0", "3", "x", " ", "\r"]), max_size=3)


def assembles(kind: int, d: dict[str, float]) -> float:
    """Line 480 in double precision, for a fresh session: the smallest margin by which the
    linkage passes (positive) or fails (negative) the assembly check."""
    if kind == 4:
        return math.inf
    a, b, c = d["a"], d["b"], d["c"]
    dd = d.get("d", 0.0)
    if kind == 2:
        a, b, c, dd = (math.fmod(math.radians(x), math.pi) for x in (a, b, c, dd))
    if kind in (3, 5):
        a = math.hypot(a, d["f"] * math.tan(math.radians(d["k"])))
    return min(b + c + dd - a, a + c + dd - b, a + b + dd - c, a + b + c - dd)


@st.composite
def sessions(draw) -> bytes:
    kind = draw(st.integers(1, 5))
    answers = {}
    for name in DIMENSIONS[kind]:
        strategy = {"k": skew_angles, "f": st.floats(0, 4).map(_text)}.get(
            name, arcs if kind == 2 else lengths)
        answers[name] = draw(strategy)
    margin = assembles(kind, {k: float(v) for k, v in answers.items()})
    assume(abs(margin) > 1e-3)                       # no single-precision borderline cases
    keys = "".join(draw(stray_menu_keys)) + str(kind)
    for name in DIMENSIONS[kind]:
        if draw(st.integers(0, 9)) == 0:
            keys += draw(junk) + "\r"
        keys += answers[name] + "\r"
    if margin < 0:                                   # illegal: any key, then a slider-crank
        keys += " 4" + "".join(draw(lengths) + "\r" for _ in "bce")
    start = draw(st.integers(-400, 400)) + draw(st.sampled_from([0, 0.5, 0.25]))
    step = draw(st.sampled_from([1, 5, 7.5, 10, 30, 45, 90])) * draw(st.sampled_from([1, -1]))
    points = draw(st.integers(0, 8))
    stop = start + step * (points - 0.5)
    keys += f"{_text(start)}\r{_text(stop)}\r{_text(step)}\r"
    keys += "".join(draw(stray_branch_keys)) + str(draw(st.integers(1, 2)))
    return keys.encode("ascii")


def run_port(keys: bytes) -> dict[str, bytes]:
    with tempfile.TemporaryDirectory() as directory:
        screen = io.BytesIO()
        status = linkage.redirected_program(io.BytesIO(keys), screen, directory)
        files = {n: open(os.path.join(directory, n), "rb").read() for n in os.listdir(directory)}
    return dict(files, SCREEN=screen.getvalue(), status=bytes([status]))


def run_pcbasic(keys: bytes) -> dict[str, bytes]:
    run = basic_runner.run_listing(keys, timeout=120)
    return dict(run.files, SCREEN=run.screen, status=bytes([0]))


# No shrinking: every PC-BASIC run costs half a second, and the message names the keys anyway.
@settings(max_examples=3, deadline=None, suppress_health_check=list(HealthCheck),
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(st.lists(sessions(), min_size=SESSIONS, max_size=SESSIONS))
def test_random_sessions_write_the_same_bytes(batch):
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        expected = list(pool.map(run_pcbasic, batch))
    for keys, want in zip(batch, expected):
        got = run_port(keys)
        assert got == want, f"keys {keys!r}:\n" + "\n".join(
            f"  {name}: PC-BASIC {want.get(name)!r}\n  {'':{len(name)}}  port     {got.get(name)!r}"
            for name in sorted(set(want) | set(got)) if want.get(name) != got.get(name))
