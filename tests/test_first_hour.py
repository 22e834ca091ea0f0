"""An engineer's first hour (issue 34): every letter defined where it is first met - the README's
first example and each command's --help - the conventions in one README table, one word a thing
(issue 33: `kind`, `class`), design's ratios under names that cannot be taken for run's lengths,
and the listing's reasons beside its corrections."""

from __future__ import annotations

import contextlib
import io
import math
import os
import random
import re
import shlex

import pytest

import linkage
from support.basic_runner import ROOT
from support.peers import need

README = (ROOT / "README.md").read_text(encoding="utf-8")
# what each letter of run's dimensions is, in the words a definition must use
ROLES = {"a": "fixed link", "b": "input crank", "c": "coupler", "d": "output crank",
         "e": "offset", "f": "vertical sector", "ksi": "skew angle"}


def help_text(*argv: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit) as done:
        linkage.main([*argv, "--help"])
    assert done.value.code == 0
    return " ".join(out.getvalue().split())          # argparse's wrapping undone


def test_the_readme_defines_the_letters_of_its_first_example():
    """The first `--a` the README shows has a, b, c, d defined within a few lines of it (before
    this, "a is the fixed link" came some 400 lines further down)."""
    lines = README.splitlines()
    first = next(i for i, line in enumerate(lines) if "--a " in line)
    near = " ".join(" ".join(lines[max(0, first - 12):first + 12]).split()).replace("**", "")
    for letter in "abcd":
        assert re.search(rf"\b{letter}\b[^.;]*?{ROLES[letter]}", near), (letter, near)


@pytest.mark.parametrize("command", ["run", "analyse"])
@pytest.mark.parametrize("kind", list(linkage.KIND_MENU))
def test_the_help_of_a_command_that_takes_dimensions_defines_each_kinds_letters(command, kind):
    """`run --help` and `analyse --help` say, for each kind, which letters it takes and what each
    is (before: `plane: --b --c --d --a`, the letters alone), and each option defines its letter."""
    text = help_text(command)
    said = re.search(rf"\b{re.escape(kind)}: (.*?)[;.](?: |$)", text)
    assert said, (kind, text)
    for letter in linkage.KIND_MENU[kind][1]:
        assert re.search(rf"--{letter} [^,]*{ROLES[letter]}", said.group(1)), (kind, letter)
        assert re.search(rf"--{letter} X {letter}, [^-]*{ROLES[letter]}", text), letter


# -- the README's conventions, held to the engine by the geometry they state ---------------------

def _sub(p, q):
    return [x - y for x, y in zip(p, q)]


def _dot(p, q):
    return sum(x * y for x, y in zip(p, q))


def _cross(p, q):
    return [p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]]


def _cs(degrees):
    return math.cos(math.radians(degrees)), math.sin(math.radians(degrees))


def conventions(kind, dims, phi, out):
    """The pins as the README's Conventions table writes them: (A, the output pin, the loop's
    error - |A P| - c, or cos of the arc AP - cos c - and the branch-1 side, > 0 on branch 1)."""
    cp, sp = _cs(phi)
    if kind == "spherical":
        cb, sb = _cs(dims["b"])
        ca, sa = _cs(dims["a"])
        cd, sd = _cs(dims["d"])
        cq, sq = _cs(out)
        a = [sb * cp, sb * sp, cb]
        u = [sd * cq, sd * sq, cd]                                   # then turned by a about y
        b = [ca * u[0] + sa * u[2], u[1], -sa * u[0] + ca * u[2]]
        b0 = [sa, 0.0, ca]
        return _dot(a, b) - _cs(dims["c"])[0], -_dot(_cross(a, b0), b)
    a = [dims["b"] * cp, dims["b"] * sp, 0.0]
    if kind == "plane":
        cq, sq = _cs(out)
        b0, p, w = [dims["a"], 0.0, 0.0], [dims["a"] + dims["d"] * cq, dims["d"] * sq, 0.0], None
        side = -_cross(_sub(b0, a), _sub(p, a))[2]                  # right of A -> B0
    elif kind == "skew":
        cq, sq = _cs(out)
        cx, sx = _cs(dims["ksi"])
        b0 = [dims["a"], dims["f"] * sx / cx, 0.0]
        w = [0.0, -sx, cx]
        p = [b0[0] + dims["d"] * cq, b0[1] + dims["d"] * sq * cx, dims["d"] * sq * sx]
        side = _dot(_cross(_sub(b0, a), w), _sub(p, a))
    elif kind == "slider":
        p = [out, dims["e"], 0.0]
        side = out - a[0]                                            # ahead of the crank pin
    else:
        cx, sx = _cs(dims["ksi"])
        f1, g = [dims["a"], 0.0, dims["f"]], [0.0, sx, -cx]
        p = [dims["a"], out * sx, dims["f"] - out * cx]
        side = out - _dot(_sub(a, f1), g)                            # ahead of A's foot
    return math.dist(a, p) - dims["c"], side


@pytest.mark.parametrize("kind", list(linkage.KIND_MENU))
def test_the_readmes_conventions_close_each_loop_and_name_its_branches(kind):
    """With the output the engine gives, the pins placed as the Conventions table says close the
    loop (to 1e-9), and branch 1 and 2 are the sides the table names, over random linkages and
    angles: a sign or a zero of the table wrong fails here."""
    rng = random.Random(34)
    checked = 0
    while checked < 200:
        dims = {k: rng.uniform(1, 10) for k in "abcdf"} | {"e": rng.uniform(-3, 3),
                                                         "ksi": rng.uniform(-70, 70)}
        if kind == "spherical":
            dims |= {k: rng.uniform(5, 175) for k in "abcd"}
        link = linkage.Linkage(kind, **{k: dims[k] for k in linkage.LINKAGE_DIMENSIONS[kind]})
        phi, branch = rng.uniform(0, 360), rng.choice((1, 2))
        motion = link.motion(phi, branch)
        if motion.status != linkage.ASSEMBLED:
            continue
        error, side = conventions(kind, dims, phi, motion.output)
        assert abs(error) < 1e-9 * (1 + max(dims.values())), (kind, dims, phi, error)
        if abs(side) > 1e-6:
            assert (side > 0) == (branch == 1), (kind, dims, phi, branch, side)
        checked += 1


def test_the_conventions_table_has_a_row_a_kind_and_says_what_g_is():
    table = README.split("## Conventions", 1)[1].split("\n## ", 1)[0]
    for kind in linkage.KIND_MENU:
        assert f"\n| `{kind}` |" in table, kind
    assert "g = f / cos ξ" in table and "crossed" in table and "open" in table
    assert "A = (sin b cos φ, sin b sin φ, cos b)" in table


# -- one vocabulary (issue 33): kind, class; the old spellings still taken -----------------------

def output_of(argv, capsys):
    status = linkage.main(argv)
    out, err = capsys.readouterr()
    return status, out, err


FG2_1 = ["design", "fourb-fg2-1", "--phij", "60", "--psij", "30", "--phi0", "50"]


def test_design_fg2_1_names_its_ratios_as_ratios_and_still_takes_the_letters(capsys):
    """FOURB-FG2-1's crank and output ratios (the review's a/d, c/d) are --crank-ratio and
    --output-ratio, which say what they are; --a and --c, which run takes for lengths, still
    mean them here, with the same answer."""
    new = output_of(FG2_1 + ["--crank-ratio", "4", "--output-ratio", "2"], capsys)
    old = output_of(FG2_1 + ["--a", "4", "--c", "2"], capsys)
    assert new[0] == old[0] == 0 and new[1] == old[1] and "solution" in new[1], new
    text = help_text("design", "fourb-fg2-1")
    assert re.search(r"--crank-ratio A, --a A the crank over the frame", text), text
    assert re.search(r"--output-ratio C, --c C the output crank over the frame", text), text
    usage = text.split(" options:")[0]
    assert "--a " not in usage and "--c " not in usage, usage


@pytest.mark.parametrize("new, old", [
    (["analyse", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9"],
     ["analyze", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9"]),
    (["design", "fourb-cr-4", "--psi", "60", "--mu-min", "40", "--analyse"],
     ["design", "fourb-cr-4", "--psi", "60", "--mu-min", "40", "--analyze"]),
    (["plot", str(ROOT / "data" / "golden" / "plane-b1"), "--kind", "plane"],
     ["plot", str(ROOT / "data" / "golden" / "plane-b1"), "--mechanism", "plane"])])
def test_one_spelling_shown_the_other_taken(new, old, capsys):
    got, before = output_of(new, capsys), output_of(old, capsys)
    assert got[0] == before[0] == 0 and got[1] == before[1] and got[1], (got, before)


def test_analyse_says_kind_and_class(capsys):
    status, out, _ = output_of(["analyse", "plane", "--a", "6", "--b", "2", "--c", "7", "--d",
                                "9"], capsys)
    names = [line.split(" = ")[0] for line in out.splitlines()]
    assert status == 0 and names[0] == "kind" and "class" in names, names
    assert "type" not in names and "mechanism" not in names


@pytest.mark.parametrize("argv", [[], ["run"], ["analyse"], ["plot"], ["design"],
                                  ["design", "fourb-fg2-1"], ["scene"], ["listing"]])
def test_the_help_calls_the_five_linkages_kinds_never_types(argv):
    """One word a thing: a linkage of the five is a kind (KIND), Grashof's is a class; `type`
    and `TYPE` are nowhere in the help (the retired words)."""
    text = help_text(*argv)
    assert not re.search(r"\btype\b", text, re.IGNORECASE), text
    if argv in (["run"], ["analyse"]):
        assert "KIND" in text and "the kind:" in text


# -- the listing: why each correction, where each kept bug --------------------------------------

ERRATA = (ROOT / "legacy_basic" / "ERRATA.md").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def listing_lines():
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert linkage.main(["listing"]) == 0
    return out.getvalue().splitlines()


def notes_under(lines, number):
    """The lines printed under listing line `number`, up to the next line of the listing."""
    start = next(i for i, line in enumerate(lines) if re.match(rf"^[ *K] {number} ", line))
    notes = []
    for line in lines[start + 1:]:
        if not line.startswith("        "):
            break
        notes.append(line.strip())
    return lines[start], " ".join(notes)


@pytest.mark.parametrize("name, number", [
    (m[1], int(m[2].split(",")[0])) for m in re.finditer(r"^### (E\d+)\. Lines? ([0-9, ]+):",
                                                         ERRATA, re.M)])
def test_the_listing_gives_each_corrections_reason_under_its_line(listing_lines, name, number):
    """Under each corrected line: the erratum and why (ERRATA.md's "Left in:" clause, what the
    scan's text would have done), not only the erratum's name."""
    if name == "E30":                       # the scan's 1245 is line 1265 (the line moved)
        number = 1265
    line, notes = notes_under(listing_lines, number)
    entry = re.search(rf"^### {name}\. .*$((?:\n(?!#).*)*)", ERRATA, re.M)[1]
    left_in = " ".join(entry.split()).replace("*", "").split("Left in: ")[1].split(" Caught")[0]
    assert line.startswith("*") and f"{name}: the scan printed" in notes, (line, notes)
    assert f"left in: {left_in}" in notes, (name, notes)


@pytest.mark.parametrize("name", [f"K{k}" for k in range(1, 15)])
def test_the_listing_marks_each_kept_bug_on_its_lines(listing_lines, name):
    where = re.search(rf"^### {name}\. (.+)$(?:\n(?!#).*)*?^On lines? ([0-9, –]+)\.$", ERRATA,
                      re.M)
    assert where, name
    first = int(re.match(r"\d+", where[2])[0])
    line, notes = notes_under(listing_lines, first)
    assert line[0] in "*K" and f"kept, {name}: {where[1]}" in notes, (line, notes)


def test_the_listing_names_the_errata_file_it_read(listing_lines):
    """The path it names is the file itself (absolute: it need not be where the user is), not
    `legacy_basic/ERRATA.md` relative to a folder the user is not in."""
    text = " ".join(listing_lines)
    named = re.findall(r"(/\S*ERRATA\.md)", text)
    assert named and all(os.path.samefile(n, ROOT / "legacy_basic" / "ERRATA.md")
                         for n in named), named


# -- the pictures say what an engineer would otherwise misread ----------------------------------

def test_fig3_says_on_its_panel_b_that_the_spike_is_the_listings_artefact():
    """Fig. 3's panel (b) dips to -3 at 180 degrees: the scene puts the erratum on the figure, with
    an arrow to that point (the PNG draws it), so that it is not read as the linkage's motion."""
    scene = linkage.load_scene(linkage.scene_path("fig3"))
    (x, y, text), = scene.panels[1].notes
    assert (x, y) == (180.0, -3.0) and "K6" in text and "artefact" in text


@pytest.mark.parametrize("notes", ['"x"', '[{ at = [180], text = "t" }]',
                                   '[{ at = [1, 2], text = "" }]',
                                   '[{ at = [1, 2], text = "t", colour = 1 }]'])
def test_a_bad_note_is_refused_naming_its_key(notes, tmp_path, capsys):
    text = (ROOT / "data" / "scenes" / "fig3-plane-four-bar.toml").read_text(encoding="utf-8")
    bad = tmp_path / "bad.toml"
    bad.write_text(re.sub(r"(?m)^notes = .*$", f"notes = {notes}", text), encoding="utf-8")
    status, out, err = output_of(["scene", str(bad)], capsys)
    assert status == 1 and "panels[2].notes" in err and "Traceback" not in err, err


def test_dashes_mean_the_far_side_of_the_sphere_and_nothing_else():
    """In the PNG and the SVG a dashed line is behind the sphere (a link grey, a coupler curve in
    its colour); the other branch's curve is its colour, solid (before: dashed, as the far side)."""
    dashed = {style for style, look in linkage._PNG_STYLES.items() if look.get("linestyle") == "--"}
    assert dashed == {"hidden", *linkage.FAR_SIDE.values()}
    css = dict(re.findall(r"polyline\.([\w-]+)\{([^}]*)\}", linkage._SVG_STYLE))
    svg_dashed = {style for style, rule in css.items()
                  if re.search(r"dasharray:([2-9]|\d\d+) \d+(;|$)", rule)}   # not dots: 1 n
    assert svg_dashed == dashed, svg_dashed
    link = linkage.Linkage("spherical", a=80, b=20, c=75, d=60)
    drawing = linkage.mechanism_drawing(link, [0.0, 90.0], 1, coupler=(60.0, 50.0), traced=[2])
    styles = {s.style for s in drawing.ground.strokes}
    assert "coupler-other-far" in styles and "coupler-other" not in styles, styles


def test_the_mu_chart_spans_mus_range_and_90_and_circles_the_worst():
    Figure = need("matplotlib.figure").Figure
    chart = [(phi, 60.0 + 10.0 * math.cos(math.radians(phi))) for phi in range(0, 361, 10)]
    ax = Figure().add_subplot()
    linkage._png_chart(ax, chart, [])
    low, high = ax.get_ylim()
    assert 40 < low < 50 and 90 <= high < 100, (low, high)     # not 0 to 180
    assert "worst μ (circled) 50.0° at 180°" in ax.get_xlabel()


@pytest.mark.parametrize("high, circled", [(130.0, "50.0° at 90°"),            # a tie: mu_min
                                           (130.0 + 1e-6, "130.0° at 270°")])   # beyond MU_TIE
def test_the_mu_chart_circles_the_worst_as_analyse_names_it(high, circled):
    """mu 50 at phi = 90 and `high` at 270: equally far from 90, analyse's mu_worst is mu_min
    (the rule of MU_TIE), and the chart circles that one, not whichever comes first."""
    Figure = need("matplotlib.figure").Figure
    chart = [(0.0, 90.0), (90.0, 50.0), (180.0, 90.0), (270.0, high), (360.0, 90.0)]
    chart = chart[2:] + chart[:2]                           # the highest before the lowest
    ax = Figure().add_subplot()
    linkage._png_chart(ax, chart, [])
    assert f"worst μ (circled) {circled}" in ax.get_xlabel(), ax.get_xlabel()


def test_a_scene_says_kind_and_still_takes_mechanism(tmp_path, capsys):
    """The scenes that come with the program say `kind = ...`; a file that says `mechanism = ...`
    (its old name) draws the same; one that says both is refused."""
    new = (ROOT / "data" / "scenes" / "fig1a-plane-four-bar.toml").read_text(encoding="utf-8")
    assert re.search(r'(?m)^kind = "plane"$', new) and not re.search(r"(?m)^mechanism = ", new)
    old = tmp_path / "old.toml"
    old.write_text(new.replace('kind = "plane"', 'mechanism = "plane"'), encoding="utf-8")
    both = tmp_path / "both.toml"
    both.write_text(new.replace('kind = "plane"', 'kind = "plane"\nmechanism = "plane"'),
                    encoding="utf-8")
    got = [output_of(["scene", str(path), "--text"], capsys)
           for path in (ROOT / "data" / "scenes" / "fig1a-plane-four-bar.toml", old)]
    assert got[0][0] == got[1][0] == 0 and got[0][1] == got[1][1], got
    status, _, err = output_of(["scene", str(both)], capsys)
    assert status == 1 and "old name of 'kind'" in err, err


def test_the_svg_says_what_its_curves_colours_and_dashes_mean():
    """With the dashes gone from the other branch's curve, the SVG names each curve's colour and
    the far side's dashes in a legend under the caption, where it draws them (none where not)."""
    link = linkage.Linkage("spherical", a=80, b=20, c=75, d=60)
    svg = linkage.svg_drawing(linkage.mechanism_drawing(link, [0.0, 90.0], 1,
                                                        coupler=(60.0, 50.0), traced=[2]))
    (legend,) = re.findall(r'<text class="legend"[^>]*>(.*?)</text>', svg)
    assert "this branch" in legend and "the other branch" in legend
    assert "behind the sphere" in legend and "followed" not in legend
    plane = linkage.Linkage("plane", a=6, b=2, c=7, d=9)
    assert 'class="legend"' not in linkage.svg_drawing(linkage.mechanism_drawing(plane, [0.0]))


# -- design -> analyse -> forces: the user's units, the branch, the next commands ----------------

def lines_of(out: str) -> dict[str, str]:
    return dict(line.split(" = ", 1) for line in out.splitlines() if " = " in line)


def pasted(command: str, capsys, **filled: str):
    """A `command.*` line of design run as the user pastes it, placeholders filled."""
    words = shlex.split(command)
    assert words[:2] == ["python3", "linkage.py"], words
    words = [filled.get(w, w) for w in words[2:]]
    return output_of(words, capsys)


@pytest.mark.parametrize("argv, scale, swing, time_ratio", [
    (["fourb-cr-4", "--psi", "50", "--mu-min", "40"], "0.2", "50 deg", "1"),
    (["fourb-cr-1", "--psi", "45", "--theta", "12", "--theta0", "60"], "0.35", "45 deg", "1.142857143"),
    (["slid-fg2-1", "--dtheta", "160", "--ds", "40", "--epsilon", "5"], "0.001", "0.04", "1.25")])
def test_design_prints_the_next_commands_in_the_users_units_on_its_branch(
        argv, scale, swing, time_ratio, capsys):
    """design --scale L prints its lengths times L and command.analyse, which - pasted - analyses
    that very linkage on its branch: the swing the data asked (a slider's stroke ds times L), the
    time ratio (180 + theta) / (180 - theta) or dtheta's, not 1.000000001 from 10-digit lengths
    typed by hand; command.forces runs once RPM and KG are filled in."""
    status, out, err = output_of(["design", *argv], capsys)
    plain = lines_of(out)
    status, out, err = output_of(["design", *argv, "--scale", scale], capsys)
    got = lines_of(out)
    assert status == 0, err
    for letter in "abcde":
        if letter in plain:
            assert float(got[letter]) == pytest.approx(float(plain[letter]) * float(scale),
                                                       rel=1e-9), letter
    status, out, err = pasted(got["command.analyse"], capsys)
    analysed = lines_of(out)
    assert status == 0, err
    assert analysed["branch"] == got["branch"] and analysed["swing"] == swing, analysed
    assert analysed["time_ratio"] == time_ratio, analysed
    status, out, err = pasted(got["command.forces"], capsys, RPM="60", KG="0.5")
    assert status == 0 and "torque_peak" in out, err


def test_design_scale_draws_and_writes_the_scene_in_the_users_units(tmp_path, capsys):
    scene = tmp_path / "cr4.toml"
    status, out, err = output_of(["design", "fourb-cr-4", "--psi", "50", "--mu-min", "40",
                                  "--scale", "0.2", "--scene", str(scene)], capsys)
    assert status == 0, err
    loaded = linkage.load_scene(str(scene))
    assert loaded.dimensions["a"] == 0.2 and loaded.branches == (2,), loaded


@pytest.mark.parametrize("scale", ["0", "-1", "inf"])
def test_design_refuses_a_scale_that_is_no_length(scale, capsys):
    with pytest.raises(SystemExit) as done:
        linkage.main(["design", "fourb-cr-4", "--psi", "50", "--mu-min", "40", "--scale", scale])
    assert done.value.code == 2 and "--scale" in capsys.readouterr().err


def test_explore_starts_on_the_branch_asked(tmp_path, capsys):
    """explore --branch 2 is the screen of branch 1 and b pressed."""
    ticks, toggled = tmp_path / "ticks.keys", tmp_path / "toggled.keys"
    ticks.write_text("Tick\nTick\n", encoding="utf-8")
    toggled.write_text("b\nTick\nTick\n", encoding="utf-8")
    plane = ["explore", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9"]
    asked = output_of([*plane, "--branch", "2", "--keys", str(ticks)], capsys)
    pressed = output_of([*plane, "--keys", str(toggled)], capsys)
    assert asked[0] == pressed[0] == 0 and asked[1] == pressed[1], asked
    assert "branch 2 (A-B)" in asked[1]


def test_mu_worst_of_a_design_whose_mu_is_40_to_140_is_mu_min(capsys):
    """FOURB-CR-4 with mu_min 40 is centric: mu runs from 40 to 140, equally far from 90 but for
    rounding (3.6e-14 here), and the README's rule - mu_min if equally far - holds to that
    rounding (MU_TIE, 1e-9 degrees): mu_worst = 40 at mu_min's angle, not 140."""
    status, out, err = output_of(["design", "fourb-cr-4", "--psi", "50", "--mu-min", "40"],
                                 capsys)
    command = lines_of(out)["command.analyse"]
    words = shlex.split(command)[3:]
    link = linkage.Linkage("plane", **{w[2:]: float(v) for w, v in zip(words[1::2], words[2::2])
                                       if w[2:] in "abcd"})
    analysis = linkage.analyse(link, 2)
    apart = abs(analysis.mu_max.value - 90.0) - abs(analysis.mu_min.value - 90.0)
    assert 0 < abs(apart) <= linkage.MU_TIE <= 1e-9, apart      # a tie only to rounding
    status, out, err = pasted(command, capsys)
    got = lines_of(out)
    assert (got["mu_min"], got["mu_max"]) == ("40", "140"), got
    assert (got["mu_worst"], got["mu_worst_at"]) == (got["mu_min"], got["mu_min_phi"]), got
    assert got["mu_worst_deviation"] == "50"


@pytest.mark.parametrize("phi, sign", [(0, 1), (90, 0), (180, -1)])
def test_forces_help_and_readme_say_the_torques_sign_and_physics_agrees(phi, sign, capsys):
    """forces --help and the README say T is the driver's torque, positive in the sense of phi,
    the peak signed, the crank counter-clockwise for a positive speed, gravity off unless asked,
    Cs = 0.10 for +-5 %, the flywheel to fit (the whole inertia less the links'); and a crank
    alone (a 2 kg rod of b = 0.5 m) held against gravity g = 10
    at phi needs m g (b/2) cos(phi): +5 N m at 0 (gravity turns it clockwise), -5 at 180."""
    text = help_text("forces")
    for words in ("positive in the sense of phi", "the largest |T| with its sign",
                  "counter- clockwise (phi increasing)", "No gravity unless asked",
                  "within +-5 % is Cs = 0.10", "flywheel_added is the rest, the flywheel to fit"):
        assert words in text, words
    readme = " ".join(README.split())
    for words in ("positive in the sense of φ", "*with its sign*", "`--fluctuation 0.10`",
                  "gravity** is off unless asked",
                  "**`flywheel_added`** is the rest: the flywheel to fit"):
        assert words in readme, words
    status, out, err = output_of(["forces", "plane", "--a", "2", "--b", "0.5", "--c", "2",
                                  "--d", "1.5", "--mass-crank", "2", "--gravity", "10", "--from",
                                  str(phi), "--to", str(phi), "--step", "1"], capsys)
    torque = float(lines_of(out)["torque_peak"].split()[0])
    assert status == 0 and torque == pytest.approx(sign * 5.0, abs=1e-9), out
    status, out, err = output_of(["forces", "plane", "--a", "2", "--b", "0.5", "--c", "2",
                                  "--d", "1.5", "--mass-crank", "2", "--from", "0", "--to", "0",
                                  "--step", "1"], capsys)
    assert float(lines_of(out)["torque_peak"].split()[0]) == 0.0, out   # no gravity unasked


def test_every_centric_crank_rocker_has_mu_worst_mu_min():
    """mu of a centric crank-rocker (FOURB-CR-4: c^2 + d^2 = a^2 + b^2 in run's letters, so cos mu
    = +-a b / (c d)) runs from mu_min to 180 - mu_min exactly; however rounded, in whatever units
    (random psi, mu_min, scale), analyse's mu_worst is mu_min (its rounding reached 187 ulps of 90
    at mu_min 5 degrees: a few ulps would not do)."""
    rng = random.Random(34)
    for _ in range(40):
        psi = rng.uniform(5, 120)
        mu, scale = rng.uniform(3, 89 - psi / 2), 10 ** rng.uniform(-3, 3)
        link = linkage.METHODS["fourb-cr-4"][0](psi=psi, mu_min=mu).design.linkage
        dims = {n: getattr(link, n) * scale for n in "abcd"}
        assert math.isclose(dims["c"] ** 2 + dims["d"] ** 2, dims["a"] ** 2 + dims["b"] ** 2)
        analysis = linkage.analyse(linkage.Linkage("plane", **dims), link.branch)
        assert analysis.mu_worst == analysis.mu_min, (psi, mu, scale, analysis.mu_max)


# -- the pictures: the angle a label names is the angle drawn -----------------------------------

@pytest.mark.parametrize("kind, dims, branch", [
    ("plane", dict(a=0.2, b=0.0777847742781538, c=0.110337791896249, d=0.184054456042127), 2),
    ("plane", dict(a=6, b=2, c=7, d=9), 1), ("slider", dict(b=2, c=7, e=1.5), 1),
    ("plane", dict(a=6, b=5, c=7, d=9), 1)])
def test_the_analyse_drawing_draws_the_output_at_its_extremes(kind, dims, branch):
    """analyse --png labels the drawn position where the output is least and greatest (ψ min,
    with its φ) and its header names analyse's angles: the position drawn is at that angle (56.52,
    not the 55 of a 5-degree sweep), the output there the extreme's value - where the extreme
    is on the branch drawn (a=6 b=5: the rocking crank's output least on its return, branch 2,
    drawn faint and numbered)."""
    analysis = linkage.analyse(linkage.Linkage(kind, **dims), branch)
    drawing = linkage.analysis_drawing(analysis)
    posed = [f.pose for f in drawing.frames if f.message is None]
    on_branch = [e for e in (analysis.output_min, analysis.output_max) if abs(linkage.wrap_degrees(
        linkage.Linkage(kind, **dims).sweep([e.phi], branch, 0)[0].output - e.value)) < 1e-9]
    assert len(on_branch) == (1 if dims.get("b") == 5 else 2), on_branch
    for extreme in on_branch:
        pose = next((p for p in posed if abs(linkage.wrap_degrees(p.phi - extreme.phi)) < 1e-9),
                    None)
        assert pose is not None, (extreme, [p.phi for p in posed])
        assert abs(linkage.wrap_degrees(pose.output - extreme.value)) < 1e-9, (pose, extreme)


def test_the_design_pictures_name_crank_positions_within_a_turn():
    """design --png's caption said "the last at φ = 386.517°": a crank position, named in
    [0, 360)."""
    result = linkage.METHODS["fourb-cr-4"][0](psi=50, mu_min=40)
    drawing = linkage.scene_drawing(linkage.design_scene(result))
    assert max(f.pose.phi for f in drawing.frames) > 360             # the sweep runs past a turn
    for frame in drawing.frames:
        phi = float(re.match(r"φ = ([-0-9.e]+)°", frame.caption)[1])
        assert 0 <= phi < 360 and math.isclose(phi, frame.pose.phi % 360, abs_tol=1e-3), frame.caption


def test_the_readmes_walk_through_pastes_what_design_prints_and_shows_what_it_answers(capsys):
    """The README's crank-rocker from start to finish: its analyse and forces commands are
    design's command.analyse and command.forces (RPM and KG filled in), and every `name = value`
    line it shows under a command is one that command prints."""
    section = README.split("## A crank-rocker from start to finish", 1)[1].split("\n## ", 1)[0]
    commands: list[str] = []
    shown: dict[str, list[str]] = {}
    for paragraph in section.split("\n\n"):
        lines = [line.strip() for line in paragraph.splitlines()]
        if not paragraph.startswith("    "):
            continue
        if lines[0].startswith("python3 linkage.py"):
            commands.append(lines[0])
        else:                                            # the output of the command before
            shown[commands[-1]] = lines
    assert len(shown) == 3, shown
    design, analyse, png, forces = commands
    status, out, err = output_of(shlex.split(design)[2:], capsys)
    printed = lines_of(out)
    assert status == 0 and analyse == printed["command.analyse"], (analyse, printed)
    assert png.startswith(analyse + " --png ")
    speed = re.search(r"--speed (\S+) --mass-crank (\S+) --mass-coupler (\S+) --mass-output (\S+)",
                      forces)
    filled = printed["command.forces"].replace("--speed RPM", f"--speed {speed[1]}")
    for role, mass in zip(("crank", "coupler", "output"), speed.groups()[1:]):
        filled = filled.replace(f"--mass-{role} KG", f"--mass-{role} {mass}")
    assert forces == filled, (forces, filled)
    for command, lines in shown.items():
        status, out, err = output_of(shlex.split(command)[2:], capsys)
        for line in lines:
            assert line == "..." or line in out.splitlines(), (command, line)

