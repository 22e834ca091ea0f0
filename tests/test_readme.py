"""The README as a newcomer uses it: every `python3 linkage.py …` command it shows - in its code
blocks (continued lines joined) and in its tables - runs from a fresh folder and exits 0, as
shown; so does every one of data/PROOFS.md, where the README's claims are proven. The folder has the repository's data/ and legacy_basic/ beside it (the README's paths
are relative to the clone); the bare menu program is given the key 6 (Exit).

Each command starts the program as the other modules do, by PROGRAM (this checkout's linkage.py
from its compiled bytecode; test_command_line.test_the_tests_start_the_program_the_users_way shows
it the same as the script), but for those in BY_SCRIPT, run as typed: compiling the script's
350 kB at each of 35 starts cost 8 s of CPU. A `bench NAME` runs at full size with
LINKAGE_LONG=1; the default run has every bench at --quick size in test_bench's quick_run
(`bench all --quick`, every name of BENCHMARKS checked there)."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

import linkage
import test_bench
import test_scenes
from support.basic_runner import ROOT
from support.program import PROGRAM

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

README = (ROOT / "README.md").read_text(encoding="utf-8")
PROOFS = (ROOT / "data" / "PROOFS.md").read_text(encoding="utf-8")
COMMAND = re.compile(r"^python3 linkage\.py(?: |$)")
TIMING = re.compile(r"^python3 linkage\.py\s+[0-9.]+\s*$")      # a row of a table of times


def readme_commands(text: str) -> list[str]:
    """The commands: indented code lines (with their `\\` continuations) and `inline code` that
    start with python3 linkage.py."""
    commands, lines = [], text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("    ") and COMMAND.match(line.strip()):
            command = line.strip()
            while command.endswith("\\") and i + 1 < len(lines):
                i += 1
                command = command[:-1].rstrip() + " " + lines[i].strip()
            if not TIMING.match(command):
                commands.append(command)
        commands += [c for c in re.findall(r"`(python3 linkage\.py[^`]*)`", line)
                     if not line.startswith("    ")]
        i += 1
    return list(dict.fromkeys(commands))


# A command another module runs as a program already, exit status and standard error checked as
# here: `bench all --quick` is tests/test_bench.py's quick_run (linkage.py copied alone, nothing of
# tests/ importable), not run a second time (8 s of CPU).
# So is `scene fig3 --png fig3.png`, test_scenes.test_a_curve_scene_says_the_png_it_wrote's (a
# PNG drawn by a process of its own, 0.9 s).
RUN_ELSEWHERE = {"python3 linkage.py " + " ".join(test_bench.QUICK_ARGS): "test_bench.quick_run",
                 "python3 linkage.py " + " ".join(test_scenes.CURVE_PNG):
                     "test_scenes.test_a_curve_scene_says_the_png_it_wrote"}
LONG = bool(os.environ.get("LINKAGE_LONG"))
BENCH = re.compile(r"^python3 linkage\.py bench [a-z]+$")        # one bench at full size
BY_SCRIPT = {"python3 linkage.py", "python3 linkage.py < data/golden/plane-b1/keys.txt"}
COMMANDS = [c for c in dict.fromkeys(readme_commands(README) + readme_commands(PROOFS))
            if c not in RUN_ELSEWHERE and (LONG or not BENCH.match(c))]


def test_the_readme_shows_the_commands_of_every_sub_command():
    shown = {c.split()[2] if len(c.split()) > 2 else "" for c in readme_commands(README)}
    assert {"", "run", "analyse", "scene", "plot", "design", "listing", "bench",
            "forces"} <= shown, shown


def test_the_commands_run_elsewhere_are_the_readmes():
    """Each command left to another module is one the README shows (an entry outlives no edit of
    the README), and it is left out here."""
    shown = readme_commands(README) + readme_commands(PROOFS)
    for command in RUN_ELSEWHERE:
        assert command in shown and command not in COMMANDS, command
    for command in shown:                    # a bench left to quick_run is one it runs
        if BENCH.match(command) and not LONG:
            assert command not in COMMANDS and command.split()[-1] in linkage.BENCHMARKS
    assert BY_SCRIPT <= set(COMMANDS)        # and the script's own start is still run here


@pytest.mark.parametrize("command", COMMANDS)
def test_a_readme_command_runs_as_shown(command, tmp_path):
    for name in ("data", "legacy_basic"):
        os.symlink(ROOT / name, tmp_path / name)
    start = [sys.executable, str(ROOT / "linkage.py")] if command in BY_SCRIPT else PROGRAM
    line = command.replace("python3 linkage.py", " ".join(f'"{a}"' for a in start), 1)
    keys = "6" if command == "python3 linkage.py" else None
    got = subprocess.run(["bash", "-c", line], cwd=tmp_path, capture_output=True, text=True,
                         input=keys, timeout=600)
    assert got.returncode == 0, (command, got.stderr[-2000:])
    assert "Traceback" not in got.stderr
