"""legacy_basic/ERRATA.md explains the whole difference between the scan and the fixed listing,
and each of its corrections is needed: reverting any one of them makes a test fail.
"""

from __future__ import annotations

import dataclasses
import re
import subprocess

import pytest

from support import basic_runner
import test_physics
from support.program import PROGRAM

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

LEGACY = basic_runner.ROOT / "legacy_basic"
HEADING = re.compile(r"^### ([EL]\d+)\. Lines? ([0-9, ]+): `(.+)` → `(.+)`$", re.MULTILINE)
LINE_START = re.compile(r"^\w\d+[ \t]")      # a line number (or the scan's B30) and white space
COMMENT_LINES = range(10, 100, 10)            # the remark box, layout rule L2


@dataclasses.dataclass(frozen=True)
class Entry:
    name: str                 # E7, L4, ...
    lines: tuple[str, ...]    # line numbers as printed in the heading
    printed: str
    corrected: str
    caught_by: str            # "physics", "prompts" or "neutral" (corrections only)


def errata() -> list[Entry]:
    text = (LEGACY / "ERRATA.md").read_text()
    entries = []
    for match in HEADING.finditer(text):
        name, lines, printed, corrected = match.groups()
        body = text[match.end():].split("\n### ", 1)[0]
        caught = re.search(r"Caught by:\s+([^\n]+)", body)
        caught_by = ("" if caught is None else "neutral" if "neutral" in caught[1]
                     else "prompts" if "prompts" in caught[1] else "physics")
        entries.append(Entry(name, tuple(n.strip() for n in lines.split(",")), printed,
                             corrected, caught_by))
    return entries


CORRECTIONS = [e for e in errata() if e.name.startswith("E")]


def squeeze(text: str) -> str:
    return re.sub(r"\s+", "", text)


def number(line: str) -> str:
    """The line number a line starts with (squeezed or not): 740, 1245, or the scan's B30."""
    return re.match(r"\w\d+", line)[0]


def scan_lines() -> list[str]:
    """The OCR listing with layout rules L1 and L3 applied: one entry per program line."""
    lines: list[str] = []
    for raw in (LEGACY / "LINKAGE.OCR.txt").read_text().splitlines():
        raw = re.sub(r"</?[a-z]+>", "", raw)        # the scan's HTML (<sub>1</sub>)
        if LINE_START.match(raw) or not lines:
            lines = [line for line in lines if number(line) != number(raw)]  # L3: kept twice
            lines.append(raw)
        else:
            lines[-1] += raw
    return lines


def listing_lines() -> list[str]:
    return basic_runner.LISTING.read_bytes().decode("ascii").split("\r\n")[:-1]


def entry_targets(entry: Entry, lines: list[str], fragment: str) -> list[int]:
    """Indices of the lines an entry applies to: its numbered lines (or the line whose number
    is itself the fragment, E22 and E30) that contain the fragment, white space ignored."""
    return [i for i, line in enumerate(lines)
            if (number(line) in entry.lines or squeeze(fragment).startswith(number(line)))
            and squeeze(fragment) in squeeze(line)]


def test_errata_headings_are_read():
    names = [e.name for e in errata()]
    assert names == ["L4"] + [f"E{i}" for i in range(1, len(CORRECTIONS) + 1)], names


def test_errata_explain_the_whole_diff():
    """OCR text + layout rules + every erratum == LINKAGE.BAS, white space aside."""
    scanned = scan_lines()
    for entry in errata():
        targets = entry_targets(entry, scanned, entry.printed)
        assert len(targets) == len(entry.lines), f"{entry.name}: printed text not found once per line"
        for i in targets:
            scanned[i] = squeeze(scanned[i]).replace(squeeze(entry.printed), squeeze(entry.corrected))
    fixed = listing_lines()
    body = lambda lines: [squeeze(l) for l in lines if int(number(l)) not in COMMENT_LINES]
    assert [number(l) for l in body(scanned)] == [number(l) for l in body(fixed)]
    for got, want in zip(body(scanned), body(fixed)):
        assert got == want, f"unexplained difference:\n  scan+errata: {got}\n  LINKAGE.BAS: {want}"


def test_remarks_keep_the_scans_words():
    """Layout rule L2: lines 10-90 are remarks that keep every word the scan shows."""
    scanned = {int(number(l)): l for l in scan_lines() if number(l).isdigit()}
    fixed = {int(number(l)): l for l in listing_lines()}
    for n in COMMENT_LINES:
        assert fixed[n].split(None, 1)[1].startswith("'"), n
        words = re.findall(r"[A-Za-z][A-Za-z.:-]+", scanned[n])
        assert all(w in fixed[n] for w in words), (n, words, fixed[n])


def reverted(entry: Entry) -> bytes:
    """LINKAGE.BAS with this one correction undone."""
    lines = listing_lines()
    targets = entry_targets(entry, lines, entry.corrected)
    assert len(targets) == len(entry.lines), f"{entry.name}: corrected text not in LINKAGE.BAS"
    for i in targets:
        assert entry.corrected in lines[i], f"{entry.name}: spacing differs from LINKAGE.BAS"
        lines[i] = lines[i].replace(entry.corrected, entry.printed)
    return ("\r\n".join(lines) + "\r\n").encode("utf-8")


# ---- the prompts -------------------------------------------------------------------------

# The paper's names for what each prompt asks (Figs. 1-2: fixed link a, crank b, coupler c or c*,
# output link d, offset e; the skew linkages' sectors and angle).
PROMPT = re.compile(
    r"(Please )?enter the (input crank|connecting rod|output crank|fixed link|center offset|"
    r"horizontal sector of the fixed link|vertical sector of the fixed link|skew angle)"
    r"( length)?: |Enter the (first|second) bound of the input angle: |Enter increment: ")
PROMPT_SESSIONS = [b"12\r7\r9\r6\r0\r0\r1\r1", b"32\r7\r9\r6\r1\r25\r0\r0\r1\r1",
                   b"42\r7\r1\r0\r0\r1\r1", b"51\r7.5\r6\r3\r45\r0\r0\r1\r1"]


def prompt_problems(listing: bytes) -> list[str]:
    """Screen lines ending in an answer whose prompt is not one of the paper's names."""
    runs = basic_runner.run_batch(PROMPT_SESSIONS, listing)
    screen = runs[0]["SCREEN"].decode("utf-8", "replace").replace("\r", "")
    asked = [line.lstrip(" ") for line in screen.split("\n")
             if "enter" in line.lower() and not line.startswith("Enter Option")]
    bad = [line for line in asked if not PROMPT.match(line)]
    return bad if len(asked) == 30 else [f"{len(asked)} prompts appeared, not 30"] + bad


def test_prompts_name_the_papers_links():
    assert prompt_problems(basic_runner.LISTING.read_bytes()) == []


# ---- every correction is needed ------------------------------------------------------------

QUICK_COARSE = (3.0, 357.0, 48.0)
QUICK = test_physics.sweeps(
    cases=("plane-crank-rocker", "spherical", "skew", "skew-imaginary", "slider", "skew-slider"),
    centres=(41.0,), branches=(1,), coarse=QUICK_COARSE)


# QUICK in four PC-BASIC runs, each only if the runs before it found no problem. A revert is
# caught if any session has a problem, however the sessions are grouped into runs (a session
# after sessions without one starts as RUN does, its variables cleared); the order only saves
# time. Each revert's sessions run one by one: the skew slider-crank's stencil (it runs most of
# the formula lines, and five points cost less than a sweep) fails 19 of the 29 physics reverts;
# the plane four-bar's sweep, which takes the DETOUR through the menu, 5 of the others; the
# stencils of the skew four-bar with an imaginary coupler and of the spherical four-bar the last
# 5. Only the neutral revert (all of QUICK in one run) and the fixed listing's check run the rest.
LEADING = [[("skew-slider", "stencil")], [("plane-crank-rocker", "coarse")],
           [("skew-imaginary", "stencil"), ("spherical", "stencil")]]
STAGES = [[s for s in QUICK if (s.case, s.kind) in stage] for stage in LEADING] + [
    [s for s in QUICK if all((s.case, s.kind) not in stage for stage in LEADING)]]


def revert_problems(entry: Entry) -> list[str]:
    listing = reverted(entry)
    if entry.caught_by == "prompts":
        return prompt_problems(listing)
    # a neutral revert runs every session anyway: in one PC-BASIC run, not four (0.4 s of CPU)
    for plan in [QUICK] if entry.caught_by == "neutral" else STAGES:
        results = test_physics.physics_problems(listing, plan)
        problems = [p for problems in results.values() for p in problems]
        if problems:
            return problems
    return []


def test_the_quick_check_passes_on_the_fixed_listing():
    """The check the reverts must fail passes on the fixed listing (else a revert would be
    "caught" by the check alone). test_physics runs every QUICK session on the fixed listing
    (test_fixed_listing_closes_the_loop_and_differentiates_right), a coarse sweep as one whose
    points hold QUICK's (its step divides QUICK's), and finds no problem; check_sweep checks
    point by point, so QUICK's sessions pass where those do. Here: that QUICK's sessions are
    among test_physics' (running them again in PC-BASIC cost 2.2 s of CPU)."""
    physics = {(s.case, s.branch, s.kind, s.keys)
               for case in test_physics.CASES for s in test_physics.sweeps(cases=(case,),
                                                                            detour=False)}
    start, stop, step = test_physics.COARSE
    assert (start, stop) == QUICK_COARSE[:2] and QUICK_COARSE[2] % step == 0
    cases = [s.case for s in QUICK if s.kind == "coarse"]
    assert len(QUICK) == 2 * len(cases)
    for sweep in test_physics.sweeps(cases=cases, centres=(41.0,), branches=(1,),
                                     coarse=test_physics.COARSE, detour=False):
        assert (sweep.case, sweep.branch, sweep.kind, sweep.keys) in physics, sweep


@pytest.mark.parametrize("entry", CORRECTIONS, ids=[e.name for e in CORRECTIONS])
def test_reverting_a_correction_is_caught(entry):
    """Each correction's revert fails the check ERRATA.md names; a revert ERRATA.md calls
    neutral must indeed change nothing the checks can see. (A test a revert, so that pytest -n
    spreads their PC-BASIC runs over the cores.)"""
    assert entry.caught_by, f"{entry.name} names no test in ERRATA.md"
    problems = revert_problems(entry)
    if entry.caught_by == "neutral":
        assert problems == [], f"{entry.name} is said to be neutral but is not"
    else:
        assert problems, f"{entry.name} reverted, yet its check passes"


def test_every_deviation_of_the_port_is_tagged_in_the_code():
    """Part 3 of ERRATA.md and the `# ERRATA Pn` tags in linkage.py name the same deviations."""
    documented = set(re.findall(r"^### (P\d+)\.", (LEGACY / "ERRATA.md").read_text(), re.M))
    tagged = set(re.findall(r"# ERRATA (P\d+)", (basic_runner.ROOT / "linkage.py").read_text()))
    assert documented and documented == tagged


# -- `linkage.py listing`: the corrected listing for the historical reader ---------------------

def _listing(*options):
    got = subprocess.run(PROGRAM + ["listing", *options], capture_output=True,
                         text=True, encoding="utf-8")
    assert got.returncode == 0 and not got.stderr, got.stderr
    return got.stdout.splitlines()


def test_the_listing_is_linkage_bas_with_each_correction_marked_under_its_line():
    out = _listing()
    program = [line[2:] for line in out if line[:2] in ("  ", "* ", "K ") and line[2:3].isdigit()]
    assert program == (LEGACY / "LINKAGE.BAS").read_text().splitlines()
    notes = {}                                 # erratum name: the program line it is under
    for i, line in enumerate(out):
        match = re.match(r"^ {8}([EL]\d+): the scan printed `(.+)`, corrected `(.+)`$", line)
        if match:
            above = next(out[j] for j in range(i - 1, 0, -1) if not out[j].startswith("    "))
            assert above.startswith("* ") and "".join(match[3].split()) in "".join(above.split())
            notes.setdefault(match[1], []).append(above)
    assert sorted(notes) == sorted(e.name for e in errata())
    assert len(notes["E24"]) == 3 and notes["E30"][0].startswith("* 1265 ")
    assert sum(line.startswith("* ") for line in out) == 33


def test_the_scan_shows_under_exactly_the_lines_that_differ_from_it_beyond_layout():
    """Independent sources agree: the lines the errata's headings mark are the lines whose
    text the scan prints otherwise (white space aside), but for the remark box (L2)."""
    out = _listing("--ocr")
    differs, marked = set(), set()
    for i, line in enumerate(out):
        if line[:2] in ("  ", "* ", "K ") and line[2:3].isdigit():
            number = int(line[2:].split()[0])
            marked.update([number] if line.startswith("*") else [])
            following = out[i + 1:]
            ends = next((k for k, f in enumerate(following) if not f.startswith("    ")), 0)
            if any(f.startswith("        scan: ") for f in following[:ends]):
                differs.add(number)
    assert marked - differs == set()
    assert differs - marked == set(COMMENT_LINES)
    assert "        scan: B30 C1=SIN(P(3))*SIN(P(4))" in out
