"""The mechanism in the terminal: the still frame of each Figs. 1-2 scene against its
snapshot (Unicode braille and ASCII), what the frame says, the frames printed with --frames N,
and, in a pseudo-terminal, the animation: it runs, q stops it, Ctrl-C and Ctrl-Z leave the
terminal as it was."""

from __future__ import annotations

import difflib
import os
import re
import subprocess

import pytest

from support import basic_runner
import linkage
from support import make_scene_snapshots
from support.program import PROGRAM
from support.terminal import Terminal

ROOT = basic_runner.ROOT
FIGURES_1_2 = sorted((ROOT / "data" / "scenes").glob("fig[12]?-*.toml"))
CAPTION = re.compile(rb"\xcf\x86 = ([-0-9.]+)\xc2\xb0")          # "φ = 35°" in UTF-8


@pytest.mark.parametrize("encoding", ["utf-8", "ascii"])
@pytest.mark.parametrize("scene", FIGURES_1_2, ids=lambda p: p.stem)
def test_the_still_frame_matches_its_snapshot(scene, encoding):
    text = make_scene_snapshots.text_plot(scene, encoding)
    lines = text.splitlines()
    assert len(lines) == 24 and max(len(line) for line in lines) <= 80
    if encoding == "ascii":
        assert text.isascii() and "phi = 30 deg" in lines[-1]
    else:
        assert any("\u2801" <= ch <= "\u28ff" for ch in text)       # drawn in braille
        assert lines[-1].startswith("φ = 30°")
    snapshot = make_scene_snapshots.snapshot_path(scene, encoding)
    want = snapshot.read_text(encoding=encoding)
    assert text == want, (f"{snapshot.name} differs (if the change is intended: python3 "
                          "tests/support/make_scene_snapshots.py):\n"
                          + "".join(difflib.unified_diff(want.splitlines(True),
                                                         text.splitlines(True), "snapshot",
                                                         "now")))


def plane_drawing(dims=dict(a=6.0, b=2.0, c=7.0, d=9.0), phis=(0.0, 90.0)):
    return linkage.mechanism_drawing(linkage.Linkage("plane", **dims), phis)


def dot_of(drawing, width, height, point):
    """Where text_drawing must put a page point: the page's bounds fitted, aspect kept, in a
    grid of braille dots (2 x 4 a character) below two title lines - worked out here from the
    layout, not taken from the renderer."""
    x0, y0, x1, y1 = drawing.bounds
    cols, rows = 2 * width - 1, 4 * (height - 3) - 1
    scale = min(cols / (x1 - x0), rows / (y1 - y0))
    x = (cols - (x1 - x0) * scale) / 2 + (point[0] - x0) * scale
    y = (rows - (y1 - y0) * scale) / 2 + (y1 - point[1]) * scale
    return round(y) // 4 + 2, round(x) // 2


def test_joints_are_drawn_where_they_are():
    """The moving pins (●) and fixed pivots (◉) stand in the character cells their page
    positions fall in, and nowhere else."""
    drawing = plane_drawing()
    for index, frame in enumerate(drawing.frames):
        lines = linkage.text_drawing(drawing, index, 100, 30, True).splitlines()
        found = {(row, col): ch for row, line in enumerate(lines) for col, ch in enumerate(line)
                 if ch in "●◉"}
        marks = drawing.ground.marks + frame.layer.marks
        want = {dot_of(drawing, 100, 30, m.at): "◉" if m.kind == "pivot" else "●"
                for m in marks}
        assert found == want


def test_a_frame_where_the_linkage_is_not_says_so():
    """a=6 b=2 c=3 d=2 at phi = 180: |A B0| = 8 > c + d = 5, the loop cannot close; the frame
    says so and draws the crank alone (phi = 0, |A B0| = 4, assembles)."""
    drawing = plane_drawing(dict(a=6.0, b=2.0, c=3.0, d=2.0), (0.0, 180.0))
    assert drawing.frames[0].message is None
    text = linkage.text_drawing(drawing, 1, 80, 24, True)
    assert text.splitlines()[-1] == "not assembled at φ = 180°"
    assert "●" in text and text.count("●") == 1                      # A; no B
    ascii_text = linkage.text_drawing(drawing, 1, 80, 24, False)
    assert ascii_text.splitlines()[-1] == "not assembled at phi = 180 deg"


@pytest.mark.parametrize("width, height", [(1, 1), (20, 8), (300, 90)])
def test_any_terminal_size_gives_a_frame_of_that_size(width, height):
    drawing = plane_drawing()
    lines = linkage.text_drawing(drawing, 0, width, height, True).splitlines()
    assert len(lines) == max(height, 8) and max(map(len, lines)) <= max(width, 20)


def test_piped_frames_are_spread_over_the_sweep(tmp_path):
    """--frames 4 of the 72 positions 30..385: 30, 120, 210, 300 degrees."""
    scene = str(ROOT / "data" / "scenes" / "fig1a-plane-four-bar.toml")
    result = subprocess.run(PROGRAM + ["scene", scene, "--frames", "4"], capture_output=True,
                            env=dict(os.environ, PYTHONIOENCODING="utf-8"), timeout=60)
    assert result.returncode == 0, result.stderr
    assert [float(a) for a in CAPTION.findall(result.stdout)] == [30.0, 120.0, 210.0, 300.0]
    lines = result.stdout.splitlines()
    assert len(lines) == 4 * 24 + 3 and lines[24] == lines[49] == lines[74] == b""
    result = subprocess.run(PROGRAM + ["scene", scene], capture_output=True,
                            env=dict(os.environ, PYTHONIOENCODING="ascii"), timeout=60)
    assert result.returncode == 0 and result.stdout.isascii()


# ---- on a real terminal ----------------------------------------------------------------------

def animated(tmp_path, scene="fig1b-spherical-four-bar"):
    return Terminal(PROGRAM + ["scene", str(ROOT / "data" / "scenes" / f"{scene}.toml")],
                    tmp_path, rows=30, cols=100)


def test_the_animation_runs_until_q_and_restores_the_terminal(tmp_path):
    term = animated(tmp_path)
    try:
        start = term.wait_for(b"\x1b[?1049h")                       # the alternate screen
        term.drain(1.0)
        angles = [float(a) for a in CAPTION.findall(term.seen[start:])]
        assert len(set(angles)) >= 4 and angles[:3] == [30.0, 35.0, 40.0]
        assert term.modes() != term.modes_before                      # single keys, no echo
        term.press(b"q")
        assert term.proc.wait(timeout=20) == 0
        term.drain(0.3)
        assert term.modes() == term.modes_before
        after = term.seen[term.wait_for(b"\x1b[?1049l"):]            # back on the main screen
        assert b"\x1b[?25h" in term.seen[start:]                      # the cursor shown again
        assert len(CAPTION.findall(after)) == 1                       # the last frame left there
        assert not list(tmp_path.iterdir())                          # no file written
    finally:
        term.close()


def test_ctrl_c_stops_the_animation_and_restores_the_terminal(tmp_path):
    term = animated(tmp_path, "fig2b-skew-slider-crank")
    try:
        term.wait_for(b"x = ")
        term.press(b"\x03")
        assert term.proc.wait(timeout=20) == 130
        term.drain(0.3)
        assert term.modes() == term.modes_before
        assert b"interrupted" in term.seen and b"\x1b[?1049l" in term.seen
    finally:
        term.close()


def test_ctrl_z_gives_the_terminal_back_and_fg_takes_it_again(tmp_path):
    """Under a shell with job control (bash, set -m): Ctrl-Z stops the animation with the
    terminal as it was (stty prints it while the program is stopped), `fg` animates again
    with single keys, q ends it."""
    scene = ROOT / "data" / "scenes" / "fig1a-plane-four-bar.toml"
    script = (f"set -m; stty -g > before.txt; {' '.join(PROGRAM)} scene {scene}; "
              "stty -g > stopped.txt; "
              "echo JOB-STOPPED; fg; echo EXIT=$?")
    term = Terminal(["bash", "-c", script], tmp_path, rows=30, cols=100)
    try:
        term.wait_for(b"\xcf\x86 = ")
        term.press(b"\x1a")
        at = term.wait_for(b"JOB-STOPPED")
        assert (tmp_path / "stopped.txt").read_text() == (tmp_path / "before.txt").read_text()
        assert b"\x1b[?1049l" in term.seen[:at]
        term.wait_for(b"\xcf\x86 = ", after=at)                     # animated again
        term.drain(0.5)
        assert term.modes() != term.modes_before
        term.press(b"q")
        term.wait_for(b"EXIT=0", after=at)
        assert term.proc.wait(timeout=20) == 0
    finally:
        term.close()
