"""The mechanism as an animated SVG, as a PNG and as a DXF. The SVG is read back with
xml.etree: its frames, which one shows without animation, the SMIL that plays them, and the
joints of two frames against joint_positions; the PNG is decoded and its pixels counted; the DXF
is read back with ezdxf and its links measured against the linkage's lengths."""

from __future__ import annotations

import math
import sys
import xml.etree.ElementTree as ET

import pytest

import linkage
from support.peers import Peer
from test_scenes import png_pixels

ezdxf = Peer("ezdxf")

SVG = "{http://www.w3.org/2000/svg}"
ANGLES = [float(a) for a in range(0, 360, 30)]


def parsed(drawing, **options):
    return ET.fromstring(linkage.svg_drawing(drawing, **options))


def frames(root):
    return [g for g in root.iter(f"{SVG}g") if g.get("class") == "frame"]


def joints_of(frame):
    return {c.get("data-joint"): (float(c.get("cx")), float(c.get("cy")))
            for c in frame.iter(f"{SVG}circle")}


def texts(element, cls):
    return ["".join(t.itertext()) for t in element.iter(f"{SVG}text") if t.get("class") == cls]


@pytest.mark.parametrize("kind", list(linkage.MECHANISM_EXAMPLES))
def test_each_frame_puts_the_joints_where_the_engine_says(kind):
    """Two frames' moving joints, in SVG pixels, against the kind's projection of
    joint_positions: svg = origin + scale (x, -y), to the file's 0.1 pixel."""
    link = linkage.Linkage(kind, **linkage.MECHANISM_EXAMPLES[kind])
    root = parsed(linkage.mechanism_drawing(link, ANGLES))
    assert root.get("data-kind") == kind
    groups = frames(root)
    assert [float(g.get("data-phi")) for g in groups] == ANGLES
    scale = float(root.get("data-scale"))
    left, top = map(float, root.get("data-origin").split())
    for index in (1, 7):
        pose = linkage.joint_positions(link, ANGLES[index])
        drawn = joints_of(groups[index])
        want = ("A", "C") if link.is_slider else ("A", "B")
        assert sorted(drawn) == sorted(want)
        for name in want:
            x, y = linkage.project(kind, pose.joints[name])
            assert drawn[name] == pytest.approx((left + scale * x, top - scale * y), abs=0.051)
    assert {c.get("data-joint") for c in root.find(f"{SVG}g[@class='ground']").iter(
        f"{SVG}circle")} >= {"A0"}


def test_the_frames_play_in_turn_and_one_shows_without_animation():
    drawing = linkage.mechanism_drawing(linkage.Linkage("plane", a=6, b=2, c=7, d=9), ANGLES)
    groups = frames(parsed(drawing, seconds_per_frame=0.5))
    assert [g.get("visibility") for g in groups] == ["visible"] + ["hidden"] * 11
    for i, g in enumerate(groups):
        (animate,) = g.findall(f"{SVG}animate")
        assert animate.get("attributeName") == "visibility"
        assert animate.get("calcMode") == "discrete" and animate.get("dur") == "6s"
        assert animate.get("repeatCount") == "indefinite"
        values = animate.get("values").split(";")
        times = [float(t) for t in animate.get("keyTimes").split(";")]
        # visible exactly from i/12 to (i + 1)/12 of the turn
        visible = [t for t, v in zip(times, values) if v == "visible"]
        assert visible == pytest.approx([i / 12], abs=1e-6)
        after = times[values.index("visible") + 1]
        assert after == pytest.approx((i + 1) / 12, abs=1e-6)
        assert times[0] == 0


def test_a_position_that_does_not_exist_is_said_and_not_drawn():
    """a=6 b=2 c=3 d=2 closes at phi = 0 and not at 180 (|A B0| = 8 > c + d): that frame says
    so, draws the crank alone; without animation the first frame shows."""
    drawing = linkage.mechanism_drawing(linkage.Linkage("plane", a=6, b=2, c=3, d=2),
                                        [180.0, 0.0])
    groups = frames(parsed(drawing))
    assert texts(groups[0], "message") == ["not assembled at φ = 180°"]
    assert sorted(joints_of(groups[0])) == ["A"]
    assert texts(groups[1], "message") == [] and sorted(joints_of(groups[1])) == ["A", "B"]
    assert [g.get("visibility") for g in groups] == ["hidden", "visible"]


def test_text_is_escaped_and_captions_are_kept():
    drawing = linkage.mechanism_drawing(linkage.Linkage("slider", b=2, c=7, e=1.5), [10.0],
                                        title='a <b> & "c"', subtitle="x < y")
    root = parsed(drawing)
    assert root.find(f"{SVG}title").text == 'a <b> & "c"'
    assert texts(root, "subtitle") == ["x < y"]
    (group,) = frames(root)
    (caption,) = texts(group, "caption")
    assert caption.startswith("φ = 10°  x = ")
    assert group.find(f"{SVG}animate") is None                  # one frame: nothing to play


def grey_pixels(data):
    width, height, channels, rows = png_pixels(data)
    return [row[i:i + 3] for row in rows for i in range(0, len(row), channels)], width, height


@pytest.mark.slow          # --quick leaves it out: renders PNGs
@pytest.mark.parametrize("kind, count, positions", [("skew", 12, 6), ("spherical", 12, 6),
                                                     ("slider", 3, 12)])
def test_the_png_overlays_the_positions(kind, count, positions):
    """Mostly white; black (the last position) and the blue of the shaft axes (the slider's: its
    line of centres); the earlier positions faint: many more light greys than in the PNG of the
    last position alone. A drawing of fewer frames than `positions` shows them all."""
    link = linkage.Linkage(kind, **linkage.MECHANISM_EXAMPLES[kind])
    drawing = linkage.mechanism_drawing(link, ANGLES[:count])
    data = linkage.png_drawing(drawing, positions=positions)
    assert data.startswith(b"\x89PNG\r\n\x1a\n")
    pixels, width, height = grey_pixels(data)
    assert width == 800 and 300 <= height <= 1000
    assert sum(p == b"\xff\xff\xff" for p in pixels) / len(pixels) > 0.8
    assert sum(max(p) < 60 for p in pixels) > 1500, "no solid last position"
    assert sum(p[2] > 150 and p[0] < 100 for p in pixels) > 200, "no blue axis"
    alone = linkage.png_drawing(drawing._replace(frames=drawing.frames[-1:]), positions=1)

    def light(pixels):
        return sum(150 < p[0] == p[1] == p[2] < 235 for p in pixels)
    assert light(pixels) > light(grey_pixels(alone)[0]) + 1000 * (min(count, positions) - 1), \
        "no faint positions"


# -- the DXF, read back ---------------------------------------------------------------------------

def dxf_of(tmp_path, *argv):
    out = tmp_path / "out.dxf"
    assert linkage.main([*argv, "--dxf", str(out)]) == 0
    doc = ezdxf.readfile(str(out))
    by_layer = {}
    for entity in doc.modelspace():
        by_layer.setdefault(entity.dxf.layer, []).append(entity)
    return by_layer


def runs(entity):
    """An entity's vertices (a LINE's two ends, a 3-D POLYLINE's points)."""
    if entity.dxftype() == "LINE":
        return [tuple(entity.dxf.start), tuple(entity.dxf.end)]
    return [tuple(v.dxf.location) for v in entity.vertices]


def length(points, sphere=False):
    """A link's length: the distance between its ends, or on the unit sphere its arc in degrees
    (the polyline's own length, which is the arc's chord sum, near the great circle's)."""
    if sphere:
        return math.degrees(sum(math.dist(p, q) for p, q in zip(points, points[1:])))
    return math.dist(points[0], points[-1])


@pytest.mark.parametrize("scene, kind, links, tolerance", [
    ("coupler-plane-four-bar", "plane", {"b": 2, "c": 7, "d": 9}, 1e-9),
    ("coupler-skew-four-bar", "skew", {"b": 1.5, "c": 4, "d": 2.5}, 1e-9),
    ("coupler-spherical-four-bar", "spherical", {"b": 20, "c": 75, "d": 60}, 0.02),
    ("coupler-plane-slider-crank", "slider", {"b": 2, "c": 7}, 1e-9)])
def test_the_dxf_holds_the_linkage_at_its_true_lengths(scene, kind, links, tolerance, tmp_path):
    """Every position's moving links, measured in the file ezdxf reads back, have the linkage's
    lengths (the spherical one's arcs, in degrees, on the unit sphere: every vertex at radius 1);
    12 positions a layer each; the fixed link; the coupler curve's points in the plane kinds'
    plane z = 0."""
    layers = dxf_of(tmp_path, "scene", scene)
    positions = sorted(name for name in layers if name.startswith("POSITION_"))
    assert len(positions) == 12, sorted(layers)
    sphere = kind == "spherical"
    for name in positions:
        measured = sorted(length(runs(e), sphere) for e in layers[name]
                          if e.dxftype() in ("LINE", "POLYLINE"))
        assert measured == pytest.approx(sorted(links.values()), abs=tolerance), (name, measured)
        texts = [e.dxf.text for e in layers[name] if e.dxftype() == "TEXT"]
        assert len(texts) == 1 and texts[0].startswith("phi = ")
        if sphere:
            for e in layers[name]:
                if e.dxftype() == "POLYLINE":
                    assert all(abs(math.dist(p, (0, 0, 0)) - 1) < 1e-9 for p in runs(e))
    assert "GROUND" in layers or kind == "slider"
    curve = [p for e in layers.get("COUPLER_CURVE", []) for p in runs(e)]
    assert len(curve) > 50
    if kind in ("plane", "slider"):
        assert all(p[2] == 0 for p in curve)


def test_the_plane_ground_is_a_from_a0_to_b0(tmp_path):
    layers = dxf_of(tmp_path, "design", "fourb-cr-4", "--psi", "60", "--mu-min", "40")
    (ground,) = layers["GROUND"]
    start, end = runs(ground)
    assert start == (0, 0, 0) and end[1:] == (0, 0) and end[0] > 0


def test_without_ezdxf_dxf_says_how_to_install_it_and_writes_nothing(tmp_path, monkeypatch,
                                                                     capsys):
    monkeypatch.setitem(sys.modules, "ezdxf", None)          # import ezdxf fails
    out = tmp_path / "x.dxf"
    assert linkage.main(["scene", "fig1a", "--dxf", str(out)]) == 1
    assert "python3 -m pip install ezdxf" in capsys.readouterr().err
    assert not out.exists()
