"""Regenerate the golden corpus: run legacy_basic/LINKAGE.BAS under PC-BASIC for every case.

    PYTHONPATH=tests python3 -m support.make_golden            # every case of cases.toml
    PYTHONPATH=tests python3 -m support.make_golden NAME ...   # only these cases

(from the repository's root; the cases are data/golden/cases.toml's).

For each case, data/golden/<name>/ receives keys.txt (the keystrokes), SCREEN.TXT (PC-BASIC's
standard output) and every file the program wrote (ANG.DAT, VEL.DAT, ACC.DAT), as bytes. The
PC-BASIC version is recorded in data/golden/PCBASIC_VERSION and the table of cases in
data/golden/README.md. This script is the only thing that writes those files.
"""

from __future__ import annotations

import concurrent.futures
import sys
import tomllib

from support import basic_runner

GOLDEN = basic_runner.ROOT / "data" / "golden"
CASES_FILE = GOLDEN / "cases.toml"
REQUIRED_VERSION = "PC-BASIC 2.0.8"

README_HEAD = """\
# The golden corpus

Each folder is one session of `legacy_basic/LINKAGE.BAS` under {version}, written by
`PYTHONPATH=tests python3 -m support.make_golden` from the cases in `cases.toml`, never by hand:
`keys.txt` (the keystrokes as typed), `SCREEN.TXT` (PC-BASIC's standard output, run as
`pcbasic LINKAGE.BAS --interface=none -q --input=keys.txt --output=STDOUT --sound=False`) and the
files the program wrote, byte for byte (CRLF line ends, the end-of-file byte 0x1A).
`tests/test_golden.py` re-runs PC-BASIC on a sample of the cases in every test run
(`LINKAGE_GOLDEN=all` for all of them) and requires identical bytes.

| case | what it covers | points | screen messages |
|---|---|---|---|
"""


def load_cases() -> list[dict]:
    with CASES_FILE.open("rb") as f:
        cases = tomllib.load(f)["case"]
    names = [c["name"] for c in cases]
    duplicates = {n for n in names if names.count(n) > 1}
    if duplicates:
        raise SystemExit(f"{CASES_FILE}: duplicate case names {sorted(duplicates)}")
    return cases


def case_keys(case: dict) -> bytes:
    return case["keys"].encode("ascii")


def generate(case: dict) -> basic_runner.Run:
    """Run one case (`pcbasic` in a process of its own) and replace its folder's contents with
    what PC-BASIC produced."""
    run = basic_runner.run_listing(case_keys(case), alone=True)
    if run.returncode != 0 or run.hard_errors:
        raise SystemExit(f"case {case['name']}: PC-BASIC stopped with {run.hard_errors} "
                         f"(exit {run.returncode}); fix the keys in {CASES_FILE.name}")
    folder = GOLDEN / case["name"]
    folder.mkdir(exist_ok=True)
    for old in folder.iterdir():
        old.unlink()
    (folder / "keys.txt").write_bytes(case_keys(case))
    (folder / "SCREEN.TXT").write_bytes(run.screen)
    for name, data in run.files.items():
        (folder / name).write_bytes(data)
    return run


def summary(case: dict) -> str:
    folder = GOLDEN / case["name"]
    ang = folder / "ANG.DAT"
    points = str(len(basic_runner.read_dat(ang.read_bytes()))) if ang.exists() else "no files"
    screen = (folder / "SCREEN.TXT").read_bytes()
    messages = [m for m in ("Illegal linkage", "Redo from start", "Division by zero", "Overflow")
                if m.encode() in screen]
    return f"| `{case['name']}` | {case['about']} | {points} | {', '.join(messages)} |"


def write_readme(cases: list[dict], version: str) -> None:
    lines = [summary(case) for case in cases]
    (GOLDEN / "README.md").write_text(README_HEAD.format(version=version) + "\n".join(lines)
                                      + "\n")


def main(argv: list[str]) -> int:
    version = basic_runner.pcbasic_version()
    if version != REQUIRED_VERSION:
        raise SystemExit(f"the corpus is made with {REQUIRED_VERSION}; this is {version}")
    cases = load_cases()
    chosen = [c for c in cases if not argv or c["name"] in argv]
    unknown = set(argv) - {c["name"] for c in cases}
    if unknown:
        raise SystemExit(f"no such case: {', '.join(sorted(unknown))}")
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        for case, _ in zip(chosen, pool.map(generate, chosen)):
            print(f"{case['name']}: written", flush=True)
    known = {c["name"] for c in cases}
    stale = [p.name for p in GOLDEN.iterdir() if p.is_dir() and p.name not in known]
    if stale:
        print(f"folders with no case in {CASES_FILE.name} (remove them): {stale}")
    (GOLDEN / "PCBASIC_VERSION").write_text(version + "\n")
    write_readme(cases, version)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
