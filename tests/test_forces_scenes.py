"""The forces where a user meets them: a scene's [dynamics] table (one parser, scene_dynamics),
the panels torque, joint_forces and shaking, the CSV's force columns, the `forces` command, and
the transmission angle of the skew kinds as the forces decide it. Physics is checked by physics
(virtual work against the motion's own velocity column, a two-force coupler), the plumbing by
what a user sees (one line on stderr, nothing written)."""

from __future__ import annotations

import contextlib
import csv
import math
from pathlib import Path

import pytest

import linkage
from linkage import Bodies, Body, Effects, Linkage

HEAD = """title = "t"
mechanism = "{mechanism}"
dimensions = {dims}
input = {{ from = 0, to = 360, step = 10 }}
branches = [1]
precision = "{precision}"
"""
PANELS = """
[[panels]]
quantities = ["displacement", "velocity"]

[[panels]]
quantities = ["torque"]
"""
PLANE = "{ a = 0.3, b = 0.1, c = 0.35, d = 0.45 }"


def scene_file(tmp_path, dynamics, mechanism="plane", dims=PLANE, precision="double",
               panels=PANELS):
    path = tmp_path / "scene.toml"
    path.write_text(HEAD.format(mechanism=mechanism, dims=dims, precision=precision)
                    + ("\n[dynamics]\n" + dynamics if dynamics is not None else "") + panels)
    return path


def run(argv, capsys):
    status = linkage.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def read_csv(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


# ---- 1. the [dynamics] table --------------------------------------------------------------

def test_every_key_of_the_table_reaches_forces(tmp_path):
    table = {"speed": 120, "crank_acceleration": 2.5, "gravity": [0.0, -9.0, 0.0],
             "crank": {"mass": 0.5, "centre": 0.04, "inertia": 0.001},
             "coupler": {"mass": 1.0, "centre": [0.1, 0.02], "inertia": 0.01},
             "output": {"mass": 2.0},
             "output_torque": -3.0,
             "coupler_force": {"at": [0.1, 0.05], "force": [1.0, 2.0, 0.0]}}
    got = linkage.scene_dynamics("x.toml", "plane", dict(a=0.3, b=0.1, c=0.35, d=0.45), table)
    assert got == linkage.Dynamics(
        Bodies(Body(0.5, 0.04, 0.001), Body(1.0, [0.1, 0.02], 0.01), Body(2.0)),
        Effects(120.0, 2.5, [0.0, -9.0, 0.0], -3.0, 0.0, ((0.1, 0.05), (1.0, 2.0, 0.0))), 1.0)


def test_a_slider_crank_names_its_output_slider_and_the_sphere_its_radius():
    slider = linkage.scene_dynamics("x.toml", "slider", dict(b=0.05, c=0.2, e=0.01),
                                    {"slider": {"mass": 0.4}, "output_force": -100})
    assert slider.bodies.output == Body(0.4) and slider.effects.output_force == -100.0
    sphere = linkage.scene_dynamics("x.toml", "spherical", dict(a=80, b=20, c=75, d=60),
                                    {"radius": 0.2})
    assert sphere.radius == 0.2 and sphere.bodies == Bodies() and sphere.effects == Effects()


@pytest.fixture
def forces_calls(monkeypatch):
    """The calls to linkage.forces (the scenes' only way to the forces), counted."""
    calls = []
    real = linkage.forces

    def counted(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)
    monkeypatch.setattr(linkage, "forces", counted)
    return calls


def test_a_scene_without_dynamics_computes_no_force(forces_calls, tmp_path, capsys):
    """No [dynamics]: forces() is never called, and the CSV has the columns it had before."""
    path = scene_file(tmp_path, None, panels=PANELS.split("[[panels]]\nquantities = "
                                                          "[\"torque\"]")[0])
    status, _, err = run(["scene", path, "--csv", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    assert forces_calls == []
    assert list(read_csv(tmp_path / "out.csv")[0]) == ["series", *linkage.CSV_HEADER]
    status, _, err = run(["scene", scene_file(tmp_path, "speed = 60\n"), "--csv",
                          tmp_path / "out.csv"], capsys)
    assert status == 0 and forces_calls, "with [dynamics] the forces are computed"


NAN = "nan"
BAD = [
    ("crank = { mass = -1 }", "dynamics.crank", "must not be negative"),
    ("crank = { mass = nan }", "dynamics.crank.mass", "a number, kg"),
    ("speed = nan", "dynamics.speed", "the crank's speed"),
    ("speed = \"fast\"", "dynamics.speed", "the crank's speed"),
    ("gravity = [0, 9.8]", "dynamics.gravity", "[gx, gy, gz]"),
    ("output_force = 5", "dynamics.output_force", "load it with output_torque"),
    ("slider = { mass = 1 }", "dynamics.slider", "unknown key"),
    ("wind = 3", "dynamics.wind", "unknown key"),
    ("coupler = { mass = 1, centre = [0.1, 0], inertia = -0.1 }", "dynamics.coupler",
     "must not be negative"),
    ("coupler = { mass = 1, centre = [0.1, 0] }", "dynamics.coupler", "give both"),
    ("coupler_force = { at = [0.1], force = [1, 0, 0] }", "dynamics.coupler_force.at", "[u, v]"),
    ("coupler_force = { at = [0.1, 0], force = [0, 0, 1] }", "dynamics.coupler_force",
     "no z component"),
]
SKEW = "{ a = 0.3, b = 0.1, c = 0.35, d = 0.45, f = 0.05, ksi = 30 }"
BAD_SPATIAL = [
    ("coupler_force = { at = [0.1, 0.02], force = [1, 0, 0] }", "dynamics.coupler_force",
     "v must be 0"),
    ("crank = { mass = 1, centre = [0, 0, 0], inertia = [[1, 0, 0], [0, -1, 0], [0, 0, 1]] }",
     "dynamics.crank", "positive semi-definite"),
    ("coupler = { mass = 1, centre = [0.1, 0.01, 0], inertia = [[0, 0, 0], [0, 1, 0], "
     "[0, 0, 1]] }", "dynamics.coupler", "centre must lie on it"),
    ("radius = 2", "dynamics.radius", "the spherical four-bar's"),
]


@pytest.mark.parametrize("dynamics, key, fragment",
                         [(d, k, f) for d, k, f in BAD]
                         + [(d, k, f) for d, k, f in BAD_SPATIAL])
def test_a_bad_value_is_one_line_naming_the_key_and_nothing_is_written(dynamics, key, fragment,
                                                                       tmp_path, capsys):
    spatial = (dynamics, key, fragment) in BAD_SPATIAL
    path = scene_file(tmp_path, dynamics + "\n", "skew" if spatial else "plane",
                      SKEW if spatial else PLANE)
    out_csv, out_png = tmp_path / "out.csv", tmp_path / "out.png"
    status, out, err = run(["scene", path, "--csv", out_csv, "--png", out_png], capsys)
    assert status == 1 and out == ""
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert str(path) in err and f"key '{key}'" in err and fragment in err, err
    assert not out_csv.exists() and not out_png.exists()


@pytest.mark.parametrize("text, key, fragment", [
    ("precision = \"basic\"", "precision", "with [dynamics]"),
    ("fast = true", "fast", "with [dynamics]"),
])
def test_dynamics_are_the_engine_s(text, key, fragment, tmp_path, capsys):
    path = scene_file(tmp_path, "speed = 60\n", precision="basic" if "basic" in text else
                      "double")
    if "fast" in text:
        path.write_text(text + "\n" + path.read_text())
    status, _, err = run(["scene", path], capsys)
    assert status == 1 and f"key '{key}'" in err and fragment in err, err


def test_a_force_panel_needs_the_dynamics(tmp_path, capsys):
    status, _, err = run(["scene", scene_file(tmp_path, None)], capsys)
    assert status == 1 and "key 'dynamics' is missing" in err, err


def test_joint_forces_are_a_panel_of_their_own(tmp_path, capsys):
    path = scene_file(tmp_path, "speed = 60\n",
                      panels="\n[[panels]]\nquantities = [\"torque\", \"joint_forces\"]\n")
    status, _, err = run(["scene", path], capsys)
    assert status == 1 and "joint_forces in a panel of its own" in err, err


# ---- 2. what comes out: the CSV's columns and the panels ---------------------------------------

def test_the_csv_s_torque_is_what_virtual_work_says(tmp_path, capsys):
    """Massless links, no gravity, a load T_out on the output: the driver's power balances the
    load's, T omega = -T_out psi' omega, psi' = the CSV's own velocity column (the engine's
    motion, not the forces' system); power is T omega; the joints are the kind's four, each a
    force in the plane; every position assembles, so every status is the motion's."""
    path = scene_file(tmp_path, "speed = 90\noutput_torque = 7.5\n")
    status, _, err = run(["scene", path, "--csv", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    rows = read_csv(tmp_path / "out.csv")
    assert list(rows[0])[6:] == [*linkage.FORCES_COLUMNS] + [
        f"{joint}_f{axis}" for joint in ("A0", "A", "B", "B0") for axis in "xyz"]
    omega = 2 * math.pi * 90 / 60
    for row in rows:
        torque, velocity = float(row["torque"]), float(row["velocity"])
        assert torque == pytest.approx(-7.5 * velocity, rel=1e-9, abs=1e-12), row["phi"]
        assert float(row["power"]) == pytest.approx(torque * omega, rel=1e-12)
        assert row["forces_status"] == row["status"] == "assembled"
        # the massless coupler is a two-force member: A's force lies along A->B
        assert float(row["A_fx"]) ** 2 + float(row["A_fy"]) ** 2 == pytest.approx(
            float(row["B_fx"]) ** 2 + float(row["B_fy"]) ** 2, rel=1e-9)


def test_an_unbounded_position_says_so_and_has_no_number(tmp_path, capsys):
    """Through the change point of a = 5, b = 2, c = 4, d = 3 (Grashof's boundary) at phi = 180
    the forces are unbounded: forces_status says so, and its numbers are nan, not inf."""
    path = scene_file(tmp_path, "speed = 60\noutput_torque = 1\n",
                      dims="{ a = 5, b = 2, c = 4, d = 3 }")
    status, _, err = run(["scene", path, "--csv", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    rows = {float(r["phi"]): r for r in read_csv(tmp_path / "out.csv")}
    at = rows[180.0]
    assert at["forces_status"] == linkage.UNBOUNDED
    assert all(at[c] == "nan" for c in ("torque", "power", "shaking_fx", "A0_fx"))
    assert all("inf" not in value for row in rows.values() for value in row.values())
    assert rows[170.0]["forces_status"] == "assembled" and rows[170.0]["torque"] != "nan"


def test_both_precisions_give_the_basic_rows_a_reason_for_no_forces(tmp_path, capsys):
    path = scene_file(tmp_path, "speed = 60\n", precision="both",
                      panels="\n[[panels]]\nquantities = [\"displacement\"]\n")
    status, _, err = run(["scene", path, "--csv", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    rows = read_csv(tmp_path / "out.csv")
    basic = [r for r in rows if r["series"].startswith("basic")]
    assert basic and all(r["forces_status"] == "no forces (precision basic)"
                         and r["torque"] == "nan" for r in basic)
    assert all(r["torque"] != "nan" for r in rows if r["series"].startswith("double"))


def test_the_text_plot_shows_torque_shaking_and_the_polar_diagram(tmp_path, capsys):
    """The panels are labelled with their units; the polar panel has an x axis of its own (force
    tick values, with zero among them), and one marker a joint in its legend."""
    path = scene_file(tmp_path, "speed = 300\ngravity = 9.81\noutput_torque = 5\n"
                      "crank = { mass = 0.5 }\ncoupler = { mass = 1.2 }\noutput = { mass = 1.5 }\n",
                      panels="\n[[panels]]\nquantities = [\"torque\"]\n[[panels]]\nquantities = "
                             "[\"shaking\"]\n[[panels]]\nquantities = [\"joint_forces\"]\n")
    status, out, err = run(["scene", path, "--text"], capsys)
    assert status == 0, err
    lines = out.splitlines()
    assert any(line.startswith("(a) driving torque T [N m]") for line in lines)
    assert any(line.startswith("(b) shaking force |F| [N]") for line in lines)
    polar = next(i for i, line in enumerate(lines) if line.startswith("(c) joint forces, polar"))
    assert all(f"{m} {j}" in lines[polar] for m, j in zip("*o+x", ("A0", "A", "B", "B0")))
    ticks = lines[-3].split()                # the polar panel's own x tick values
    assert "0" in ticks and float(ticks[0]) < 0 < float(ticks[-1])
    assert lines[-2].split()[0] == "0" and lines[-2].split()[-1] == "360"
    assert lines[-1].startswith("x axes: input angle phi [deg]")
    assert len(lines) <= linkage.TEXT_HEIGHT and max(map(len, lines)) <= linkage.TEXT_WIDTH


ALL_FORCE_PANELS = ("\n[[panels]]\nquantities = [\"torque\"]\n[[panels]]\nquantities = "
                    "[\"shaking\"]\n[[panels]]\nquantities = [\"joint_forces\"]\n")
LOADED = ("speed = 300\ngravity = 9.81\noutput_torque = 5\ncrank = { mass = 0.5 }\n"
          "coupler = { mass = 1.2 }\noutput = { mass = 1.5 }\n")


@pytest.mark.parametrize("mechanism, dims, branch", [
    ("plane", PLANE, "[1, 2]"),
    ("spherical", "{ a = 60, b = 30, c = 60, d = 50 }", "[1]"),
    ("plane", "{ a = 4, b = 1, c = 2, d = 3 }", '["follow"]')])      # a change point at 180
def test_plot_redraws_the_force_panels_from_the_scene_s_csv(mechanism, dims, branch, tmp_path,
                                                            capsys):
    """`plot OUT.csv` draws, from the CSV alone, the torque, shaking and joint-force panels the
    scene drew (the same text, line for line, but the title's), for two branches, the
    spherical kind's moments and a motion followed through a change point (its unbounded
    position a gap); the Forces read back are the scene's (repr round trips; the speed from
    power / torque)."""
    path = scene_file(tmp_path, LOADED, mechanism, dims, panels=ALL_FORCE_PANELS)
    path.write_text(path.read_text().replace("branches = [1]", f"branches = {branch}"))
    status, drawn, err = run(["scene", path, "--text", "--csv", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    status, redrawn, err = run(["plot", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    def panels(out):
        lines = out.splitlines()
        return lines[next(i for i, line in enumerate(lines) if line.startswith("(a) ")):]
    assert panels(redrawn) == panels(drawn)
    assert redrawn.split()[:3] == ["The", "forces", "in"]
    scene = linkage.load_scene(str(path))
    for series in linkage.csv_forces_series(str(tmp_path / "out.csv")):
        want = linkage.scene_forces(scene, series.branch)
        assert [f._replace(speed_rpm=0) for f in series.forces] == \
            [f._replace(speed_rpm=0) for f in want]
        assert series.forces[0].speed_rpm == pytest.approx(300, rel=1e-12)
        assert series.precision == "double"


def test_plot_refuses_a_csv_without_forces_in_one_line(tmp_path, capsys):
    """A CSV without force columns, a row cut short, a file not text: one line on stderr, exit
    1, and no PNG written."""
    path = scene_file(tmp_path, None, panels="\n[[panels]]\nquantities = [\"displacement\"]\n")
    status, _, err = run(["scene", path, "--csv", tmp_path / "plain.csv"], capsys)
    assert status == 0, err
    loaded = scene_file(tmp_path, LOADED)
    status, _, err = run(["scene", loaded, "--csv", tmp_path / "loaded.csv"], capsys)
    assert status == 0, err
    lines = (tmp_path / "loaded.csv").read_text().splitlines()
    (tmp_path / "cut.csv").write_text("\n".join(lines[:3] + [",".join(lines[3].split(",")[:20])])
                                      + "\n")
    (tmp_path / "binary.csv").write_bytes(b"\xff\xfe\x00")
    (tmp_path / "none.csv").write_text(lines[0] + "\n")
    for name, fragment in (("plain.csv", "not the CSV of a scene with [dynamics]"),
                           ("cut.csv", "line 4: not a row of the scene's CSV (20 fields"),
                           ("binary.csv", "cannot be read"),
                           ("none.csv", "holds no position whose forces are known")):
        status, out, err = run(["plot", tmp_path / name, "--png", tmp_path / "out.png"], capsys)
        assert status == 1 and out == "" and len(err.splitlines()) == 1, (name, err)
        assert fragment in err, (name, err)
        assert not (tmp_path / "out.png").exists()


# ---- 3. the forces command ------------------------------------------------------------------

KIND_ARGS = ["forces", "plane", "--a", "0.3", "--b", "0.1", "--c", "0.35", "--d", "0.45",
             "--speed", "300", "--mass-crank", "0.5", "--mass-coupler", "1.2", "--mass-output",
             "1.5", "--gravity", "9.80665", "--output-torque", "5", "--step", "10"]


def lines_of(out):
    return dict(line.split(" = ", 1) for line in out.splitlines())


def test_the_command_s_kind_form_and_scene_form_agree(tmp_path, capsys):
    """The options are the scene's [dynamics] by another road (each link a rod of its mass):
    the same lines, read by the one parser."""
    path = scene_file(tmp_path, "speed = 300\ngravity = 9.80665\noutput_torque = 5\n"
                      "crank = { mass = 0.5 }\ncoupler = { mass = 1.2 }\noutput = { mass = 1.5 }\n")
    status, from_scene, err = run(["forces", path], capsys)
    assert status == 0, err
    status, from_options, err = run(KIND_ARGS, capsys)
    assert status == 0, err
    assert from_scene == from_options


def test_the_command_s_numbers_are_the_forces_summary_s(capsys):
    """Every figure is there with its unit; the flywheel is the energy swing over Cs omega^2,
    recomputed here from the torque curve by the trapezoid rule (and halves when Cs doubles)."""
    status, out, err = run(KIND_ARGS, capsys)
    assert status == 0, err
    got = lines_of(out)
    for name, unit in (("torque_peak", "N m"), ("torque_rms", "N m"), ("power_mean", "W"),
                       ("joint_A0_force_peak", "N"), ("joint_B0_force_peak", "N"),
                       ("shaking_force_peak", "N"), ("shaking_moment_peak", "N m"),
                       ("flywheel_inertia", "kg m^2")):
        assert got[name].endswith(" " + unit), name
    results = swept_forces()
    torques = [r.torque for r in results]
    peak = max(torques, key=abs)
    assert float(got["torque_peak"].split()[0]) == pytest.approx(peak, rel=1e-9)
    assert float(got["torque_peak_phi"]) == results[torques.index(peak)].phi
    mean = sum((a + b) / 2 for a, b in zip(torques, torques[1:])) / (len(torques) - 1)
    energy, swing = [0.0], math.radians(10)
    for a, b in zip(torques, torques[1:]):
        energy.append(energy[-1] + ((a + b) / 2 - mean) * swing)
    omega = 2 * math.pi * 300 / 60
    assert float(got["flywheel_inertia"].split()[0]) == pytest.approx(
        (max(energy) - min(energy)) / (0.05 * omega ** 2), rel=1e-9)
    status, out, _ = run(KIND_ARGS + ["--fluctuation", "0.1"], capsys)
    assert float(lines_of(out)["flywheel_inertia"].split()[0]) == pytest.approx(
        float(got["flywheel_inertia"].split()[0]) / 2, rel=1e-9)


def swept_forces():
    return linkage.Linkage("plane", a=0.3, b=0.1, c=0.35, d=0.45).forces(
        range(0, 361, 10), 1, Bodies(Body(0.5), Body(1.2), Body(1.5)),
        Effects(300, gravity=9.80665, output_torque=5))


@pytest.mark.parametrize("argv, status, fragment", [
    (["forces", "plane", "--a", "0.3", "--b", "0.1", "--c", "0.35", "--d", "0.45",
      "--mass-crank", "-1"], 1, "--mass-crank: what the forces can take"),
    (["forces", "slider", "--b", "0.1", "--c", "0.35", "--e", "0", "--output-torque", "3"], 1,
     "--output-torque: what the forces can take"),
    (["forces", "fig3"], 1, "key 'dynamics' is missing"),
    (["forces", "fig3", "--speed", "10"], 2, "these options go with a KIND"),
    (["forces", "plane", "--a", "0.3", "--b", "0.1", "--c", "0.35"], 2, "missing --d"),
    (["forces", "plane", "--a", "0.3", "--b", "0.1", "--c", "0.35", "--d", "0.45",
      "--fluctuation", "0"], 2, "--fluctuation 0"),
    (["forces", "plane", "--a", "0.3", "--b", "0.1", "--c", "0.35", "--d", "0.45",
      "--step", "0"], 2, "--step 0"),
])
def test_the_command_refuses_with_one_line(argv, status, fragment, capsys):
    with pytest.raises(SystemExit) if status == 2 else contextlib.nullcontext():
        assert linkage.main(argv) == status
    out, err = capsys.readouterr()
    assert fragment in err and "Traceback" not in err and out == "", err


def test_unbounded_angles_are_named_and_the_flywheel_refused(capsys):
    status, out, err = run(["forces", "plane", "--a", "5", "--b", "2", "--c", "4", "--d", "3",
                            "--speed", "60", "--output-torque", "1", "--step", "10"], capsys)
    assert status == 0, err
    got = lines_of(out)
    assert got["unbounded"] == "180"          # a + b = c + d: the change point at phi = 180
    assert got["flywheel_inertia"].startswith("none")


def test_the_engine_shakes_its_frame_as_the_textbook_says(tmp_path, capsys):
    """An in-line engine (e = 0) at top dead centre (phi = 0): the piston's acceleration is
    r w^2 (1 + r/l), the crank pin's r w^2, a point of the rod a fraction k of the way from the
    pin is (1 - k) and k of them (a rigid body's accelerations are affine in position); with the
    crank balanced the frame is shaken by m a of the rod and the piston alone."""
    r, l, k, rpm, rod, piston = 0.04, 0.14, 0.045 / 0.14, 3000, 0.5, 0.4
    path = scene_file(tmp_path, f"speed = {rpm}\ncrank = {{ mass = 2, centre = 0, inertia = "
                      f"0.004 }}\ncoupler = {{ mass = {rod}, centre = [{k * l}, 0], inertia = "
                      f"0.0012 }}\nslider = {{ mass = {piston} }}\n", "slider",
                      f"{{ b = {r}, c = {l}, e = 0 }}")
    status, _, err = run(["scene", path, "--csv", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    at_tdc = read_csv(tmp_path / "out.csv")[0]
    assert float(at_tdc["phi"]) == 0.0
    w2 = (2 * math.pi * rpm / 60) ** 2
    textbook = (rod * ((1 - k) + k * (1 + r / l)) + piston * (1 + r / l)) * r * w2
    got = math.hypot(float(at_tdc["shaking_fx"]), float(at_tdc["shaking_fy"]))
    assert got == pytest.approx(textbook, rel=1e-9)


# ---- 5. the skew kinds' transmission angle, decided by the forces ------------------------------

def norm(v):
    return math.sqrt(sum(x * x for x in v))


def angle(u, v):
    return math.degrees(math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(u, v))
                                                 / (norm(u) * norm(v))))))


SKEW_CASES = [
    ("skew-slider", dict(a=3, b=1.5, c=4, f=1, ksi=30)),           # issue 30's example
    ("skew-slider", dict(a=6, b=1, c=7.5, f=3, ksi=45)),
    ("skew", dict(a=4, b=1.5, c=4, d=2.5, f=2, ksi=40)),
    ("skew", dict(a=0.2, b=0.075, c=0.2, d=0.125, f=0.1, ksi=-25)),
]


@pytest.mark.parametrize("kind, dims", SKEW_CASES, ids=[f"{k}-{d['ksi']}" for k, d in SKEW_CASES])
def test_the_skew_transmission_angle_is_what_the_forces_transmit(kind, dims):
    """Massless links and a unit load on the output (1 N m about its axis; 1 N along a slider's
    guide): the coupler is a two-force member, so the reaction at the output pin lies along
    A->P, and the load it balances is |F| |P_q| sin mu, |P_q| = d (the output crank) or 1 (the
    guide). mu = linkage.transmission's, at every assembled angle of a turn on both branches.
    Neither other reading predicts it: mu taken about the input shaft's direction (the
    program's before), nor the angle between the pin's path and B's velocity relative to A
    (the review's, from the motion) - each misses by degrees somewhere along the turn."""
    link = Linkage(kind, **dims)
    slider = kind == "skew-slider"
    load = Effects(0.0, output_force=1.0) if slider else Effects(0.0, output_torque=1.0)
    pin, arm = ("C", 1.0) if slider else ("B", dims["d"])
    misses = {"about the input shaft": 0.0, "from the motion": 0.0}
    checked = 0
    for branch in (1, 2):
        phis = [float(p) for p in range(0, 360, 7)]
        for f, m, mu in zip(link.forces(phis, branch, Bodies(), load),
                            link.sweep(phis, branch, 1), link.transmission(phis, branch)):
            if f.torque is None or mu is None:
                continue
            pose = linkage.joint_positions(link, m.phi, branch)
            line = [p - a for p, a in zip(pose.joints[pin], pose.joints["A"])]
            force = f.joints[pin].force
            assert norm(linkage.cross(force, line)) <= 1e-9 * norm(force) * norm(line)
            predicted = 1.0 / (norm(force) * arm)           # sin mu, from the forces alone
            assert math.sin(math.radians(mu)) == pytest.approx(predicted, rel=1e-9, abs=1e-12), \
                (kind, dims, branch, m.phi, mu)
            checked += 1
            dims_ = linkage.pin_dimensions(link.scaled)
            c, s = linkage.cos_sin_degrees(m.phi)
            a, p, p_q = linkage.joint_kinematics(link, dims_, c, s, m.output, 1, m.velocity,
                                                 None, linkage.cos_sin_degrees)
            about_z = angle(p_q, linkage.cross((0.0, 0.0, 1.0), line))
            relative = angle(p_q, [x - y for x, y in zip(p[1], a[1])])
            for name, other in (("about the input shaft", about_z), ("from the motion",
                                                                        relative)):
                misses[name] = max(misses[name], abs(math.sin(math.radians(other)) - predicted))
    assert checked > 20
    assert min(misses.values()) > 0.01, misses


def test_the_sphere_s_radius_reaches_the_forces(tmp_path, capsys):
    """The spherical four-bar's arcs are angles; its sphere's radius scales every length, so
    without gravity or loads the inertia torque goes as mass x length^2: twice the radius, four
    times the torque at every angle."""
    torques = []
    for radius in (0.1, 0.2):
        path = scene_file(tmp_path, f"speed = 120\nradius = {radius}\ncrank = {{ mass = 0.2 }}\n"
                          "coupler = { mass = 0.4 }\noutput = { mass = 0.3 }\n", "spherical",
                          "{ a = 80, b = 20, c = 75, d = 60 }")
        status, _, err = run(["scene", path, "--csv", tmp_path / "out.csv"], capsys)
        assert status == 0, err
        torques.append([float(r["torque"]) for r in read_csv(tmp_path / "out.csv")])
    assert max(map(abs, torques[0])) > 1e-3
    assert torques[1] == pytest.approx([4 * t for t in torques[0]], rel=1e-9, abs=1e-12)


# ---- 6. the mechanism drawn with its joints' forces as arrows ----------------------------------

ARROWS = """title = "t"
mechanism = "{mechanism}"
dimensions = {dims}
input = {{ from = 0, to = 360, step = 45 }}
branches = [1]
{forces}
{dynamics}
[[panels]]
quantities = ["mechanism"]
"""


def test_a_massless_coupler_s_arrows_lie_along_it(tmp_path):
    """Massless links and a load on the output: the coupler is a two-force member, so the arrows
    at A (the crank's force on it) and at B (its force on the output, which a massless body
    passes on whole) are one and the same vector along A->B; the longest arrow of the sweep is a
    quarter of the drawing's span."""
    path = tmp_path / "arrows.toml"
    path.write_text(ARROWS.format(mechanism="plane", dims=PLANE, forces="forces = true",
                                  dynamics="[dynamics]\nspeed = 60\noutput_torque = -5\n"))
    scene = linkage.load_scene(str(path))
    drawing = linkage.scene_drawing(scene)
    longest = 0.0
    for frame in drawing.frames:
        shafts = {s.points[0]: s.points[1] for s in frame.layer.strokes
                  if s.style == "force" and len(s.points) == 2}
        a, b = frame.pose.joints["A"][:2], frame.pose.joints["B"][:2]
        line = (b[0] - a[0], b[1] - a[1])
        at_a = next(tip for tail, tip in shafts.items() if math.dist(tail, a) < 1e-12)
        at_b = next(tip for tail, tip in shafts.items() if math.dist(tail, b) < 1e-12)
        arrows = [(tip[0] - tail[0], tip[1] - tail[1]) for tail, tip in ((a, at_a), (b, at_b))]
        for x, y in arrows:
            assert abs(x * line[1] - y * line[0]) <= 1e-9 * norm((x, y)) * norm(line)
        assert math.dist(*arrows) <= 1e-9 * norm(arrows[0])
        longest = max([longest] + [math.dist(tail, tip) for tail, tip in shafts.items()])
    joints = [q for f in drawing.frames for q in f.pose.joints.values()]
    span = max(max(q[i] for q in joints) - min(q[i] for q in joints) for i in (0, 1))
    assert longest == pytest.approx(0.25 * span, rel=1e-9)
    assert "arrows: joint forces, the longest" in drawing.subtitle


@pytest.mark.parametrize("mechanism, dims", [("plane", PLANE),
                                             ("spherical", "{ a = 80, b = 20, c = 75, d = 60 }")])
def test_dynamics_without_forces_true_draws_no_arrows(mechanism, dims, tmp_path):
    """A mechanism scene's [dynamics] without forces = true (the explorer's torque, saved) is
    read, and the scene is drawn as it is without one: no arrows."""
    path = tmp_path / "plain.toml"
    path.write_text(ARROWS.format(mechanism=mechanism, dims=dims, forces="", dynamics=""))
    with_dynamics = tmp_path / "dynamics.toml"
    with_dynamics.write_text(ARROWS.format(mechanism=mechanism, dims=dims, forces="",
                                           dynamics="[dynamics]\nspeed = 60\n"
                                                    "output_torque = -5\n"))
    plain, scene = (linkage.load_scene(str(p)) for p in (path, with_dynamics))
    assert scene.dynamics is not None and not scene.arrows
    assert scene.dynamics.effects.output_torque == -5.0
    assert linkage.scene_drawing(scene) == linkage.scene_drawing(plain)


@pytest.mark.parametrize("mechanism, dims, forces, dynamics, fragment", [
    ("plane", PLANE, "forces = true", "", "forces = true with a [dynamics] table"),
    ("plane", PLANE, "forces = 1", "[dynamics]\nspeed = 60\n", "true or false"),
    ("spherical", "{ a = 80, b = 20, c = 75, d = 60 }", "forces = true",
     "[dynamics]\nspeed = 60\n", "false for the spherical four-bar"),
    ("plane", PLANE, "forces = true", "[dynamics]\ncrank = { mass = -2 }\n",
     "must not be negative"),
])
def test_arrows_need_their_dynamics(mechanism, dims, forces, dynamics, fragment, tmp_path,
                                    capsys):
    path = tmp_path / "arrows.toml"
    path.write_text(ARROWS.format(mechanism=mechanism, dims=dims, forces=forces,
                                  dynamics=dynamics))
    status, out, err = run(["scene", path, "--svg", tmp_path / "out.svg"], capsys)
    assert status == 1 and fragment in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "out.svg").exists()


def test_the_spherical_kind_s_radius_is_an_option_too(capsys):
    """forces spherical ... --radius 0.1 says what the bundled scene forces-spherical-four-bar
    (radius = 0.1 in its [dynamics]) says: the sphere's radius reaches the forces both ways."""
    status, from_scene, err = run(["forces", "forces-spherical-four-bar"], capsys)
    assert status == 0, err
    status, from_options, err = run([
        "forces", "spherical", "--a", "80", "--b", "20", "--c", "75", "--d", "60", "--speed",
        "120", "--gravity", "9.80665", "--radius", "0.1", "--mass-crank", "0.2", "--mass-coupler",
        "0.4", "--mass-output", "0.3", "--output-torque", "-0.5", "--step", "2"], capsys)
    assert status == 0, err
    assert from_options == from_scene
    assert lines_of(from_scene)["joint_A0_moment_peak"].endswith(" N m")


def test_the_readme_shows_the_command_s_current_output(capsys):
    """README's "What it takes to drive it" shows `forces forces-plane` with what it prints."""
    readme = (Path(linkage.__file__).parent / "README.md").read_text(encoding="utf-8")
    status, out, err = run(["forces", "forces-plane"], capsys)
    assert status == 0, err
    assert "    python3 linkage.py forces forces-plane\n\n" + "".join(
        "    " + line for line in out.splitlines(True)) in readme


def test_numbers_past_the_floats_range_are_named_not_printed(tmp_path, capsys):
    """A speed of 1e200 rpm squares past the largest float: no inf or nan reaches the user, the
    angles are listed as overflow (the CSV's forces_status says so)."""
    status, out, err = run(["forces", "plane", "--a", "0.3", "--b", "0.1", "--c", "0.35", "--d",
                            "0.45", "--speed", "1e200", "--mass-crank", "1", "--step", "90"],
                           capsys)
    assert status == 0, err
    got = lines_of(out)
    assert got["overflow"] == "0, 90, 180, 270, 360" and got["unbounded"] == "none"
    assert "inf" not in out and "nan" not in out
    path = scene_file(tmp_path, "speed = 1e200\ncrank = { mass = 1 }\n")
    status, _, err = run(["scene", path, "--csv", tmp_path / "out.csv"], capsys)
    assert status == 0, err
    rows = read_csv(tmp_path / "out.csv")
    assert all(r["forces_status"] == linkage.OUT_OF_RANGE and r["torque"] == "nan" for r in rows)
    assert not any("inf" in v for r in rows for v in r.values())
