"""Run legacy_basic/LINKAGE.BAS (or a variant of it) under PC-BASIC, the reference interpreter.

One place knows how PC-BASIC is invoked, so that the golden generator, the golden test, the
physics tests and the errata mutation test all run the listing the same way:

    pcbasic LINKAGE.BAS --interface=none -q --input=keys.txt --output=STDOUT --sound=False

in a fresh directory, which is where the program's OPEN "O" files land (started as NO_YIELD,
below). Standard output is the
screen transcript (PC-BASIC's --output=FILE loses the end of the screen text, so it is not used).

The tests' runs are that command line run by a PC-BASIC server (SERVER, below): a Python process
that has imported PC-BASIC once and calls its command line's entry point once a run, so that a
run does not pay for starting Python and importing PC-BASIC again (0.15 s of CPU of the 0.2 s a
trivial run costs). Every run is a fresh call of the entry point, which makes a fresh session:
tests/test_golden.py holds the runs to the bytes `pcbasic` wrote, and a run after one that leaves
all it can behind to the same run in a process of its own. What makes data (make_golden.py,
make_text_table.py) and the accuracy bench, which times the run, start `pcbasic` alone.
"""

from __future__ import annotations

import atexit
import dataclasses
import json
import os
import re
import select
import shutil
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

from support.peers import need

ROOT = Path(__file__).resolve().parents[2]
LISTING = ROOT / "legacy_basic" / "LINKAGE.BAS"
DAT_FILES = ("ANG.DAT", "VEL.DAT", "ACC.DAT")

# A hard error stops the program and names the line ("Syntax error in 1250"); the soft ones
# ("Overflow", "Division by zero") are printed alone and the program carries on.
HARD_ERROR = re.compile(rb"^[A-Z][A-Za-z ]+ in \d+", re.MULTILINE)


# `python3 -m pcbasic`, but without the time.sleep(0) calls of PC-BASIC's event loop (three a
# statement, eventcycle.py), which only yield the processor to an interactive interface thread:
# with --interface=none and the keys read from a file nothing waits for them, and on a busy
# machine each yield gives up the core, so that a run took twice its CPU time in wall time.
# Every other sleep is kept; what the program computes, prints and writes is the same bytes
# (tests/test_golden.py holds those to data/golden).
_UNYIELDING = ("import sys, time\n"
               "sleep = time.sleep\n"
               "time.sleep = lambda seconds: sleep(seconds) if seconds else None\n"
               "from pcbasic.main import main, script_entry_point_guard\n")
NO_YIELD = _UNYIELDING + ("with script_entry_point_guard():\n"
                          "    main()\n")


def pcbasic_command() -> list[str]:
    """The PC-BASIC of the Python running the tests (so a venv's copy is used), as NO_YIELD."""
    need("pcbasic", load=False)
    return [sys.executable, "-c", NO_YIELD]


def pcbasic_version() -> str:
    out = subprocess.run(pcbasic_command() + ["--version"], capture_output=True, check=True)
    return out.stdout.decode().splitlines()[0].strip()


def _environment() -> dict[str, str]:
    env = dict(os.environ)
    env.update(LANG="C.UTF-8", LC_ALL="C.UTF-8", PYTHONIOENCODING="utf-8", SDL_VIDEODRIVER="dummy")
    return env


# The PC-BASIC server, run as `python3 -c SERVER JOBS REPLIES` (two pipes' descriptors). Its
# standard input is /dev/null, as a run's was (PC-BASIC reads a standard input that is no
# terminal as typed keys). It reads one job a line from JOBS: the folder, the arguments of
# `pcbasic` and the files for standard output and error; it runs the command line there, with
# those files as descriptors 1 and 2, and writes the exit status to REPLIES. EOF on JOBS ends it.
SERVER = _UNYIELDING + """\
import json, os, traceback
jobs = os.fdopen(int(sys.argv[1]), "rb")
replies = os.fdopen(int(sys.argv[2]), "wb", buffering=0)
for line in jobs:
    job = json.loads(line)
    sys.stdout.flush()
    sys.stderr.flush()
    kept = os.dup(1), os.dup(2)
    for fd, name in ((1, "out"), (2, "err")):
        opened = os.open(job[name], os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
        os.dup2(opened, fd)
        os.close(opened)
    os.chdir(job["cwd"])
    try:
        with script_entry_point_guard():
            main(*job["args"])
        status = 0
    except SystemExit as end:
        status = end.code if isinstance(end.code, int) else 0 if end.code is None else 1
    except BaseException:
        traceback.print_exc()
        status = 1
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except Exception:
        status = status or 1
    for fd, old in zip((1, 2), kept):
        os.dup2(old, fd)
        os.close(old)
    os.chdir("/")
    replies.write(b"%d\\n" % status)
"""


class _Server:
    """One PC-BASIC server process, its two pipes and the runs it has made."""

    def __init__(self) -> None:
        need("pcbasic", load=False)
        self.files = tempfile.mkdtemp(prefix="linkage-pcbasic-server-")
        jobs_in, self.jobs = os.pipe()
        self.replies, replies_out = os.pipe()
        self.proc = subprocess.Popen(
            [sys.executable, "-c", SERVER, str(jobs_in), str(replies_out)],
            pass_fds=(jobs_in, replies_out), stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=_environment(), cwd="/")
        os.close(jobs_in)
        os.close(replies_out)
        self.runs = 0

    def run(self, args: list[str], cwd: Path, timeout: float) -> tuple[bytes, int, bool]:
        """Run `pcbasic ARGS` in `cwd`: its standard output, its exit status, and whether this
        server can take another run (not after a run that failed or ended the server)."""
        out, err = os.path.join(self.files, "stdout"), os.path.join(self.files, "stderr")
        job = json.dumps({"args": args, "cwd": str(cwd), "out": out, "err": err})
        os.write(self.jobs, job.encode() + b"\n")
        self.runs += 1
        reply = b""
        while not reply.endswith(b"\n"):
            if not select.select([self.replies], [], [], timeout)[0]:
                raise subprocess.TimeoutExpired(["pcbasic"] + args, timeout)
            chunk = os.read(self.replies, 64)
            if not chunk:
                break
            reply += chunk
        status = int(reply) if reply.endswith(b"\n") else self.proc.wait()
        with open(out, "rb") as screen:
            return screen.read(), status, status == 0 and reply.endswith(b"\n")

    def close(self, kill: bool = False) -> None:
        if kill:
            self.proc.kill()
        for fd in (self.jobs, self.replies):
            os.close(fd)
        self.proc.wait()
        shutil.rmtree(self.files, ignore_errors=True)


class _Servers:
    """The idle servers: a run takes one (or starts one) and gives it back after a clean run, so
    that runs from several threads at once each have a server of their own. A server makes at
    most RUNS runs (the memory it holds grows by about half a megabyte a run)."""

    RUNS = 50

    def __init__(self) -> None:
        self.idle: list[_Server] = []
        self.lock = threading.Lock()
        atexit.register(self.close)

    def run(self, args: list[str], cwd: Path, timeout: float) -> tuple[bytes, int, int]:
        """The standard output and exit status of `pcbasic ARGS` in `cwd`, and the server's id."""
        with self.lock:
            server = self.idle.pop() if self.idle else None
        server = server or _Server()
        try:
            screen, status, reusable = server.run(args, cwd, timeout)
        except BaseException:                   # the time is up, or the run was interrupted
            server.close(kill=True)
            raise
        if reusable and server.runs < self.RUNS:
            with self.lock:
                self.idle.append(server)
        else:
            server.close()
        return screen, status, server.proc.pid

    def close(self) -> None:
        with self.lock:
            idle, self.idle = self.idle, []
        for server in idle:
            server.close()


_SERVERS = _Servers()


@dataclasses.dataclass(frozen=True)
class Run:
    """What one PC-BASIC run left behind: the screen text and every file it wrote."""

    screen: bytes
    files: dict[str, bytes]
    returncode: int
    server: int = dataclasses.field(default=0, compare=False)   # its process id; 0: run alone

    @property
    def hard_errors(self) -> list[bytes]:
        return HARD_ERROR.findall(self.screen)


def run_listing(keys: bytes, listing: bytes | None = None, *, double: bool = False,
                quit_at_end: bool = True, timeout: float = 600.0, alone: bool = False) -> Run:
    """Type `keys` into the listing (LINKAGE.BAS unless given) and collect screen and files.

    `double` passes --double (double-precision SIN/COS/TAN/ATN, GW-BASIC's /d switch).
    Without `quit_at_end` the interpreter drops to direct mode when the program ends and reads
    the rest of `keys` as commands, which is how `run_batch` chains sessions.
    """
    source = LISTING.read_bytes() if listing is None else listing
    return run_program(source, keys, double=double, quit_at_end=quit_at_end, timeout=timeout,
                       alone=alone)


def run_program(source: bytes, keys: bytes = b"", inputs: dict[str, bytes] | None = None, *,
                double: bool = False, quit_at_end: bool = True, timeout: float = 600.0,
                alone: bool = False) -> Run:
    """Run the GW-BASIC program `source` (CRLF lines) in a fresh directory holding the files
    `inputs`, typing `keys`; return the screen and every file the program left (the program,
    the keys and the input files excluded). `alone` runs it in a process of its own, `pcbasic`
    as a user starts it, instead of by a server."""
    inputs = inputs or {}
    with tempfile.TemporaryDirectory(prefix="linkage-pcbasic-") as tmp:
        work = Path(tmp)
        (work / "PROGRAM.BAS").write_bytes(source)
        (work / "keys.txt").write_bytes(keys)
        for name, data in inputs.items():
            (work / name).write_bytes(data)
        args = ["PROGRAM.BAS", "--interface=none", "--input=keys.txt", "--output=STDOUT",
                "--sound=False"]
        if quit_at_end:
            args.append("-q")
        if double:
            args.append("--double")
        if alone:
            proc = subprocess.run(pcbasic_command() + args, cwd=work, capture_output=True,
                                  timeout=timeout, env=_environment(), stdin=subprocess.DEVNULL)
            screen, status, server = proc.stdout, proc.returncode, 0
        else:
            screen, status, server = _SERVERS.run(args, work, timeout)
        files = {p.name: p.read_bytes() for p in sorted(work.iterdir())
                 if p.name not in ("PROGRAM.BAS", "keys.txt") and p.name not in inputs}
    return Run(screen=screen, files=files, returncode=status, server=server)


def _batch_name(session: int, name: str) -> str:
    """An 8.3 file name for session's copy of name: S007ANG.DAT."""
    return "S%03d%s" % (session, name)


def run_batch(sessions: list[bytes], listing: bytes | None = None, *, double: bool = False,
              timeout: float = 600.0, alone: bool = False) -> list[dict[str, bytes]]:
    """Run several sessions in one run of the interpreter (one screen for all).

    After each session the three DAT files are renamed in direct mode (NAME ... AS ...) and
    the program is started again with RUN, which clears all variables as a fresh start does.
    Returns, per session, the DAT files it wrote (missing ones are absent) and, under the key
    "SCREEN", the whole transcript (shared by all sessions).
    """
    keys = b""
    for i, session in enumerate(sessions):
        keys += session
        for name in DAT_FILES:
            keys += b'NAME "%s" AS "%s"\r' % (name.encode(), _batch_name(i, name).encode())
        keys += b"RUN\r" if i + 1 < len(sessions) else b"SYSTEM\r"
    run = run_listing(keys, listing, double=double, quit_at_end=False, timeout=timeout,
                      alone=alone)
    results = []
    for i in range(len(sessions)):
        got = {"SCREEN": run.screen}
        for name in DAT_FILES:
            renamed = _batch_name(i, name)
            if renamed in run.files:
                got[name] = run.files[renamed]
        results.append(got)
    return results


def double_precision_variant(listing: bytes) -> bytes:
    """The listing with its arithmetic in double precision, every formula line untouched.

    Three edits, each forced by GW-BASIC: DEFDBL for all variables but the L... loop counter
    (a FOR counter may not be double: "Type mismatch"); PI to double precision; and the FOR PHI
    loop (whose counter is PHI) written as an explicit loop so that PHI can be double.
    Run it with double=True so that SIN, COS, TAN and ATN are double precision too.
    """
    edits = {
        b"110 PI=3.141592654#:CIM=0": b"110 PI=4#*ATN(1#):CIM=0",
        b"1050 FOR PHI=PHIB(1) TO PHIB(2) STEP INC":
            b"1050 PHI=PHIB(1)-INC\r\n1055 PHI=PHI+INC:IF PHI>PHIB(2)+INC/1000000# THEN 1350",
        b"1340 UIM=0:NEXT PHI": b"1340 UIM=0:GOTO 1055",
    }
    for old, new in edits.items():
        if listing.count(old) != 1:
            raise ValueError(f"listing has no unique line {old!r}")
        listing = listing.replace(old, new)
    return b"5 DEFDBL A-K,M-Z\r\n" + listing


def read_dat(data: bytes) -> list[tuple[float, float]]:
    """Parse a WRITE # file: 'x,y' lines ended by CRLF, then the 0x1A end-of-file byte.

    Double-precision values are written with a D exponent (6.647498685352924D-02).
    """
    text = data.rstrip(b"\x1a").decode("ascii").replace("D", "E")
    rows = []
    for line in text.split("\r\n"):
        if line:
            x, y = line.split(",")
            rows.append((float(x), float(y)))
    return rows
