"""Where the mechanism view puts its letters: in every frame
of the Figs. 1-2 scenes and of 200 random linkages of each kind (some with a coupler point), no
letter's box meets a joint's or pivot's mark, a link, a ground line or its hatching, or another
letter, and none leaves the page; in the terminal at 80 x 24 every letter is shown; no link crosses the slider's guide or a pivot's hatching but the link that turns about
that pivot. The geometry is worked out here from the Drawing's own items (its strokes, marks
and Drawing.letters, the size the SVG draws letters and marks at), not from the placing code.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from support import basic_runner
import linkage
from test_mechanism_geometry import LINKAGES

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

SCENES = basic_runner.ROOT / "data" / "scenes"
FIGURES_1_2 = sorted(SCENES.glob("fig[12]?-*.toml"))
SOLID = ("link", "ground", "hatch", "hidden")       # what a letter must not touch


def box_of(label, letters):
    """The label's box (left, bottom, right, top): its characters side by side, centred."""
    half_w, half_h = len(label.text) * letters.width / 2, letters.height / 2
    return (label.at[0] - half_w, label.at[1] - half_h, label.at[0] + half_w,
            label.at[1] + half_h)


def grown(box, by):
    return (box[0] - by, box[1] - by, box[2] + by, box[3] + by)


def segment_meets_box(p, q, box) -> bool:
    """Separating axes: the boxes' axes (the segment's bounding box against the box) and the
    segment's normal (all four corners strictly on one side of its line)."""
    if max(p[0], q[0]) < box[0] or min(p[0], q[0]) > box[2] or \
            max(p[1], q[1]) < box[1] or min(p[1], q[1]) > box[3]:
        return False
    sides = [(q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0])
             for x in (box[0], box[2]) for y in (box[1], box[3])]
    return not (all(s > 0 for s in sides) or all(s < 0 for s in sides))


def distance_to_box(point, box) -> float:
    dx = max(box[0] - point[0], 0.0, point[0] - box[2])
    dy = max(box[1] - point[1], 0.0, point[1] - box[3])
    return math.hypot(dx, dy)


def covered_letters(drawing, frame) -> list[str]:
    """Every letter of the frame that something covers, said as 'letter: what'."""
    letters = drawing.letters
    marks = drawing.ground.marks + frame.layer.marks
    strokes = [s for s in drawing.ground.strokes + frame.layer.strokes if s.style in SOLID]
    labels = drawing.ground.labels + frame.layer.labels
    found = []
    for i, label in enumerate(labels):
        box = box_of(label, letters)
        x0, y0, x1, y1 = drawing.bounds
        if box[0] < x0 or box[1] < y0 or box[2] > x1 or box[3] > y1:
            found.append(f"{label.text}: off the page")
        found += [f"{label.text}: on the mark of {m.name}" for m in marks
                  if distance_to_box(m.at, box) < letters.mark]
        wide = grown(box, letters.line)                # a line is drawn 2 * line wide
        found += [f"{label.text}: on a {s.style} stroke" for s in strokes
                  if any(segment_meets_box(p, q, wide) for p, q in zip(s.points, s.points[1:]))]
        for other in labels[i + 1:]:
            b = box_of(other, letters)
            if box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3]:
                found.append(f"{label.text}: on the letter {other.text}")
    return found


def check_letters(drawing, where) -> None:
    bad = [f"{where} phi={f.pose.phi:g}: {what}" for f in drawing.frames
           for what in covered_letters(drawing, f)]
    assert not bad, "\n".join(bad[:20]) + f"\n({len(bad)} in all)"


def drawn_area(text: str) -> str:
    """The terminal frame less its two title lines and its caption."""
    return "\n".join(text.splitlines()[2:-1])


def check_terminal(drawing, index, where, width=80, height=24) -> None:
    """Every letter of frame `index` is in its terminal frame (Unicode and ASCII) as often as
    the drawing has it: none drawn over by a mark (marks are drawn last) or another letter."""
    frame = drawing.frames[index]
    texts = [label.text for label in drawing.ground.labels + frame.layer.labels]
    for unicode in (True, False):
        area = drawn_area(linkage.text_drawing(drawing, index, width, height, unicode))
        for text in set(texts):
            shown = linkage._plain(text, unicode)
            assert area.count(shown) >= texts.count(text), \
                f"{where} phi={frame.pose.phi:g} {'Unicode' if unicode else 'ASCII'}: " \
                f"{shown!r} lost\n{area}"


@pytest.mark.parametrize("scene", FIGURES_1_2, ids=lambda p: p.stem)
def test_no_letter_is_covered_in_any_frame_of_figures_1_and_2(scene):
    drawing = linkage.scene_drawing(linkage.load_scene(str(scene)))
    assert len(drawing.frames) == 72
    check_letters(drawing, scene.stem)


@pytest.mark.parametrize("scene", FIGURES_1_2, ids=lambda p: p.stem)
def test_every_letter_and_mark_is_in_each_terminal_frame_at_80_by_24(scene):
    drawing = linkage.scene_drawing(linkage.load_scene(str(scene)))
    for index in range(len(drawing.frames)):
        check_terminal(drawing, index, scene.stem)


@pytest.mark.parametrize("scene", FIGURES_1_2, ids=lambda p: p.stem)
def test_the_terminal_snapshots_have_every_letter(scene):
    """The stored 80 x 24 frames (data/scenes/snapshots, the first frame) show every letter
    the paper gives the linkage."""
    from support import make_scene_snapshots
    letters = {"plane": "abcd", "spherical": "abcd", "skew": "abcdfgξ", "slider": "be",
               "skew-slider": "abcfξ"}[linkage.load_scene(str(scene)).kind]
    for encoding in ("utf-8", "ascii"):
        area = drawn_area(make_scene_snapshots.snapshot_path(scene, encoding).read_text(
            encoding=encoding))
        for letter in letters:
            assert linkage._plain(letter, encoding == "utf-8") in area, (scene.stem, encoding,
                                                                          letter)
        assert "c*" in area or "c" in letters


def pivots_of(stroke, marks, reach):
    """The pivots within `reach` of either end of a stroke: where a link turns."""
    return {m.name for m in marks if m.kind == "pivot"
            for end in (stroke.points[0], stroke.points[-1]) if math.dist(end, m.at) <= reach}


@pytest.mark.parametrize("scene", FIGURES_1_2, ids=lambda p: p.stem)
def test_links_keep_off_the_hatching(scene):
    """No link (the block included) crosses the slider's guide or its hatching. A pivot's
    hatching is crossed by the link turning about it (a crank that turns fully crosses any side
    of it), and a crank-rocker's coupler sweeps across the crank's pivot at the folded position
    whichever side the hatching is on: other links cross a pivot's hatching in at most 5 of the
    72 frames, and never in the still frame (the first, phi = 30)."""
    drawing = linkage.scene_drawing(linkage.load_scene(str(scene)))
    reach = 2.5 * drawing.size
    hatches = [s for s in drawing.ground.strokes if s.style == "hatch"]
    crossed = {}
    for frame in drawing.frames:
        for link in (s for s in frame.layer.strokes if s.style in ("link", "hidden")):
            turns_at = pivots_of(link, drawing.ground.marks, 1e-9)
            for hatch in hatches:
                near = pivots_of(hatch, drawing.ground.marks, reach)
                if any(crosses(p, q, *hatch.points) for p, q in zip(link.points, link.points[1:])) \
                        and not near & turns_at:
                    crossed.setdefault(" ".join(sorted(near)) or "the guide", set()).add(
                        frame.pose.phi)
    assert "the guide" not in crossed, sorted(crossed["the guide"])
    for pivots, phis in crossed.items():
        assert len(phis) <= 5 and drawing.frames[0].pose.phi not in phis, (pivots, sorted(phis))


def crosses(p, q, r, s, tol=1e-9) -> bool:
    """Whether segments p q and r s cross: each one's ends more than tol (relative to its
    length) on both sides of the other's line; touching is not crossing."""
    def side(a, b, c):                     # c's distance from the line a b, over |a b|
        return ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / (
            math.dist(a, b) ** 2 or 1.0)
    return all(min(side(a, b, c), side(a, b, d)) < -tol < tol < max(side(a, b, c), side(a, b, d))
               for a, b, c, d in ((p, q, r, s), (r, s, p, q)))


# ---- random linkages -------------------------------------------------------------------------

def coupler_point(kind, dims, fu, fv):
    """A point on the coupler: u, v a fraction of its length (of a half turn on the sphere)."""
    reach = 180.0 if kind == "spherical" else dims["c"]
    return fu * reach, 0.0 if kind in ("skew", "skew-slider") else fv * reach


DRAWS = 60


@pytest.mark.parametrize("kind", list(LINKAGES))
def test_no_letter_is_covered_on_random_linkages(kind):
    """DRAWS linkages of the kind, each drawn at 12 angles 30 degrees apart from a random start,
    one in two with a coupler point; each frame's letters uncovered, and on the terminal (one
    frame a linkage, 80 x 24) every letter shown. At least a third of the draws must be
    drawn with the linkage assembled in some frame, so that the check is not empty (random
    spherical linkages assemble about half the time)."""
    drawn = []

    @settings(max_examples=DRAWS, derandomize=True, deadline=None,
              suppress_health_check=list(HealthCheck), database=None)
    @given(LINKAGES[kind], st.floats(0.0, 360.0), st.booleans(), st.floats(-1.0, 1.0),
           st.floats(-1.0, 1.0))
    def check(dims, start, with_point, fu, fv):
        link = linkage.Linkage(kind, **dims)
        point = coupler_point(kind, dims, fu, fv) if with_point else None
        try:
            drawing = linkage.mechanism_drawing(link, [start + 30.0 * k for k in range(12)],
                                                coupler=point)
        except ValueError:
            return
        where = f"{kind} {dims} coupler={point}"
        check_letters(drawing, where)
        shown = [i for i, f in enumerate(drawing.frames) if f.message is None]
        if shown:
            drawn.append(where)
            check_terminal(drawing, shown[len(shown) // 2], where)

    check()
    assert len(drawn) >= DRAWS // 3, len(drawn)
