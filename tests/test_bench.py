"""The benchmarks. The accuracy bench's machinery (tests/support/bench_accuracy.py), on a tiny
sweep: it scores the engine within the bounds tests/test_engine.py asserts and the faithful program
at single precision's error, it counts the points where the listing fails apart from the errors,
PC-BASIC's row agrees with the port's, and a missing mpmath or PC-BASIC is said, not a traceback.
And linkage.py's own benchmarks run with nothing of tests/: the program stands without its tests.
No time is asserted: the benchmarks print times."""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import linkage
import support
from support import basic_runner, bench_accuracy
from test_engine import TOL

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

ROOT = Path(__file__).resolve().parent.parent

# (label, kind, dims, input angles): each point is an angle on one branch, so 16 points here.
TINY = [
    ("crank-rocker", "plane", dict(a=6.0, b=2.0, c=7.0, d=9.0), [41.0, 180.0]),  # K6 at 180
    ("change-point", "plane", dict(a=4.0, b=2.0, c=3.0, d=5.0), [0.0, 10.0]),    # K7 at 0
    ("slider", "slider", dict(b=2.0, c=7.0, e=1.5), [97.0, 233.0]),
    # ksi = 90: line 400's TAN(KSI) overflows and line 480 refuses the linkage
    ("skew-slider-ksi-90", "skew-slider", dict(a=-1.5, b=2.0, c=7.0, f=0.0, ksi=90.0), [90.0]),
    ("spherical", "spherical", dict(a=80.0, b=20.0, c=75.0, d=60.0), [233.0]),
]
POINTS = 2 * sum(len(phis) for *_, phis in TINY)
# velocity 6.3 and -5.3, acceleration -62.5 and 62.5 on the two branches: the listing writes +-3
CLIPPED = [("double-rocker", "plane", dict(a=2.0, b=2.0, c=2.0, d=0.5), [-75.0])]
COLUMNS = {"angle": TOL["output"], "position": TOL["slider-output"],
           "velocity": TOL["velocity"], "acceleration": TOL["acceleration"]}


@pytest.fixture(scope="module")
def tallies():
    rows = bench_accuracy.measure_accuracy(TINY, TINY, repeats=1)
    return dict(zip(("faithful", "listing", "engine", "mp30", "mp50", "basic"), rows))


def test_every_row_is_measured_on_every_point(tallies):
    assert [t.method for t in tallies.values()] == list(bench_accuracy.ACCURACY_METHODS)
    for name, t in tallies.items():
        assert t.points == POINTS, name
        assert t.seconds is not None and t.seconds > 0, name
    assert tallies["engine"].computed == POINTS
    # the listing refuses skew-slider-ksi-90: neither the port nor PC-BASIC computes it
    assert tallies["faithful"].computed == tallies["basic"].computed == POINTS - 2


def test_the_engine_is_within_test_engines_bounds(tallies):
    engine = tallies["engine"]
    assert engine.failures == {}
    assert set(engine.worst) == set(COLUMNS)
    for column, bound in COLUMNS.items():
        assert engine.worst[column][0] <= bound, (column, engine.worst[column])


def test_the_faithful_program_has_single_precisions_error(tallies):
    """Seven written digits and 24-bit arithmetic: the angle is off by 1e-7 to 1e-3 degree, far
    above the engine's bound; at 180 degrees the listing's spike (K6) is the worst velocity."""
    faithful, engine = tallies["faithful"], tallies["engine"]
    angle = faithful.worst["angle"][0]
    assert 1e-7 <= angle <= 1e-3, faithful.worst
    assert 1e-9 <= faithful.worst["position"][0] <= 1e-5, faithful.worst
    for column in COLUMNS:
        assert faithful.worst[column][0] >= 1000 * COLUMNS[column], (column, faithful.worst)
        assert faithful.worst[column][0] >= 1000 * engine.worst[column][0], column
    error, where = faithful.worst["velocity"]
    assert error >= 0.25 and where.startswith("crank-rocker 180.0/"), faithful.worst


def test_failures_are_counted_apart_from_the_errors(tallies):
    faithful, listing = tallies["faithful"], tallies["listing"]
    assert faithful.failures[bench_accuracy.ILLEGAL] == 2      # skew-slider-ksi-90, both branches
    assert faithful.failures[bench_accuracy.DIVISION] >= 1     # the change point at 0 (K7)
    assert listing.failures[bench_accuracy.DIVISION] >= 1
    for t in (faithful, listing):
        for error, where in t.worst.values():
            assert not where.startswith("change-point 0.0/"), (t.method, where)
            assert error < 1e30                                    # no 1.701412E+38 in the errors
    # the engine says change-point there: not a failure, and its values (the limits) are compared
    assert tallies["engine"].failures == {}


def test_ratios_beyond_3_are_compared_clipped():
    """The listing clips VEL and ACC to +-3 (K9): there its 3 is right, and the bench counts the
    values it compared so."""
    faithful = bench_accuracy.measure_accuracy(CLIPPED, None, repeats=1)[0]
    assert faithful.beyond_clip == 4 and faithful.failures == {}
    assert faithful.worst["velocity"][0] <= 1e-5 and faithful.worst["acceleration"][0] <= 1e-5


def test_the_reference_rows(tallies):
    """The 50-digit reference against an 80-digit run, the 30-digit run against the reference:
    each good to its digits."""
    for name, bound in (("mp50", 1e-45), ("mp30", 1e-25)):
        t = tallies[name]
        assert t.failures == {} and set(t.worst) == set(COLUMNS), name
        for column, (error, where) in t.worst.items():
            assert error <= bound, (name, column, error, where)


def test_pcbasic_row_is_the_ports(tallies):
    """PC-BASIC's files, with the soft errors read from each session's part of the screen, score
    as the port's lines: the same failures, the same worst errors to the last written digit."""
    faithful, basic = tallies["faithful"], tallies["basic"]
    assert basic.failures == faithful.failures
    assert basic.worst.keys() == faithful.worst.keys()
    for column, (error, _) in basic.worst.items():
        assert error == pytest.approx(faithful.worst[column][0], rel=1e-5, abs=1e-6), column


def test_missing_mpmath_and_pcbasic_are_said(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "mpmath", None)               # import mpmath fails
    monkeypatch.delitem(sys.modules, "support.engine_reference", raising=False)
    monkeypatch.delattr(support, "engine_reference", raising=False)    # imported afresh
    monkeypatch.setattr(basic_runner, "pcbasic_command",
                        lambda: [sys.executable, "-m", "no_pcbasic_here"])
    rows = bench_accuracy.measure_accuracy(TINY[:1], TINY[:1], repeats=1)
    faithful, listing, engine, mp30, mp50, basic = rows
    assert "mpmath is not installed" in mp30.note and "mpmath is not installed" in mp50.note
    assert mp30.seconds is None and mp50.seconds is None
    assert basic.note.startswith("PC-BASIC is not installed") and basic.seconds is None
    for t in (faithful, listing, engine):
        assert t.seconds is not None and t.worst == {} and "mpmath" in t.unscored
    bench_accuracy.print_accuracy_table(rows, sys.stdout)
    printed = capsys.readouterr().out
    assert "mpmath is not installed" in printed and "PC-BASIC is not installed" in printed


QUICK_ARGS = ["bench", "all", "--quick"]     # the README's command (run here, not in test_readme)


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    """`bench all --quick` as a user runs it, from linkage.py copied alone (with legacy_basic/ for
    PC-BASIC's run), isolated (-I: neither the folder nor PYTHONPATH on its path) and every
    module of tests/ and tests/support/ refused at import: its standard output."""
    folder = tmp_path_factory.mktemp("alone")
    shutil.copy(linkage.__file__, folder / "linkage.py")
    shutil.copytree(ROOT / "legacy_basic", folder / "legacy_basic")
    refused = sorted({p.stem for p in (ROOT / "tests").glob("**/*.py")} | {"support"})
    code = textwrap.dedent(f"""
        import importlib.abc, runpy, sys
        class Refuse(importlib.abc.MetaPathFinder):
            def find_spec(self, name, path=None, target=None):
                if name.split(".")[0] in {refused!r}:
                    raise ImportError(f"linkage.py imported {{name}} from tests/")
        sys.meta_path.insert(0, Refuse())
        sys.argv = ["linkage.py"] + sys.argv[1:]
        runpy.run_path("linkage.py", run_name="__main__")
    """)
    run = subprocess.run([sys.executable, "-I", "-c", code, *QUICK_ARGS],
                         capture_output=True, text=True, cwd=folder, timeout=300)
    assert run.returncode == 0 and "Traceback" not in run.stderr, run.stderr
    return run.stdout


def test_the_programs_benchmarks_run_without_tests(quick_run):
    """Each bench name runs with nothing of tests/ (--quick: tiny sizes), the port writes
    PC-BASIC's bytes, and `bench accuracy` names the script that measures it."""
    for name in linkage.BENCHMARKS:
        assert f"\n== {name}: " in quick_run, name
    assert "the DAT files and the screen are identical" in quick_run
    # bench accuracy, the program's own ladder, names the tests' (against mpmath) beside it
    assert bench_accuracy.COMMAND in quick_run


def summary_rows(text):
    """The rows of the first markdown table after "## Summary" (data/BENCHMARKS.md) or after
    "== the README's speed table" (bench all's output): lists of their cells."""
    lines = text.split("\n## Summary\n" if "\n## Summary\n" in text
                       else "\n== the README's speed table", 1)[1].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("|"))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
    return rows


def test_bench_all_prints_every_row_of_the_readmes_speed_table(quick_run):
    """Every row of the table the README's "Speed and accuracy" points to (data/BENCHMARKS.md,
    "Summary") has its line in `bench all`'s table, in order: what, a figure, the load average
    where the program measured it, the command that makes it; the figures the program leaves to
    the tests' scripts (a C loop, pylinkage, mpmath) name the script."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "data/BENCHMARKS.md#summary" in readme
    documented = summary_rows((ROOT / "data" / "BENCHMARKS.md").read_text(encoding="utf-8"))
    printed = summary_rows(quick_run)
    assert [row[0] for row in printed] == [row[0] for row in documented]
    assert [row[0] for row in documented] == [row[0] for row in linkage.SPEED_TABLE]
    for (what, bench, command), (_, figure, load, shown) in zip(linkage.SPEED_TABLE, printed):
        assert figure and shown == f"`{command}`", what
        if bench is None:
            assert "run the command" in figure and "support." in command, what
        else:
            assert any(c.isdigit() for c in figure), what
            low, high = load.split("-")
            assert float(low) >= 0 and float(high) >= 0, what


def test_bench_all_is_bench_without_a_name():
    """`bench all` and `bench` are the same command; all named beside another bench is refused."""
    given = dict(quick=True, png=None)
    assert linkage.bench_options(given | {"names": ["all"]}) == \
        linkage.bench_options(given | {"names": []})
    with pytest.raises(linkage.UsageError, match="bench all runs every bench"):
        linkage.bench_options(given | {"names": ["all", "port"]})


def test_the_accuracy_script_runs_as_a_script():
    """The accuracy bench run as the README says (bench_accuracy.COMMAND, from the repository's
    root) finds this checkout's program and its instruments: one random point a kind (the whole
    run takes minutes)."""
    env = {**os.environ, "PYTHONPATH": "tests"}
    command = [sys.executable, *bench_accuracy.COMMAND.split()[2:], "--random", "1", "1"]
    run = subprocess.run(command, env=env, capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert run.returncode == 0, run.stderr
    said = run.stdout.splitlines()
    assert said[0] == f"$ {bench_accuracy.COMMAND} --random 1 1"
    assert said[1].startswith(f"linkage.py {linkage.__version__} on ")
    assert [line.split(":")[0] for line in said if not line.startswith((" ", "$", "linkage",
                                                                        "random"))] == \
        list(bench_accuracy.engine_harness.KINDS)


PORT_ROWS = ("python3 -m linkage", "python3 linkage.py", "in this process")


def test_bench_port_runs_both_as_programs_and_compares_their_bytes(quick_run):
    """bench port starts the port (as the module from cached bytecode and as the script) and
    PC-BASIC as programs on the same keys, reports the CPU ratio of the programs with the
    in-process one beside it, and finds their DAT files and screens the same bytes. (Its part
    of quick_run's `bench all --quick`, which runs bench_port(quick=True) as this test did.)"""
    text = quick_run.split("\n== port: ", 1)[1].split("\n== ", 1)[0]
    assert "the DAT files and the screen are identical" in text, text
    assert "times faster than PC-BASIC by CPU time" in text and "in this process, " in text
    assert "user and system of the child process" in text
    rows = {line.split("  ")[0] for line in text.splitlines()}
    assert set(PORT_ROWS) | {"PC-BASIC"} <= rows, text


def test_bench_port_says_which_bytes_differ(tmp_path):
    """A "PC-BASIC" that writes other bytes is caught, file by file; one that is missing is
    said, and the port's rows are still shown."""
    fake = tmp_path / "fake_pcbasic.py"
    fake.write_text("import sys\n"
                    "for name in ('ANG.DAT', 'VEL.DAT'):\n"
                    "    open(name, 'wb').write(b'0,0\\r\\n\\x1a')\n"
                    "open('ACC.DAT', 'wb').write(open('ANG.DAT', 'rb').read())\n"
                    "sys.stdout.write('Enter Option: _')\n")
    out = io.StringIO()
    linkage.bench_port(out, quick=True, basic_command=[sys.executable, str(fake)])
    assert "are DIFFERENT: ANG.DAT, VEL.DAT, ACC.DAT, the screen" in out.getvalue()
    out = io.StringIO()
    linkage.bench_port(out, quick=True, basic_command=[str(tmp_path / "no-such-program")])
    text = out.getvalue()
    assert "PC-BASIC: not installed" in text and "times faster" not in text
    assert all(f"\n{row} " in text for row in PORT_ROWS), text


def test_bench_accuracy_ranks_the_ladder(tmp_path):
    """bench accuracy (the program's own, standard library and numpy): every rung on every kind;
    against 110 digits the double engine and numpy are within 1e-12 degrees of the output (the
    test_engine bound is far tighter; this is the bench's own reference, not a second one), 50
    digits within 1e-15, and GW-BASIC's single precision errs by more than 1e-7 on the plane
    four-bar (its 24-bit mantissa; at phi = 180 its t = tan(phi/2) is infinite); --png draws."""
    rungs = linkage.measure_accuracy(count=5)
    assert {(r.name, r.kind) for r in rungs} == {(n, k) for n in linkage.ACCURACY_RUNGS
                                                 for k in linkage.LINKAGE_DIMENSIONS}
    worst = {(r.name, r.kind): max(e[0] for e in r.errors) for r in rungs if r.errors}
    for kind in linkage.LINKAGE_DIMENSIONS:
        assert worst[linkage.ACCURACY_RUNGS[1], kind] < 1e-12, kind
        assert worst[linkage.ACCURACY_RUNGS[2], kind] < 1e-12, kind
        assert worst[linkage.ACCURACY_RUNGS[3], kind] < 1e-15, kind
    assert worst[linkage.ACCURACY_RUNGS[0], "plane"] > 1e-7
    assert all(r.seconds > 0 for r in rungs)
    out = tmp_path / "acc.png"
    assert linkage.main(["bench", "accuracy", "--quick", "--png", str(out)]) == 0
    assert out.read_bytes().startswith(b"\x89PNG")


def test_the_screen_scores_the_points_random_draws(monkeypatch):
    """`--screen N S` meets the linkages `--random N S` meets (so its worst points are of the
    claim's distribution), and with every point kept for the reference it scores them all there;
    what it finds is within the bounds test_engine holds random points to."""
    from test_engine import random_bound
    seen = {"random": set(), "screen": set()}
    which = ["random"]
    reference = bench_accuracy.engine_harness.ref

    def recorded(kind, dims, phi, *args):
        seen[which[0]].add((kind, tuple(sorted(dims.items())), phi))
        return reference(kind, dims, phi, *args)
    monkeypatch.setattr(bench_accuracy.engine_harness, "ref", recorded)
    bench_accuracy.random_accuracy(io.StringIO(), points=3, seed=5)
    which[0] = "screen"
    found = bench_accuracy.screened_accuracy(io.StringIO(), points=3, seed=5, keep=3)
    assert len(seen["random"]) == 15 and seen["screen"] == seen["random"]
    assert set(found) == set(bench_accuracy.engine_harness.KINDS)
    for kind, worst in found.items():
        for quantity, (error, call, _) in worst.items():
            if quantity != "conditioned":
                assert error <= random_bound(kind, quantity), (kind, quantity, error, call)
