"""A newcomer's first hour: the CSV export and the one-liners that read the original's DAT files,
a scene that writes only what it is asked for, one version and one spelling of each dimension."""

from __future__ import annotations

import csv
import importlib.metadata
import os
import struct
import subprocess
import sys
import tempfile
import tomllib

import pytest

from support import basic_runner
import linkage
from support.peers import Peer, lack
from support.program import PROGRAM, SCRIPT

numpy = Peer("numpy")

SCENES = basic_runner.ROOT / "data" / "scenes"
GOLDEN = basic_runner.ROOT / "data" / "golden"
# a skew slider-crank that cannot be assembled at 180 and 210 degrees
SKEW_SLIDER = ["run", "skew-slider", "--b", "2", "--c", "3", "--a", "1", "--f", "1", "--ksi", "60",
               "--from", "0", "--to", "360", "--step", "30", "--branch", "1"]


def run(args, directory) -> subprocess.CompletedProcess:
    return subprocess.run(PROGRAM + args, cwd=directory, capture_output=True, timeout=300)


def test_the_csv_of_a_double_run_has_every_point_with_its_status(tmp_path):
    result = run(SKEW_SLIDER + ["--precision", "double", "--csv", "out.csv"], tmp_path)
    assert result.returncode == 0, result.stderr
    assert b"wrote out.csv (13 rows)" in result.stderr
    with open(tmp_path / "out.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["phi", "output", "velocity", "acceleration", "status",
                             "transmission"]
    assert [float(r["phi"]) for r in rows] == [30.0 * i for i in range(13)]
    assert all((r["transmission"] == "nan") == (r["status"] != "assembled") for r in rows)
    missing = [r for r in rows if r["status"] != "assembled"]
    assert [(r["phi"], r["status"], r["output"]) for r in missing] == [
        ("180.0", "not-assembled", "nan"), ("210.0", "not-assembled", "nan")]
    ang = linkage.read_dat(str(tmp_path / "ANG.DAT"))   # the same numbers as the DAT files
    assert [(float(r["phi"]), float(r["output"])) for r in rows if r not in missing] == ang
    table = numpy.loadtxt(tmp_path / "out.csv", delimiter=",", skiprows=1, usecols=(0, 1, 2, 3))
    assert table.shape == (13, 4) and numpy.isnan(table[6, 1:]).all()


def test_the_csv_of_a_basic_run_holds_the_original_numbers_and_the_true_status(tmp_path):
    result = run(SKEW_SLIDER + ["--csv", "out.csv"], tmp_path)
    assert result.returncode == 0, result.stderr
    with open(tmp_path / "out.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    ang = linkage.read_dat(str(tmp_path / "ANG.DAT"))
    vel = linkage.read_dat(str(tmp_path / "VEL.DAT"))
    assert [(float(r["phi"]), float(r["output"])) for r in rows] == ang
    assert [float(r["velocity"]) for r in rows] == [v for _, v in vel]
    # the original writes zeros where there is no position; the status tells
    assert [r["status"] for r in rows if r["output"] == "0.0"] == ["not-assembled"] * 2


def test_the_csv_of_a_scene_has_a_row_a_point_of_each_series(tmp_path):
    result = run(["scene", str(SCENES / "hard-spike-180.toml"), "--csv", "s.csv"], tmp_path)
    assert result.returncode == 0, result.stderr
    assert sorted(os.listdir(tmp_path)) == ["s.csv"]      # no DAT file without --dir
    with open(tmp_path / "s.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0])[0] == "series"
    assert {r["series"] for r in rows} == {"basic-branch2", "double-branch2"}
    assert len(rows) == 2 * 5
    table = numpy.loadtxt(tmp_path / "s.csv", delimiter=",", skiprows=1, usecols=(1, 2, 3, 4))
    assert table.shape == (10, 4)


def test_a_scene_writes_dat_files_only_when_asked(tmp_path):
    result = run(["scene", str(SCENES / "fig3-plane-four-bar.toml"), "--text"], tmp_path)
    assert result.returncode == 0 and os.listdir(tmp_path) == []
    result = run(["scene", str(SCENES / "fig3-plane-four-bar.toml"), "--dir", "out"], tmp_path)
    assert result.returncode == 0 and b"wrote the DAT files of" in result.stderr
    assert sorted(os.listdir(tmp_path / "out")) == ["ACC.DAT", "ANG.DAT", "VEL.DAT"]


def test_a_mechanism_scene_has_no_csv(tmp_path):
    result = run(["scene", str(SCENES / "fig1a-plane-four-bar.toml"), "--csv", "x.csv"], tmp_path)
    assert result.returncode == 2 and b"draws the mechanism" in result.stderr


@pytest.mark.filterwarnings("ignore:loadtxt. input contained no data")
@pytest.mark.parametrize("case", ["plane-b1", "skew-slider-b1", "plane-reversed-range"])
def test_the_readme_one_liners_read_the_original_files(case):
    """README: numpy.loadtxt(path, delimiter=",", comments="\\x1a") and linkage.read_dat."""
    for name in ("ANG.DAT", "VEL.DAT", "ACC.DAT"):
        path = GOLDEN / case / name
        table = numpy.loadtxt(path, delimiter=",", comments="\x1a", ndmin=2)
        pairs = linkage.read_dat(str(path))
        assert [tuple(row) for row in table] == [(numpy.float64(x), numpy.float64(y))
                                                 for x, y in pairs]
        lines = path.read_bytes().split(b"\r\n")
        assert len(pairs) == len(lines) - 1 and lines[-1] == b"\x1a"


def test_one_version_everywhere(tmp_path):
    """--version, the module's __version__ and the installed distribution's (pyproject's name:
    the clean environment CI makes has only that one) agree."""
    result = run(["--version"], tmp_path)
    assert result.stdout.decode().strip() == f"linkage.py {linkage.__version__}"
    project = tomllib.loads((basic_runner.ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    try:
        installed = importlib.metadata.version(project["name"])
    except importlib.metadata.PackageNotFoundError:
        lack(f"needs {project['name']} installed (python3 -m pip install -e '.[test]')")
    assert installed == linkage.__version__


def test_ksi_is_the_one_spelling_and_skew_still_works(tmp_path):
    base = ["run", "skew", "--b", "2", "--c", "7", "--d", "9", "--a", "6", "--f", "1.5",
            "--from", "0", "--to", "90", "--step", "10", "--branch", "1"]
    (tmp_path / "new").mkdir()
    (tmp_path / "old").mkdir()
    new = run(base + ["--ksi", "25", "--dir", "new"], tmp_path)
    old = run(base + ["--skew", "25", "--dir", "old"], tmp_path)
    assert new.returncode == old.returncode == 0
    assert b"--skew is now --ksi" in old.stderr and b"--skew" not in new.stderr
    for name in ("ANG.DAT", "VEL.DAT", "ACC.DAT"):
        assert (tmp_path / "new" / name).read_bytes() == (tmp_path / "old" / name).read_bytes()
    help_text = run(["run", "--help"], tmp_path).stdout
    assert b"--ksi" in help_text and b"--skew" not in help_text.replace(b"--skew-", b"")


@pytest.mark.parametrize("argv, keys", [
    (["--version"], b""), (["run", "plane", "--a", "6"], b""), ([], b"12\r7\r9\r6\r0\r90\r45\r1"),
    (["design", "fourb-cr-4", "--psi", "60", "--mu-min", "40", "--svg", "d.svg"], b"")])
def test_the_tests_start_the_program_the_users_way(argv, keys, tmp_path):
    """PROGRAM (the tests' start from compiled bytecode) is `python3 linkage.py` (SCRIPT): the
    same output, files and exit status, on this checkout's linkage.py."""
    done = []
    for start in (SCRIPT, PROGRAM):
        folder = tmp_path / str(len(done))
        folder.mkdir()
        got = subprocess.run(start + argv, input=keys, cwd=folder, capture_output=True,
                             timeout=300)
        done.append((got.returncode, got.stdout, got.stderr,
                     {p.name: p.read_bytes() for p in folder.iterdir()}))
    assert done[0] == done[1]
    assert done[0][0] in (0, 2) and b"Traceback" not in done[0][2]


def _parsed(parser, argv) -> tuple:
    """What parser makes of argv: its values (the sub-command by its handler) or its exit
    status, and what it printed."""
    import contextlib
    import io
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            given = vars(parser.parse_args(argv))
            given.pop("parser", None)
            given["command_row"] = given["command_row"].handler
            got: object = given
        except SystemExit as e:
            got = e.code
    return got, out.getvalue(), err.getvalue()


def test_the_parser_made_for_a_command_line_parses_it_as_the_whole_parser():
    """main builds the sub-parsers' options only for the sub-commands argv names (build_parser
    (argv)): every command's help, its refusals and the top parser's (its usage lists every
    command) are the whole parser's, word for word."""
    whole = linkage.build_parser()
    methods = list(linkage.METHODS)
    cases = [["--help"], ["--version"], ["x"], ["design", "--help"], ["design", "nosuch"],
             ["design", methods[0], "--help"], ["design", methods[-1], "--psi", "x"],
             ["design", methods[1]]]
    for name, command in linkage.COMMANDS.items():
        cases += [[name, "--help"], ["--nosuch", name, "x"]] + [[a] for a in command.aliases]
    cases += [["run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9", "--from", "0",
               "--to", "90", "--step", "10", "--branch", "1"], ["scene", "fig3", "design"]]
    for argv in cases:
        assert _parsed(linkage.build_parser(argv), argv) == _parsed(whole, argv), argv


def test_the_test_run_is_derandomized_unless_asked_to_explore():
    """The README's test command is CI's run: the same examples every time (LINKAGE_EXPLORE=1
    explores)."""
    import hypothesis
    assert hypothesis.settings().derandomize == (not os.environ.get("LINKAGE_EXPLORE"))


def _two_curve_figure(second):
    """A one-panel figure of velocity (0 everywhere) and `second`, as the text plot draws it."""
    xs = [float(x) for x in range(0, 361, 10)]
    curve = lambda quantity, ys: linkage.Curve(quantity, quantity, "basic", 1,
                                               (tuple(zip(xs, ys)),))
    panel = linkage.Panel("b", ("velocity", "acceleration"),
                          (("velocity", "v", "rad/rad"), ("acceleration", "a", "rad/rad^2")),
                          (curve("velocity", [0.0] * len(xs)),
                           curve("acceleration", [second(x) for x in xs])), None)
    return linkage.text_figure(linkage.Figure("t", "s", ("input angle", "phi", "deg"), (panel,)))


def test_a_curve_under_another_stays_visible():
    """Where the acceleration lies on the velocity the cells show # (not the acceleration's o
    alone), and the line under the plot says what # is; apart, each keeps its marker."""
    together = _two_curve_figure(lambda x: 0.0 if x < 180 else 2.0)
    rows = [line for line in together.splitlines() if "#" in line]
    assert rows and together.splitlines()[-1].endswith("# = two curves")
    apart = _two_curve_figure(lambda x: 2.0)
    assert "#" not in apart and "*" in apart and "o" in apart


@pytest.mark.slow          # --quick leaves it out: renders PNGs
def test_png_size_and_dpi(tmp_path, monkeypatch, capsys):
    """(In this process: a PNG written by the program's process is test_scenes'
    test_a_curve_scene_says_the_png_it_wrote, and the README's commands.)"""
    monkeypatch.chdir(tmp_path)
    scene = str(SCENES / "fig3-plane-four-bar.toml")
    assert linkage.main(["scene", scene, "--png", "a.png", "--size", "1200x900"]) == 0
    assert linkage.main(["scene", scene, "--png", "b.png", "--dpi", "180"]) == 0
    assert linkage.main(["scene", scene, "--png", "c.png"]) == 0
    size = {n: struct.unpack(">II", (tmp_path / n).read_bytes()[16:24]) for n in
            ("a.png", "b.png", "c.png")}
    assert size["a.png"] == (1200, 900)
    assert size["c.png"][0] == 648 and size["b.png"] == (2 * size["c.png"][0],
                                                          2 * size["c.png"][1])
    capsys.readouterr()
    with pytest.raises(SystemExit) as refused:
        linkage.main(["plot", ".", "--size", "10x10"])
    assert refused.value.code == 2 and "WIDTHxHEIGHT" in capsys.readouterr().err


def test_main_gives_back_the_signal_handlers_it_installed(tmp_path, capsys):
    """main() turns SIGTERM and SIGHUP into an interrupt while it runs, and only then: a caller
    in the same process (pytest itself) keeps its own handlers."""
    import signal
    mine = {s: (lambda *a: None) for s in (signal.SIGTERM, signal.SIGHUP)}
    saved = {s: signal.signal(s, h) for s, h in mine.items()}
    try:
        assert linkage.main(["analyse", "plane", "--a", "6", "--b", "2", "--c", "7",
                             "--d", "9"]) == 0
        assert linkage.main(["analyse", "plane", "--a", "6", "--b", "1", "--c", "1",
                             "--d", "1"]) == 1          # a run that fails gives them back too
        for s, h in mine.items():
            assert signal.getsignal(s) is h
    finally:
        for s, h in saved.items():
            signal.signal(s, h)


def test_the_installed_command_stops_quietly_when_its_reader_stops():
    """The `linkage` command calls main() itself (no __main__ guard): a reader that stops
    (`| head`) ends it with status 141 and nothing on standard error, as for a shell tool."""
    program = [sys.executable, "-c", "import sys, linkage; sys.exit(linkage.main(sys.argv[1:]))",
               "run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9", "--from", "0",
               "--to", "360", "--step", ".001", "--branch", "1", "--precision", "double",
               "--csv", "-", "--dir", "{dir}"]
    with tempfile.TemporaryDirectory() as where:
        child = subprocess.Popen([w.replace("{dir}", where) for w in program],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 cwd=basic_runner.ROOT)
        assert child.stdout.readline().startswith(b"phi,")
        child.stdout.close()
        stderr = child.stderr.read()
        assert child.wait(timeout=120) == 141, stderr
        assert stderr == b""


@pytest.mark.parametrize("argv, why", [
    ("plane --a 6 --b 2 --c 1 --d 1", "the fixed link DIAG = 6 is longer than BT + CT + DT = 4"),
    ("plane --a 1 --b 2 --c 9 --d 1", "the connecting rod CT = 9 is longer than DIAG + BT + DT = 4"),
    ("spherical --a 100 --b 20 --c 30 --d 40",          # 100 > 20 + 30 + 40, in degrees
     "the fixed link DIAG = 100 degrees is longer than BT + CT + DT = 90 degrees"),
    ("spherical --a 280 --b 20 --c 30 --d 40",          # 280 modulo 180 is 100 (ERRATA K11),
     "the fixed link DIAG = 99.9999"),                  # in single precision
    ("skew --a 6 --b 2 --c 20 --d 1 --f 1 --ksi 30",     # DIAG = (36 + tan^2 30)^.5 = 6.027714
     "the connecting rod CT = 20 is longer than DIAG + BT + DT = 9.02771"),
    ("skew-slider --a 6 --b 2 --c 20 --f 1 --ksi 30",    # DT never asked: 0 (ERRATA K4)
     "the connecting rod CT = 20 is longer than DIAG + BT + DT = 8.02771"),
])
def test_run_says_why_a_linkage_is_illegal(tmp_path, argv, why):
    """The menu says only "Illegal linkage (impossible to assemble)", as the original; run says
    which link line 480 finds longer than the other three together, and writes nothing."""
    got = subprocess.run(PROGRAM + ["run", *argv.split(), "--from", "0", "--to", "360",
                                    "--step", "10", "--branch", "1", "--dir", str(tmp_path)],
                         capture_output=True, text=True)
    assert got.returncode == 1 and not list(tmp_path.iterdir())
    assert got.stderr.startswith("linkage.py: Illegal linkage (impossible to assemble): "
                                 f"line 480: {why}"), got.stderr


def test_the_basic_csv_marks_the_points_the_original_clipped(tmp_path):
    """The original clips VEL and ACC to +-3 (ERRATA K9): its spike at phi = 180 (K6) and the
    rates near the plane four-bar's dead centres are written as +-3. Those rows say `clipped`;
    the engine's rates there are beyond 3 (or, at 180, the spike is the listing's own)."""
    got = subprocess.run(PROGRAM + ["run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9",
                                    "--from", "0", "--to", "360", "--step", "2", "--branch", "1",
                                    "--dir", str(tmp_path), "--csv", "-"],
                         capture_output=True, text=True)
    rows = list(csv.DictReader(got.stdout.splitlines()))
    clipped = [r for r in rows if r["status"] == "clipped"]
    assert [(round(float(r["phi"]), 3), r["acceleration"]) for r in clipped] == [(180, "-3.0")]
    assert all(r["status"] == "assembled" for r in rows if r not in clipped)
    rocker = subprocess.run(PROGRAM + ["run", "plane", "--a", "4", "--b", "3.9", "--c", "1.1",
                                       "--d", "1", "--from", "0", "--to", "360", "--step", "1",
                                       "--branch", "1", "--dir", str(tmp_path), "--csv", "-"],
                            capture_output=True, text=True)
    rows = list(csv.DictReader(rocker.stdout.splitlines()))
    at_three = [r for r in rows if "3.0" in (r["velocity"].lstrip("-"),
                                             r["acceleration"].lstrip("-"))]
    assert at_three and all(r["status"] in ("clipped", "not-assembled", "dead-centre")
                            for r in at_three)
    assert {r["status"] for r in at_three} >= {"clipped"}


@pytest.mark.parametrize("precision", ["basic", "double"])
def test_run_makes_a_missing_output_folder_as_scene_does(tmp_path, precision):
    argv = PROGRAM + ["run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9", "--from", "0",
                      "--to", "360", "--step", "90", "--branch", "1", "--precision", precision]
    got = subprocess.run(argv + ["--dir", str(tmp_path / "new" / "folder")], capture_output=True)
    assert got.returncode == 0, got.stderr
    assert sorted(p.name for p in (tmp_path / "new" / "folder").iterdir()) == [
        "ACC.DAT", "ANG.DAT", "VEL.DAT"]
    (tmp_path / "file").write_text("in the way")
    got = subprocess.run(argv + ["--dir", str(tmp_path / "file" / "x")], capture_output=True,
                         text=True)
    assert got.returncode == 2 and "cannot make the folder: Not a directory" in got.stderr
    assert (tmp_path / "file").read_text() == "in the way"


@pytest.mark.parametrize("argv, option", [
    (["scene", "fig3", "--dir", "{folder}"], "--dir"),
    (["design", "fourb-cr-4", "--psi", "60", "--mu-min", "40", "--dat", "{folder}"], "--dat"),
])
def test_scene_and_design_follow_runs_folder_rule(tmp_path, argv, option):
    """One rule for an output folder: made if missing (with its parents), refused with exit
    status 2 and the same words as run's where a file is in the way."""
    made = tmp_path / "new" / "folder"
    got = subprocess.run(PROGRAM + [a.replace("{folder}", str(made)) for a in argv],
                         capture_output=True, text=True, cwd=tmp_path)
    assert got.returncode == 0, got.stderr
    assert sorted(p.name for p in made.iterdir()) == ["ACC.DAT", "ANG.DAT", "VEL.DAT"]
    (tmp_path / "file").write_text("in the way")
    got = subprocess.run(PROGRAM + [a.replace("{folder}", str(tmp_path / "file" / "x"))
                                    for a in argv], capture_output=True, text=True, cwd=tmp_path)
    assert got.returncode == 2
    assert f"{option} '{tmp_path / 'file' / 'x'}': cannot make the folder: Not a directory" \
        in got.stderr


# ---- hostile numbers (issue 35, item 5) ---------------------------------------------------------

CURVE_SCENE = ('title = "t"\nmechanism = "plane"\ndimensions = {{ a = 6, b = 2, c = 7, d = 9 }}\n'
               'input = {{ from = 0, to = 360, step = 10 }}\nbranches = [1]\n'
               'precision = "double"\n\n[[panels]]\nquantities = ["displacement"]\n'
               'limits = {limits}\n')
MECHANISM_SCENE = ('title = "t"\nmechanism = "plane"\ndimensions = {{ a = 6, b = 2, c = 7, d = 9 }}'
                   '\ninput = {{ from = 0, to = 360, step = 30 }}\nbranches = [{branch}]\n\n'
                   '[[panels]]\nquantities = ["mechanism"]\n')


def refused_in_one_line(result: subprocess.CompletedProcess, *words: bytes) -> None:
    assert result.returncode == 1, result.stderr
    assert b"Traceback" not in result.stderr and result.stderr.count(b"\n") == 1, result.stderr
    assert all(w in result.stderr for w in words), result.stderr


@pytest.mark.parametrize("limits", ["[-1e308, 1e308]", "[0, 1e-320]", "[-1e101, 0]",
                                    "[1, 1.0000000000000002]"])
@pytest.mark.parametrize("png", [False, True])
def test_a_panel_whose_limits_cannot_be_drawn_is_refused(limits, png, tmp_path):
    """Issue 35, item 5: limits = [-1e308, 1e308] ended in OverflowError (the text plot) or
    ValueError (--png), [0, 1e-320] in a math domain error. They are refused, naming the key,
    and nothing is written."""
    (tmp_path / "s.toml").write_text(CURVE_SCENE.format(limits=limits))
    result = run(["scene", "s.toml"] + (["--png", "o.png"] if png else []), tmp_path)
    refused_in_one_line(result, b"panels[1].limits")
    assert sorted(os.listdir(tmp_path)) == ["s.toml"]


def test_limits_at_the_ends_of_the_drawn_range_are_drawn(tmp_path):
    (tmp_path / "s.toml").write_text(CURVE_SCENE.format(limits="[-1e100, 1e100]"))
    result = run(["scene", "s.toml"], tmp_path)
    assert result.returncode == 0 and b"Traceback" not in result.stderr, result.stderr


@pytest.mark.parametrize("png", [False, True])
def test_values_closer_than_an_axis_divides_are_drawn_as_one(png, tmp_path):
    """Issue 35, item 5: an ANG.DAT holding 0,0 and 1,5E-324 ended in "math domain error" (the
    y axis divided a span of 5e-324). Values that close are one value on the axis: drawn."""
    (tmp_path / "ANG.DAT").write_bytes(b"0,0\r\n1,5E-324\r\n\x1a")
    result = run(["plot", "."] + (["--png", "o.png"] if png else []), tmp_path)
    assert result.returncode == 0 and b"Traceback" not in result.stderr, result.stderr
    if png:
        assert (tmp_path / "o.png").read_bytes().startswith(b"\x89PNG")
    else:
        assert b"(a) output ANG.DAT" in result.stdout


@pytest.mark.parametrize("optimised", [[], ["-O"]])
def test_a_mechanism_scene_takes_the_branches_a_curve_scene_takes(optimised, tmp_path):
    """Issue 35, item 5: branches = [1.0], which a curve scene takes as branch 1, ended a
    mechanism scene in AssertionError (and drew, unchecked, under python3 -O). It is branch 1:
    the same drawing as branches = [1]."""
    start = [sys.executable] + optimised + PROGRAM[1:]
    drawn = {}
    for branch in ("1", "1.0"):
        (tmp_path / "m.toml").write_text(MECHANISM_SCENE.format(branch=branch))
        done = subprocess.run(start + ["scene", "m.toml", "--frames", "2"], cwd=tmp_path,
                              capture_output=True, timeout=120)
        assert done.returncode == 0 and b"Traceback" not in done.stderr, done.stderr
        drawn[branch] = done.stdout
    assert drawn["1.0"] == drawn["1"]
    (tmp_path / "m.toml").write_text(MECHANISM_SCENE.format(branch="1.5"))
    done = subprocess.run(start + ["scene", "m.toml"], cwd=tmp_path, capture_output=True,
                          timeout=120)
    refused_in_one_line(done, b"branches")


@pytest.mark.parametrize("dtheta", ["5e-324", "1e-300", "359.99999999999994"])
def test_a_design_datum_its_formula_cannot_take_is_refused(dtheta, tmp_path):
    """Issue 35, item 5: design slid-fg2-1 --dtheta 5e-324 ended in ZeroDivisionError (cot of a
    crank rotation that rounds to 0). Refused in one line naming dtheta; nothing written."""
    result = run(["design", "slid-fg2-1", "--dtheta", dtheta, "--ds", "28.2", "--epsilon", "1",
                  "--dat", "dd"], tmp_path)
    refused_in_one_line(result, b"dtheta")
    assert result.stdout == b""
    assert not (tmp_path / "dd").exists() or os.listdir(tmp_path / "dd") == []


# ---- small things (issue 35, item 7) ------------------------------------------------------------

@pytest.mark.parametrize("option", ["--svg", "--png"])
def test_a_full_device_is_named_not_called_standard_output(option, tmp_path):
    """Issue 35, item 7: `scene fig1a --svg /dev/full` said "standard output: No space left on
    device". The message names the file."""
    result = run(["scene", "fig1a", option, "/dev/full"], tmp_path)
    assert result.returncode == 1
    assert result.stderr == b"linkage.py: /dev/full: No space left on device\n"


def test_scene_list_takes_no_output(tmp_path):
    """Issue 35, item 7: `scene --list --png x` listed the scenes and ignored --png (exit 0)."""
    for extra in (["--png", "x"], ["--csv", "x"], ["--dir", "x"], ["--text"]):
        result = run(["scene", "--list"] + extra, tmp_path)
        assert result.returncode == 2 and extra[0].encode() in result.stderr
        assert b"Traceback" not in result.stderr and result.stdout == b""
    assert os.listdir(tmp_path) == []


def test_a_one_point_png_is_drawn_without_a_warning(tmp_path):
    """Issue 35, item 7: a PNG of one point printed matplotlib's UserWarning "Attempting to set
    identical low and high xlims" on standard error."""
    (tmp_path / "ANG.DAT").write_bytes(b"0,1\r\n\x1a")
    result = run(["plot", ".", "--png", "one.png"], tmp_path)
    assert result.returncode == 0
    assert result.stderr == b"linkage.py: wrote one.png\n"
    assert (tmp_path / "one.png").read_bytes().startswith(b"\x89PNG")


# -- the command line as data: one typed value a command, its "goes with" rules as rows --------

def _flags_and_choices(command) -> dict[str, tuple | None]:
    """Each flag of a COMMANDS row: the values it may hold (its choices), None where any."""
    return {flag: tuple(o.settings["choices"]) if "choices" in o.settings else None
            for o in command.options for flag in o.names if flag.startswith("-")}


def test_every_rule_names_flags_and_values_its_command_has():
    """A rule that names a flag the command lacks (a typo, an option renamed) would never fire:
    each side of every rule is one of its command's flags, with values among its choices."""
    rules = 0
    for name, command in linkage.COMMANDS.items():
        flags = _flags_and_choices(command)
        for rule in command.rules:
            for side in (rule.given, *rule.needs):
                flag, _, values = side.partition(" ")
                assert flag in flags, (name, side)
                for value in values.split(" or ") if values else ():
                    assert flags[flag] is None or value in flags[flag], (name, side)
                rules += 1
    assert rules >= 10


@pytest.mark.parametrize("typed, expected", [
    ({"--branch": "follow", "--precision": "basic"},
     "--branch follow goes with --precision double (the original program has branches 1 and 2 "
     "only)"),
    ({"--branch": "follow", "--precision": "double", "--fast": True},
     "--fast goes with --branch 1 or 2 (the vectorised path computes the listing's branches)"),
    ({"--branch": "2", "--precision": "double", "--fast": True}, None),
    ({"--branch": "1", "--start-branch": "2", "--precision": "double"},
     "--start-branch goes with --branch follow"),
    ({"--branch": "1", "--coupler": ["1"], "--precision": "double"},
     "--coupler goes with --csv (it adds columns to the CSV: give --csv OUT too)"),
    ({"--branch": "1", "--coupler": ["1"], "--precision": "double", "--csv": "x.csv"}, None),
])
def test_broken_rule_reads_the_rows_as_they_read(typed, expected):
    """broken_rule on run's rows: the first rule broken, said as the row reads; a default
    (--precision basic) counts as held, a flag not typed as not given."""
    values = {"--precision": "basic", **typed}
    assert linkage.broken_rule(linkage.COMMANDS["run"].rules, values, set(typed)) == expected


def test_no_handler_rebinds_what_it_was_given():
    """Handlers take their command's typed value (a NamedTuple) and never assign to it: no
    `args.x = ...` anywhere in the program."""
    import ast
    tree = ast.parse(open(linkage.__file__, encoding="utf-8").read())
    rebound = [node.lineno for node in ast.walk(tree) if isinstance(node, ast.Assign)
               for target in node.targets if isinstance(target, ast.Attribute)
               and isinstance(target.value, ast.Name) and target.value.id == "args"]
    assert rebound == []
    for name, command in linkage.COMMANDS.items():
        hints = command.handler.__annotations__
        assert hints.get("args") not in (None, "argparse.Namespace"), name


@pytest.mark.parametrize("argv, message", [
    (["explore", "--size", "100x30"], b"--size goes with --keys"),
    (["bench", "engine", "--png", "x.png"], b"--png goes with bench accuracy"),
    (["run", "slider", "--b", "1", "--c", "3", "--e", "0", "--from", "0", "--to", "10",
      "--step", "5", "--branch", "1", "--clip"], b"--clip goes with --precision double"),
])
def test_a_rule_broken_is_a_usage_error_before_any_work(argv, message, tmp_path):
    result = run(argv, tmp_path)
    assert result.returncode == 2 and message in result.stderr, result.stderr
    assert b"usage:" in result.stderr and os.listdir(tmp_path) == []


_THREADS_AFTER_A_FAST_RUN = """
import os, sys
sys.path.insert(0, sys.argv[1])
import linkage
sys.argv = ["linkage.py", "run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9",
            "--from", "0", "--to", "10", "--step", "1", "--branch", "1", "--precision", "double", "--fast",
            "--dir", sys.argv[2]]
status = linkage.main()
print(status, "numpy" in sys.modules, len(os.listdir("/proc/self/task")),
      os.environ.get("OPENBLAS_NUM_THREADS"))
"""


@pytest.mark.parametrize("given, threads", [(None, 1), ("2", 2)])
def test_the_programs_numpy_starts_no_blas_threads_unless_asked(tmp_path, given, threads):
    """The program's process (main with argv None, as `python3 linkage.py` runs it) imports
    numpy for --fast with OpenBLAS held to the one thread (the program multiplies no matrices;
    the pool's start cost a third of numpy's import); a user's OPENBLAS_NUM_THREADS is kept.
    Counted as the process's threads after the run: OpenBLAS starts one a core (CI has two)."""
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS",
                                                              "OMP_NUM_THREADS")}
    if given:
        env["OPENBLAS_NUM_THREADS"] = given
    run = subprocess.run([sys.executable, "-c", _THREADS_AFTER_A_FAST_RUN,
                          os.path.dirname(SCRIPT[1]), str(tmp_path)],
                         capture_output=True, text=True, env=env, check=True)
    status, imported, count, variable = run.stdout.split()
    assert (status, imported) == ("0", "True"), run.stderr
    assert (int(count), variable) == (threads, given or "1")
    assert (tmp_path / "ANG.DAT").exists()
