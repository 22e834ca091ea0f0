"""Simulation scenes (a scene's [simulation] table, issue 31): the keys reach simulate() as its
arguments (the CSV's rows are those of simulate() called directly), the released double-rocker
keeps its energy, the rhombus stays a parallelogram through its change points, a flywheel holds
the engine's speed closer, the events are said, the figure is drawn against time and the linkage
moves in real time; bad input is refused in one line with nothing written."""

from __future__ import annotations

import contextlib
import csv
import io
import math
import re

import pytest

import linkage
from linkage import Bodies, Body, Driver, Effects, Linkage, Spring, Torsion, simulate
from support import make_scene_snapshots
from support.basic_runner import ROOT

SCENES = ROOT / "data" / "scenes"
SIMULATION_SCENES = sorted(SCENES.glob("simulate-*.toml"))


def run(argv):
    """main(argv) in this process: (status, standard output, standard error)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = linkage.main([str(a) for a in argv])
    return status, out.getvalue(), err.getvalue()


_csvs: dict = {}


def scene_csv(name, tmp_path_factory):
    """`scene NAME --csv OUT` run once: (its rows as dicts of floats, standard error)."""
    if name not in _csvs:
        out = tmp_path_factory.mktemp(name) / "run.csv"
        status, _, err = run(["scene", SCENES / f"{name}.toml", "--csv", out])
        assert status == 0, err
        with open(out, newline="") as fh:
            rows = [{k: v if k == "coordinate" else float(v) for k, v in r.items()}
                    for r in csv.DictReader(fh)]
        _csvs[name] = rows, err
    return _csvs[name]


# -- the keys are simulate()'s arguments ---------------------------------------------------------

EVERY_KEY = """title = "every key"
kind = "plane"
dimensions = { a = 3.0, b = 2.5, c = 1.0, d = 2.0 }
branches = [1]

[dynamics]
gravity = 9.81
crank = { mass = 1.0 }
coupler = { mass = 0.5 }
output = { mass = 1.0 }
output_torque = -0.5

[simulation]
time = 0.8
step = 0.05
tolerance = 1e-9
initial = { angle = 320, speed = 3 }
torque = 0.7
motor = { stall_torque = 2.0, free_speed = 60 }
spring = [{ between = ["B", [3.0, 3.0]], k = 40.0, free_length = 1.0 },
          { between = ["A0", "A"], k = 5.0, free_length = 2.0 }]
torsion = [{ at = "A0", k = 3.0, free_angle = 320, damping = 0.2 },
           { at = "B0", k = 2.0, free_angle = -120 }]
until_angle = 330

[[panels]]
quantities = ["phi"]
"""


def test_the_csv_rows_are_those_of_simulate_called_with_the_keys(tmp_path):
    scene = tmp_path / "every.toml"
    scene.write_text(EVERY_KEY)
    status, _, err = run(["scene", scene, "--csv", tmp_path / "run.csv"])
    assert status == 0, err
    direct = simulate(
        Linkage("plane", a=3.0, b=2.5, c=1.0, d=2.0), Bodies(Body(1.0), Body(0.5), Body(1.0)),
        Effects(gravity=9.81, output_torque=-0.5), driver=Driver(0.7, 2.0, 60.0),
        springs=[Spring("B", (3.0, 3.0), 40.0, 1.0), Spring("A0", "A", 5.0, 2.0)],
        torsions=[Torsion("A0", 3.0, 320.0, 0.2), Torsion("B0", 2.0, -120.0, 0.0)],
        initial=(320.0, 3.0), time=0.8, step=0.05, tolerance=1e-9, branch=1, until_angle=330.0)
    lines = (tmp_path / "run.csv").read_text().splitlines()
    assert lines[0] == ("t,phi,omega,alpha,output,output_rate,output_acceleration,energy,work,"
                        "drift,coordinate")
    e0 = direct.rows[0].energy
    want = [[repr(float(v) + 0.0) for v in r[:9]] + [repr(r.energy - r.work - e0 + 0.0),
                                                       r.coordinate] for r in direct.rows]
    assert [line.split(",") for line in lines[1:]] == want
    assert direct.events[-1].kind == linkage.ANGLE_REACHED          # until_angle reached it
    assert "angle reached at t = " in err and "the crank at 330 degrees" in err


# -- the scenes: what each shows, checked by physics -----------------------------------------------

def test_the_released_double_rocker_keeps_its_energy_through_its_dead_centres(tmp_path_factory):
    rows, err = scene_csv("simulate-released-four-bar", tmp_path_factory)
    e0 = rows[0]["energy"]
    assert all(r["work"] == 0.0 for r in rows)                      # no driver, load or damper
    assert max(abs(r["energy"] - e0) for r in rows) < 1e-8 * abs(e0)
    assert max(abs(r["drift"]) for r in rows) < 1e-8 * abs(e0)
    # released from rest: the speed it has is what gravity gave it, 1/2 J w^2 = V0 - V
    assert rows[0]["omega"] == 0.0 and len(rows) == 301
    dead = re.search(r"dead centre of the input: (\d+) times", err)
    assert dead and int(dead[1]) >= 8, err
    assert {r["coordinate"] for r in rows} == {"input", "output"}
    # it swings back to where it started each period: the crank never passes 320 degrees
    assert max(r["phi"] for r in rows) < 320.0 + 1e-6


def test_the_spherical_double_rocker_swings_through_its_input_dead_centres(tmp_path_factory):
    """The spatial kinds change coordinate as the plane ones do: released at 50 degrees, the
    crank falls to its input's dead centre (coupler and rocker on one great circle: the arc
    from A to B0 is d - c or d + c, solved here) and turns back, again and again, never past
    it, the energy kept; once the run ended there (STUCK)."""
    rows, err = scene_csv("simulate-released-spherical", tmp_path_factory)
    e0 = rows[0]["energy"]
    assert all(r["work"] == 0.0 for r in rows)
    assert max(abs(r["drift"]) for r in rows) < 1e-8 * abs(e0)
    assert {r["coordinate"] for r in rows} == {"input", "output"}
    dead = re.search(r"dead centre of the input: (\d+) times, the first at t = \S+ s, "
                     r"phi = (\S+) deg", err)
    assert dead and int(dead[1]) >= 3 and "stuck" not in err, err
    # A = (sin b cos phi, sin b sin phi, cos b), B0 = (sin a, 0, cos a): A . B0 = cos(d -+ c)
    a, b, c, d = (math.radians(x) for x in (60.0, 70.0, 30.0, 50.0))
    phis = [math.degrees(math.acos((math.cos(arc) - math.cos(a) * math.cos(b))
                                   / (math.sin(a) * math.sin(b))))
            for arc in (d - c, d + c) if abs(math.cos(arc) - math.cos(a) * math.cos(b))
            <= math.sin(a) * math.sin(b)]
    lowest = min(phis, key=lambda p: abs(p - 50.0))
    assert abs(float(dead[2]) - lowest) < 1e-4, (dead[2], phis)
    assert min(r["phi"] for r in rows) > lowest - 1e-9
    assert max(r["phi"] for r in rows) < 50.5


def test_the_rhombus_stays_a_parallelogram_through_its_change_points(tmp_path_factory):
    rows, err = scene_csv("simulate-rhombus", tmp_path_factory)
    assert max(abs(math.remainder(r["output"] - r["phi"], 360.0)) for r in rows) < 1e-7
    assert rows[-1]["phi"] < -3 * 360.0                              # it turned over and over
    crossings = re.search(r"change point: (\d+) times", err)
    assert crossings and int(crossings[1]) >= 8, err
    # the coupler translates: J = 1/3 + 1 + 1/3, V = 2 g sin(phi); the speed from the energy
    for r in rows[::50]:
        want = (2.0 * (rows[0]["energy"] - 2.0 * 9.81 * math.sin(math.radians(r["phi"])))
                / (5.0 / 3.0))
        assert abs(r["omega"] ** 2 - want) < 1e-6, r


def steady_fluctuation(rows):
    """(max - min) / mean of the crank's speed over the last second of the run."""
    end = rows[-1]["t"]
    speeds = [r["omega"] for r in rows if r["t"] >= end - 1.0]
    return (max(speeds) - min(speeds)) / (sum(speeds) / len(speeds))


def test_a_flywheel_holds_the_engines_speed_closer(tmp_path_factory):
    plain, _ = scene_csv("simulate-engine-run-up", tmp_path_factory)
    flywheel, _ = scene_csv("simulate-engine-flywheel", tmp_path_factory)
    without, with_ = steady_fluctuation(plain), steady_fluctuation(flywheel)
    assert with_ < without / 3, (with_, without)
    for rows in (plain, flywheel):
        mean = sum(r["omega"] for r in rows if r["t"] >= 3.0) / sum(r["t"] >= 3.0 for r in rows)
        assert 0.9 * 100 * math.pi < mean < 100 * math.pi          # run up near 3000 rpm
        # the motor's work is the energy gained (no other force does work)
        assert abs(rows[-1]["energy"] - rows[-1]["work"]) < 1e-4 * rows[-1]["work"]


@pytest.mark.parametrize("path", SIMULATION_SCENES, ids=lambda p: p.stem)
def test_each_simulation_scene_prints_its_snapshot(path):
    for encoding in make_scene_snapshots.encodings(path):
        want = make_scene_snapshots.snapshot_path(path, encoding).read_text(encoding=encoding)
        assert make_scene_snapshots.text_plot(path, encoding) == want, path.stem


def test_the_figure_is_drawn_against_time(tmp_path_factory):
    status, text, _ = run(["scene", SCENES / "simulate-released-four-bar.toml"])
    assert status == 0
    lines = text.splitlines()
    assert lines[-1] == "x axes: time t [s]"
    assert "0.0        0.5        1.0" in lines[-2]
    assert "(c) energy drift E - W - E0 [J]" in text


# -- the linkage moving in real time -----------------------------------------------------------------

def test_the_mechanism_moves_in_real_time(tmp_path):
    path = SCENES / "simulate-rhombus-moving.toml"
    svg, png = tmp_path / "m.svg", tmp_path / "m.png"
    status, _, err = run(["scene", path, "--svg", svg, "--png", png])
    assert status == 0, err
    text = svg.read_text()
    frames = int(re.search(r'data-frames="(\d+)"', text)[1])
    assert frames == 101                                  # 4 s, a row every 0.04 s
    assert re.search(r'dur="([0-9.]+)s"', text)[1] == "4.04"     # 0.04 s a frame: real time
    phis = [float(p) for p in re.findall(r'data-phi="([^"]+)"', text)]
    rows = simulate(Linkage("plane", a=1, b=1, c=1, d=1), Bodies(Body(1.0), Body(1.0), Body(1.0)),
                    Effects(gravity=9.81), initial=(90.0, -30.0 / math.pi), time=4.0, step=0.04,
                    tolerance=1e-9, branch=2).rows
    assert phis == [r.phi for r in rows[:101]]
    assert "t = 2.00 s" in text and png.read_bytes()[:4] == b"\x89PNG"
    status, out, _ = run(["scene", path, "--frames", "3"])
    assert status == 0 and out.count("t = ") == 3


def path_circles(drawing):
    """The (centre, radius) of each closed "path" stroke of the drawing's ground (page units)."""
    found = []
    for s in drawing.ground.strokes:
        if s.style == "path" and s.points[0] == pytest.approx(s.points[-1], abs=1e-9):
            xs, ys = zip(*s.points[:-1])
            centre = (sum(xs) / len(xs), sum(ys) / len(ys))
            radii = [math.dist(centre, p) for p in s.points]
            assert max(radii) - min(radii) < 1e-9          # a circle
            found.append((centre, radii[0]))
    return sorted(found)


def test_the_rhombus_is_drawn_with_both_pins_paths():
    """The rhombus's output turns fully: its pin B's path, the circle of d = 1 about B0 = (1, 0),
    is drawn beside A's about A0; a rocker's output (the released double-rocker's) has only A's
    circle, its swing shown by its extremes."""
    scene = linkage.load_scene(str(SCENES / "simulate-rhombus-moving.toml"))
    drawing = linkage.simulation_drawing(scene, linkage.scene_run(scene))
    circles = path_circles(drawing)
    assert [c for c, _ in circles] == [pytest.approx((0.0, 0.0), abs=1e-9),
                                        pytest.approx((1.0, 0.0), abs=1e-9)]
    assert [r for _, r in circles] == [pytest.approx(1.0, abs=1e-9)] * 2
    rocker = Linkage("plane", a=3.0, b=2.5, c=1.0, d=2.0)
    drawn = linkage.mechanism_drawing(rocker, [300.0 + 5.0 * i for i in range(9)])
    assert [r for _, r in path_circles(drawn)] == [pytest.approx(2.5)]


def frames_drawn(monkeypatch, drawing, seconds_a_frame, until):
    """(clock, frame) of each frame the terminal animation draws while the clock runs to `until`
    seconds, the clock a fake: it moves by the seconds the animation waits, and by
    seconds_a_frame while each frame is drawn (a machine too loaded to keep the frames' pace)."""
    now = [0.0]
    drawn = []

    def text_drawing(d, index, *args):
        drawn.append((now[0], index))
        now[0] += seconds_a_frame
        return f"frame {index}"

    def key_within(fd, seconds):
        now[0] += seconds
        return b"q" if now[0] >= until else None

    monkeypatch.setattr(linkage, "text_drawing", text_drawing)
    monkeypatch.setattr("sys.stdin", io.StringIO())          # no keys: no terminal to read
    fps = 1.0 / drawing.seconds
    assert linkage._animate(drawing, io.StringIO(), fps, True, lambda: now[0], key_within) == 0
    return drawn[:-1]                   # the last: the frame left on the screen after q


def test_the_terminal_animation_drops_frames_rather_than_fall_behind_real_time(monkeypatch):
    """The rhombus's 4 s run, 101 frames 0.04 s apart (the row's t = 0.04 i), animated for two
    passes: each frame drawn is the one due at the clock's time; where each takes 3.3 frames'
    time to draw, two or three frames in four are dropped and a pass still takes 4.04 s."""
    scene = linkage.load_scene(str(SCENES / "simulate-rhombus-moving.toml"))
    drawing = linkage.simulation_drawing(scene, linkage.scene_run(scene))
    count, seconds = len(drawing.frames), drawing.seconds
    assert count == 101 and seconds == pytest.approx(0.04)
    unloaded = frames_drawn(monkeypatch, drawing, 0.0, 2 * count * seconds)
    assert [i for _, i in unloaded] == list(range(count)) * 2
    assert all(abs(t - k * seconds) < 1e-9 for k, (t, _) in enumerate(unloaded))
    loaded = frames_drawn(monkeypatch, drawing, 3.3 * seconds, 2 * count * seconds)
    for t, i in loaded:             # the frame due at t: frame i shows the run's t = 0.04 i
        late = (t / seconds - i + 1e-6) % count         # frames since frame i was due
        assert late < 1.0 + 2e-6, (t, i)
    gaps = {(j - i) % count for (_, i), (_, j) in zip(loaded, loaded[1:])}
    assert gaps == {3, 4}
    wrap = next(k for k in range(1, len(loaded)) if loaded[k][1] < loaded[k - 1][1])
    assert loaded[wrap - 1][1] >= count - 4                     # the whole span shown ...
    assert count * seconds <= loaded[wrap][0] < (count + 4) * seconds   # ... in its 4.04 s
    assert len(loaded) == pytest.approx(2 * count / 3.3, abs=2)


def test_a_fast_run_is_drawn_at_most_25_frames_a_second():
    scene = linkage.load_scene(str(SCENES / "simulate-rhombus-moving.toml"))
    settings = scene.simulation._replace(step=0.01, time=1.0)
    scene = scene._replace(simulation=settings)
    drawing = linkage.simulation_drawing(scene, linkage.scene_run(scene))
    assert len(drawing.frames) == 26 and drawing.seconds == pytest.approx(0.04)


# -- bad input ---------------------------------------------------------------------------------------

RELEASED = (SCENES / "simulate-released-four-bar.toml").read_text()


def changed(old, new, text=RELEASED):
    assert old in text, old
    return text.replace(old, new)


BAD = [
    ("unassembled", changed("angle = 320", "angle = 90"),
     "the linkage does not assemble at the initial angle 90 degrees"),
    ("no inertia", changed("crank = { mass = 1.0 }\ncoupler = { mass = 0.5 }\n"
                           "output = { mass = 1.0 }\n", "").replace(
        "initial =", "torque = 1.0\ninitial ="), "the reduced inertia at the initial angle is zero"),
    ("nan", changed("time = 3.0", "time = nan"), "key 'simulation.time': expected a number"),
    ("negative tolerance", changed("tolerance = 1e-9", "tolerance = -1e-9"),
     "the tolerance must be above 0"),
    ("absurd time", changed("time = 3.0", "time = 1e12"), "the run's time (s) must be above 0 and "
                                                         "at most 1e+07"),
    ("too many rows", changed("step = 0.01", "step = 1e-9"), "rows, more than 1,000,000"),
    ("unknown key", changed("tolerance =", "tolerence ="), "unknown key 'simulation.tolerence'"),
    ("unknown spring key", changed("initial =", "spring = { between = [\"A\", \"B\"], k = 1, "
                                   "free_length = 1, c = 2 }\ninitial ="),
     "unknown key 'simulation.spring.c'"),
    ("bad spring point", changed("initial =", "spring = { between = [\"A\", \"Q\"], k = 1, "
                                 "free_length = 1 }\ninitial ="), "a spring's point is a joint"),
    ("bad torsion pivot", changed("initial =", "torsion = { at = \"A\", k = 1 }\ninitial ="),
     "key 'simulation.torsion.at'"),
    ("motor without free speed", changed("initial =", "motor = { stall_torque = 1 }\ninitial ="),
     "a motor line needs its free speed"),
    ("no initial", changed("initial = { angle = 320, speed = 0 }", ""),
     "key 'simulation.initial' is missing"),
    ("a speed in dynamics", changed("gravity = 9.81", "gravity = 9.81\nspeed = 100"),
     "key 'dynamics.speed': expected no speed with [simulation]"),
    ("an input range", changed("branches = [1]", "branches = [1]\ninput = { from = 0, to = 1, "
                                                 "step = 1 }"), "key 'input': expected no input"),
    ("follow", changed("branches = [1]", "branches = [\"follow\"]"),
     "key 'branches': expected [1] or [2]"),
    ("no dynamics", RELEASED[:RELEASED.index("[dynamics]")] + RELEASED[RELEASED.index(
        "[simulation]"):], "key 'dynamics' is missing"),
    ("bad panel", changed('quantities = ["phi"]', 'quantities = ["torque"]'),
     "key 'panels[1].quantities': expected a list of one or more of phi, omega"),
]


@pytest.mark.parametrize("name, text, message", BAD, ids=[b[0] for b in BAD])
def test_bad_input_is_one_line_and_nothing_written(tmp_path, name, text, message):
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    status, out, err = run(["scene", scene, "--csv", tmp_path / "run.csv",
                            "--png", tmp_path / "run.png"])
    assert status == 1 and not out
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert message in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_a_spatial_kind_runs_from_its_scene_and_keeps_its_energy(tmp_path):
    """The released double-rocker's scene made a spherical four-bar (simulate takes the spatial
    kinds since the simulation's core does): the run is written whole, its energy kept to the
    tolerance's order (the drift column: E - W - E0, against the energy's swing)."""
    scene = tmp_path / "spherical.toml"
    scene.write_text(changed('kind = "plane"\ndimensions = { a = 0.3, b = 0.25, c = 0.1, d = 0.2 }',
                             'kind = "spherical"\ndimensions = { a = 60, b = 20, c = 70, d = 50 }'
                             '\n'))
    status, _, err = run(["scene", scene, "--csv", tmp_path / "run.csv"])
    assert status == 0, err
    with open(tmp_path / "run.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    energy = [float(r["energy"]) for r in rows]
    assert len(rows) > 10 and max(energy) > min(energy)
    assert max(abs(float(r["drift"])) for r in rows) < 1e-6 * (max(energy) - min(energy) + 1.0)


def test_dir_is_refused_for_a_run_in_time(tmp_path):
    with pytest.raises(SystemExit) as stop, contextlib.redirect_stderr(io.StringIO()) as err:
        linkage.main(["scene", str(SCENES / "simulate-rhombus.toml"), "--dir", str(tmp_path / "d")])
    assert stop.value.code == 2 and "its rows go to --csv" in err.getvalue()
    assert not (tmp_path / "d").exists()
