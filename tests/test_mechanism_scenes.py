"""The mechanism view from the command line: the Figs. 1-2 scenes, `scene FILE --svg`,
`--frames`, `design ... --svg/--text`, and what each refuses. The geometry itself is checked in
test_mechanism_geometry.py, the renderers in test_mechanism_text.py and test_mechanism_svg.py.
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

import linkage
from support.program import PROGRAM

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "data" / "scenes"
FIGURES_1_2 = sorted(SCENES.glob("fig[12]*.toml"))
SVG = "{http://www.w3.org/2000/svg}"


def run(argv):
    """linkage.main(argv) in this process: (status, standard output, standard error)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = linkage.main(argv)
    return status, out.getvalue(), err.getvalue()


def frames_of(svg_path):
    root = ET.parse(svg_path).getroot()
    return [g for g in root.iter(f"{SVG}g") if g.get("class") == "frame"]


def test_figures_1_and_2_are_the_five_linkages_lettered_as_the_paper_letters_them():
    scenes = [linkage.load_scene(str(p)) for p in FIGURES_1_2]
    assert [s.kind for s in scenes] == ["plane", "spherical", "skew", "slider",
                                             "skew-slider"]
    letters = {"plane": {"a", "b", "c", "d"}, "spherical": {"a", "b", "c", "d"},
               "skew": {"a", "b", "c", "d", "f", "ξ"}, "slider": {"b", "c*", "e"},
               "skew-slider": {"a", "b", "c", "f", "ξ"}}
    for scene in scenes:
        assert scene.draws_mechanism
        drawing = linkage.scene_drawing(scene)
        shown = {label.text for label in drawing.ground.labels}
        shown |= {label.text for label in drawing.frames[0].layer.labels}
        assert letters[scene.kind] <= shown, (scene.path, shown)
        assert all(f.message is None for f in drawing.frames), scene.path   # they turn fully


@pytest.mark.parametrize("path", FIGURES_1_2, ids=lambda p: p.stem)
def test_a_mechanism_scene_writes_an_animated_svg_and_no_dat_file(path, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(["scene", str(path), "--svg", "fig.svg"])
    assert status == 0, err
    assert out == "" and "wrote fig.svg (72 positions)" in err
    assert sorted(os.listdir(tmp_path)) == ["fig.svg"]              # no DAT file, no temporary
    assert len(frames_of(tmp_path / "fig.svg")) == 72


def test_piped_a_mechanism_scene_prints_one_still_frame_or_n(tmp_path):
    scene = str(SCENES / "fig1a-plane-four-bar.toml")
    status, one, err = run(["scene", scene])
    assert status == 0, err
    status, three, err = run(["scene", scene, "--frames", "3"])
    assert status == 0, err
    assert one.count("φ = ") + one.count("phi = ") == 1
    assert three.count("φ = ") + three.count("phi = ") == 3


def test_the_design_moves_with_its_design_positions_marked(tmp_path):
    """design --svg animates the whole motion (a full turn of this crank-rocker); each design
    position is drawn faint in the ground, its pins where the engine puts them, and numbered."""
    svg = tmp_path / "design.svg"
    argv = ["design", "fourb-fg3-1", "--phi", "45", "90", "135", "--psi", "95", "70", "60"]
    status, out, err = run(argv + ["--svg", str(svg)])
    assert status in (0, 3), err
    values = dict(line.split(" = ", 1) for line in out.splitlines())
    positions = [float(values[f"position{i}.phi"]) for i in (1, 2, 3)]
    frames = frames_of(svg)
    assert len(frames) == 72
    assert float(frames[0].get("data-phi")) == pytest.approx(positions[0])
    root = ET.parse(svg).getroot()
    ground = next(g for g in root.iter(f"{SVG}g") if g.get("class") == "ground")
    marked = [p for p in ground.iter(f"{SVG}polyline") if p.get("class") == "marked"]
    assert len(marked) == 3 * 3                                  # crank, coupler, output each
    scale = float(root.get("data-scale"))
    left, top = (float(v) for v in root.get("data-origin").split())
    link = linkage.Linkage("plane", **{k: float(values[k]) for k in "abcd"})
    for i, phi in enumerate(positions):
        pose = linkage.joint_positions(link, phi, int(values["branch"]))
        crank = [tuple(map(float, xy.split(","))) for xy in marked[3 * i].get("points").split()]
        assert crank[1] == pytest.approx((left + scale * pose.joints["A"][0],
                                          top - scale * pose.joints["A"][1]), abs=0.06)
    for frame in frames:                          # the numbers placed in every frame
        numbers = [t.text for t in frame.iter(f"{SVG}text") if t.text.isdigit()]
        assert sorted(numbers) == ["1", "2", "3"]
    status, text, err = run(argv + ["--text"])
    assert status in (0, 3), err
    assert text.startswith(out)                           # the design first, then its drawing
    assert text[len(out):].count("φ = ") + text[len(out):].count("phi = ") == 3


def test_displacement_only_scenes_compute_no_joint_position(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(linkage, "joint_positions", lambda *a: calls.append(a))
    status, _, err = run(["scene", str(SCENES / "fig3-plane-four-bar.toml"), "--dir",
                          str(tmp_path), "--text"])
    assert status == 0, err
    assert calls == []


MECHANISM_SCENE = """
mechanism = "plane"
dimensions = {{ {dims} }}
input = {{ from = 0, to = 360, step = {step} }}
branches = [1]
{extra}
[[panels]]
quantities = ["mechanism"]
{panel}
"""


def scene_file(tmp_path, dims="a = 6, b = 2, c = 7, d = 9", step=10, extra="", panel=""):
    path = tmp_path / "s.toml"
    path.write_text(MECHANISM_SCENE.format(dims=dims, step=step, extra=extra, panel=panel))
    return str(path)


@pytest.mark.parametrize("what, kwargs, options, fragments", [
    ("never assembles", dict(dims="a = 20, b = 1, c = 1, d = 1"), [],
     ["'dimensions'", "assembles at none"]),
    ("a zero-length link", dict(dims="a = 6, b = 0, c = 7, d = 9"), [],
     ["'dimensions'", "b = 0", "greater than 0"]),
    ("too many positions", dict(step=0.01), [], ["'input.step'", "3,600"]),
    ("no frames", {}, ["--frames", "0"], ["--frames 0", "1 to 3,600"]),
    ("a million frames", {}, ["--frames", "1000000"], ["--frames 1000000"]),
    ("another panel too", dict(panel='[[panels]]\nquantities = ["displacement"]'), [],
     ["'panels'", "a scene of its own"]),
    ("basic precision", dict(extra='precision = "basic"'), [], ["'precision'", "double"]),
    ("bad angles", dict(panel="angles = []"), [], ["'panels[1].angles'"]),
])
def test_a_bad_mechanism_scene_is_explained_and_writes_nothing(what, kwargs, options, fragments,
                                                               tmp_path):
    path = scene_file(tmp_path, **kwargs)
    out = tmp_path / "out"
    out.mkdir()
    result = subprocess.run(PROGRAM + ["scene", path, "--svg", str(out / "m.svg")] + options,
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 1, (what, result.stderr)
    assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1, what
    for fragment in fragments:
        assert fragment in result.stderr, (what, result.stderr)
    assert os.listdir(out) == [], what


def test_an_unwritable_svg_path_is_explained(tmp_path):
    path = scene_file(tmp_path)
    result = subprocess.run(PROGRAM + ["scene", path, "--svg", str(tmp_path / "no" / "m.svg")],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 1 and "Traceback" not in result.stderr
    assert "No such file or directory" in result.stderr and str(tmp_path / "no") in result.stderr
    os.chmod(tmp_path, 0o500)
    try:
        result = subprocess.run(PROGRAM + ["scene", path, "--svg", str(tmp_path / "m.svg")],
                                capture_output=True, text=True, timeout=60)
    finally:
        os.chmod(tmp_path, 0o700)
    if os.geteuid() != 0:                      # root writes anywhere
        assert result.returncode == 1 and "Permission denied" in result.stderr


def test_an_interrupted_svg_leaves_the_old_file(tmp_path, monkeypatch):
    target = tmp_path / "m.svg"
    target.write_text("old")

    def interrupted(drawing, *args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr(linkage, "svg_drawing", interrupted)
    status, _, err = run(["scene", scene_file(tmp_path), "--svg", str(target)])
    assert status == 130 and "interrupted" in err
    assert target.read_text() == "old"
    assert sorted(os.listdir(tmp_path)) == ["m.svg", "s.toml"]


def test_svg_and_frames_belong_to_mechanism_scenes(tmp_path):
    result = subprocess.run(PROGRAM + ["scene", str(SCENES / "fig3-plane-four-bar.toml"),
                                       "--svg", str(tmp_path / "x.svg")],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and "mechanism scene" in result.stderr
    assert os.listdir(tmp_path) == []


def test_the_readmes_svg_is_what_the_program_draws(tmp_path):
    """data/scenes/fig1c-skew-four-bar.svg, shown in the README, is the scene's --svg now (if
    a change to the drawing is intended: python3 linkage.py scene data/scenes/fig1c-skew-four-
    bar.toml --svg data/scenes/fig1c-skew-four-bar.svg)."""
    status, _, err = run(["scene", str(SCENES / "fig1c-skew-four-bar.toml"), "--svg",
                          str(tmp_path / "now.svg")])
    assert status == 0, err
    assert (tmp_path / "now.svg").read_bytes() == (SCENES / "fig1c-skew-four-bar.svg").read_bytes()


@pytest.mark.parametrize("kind, dims", [
    ("skew-slider", dict(a=-1.5, b=2.0, c=7.0, f=0.0, ksi=90.0)),    # the hard case skew-slider-ksi-90
    ("skew", dict(a=-3.0, b=0.5, c=1.5, d=3.0, f=3.0, ksi=30.0)),
])
def test_a_skew_linkage_with_a_negative_offset_is_drawn(kind, dims):
    """A skew linkage's a is the signed horizontal sector of the fixed link: a < 0 is drawn (the
    fixed link hatched from F0 to F1 = (a, 0, f), the pivots where joint_positions puts them);
    a = 0 has no fixed link to draw and is refused with the reason."""
    link = linkage.Linkage(kind, **dims)
    drawing = linkage.mechanism_drawing(link, [0.0, 90.0, 180.0, 270.0])
    placed = [f for f in drawing.frames if f.message is None]
    assert placed and "a" in [label.text for label in drawing.frames[0].layer.labels]
    f1 = linkage.project(kind, linkage.joint_positions(link, 0.0).joints["F1"])
    assert f1[0] != 0 or f1[1] != 0
    with pytest.raises(ValueError, match="needs a != 0"):
        linkage.mechanism_drawing(linkage.Linkage(kind, **{**dims, "a": 0.0}), [0.0])


def test_every_stroke_of_a_spherical_drawing_has_two_points_or_more():
    """An arc that crosses the sphere's rim is split there into its front and hidden parts; a
    part of one point is no stroke (it drew nothing, and a renderer may choke on it)."""
    import random
    rng = random.Random(1)
    strokes = 0
    for _ in range(60):
        a, b, c, d = (rng.uniform(5.0, 170.0) for _ in range(4))
        try:
            drawing = linkage.mechanism_drawing(linkage.Linkage("spherical", a=a, b=b, c=c, d=d),
                                                [15.0 * i for i in range(24)])
        except ValueError:
            continue
        for layer in [drawing.ground] + [frame.layer for frame in drawing.frames]:
            for stroke in layer.strokes:
                strokes += 1
                assert len(stroke.points) >= 2, (a, b, c, d, stroke)
    assert strokes > 1000
