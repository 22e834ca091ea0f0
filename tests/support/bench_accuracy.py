"""What accuracy costs in time: six ways of computing the same points, each timed and scored
against the 50-digit reference.

    PYTHONPATH=tests python3 -m support.bench_accuracy                   (minutes: mpmath, PC-BASIC)
    PYTHONPATH=tests python3 -m support.bench_accuracy --random [POINTS [SEED]]   (random points)
    PYTHONPATH=tests python3 -m support.bench_accuracy --screen [POINTS [SEED]]   (many of them)

(from the repository's root; --random: the engine alone at random points; --screen: the same
points, many more, each first scored against the program's 110-digit decimal redo and the worst
of them against the 50-digit reference).

The methods: GW-BASIC single precision (the port's own lines 250-930 and 1060-1330), the listing's
formulas in double (listing_model.py), the accurate engine, mpmath at 30 and 50 digits, and PC-BASIC
running legacy_basic/LINKAGE.BAS. The measuring instruments are the tests' own, which is why this
is a script here and not a `bench` of linkage.py (data/BENCHMARKS.md, "What accuracy costs in
time"): engine_harness.py (the two sweeps, the scoring rules), engine_reference.py (the mpmath
solver written from the geometry, which is the reference), listing_model.py (the listing's formulas
in double precision) and basic_runner.py (PC-BASIC). A point is one input angle on one branch.
tests/test_bench.py runs it on a tiny sweep.
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
import textwrap
import time
from typing import NamedTuple

import linkage
from linkage import (ASSEMBLED, DIV_ZERO, INDETERMINATE, NOT_ASSEMBLED, OVERFLOW, Linkage,
                     Variables, coefficients, degrees_to_radians, dimensions, input_value,
                     soft_errors, sweep_point)
from support import basic_runner, engine_harness, listing_model

COMMAND = "PYTHONPATH=tests python3 -m support.bench_accuracy"    # from the repository's root
DIVISION = "division by zero"   # GW-BASIC's soft error (or overflow) at the point, K7; Python's
#                                 ZeroDivisionError or a non-finite number for the listing in double
ILLEGAL = "illegal linkage"     # line 480's assembly check refuses the linkage: no point computed
NO_ANSWER = "no answer"         # the solver gave up, or PC-BASIC wrote no line
WRONG_STATUS = "wrong status"   # a value where the reference has none, or none where it has one
FAILURES = (DIVISION, ILLEGAL, NO_ANSWER, WRONG_STATUS)
CLIP = 3.0                      # lines 1200-1300 write VEL and ACC clipped to +-3 (K9)
ERROR_COLUMNS = ("angle", "position", "velocity", "acceleration")
PCBASIC_EVERY = 5               # PC-BASIC's short sweep: every 5th angle of the ordinary sweep
ACCURACY_REPEATS = 3            # the fast methods' time is the best of this many runs
PCBASIC_TIMEOUT = 1800          # seconds: PC-BASIC takes a quarter of a second a session


class Answer(NamedTuple):
    """One method's answer at one point: a status (the engine's ASSEMBLED, DEAD_CENTRE,
    NOT_ASSEMBLED, INDETERMINATE, or DIVISION, ILLEGAL, NO_ANSWER), the values it gives (None
    where it gives none), whether VEL and ACC are clipped to +-3, and the lines written (the
    faithful program and PC-BASIC)."""

    status: str
    output: object = None
    velocity: object = None
    acceleration: object = None
    clipped: bool = False
    lines: bytes | None = None


@dataclasses.dataclass
class Tally:
    """One method on one sweep: its time per point and its worst errors against the reference,
    each with the point where it occurs; the points where it failed, by kind, are not in them."""

    method: str
    note: str = ""                 # why the row has no numbers, or how it was run
    seconds: float | None = None   # time for the `computed` points
    computed: int = 0
    points: int = 0
    worst: dict = dataclasses.field(default_factory=dict)   # column: (error, where)
    failures: dict = dataclasses.field(default_factory=dict)
    beyond_clip: int = 0           # VEL/ACC values whose reference exceeds +-3, compared clipped
    first_wrong: str = ""
    unscored: str = ""             # why there are no errors (no reference)

    @property
    def per_point(self) -> float | None:
        return self.seconds / self.computed if self.seconds is not None and self.computed else None


def _reference():
    """engine_reference.py (it needs mpmath), or None and why it is missing: the rows that need
    it say so."""
    try:
        from support import engine_reference
    except ImportError as e:
        return None, f"{e.name} is not installed (pip install mpmath)"
    return engine_reference, ""


def _typed_linkage(kind: str, dims: dict):
    """Lines 250-480 given the dimensions typed at the prompts: the menu key, the answers typed
    (in the order the listing asks), and the listing's variables, or None where line 480 refuses
    the linkage. Soft errors go to the caller's soft_errors() block."""
    key, typed = linkage.typed_dimensions(kind, dims)
    v, answers = Variables(), iter(typed)
    legal = dimensions(v, int(key), lambda prompt: input_value(next(answers)))
    return key, typed, v if legal else None


def _written(lines, soft_errors: int) -> Answer:
    """What the listing wrote for one point (the "phi,value" lines of ANG, VEL and ACC.DAT, str or
    bytes) and the soft errors it printed meanwhile, as an Answer: 0, 0, 0 is its mark of a
    position that does not assemble (K8); after "Division by zero" or "Overflow" the values are
    not compared."""
    text = tuple(line.encode("ascii") if isinstance(line, str) else line for line in lines)
    output, velocity, acceleration = (float(line.split(b",")[1]) for line in text)
    if output == velocity == acceleration == 0:
        return Answer(NOT_ASSEMBLED, clipped=True, lines=b"".join(text))
    status = DIVISION if soft_errors else ASSEMBLED
    return Answer(status, output, velocity, acceleration, True, b"".join(text))


def _faithful_method(cases, repeats):
    """GW-BASIC single precision, the port's own lines 250-930 (coefficients) and 1060-1330
    (sweep_point): what `run --precision basic` computes, each angle typed as the sweep's bounds
    (--from PHI --to PHI), so without the FOR loop's drift (K10)."""
    jobs = []
    for label, kind, dims, phis in cases:
        with soft_errors() as errors:
            key, _, v = _typed_linkage(kind, dims)
            if v is not None:
                co = coefficients(v, int(key))
                angles = [degrees_to_radians(input_value(linkage.typed_number(phi))) for phi in phis]
        if v is not None:
            jobs.append((label, phis, (co, v.S, angles), len(errors)))
        else:
            jobs.append((label, phis, None, 0))

    def compute():
        out = []
        for _, _, job, _ in jobs:
            rows = []
            if job is not None:
                co, S, angles = job
                for PHI in angles:
                    for SOL in (1, 2):
                        with soft_errors() as errors:
                            rows.append((sweep_point(co, PHI, SOL, S), len(errors)))
            out.append(rows)
        return out
    seconds, raw = linkage._timed(repeats, compute)
    answers, computed = {}, 0
    for (label, phis, job, setup_errors), rows in zip(jobs, raw):
        for i, phi in enumerate(phis):
            for branch in (1, 2):
                if job is None:
                    answers[label, phi, branch] = Answer(ILLEGAL)
                    continue
                lines, soft = rows[2 * i + branch - 1]
                answers[label, phi, branch] = _written(lines, soft + setup_errors)
                computed += 1
    return seconds, computed, answers


def _listing_double_method(cases, repeats, model):
    """The listing's formulas in double precision: tests/support/listing_model.py, the
    transcription of lines 250-930 and 1060-1330 that the tests hold against PC-BASIC's DEFDBL
    variant; unclipped."""
    coefficients_of = []
    for _, kind, dims, _ in cases:
        try:
            coefficients_of.append(model.coefficients(kind, dims))
        except (ArithmeticError, ValueError):
            coefficients_of.append(None)

    def compute():
        return [[model.point(co, phi, branch) for phi in phis for branch in (1, 2)]
                if co is not None else [] for co, (_, _, _, phis) in zip(coefficients_of, cases)]
    seconds, raw = linkage._timed(repeats, compute)
    status_of = {"ok": ASSEMBLED, "uim": NOT_ASSEMBLED, "division": DIVISION}
    answers, computed = {}, 0
    for (label, _, _, phis), co, rows in zip(cases, coefficients_of, raw):
        for i, phi in enumerate(phis):
            for branch in (1, 2):
                if co is None:
                    answers[label, phi, branch] = Answer(DIVISION)
                    continue
                status, *values = rows[2 * i + branch - 1]
                status = status_of[status]
                if status == ASSEMBLED and not all(math.isfinite(x) for x in values):
                    status = DIVISION
                answers[label, phi, branch] = (Answer(status, *values) if status == ASSEMBLED
                                               else Answer(status))
                computed += 1
    return seconds, computed, answers


def _engine_method(cases, repeats):
    """The accurate engine: Linkage(kind, **dims).sweep(phis, branch), displacement, velocity and
    acceleration."""
    links = [Linkage(kind, **dims) for _, kind, dims, _ in cases]

    def compute():
        return [(link.sweep(phis, 1), link.sweep(phis, 2))
                for link, (_, _, _, phis) in zip(links, cases)]
    seconds, raw = linkage._timed(repeats, compute)
    answers, computed = {}, 0
    for (label, _, _, phis), branches in zip(cases, raw):
        for branch, motions in zip((1, 2), branches):
            for phi, m in zip(phis, motions):
                answers[label, phi, branch] = Answer(m.status, m.output, m.velocity,
                                                     m.acceleration)
                computed += 1
    return seconds, computed, answers


def _mpmath_method(cases, reference, dps):
    """tests/support/engine_reference.py's solver at `dps` digits: root finding on the loop closure
    written from the geometry, implicit differentiation; one solve gives both branches. Returns
    also the solver's own points (the reference for the others)."""
    def compute():
        out = {}
        for label, kind, dims, phis in cases:
            for phi in phis:
                try:
                    out[label, phi] = reference.solve(kind, dims, phi, dps)
                except ArithmeticError as e:   # the output link is free ("indeterminate")
                    out[label, phi] = INDETERMINATE if "indeterminate" in str(e) else NO_ANSWER
                except ValueError:             # mpmath's root finder gave up
                    out[label, phi] = NO_ANSWER
        return out
    seconds, solved = linkage._timed(1, compute)
    answers = {}
    for (label, phi), result in solved.items():
        for branch in (1, 2):
            if isinstance(result, str):
                answers[label, phi, branch] = Answer(result)
            else:
                r = result[branch]
                answers[label, phi, branch] = Answer(r.status, r.output, r.velocity,
                                                     r.acceleration)
    return seconds, len(answers), answers, {k: v for k, v in solved.items()
                                            if not isinstance(v, str)}


def _pcbasic_method(cases, runner):
    """legacy_basic/LINKAGE.BAS under PC-BASIC, one session per point (menu key, dimensions,
    --from PHI --to PHI, branch) in one interpreter (tests/basic_runner.run_batch, at most
    PCBASIC_TIMEOUT seconds, in a process of its own); the time is the whole run's, start-up
    and menus included. Soft
    errors are read from each session's part of the screen. Linkages the listing refuses (line
    480) are not typed in: the program would return to its menu and swallow the next session's
    keys."""
    sessions, where, answers = [], [], {}
    for label, kind, dims, phis in cases:
        with soft_errors():
            key, typed, v = _typed_linkage(kind, dims)
        for phi in phis:
            for branch in (1, 2):
                if v is None:
                    answers[label, phi, branch] = Answer(ILLEGAL)
                    continue
                answers_typed = typed + [linkage.typed_number(phi)] * 2 + ["1"]     # from, to, step
                keys = key + "".join(t + "\r" for t in answers_typed)
                sessions.append((keys + str(branch)).encode("ascii"))
                where.append((label, phi, branch))
    if not sessions:
        return 0.0, 0, answers
    start = time.perf_counter()
    results = runner.run_batch(sessions, timeout=PCBASIC_TIMEOUT, alone=True)
    seconds = time.perf_counter() - start
    screens = results[0]["SCREEN"].split(b'NAME "ANG.DAT" AS')
    for i, (point, files) in enumerate(zip(where, results)):
        if not all(name in files for name in runner.DAT_FILES):
            answers[point] = Answer(NO_ANSWER)
            continue
        lines = [files[name].rstrip(b"\x1a") for name in runner.DAT_FILES]
        if not all(line.count(b"\r\n") == 1 for line in lines):
            answers[point] = Answer(NO_ANSWER)
            continue
        soft = screens[i].count(DIV_ZERO.encode()) + screens[i].count(OVERFLOW.encode())
        answers[point] = _written(tuple(lines), soft)
    return seconds, len(sessions), answers


def _clipped(r):
    """The reference point r as the listing writes it: VEL and ACC clipped to +-3."""
    if r.velocity is None:
        return r, 0
    clip = [max(-CLIP, min(CLIP, x)) for x in (r.velocity, r.acceleration)]
    beyond = sum(abs(x) > CLIP for x in (r.velocity, r.acceleration))
    return dataclasses.replace(r, velocity=clip[0], acceleration=clip[1]), beyond


def _score(tally, harness, cases, answers, references):
    """Add each answer of `answers` (those of `cases`' points it has) to `tally`, against
    `references` {(label, phi): {branch: reference point}} (none: times only)."""
    for label, kind, dims, phis in cases:
        for phi in phis:
            for branch in (1, 2):
                a = answers.get((label, phi, branch))
                if a is None:
                    continue
                tally.points += 1
                if a.status in FAILURES:
                    tally.failures[a.status] = tally.failures.get(a.status, 0) + 1
                    continue
                if (label, phi) not in references:
                    continue
                r = references[label, phi][branch]
                if a.clipped:
                    r, beyond = _clipped(r)
                    tally.beyond_clip += beyond
                verdict, errors = harness.score(kind, dims, phi, branch, a.status, a.output,
                                                a.velocity, a.acceleration, r)
                here = f"{label} {phi}/{branch}"
                if verdict != "ok":
                    tally.failures[WRONG_STATUS] = tally.failures.get(WRONG_STATUS, 0) + 1
                    tally.first_wrong = tally.first_wrong or f"{here}: {verdict}"
                for quantity, error in errors.items():
                    column = quantity
                    if quantity == "output":
                        column = "position" if kind in harness.SLIDERS else "angle"
                    if error >= tally.worst.get(column, (-1.0, ""))[0]:
                        tally.worst[column] = (error, here)


ACCURACY_METHODS = ("GW-BASIC single precision (the port)", "the listing's formulas in double",
                    "the engine", "mpmath, 30 digits", "mpmath, 50 digits (the reference)",
                    "PC-BASIC running the listing")
ACCURACY_NOTES = (
    "How it is measured. A point is one input angle on one branch. Each method's worst error over "
    "the sweep against the 50-digit reference (tests/support/engine_reference.py: root finding on "
    "the loop closure written from the geometry; mpmath rows carry 10 guard digits), as "
    "tests/test_engine.py scores:",
    """\
  angle         |psi - psi_ref| in degrees, wrapped (the four-bars' output)
  position      |x - x_ref| / the linkage's largest length (the slider-cranks' output)
  velocity,     |v - v_ref| where |v_ref| <= 1, |v - v_ref| / |v_ref| above (d/dphi and
  acceleration  d2/dphi2 of psi in radians per radian, of x in length per radian)""",
    f"Time a point: the sweep's time over its points, best of {ACCURACY_REPEATS} (mpmath, "
    "PC-BASIC: one run), each linkage set up beforehand (Linkage(), the coefficients); the mpmath "
    "solver gives both branches of an angle at once. Not in the errors, counted in the last "
    f"column: {DIVISION} (GW-BASIC's soft error or overflow; Python's, or a number not finite, "
    f"for the listing in double), {ILLEGAL} (line 480 refuses the linkage), {WRONG_STATUS} (a "
    "value where the reference has no position, or none where it has one, beyond rounding). The "
    "faithful program and PC-BASIC get each angle typed as both bounds (no FOR-loop drift, K10); "
    "they write 0, 0, 0 where the linkage does not assemble (K8), and their VEL and ACC are "
    "compared with the reference clipped to +-3 (K9). \"Worst at\" names the point: case "
    "phi/branch.")


def measure_accuracy(cases, pcbasic_cases=None, repeats=ACCURACY_REPEATS) -> list[Tally]:
    """Time the six methods on `cases` [(label, kind, dims, phis)] and score them against the
    50-digit reference (the 50-digit row against an 80-digit run). PC-BASIC runs `pcbasic_cases`
    (None: not at all). One Tally per method, in the order of ACCURACY_METHODS."""
    harness, model, runner = engine_harness, listing_model, basic_runner
    reference, missing = _reference()
    tallies = [Tally(name) for name in ACCURACY_METHODS]
    faithful, listing, engine, mp30, mp50, basic = tallies
    runs = [(faithful, _faithful_method(cases, repeats)),
            (listing, _listing_double_method(cases, repeats, model)),
            (engine, _engine_method(cases, repeats))]
    references, truth = {}, {}
    if reference is None:
        mp30.note = mp50.note = missing
    else:
        *run50, references = _mpmath_method(cases, reference, 50)
        runs.append((mp50, tuple(run50)))
        runs.append((mp30, _mpmath_method(cases, reference, 30)[:3]))
        truth_seconds, truth_points, _, truth = _mpmath_method(cases, reference, 80)
        mp50.note = (f"errors against an 80-digit run "
                     f"({_duration(truth_seconds / max(truth_points, 1))} a point)")
    if pcbasic_cases is None:
        basic.note = "not run"
    else:
        try:
            version = runner.pcbasic_version()
        except (OSError, ImportError, subprocess.CalledProcessError) as e:
            basic.note = f"PC-BASIC is not installed (pip install pcbasic==2.0.8): {e}"
        else:
            try:
                run = _pcbasic_method(pcbasic_cases, runner)
            except subprocess.TimeoutExpired:
                basic.note = f"{version} did not finish in {PCBASIC_TIMEOUT} s"
            else:
                runs.append((basic, run))
                port = runs[0][1][2]
                same = sum(a.lines is not None and a.lines == getattr(port.get(k), "lines", None)
                           for k, a in run[2].items())
                basic.note = (f"{version}, one session per point; wrote the port's bytes at "
                              f"{same} of {run[1]} points")
    for tally, (seconds, computed, answers) in runs:
        tally.seconds, tally.computed = seconds, computed
        against = truth if tally is mp50 else references
        _score(tally, harness, pcbasic_cases if tally is basic else cases, answers, against)
        tally.unscored = missing
    return tallies


def _duration(seconds: float | None) -> str:
    if seconds is None:
        return "—"
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)):
        if seconds >= scale or unit == "µs":
            return f"{seconds / scale:.3g} {unit}"
    raise AssertionError


def _error_text(tally: Tally, column: str) -> str:
    if column not in tally.worst:
        return "n/a" if tally.unscored else "—"
    error = tally.worst[column][0]
    return "0" if error == 0 else f"{error:.1e}"


def print_accuracy_table(tallies: list[Tally], out) -> None:
    """The tallies as a Markdown table, then where each method's worst errors are."""
    print("| method | time a point | points | angle ° | position | velocity | acceleration "
          "| not in the errors |", file=out)
    print("|---|--:|--:|--:|--:|--:|--:|---|", file=out)
    for t in tallies:
        failed = ", ".join(f"{n} {kind}" for kind, n in t.failures.items()) or "—"
        if t.seconds is None:
            print(f"| {t.method} | {t.note} ||||||||", file=out)
            continue
        errors = " | ".join(_error_text(t, column) for column in ERROR_COLUMNS)
        print(f"| {t.method} | {_duration(t.per_point)} | {t.points} | {errors} | {failed} |",
              file=out)
    print(file=out)
    for t in tallies:
        if t.seconds is None:
            continue
        where = "; ".join(f"{column} {t.worst[column][1]}" for column in ERROR_COLUMNS
                          if column in t.worst and t.worst[column][0] > 0)
        extra = [t.note] if t.note else []
        if t.unscored:
            extra.append(f"no errors: {t.unscored}")
        if t.beyond_clip:
            extra.append(f"{t.beyond_clip} VEL/ACC values beyond ±3 compared clipped")
        if t.first_wrong:
            extra.append(f"first wrong status: {t.first_wrong}")
        print(f"- {t.method}: worst at {where or '—'}"
              + "".join(f"; {e}" for e in extra), file=out)


def bench_accuracy(out) -> None:
    """What accuracy costs in time: six methods, two sweeps, errors against 50 digits."""
    harness = engine_harness
    ordinary = [(name, kind, dims, harness.ORDINARY_PHIS)
                for name, (kind, dims) in harness.ORDINARY_CASES.items()]
    hard = [(c["name"], c["kind"], c["dims"], [float(phi) for phi in c["phis"]])
            for c in harness.load_hard_cases()]
    short = [(name, kind, dims, phis[::PCBASIC_EVERY]) for name, kind, dims, phis in ordinary]
    intro, definitions, rules = ACCURACY_NOTES
    print(textwrap.fill(intro, 100), definitions, textwrap.fill(rules, 100), sep="\n", file=out)
    for title, cases, pcbasic_cases in (
            ("ordinary sweep: tests/test_physics.py's linkages, phi = 3, 11, ..., 355; PC-BASIC "
             f"every {PCBASIC_EVERY}th angle", ordinary, short),
            (f"hard catalogue: data/hard_cases.toml, {len(hard)} linkages", hard, hard)):
        print(f"\n{title}\n", file=out)
        print_accuracy_table(measure_accuracy(cases, pcbasic_cases), out)


RANDOM_POINTS = 400              # --random: points a kind (the 50-digit reference: ~25 ms each)


def random_point(rng, kind):
    """A linkage of `kind` drawn as test_engine's hypothesis strategy draws it (lengths 0.2 to 10,
    offsets -5 to 5, spherical arcs 2 to 178 degrees, skew angles within 75, 89 for the skew
    slider-crank), an input angle in [0, 360) and a branch."""
    length, signed = (lambda: rng.uniform(0.2, 10.0)), (lambda: rng.uniform(-5.0, 5.0))
    dims = {"plane": lambda: dict(a=length(), b=length(), c=length(), d=length()),
            "spherical": lambda: {k: rng.uniform(2.0, 178.0) for k in "abcd"},
            "skew": lambda: dict(a=length(), b=length(), c=length(), d=length(), f=signed(),
                                 ksi=rng.uniform(-75.0, 75.0)),
            "slider": lambda: dict(b=length(), c=length(), e=signed()),
            "skew-slider": lambda: dict(a=signed(), b=length(), c=length(), f=signed(),
                                        ksi=rng.uniform(-89.0, 89.0))}[kind]()
    return dims, rng.uniform(0.0, 360.0), rng.choice((1, 2))


def random_accuracy(out, points=RANDOM_POINTS, seed=1) -> None:
    """The engine's worst errors against the 50-digit reference at `points` random points a
    kind (random_point; those without a position are drawn again), each worst point printed as
    the call that reproduces it."""
    import random
    harness = engine_harness
    rng = random.Random(seed)
    print(f"random points: {points} a kind (seed {seed}), each with a position on its branch; "
          "the engine's worst error against 50 digits, scored as tests/test_engine.py scores",
          file=out)
    for kind in harness.KINDS:
        worst, wrong, done = {}, 0, 0
        while done < points:
            dims, phi, branch = random_point(rng, kind)
            m = Linkage(kind, **dims).motion(phi, branch)
            if m.status == NOT_ASSEMBLED:
                continue
            done += 1
            verdict, errors = harness.score(kind, dims, phi, branch, m.status, m.output,
                                            m.velocity, m.acceleration, harness.ref(kind, dims,
                                                                                    phi)[branch])
            wrong += verdict != "ok"
            for quantity, error in errors.items():
                if error > worst.get(quantity, (-1.0,))[0]:
                    worst[quantity] = (error, f"Linkage({kind!r}, **{dims!r}).motion({phi!r}, "
                                              f"{branch})")
        print(f"{kind}: " + ", ".join(f"{q} {e:.1e}" for q, (e, _) in worst.items())
              + (f"; {wrong} wrong status" if wrong else ""), file=out)
        for quantity, (error, call) in worst.items():
            print(f"    {quantity} {error:.2e}: {call}", file=out)


SCREEN_POINTS = 20_000           # --screen: points a kind (the decimal redo: ~0.2-1.3 ms each)
SCREEN_KEEP = 12                 # the worst this many a quantity and kind go to the reference


def screened_accuracy(out, points=SCREEN_POINTS, seed=1, keep=SCREEN_KEEP) -> dict:
    """random_accuracy's points (the same draws: `--screen N S` and `--random N S` meet the same
    linkages), each scored first against Linkage.decimal_motion (the engine's formulas in 110
    digits, exact to the double it rounds to: a screen, cheap enough for 10^5 points); the `keep`
    worst of each quantity and kind, and every point whose status is not plainly assembled, are
    then scored against the 50-digit reference (engine_reference.py), which decides. Prints, and
    returns, {kind: {quantity: (error, call, velocity)}}; the output's error over 1 + |dpsi/dphi|
    (its condition: the angle's rounding carried through the linkage) beside it."""
    import heapq
    import random
    harness = engine_harness
    rng = random.Random(seed)
    print(f"random points: {points:,} a kind (seed {seed}), drawn as --random draws them; each "
          f"screened against the 110-digit decimal redo, the {keep} worst a quantity and every "
          "point not plainly assembled then scored against 50 digits as tests/test_engine.py "
          "scores", file=out, flush=True)
    found = {}
    for kind in harness.KINDS:
        worst = {q: [] for q in ("output", "velocity", "acceleration", "conditioned")}
        odd, done = [], 0
        while done < points:
            dims, phi, branch = random_point(rng, kind)
            link = Linkage(kind, **dims)
            m = link.motion(phi, branch)
            if m.status == NOT_ASSEMBLED:
                continue
            done += 1
            d = link.decimal_motion(phi, branch, finest=True)
            if m.status != ASSEMBLED or d.status != ASSEMBLED:
                odd.append((dims, phi, branch))
                continue
            out_error = harness.output_error(kind, dims, m.output, d.output)
            errors = {"output": out_error,
                      "velocity": harness.ratio_error(m.velocity, d.velocity),
                      "acceleration": harness.ratio_error(m.acceleration, d.acceleration),
                      "conditioned": out_error / (1.0 + abs(d.velocity))}
            for quantity, error in errors.items():
                entry = (error, done, (dims, phi, branch))
                if len(worst[quantity]) < keep:
                    heapq.heappush(worst[quantity], entry)
                else:
                    heapq.heappushpop(worst[quantity], entry)
        suspects = {(tuple(sorted(p[0].items())), p[1], p[2]): p
                    for p in odd + [e[2] for q in worst.values() for e in q]}
        confirmed, wrong = {}, []
        for dims, phi, branch in suspects.values():
            m = Linkage(kind, **dims).motion(phi, branch)
            r = harness.ref(kind, dims, phi)[branch]
            verdict, errors = harness.score(kind, dims, phi, branch, m.status, m.output,
                                            m.velocity, m.acceleration, r)
            if verdict != "ok":
                wrong.append(verdict)
            velocity = float(r.velocity) if r.velocity is not None else math.inf
            if "output" in errors:
                errors["conditioned"] = errors["output"] / (1.0 + abs(velocity))
            call = f"Linkage({kind!r}, **{dims!r}).motion({phi!r}, {branch})"
            for quantity, error in errors.items():
                if error > confirmed.get(quantity, (-1.0,))[0]:
                    confirmed[quantity] = (error, call, velocity)
        found[kind] = confirmed
        print(f"{kind}: " + ", ".join(f"{q} {e:.2e}" for q, (e, _, _) in confirmed.items())
              + f"; {len(suspects)} points against 50 digits ({len(odd)} not plainly assembled)"
              + (f"; {len(wrong)} wrong status: {wrong[0]}" if wrong else ""), file=out)
        for quantity, (error, call, velocity) in confirmed.items():
            print(f"    {quantity} {error:.3e} (d output/d phi {velocity:.3g}): {call}", file=out)
        out.flush()
    return found


if __name__ == "__main__":
    print(f"$ {COMMAND} {' '.join(sys.argv[1:])}".rstrip())
    print(f"linkage.py {linkage.__version__} on {linkage.machine()}")
    if sys.argv[1:2] == ["--random"]:
        random_accuracy(sys.stdout, *map(int, sys.argv[2:4]))
    elif sys.argv[1:2] == ["--screen"]:
        screened_accuracy(sys.stdout, *map(int, sys.argv[2:4]))
    else:
        bench_accuracy(sys.stdout)
