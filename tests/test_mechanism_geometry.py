"""Where joint_positions puts the joints, checked from first principles: every link
between its joints has its length, every revolute joint turns about its axis, spherical joints
lie on the unit sphere, the slider on its line, and the output link's angle (the slider's
position) measured from the joints is the engine's psi (x). The frames are those of
tests/test_physics.py (the listing's coefficients imply them); the angles are measured here with
geometric definitions (cross products of the joints and axes), not with joint_positions' own
formulas. Hypothesis draws 1,000 linkages of each kind, each at 4 angles on both branches;
a fixed table holds the paper's and the hard cases' linkages."""

from __future__ import annotations

import math
import tomllib

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from support import basic_runner
import linkage
from test_physics import CASES

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

LENGTH_TOL = 1e-12      # |measured - dimension|, relative to the linkage's largest length
ANGLE_TOL = 1e-9        # degrees, the output angle measured from the joints against the engine's


def sub(p, q):
    return tuple(a - b for a, b in zip(p, q))


def dot(u, v):
    return sum(a * b for a, b in zip(u, v))


def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def norm(v):
    return math.sqrt(dot(v, v))


def unit(v):
    return tuple(c / norm(v) for c in v)


def angle_about(v, e1, e2):
    """The angle (degrees) of v in the plane of the orthonormal e1, e2, from e1 toward e2."""
    return math.degrees(math.atan2(dot(v, e2), dot(v, e1)))


def angle_difference(x, y):
    return abs((x - y + 180.0) % 360.0 - 180.0)


def problems(kind, dims, phi, branch):
    """Everything wrong with the joints of one pose, as readable lines (empty when right)."""
    link = linkage.Linkage(kind, **dims)
    pose = linkage.joint_positions(link, phi, branch)
    motion = link.motion(phi, branch, 0)
    j, axes = pose.joints, pose.axes
    scale = max(abs(v) for k, v in dims.items() if k != "ksi") if kind != "spherical" else 1.0
    out = []

    def length(p, q, want, what):
        got = norm(sub(j[p], j[q]))
        if abs(got - want) > LENGTH_TOL * scale:
            out.append(f"{what} |{p}{q}| = {got!r}, want {want!r}")

    def zero(value, what, tol=LENGTH_TOL * scale):
        if abs(value) > tol:
            out.append(f"{what}: {value!r}, want 0")

    def output_angle(got):
        if angle_difference(got, motion.output) > ANGLE_TOL:
            out.append(f"the output angle from the joints is {got!r}, "
                       f"the engine's {motion.output!r}")

    for name, (point, direction) in axes.items():
        zero(norm(direction) - 1.0, f"axis {name} is not a unit vector", 1e-15)
    assembled = motion.status in (linkage.ASSEMBLED, linkage.DEAD_CENTRE, linkage.CHANGE_POINT)
    output_joint = "C" if link.is_slider else "B"
    if (output_joint in j) != assembled or pose.status != motion.status:
        out.append(f"status {motion.status} but joints {sorted(j)}")
        return out
    z = (0.0, 0.0, 1.0)
    if kind == "spherical":
        rad = {k: math.radians(dims[k]) for k in "abcd"}
        for name in j:
            zero(norm(j[name]) - (0.0 if name == "O" else 1.0), f"{name} off the unit sphere")
        for p, q, k in (("A0", "A", "b"), ("A", "B", "c"), ("B", "B0", "d"), ("A0", "B0", "a")):
            if p in j and q in j:
                zero(dot(j[p], j[q]) - math.cos(rad[k]), f"arc {p}{q} is not {k}")
        zero(norm(sub(axes["input"][1], j["A0"])) + norm(sub(axes["output"][1], j["B0"])),
             "the shafts do not pass through A0 and B0")
        e2 = unit(cross(j["A0"], j["B0"]))             # normal to the fixed link's plane
        if abs(math.sin(rad["b"])) > 1e-9 and \
                angle_difference(angle_about(j["A"], cross(e2, j["A0"]), e2), phi) > ANGLE_TOL:
            out.append("the crank is not at phi about the input axis")
        if "B" in j:
            output_angle(angle_about(j["B"], cross(e2, j["B0"]), e2))
        return out
    a0, a = j["A0"], j["A"]
    length("A0", "A", dims["b"], "the crank b")
    zero(dot(sub(a, a0), axes["input"][1]), "the crank is not square to the input axis")
    zero(norm(cross(sub(a0, axes["input"][0]), axes["input"][1])), "A0 off the input axis")
    if kind in ("plane", "slider"):
        for name in j:
            zero(j[name][2], f"{name} out of the plane")
    if kind == "plane":
        length("A0", "B0", dims["a"], "the fixed link a")
        e1 = unit(sub(j["B0"], a0))
        e2 = cross(z, e1)
        if angle_difference(angle_about(sub(a, a0), e1, e2), phi) > ANGLE_TOL:
            out.append("the crank is not at phi from the fixed link")
        if "B" in j:
            length("A", "B", dims["c"], "the coupler c")
            length("B0", "B", dims["d"], "the output crank d")
            output_angle(angle_about(sub(j["B"], j["B0"]), e1, e2))
    elif kind == "slider":
        point, direction = axes["guide"]
        zero(point[1] - dims["e"], "the guide is not at the offset e")
        zero(abs(direction[0]) - 1.0, "the guide is not parallel to x")
        if "C" in j:
            length("A", "C", dims["c"], "the rod c")
            zero(norm(cross(sub(j["C"], point), direction)), "the slider is off its guide")
            if abs(dot(sub(j["C"], (0.0, dims["e"], 0.0)), (1.0, 0.0, 0.0)) - motion.output) \
                    > LENGTH_TOL * scale:
                out.append("the slider is not at the engine's x")
    else:
        out += skew_problems(kind, dims, phi, pose, motion, scale)
    return out


def skew_problems(kind, dims, phi, pose, motion, scale):
    """The skew linkages: the common perpendicular F0 F1 (length a) square to both shafts and
    meeting the input shaft f above the crank's plane, the shafts at ksi, the output crank d (or
    the slider) on the output shaft (the guide)."""
    j, axes, out = pose.joints, pose.axes, []
    cos_ksi = math.cos(math.radians(dims["ksi"]))
    z = axes["input"][1]
    shaft = "output" if kind == "skew" else "guide"
    point, w = axes[shaft]
    f0, f1 = j["F0"], j["F1"]
    perpendicular = sub(f1, f0)
    checks = [(norm(perpendicular) - abs(dims["a"]), "|F0 F1| is not |a|"),
              (dot(perpendicular, z), "F0 F1 is not square to the input shaft"),
              (dot(perpendicular, w), f"F0 F1 is not square to the {shaft}"),
              (norm(sub(f0, j["A0"])) - abs(dims["f"]), "|A0 F0| is not f"),
              (norm(cross(sub(f0, j["A0"]), z)), "F0 is off the input shaft"),
              (norm(cross(sub(f1, point), w)), f"F1 is off the {shaft}"),
              (abs(dot(z, w)) - abs(cos_ksi), f"the {shaft} is not at ksi to the input shaft")]
    e1 = tuple(math.copysign(1.0, dims["a"]) * c for c in unit(perpendicular)) if dims["a"] \
        else (1.0, 0.0, 0.0)                       # the frame's x: F0 to F1 when a > 0
    if angle_difference(angle_about(sub(j["A"], j["A0"]), e1, cross(z, e1)), phi) > ANGLE_TOL:
        out.append("the crank is not at phi from the common perpendicular")
    if kind == "skew":
        b0 = j["B0"]
        checks += [(norm(cross(sub(b0, f1), w)), "B0 is off the output shaft"),
                   (b0[2], "B0 is not in the crank's plane z = 0")]
        if "B" in j:
            checks += [(norm(sub(j["B"], b0)) - dims["d"], "|B0 B| is not d"),
                       (dot(sub(j["B"], b0), w), "the output crank is not square to its shaft"),
                       (norm(sub(j["B"], j["A"])) - dims["c"], "|A B| is not c")]
            psi = angle_about(sub(j["B"], b0), e1, cross(w, e1))
            if angle_difference(psi, motion.output) > ANGLE_TOL:
                out.append(f"psi from the joints {psi!r}, the engine's {motion.output!r}")
    elif "C" in j:
        checks += [(norm(cross(sub(j["C"], f1), w)), "the slider is off its guide"),
                   (norm(sub(j["C"], j["A"])) - dims["c"], "|A C| is not c"),
                   (dot(sub(j["C"], f1), w) - motion.output, "the slider is not at x")]
    out += [f"{what}: off by {value!r}" for value, what in checks
            if abs(value) > LENGTH_TOL * scale]
    return out


# ---- hypothesis: random linkages -------------------------------------------------------------

length = st.floats(0.1, 10.0)
offset = st.floats(-5.0, 5.0)
arc = st.floats(5.0, 175.0)
ksi = st.floats(-75.0, 75.0)
LINKAGES = {
    "plane": st.fixed_dictionaries(dict(a=length, b=length, c=length, d=length)),
    "spherical": st.fixed_dictionaries(dict(a=arc, b=arc, c=arc, d=arc)),
    "skew": st.fixed_dictionaries(dict(a=length, b=length, c=length, d=length, f=offset,
                                       ksi=ksi)),
    "slider": st.fixed_dictionaries(dict(b=length, c=length, e=offset)),
    "skew-slider": st.fixed_dictionaries(dict(a=length, b=length, c=length, f=offset, ksi=ksi)),
}
DRAWS = 150


@pytest.mark.parametrize("kind", list(LINKAGES))
def test_random_linkages_hold_together(kind):
    """DRAWS linkages, each at 4 angles 90 degrees apart from a random start, on both branches;
    at least a third of the draws must assemble somewhere, so that the checks are not empty."""
    assembled = []

    @settings(max_examples=DRAWS, derandomize=True, deadline=None,
              suppress_health_check=list(HealthCheck), database=None)
    @given(LINKAGES[kind], st.floats(-720.0, 720.0))
    def check(dims, start):
        count = 0
        for branch in (1, 2):
            for k in range(4):
                phi = start + 90.0 * k
                found = problems(kind, dims, phi, branch)
                assert not found, f"{kind} {dims} phi={phi!r} branch {branch}: {found}"
                count += linkage.Linkage(kind, **dims).motion(phi, branch, 0).output is not None
        assembled.append(count > 0)

    check()
    assert len(assembled) >= DRAWS and sum(assembled) >= DRAWS / 3, (len(assembled),
                                                                       sum(assembled))


# ---- a fixed table: the paper's linkages and the hard cases -----------------------------------

def table():
    rows = [(f"example-{kind}", kind, dims) for kind, dims in linkage.MECHANISM_EXAMPLES.items()]
    rows += [(name, kind, dims) for name, (kind, dims) in CASES.items()]
    hard = tomllib.loads((basic_runner.ROOT / "data" / "hard_cases.toml").read_text())
    rows += [(case["name"], case["kind"], case["dims"]) for case in hard["case"]]
    return rows


TABLE = table()


@pytest.mark.parametrize("name, kind, dims", TABLE, ids=[row[0] for row in TABLE])
def test_the_table_holds_together(name, kind, dims):
    dims = {k: float(v) for k, v in dims.items()}
    found = [f"phi={phi} branch {branch}: {p}" for branch in (1, 2)
             for phi in [float(x) for x in range(-180, 541, 30)] + [179.999999, 1e-9]
             for p in problems(kind, dims, phi, branch)]
    assert not found, found[:5]


def test_the_marks_are_the_projected_joints():
    """Each frame's joint marks stand where project() puts joint_positions' joints."""
    for kind, dims in linkage.MECHANISM_EXAMPLES.items():
        link = linkage.Linkage(kind, **dims)
        drawing = linkage.mechanism_drawing(link, [0.0, 100.0, 250.0])
        for frame in drawing.frames:
            pose = linkage.joint_positions(link, frame.pose.phi)
            for mark in frame.layer.marks + drawing.ground.marks:
                assert mark.at == pytest.approx(linkage.project(kind, pose.joints[mark.name]),
                                                abs=1e-12), (kind, mark)
