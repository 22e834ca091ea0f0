"""Scenes and plots: every scene of data/scenes runs, writes its DAT files, draws a
real PNG and the plain-text plot stored in data/scenes/snapshots/ (python3
tests/support/make_scene_snapshots.py rewrites those, and nothing else does). The text plot puts the
curve where an independent solution of the linkage says it is; a displacement-only scene asks the
engine for no derivative; the faithful numbers are PC-BASIC's (the golden corpus); a scene with a
mistake gets a message naming the file, the key and what was expected, and no traceback.
"""

from __future__ import annotations

import contextlib
import difflib
import io
import math
import os
import re
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import pytest

from support import basic_runner
import linkage
from support import make_scene_pngs, make_scene_snapshots
from support.peers import need
from support.program import PROGRAM

ROOT = basic_runner.ROOT
ALL_SCENES = sorted((ROOT / "data" / "scenes").glob("*.toml"))
LOADED = {p: linkage.load_scene(str(p)) for p in ALL_SCENES}
SCENES = [p for p in ALL_SCENES if not LOADED[p].draws_mechanism       # curves against phi
          and LOADED[p].simulation is None]             # (a run in time: test_simulate_scenes)
GOLDEN = ROOT / "data" / "golden"


def scene_id(path):
    return path.stem


# ---- every scene: DAT files, PNG, text snapshot ----------------------------------------------

_drawn = {}


@pytest.fixture
def drawn(request, tmp_path_factory):
    """`scene FILE --png --text`, run once per scene (in this process: matplotlib is imported
    once); (scene, standard output, standard error, the DAT folder, the PNG)."""
    need("matplotlib", load=False)
    path = request.param
    if path not in _drawn:
        out = tmp_path_factory.mktemp(path.stem)
        png = out / "figure.png"
        stdout, stderr = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            status = linkage.main(["scene", str(path), "--dir", str(out / "dat"), "--png",
                                   str(png), "--text"])
        assert status == 0, stderr.getvalue()
        _drawn[path] = (linkage.load_scene(str(path)), stdout.getvalue(), stderr.getvalue(),
                        out / "dat", png)
    return _drawn[path]


def png_chunks(data: bytes):
    """Check a PNG's signature and every chunk's CRC; its IHDR fields and its IDAT data
    decompressed: (width, height, channels, raw rows, each a filter byte and the pixels)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG signature"
    chunks, at = [], 8
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        crc, = struct.unpack(">I", data[at + 8 + length:at + 12 + length])
        assert zlib.crc32(kind + body) == crc, f"bad CRC in chunk {kind!r}"
        chunks.append((kind, body))
        at += 12 + length
    assert chunks[0][0] == b"IHDR" and chunks[-1][0] == b"IEND"
    width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", chunks[0][1])
    assert depth == 8 and interlace == 0 and colour in (0, 2, 6)
    channels = {0: 1, 2: 3, 6: 4}[colour]
    raw = zlib.decompress(b"".join(body for kind, body in chunks if kind == b"IDAT"))
    stride = width * channels + 1
    assert len(raw) == height * stride, "IDAT does not hold height x width pixels"
    rows = [raw[y * stride:(y + 1) * stride] for y in range(height)]
    assert all(row[0] <= 4 for row in rows), "a row with an unknown filter"
    return width, height, channels, rows


def png_pixels(data: bytes):
    """The decoded pixels of a PNG (png_chunks, then the row filters undone): rows of bytes."""
    width, height, channels, raw_rows = png_chunks(data)
    rows, previous = [], bytearray(width * channels)
    for raw in raw_rows:
        kind, line = raw[0], bytearray(raw[1:])
        for i in range(len(line)):
            left = line[i - channels] if i >= channels else 0
            up, corner = previous[i], previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                line[i] = (line[i] + (left if pa <= pb and pa <= pc else up if pb <= pc
                                      else corner)) & 255
        rows.append(bytes(line))
        previous = line
    return width, height, channels, rows


@pytest.mark.parametrize("drawn", SCENES, ids=scene_id, indirect=True)
def test_the_scene_writes_its_dat_files(drawn):
    scene, _, _, directory, _ = drawn
    plan = [(p, b) for b in scene.branches for p in scene.precisions]
    for precision, branch in plan:
        folder = directory if len(plan) == 1 else directory / f"{precision}-branch{branch}"
        names = sorted(n for n in os.listdir(folder) if n.endswith(".DAT"))
        shown = {q for panel in scene.panels for q in panel.quantities}
        level = 2 if "acceleration" in shown else 1 if "velocity" in shown else 0
        want = ["ANG.DAT", "VEL.DAT", "ACC.DAT"][:level + 1]
        if "transmission" in shown and precision == "double":
            want.append("MU.DAT")           # the engine's transmission angle, beside them
        assert names == sorted(want), folder
        for name in names:
            data = (folder / name).read_bytes()
            assert data.endswith(b"\x1a") and b"\r\n" in data, name
            assert not re.search(rb"[^\r]\n", data), f"{name}: a line ends without CR"


@pytest.mark.parametrize("drawn", SCENES, ids=scene_id, indirect=True)
def test_the_png_is_a_real_image(drawn):
    _, _, _, _, png = drawn
    data = png.read_bytes()
    assert 5_000 < len(data) < 100_000
    width, height, _, rows = png_chunks(data)
    assert 400 <= width <= 1600 and 200 <= height <= 1600
    assert len({row[1:] for row in rows}) > height // 4, "too few different rows for a figure"


@pytest.mark.parametrize("drawn", [p for p in SCENES if p.stem == "fig3-plane-four-bar"],
                         ids=scene_id, indirect=True)
def test_the_png_shows_text_and_curves(drawn):
    """Fig. 3's PNG decoded: mostly white, with dark pixels (text, axes, the displacement
    curve), blue ones (velocity) and red ones (acceleration)."""
    _, _, _, _, png = drawn
    width, height, channels, rows = png_pixels(png.read_bytes())
    pixels = [row[i:i + 3] for row in rows for i in range(0, len(row), channels)]
    assert 0.6 < sum(p == b"\xff\xff\xff" for p in pixels) / len(pixels) < 0.98
    assert sum(max(p) < 60 for p in pixels) > 2000
    assert sum(p[2] > 150 and p[0] < 80 for p in pixels) > 200, "no blue curve"
    assert sum(p[0] > 180 and p[1] < 80 and p[2] < 80 for p in pixels) > 200, "no red curve"


@pytest.mark.parametrize("drawn", SCENES, ids=scene_id, indirect=True)
def test_the_text_plot_matches_its_snapshot(drawn):
    scene, text, _, _, _ = drawn
    lines = text.splitlines()
    assert len(lines) <= 24 and max(len(line) for line in lines) <= 80
    assert all(ch.isascii() for ch in text)
    snapshot = make_scene_snapshots.snapshot_path(Path(scene.path))
    assert snapshot.exists(), ("no snapshot: PYTHONPATH=tests python3 -m "
                               "support.make_scene_snapshots")
    want = snapshot.read_text(encoding="ascii")
    assert text == want, (f"{snapshot.name} differs (if the change is intended: python3 "
                          "tests/support/make_scene_snapshots.py):\n"
                          + "".join(difflib.unified_diff(want.splitlines(True),
                                                         text.splitlines(True), "snapshot",
                                                         "now")))


def test_every_scene_has_a_snapshot_and_every_snapshot_a_scene():
    stored = sorted(p.name for p in make_scene_snapshots.SNAPSHOTS.glob("*.txt"))
    assert stored == sorted(make_scene_snapshots.snapshot_path(p, encoding).name
                            for p in ALL_SCENES for encoding in make_scene_snapshots.encodings(p))
    mechanisms = sum(scene.draws_mechanism for scene in LOADED.values())
    assert len(stored) == len(ALL_SCENES) + mechanisms


@pytest.mark.parametrize("drawn", SCENES, ids=scene_id, indirect=True)
def test_the_figure_is_labelled(drawn):
    """Title with the branch and the precision; each panel names its quantities with units; the
    x axis is the input angle in degrees."""
    scene, text, _, _, _ = drawn
    head = " ".join(" ".join(text.splitlines()[:3]).split())      # a wrapped line rejoined
    assert re.search(r"branch(es)? 1 \(A\+B\)|branch(es)? 2 \(A-B\)|branch follow \(the", head)
    assert {"basic": "precision basic", "double": "precision double"}[scene.precisions[0]] in head
    headers = [line for line in text.splitlines() if re.match(r"\([abc]\) ", line)]
    assert len(headers) == len(scene.panels)
    slider = scene.kind in ("slider", "skew-slider")
    units = {"displacement": "[length]" if slider else "[deg]",
             "velocity": "[length/rad]" if slider else "[rad/rad]",
             "acceleration": "[length/rad^2]" if slider else "[rad/rad^2]",
             "transmission": "mu [deg]", "torque": "T [N m]", "shaking": "|F| [N]",
             "joint_forces": "against"}
    for header, panel in zip(headers, scene.panels):
        for quantity in panel.quantities:
            assert units[quantity] in header, header
    assert text.splitlines()[-1].startswith("x axes: input angle phi [deg]")


@pytest.mark.parametrize("drawn", SCENES, ids=scene_id, indirect=True)
def test_the_figure_says_where_the_original_clipped(drawn):
    """ERRATA K9: the original writes VEL and ACC clipped to +-3. A figure with a basic series
    whose VEL.DAT or ACC.DAT holds a 3 says so under the plot and in the PNG's legend."""
    scene, text, _, folder, _ = drawn
    touches = any(abs(v) == 3
                  for name in ("VEL.DAT", "ACC.DAT") for path in folder.rglob(name)
                  if "double" not in str(path.parent.name) and "basic" in scene.precisions
                  for _, v in linkage.read_dat(str(path)))
    assert ("basic clipped at +-3" in text.splitlines()[-1]) == touches


def test_the_clipped_curve_is_named_so_in_the_legend(tmp_path):
    """Fig. 3's basic acceleration touches -3 at phi = 180 (the listing's spike, clipped): its
    legend entry says so; the velocity, which stays within 1, does not."""
    scene = linkage.load_scene(str(ROOT / "data" / "scenes" / "fig3-plane-four-bar.toml"))
    figure = linkage.scene_figure(scene, linkage.compute_scene(scene, str(tmp_path)))
    assert [c.label for p in figure.panels for c in p.curves] == [
        "displacement", "velocity", "acceleration (clipped at +-3)"]


# ---- the text plot puts the curve in the right cells -----------------------------------------

def read_axes(text: str):
    """From a text plot, reading only the tick values printed on its axes: for each panel its
    lines and the map value -> fractional line index; and the map x -> fractional column."""
    lines = text.splitlines()
    axis_lines = [i for i, line in enumerate(lines) if re.fullmatch(r" +\+[-+]{10,}", line)]
    column0 = lines[axis_lines[-1]].index("+")            # the y axes' column, the x axis's 0
    ticks = [m.start() for m in re.finditer(r"\+", lines[axis_lines[-1]])]
    columns = {}
    for m in re.finditer(r"-?[\d.]+", lines[axis_lines[-1] + 1]):
        columns[next(c for c in ticks if m.start() <= c < m.end())] = float(m[0])
    (c0, v0), (c1, v1) = min(columns.items()), max(columns.items())

    def x_column(x):
        return c0 + (x - v0) * (c1 - c0) / (v1 - v0)
    panels, top = [], 0
    for end in axis_lines:
        rows = {}
        for i in range(end - 1, top, -1):
            label = lines[i][:column0 - 1].strip()
            if len(lines[i]) <= column0 or lines[i][column0 - 1] != " " or not re.fullmatch(
                    r"(-?[\d.]+)?", label):
                break                                      # the panel's header
            if label:
                rows[i] = float(label)
        (r0, w0), (r1, w1) = min(rows.items()), max(rows.items())

        def y_line(y, r0=r0, w0=w0, r1=r1, w1=w1):
            return r0 + (y - w0) * (r1 - r0) / (w1 - w0)
        panels.append((lines, y_line))
        top = end
    return panels, x_column


def marked(lines, line_at: float, column_at: float, markers: str) -> bool:
    """Whether a marker is in the cell of (line_at, column_at), or in the neighbouring cell where
    the position is within a tenth of a cell of the boundary."""
    return any(c < len(lines[r]) and lines[r][c] in markers
               for r in cells_near(line_at) for c in cells_near(column_at))


def cells_near(position: float):
    """The cell of a fractional position, and its neighbour if the position is within a tenth of
    a cell of the boundary (the plot rounds half up; the expected value is independent)."""
    cell = math.floor(position + 0.5)
    near = position + 0.5 - cell
    return {cell} | ({cell - 1} if near < 0.1 else {cell + 1} if near > 0.9 else set())


def plane_output(dims, phi_deg, branch):
    """psi (degrees) of the plane four-bar by the triangle (law of cosines), independent of
    linkage.py: crank pivot at the origin, output pivot at (a, 0); branch 1 is the assembly on the
    counter-clockwise side of the pivot-to-crank-tip line (PC-BASIC's plane-b1 confirms it)."""
    a, b, c, d = (dims[k] for k in "abcd")
    phi = math.radians(phi_deg)
    bx, by = b * math.cos(phi) - a, b * math.sin(phi)
    r = math.hypot(bx, by)
    alpha = math.acos((d * d + r * r - c * c) / (2 * d * r))
    psi = math.degrees(math.atan2(by, bx) + (alpha if branch == 1 else -alpha))
    return (psi + 180.0) % 360.0 - 180.0


def test_the_geometry_is_the_listing_s_branch_1():
    """The independent solution agrees with what PC-BASIC wrote (golden plane-b1)."""
    dims = dict(a=6.0, b=2.0, c=7.0, d=9.0)
    for phi, psi in linkage.read_dat(str(GOLDEN / "plane-b1" / "ANG.DAT")):
        assert abs(plane_output(dims, phi, 1) - psi) < 2e-3, phi


def test_the_curve_passes_through_the_right_cells(tmp_path, capsys):
    """Fig. 3's text plot: at known input angles (points of the sweep) the marker is in the cell
    that the printed tick values give for the triangle's psi."""
    path = ROOT / "data" / "scenes" / "fig3-plane-four-bar.toml"
    assert linkage.main(["scene", str(path), "--dir", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    (panel_a, _), x_column = read_axes(text)
    lines, y_line = panel_a
    dims = linkage.load_scene(str(path)).dimensions
    for phi in (0.0, 30.0, 72.0, 120.0, 200.0, 288.0, 330.0, 358.0):
        psi = plane_output(dims, phi, 1)
        assert marked(lines, y_line(psi), x_column(phi), "*"), \
            f"phi={phi}: psi={psi:.3f} not drawn at line {y_line(psi):.2f}, column " \
            f"{x_column(phi):.2f}:\n{text}"


def test_the_velocity_passes_through_the_right_cells(tmp_path, capsys):
    """A velocity-only scene of the same linkage (one tall panel), branch 2 in double precision:
    the marker is where the triangle's central difference puts it."""
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_TEXT.format(mechanism="plane", dims="{ a = 6, b = 2, c = 7, d = 9 }",
                                       precision="double", panels=panels_text(["velocity"]))
                     .replace("[1]", "[2]"))
    assert linkage.main(["scene", str(scene), "--dir", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    ((lines, y_line),), x_column = read_axes(text)
    dims = dict(a=6.0, b=2.0, c=7.0, d=9.0)
    h = 1e-5
    for phi in range(0, 361, 15):
        velocity = (plane_output(dims, phi + h, 2) - plane_output(dims, phi - h, 2)) / (2 * h)
        assert marked(lines, y_line(velocity), x_column(phi), "*"), \
            f"phi={phi}: velocity {velocity:.4f} not drawn:\n{text}"


def test_a_straight_line_is_drawn_cell_by_cell():
    """The renderer alone: y = x from 0 to 100, a point every 10; each point in its cell, every
    column between them marked within a line of the exact position, and no more."""
    run = tuple((float(x), float(x)) for x in range(0, 101, 10))
    curve = linkage.Curve("line", "velocity", "double", 1, (run,))
    panel = linkage.Panel("a", ("velocity",), (("velocity", "v", "u"),), (curve,), None)
    figure = linkage.Figure("t", "s", ("input angle", "phi", "deg"), (panel,))
    text = linkage.text_figure(figure)
    ((lines, y_line),), x_column = read_axes(text)
    for x, y in run:
        assert marked(lines, y_line(y), x_column(x), "*"), (x, text)
    first, last = round(x_column(0)), round(x_column(100))
    for column in range(first, last + 1):
        x = (column - x_column(0)) / (x_column(100) - x_column(0)) * 100
        near = [r for r, line in enumerate(lines) if column < len(line) and line[column] == "*"]
        assert near and all(abs(r - y_line(x)) <= 1.0 for r in near), (column, text)
    assert sum(line.count("*") for line in lines) <= 2 * (last - first + 1)


# ---- derivatives only where a panel shows them -----------------------------------------------

SCENE_TEXT = """
mechanism = "{mechanism}"
dimensions = {dims}
input = {{ from = 0, to = 360, step = 5 }}
branches = [1]
precision = "{precision}"
{panels}
"""


def panels_text(*panels):
    return "\n".join(f"[[panels]]\nquantities = {list(p)!r}".replace("'", '"') for p in panels)


@pytest.fixture
def engine_calls(monkeypatch):
    """Every call of the engine's sweep loops, with the derivative level it was asked for."""
    calls = []
    for name in ("_sweep_four_bar", "_sweep_slider"):
        loop = getattr(linkage, name)

        def counted(link, phis, sign, level, loop=loop):
            calls.append((link.kind, len(phis), level))
            return loop(link, phis, sign, level)
        monkeypatch.setattr(linkage, name, counted)
    precise = linkage.Linkage._precise

    def counted_precise(self, phi, sign, level):
        calls.append((self.kind, 1, level))
        return precise(self, phi, sign, level)
    monkeypatch.setattr(linkage.Linkage, "_precise", counted_precise)
    return calls


@pytest.mark.parametrize("mechanism, dims", [
    ("plane", "{ a = 6, b = 2, c = 7, d = 9 }"),
    ("skew-slider", "{ a = 6, b = 1, c = 7.5, f = 3, ksi = 45 }"),
    ("slider", "{ b = 2, c = 3, e = 1 }"),          # a change point at 270: the decimal path
])
@pytest.mark.parametrize("panels, level", [
    ((["displacement"],), 0),
    ((["displacement"], ["velocity"]), 1),
    ((["velocity", "acceleration"],), 2),
])
def test_the_engine_computes_only_what_the_panels_show(mechanism, dims, panels, level,
                                                       engine_calls, tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_TEXT.format(mechanism=mechanism, dims=dims, precision="double",
                                       panels=panels_text(*panels)))
    assert linkage.main(["scene", str(scene), "--dir", str(tmp_path)]) == 0
    assert engine_calls, "the engine was not called"
    assert {call[2] for call in engine_calls} == {level}
    assert sum(n for kind, n, _ in engine_calls if n > 1) == 73      # one sweep, 0 to 360 by 5
    written = sorted(n for n in os.listdir(tmp_path) if n.endswith(".DAT"))
    assert written == sorted(["ANG.DAT", "VEL.DAT", "ACC.DAT"][:level + 1])


def test_a_faithful_scene_asks_the_engine_only_whether_it_assembles(engine_calls, tmp_path,
                                                                     capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_TEXT.format(mechanism="plane", dims="{ a = 6, b = 2, c = 7, d = 9 }",
                                       precision="basic",
                                       panels=panels_text(["velocity", "acceleration"])))
    assert linkage.main(["scene", str(scene), "--dir", str(tmp_path)]) == 0
    assert [level for _, _, level in engine_calls] == [0]


@pytest.mark.parametrize("panels, level", [
    ((["displacement"],), 0),
    ((["displacement"], ["velocity"]), 1),
    ((["velocity", "acceleration"],), 2),
])
def test_the_listing_computes_only_what_the_panels_show(panels, level, monkeypatch, tmp_path,
                                                        capsys):
    """A faithful scene runs the listing's sweep point only as far as its panels need: the
    lines past 1150 (velocity) and past 1210 (acceleration) never run for a scene without them,
    and their files are not written."""
    computed = []
    points = linkage.sweep_points

    def counted(co, SOL, S, derivatives=2):
        point = points(co, SOL, S, derivatives)

        def lines(PHI):
            written = point(PHI)
            computed.append((derivatives, tuple(line is not None for line in written)))
            return written
        return lines
    monkeypatch.setattr(linkage, "sweep_points", counted)
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_TEXT.format(mechanism="plane", dims="{ a = 6, b = 2, c = 7, d = 9 }",
                                       precision="basic", panels=panels_text(*panels)))
    assert linkage.main(["scene", str(scene), "--dir", str(tmp_path)]) == 0
    shown = tuple(i <= level for i in range(3))
    assert computed == [(level, shown)] * 73                        # 0 to 360 by 5
    written = sorted(n for n in os.listdir(tmp_path) if n.endswith(".DAT"))
    assert written == sorted(["ANG.DAT", "VEL.DAT", "ACC.DAT"][:level + 1])


def test_the_listing_s_lines_do_not_depend_on_what_is_left_out():
    """ANG.DAT's line (and VEL.DAT's) is the same whether or not the rest is computed."""
    v = linkage.Variables()
    answers = iter(["2", "7", "9", "6"])
    linkage.dimensions(v, 1, lambda prompt: linkage.input_value(next(answers)))
    co = linkage.coefficients(v, 1)
    for degrees in (0, 40, 180, 275.5):
        phi = linkage.degrees_to_radians(linkage.Single(degrees))
        full = linkage.sweep_point(co, phi, 1, v.S)
        assert linkage.sweep_point(co, phi, 1, v.S, 0) == (full[0], None, None)
        assert linkage.sweep_point(co, phi, 1, v.S, 1) == (full[0], full[1], None)


def test_the_committed_displacement_only_scene(engine_calls, tmp_path, capsys):
    path = ROOT / "data" / "scenes" / "plane-both-assemblies.toml"
    assert linkage.load_scene(str(path)).derivatives == 0
    assert linkage.main(["scene", str(path), "--dir", str(tmp_path)]) == 0
    assert [(n, level) for _, n, level in engine_calls] == [(361, 0), (361, 0)]


# ---- the numbers: PC-BASIC's and the engine's ------------------------------------------------

GOLDEN_TWINS = {  # scene: the golden case with the same linkage (same answers, other range)
    "fig3-plane-four-bar": "plane-b1",
    "fig4-spherical-wobble-plate": "spherical-wobble-plate",
    "fig5-skew-four-bar": "skew-b1",
    "fig6-skew-slider-crank": "skew-slider-b1",
    "hard-spike-180": "plane-spike-180",
    "hard-change-point": "plane-change-point",
    "hard-dead-centre": "plane-double-rocker",
}


@pytest.mark.parametrize("name, case", GOLDEN_TWINS.items())
def test_the_basic_numbers_are_pc_basic_s(name, case, tmp_path):
    """The scene's linkage with its golden twin's range writes the files PC-BASIC wrote."""
    scene = linkage.load_scene(str(ROOT / "data" / "scenes" / f"{name}.toml"))
    keys = (GOLDEN / case / "keys.txt").read_bytes().decode("ascii")
    answers = keys[1:].split("\r")
    menu = linkage.KIND_MENU[scene.kind]
    assert keys[0] == menu[0]
    asked = dict(zip(menu[1], map(float, answers)))
    assert {("ksi" if k == "skew" else k): v for k, v in asked.items()} == scene.dimensions
    start, stop, step = map(float, answers[-4:-1])
    twin = scene._replace(start=start, stop=stop, step=step,
                          branches=(int(answers[-1]),), precisions=("basic",))
    linkage.compute_scene(twin, str(tmp_path))
    written = sorted(n for n in os.listdir(tmp_path) if n.endswith(".DAT"))
    assert written == sorted(["ANG.DAT", "VEL.DAT", "ACC.DAT"][:scene.derivatives + 1])
    for name_ in written:
        assert (tmp_path / name_).read_bytes() == (GOLDEN / case / name_).read_bytes(), name_


@pytest.mark.parametrize("drawn", [p for p in SCENES if p.stem == "hard-spike-180"],
                         ids=scene_id, indirect=True)
def test_the_spike_scene_shows_the_spike_and_the_true_value(drawn):
    """At phi = 180 the original writes VEL .5450 and ACC 3 (the issue's numbers); the engine
    writes the velocity the triangle's central difference gives, 0.25."""
    _, _, _, directory, _ = drawn
    basic = dict(linkage.read_dat(str(directory / "basic-branch2" / "VEL.DAT")))
    double = dict(linkage.read_dat(str(directory / "double-branch2" / "VEL.DAT")))
    assert round(basic[180.0], 4) == 0.545
    assert dict(linkage.read_dat(str(directory / "basic-branch2" / "ACC.DAT")))[180.0] == 3
    dims = dict(a=6.0, b=2.0, c=7.0, d=9.0)
    h = 1e-5
    true = (plane_output(dims, 180 + h, 2) - plane_output(dims, 180 - h, 2)) / (2 * h)
    assert abs(double[180.0] - true) < 1e-8 and abs(true - 0.25) < 1e-8


# ---- plot: the figure of existing DAT files --------------------------------------------------

def test_read_dat_reads_gw_basic_and_double_files(tmp_path):
    path = tmp_path / "VEL.DAT"
    path.write_bytes(b"0,.5\r\n10,-1.713751E-02\r\n20,3\r\n30.5,-.25\r\n\x1a")
    assert linkage.read_dat(str(path)) == [(0, 0.5), (10, -0.01713751), (20, 3), (30.5, -0.25)]
    path.write_bytes(b"0.0,0.25000000000000006\r\n1.0,-1.7e-05\r\n\x1a")
    assert linkage.read_dat(str(path)) == [(0.0, 0.25000000000000006), (1.0, -1.7e-05)]


def test_plot_draws_what_the_menu_program_wrote(tmp_path):
    """The menu program's own files (PC-BASIC's plane-b1) drawn by `plot`: the same plot area as
    the scene of that linkage and range."""
    result = subprocess.run(PROGRAM + ["plot", "plane-b1", "--mechanism", "plane"], cwd=GOLDEN,
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert "precision basic (from the number format)" in result.stdout
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_TEXT.replace("step = 5", "step = 10").format(
        mechanism="plane", dims="{ a = 6, b = 2, c = 7, d = 9 }", precision="basic",
        panels=panels_text(["displacement"], ["velocity", "acceleration"])))
    drawn = subprocess.run(PROGRAM + ["scene", str(scene), "--dir", str(tmp_path)],
                           capture_output=True, text=True, timeout=60)
    assert result.stdout.splitlines()[2:] == drawn.stdout.splitlines()[2:]


def test_plot_overlays_the_series_of_a_scene(tmp_path):
    """`plot` of a scene's folder (one folder a series) draws the scene's figure again."""
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_TEXT.format(
        mechanism="plane", dims="{ a = 4, b = 2, c = 3, d = 5 }", precision="both",
        panels=panels_text(["displacement"], ["velocity", "acceleration"]))
        .replace("branches = [1]", "branches = [1, 2]"))
    drawn = subprocess.run(PROGRAM + ["scene", str(scene), "--dir", str(tmp_path)],
                           capture_output=True, text=True, timeout=60)
    assert drawn.returncode == 0, drawn.stderr
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_dir()) == [
        "basic-branch1", "basic-branch2", "double-branch1", "double-branch2"]
    result = subprocess.run(PROGRAM + ["plot", str(tmp_path), "--mechanism", "plane"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    subtitle = next(i for i, line in enumerate(lines)
                    if "precision basic and double; branches 1, 2" in line)
    # the title is the folder's name, wrapped where long (under pytest-xdist it is)
    assert lines[subtitle + 1:] == drawn.stdout.splitlines()[2:]


@pytest.mark.parametrize("content, message", [
    (None, "no ANG.DAT, VEL.DAT or ACC.DAT here"),
    (b"0,.5\r\n10;3\r\n\x1a", "ANG.DAT: line 2: expected two numbers"),
    (b"0,.5\r\nten,3\r\n\x1a", "ANG.DAT: line 2: expected two numbers"),
    (b"0,.5\r\n1,nan\r\n\x1a", "ANG.DAT: line 2: expected two numbers"),
    (b"\r\n\x1a", "hold no point to draw"),      # issue 22, item 9: was drawn empty, exit 0
    (b"\x1a", "hold no point to draw"),
])
def test_plot_of_bad_files_says_which_line(content, message, tmp_path):
    if content is not None:
        (tmp_path / "ANG.DAT").write_bytes(content)
    result = subprocess.run(PROGRAM + ["plot", str(tmp_path)], capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 1
    assert message in result.stderr and "Traceback" not in result.stderr


# ---- PNG or text -----------------------------------------------------------------------------

def test_png_without_matplotlib_names_the_extra(tmp_path):
    scene = ROOT / "data" / "scenes" / "fig3-plane-four-bar.toml"
    code = ("import sys; sys.modules['matplotlib'] = None; "
            "import linkage; sys.exit(linkage.main(sys.argv[1:]))")
    result = subprocess.run([sys.executable, "-c", code, "scene", str(scene), "--dir",
                             str(tmp_path), "--png", str(tmp_path / "f.png")],
                            capture_output=True, text=True, timeout=60,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert result.returncode == 1
    assert "python3 -m pip install matplotlib" in result.stderr
    assert "Traceback" not in result.stderr
    assert os.listdir(tmp_path) == [], "work was done before finding matplotlib missing"


def test_png_alone_draws_no_text_and_text_is_the_default(tmp_path, capsys):
    need("matplotlib", load=False)
    scene = str(ROOT / "data" / "scenes" / "fig4-spherical-wobble-plate.toml")
    assert linkage.main(["scene", scene, "--dir", str(tmp_path), "--png",
                         str(tmp_path / "f.png")]) == 0
    assert capsys.readouterr().out == ""
    assert (tmp_path / "f.png").stat().st_size > 5000
    assert linkage.main(["scene", scene, "--dir", str(tmp_path)]) == 0
    assert capsys.readouterr().out.startswith("Fig. 4")


# ---- scene files with mistakes ---------------------------------------------------------------

GOOD = {
    "title": '"t"',
    "mechanism": '"plane"',
    "dimensions": "{ a = 6, b = 2, c = 7, d = 9 }",
    "input": "{ from = 0, to = 90, step = 10 }",
    "branches": "[1]",
    "precision": '"double"',
}
GOOD_PANELS = '[[panels]]\nquantities = ["displacement"]\n'


def scene_file(**changes):
    keys = {**GOOD, **changes}
    panels = keys.pop("panels", GOOD_PANELS)
    return "".join(f"{k} = {v}\n" for k, v in keys.items() if v is not None) + panels


MISTAKES = [
    ("unknown key", scene_file(colour='"red"'),
     ["unknown key 'colour'", "expected one of", "'mechanism'"]),
    ("misspelt input key", scene_file(input="{ from = 0, too = 90, step = 10 }"),
     ["unknown key 'input.too'", "'input.to'"]),
    ("wrong type", scene_file(input='{ from = 0, to = 90, step = "10" }'),
     ["key 'input.step'", "expected a number (degrees)", "got the string '10'"]),
    ("wrong type of dimension", scene_file(dimensions='{ a = 6, b = 2, c = true, d = 9 }'),
     ["key 'dimensions.c'", "expected a number, the coupler", "got a boolean"]),
    ("missing dimension", scene_file(dimensions="{ a = 6, b = 2, c = 7 }"),
     ["key 'dimensions.d' is missing", "expected a number, the output crank",
      "a plane linkage takes a, b, c, d"]),
    ("dimension of another mechanism", scene_file(dimensions="{ a = 6, b = 2, c = 7, d = 9, "
                                                             "e = 1 }"),
     ["unknown key 'dimensions.e'", "a plane linkage takes a, b, c, d"]),
    ("missing key", scene_file(branches=None),
     ["key 'branches' is missing", "expected a list of branches, 1 (A+B) and/or 2 (A-B)"]),
    ("unknown mechanism", scene_file(mechanism='"planar"'),
     ["key 'mechanism'", "expected one of plane, spherical, skew, slider, skew-slider",
      "got the string 'planar'"]),
    ("branch 3", scene_file(branches="[3]"),
     ["key 'branches'", "expected [1], [2] or [1, 2]"]),
    ("precision", scene_file(precision='"single"'),
     ["key 'precision'", "expected basic, double or both", "got the string 'single'"]),
    ("step of the wrong sign", scene_file(input="{ from = 0, to = 90, step = -10 }"),
     ["key 'input.step'", "with the sign of to - from"]),
    ("no panels", scene_file(panels="panels = []\n"),
     ["key 'panels'", "a list of 1 to 3 tables"]),
    ("unknown quantity", scene_file(panels='[[panels]]\nquantities = ["jerk"]\n'),
     ["key 'panels[1].quantities'", "displacement, velocity, acceleration",
      "got a list"]),
    ("bad limits", scene_file(panels='[[panels]]\nquantities = ["velocity"]\nlimits = [3, -3]\n'),
     ["key 'panels[1].limits'", "low < high"]),
    ("cannot assemble", scene_file(dimensions="{ a = 10, b = 1, c = 2, d = 2 }"),
     ["key 'dimensions'", "a linkage that can be assembled somewhere from 0 to 90 degrees",
      "assembles at none of those 10 input angles"]),
    ("cannot assemble in the range", scene_file(dimensions="{ a = 5, b = 4, c = 2, d = 3 }",
                                                input="{ from = 70, to = 180, step = 10 }"),
     ["key 'dimensions'", "somewhere from 70 to 180 degrees"]),
    ("the original's assembly check", scene_file(mechanism='"skew-slider"', precision='"basic"',
                                                 dimensions="{ a = 3, b = 2, c = 7, f = 1, "
                                                            "ksi = 30 }"),
     ["key 'dimensions'", "what the original program accepts",
      "Illegal linkage (impossible to assemble)"]),
    ("not TOML", "mechanism = plane\n", ["not a TOML file", "line 1"]),
]


def test_a_figure_too_big_for_the_terminal_is_explained(tmp_path, capsys):
    """Three panels of two quantities, four series each: no room for the plots in 80 x 24."""
    need("matplotlib", load=False)
    panel = '[[panels]]\nquantities = ["velocity", "acceleration"]\n'
    path = tmp_path / "big.toml"
    path.write_text(scene_file(precision='"both"', branches="[1, 2]", panels=panel * 3))
    assert linkage.main(["scene", str(path), "--dir", str(tmp_path)]) == 1
    assert "the text plot does not fit in 80 x 24 characters" in capsys.readouterr().err
    assert linkage.main(["scene", str(path), "--dir", str(tmp_path), "--png",
                         str(tmp_path / "big.png")]) == 0
    assert (tmp_path / "big.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_png_that_cannot_be_written_is_explained(tmp_path, capsys):
    need("matplotlib", load=False)
    path = tmp_path / "s.toml"
    path.write_text(scene_file())
    out = tmp_path / "no such folder" / "f.png"
    assert linkage.main(["scene", str(path), "--dir", str(tmp_path), "--png", str(out)]) == 1
    assert capsys.readouterr().err == f"linkage.py: {out}: No such file or directory\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]   # the set: none of it


def test_a_scene_writes_its_set_of_files_all_or_none(tmp_path, capsys):
    """DAT files of every series, the CSV and the PNG: a failure of any one (here the PNG, the
    last to be made; then the CSV) leaves the old set as it was, byte for byte."""
    need("matplotlib", load=False)
    path = tmp_path / "s.toml"
    panels = GOOD_PANELS + '[[panels]]\nquantities = ["velocity", "acceleration"]\n'
    path.write_text(scene_file(precision='"both"', branches="[1, 2]", panels=panels))
    out = tmp_path / "out"
    assert linkage.main(["scene", str(path), "--dir", str(out), "--csv", str(tmp_path / "t.csv"),
                         "--png", str(tmp_path / "f.png")]) == 0
    def state():
        return {p.relative_to(tmp_path): p.read_bytes() for p in sorted(tmp_path.rglob("*"))
                if p.is_file() and p != path}
    before = state()
    assert len([p for p in before if p.suffix == ".DAT"]) == 12
    path.write_text(scene_file(precision='"both"', branches="[1, 2]", panels=panels,
                               input="{ from = 0, to = 90, step = 5 }"))
    (tmp_path / "f.png").unlink()
    (tmp_path / "f.png").mkdir()                             # the PNG cannot be written
    capsys.readouterr()
    assert linkage.main(["scene", str(path), "--dir", str(out), "--csv", str(tmp_path / "t.csv"),
                         "--png", str(tmp_path / "f.png")]) == 1
    assert "f.png: it is a folder" in capsys.readouterr().err
    assert state() == {p: b for p, b in before.items() if p.name != "f.png"}
    assert not [p for p in out.rglob(".*")]                  # no staging folder left behind


@pytest.mark.parametrize("what, content, fragments", MISTAKES, ids=[m[0] for m in MISTAKES])
def test_a_scene_with_a_mistake_is_explained(what, content, fragments, tmp_path, capsys):
    path = tmp_path / "mistake.toml"
    path.write_text(content)
    assert linkage.main(["scene", str(path), "--dir", str(tmp_path)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    message = captured.err
    assert message.startswith(f"linkage.py: {path}: "), message
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"


def test_the_mistakes_leave_no_traceback(tmp_path):
    """The same from the command line, for the kinds of mistake: exit status 1, one line."""
    for what, content, fragments in MISTAKES[::4] + [("missing file", None, ["cannot read"])]:
        path = tmp_path / "mistake.toml"
        if content is None:
            path = tmp_path / "absent.toml"
        else:
            path.write_text(content)
        result = subprocess.run(PROGRAM + ["scene", str(path), "--dir", str(tmp_path)],
                                capture_output=True, text=True, timeout=60)
        assert result.returncode == 1, what
        assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1, what
        assert fragments[0] in result.stderr, what


def test_the_readme_shows_a_current_terminal_plot():
    """The README's terminal plot is the stored snapshot of its scene, and its PNG exists."""
    readme = (ROOT / "README.md").read_text()
    snapshot = make_scene_snapshots.SNAPSHOTS / "hard-spike-180.txt"
    assert "".join("    " + line for line in snapshot.read_text().splitlines(True)) in readme
    png = re.search(r"!\[[^]]*\]\(([^)]+\.png)\)", readme)[1]
    data = (ROOT / png).read_bytes()
    assert png.startswith("data/") and len(data) < 100_000
    assert png_chunks(data)[0] >= 400


# -- scenes by name: those that come with the program ------------------------------------------

def test_a_scene_is_named_by_a_unique_start_of_its_name(tmp_path):
    by_name = subprocess.run(PROGRAM + ["scene", "fig3"], capture_output=True, text=True,
                             cwd=tmp_path)
    by_file = subprocess.run(PROGRAM + ["scene", str(ROOT / "data/scenes/fig3-plane-four-bar.toml")],
                             capture_output=True, text=True, cwd=tmp_path)
    assert by_name.returncode == 0, by_name.stderr
    assert by_name.stdout == by_file.stdout and by_name.stdout.startswith("Fig. 3  Plane")


@pytest.mark.parametrize("name, message", [
    ("fig1", "'fig1' names 3 scenes: fig1a-plane-four-bar, fig1b-spherical-four-bar, "
             "fig1c-skew-four-bar"),
    ("fig9", "'fig9' is neither a scene file nor the name of a scene of the program"),
    ("fig3.toml", "fig3.toml: cannot read the scene: No such file or directory"),
])
def test_a_name_that_is_not_one_scene_is_refused_with_the_reason(tmp_path, name, message):
    got = subprocess.run(PROGRAM + ["scene", name], capture_output=True, text=True, cwd=tmp_path)
    assert got.returncode == 1 and not got.stdout
    assert got.stderr.startswith(f"linkage.py: {message}")


def test_the_list_names_every_scene_with_its_title():
    got = subprocess.run(PROGRAM + ["scene", "--list"], capture_output=True, text=True)
    assert got.returncode == 0 and not got.stderr
    listed = [line.split(None, 1) for line in got.stdout.splitlines()]
    files = sorted((ROOT / "data" / "scenes").glob("*.toml"))
    assert [name for name, _ in listed] == [p.stem for p in files]
    for (_, title), path in zip(listed, files):
        assert f'title = "{title}"' in path.read_text()


def test_the_list_takes_no_scene_and_a_scene_is_needed_without_it():
    for argv, message in ((["--list", "fig3"], "--list takes no scene"),
                          ([], "give a scene")):
        got = subprocess.run(PROGRAM + ["scene", *argv], capture_output=True, text=True)
        assert got.returncode == 2 and message in got.stderr


CURVE_PNG = ["scene", "fig3", "--png", "fig3.png"]     # the README's (test_readme leaves it here)


def test_a_curve_scene_says_the_png_it_wrote(tmp_path):
    need("matplotlib", load=False)
    got = subprocess.run(PROGRAM + CURVE_PNG, capture_output=True, text=True, cwd=tmp_path)
    assert got.returncode == 0, got.stderr
    assert got.stderr == "linkage.py: wrote fig3.png\n" and (tmp_path / "fig3.png").exists()


def test_every_stored_png_is_drawn_by_its_scene_at_its_size():
    """The README's PNGs under data/scenes are each redrawn by support.make_scene_pngs from the
    scene beside it: none without its row and its scene, no row without its PNG, each at the size
    its row names (a PNG drawn some other way, or a scene renamed, fails here)."""
    stored = {png.stem for png in make_scene_snapshots.SCENES.glob("*.png")}
    assert stored == set(make_scene_pngs.PNG_OPTIONS)
    for name, options in make_scene_pngs.PNG_OPTIONS.items():
        size = [options[options.index("--size") + 1]] if "--size" in options else []
        assert (make_scene_snapshots.SCENES / f"{name}.toml").exists(), name
        data = (make_scene_snapshots.SCENES / f"{name}.png").read_bytes()
        width, height = struct.unpack(">II", data[16:24])
        assert size in ([], [f"{width}x{height}"]), (name, width, height)
