"""linkage: Freudenstein and Mohammad Beigi's microcomputer kinematic analysis of the basic
linkage mechanisms, ported from the IBM-PC BASIC program of their paper ("On a computationally
efficient microcomputer kinematic analysis of the basic linkage mechanisms", Mechanism and
Machine Theory, 1980s).

    python3 linkage.py                  the original program: menu 1-6, prompts, ANG/VEL/ACC.DAT
    python3 linkage.py run KIND ...     the same program driven by options (see --help)
    python3 linkage.py analyse KIND ... the linkage's class, ranges and transmission angle
    python3 linkage.py scene NAME|FILE  a figure: the paper's, a coupler curve (scene --list)
    python3 linkage.py plot [DIR]       the figure of DAT files already written
    python3 linkage.py design METHOD .. a linkage synthesised by one of the review's methods
    python3 linkage.py listing [--ocr]  the BASIC listing as corrected, with its errata
    python3 linkage.py explore [KIND]   change a dimension and watch the linkage answer
    python3 linkage.py bench            speed (what accuracy costs: tests/support/bench_accuracy.py)

Fidelity: ANG.DAT, VEL.DAT and ACC.DAT are byte-identical to those legacy_basic/LINKAGE.BAS
writes under PC-BASIC 2.0.8 given the same keystrokes, and so is the screen transcript, computed
in GW-BASIC's own single precision (tests/test_port.py holds the port to all 44 golden cases,
tests/test_differential.py to random sessions). Deviations from the original are marked
`# ERRATA Pn` here and listed in legacy_basic/ERRATA.md, Part 3: only where the original would
hang or lose data (P1-P7).

Sections, each used only by those after it (its header says which it uses, and what it offers
them): 1. files, messages and the terminal (the one writer of files, say, signals, single keys);
2. the five linkages (their kinds, dimensions and names: the one table); 3. GW-BASIC single
precision; 4. the listing's computation; 5. the original program (screen, keys, INPUT, the menu
session); 6. the accurate engine (the closure solved, swept and followed); 7. what the engine
derives (joints, coupler point, transmission angle); 8. the linkage analysed (analyse); 9.
forces (driving torque, joint reactions, shaking); 10. the numpy path (the engine and what it
derives, on arrays); 11. the numpy path: formulas traced once, replayed on arrays; 12. the numpy
path: forces on arrays; 13. simulation: the equation of motion in its coordinates (through dead
centres and change points); 14. simulation: the run, stepped in time and its events; 15. the
linkage (Linkage, a method for each question); 16. DAT and CSV files; 17. the mechanism drawn;
18. the mechanism's renderers (terminal, SVG, PNG, DXF); 19. synthesis: what a design is; 20.
synthesis: the review's methods; 21. synthesis: designs measured and checked; 22. scenes (read
and checked); 23. scenes computed (DAT files, forces, CSV); 24. plots; 25. simulation scenes (a
run in time: its CSV, plots and motion); 26. the explorer (a dimension changed, the linkage
watched in the terminal); 27. benchmarks of the program itself; 28. the speed table (every bench
run, the README's figures); 29. commands run, analyse and forces (each command's one typed value,
validated once, and its handler); 30. commands scene, plot, design, listing, explore and bench;
31. the command line (argparse, from the table of commands), last. The engine, the view and synthesis never use the original program.
"""

from __future__ import annotations

import collections
import contextlib
import contextvars
import decimal
import fractions
import functools
import io
import itertools
import math
import os
import re
import shutil
import struct
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from decimal import Decimal
from fractions import Fraction
from typing import IO, TYPE_CHECKING, Any, BinaryIO, ParamSpec, TextIO, TypeAlias, cast

if TYPE_CHECKING:                       # for annotations only: numpy, matplotlib and argparse are
    from typing import NamedTuple       # imported where they are used; NamedTuple: see below
    import argparse
    import numpy
    import matplotlib.axes
    import matplotlib.backends.backend_agg
    import matplotlib.figure
    import tempfile
    from types import ModuleType
else:
    class _NamedTupleType(type):
        """What `class X(NamedTuple):` makes at run time: collections.namedtuple of the annotated
        fields, with their defaults, and the class body's docstring and methods; the annotations
        are kept as written (strings). typing.NamedTuple makes the same class but first compiles
        each annotation into a ForwardRef, which doubled the time: 14 ms against 7 for the
        module's 76 classes, a seventh of `python3 -c pass` (data/BENCHMARKS.md, "Start-up as
        users run it"). mypy checks these classes as typing's (the branch above), and what typing
        would refuse at run time (a field without a default after one with); tests/test_layout.py
        holds each class to the one typing makes."""

        def __new__(cls, name: str, bases: tuple[type, ...], body: dict[str, Any]) -> type:
            if not bases:                                       # NamedTuple itself
                return super().__new__(cls, name, bases, body)
            fields = body.get("__annotations__", {})
            made = collections.namedtuple(name, fields, module=body["__module__"],
                                          defaults=[body[f] for f in fields if f in body])
            for key, value in body.items():
                if key not in fields and key != "__module__":
                    setattr(made, key, value)
            return made

    class NamedTuple(metaclass=_NamedTupleType):
        """typing.NamedTuple at run time: see _NamedTupleType."""

__version__ = "0.2.0"
PROG = "linkage" if os.path.basename(sys.argv[0] or "") == "linkage" else "linkage.py"


# ---- 1. Files, messages and the terminal ---------------------------------------------------------
#
# Holds: what every later section writes and says with: the one writer of files (written whole or
# not at all: written_whole, WrittenSet, DatFiles), the messages on standard error (say, said,
# printable), the signals that end a run cleanly, the progress of a long sweep, a terminal's single
# keys, and the files that come with the program.
#
# Uses: nothing.
# Offers: ProgramStop, WriteError, reader_gone, printable, say, said, Interrupted, signals_caught,
#   interrupted_status, held_import, WrittenSet, staging_folder, written, SHIPPED, shipped_folders,
#   shipped_file, written_whole, WholeWrites, whole_stdout, DatFiles, Progress, is_terminal,
#   single_keys.


class ProgramStop(Exception):
    """The program stops where going on would hang or lose data (the original's menu session, a
    sweep of no point, a file that cannot be written); the message says why, in one line."""


class WriteError(ProgramStop):
    """A file could not be written (the message names it and says why); nothing half-written
    is left and the old files stand."""


def reader_gone(e: BaseException) -> bool:
    """Whether `e` is standard output's reader gone (`| head`): a BrokenPipeError naming no file.
    The one rule for it, in every command: no message, exit status 141 (main, as a shell's
    128 + SIGPIPE); a FIFO named as an output whose reader leaves is a file that could not be
    written (its name, exit 1)."""
    return isinstance(e, BrokenPipeError) and e.filename is None


def printable(text: str) -> str:
    """text with every character that is not printable (a control character, an escape
    sequence's ESC) written as its Python escape, \\x1b: what a scene's title or a user's word
    may show on a terminal or in an SVG."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def say(message: object, who: str = PROG) -> None:
    """A line on standard error, where there is one (it may be closed)."""
    if sys.stderr is not None:                  # None: closed (print would use stdout)
        with contextlib.suppress(OSError, ValueError, AttributeError):
            print(f"{who}: {message}", file=sys.stderr, flush=True)


def said(message: object, status: int) -> int:
    say(message)
    return status


class Interrupted(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised wherever the program is, as Ctrl-C raises KeyboardInterrupt:
    on the way out every file being written is removed (exit status 128 + the signal)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


def _interrupted(signum: int, frame: object) -> None:
    raise Interrupted(signum)


@contextlib.contextmanager
def signals_caught() -> Iterator[None]:
    """While it lasts, SIGTERM and SIGHUP become Interrupted (main() runs in it; in the main
    thread only, elsewhere nothing changes); the handlers they had are given back after."""
    import signal
    saved = {}
    with contextlib.suppress(ValueError):       # not the main thread
        for name in ("SIGTERM", "SIGHUP"):
            if hasattr(signal, name):
                number = getattr(signal, name)
                saved[number] = signal.signal(number, _interrupted)
    try:
        yield
    finally:
        for number, handler in saved.items():
            signal.signal(number, handler)


def interrupted_status(e: KeyboardInterrupt) -> int:
    """The exit status of an interrupted run: 130 for Ctrl-C, 128 + n for signal n."""
    return 128 + getattr(e, "signum", 2)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


# -- writing files: whole or not at all (ERRATA P3) --------------------------------------------
#
# Every file the program writes goes through _Temporary: the menu's and run's DAT files in both
# precisions, design --dat, the scenes' DAT files, the SVG and PNG drawings. It is written as it
# comes under a unique name in the target folder, flushed to the disk and renamed over its own
# name only when complete; on any failure or signal it is removed and the old file stands.


class _Temporary:
    """A file being written under a unique temporary name beside `path` (binary, or text in
    `encoding` with no newline translation). finish() flushes it to the disk and closes it,
    rename() then gives it its name; discard() removes it. OSError from here names `path`, never
    the temporary."""

    def __init__(self, path: str, encoding: str | None = None) -> None:
        import tempfile
        self.path = path
        folder = os.path.dirname(os.path.abspath(path))
        if os.path.isdir(path):
            raise IsADirectoryError(21, "it is a folder", path)
        try:
            fd, self.temporary = tempfile.mkstemp(prefix=f".{os.path.basename(path)}.",
                                                  suffix=".partial", dir=folder)
        except OSError as e:
            raise OSError(e.errno, e.strerror, path) from None
        self.there = True                       # the temporary file, until renamed or removed
        try:
            os.fchmod(fd, 0o666 & ~_umask())
            self.file: IO[Any] = (os.fdopen(fd, "wb") if encoding is None
                                  else os.fdopen(fd, "w", encoding=encoding, newline=""))
        except BaseException:
            os.close(fd)
            self._remove()
            raise

    def write(self, data: bytes | str) -> None:
        try:
            self.file.write(data)
        except OSError as e:
            raise OSError(e.errno, e.strerror, self.path) from None

    def finish(self) -> None:
        """Flush and close, ready to be renamed (again: nothing more to do)."""
        if self.file.closed:
            return
        try:
            self.file.flush()
            os.fsync(self.file.fileno())
            self.file.close()
        except OSError as e:
            raise OSError(e.errno, e.strerror, self.path) from None

    def rename(self) -> None:
        try:
            os.replace(self.temporary, self.path)
        except OSError as e:
            raise OSError(e.errno, e.strerror, self.path) from None
        self.there = False

    def discard(self) -> None:
        """Remove the temporary file, whatever state it is in; never fails."""
        with contextlib.suppress(OSError, ValueError):
            self.file.close()                   # may fail to flush (a full disk): no matter
        self._remove()

    def _remove(self) -> None:
        if self.there:
            with contextlib.suppress(OSError):
                os.unlink(self.temporary)
            self.there = False


@contextlib.contextmanager
def _signals_held(drop: bool = False) -> Iterator[None]:
    """While the block runs, SIGINT, SIGTERM and SIGHUP are held back; after it, one that came
    meanwhile is delivered (drop: dropped, the work it would have stopped being done). Around
    the making of a temporary file and its record, so that no signal falls between the two and
    leaves a file that nothing removes. Inside another such block (held_import's within), the
    signals stay held, and pending, until the outer one ends."""
    import signal
    held = {getattr(signal, n) for n in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, n)}
    masks = hasattr(signal, "pthread_sigmask")              # not on Windows
    before: set[int | signal.Signals] = set()
    if masks:
        before = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        if masks:
            pending = signal.sigpending() & (held - before)     # an outer block's: its own
            if pending and drop:
                signal.sigtimedwait(pending, 0)
            signal.pthread_sigmask(signal.SIG_SETMASK, before)


@contextlib.contextmanager
def held_import(name: str) -> Iterator[None]:
    """Around the import of the module `name` with C extensions (numpy, matplotlib), unless it
    is imported already: SIGINT, SIGTERM and SIGHUP held until it is done, then delivered. An
    extension's initialisation may run Python code (its own imports), where the handler would
    raise: an extension that clears the errors of what it imports there swallows the signal, and
    the program goes on as if none had come (numpy's _multiarray_umath importing datetime: a
    double run SIGHUP'd 24-41 ms after its first .partial file finished and exited 0). Held, the
    signal waits; and any thread the extension starts (a BLAS's workers) inherits the mask, so
    that these signals always reach the main thread, which holds them where it must."""
    if name in sys.modules:
        yield                                   # imported already: nothing to hold
        return
    with _signals_held():
        yield


@contextlib.contextmanager
def _renaming(*folders: str) -> Iterator[None]:
    """While the block runs: SIGINT, SIGTERM and SIGHUP held back, and the folders locked (in
    one order) against another of our sessions renaming its set into them; a signal that came
    meanwhile is dropped, as the work it would have stopped is done."""
    locks = []
    for folder in sorted({os.path.realpath(f) for f in folders}):
        with contextlib.suppress(ImportError, OSError):
            import fcntl
            lock = os.open(folder, os.O_RDONLY)
            locks.append(lock)
            fcntl.flock(lock, fcntl.LOCK_EX)
    try:
        with _signals_held(drop=True):
            yield
    finally:
        for lock in locks:
            os.close(lock)                      # and with it the lock


class WrittenSet:
    """The files one command writes, put in place all together or not at all: each is written
    under a temporary name (file()) or staged elsewhere in its folder's file system (adopt(),
    e.g. a scene's DAT files written in a hidden folder), and only when the block ends without
    an error are they renamed into place, together, signals held (with the names removed() of an
    old set that the new one does not write). On any failure every one is removed and the old
    files stand. Outputs that are no regular file (-, a FIFO, a device) cannot be: opened()
    keeps what is written to them and writes it before any file is renamed (if it fails, the old
    files stand; once it is written, the files are put in place)."""

    def __init__(self) -> None:
        self._files: list[_Temporary] = []
        self._moves: list[tuple[str, str]] = []
        self._removed: list[str] = []
        self._streams: list[tuple[str, bytes]] = []

    def __enter__(self) -> WrittenSet:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: object) -> None:
        try:
            if kind is None:
                self._commit()
        finally:
            for f in self._files:
                f.discard()

    def file(self, path: str) -> _Temporary:
        """A file of the set, to write (bytes) now and to be put in place with the rest."""
        with _signals_held():                   # made and recorded, or neither
            self._files.append(_Temporary(path))
        return self._files[-1]

    def adopt(self, staged: str, path: str) -> None:
        """`staged`, a finished file on the same file system, becomes `path` with the rest."""
        self._moves.append((staged, path))

    def removed(self, path: str) -> None:
        """`path`, a file of the old set that the new one does not write, goes with the old set."""
        self._removed.append(path)

    @contextlib.contextmanager
    def opened(self, path: str) -> Iterator[_Temporary | _Stream | BinaryIO]:
        """As written_whole(path), but put in place with the set; an output that is no regular
        file gets what was written before the set's files are renamed into place."""
        if path == "-" or _is_stream(path):
            import io
            buffer = io.BytesIO()
            yield buffer
            self._streams.append((path, buffer.getvalue()))
        else:
            yield self.file(path)

    def _commit(self) -> None:
        """Put the set in place: the files finished, then the streams written whole (a stream
        cannot be taken back: if one fails, no file has been renamed and the old ones stand),
        and only then every file renamed."""
        for f in self._files:
            f.finish()
        targets = [f.path for f in self._files] + [p for _, p in self._moves] + self._removed
        folders = {os.path.dirname(os.path.abspath(p)) for p in targets}
        for path in targets:                    # what would stop the renames, before a stream
            if os.path.isdir(path):
                raise IsADirectoryError(21, "it is a folder", path)
        for path, data in self._streams:
            with written_whole(path) as out:
                out.write(data)
        for folder in folders:
            try:
                os.makedirs(folder, exist_ok=True)
            except OSError as e:
                raise OSError(e.errno, e.strerror, folder) from None
        with _renaming(*folders):
            for path in targets:
                if os.path.isdir(path):
                    raise IsADirectoryError(21, "it is a folder", path)
            for f in self._files:
                f.rename()
            for staged, path in self._moves:
                try:
                    os.replace(staged, path)
                except OSError as e:
                    raise OSError(e.errno, e.strerror, path) from None
            for path in self._removed:
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(path)


def staging_folder(folder: str | None) -> tempfile.TemporaryDirectory[str]:
    """A hidden temporary folder in `folder` (the system's temporary folder for None), to write
    a set in before WrittenSet.adopt puts it in place: on the same file system, so that the
    renames are atomic; removed with what is left in it. OSError names `folder`."""
    import tempfile
    try:
        return tempfile.TemporaryDirectory(prefix=".linkage-", dir=folder)
    except OSError as e:
        raise OSError(e.errno, e.strerror, folder) from None


def written(path: str, outputs: WrittenSet | None = None,
            ) -> contextlib.AbstractContextManager[_Temporary | _Stream | BinaryIO]:
    """written_whole(path), or the file of the set `outputs` if one is given."""
    return written_whole(path) if outputs is None else outputs.opened(path)


# The files that come with the program: beside linkage.py in the repository (data/scenes,
# legacy_basic), or where `pip install` put them (pyproject.toml's data-files, under
# share/fmb-linkage/ of the installation's prefix).
SHIPPED = {"scenes": os.path.join("data", "scenes"), "legacy_basic": "legacy_basic"}


def shipped_folders(kind: str) -> list[str]:
    """The folders that hold the files of `kind` (a key of SHIPPED) that come with the program,
    the repository's first; those that exist."""
    import site
    here = os.path.dirname(os.path.abspath(__file__))
    places = [os.path.join(here, SHIPPED[kind])]
    places += [os.path.join(base, "share", "fmb-linkage", kind)
               for base in (sys.prefix, getattr(site, "USER_BASE", None) or "") if base]
    return [p for p in dict.fromkeys(places) if os.path.isdir(p)]


def shipped_file(kind: str, name: str) -> str:
    """The path of the file `name` of `kind` that comes with the program (FileNotFoundError,
    naming where it looked, if none does)."""
    for folder in shipped_folders(kind):
        if os.path.isfile(os.path.join(folder, name)):
            return os.path.join(folder, name)
    raise FileNotFoundError(2, "not installed with the program", os.path.join(SHIPPED[kind], name))


@contextlib.contextmanager
def written_whole(path: str) -> Iterator[_Temporary | _Stream]:
    """Open `path` for writing (bytes) so that it is written whole or not at all: into a
    temporary file of a unique name in the same folder, flushed to the disk and renamed over
    `path` when the block ends; removed on any failure or interrupt, leaving `path` as it was.
    An output that is no regular file - "-" (standard output), a FIFO, a character device such
    as /dev/null - is written straight through, never replaced by one."""
    if path == "-" or _is_stream(path):
        with _streamed(path) as out:
            yield out
        return
    temporary = None
    try:
        with _signals_held():                   # made and recorded, or neither
            temporary = _Temporary(path)
        yield temporary
        temporary.finish()
        with _renaming(os.path.dirname(os.path.abspath(path))):
            temporary.rename()
    finally:
        if temporary is not None:
            temporary.discard()


def _is_stream(path: str) -> bool:
    """Whether `path` names an existing FIFO or character device (through a link too)."""
    import stat
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return False
    return stat.S_ISFIFO(mode) or stat.S_ISCHR(mode)


class _Stream:
    """An output that is no regular file - standard output ("-"), a FIFO, a device - written
    straight through: every byte given to write() is written (a short write of an unbuffered
    stream, `python3 -u`, is written on from where it stopped), or OSError names `path` (none
    for standard output: the one output the program writes without naming it). finish()
    flushes it, as _Temporary.finish() makes a file ready."""

    def __init__(self, path: str, out: BinaryIO) -> None:
        self.path, self.out = path, out

    def _failed(self, e: OSError) -> OSError:
        return OSError(e.errno, e.strerror, None if self.path == "-" else self.path)

    def write(self, data: bytes) -> int:
        try:
            return _write_all(self.out, data)
        except OSError as e:
            raise self._failed(e) from None

    def finish(self) -> None:
        try:
            self.out.flush()
        except OSError as e:
            raise self._failed(e) from None


def _write_all(out: Any, data: bytes) -> int:
    """Write all of `data` to `out`: a buffered stream does (BufferedWriter), a raw one
    (FileIO: standard output under `python3 -u`) may write part and return its count, and the
    rest is written after it (a pipe whose reader left then fails: BrokenPipeError)."""
    view = memoryview(data).cast("B")
    done = 0
    while done < len(view):
        count = out.write(view[done:])
        if count is None:                       # a non-blocking stream that is full
            raise BlockingIOError(11, "the output cannot take more now")
        done += count
    return done


class WholeWrites(io.RawIOBase):
    """A raw binary stream (FileIO) whose write() writes all it is given, as _write_all: what
    standard output's text layer writes through under `python3 -u` (whole_stdout)."""

    def __init__(self, raw: Any) -> None:
        super().__init__()
        self.raw = raw

    def write(self, data: Any) -> int:
        return _write_all(self.raw, data)

    def writable(self) -> bool:
        return True

    def fileno(self) -> int:
        return int(self.raw.fileno())

    def isatty(self) -> bool:
        return bool(self.raw.isatty())


@contextlib.contextmanager
def whole_stdout() -> Iterator[None]:
    """While it lasts, standard output's text layer writes whole: where Python wrote it
    unbuffered (`python3 -u`, PYTHONUNBUFFERED), a short write of its raw stream - a pipe whose
    reader left after part - was taken as whole, and the text or file said written; then
    sys.stdout is a text layer as Python's, over WholeWrites. Elsewhere nothing changes."""
    stdout = sys.stdout
    if not isinstance(getattr(stdout, "buffer", None), io.FileIO):
        yield
        return
    assert stdout is not None
    raw = io.FileIO(stdout.fileno(), "wb", closefd=False)
    sys.stdout = io.TextIOWrapper(cast("BinaryIO", WholeWrites(raw)), encoding=stdout.encoding,
                                  errors=stdout.errors, write_through=True,
                                  line_buffering=bool(stdout.line_buffering))
    try:
        yield
    finally:
        if sys.stdout is not None:
            with contextlib.suppress(OSError, ValueError):
                sys.stdout.flush()
        sys.stdout = stdout


@contextlib.contextmanager
def _streamed(path: str) -> Iterator[_Stream]:
    """The output written straight to standard output ("-") or to the FIFO or device, whole
    (_Stream): the block's writes, then a flush."""
    if path == "-":
        stdout = sys.stdout
        if stdout is None:
            raise OSError(9, "standard output is closed", "-")
        stream = _Stream(path, stdout.buffer)
        try:
            stdout.flush()
        except OSError as e:
            raise stream._failed(e) from None
        yield stream
        stream.finish()
        return
    try:
        out = open(path, "wb")
    except OSError as e:
        raise OSError(e.errno, e.strerror, path) from None
    stream = _Stream(path, out)
    try:
        yield stream
        stream.finish()
    finally:
        with contextlib.suppress(OSError):
            out.close()                         # flushed, or failed: nothing more to say


class DatFiles:  # ERRATA P3
    """ANG.DAT, VEL.DAT and ACC.DAT written as GW-BASIC's sequential files (CR LF lines, the
    end-of-file byte 1A on CLOSE), by the menu, `run` in both precisions, design --dat and the
    scenes. They are written as the points come under temporary names of their own (two
    sessions in one folder never share one), and on CLOSE flushed to the disk and renamed into
    place together, signals held and the folder locked: the folder holds the old set or the new
    one, never a mixture (a name of the three that this set does not write is removed with the
    old set). Any failure or interrupt removes them. Write errors are a ProgramStop that names
    the file and the reason."""

    NAMES = ("ANG.DAT", "VEL.DAT", "ACC.DAT")
    MU = "MU.DAT"        # the accurate engine's transmission angle, beside them (a scene's)

    def __init__(self, directory: str, count: int = 3,
                 transmission: bool | None = None) -> None:
        """The first `count` of the three files (a scene may ask for fewer), and MU.DAT where
        `transmission` is True (False: an old one is removed with the old set, as the three's
        are; None, the original program's sets: MU.DAT is not theirs to touch)."""
        self.directory = directory
        self.points = 0
        self._files: list[_Temporary] = []
        self._names = self.NAMES[:count] + ((self.MU,) if transmission else ())
        self._family = self.NAMES + (() if transmission is None else (self.MU,))
        try:
            with _signals_held():               # each made and recorded, or neither
                for name in self._names:
                    self._files.append(_Temporary(os.path.join(directory, name), "ascii"))
            # written to directly: the sweep's inner loop (text files: opened in "ascii")
            self._open = [cast("TextIO", t.file) for t in self._files]
        except BaseException as e:
            self.discard()
            if isinstance(e, IsADirectoryError):
                raise WriteError(self._why(e)) from None
            if isinstance(e, OSError):
                raise WriteError(self._why(e, f"cannot write the DAT files in {directory!r}")) \
                    from None
            raise

    def __enter__(self) -> DatFiles:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: object) -> None:
        if kind is None:
            self.close()
        else:
            self.discard()

    def write(self, lines: Iterable[str | bytes | None], points: int = 1) -> None:
        """One point's line (or None) for each file; or the lines of `points` points, bytes
        for each file."""
        try:
            for f, line in zip(self._open, lines):
                if isinstance(line, bytes):
                    f.flush()
                    f.buffer.write(line)
                elif line is not None:
                    f.write(line)
        except OSError as e:
            written = next(t for t in self._files if t.file is f)
            self.discard()
            raise WriteError(self._why(OSError(e.errno, e.strerror, written.path))) from None
        self.points += points

    def close(self, before_rename: Callable[[], object] | None = None) -> None:
        """CLOSE (line 1350): the end-of-file byte, then the files get their names;
        before_rename(), if given, runs once they are on the disk and before any is renamed
        (another file of the same command finishing: if it fails, this set is not put in place)."""
        try:
            for f in self._files:
                f.write("\x1a")
                f.finish()
            if before_rename is not None:
                before_rename()
            with _renaming(self.directory):
                for f in self._files:
                    if os.path.isdir(f.path):
                        raise IsADirectoryError(21, "it is a folder", f.path)
                for f in self._files:
                    f.rename()
                for name in self._family:
                    if name not in self._names:
                        with contextlib.suppress(FileNotFoundError):
                            os.unlink(os.path.join(self.directory, name))
        except OSError as e:
            if reader_gone(e):                  # before_rename: --csv -, its reader gone
                raise
            raise WriteError(self._why(e)) from None
        finally:
            self.discard()

    def discard(self) -> None:
        for f in self._files:
            f.discard()

    @staticmethod
    def _why(e: OSError, what: str | None = None) -> str:
        return (f"{what or f'cannot write {e.filename}'}: {e.strerror}; the DAT files there "
                "are as they were")


class Progress:
    """A long sweep's progress on a terminal's standard error: points done, rate, time left,
    redrawn at most twice a second once the sweep has run a second, and wiped at the end.
    Nothing where standard error is not a terminal (never in the files or a piped transcript),
    nor for `total` 0 (unknown)."""

    def __init__(self, total: float, out: TextIO | None = None) -> None:
        import time
        out = sys.stderr if out is None else out
        self.total, self.done, self.out, self.shown = total, 0, out, False
        self.live = bool(total) and out is not None and is_terminal(out)
        self.clock = time.monotonic
        self.start = self.clock()
        self.next = self.start + 1.0            # first shown once the sweep has run a second

    def __call__(self, points: int = 1) -> None:
        self.done += points
        if self.live and (self.done & 255 == 0 or points > 1) and self.clock() >= self.next:
            self._show()

    def _show(self) -> None:
        now = self.clock()
        self.next = now + 0.5
        rate = self.done / max(now - self.start, 1e-9)
        left = max(self.total - self.done, 0) / rate
        text = (f"\r{self.done:,} of {self.total:,.0f} points, {rate:,.0f} a second, "
                f"{_time_left(left)} left")
        with contextlib.suppress(OSError, ValueError):
            self.out.write(text + "\x1b[K")
            self.out.flush()
            self.shown = True

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        if self.shown:
            with contextlib.suppress(OSError, ValueError):
                self.out.write("\r\x1b[K")
                self.out.flush()


def _time_left(seconds: float) -> str:
    if seconds < 60:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        return f"{seconds // 60:.0f} min {seconds % 60:02.0f} s"
    return f"{seconds // 3600:.0f} h {seconds % 3600 // 60:02.0f} min"


def is_terminal(stream: Any) -> bool:
    """Whether `stream` is a terminal (False for None, a closed stream, anything else)."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        return stream.isatty()
    return False


@contextlib.contextmanager
def single_keys(fd: int | None, enter: Callable[[], object] | None = None,
                leave: Callable[[], object] | None = None,
                carriage_return: bool = False) -> Iterator[None]:
    """The terminal on file descriptor fd takes single keys with no echo (Ctrl-C still
    interrupts) inside the block, and is put back as it was on leaving it, however it is left.
    Ctrl-Z (SIGTSTP) puts it back before the program stops; `fg` takes single keys again.
    enter() and leave() draw what else the screen needs; carriage_return keeps Enter a CR.
    fd None (no terminal to read): only enter() and leave()."""
    import signal
    saved: list[Any] = []                       # the terminal's modes (termios.tcgetattr)
    mode: list[Any] = []
    if fd is not None:
        import termios
        saved, mode = termios.tcgetattr(fd), termios.tcgetattr(fd)
        if carriage_return:
            mode[0] &= ~termios.ICRNL
        mode[3] &= ~(termios.ICANON | termios.ECHO)
        mode[6][termios.VMIN], mode[6][termios.VTIME] = 1, 0

    def begin() -> None:
        if fd is not None:
            termios.tcsetattr(fd, termios.TCSAFLUSH, mode)
        if enter:
            enter()

    def end() -> None:              # the terminal may be gone (SIGHUP): restore what can be
        if leave:
            with contextlib.suppress(OSError, ValueError):
                leave()
        if fd is not None:
            with contextlib.suppress(OSError, termios.error):
                termios.tcsetattr(fd, termios.TCSAFLUSH, saved)

    def stop(signum: int, frame: object) -> None:
        end()
        signal.signal(signal.SIGTSTP, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGTSTP)         # stopped here until `fg`
        signal.signal(signal.SIGTSTP, stop)
        begin()

    try:
        before = signal.signal(signal.SIGTSTP, stop)
    except ValueError:                               # not the main thread: no signals
        before = None
    try:
        begin()
        yield
    finally:
        end()
        if before is not None:
            signal.signal(signal.SIGTSTP, before)


# ---- 2. The five linkages: their kinds, dimensions and names -------------------------------------
#
# Holds: the one table of the five kinds (plane, spherical and skew four-bar, plane and skew
# slider-crank): their names, their dimensions in the engine's order and in the order the listing
# asks for them (KIND_MENU, the menu's key), what each dimension is, the status a computed
# position can have, degrees against radians, and an ordinary decimal number as typed (DECIMAL: the
# commands' and the explorer's one pattern).
#
# Uses: nothing.
# Offers: PLANE_FOUR_BAR, SPHERICAL_FOUR_BAR, SKEW_FOUR_BAR, PLANE_SLIDER_CRANK, SKEW_SLIDER_CRANK,
#   LINKAGE_DIMENSIONS, KIND_NAMES, SLIDER_CRANKS, DIMENSION_NAMES, ASSEMBLED, DEAD_CENTRE,
#   CHANGE_POINT, NOT_ASSEMBLED, INDETERMINATE, STOPPED, RAD, DEG, KIND_MENU, DECIMAL, typed_number,
#   typed_dimensions, letters_defined.


# The five kinds, named as tests/test_physics.py names them, with their dimensions: lengths as
# typed; the spherical linkage's arcs and the skew angle ksi in degrees.
PLANE_FOUR_BAR = "plane"
SPHERICAL_FOUR_BAR = "spherical"
SKEW_FOUR_BAR = "skew"
PLANE_SLIDER_CRANK = "slider"
SKEW_SLIDER_CRANK = "skew-slider"
LINKAGE_DIMENSIONS = {
    PLANE_FOUR_BAR: ("a", "b", "c", "d"),
    SPHERICAL_FOUR_BAR: ("a", "b", "c", "d"),
    SKEW_FOUR_BAR: ("a", "b", "c", "d", "f", "ksi"),
    PLANE_SLIDER_CRANK: ("b", "c", "e"),
    SKEW_SLIDER_CRANK: ("a", "b", "c", "f", "ksi"),
}
KIND_NAMES = {PLANE_FOUR_BAR: "plane four-bar", SPHERICAL_FOUR_BAR: "spherical four-bar",
                   SKEW_FOUR_BAR: "skew four-bar", PLANE_SLIDER_CRANK: "plane slider-crank",
                   SKEW_SLIDER_CRANK: "skew slider-crank"}
SLIDER_CRANKS = (PLANE_SLIDER_CRANK, SKEW_SLIDER_CRANK)     # the rest are four-bars
DIMENSION_NAMES = {"a": "the fixed link", "b": "the input crank", "c": "the coupler",
                   "d": "the output crank", "e": "the slider offset",
                   "f": "the vertical sector of the fixed link",
                   "ksi": "the skew angle (degrees)"}

# The status of a computed position (Motion.status).
ASSEMBLED = "assembled"          # output, and the derivatives asked for, are given
DEAD_CENTRE = "dead-centre"      # output given (the double root: the same on both branches),
#                                  velocity and acceleration None: the discriminant is zero (to
#                                  1e-33 of its scale), the velocity infinite or, where the two
#                                  branches cross (change point), undetermined
CHANGE_POINT = "change-point"    # the two branches cross here (a double zero of the
#                                  discriminant, e.g. a + b = c + d): output given (the double
#                                  root), velocity and acceleration the limits of the listing's
#                                  branch from above (phi -> phi0+); see the section's notes
NOT_ASSEMBLED = "not-assembled"  # the linkage cannot be assembled at this input angle: all None
INDETERMINATE = "indeterminate"  # the output link is free (every psi closes the loop, e.g. the
#                                  crank tip on the output pivot and c = d): all None
STOPPED = "stopped"              # branch="follow" only: the followed motion ended before
#                                  this angle (at a dead centre the crank cannot pass, or where
#                                  the linkage does not assemble, or its output link is free):
#                                  all None

RAD = math.pi / 180.0            # radians per degree
DEG = 180.0 / math.pi            # degrees per radian


# kind: (the original program's menu key, the dimensions in the order the listing asks for them:
# the menu's order, against LINKAGE_DIMENSIONS' order of the paper's letters).
KIND_MENU = {
    PLANE_FOUR_BAR: ("1", ("b", "c", "d", "a")),
    SPHERICAL_FOUR_BAR: ("2", ("b", "c", "d", "a")),
    SKEW_FOUR_BAR: ("3", ("b", "c", "d", "a", "f", "ksi")),
    PLANE_SLIDER_CRANK: ("4", ("b", "c", "e")),
    SKEW_SLIDER_CRANK: ("5", ("b", "c", "a", "f", "ksi")),
}


DECIMAL = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")  # 2, -0.5, 1e-3 as typed


def typed_number(x: float) -> str:
    """A number as it would be typed at the original's INPUT prompt."""
    return repr(float(x))


def typed_dimensions(kind: str, dims: dict[str, float]) -> tuple[str, list[str]]:
    """The menu key and the dimensions as typed, in the order the listing asks for them."""
    key, asked = KIND_MENU[kind]
    return key, [typed_number(dims[n]) for n in asked]


def letters_defined(kind: str) -> str:
    """The kind's dimension letters as options, each with what it is, in the menu's order:
    "--b the input crank, --c the coupler, ..." (the command line's help says it per kind)."""
    return ", ".join(f"--{n} {DIMENSION_NAMES[n]}" for n in KIND_MENU[kind][1])


# ---- 3. GW-BASIC single precision ----------------------------------------------------------------
#
# GW-BASIC single precision (Microsoft Binary Format) as PC-BASIC 2.0.8 computes it.
#
# A single is held as a plain Python float whose value is exactly representable
# in MBF: a 24-bit mantissa 0.1xxx (binary) times 2**(E-128) with the exponent
# byte E in 1..255, or 0.0.  Every such value is an exact IEEE double, so
# comparisons, negation, INT and the FOR test need no emulation; the arithmetic
# functions below reproduce the interpreter's own rounding bit for bit.
#
# Soft errors ("Overflow", "Division by zero") do not stop the computation:
# the function returns +-MAX and calls the `err` callable it was given with the
# message, in the order the interpreter prints them.
#
# Uses: nothing.
# Offers: MBF_MAX, OVERFLOW, DIV_ZERO, ErrorSink, mbf_from_bytes, mbf_to_bytes, mbf_add, mbf_sub,
#   mbf_mul, mbf_scaled, mbf_div, mbf_neg, mbf_int, mbf_write_text, mbf_print_text, mbf_sin,
#   mbf_cos, mbf_tan, mbf_atn, mbf_exp, mbf_log, mbf_sqr, mbf_power, mbf_ipower, decimal_parts,
#   mbf_parse, scaled_to_single, mbf_for_values, mbf_for_final.


MBF_MAX = math.ldexp(0xFFFFFF, 127 - 24)      # 1.701412E+38, the overflow value
OVERFLOW = "Overflow"
DIV_ZERO = "Division by zero"
ErrorSink = Callable[[str], object]     # err(message): where a soft error goes
_T24 = 16777216.0                        # 2**24
_TOP = 2.0 ** 127                        # the first magnitude beyond the single range
_BOTTOM = 2.0 ** -128                    # the smallest magnitude in it
_F32_LOW = 2.0 ** -126                   # the smallest normal IEEE single
_frexp, _ldexp = math.frexp, math.ldexp
_pack32, _unpack32 = struct.Struct("f").pack, struct.Struct("f").unpack   # IEEE singles


def _ignore(message: str) -> None:
    """Default soft-error sink: drop the message."""


# --------------------------------------------------------------------------
# representation helpers

def _split(x: float) -> tuple[bool, int, int]:
    """Return (negative, mantissa, exponent byte) of a nonzero single."""
    f, e = math.frexp(x)
    if f < 0:
        return True, int(-f * _T24), e + 128
    return False, int(f * _T24), e + 128


def _make(mbf_neg: bool, m: int, eb: int, err: ErrorSink) -> float:
    """Build a single from a 24-bit mantissa (possibly 2**24 after a rounding
    carry) and an exponent byte; handles overflow and underflow to zero."""
    if m >> 24:
        m >>= 1
        eb += 1
    if eb > 255:
        err(OVERFLOW)
        return -MBF_MAX if mbf_neg else MBF_MAX
    if eb <= 0 or m == 0:
        return 0.0
    v = math.ldexp(m, eb - 152)
    return -v if mbf_neg else v


def _round3(m: int, ah: int) -> int:
    """GW $ROUNS: keep the top 3 bits of the guard byte `ah`, round half to
    even on them.  Returns the rounded mantissa (may be 2**24)."""
    ah &= 0xE0
    if ah & 0x80:
        m += 1
        if ah == 0x80:
            m &= ~1
    return m


def mbf_from_bytes(b: bytes) -> float:
    """CVS: the single stored in 4 MBF bytes (exponent byte 0 means zero)."""
    if b[3] == 0:
        return 0.0
    m = b[0] | b[1] << 8 | (b[2] | 0x80) << 16
    v = math.ldexp(m, b[3] - 152)
    return -v if b[2] & 0x80 else v


def mbf_to_bytes(x: float) -> bytes:
    """MKS$: the 4 MBF bytes of a single (-0.0, made by unary minus of a
    zero, keeps its sign bit as in PC-BASIC)."""
    if x == 0:
        return b"\0\0\x80\0" if math.copysign(1.0, x) < 0 else bytes(4)
    mbf_neg, m, eb = _split(x)
    return bytes((m & 255, (m >> 8) & 255, ((m >> 16) & 0x7F) | (0x80 if mbf_neg else 0), eb))


# --------------------------------------------------------------------------
# the four operations

def mbf_add(x: float, y: float, err: ErrorSink = _ignore) -> float:
    """X+Y as PC-BASIC computes it (observed; data/PCBASIC_NOTES.md).
    Equal signs: the exact sum rounded to nearest, ties to even.
    Opposite signs: the smaller operand is aligned keeping one guard byte
    (bits below it are dropped; bit 5 of the guard is set when any of its
    bits 0-4 is), subtracted, normalised and rounded by GW's $ROUNS.  Two
    quirks: a one-bit normalisation whose guard reads as a tie (100xxxxx,
    not exactly 80h) on an even mantissa drops the guard first; and a small
    operand of exactly half an ulp 24 places down leaves X unchanged."""
    if x == 0:
        return y if y != 0 else 0.0          # a sum of zeros is +0, whatever their signs
    if y == 0:
        return x
    s = x + y
    if (x > 0) is (y > 0) or 0.125 < -x / y < 8.0:
        # Equal signs: the double sum is exact while the exponents are at most 28 apart;
        # further apart, it rounds to within an eighth of X's last place, and the single sum
        # is X anyway. Opposite signs, |X| and |Y| less than 8 times apart (the rounded
        # quotient is so only if the exact one is): the exponents are at most 3 apart, no bit
        # reaches the guard byte's low 5, and the guard arithmetic below rounds the exact
        # difference half to even. Either way the sum is rounded to 24 bits, half to even:
        # as IEEE single precision rounds it, where that is normal (from 2**-126).
        if _F32_LOW <= s < _TOP or -_TOP < s <= -_F32_LOW:
            v = _unpack32(_pack32(s))[0]
        elif s == 0:
            return 0.0
        else:
            f, e = _frexp(s)
            v = _ldexp(round(f * _T24), e - 24)
        if _BOTTOM <= v < _TOP or -_TOP < v <= -_BOTTOM:
            return v
        if -_BOTTOM < v < _BOTTOM:
            return 0.0
        err(OVERFLOW)
        return math.copysign(MBF_MAX, x)
    nx, mx, ex = _split(x)
    ny, my, ey = _split(y)
    if ex < ey or (ex == ey and mx < my):
        x, nx, mx, ex, ny, my, ey = y, ny, my, ey, nx, mx, ex
    c = ex - ey
    if c >= 25 or (c == 24 and my == 1 << 23):
        return x
    v = (my << 8) >> c
    d = (mx << 8) - ((v >> 8) << 8 | _sticky(v & 0xFF))
    if d == 0:
        return 0.0
    m, g = d >> 8, d & 0xFF
    if m < 1 << 23:
        if g & 0xE0 == 0x80 and g != 0x80 and not m & 1:
            g = 0
        while m < 1 << 23:
            m = m << 1 | g >> 7
            g = _sticky((g << 1) & 0xFF)
            ex -= 1
    if ex <= 0:
        return 0.0
    return _make(nx, _round3(m, g), ex, err)


def _sticky(g: int) -> int:
    """Guard byte with its sticky bit 5 set when any of bits 0-4 is set."""
    return g | 0x20 if g & 0x1F else g


def mbf_sub(x: float, y: float, err: ErrorSink = _ignore) -> float:
    """X-Y: X when Y is zero (+0 for a zero X), else X plus the negated Y."""
    if y == 0:
        return x if x != 0 else 0.0
    return mbf_add(x, -y, err)


def mbf_mul(x: float, y: float, err: ErrorSink = _ignore) -> float:
    """X*Y as GW $FMULS: the 48-bit product truncated to 24+3 bits, then
    rounded half to even on those 3 bits."""
    p = x * y                     # exact: 24x24 bits fit a double
    if p == 0:
        return 0.0
    f, e = math.frexp(p)
    t = int(abs(f) * 134217728.0)                  # 27 bits, truncated
    m, g = t >> 3, t & 7
    if g > 4 or (g == 4 and m & 1):
        m += 1
    v = math.ldexp(m, e - 24)
    if v >= _TOP:
        err(OVERFLOW)
        return math.copysign(MBF_MAX, p)
    if v < _BOTTOM:
        return 0.0
    return v if p > 0 else -v


def mbf_scaled(k: float, x: float, err: ErrorSink = _ignore) -> float:
    """K*X for K a power of two (the listing's .5, 2 and 4): mbf_mul's product, which is exact,
    so K*X itself inside the single's range (mbf_mul for the rest: 0, or "Overflow")."""
    v = k * x
    if _BOTTOM <= v < _TOP or -_TOP < v <= -_BOTTOM:
        return v
    return mbf_mul(k, x, err)


def mbf_div(x: float, y: float, err: ErrorSink = _ignore) -> float:
    """X/Y as PC-BASIC computes it (observed; data/PCBASIC_NOTES.md): restoring long
    division of the mantissas held with a guard byte (m << 8), where the
    divisor register is shifted right after each of the 24 quotient bits so
    that its low bits fall off (the quotient comes out a little too large
    for divisors with many low 1-bits); it starts one place lower when the
    dividend mantissa is the smaller.  Rounding compares the remainder with
    H = (next divisor) + 1: above rounds up, equal rounds to even.  Division
    by zero reports the error and gives +-MBF_MAX with the sign bit of X (so -0/0 is
    -MBF_MAX; the sign of a zero Y does not matter)."""
    if y == 0:
        err(DIV_ZERO)
        return math.copysign(MBF_MAX, x)
    if x == 0:
        return 0.0
    fx, ex = _frexp(x)
    fy, ey = _frexp(y)
    mx = int((fx if fx > 0 else -fx) * _T24)
    my = int((fy if fy > 0 else -fy) * _T24)
    eb = ex - ey + 129
    dv = my << 8
    if mx < my:
        dv >>= 1
        eb -= 1
    # The first 8 quotient bits in one division: dv >> i is exact for i < 8 (dv has at least
    # 7 low zero bits), so they are the exact quotient's; the other 16 follow the register.
    q, rem = divmod(mx << 15, dv)
    dv >>= 8
    # Those 16 bits take the divisor M = dv >> i at step i (M >= 2**22): each M >> i exceeds
    # the sum of all after it, so they are the largest t with S(t) <= rem, S(t) the sum of
    # M >> i over t's bits; and S(t) = t*M/2**15 - F(t), 0 <= F(t) < 16 (the fractions cut
    # off). With t0, r = divmod(rem * 2**15, M), t is t0 or t0 + 1. If t0 + 1: r > M - 2**19,
    # above H = ((M >> 16) + 1) * 2**15, and what remains, F(t0 + 1) - (M - r)/2**15, is under
    # 16, below H/2**15 (no rounding). If t0: what remains is r/2**15 + F(t0), above
    # H/2**15 (rounded up) when r > H, not when r + 16 * 2**15 <= H. Either way t0 + (r > H),
    # unless r is in (H - 2**19, H]: then the register's own loop.
    t, r = divmod(rem << 8, dv)                 # rem, a multiple of 2**7, is rem * 2**7 here
    h = ((dv >> 16) + 1) << 15
    if (r > h or r + 524288 <= h) and t < 65536:
        q = (q << 16) + t + (r > h)
    else:
        rem >>= 7
        for _ in range(16):
            q <<= 1
            if rem >= dv:
                rem -= dv
                q |= 1
            dv >>= 1
        if rem > dv + 1 or (rem == dv + 1 and q & 1):
            q += 1
    v = _ldexp(q, eb - 152)                     # q may be 2**24 (a carry): the same value
    if _BOTTOM <= v < _TOP:
        return v if (x > 0) is (y > 0) else -v
    return _make((x > 0) is not (y > 0), q, eb, err)


def mbf_neg(x: float) -> float:
    """Unary minus: flips the sign bit, also of a zero (MKS$ shows it)."""
    return -x


def mbf_int(x: float) -> float:
    """INT: the largest integer not above X (always exact in MBF)."""
    return float(math.floor(x))


# --------------------------------------------------------------------------
# decimal scaling: the register PC-BASIC multiplies and divides by ten in
#
# Numbers are turned into text and text into numbers by scaling a mantissa register by ten
# (observed; data/PCBASIC_NOTES.md, "The decimal register"). The register holds a single's 24
# bits and a guard byte (32 bits), or a double's 56 bits and a guard byte (64 bits); a value
# is (m, e) with m * 2**e, m normalised to the register's width.

def _times_ten(m: int, e: int, width: int) -> tuple[int, int]:
    """x*4 + x: the aligned x loses its two low bits, which survive as a sticky low bit; a
    carry out of the register shifts the sum right, dropping its low bit."""
    s = m + (m >> 2)
    e += 3
    if s >> width:
        s >>= 1
        e += 1
    return s | (m & 3 != 0), e


def _tenth(m: int, e: int, width: int) -> tuple[int, int]:
    """x/10: the quotient of m*8 by ten, one unit low when that is exact, cut to the
    register's width; when m is below ten's mantissa (0xA0...) the quotient has one bit
    fewer and the register is filled with a zero bit."""
    q = ((m << 3) - 1) // 10
    sh = q.bit_length() - width
    return (q >> sh if sh > 0 else q << -sh), e - 3 + sh


def _round_register(m: int, e: int, drop: int) -> tuple[int, int]:
    """Drop the low `drop` bits of the register, rounding to nearest, ties to even."""
    q = m >> drop
    rest = m & ((1 << drop) - 1)
    half = 1 << (drop - 1)
    if rest > half or (rest == half and q & 1):
        q += 1
    return q, e + drop


def _digits(x: float) -> tuple[str, int]:
    """Seven decimal digits and the decimal exponent k of |x| (x != 0), so
    that |x| ~ 0.ddddddd * 10**k, as PC-BASIC makes them (observed; see
    data/PCBASIC_NOTES.md, "Numbers to text").  The mantissa goes into the
    32-bit decimal register; a value above 9999999 is divided by ten while it
    stays above 9999999, any other value is multiplied by ten while it is
    below 999999.9375 (so a single just below a power of ten, such as
    .99999994, can print as that power: "1").  The register is rounded half
    up to 24 bits and the single is rounded like WRITE does it: mbf_add .5 in
    single if not whole, truncate."""
    f, e = _frexp(x if x > 0 else -x)
    m = int(f * 4294967296.0)          # |x| = m * 2**e, m the register's 32 bits
    e -= 32
    k = 0
    if not -9999999 <= x <= 9999999:
        while math.ldexp(m, e) > 9999999:
            m, e = _tenth(m, e, 32)
            k += 1
    else:
        # _times_ten inline while m * 2**e < 999999.9375 (with m in [2**31, 2**32): always
        # for e < -12, never for e > -12)
        while e < -12 or (e == -12 and m < 4095999744):
            s = m + (m >> 2)
            if s >> 32:
                s >>= 1
                e += 1
            m = s | (m & 3 != 0)
            e += 3
            k -= 1
    q = (m >> 8) + ((m & 0xFF) >= 0x80)
    # WRITE's mbf_add(y, .5), truncated, for y = q * 2**(e+8) < 2**24: y is whole from 2**23
    # up; below, y + .5 fits 24 bits unless it passes a power of two, and then it is less than
    # .5 over that whole number, which its rounding (to a last place of at most 1) cannot
    # carry it past: so the digits are floor(y + .5), for a whole y too.
    digits = str(int(_ldexp(q, e + 8) + 0.5))
    return digits, len(digits) + k


def _text(x: float) -> str:
    """The digits of x without sign or padding, as PRINT and WRITE show them."""
    if x == 0:
        return "0"
    d, k = _digits(x)
    d = d.rstrip("0")
    nd = len(d)
    if 0 < k <= 7:
        if nd <= k:
            return d + "0" * (k - nd)
        return d[:k] + "." + d[k:]
    if k <= 0 and nd - k <= 7:
        return "." + "0" * -k + d
    e = k - 1
    return "%s%sE%s%02d" % (d[0], "." + d[1:] if nd > 1 else "", "-" if e < 0 else "+", abs(e))


def mbf_write_text(x: float) -> str:
    """Number as WRITE # writes it: '-' for negatives, no padding."""
    return ("-" if x < 0 else "") + _text(x)


def mbf_print_text(x: float) -> str:
    """Number as PRINT shows it: sign or space in front, a space after."""
    return ("-" if x < 0 else " ") + _text(x) + " "


# --------------------------------------------------------------------------
# functions.  PC-BASIC evaluates SIN, COS, TAN, ATN, EXP, LOG, SQR and X^Y
# with a single exponent Y (whole or not: (-1)^(LOP+1) too) in IEEE double
# precision on the exact value of the single argument and converts the result
# by truncation toward zero to 23 significant bits (24 from 2**23 up), so the
# last mantissa bit of a result below 2**23 is always 0.  X^N with an integer
# exponent (the literal 2 of T^2) is repeated multiplication: mbf_ipower.

_TRIG_LIMIT = 5e16       # SIN/COS/TAN of |x| >= this give 0, 1, 0
_TINY = math.ldexp(1.0, -1001)   # double results this small count as overflow


def _from_float(v: float, err: ErrorSink) -> float:
    """Single from the IEEE double v: truncate toward zero to 23 significant
    bits (24 bits when |v| >= 2**23).  |v| >= 2**127 and, oddly, also
    0 < |v| <= 2**-1001 report "Overflow" and give +MBF_MAX whatever the sign;
    other results below the single range give 0."""
    if v == 0:
        return 0.0
    f, e = math.frexp(abs(v))
    if e >= 128 or abs(v) <= _TINY:
        err(OVERFLOW)
        return MBF_MAX
    bits = 24 if e >= 24 else 23
    m = int(f * (1 << bits)) << (24 - bits)
    return _make(v < 0, m, e + 128, err)


def mbf_sin(x: float, err: ErrorSink = _ignore) -> float:
    """SIN: math.sin, truncated to 23 bits; 0 when |x| >= 5E+16."""
    return 0.0 if abs(x) >= _TRIG_LIMIT else _from_float(math.sin(x), err)


def mbf_cos(x: float, err: ErrorSink = _ignore) -> float:
    """COS: math.cos, truncated to 23 bits; 1 when |x| >= 5E+16."""
    return 1.0 if abs(x) >= _TRIG_LIMIT else _from_float(math.cos(x), err)


def mbf_tan(x: float, err: ErrorSink = _ignore) -> float:
    """TAN: math.tan, truncated to 23 bits; 0 when |x| >= 5E+16."""
    return 0.0 if abs(x) >= _TRIG_LIMIT else _from_float(math.tan(x), err)


def mbf_atn(x: float, err: ErrorSink = _ignore) -> float:
    """ATN: math.atan, truncated to 23 bits."""
    return _from_float(math.atan(x), err)


def mbf_exp(x: float, err: ErrorSink = _ignore) -> float:
    """EXP: math.exp, truncated to 23 bits (24 from 2**23 up); above the
    single range "Overflow" and +MBF_MAX, below it 0."""
    try:
        v = math.exp(x)
    except OverflowError:
        err(OVERFLOW)
        return MBF_MAX
    return _from_float(v, err)


def mbf_log(x: float, err: ErrorSink = _ignore) -> float:
    """LOG: math.log, truncated to 23 bits; X <= 0 is an Illegal function
    call (ValueError)."""
    if x <= 0:
        raise ValueError("Illegal function call")
    return _from_float(math.log(x), err)


def mbf_sqr(x: float, err: ErrorSink = _ignore) -> float:
    """SQR: math.sqrt, truncated to 23 bits (24 from 2**23 up); X < 0 is an
    Illegal function call (ValueError)."""
    if x < 0:
        raise ValueError("Illegal function call")
    return _from_float(math.sqrt(x), err)


def mbf_power(x: float, y: float, err: ErrorSink = _ignore) -> float:
    """X^Y with a single (or double) exponent Y, whole or not: math.pow
    truncated to 23 bits.  Y = 0 gives 1; 0^Y is 0 for Y > 0 and "Division
    by zero" with +MBF_MAX for Y < 0; a negative X with a fractional Y is an
    Illegal function call (ValueError); overflow gives +MBF_MAX for either sign."""
    if y == 0:
        return 1.0
    if x == 0:
        if y < 0:
            err(DIV_ZERO)
            return MBF_MAX
        return 0.0
    if x < 0 and y != math.floor(y):
        raise ValueError("Illegal function call")
    try:
        v = math.pow(x, y)
    except OverflowError:
        err(OVERFLOW)
        return MBF_MAX
    return _from_float(v, err)


def mbf_ipower(x: float, n: int, err: ErrorSink = _ignore) -> float:
    """X^N with an integer-typed exponent (an integer literal such as the 2
    in T^2, or an N% variable).  N >= 1: left-to-right binary powering with
    single multiplications (square, then times X for each further 1 bit of
    N); the first overflow ends it with +-MBF_MAX of that product's sign.
    N = 0 gives 1; N < 0 is computed like mbf_power()."""
    if n == 2:
        return mbf_mul(x, x, err)        # the same, one overflow at most
    if n < 0:
        return mbf_power(x, float(n), err)
    if n == 0:
        return 1.0
    seen: list[str] = []
    r = x
    for bit in bin(n)[3:]:
        r = mbf_mul(r, r, seen.append)
        if not seen and bit == "1":
            r = mbf_mul(r, x, seen.append)
        if seen:
            err(OVERFLOW)
            return r
    return r


# --------------------------------------------------------------------------
# text to number, FOR loops

def decimal_parts(text: str) -> tuple[bool, int, int, bool]:
    """A decimal number's text as (negative, N, k, double): its value is N * 10**k, and
    `double` tells that it is read in double precision: a # after it, a D exponent, or eight
    digits or more without a ! after it, counted from the first nonzero one and not counting
    zeros that end the fraction ("7105.4530" has seven, "71054530" eight)."""
    s = text.strip().upper()
    suffix = s[-1:]
    s = s.rstrip("!#%")
    negative = s.startswith("-")
    s = s.lstrip("+-")
    mantissa, _, exponent = s.replace("D", "E").partition("E")
    whole, _, fraction = mantissa.partition(".")
    digits = (whole + fraction).lstrip("0")
    counted = len(digits) - min(len(fraction) - len(fraction.rstrip("0")), len(digits))
    k = (int(exponent) if exponent.strip("+-") else 0) - len(fraction)
    double = suffix == "#" or "D" in s or (counted >= 8 and suffix != "!")
    return negative, int(digits or "0"), k, double


def mbf_parse(text: str, err: ErrorSink = _ignore) -> float:
    """A number typed at INPUT or written as a program literal (`.5`, `180!`,
    `2`, `1e3`, `3.141592654#`, `  -12  `) as the single it becomes (observed;
    data/PCBASIC_NOTES.md, "Text to numbers"): the digits as an integer N in
    the decimal register (a double's 64 bits, or a single's 32 with N first
    cut to 24 bits), multiplied or divided by ten once a decimal place, then
    rounded to nearest, ties to even, on the guard byte of the 32 bits (a
    double is first rounded so to 56 bits, and its top 32 bits kept)."""
    negative, n, k, double = decimal_parts(text)
    return scaled_to_single(negative, n, k, double, err) if n else 0.0


def scaled_to_single(negative: bool, n: int, k: int, double: bool,
                     err: ErrorSink) -> float:
    """N * 10**k through the decimal register (see mbf_parse); n may be 0 only with the
    zero-mantissa quirk of input_value (n=0 reads as 2**-129)."""
    width = 64 if double else 32
    if n == 0:
        m, e = 1 << (width - 1), -129 - (width - 1)
    else:
        if not double and n.bit_length() > 24:     # only with zeros ending the fraction
            cut = n.bit_length() - 24
            n = n >> cut << cut
        sh = n.bit_length() - width
        m, e = (n >> sh, sh) if sh > 0 else (n << -sh, sh)
    for _ in range(-k):
        m, e = _tenth(m, e, width)
        if e < -400:                                # far below the single range
            return 0.0
    for _ in range(k):
        m, e = _times_ten(m, e, width)
        if e > 400:                                 # far above it
            break
    if double:
        m, e = _round_register(m, e, 8)             # the double: 56 bits
        if m >> 56:
            m, e = m >> 1, e + 1
        m, e = m >> 24, e + 24                      # made single: its top 32 bits
    m, e = _round_register(m, e, 8)
    return _make(negative, m, e + 152, err)


def mbf_for_values(start: float, stop: float, step: float,
                   err: ErrorSink = _ignore) -> Iterator[float]:
    """The values a single FOR variable takes: FOR V=start TO stop STEP step
    runs the body with V=start unless start is already past stop, then adds
    step in single precision after each pass and goes on while V has not
    passed stop (STEP 0 runs the body once).  The last value yielded is not
    the variable's value after the loop: see mbf_for_final()."""
    v = start
    if (step > 0 and v > stop) or (step < 0 and v < stop):
        return
    while True:
        yield v
        v = mbf_add(v, step, err)
        if not ((step > 0 and v <= stop) or (step < 0 and v >= stop)):
            return


def mbf_for_final(start: float, stop: float, step: float,
                  err: ErrorSink = _ignore) -> float:
    """The FOR variable's value after the loop has ended (start+step when
    the body never ran)."""
    last = start
    for last in mbf_for_values(start, stop, step, err):
        pass
    return mbf_add(last, step, err)


# ---- 4. The listing's computation: lines 110, 250-930 and 1050-1340 ------------------------------
#
# The listing's variables keep their BASIC names here, so that this section can be read beside
# legacy_basic/LINKAGE.BAS line by line. In the paper's symbols (eqs. (1)-(3), Table 1):
#
#   listing          paper                     listing         paper
#   A B C D          a b c d (fixed link,      P(1..8)         p1..p8, real parts
#                    crank, coupler, output)   PIM(1..8)       p1..p8, imaginary parts
#   E                e (slider offset)         A1 B1 C1 D1 E1  A1 A2 A3 A4 A5
#   F, KSI, G        f, xi, g = f / cos xi     F1 G1 H1 I1 J1  A6 A7 A8 A9 A10
#   S                s (1 for slider-cranks)   T, U(1..2)      t = tan(phi/2), u (or x)
#   BT CT DT DIAG    b c d a for the check     M1, M11         m1 (dpsi/dphi), m1' (sliders)
#   CIM              1: coupler imaginary      M2, M22         m2, m2' (eqs. (5)-(7))
#
# Arithmetic is GW-BASIC's: a `Single` rounds every + - * / ^ as PC-BASIC does, and Python's
# operator precedence is BASIC's (^ first, then unary minus, then * /, then + -, each left to
# right), so an expression below evaluates in the listing's order when written as the listing
# writes it. Literals (2, .5, 180 for 180!) are exact singles. Soft errors ("Overflow",
# "Division by zero") go, in order, to the list of the soft_errors() block they happen in - a
# session's own (Screen.errors), for its screen to show: a context variable, so that two
# sessions in one process, in two threads or contexts, never see each other's.
#
# Uses: section 3.
# Offers: Single, soft_errors, soft_error, SIN, COS, TAN, ATN, INT, ZERO, PI, Variables, PROMPTS,
#   dimensions, ASSEMBLY_NAMES, assembly_refusal, coefficients, degrees_to_radians, sweep_angles,
#   DatLines, sweep_point, sweep_points, sweep_point_fast, sweep_point_as_listed.


class Single:
    """A GW-BASIC single-precision value; arithmetic rounds as PC-BASIC 2.0.8 does.

    The value is the float `v`. The other operand of an operator is a Single or a literal of
    the listing (2, .5). Adding or multiplying by a zero is answered here without calling the
    mbf_ function (over half of the plane four-bar's terms are zeros), and results are made
    with object.__new__ (together about 5 % of the time of a sweep point)."""

    __slots__ = ("v", "_square")
    v: float
    _square: Single                     # T^2, remembered (see __pow__)

    def __init__(self, v: float = 0.0) -> None:
        self.v = v

    def __repr__(self) -> str:
        return f"Single({mbf_write_text(self.v)})"

    def __add__(self, other: Single | float) -> Single:
        y = other.v if other.__class__ is Single else float(other)
        if y == 0:                              # a sum of zeros is +0 (mbf_add)
            return self if self.v != 0 else ZERO
        if self.v == 0:
            return _single(y)
        return _single(mbf_add(self.v, y, soft_error))

    def __radd__(self, other: float) -> Single:
        return _single(mbf_add(float(other), self.v, soft_error))

    def __sub__(self, other: Single | float) -> Single:
        return _single(mbf_sub(self.v, other.v if other.__class__ is Single else float(other),
                               soft_error))

    def __rsub__(self, other: float) -> Single:
        return _single(mbf_sub(float(other), self.v, soft_error))

    def __mul__(self, other: Single | float) -> Single:
        y = other.v if other.__class__ is Single else float(other)
        if y == 0 or self.v == 0:               # a product with a zero is +0 (mbf_mul)
            return ZERO
        return _single(mbf_mul(self.v, y, soft_error))

    def __rmul__(self, other: float) -> Single:
        if self.v == 0:
            return ZERO
        return _single(mbf_mul(float(other), self.v, soft_error))

    def __truediv__(self, other: Single | float) -> Single:
        return _single(mbf_div(self.v, other.v if other.__class__ is Single else float(other),
                               soft_error))

    def __rtruediv__(self, other: float) -> Single:
        return _single(mbf_div(float(other), self.v, soft_error))

    def __pow__(self, other: Single | float) -> Single:
        if other.__class__ is not int:
            return _single(mbf_power(self.v, _value(other), soft_error))
        if other != 2:                 # an integer literal: repeated multiplication
            return _single(mbf_ipower(self.v, other, soft_error))
        # T^2 comes twenty times a point: remembered, unless it overflowed (the interpreter
        # says "Overflow" each time it evaluates it)
        try:
            return self._square
        except AttributeError:
            overflowed = []

            def err(message: str) -> None:
                overflowed.append(message)
                soft_error(message)
            square = _single(mbf_mul(self.v, self.v, err))
            if not overflowed:
                self._square = square
            return square

    def __rpow__(self, other: float) -> Single:
        return _single(mbf_power(float(other), self.v, soft_error))

    def __float__(self) -> float: return self.v
    def __neg__(self) -> Single: return _single(mbf_neg(self.v))
    def __lt__(self, other: Single | float) -> bool: return self.v < _value(other)
    def __le__(self, other: Single | float) -> bool: return self.v <= _value(other)
    def __gt__(self, other: Single | float) -> bool: return self.v > _value(other)
    def __ge__(self, other: Single | float) -> bool: return self.v >= _value(other)
    # a Single equals a number only, as BASIC compares them (object's __eq__ takes anything)
    def __eq__(self, other: Single | float) -> bool:  # type: ignore[override]
        return self.v == _value(other)

    def __hash__(self) -> int: return hash(self.v)


def _single(v: float) -> Single:
    """Single(v) without the call of __init__ (an operator's result)."""
    s = _new_object(Single)
    s.v = v
    return s


_new_object = object.__new__


def _value(x: Single | float) -> float:
    return x.v if x.__class__ is Single else float(x)


_SOFT_ERRORS: contextvars.ContextVar[list[str]] = contextvars.ContextVar("soft_errors")


@contextlib.contextmanager
def soft_errors(sink: list[str] | None = None) -> Iterator[list[str]]:
    """The soft errors of the GW-BASIC operations in the block go to `sink` (a new list if none
    is given), which the block yields; the previous one is back after it."""
    sink = [] if sink is None else sink
    token = _SOFT_ERRORS.set(sink)
    try:
        yield sink
    finally:
        _SOFT_ERRORS.reset(token)


def soft_error(message: str) -> None:
    """The `err` of the operators: the message to the current soft_errors() block's list
    (outside one, where no screen would show it, it is dropped)."""
    sink = _SOFT_ERRORS.get(None)
    if sink is not None:
        sink.append(message)


def SIN(x: Single) -> Single: return Single(mbf_sin(x.v, soft_error))
def COS(x: Single) -> Single: return Single(mbf_cos(x.v, soft_error))
def TAN(x: Single) -> Single: return Single(mbf_tan(x.v, soft_error))
def ATN(x: Single) -> Single: return Single(mbf_atn(x.v, soft_error))
def INT(x: Single) -> Single: return Single(mbf_int(x.v))


ZERO = Single(0.0)
PI = Single(mbf_parse("3.141592654#"))                                  # 110
_PI = PI.v


class Variables:
    """The listing's variables that matter between passes through the menu: "Illegal linkage"
    goes back with GOTO 130, not RUN, so every one keeps its value (ERRATA K1-K3). Each starts
    at 0, as after RUN (a class attribute until assigned: a Single is never changed in place)."""

    A = B = C = D = E = F = G = KSI = S = CIM = BT = CT = DT = DIAG = ZERO


PROMPTS = {
    "b": "Please enter the input crank length: ",
    "c": "       enter the connecting rod length: ",
    "d": "       enter the output crank length: ",
    "a": "       enter the fixed link length: ",
    "a-skew": "       enter the horizontal sector of the fixed link length: ",
    "e": "       enter the center offset: ",
    "f": "       enter the vertical sector of the fixed link: ",
    "ksi": "       enter the skew angle: ",
    "from": "Enter the first bound of the input angle: ",
    "to": "Enter the second bound of the input angle: ",
    "step": "Enter increment: ",
}


def dimensions(v: Variables, bartype: int, ask: Callable[[str], Single]) -> bool:
    """Lines 250-480: ask for linkage `bartype`'s dimensions (ask(prompt) is INPUT), convert
    them and run the assembly check. True when the linkage passes it."""
    if bartype >= 4:                                                        # 250
        v.S = Single(1.0)
    v.B = ask(PROMPTS["b"]); v.BT = v.B                                     # 260
    v.C = ask(PROMPTS["c"]); v.CT = v.C                                     # 270
    if not v.S == 1:                                                        # 280
        v.D = ask(PROMPTS["d"]); v.DT = v.D                                 # 290
    if bartype <= 2:                                                        # 300
        v.A = ask(PROMPTS["a"]); v.DIAG = v.A
    if bartype in (3, 5):                                                   # 310
        v.A = ask(PROMPTS["a-skew"])
    if bartype == 4:                                                        # 320
        v.E = ask(PROMPTS["e"])
        v.C = (v.C**2 - v.E**2)                                             # 450
    else:
        if bartype == 2:                                                    # 330
            v.A = (v.A / 180) * PI; v.DIAG = v.A - (INT(v.A / PI) * PI)     # 340
            v.B = (v.B / 180) * PI; v.BT = v.B - (INT(v.B / PI) * PI)       # 350
            v.C = (v.C / 180) * PI; v.CT = v.C - (INT(v.C / PI) * PI)       # 360
            v.D = (v.D / 180) * PI; v.DT = v.D - (INT(v.D / PI) * PI)       # 370
        if bartype not in (3, 5):                                           # 380
            return _assembles(v, bartype)
        v.F = ask(PROMPTS["f"])                                             # 390
        v.KSI = ask(PROMPTS["ksi"]); v.KSI = (v.KSI / 180) * PI             # 400
        v.DIAG = (v.A**2 + (v.F * TAN(v.KSI))**2)**.5
        if bartype == 5:                                                    # 410
            v.G = ZERO
        else:
            v.G = v.F / COS(v.KSI)                                          # 420
        v.C = (v.C**2 - v.F**2 - v.G**2 + 2 * v.F * v.G * COS(v.KSI))       # 430
    if v.C >= 0:                                                            # 460
        v.C = v.C**.5; v.CIM = ZERO
    if v.C < 0:                                                             # 470
        v.CIM = Single(1.0); v.C = (-v.C)**.5
    return _assembles(v, bartype)


def _assembles(v: Variables, bartype: int) -> bool:
    """Line 480, the assembly check (none for the plane slider-crank; see ERRATA K4)."""
    DIAG, BT, CT, DT = v.DIAG, v.BT, v.CT, v.DT
    return not (bartype != 4 and (DIAG > BT + CT + DT or BT > DIAG + CT + DT
                                  or CT > DIAG + BT + DT or DT > DIAG + BT + CT))


ASSEMBLY_NAMES = {"DIAG": "the fixed link DIAG", "BT": "the input crank BT",
                  "CT": "the connecting rod CT", "DT": "the output crank DT"}


def assembly_refusal(v: Variables, bartype: int) -> str:
    """Why line 480 refuses the linkage: the link longer than the other three together, in the
    units typed (a spherical arc in degrees, modulo 180 as line 340-370 reduce it, ERRATA K11;
    the skew slider-crank's DT is the output crank it never asks for, K4)."""
    links = {name: getattr(v, name).v for name in ASSEMBLY_NAMES}
    degrees = bartype == 2
    if degrees:
        links = {name: value * 180 / math.pi for name, value in links.items()}
    longest = max(links, key=lambda name: links[name] - (sum(links.values()) - links[name]))
    others = [name for name in links if name != longest]
    unit = " degrees" if degrees else ""
    note = {2: " (the arcs taken modulo 180 degrees, ERRATA K11)",
            3: " (DIAG = (a^2 + (f tan ksi)^2)^.5)",
            5: " (DIAG = (a^2 + (f tan ksi)^2)^.5; DT is the output crank the skew slider-crank "
               "is never asked for, ERRATA K4)"}.get(bartype, "")
    return (f"line 480: {ASSEMBLY_NAMES[longest]} = {links[longest]:.7g}{unit} is longer than "
            f"{' + '.join(others)} = {sum(links[n] for n in others):.7g}{unit}{note}")


def coefficients(v: Variables, bartype: int) -> tuple[Single, ...]:
    """Lines 520-930: the coefficients A1..J1 of the half-tangent equation (2)."""
    A, B, C, D, F, G, KSI, S = v.A, v.B, v.C, v.D, v.F, v.G, v.KSI, v.S
    P, PIM = [ZERO] * 9, [ZERO] * 9                     # P(1..8), PIM(1..8); index 0 unused
    if v.CIM == 0:                                                          # 520
        P[1] = (A - B + C - D) / 2; P[2] = (A - B - C - D) / 2              # 540
        P[3] = (A + B + C - D) / 2; P[4] = (A + B - C - D) / 2              # 550
        P[5] = (A - B + C + D) / 2; P[6] = (A - B - C + D) / 2              # 560
        P[7] = (A + B + C + D) / 2; P[8] = (A + B - C + D) / 2              # 570
    else:
        for LOP in range(1, 9):                                             # 590
            PIM[LOP] = ((-Single(1.0))**(Single(float(LOP)) + 1)) * C / 2
        P[1] = (A - B - D) / 2; P[2] = P[1]                                 # 600
        P[3] = (A + B - D) / 2; P[4] = P[3]                                 # 610
        P[5] = (A - B + D) / 2; P[6] = P[5]                                 # 620
        P[7] = (A + B + D) / 2; P[8] = P[7]                                 # 630
    if bartype == 3:                                                        # 640
        A1 = (P[7] * P[8]) - (PIM[7] * PIM[8])                              # 650
        B1 = (P[1] * P[2]) - (PIM[1] * PIM[2])                              # 660
        C1 = (P[3] * P[4]) - (PIM[3] * PIM[4])                              # 670
        D1 = -2 * COS(KSI) * B * D                                          # 680
        E1 = (P[5] * P[6]) - (PIM[5] * PIM[6])                              # 690
        F1 = -G * B * SIN(KSI)                                              # 700
        G1 = F * D * SIN(KSI); H1 = I1 = J1 = ZERO                          # 710
    elif bartype >= 4:                                                      # 730
        A1 = 4 * ((P[7] * P[8]) - (PIM[7] * PIM[8])); B1 = S; C1 = S        # 740
        D1 = -4 * B * SIN(KSI)                                              # 750
        if bartype == 4:
            D1 = ZERO
        E1 = 4 * ((P[5] * P[6]) - (PIM[5] * PIM[6]))                        # 760
        F1 = G1 = I1 = ZERO                                                 # 770
        if bartype == 4:
            I1 = -4 * v.E * B
        H1 = -2 * F * COS(KSI)                                              # 780
        if bartype == 4:
            H1 = -2 * B
        J1 = -2 * F * COS(KSI)                                              # 790
        if bartype == 4:
            J1 = 2 * B
    elif bartype == 2:                                                      # 800
        A1 = SIN(P[7]) * SIN(P[8])                                          # 810
        B1 = SIN(P[1]) * SIN(P[2])                                          # 820
        C1 = SIN(P[3]) * SIN(P[4])                                          # 830
        D1 = -2 * SIN(B) * SIN(D)                                           # 840
        E1 = SIN(P[5]) * SIN(P[6])                                          # 850
        F1 = G1 = H1 = I1 = J1 = ZERO                                       # 860
    else:                                                                   # 870
        A1 = P[7] * P[8]                                                    # 880
        B1 = P[1] * P[2]                                                    # 890
        C1 = P[3] * P[4]                                                    # 900
        D1 = -2 * B * D                                                     # 910
        E1 = P[5] * P[6]                                                    # 920
        F1 = G1 = H1 = I1 = J1 = ZERO                                       # 930
    return A1, B1, C1, D1, E1, F1, G1, H1, I1, J1


def degrees_to_radians(x: Single) -> Single:
    """Lines 960, 1000, 1010: (X/180!)*PI."""
    return (x / 180) * PI


def sweep_angles(PHI1: Single, PHI2: Single, INC: Single) -> Iterator[Single]:
    """Line 1050, FOR PHI=PHIB(1) TO PHIB(2) STEP INC: the values PHI takes."""
    for phi in mbf_for_values(PHI1.v, PHI2.v, INC.v, soft_error):
        yield Single(phi)


def _roots_and_angle_line(U11: Single, U12: Single, PHI: Single, SOL: int,
                          S: Single) -> tuple[tuple[Single, Single], str, str]:
    """Lines 1100-1150: the two roots U(1), U(2), the input angle's text and the ANG.DAT line
    (the output angle in degrees for the four-bars, S = 0; the root itself for the sliders)."""
    U = (U11 + U12, U11 - U12)                                                           # 1100-1110
    PSI: tuple[Single, ...] = U                                                          # 1120
    if S == 0:                                                                           # 1130-1140
        PSI = tuple((2*ATN(u)/PI)*180 for u in U)
    angle = mbf_write_text(((PHI/PI)*180).v)
    return U, angle, f"{angle},{mbf_write_text(PSI[SOL - 1].v)}\r\n"                   # 1150


def _clip3(m: float) -> float:
    """Lines 1200-1210 and 1290-1300: VEL and ACC are clipped to +-3."""
    return 3.0 if m > 3 else -3.0 if m < -3 else m


DatLines: TypeAlias = tuple[str, str | None, str | None]   # ANG.DAT's, VEL.DAT's, ACC.DAT's line


def _write_lines(angle: str, ang: str, m1: float, m2: float,
                 derivatives: int) -> tuple[str, str, str | None]:
    """Lines 1200-1210, 1290-1300 and 1320-1330: the VEL.DAT and ACC.DAT lines beside the
    ANG.DAT line (ACC's only if `derivatives` is 2), VEL and ACC clipped to +-3."""
    vel = f"{angle},{mbf_write_text(_clip3(m1))}\r\n"
    if derivatives == 1:
        return ang, vel, None
    return ang, vel, f"{angle},{mbf_write_text(_clip3(m2))}\r\n"


def sweep_point(co: tuple[Single, ...], PHI: Single, SOL: int, S: Single,
                derivatives: int = 2) -> DatLines:
    """Lines 1060-1330 at one input angle: the lines WRITE # puts in ANG.DAT, VEL.DAT, ACC.DAT
    for solution SOL (1 is (A+B), 2 is (A-B)). The program always computes all three; a scene
    that shows fewer asks for `derivatives` 0 (lines 1060-1150 only) or 1 (without lines
    1220-1300), and gets None for what it did not ask for.

    The listing evaluates some subexpressions several times (the numerator of line 1070 three
    times, the sum of line 1250 twice a root); every evaluation gives the same single, so this
    computes each once (sweep_point_fast), about a third fewer operations. What is not the same
    is the screen: a subexpression that overflows says "Overflow" each time it is evaluated. So a
    point that raises any soft error is computed again as the listing writes it
    (sweep_point_as_listed), and its messages are those.

    One point (the tests' and bench's entry); a sweep makes its point function once
    (sweep_points, as session_sweep does) and calls it at each angle."""
    return sweep_points(co, SOL, S, derivatives)(PHI)



def sweep_points(co: tuple[Single, ...], SOL: int, S: Single,
                 derivatives: int = 2) -> Callable[[Single], DatLines]:
    """sweep_point for every point of one sweep: what the coefficients alone make (G1+J1,
    .5*D1, ...) is computed once, not at each point (all points, as listed, if that says
    anything)."""
    try:
        constants = _sweep_constants(co, derivatives)
    except _Redo:
        return lambda PHI: sweep_point_as_listed(co, PHI, SOL, S, derivatives)

    def point(PHI: Single) -> DatLines:
        try:
            return _point_fast(constants, PHI.v, SOL, S.v, derivatives)
        except _Redo:
            return sweep_point_as_listed(co, PHI, SOL, S, derivatives)
    return point


class _Redo(Exception):
    """A soft error in sweep_point_fast: the point is to be computed as listed."""


def _redo(message: str) -> None:
    raise _Redo(message)


def _sweep_constants(co: tuple[Single, ...], derivatives: int) -> tuple[float, ...]:
    """The coefficients' floats and what they alone make in lines 1070-1250: G1+J1, G1+H1,
    .5*D1, .5*F1, .5*I1, .5*(G1+J1), .5*(G1+H1) and 2*C1 (_Redo on a soft error)."""
    A1, B1, C1, D1, E1, F1, G1, H1, I1, J1 = [c.v for c in co]
    GJ, GH = mbf_add(G1, J1, _redo), mbf_add(G1, H1, _redo)
    if derivatives == 0:
        return A1, B1, C1, D1, E1, F1, G1, H1, I1, J1, GJ, GH, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    HD, HF, HI = (mbf_scaled(.5, x, _redo) for x in (D1, F1, I1))
    GJH, GHH = mbf_scaled(.5, GJ, _redo), mbf_scaled(.5, GH, _redo)
    C12 = mbf_scaled(2.0, C1, _redo) if derivatives == 2 else 0.0
    return A1, B1, C1, D1, E1, F1, G1, H1, I1, J1, GJ, GH, HD, HF, HI, GJH, GHH, C12


def sweep_point_fast(co: tuple[Single, ...], PHI: Single, SOL: int, S: Single,
                     derivatives: int = 2) -> DatLines:
    """sweep_point with each repeated subexpression computed once, in the listing's order of
    operations (a+b+c is (a+b)+c, a*b*c is (a*b)*c), on the singles' floats with the mbf_
    functions (no Single made: half the time; the literals .5, 2 and 4 by mbf_scaled); the first
    soft error raises _Redo. X-Y is X+(-Y) (mbf_sub); the sums and products commute, so
    U(LOP)^2+1 is 1+U(LOP)^2. Lines 1130-1140 are computed for PSI(SOL) only: ATN is within
    +-PI/2, so the other PSI can raise no soft error; and the root not written only where it
    could (_quiet_root). A sweep runs the same _point_fast through sweep_points."""
    return _point_fast(_sweep_constants(co, derivatives), PHI.v, SOL, S.v, derivatives)


def _point_fast(constants: tuple[float, ...], phi: float, SOL: int, S: float,
                derivatives: int) -> DatLines:
    """sweep_point_fast from the sweep's constants (_sweep_constants), PHI's and S's floats."""
    A1, B1, C1, D1, E1, F1, G1, H1, I1, J1, GJ, GH, HD, HF, HI, GJH, GHH, C12 = constants
    add, mul, scaled, div, e = mbf_add, mbf_mul, mbf_scaled, mbf_div, _redo
    T = mbf_tan(scaled(.5, phi, e), e)                                                   # 1060
    T2 = mul(T, T, e)
    D1T, F1T = mul(D1, T, e), mul(F1, T, e)
    GJT2 = mul(GJ, T2, e)
    NUM = add(add(D1T, GJT2, e), GH, e)                           # D1*T + (G1+J1)*T^2 + (G1+H1)
    DEN = add(add(B1, mul(C1, T2, e), e), F1T, e)                 # B1 + C1*T^2 + F1*T
    DEN2 = scaled(2.0, DEN, e)
    U11 = div(-NUM, DEN2, e)                                                             # 1070
    NUM2 = mul(NUM, NUM, e)
    DISC = mul(scaled(4.0, DEN, e),                               # 4*DEN*(A1*T^2+E1+F1*T+I1*T)
               add(add(add(mul(A1, T2, e), E1, e), F1T, e), mul(I1, T, e), e), e)
    if NUM2 < DISC:                                                                      # 1080
        U11 = U12 = 0.0
        UIM = True
    else:
        UIM = False
        U12 = div(mbf_power(add(NUM2, -DISC, e), .5, e), DEN2, e)                        # 1090
    U = (add(U11, U12, e), add(U11, -U12, e))                                            # 1100-1110
    PSI = U[SOL - 1]                                                                     # 1120
    if S == 0:                                                                           # 1130-1140
        PSI = mul(div(scaled(2.0, mbf_atn(PSI, e), e), _PI, e), 180.0, e)
    angle = mbf_write_text(mul(div(phi, _PI, e), 180.0, e))
    ang = f"{angle},{mbf_write_text(PSI)}\r\n"                                          # 1150
    if derivatives == 0:
        return ang, None, None
    OT = add(1.0, T2, e)
    NEG_OT = -OT
    A1T, C1T, GJT = mul(A1, T, e), mul(C1, T, e), mul(GJ, T, e)
    TAIL = mul(HD, T, e)                                          # .5*D1*T, then + F1*u*T ...
    GJT2H = mul(GJH, T2, e)
    P1B = Q1A = C2T = T3 = 0.0
    if derivatives == 2:
        P1B = add(add(add(GJT2, D1T, e), G1, e), H1, e)           # (G1+J1)*T^2 + D1*T + G1 + H1
        Q1A = scaled(2.0, OT, e)
        C2T = mul(C12, T, e)
        T3 = add(mul(3.0, T2, e), 1.0, e)
    for k, u in enumerate(U):                                                            # 1160
        if k != SOL - 1 and _quiet_root(u, T, T2, constants, (
                OT, DEN, TAIL, GJT2H, GHH, A1T, C1T, HD, HF, GJT, HI, GJ, P1B, Q1A, C2T, T3),
                derivatives):
            continue            # the root not written, which can say nothing: not computed
        U2 = mul(u, u, e)
        OU = add(1.0, U2, e)
        C1u, F1u = mul(C1, u, e), mul(F1, u, e)
        # the sum of lines 1170 and 1250: B1*u + C1*u*T^2 + .5*D1*T + F1*u*T + .5*(G1+J1)*T^2
        # + .5*(G1+H1)
        S0 = add(add(add(add(add(mul(B1, u, e), mul(C1u, T2, e), e), TAIL, e), mul(F1u, T, e), e),
                     GJT2H, e), GHH, e)
        # 1170: -(1+T^2)*(A1*T + C1*T*u^2 + .5*D1*u + .5*F1*(u^2+1) + (G1+J1)*T*u + .5*I1)
        #       / ((1+u^2)*S0)
        M1 = div(mul(NEG_OT, add(add(add(add(add(A1T, mul(C1T, U2, e), e), mul(HD, u, e), e),
                                             mul(HF, OU, e), e), mul(GJT, u, e), e), HI, e), e),
                 mul(OU, S0, e), e)
        M11 = M1                                                                         # 1172
        if S == 1:                                                                       # 1175
            M11 = div(mul(OU, M1, e), 2.0, e)
        if UIM:                                                                          # 1180
            M11 = M1 = 0.0
        if derivatives == 2:
            P1 = add(mul(add(mul(3.0, U2, e), 1.0, e), DEN, e), mul(u, P1B, e), e)       # 1220
            Q1 = mul(Q1A, add(add(add(mul(C2T, u, e), HD, e), F1u, e), GJT, e), e)       # 1230
            # 1240: ((1+T^2)/(1+u^2))*((3*T^2+1)*(A1 + C1*u^2 + (G1+J1)*u)
            #       + T*(F1*(u^2+1) + D1*u + I1))
            R1 = mul(div(OT, OU, e),
                     add(mul(T3, add(add(A1, mul(C1, U2, e), e), mul(GJ, u, e), e), e),
                         mul(T, add(add(mul(F1, OU, e), mul(D1, u, e), e), I1, e), e), e), e)
            S1 = scaled(2.0, S0, e)                                                      # 1250
            M1S = mul(M1, M1, e)
            M2 = div(-add(add(mul(P1, M1S, e), mul(Q1, M1, e), e), R1, e), S1, e)       # 1260
            M22 = M2                                                                     # 1262
            if S == 1:                                                                   # 1265
                M22 = div(mul(add(mul(M1S, u, e), M2, e), OU, e), 2.0, e)
            if UIM:                                                                      # 1270
                M22 = 0.0
        if k == SOL - 1:
            vel, acc = M11, (M22 if derivatives == 2 else 0.0)     # 0.0: not written
    return _write_lines(angle, ang, vel, acc, derivatives)                              # 1200-1330


_QUIET_LIMIT = 2.0 ** 120      # a bound below it leaves 2**7 to the largest single, 2**127
_QUIET_SLACK = 2.0 ** -18     # 10 roundings in S0, each within 1.5 ulps (measured): < 2**-20.3


def _quiet_root(u: float, T: float, T2: float, co: tuple[float, ...],
                singles: tuple[float, ...], derivatives: int) -> bool:
    """Whether lines 1170-1300 for the root u certainly raise no soft error, so that
    sweep_point_fast may leave out the root it does not write (a third of a point's
    operations). Each value of those lines is bounded above in doubles from the singles they
    start from (a sum by the sum of its terms' bounds, a product by the product of theirs, a
    quotient by its numerator's over a lower bound of its divisor), and none may come near
    2**127 ("Overflow"); the one divisor that can be zero, S0 of line 1170 (2*S0 in line
    1260), must be away from zero by more than its roundings and underflows can move it
    ("Division by zero"). A single rounding is within 1.5 ulps (2**-23.4), and the bounds
    allow 1e-4 over a line, so no bound is crossed unseen. False: the root is computed."""
    A1, B1, C1, D1, _, F1, _, _, I1 = co[:9]
    OT, DEN, TAIL, GJT2H, GHH, A1T, C1T, HD, HF, GJT, HI, GJ, P1B, Q1A, C2T, T3 = singles
    au, aT, U2 = abs(u), abs(T), u * u
    OU = 1.0 + U2
    b1, c1, f1 = abs(B1) * au, abs(C1) * au, abs(F1) * au
    S0 = B1 * u + C1 * u * T2 + TAIL + F1 * u * T + GJT2H + GHH    # as line 1170, in doubles
    B_S0 = b1 + c1 * T2 + abs(TAIL) + f1 * aT + abs(GJT2H) + abs(GHH)
    low = abs(S0) - _QUIET_SLACK * B_S0 - 2.0 ** -124 * (1.0 + T2 + aT)   # and 8 underflows
    if not low * OU > 2.0 ** -100:
        return False
    OT, HD = abs(OT), abs(HD)
    B_N = abs(A1T) + abs(C1T) * U2 + HD * au + abs(HF) * OU + abs(GJT) * au + abs(HI)
    B_M1 = OT * B_N * 1.0001 / (low * OU)
    if not max(OU, b1, c1, c1 * T2, f1, f1 * aT, OU * B_S0, OT * B_N, OU * B_M1) < _QUIET_LIMIT:
        return False
    if derivatives < 2:
        return True
    B_P1 = ((3.0 * U2 + 1.0) * abs(DEN) + au * abs(P1B)) * 1.0001                # 1220
    B_Q1 = abs(Q1A) * (abs(C2T) * au + HD + f1 + abs(GJT)) * 1.0001               # 1230
    B_A = abs(A1) + abs(C1) * U2 + abs(GJ) * au                                   # 1240
    B_F = abs(F1) * OU + abs(D1) * au + abs(I1)
    B_R1 = OT * (abs(T3) * B_A + aT * B_F) * 1.0001
    B_M2 = (B_P1 * B_M1 * B_M1 + B_Q1 * B_M1 + B_R1) * 1.0001 / (2.0 * low)       # 1260
    return max(3.0 * U2 + 1.0, B_P1, abs(C2T) * au, B_Q1, OT, abs(T3) * B_A, B_F * aT, B_F,
               B_R1, 2.0 * B_S0, B_M1 * B_M1, B_P1 * B_M1 * B_M1, B_Q1 * B_M1,
               OU * (B_M1 * B_M1 * au + B_M2)) < _QUIET_LIMIT                  # and 1265


def sweep_point_as_listed(co: tuple[Single, ...], PHI: Single, SOL: int, S: Single,
                          derivatives: int = 2) -> DatLines:
    """sweep_point exactly as the listing writes it, every subexpression evaluated where the
    listing evaluates it (the reference sweep_point_fast is held to; used when a point raises
    a soft error)."""
    A1, B1, C1, D1, E1, F1, G1, H1, I1, J1 = co
    T = TAN(.5 * PHI)                                                                    # 1060
    U11 = -(D1*T + (G1+J1)*T**2 + (G1+H1)) / (2*(B1 + C1*(T**2) + F1*T))                # 1070
    if ((D1*T + (G1+J1)*T**2 + (G1+H1))**2) < 4*(B1 + C1*(T**2) + F1*T)*(A1*(T**2) + E1 + F1*T + I1*T):  # 1080
        U11 = U12 = ZERO
        UIM = True
    else:
        UIM = False
        U12 = ((((D1*T + (G1+J1)*T**2 + (G1+H1))**2) - 4*(B1 + C1*(T**2) + F1*T)*(A1*(T**2) + E1 + F1*T + I1*T))**.5) / (2*(B1 + C1*(T**2) + F1*T))  # 1090
    U, angle, ang = _roots_and_angle_line(U11, U12, PHI, SOL, S)                         # 1100-1150
    if derivatives == 0:
        return ang, None, None
    M11, M22 = [ZERO, ZERO], [ZERO, ZERO]
    for k, u in enumerate(U):                                                            # 1160
        M1 = -(1 + T**2)*(A1*T + C1*T*u**2 + .5*D1*u + .5*F1*(u**2 + 1) + (G1+J1)*T*u + .5*I1) / ((1 + u**2)*(B1*u + C1*u*T**2 + .5*D1*T + F1*u*T + .5*(G1+J1)*T**2 + .5*(G1+H1)))  # 1170
        M11[k] = M1                                                                      # 1172
        if S == 1:                                                                       # 1175
            M11[k] = (1 + u**2)*M1/2
        if UIM:                                                                          # 1180
            M11[k] = M1 = ZERO
        if derivatives == 1:
            continue
        P1 = (3*u**2 + 1)*(B1 + C1*T**2 + F1*T) + u*((G1+J1)*T**2 + D1*T + G1 + H1)      # 1220
        Q1 = 2*(1 + T**2)*(2*C1*T*u + .5*D1 + F1*u + (G1+J1)*T)                          # 1230
        R1 = ((1 + T**2)/(1 + u**2))*((3*T**2 + 1)*(A1 + C1*u**2 + (G1+J1)*u) + T*(F1*(u**2 + 1) + D1*u + I1))  # 1240
        S1 = 2*(B1*u + C1*u*T**2 + .5*D1*T + F1*u*T + .5*(G1+J1)*T**2 + .5*(G1+H1))      # 1250
        M2 = -(P1*M1**2 + Q1*M1 + R1)/S1                                                 # 1260
        M22[k] = M2                                                                      # 1262
        if S == 1:                                                                       # 1265
            M22[k] = ((M1**2)*u + M2)*(1 + u**2)/2
        if UIM:                                                                          # 1270
            M2 = M22[k] = ZERO
    return _write_lines(angle, ang, M11[SOL - 1].v, M22[SOL - 1].v, derivatives)        # 1200-1330


# ---- 5. The original program: keys, screen, INPUT, the session -----------------------------------
#
# Holds: the menu program as the original runs it: the screen and its transcript, keys one at a
# time, INPUT's reading of an answer, the session of menus and prompts; the menu program on a
# terminal or driven by keys (menu_program, redirected_program).
#
# Uses: sections 1, 3 and 4.
# Offers: EndOfKeys, Keys, Screen, input_number, INPUT_LINE, input_value, DOUBLE_OVERFLOW,
#   key_value, MENU, BYTES_PER_POINT, run_session, answered_session, session_sweep, check_sweep,
#   menu_program, redirected_program.


class EndOfKeys(Exception):  # ERRATA P4
    """The keystrokes ran out while the program waited for one."""


class Keys:
    """Keystrokes one at a time from a byte stream, as PC-BASIC reads its --input file:
    CR LF is one Enter, NUL and the byte after it are one extended key. On a terminal
    (`pending` tells whether more bytes are already waiting) an ANSI escape sequence, which is
    what the arrow and function keys send, is one extended key too; Esc alone stays Esc."""

    def __init__(self, read_byte: Callable[[], bytes], fold_crlf: bool,
                 pending: Callable[[], bool] | None = None) -> None:
        self._read = read_byte
        self._fold = fold_crlf
        self._ready = pending
        self._pushed_back = b""
        self.line_feeds = 0        # read so far: a hint when the keys run out

    def _byte(self) -> bytes:
        if self._pushed_back:
            byte, self._pushed_back = self._pushed_back, b""
            return byte
        byte = self._read()
        if not byte:
            raise EndOfKeys
        if byte == b"\n":
            self.line_feeds += 1
        return byte

    def get(self) -> str:
        byte = self._byte()
        if byte == b"\0":
            return "\0" + self._byte().decode("latin-1")
        if byte == b"\x1b" and self._ready is not None and self._ready():
            sequence = self._byte()
            while sequence[-1:] in b"[O0123456789;" and self._ready():
                sequence += self._byte()
            return "\0" + sequence.decode("latin-1")
        if byte == b"\r" and self._fold:
            try:
                after = self._byte()
            except EndOfKeys:
                after = b""
            if after != b"\n":
                self._pushed_back = after
        return byte.decode("latin-1")


class Screen:  # ERRATA P6
    """PRINT, CLS, LOCATE and SOUND. On a terminal they draw with ANSI codes; redirected, the
    output is PC-BASIC's own transcript (--output=STDOUT): lines ended by CR LF, no positions."""

    def __init__(self, write: Callable[[str], object], terminal: bool,
                 soft_errors: Callable[[str], object] | None = None) -> None:
        self._write = write
        self._write_soft_error = write if soft_errors is None else soft_errors
        self.terminal = terminal
        self.errors: list[str] = []        # the session's soft errors not shown yet

    def text(self, s: str) -> None:
        self.show_soft_errors()
        self._write(s)

    def line(self, s: str = "") -> None:
        self.text(s + "\r\n")

    def cls(self) -> None:
        if self.terminal:
            self.text("\x1b[2J\x1b[H")

    def locate(self, row: int, column: int) -> None:
        if self.terminal:
            self.text(f"\x1b[{row};{column}H")

    def beep(self) -> None:
        """SOUND 1500,1: the terminal's bell (PC-BASIC run with --sound=False prints nothing)."""
        if self.terminal:
            self._write("\a")

    def show_soft_errors(self) -> None:
        while self.errors:
            self._write_soft_error(self.errors.pop(0) + "\r\n")


def input_number(screen: Screen, keys: Keys, prompt: str) -> Single:
    """INPUT "prompt",X: read a line with GW-BASIC's editing keys and convert it as INPUT does;
    "?Redo from start" and the prompt again when it is not one number."""
    while True:
        screen.text(prompt)
        typed, echo = _read_line(screen, keys, column=len(prompt))
        if not screen.terminal:
            screen.text(echo)
        screen.line()
        with soft_errors(screen.errors):            # "Overflow": the screen's to show
            value = input_value(typed)
        if value is not None:
            return value
        screen.line("?Redo from start")


INPUT_LINE = 255     # characters of an answer kept, as GW-BASIC's line buffer keeps them


def _read_line(screen: Screen, keys: Keys, column: int) -> tuple[str, str]:  # ERRATA P5, P7
    """The line typed up to Enter, and its echo. Backspace deletes, Esc clears, Tab moves to the
    next of GW-BASIC's 8-column stops (the echo shows the gap only once something follows it),
    a line feed only breaks the echo (PC-BASIC's behaviour); other control keys and extended
    keys are ignored. The answer keeps its first INPUT_LINE characters (the echo of a redirected
    session shows them all, as PC-BASIC's transcript does; a terminal takes no more)."""
    pieces: list[str] = []     # typed characters; "\t" + the spaces of a Tab; "\n", a line feed
    length = 0                 # characters typed so far, a Tab's spaces among them
    while True:
        key = keys.get()
        if key == "\r":
            while pieces and pieces[-1].startswith("\t"):
                pieces.pop()
            echo = "".join(p.lstrip("\t") for p in pieces)
            return echo.replace("\n", "")[:INPUT_LINE], echo
        if key == "\b" or (key == "\x7f" and screen.terminal):
            while pieces and pieces[-1] == "\n":
                pieces.pop()
            if pieces:
                length -= 1
                pieces[-1] = pieces[-1][:-1]
                if pieces[-1] in ("", "\t"):
                    pieces.pop()
                if screen.terminal:
                    screen.text("\b \b")
        elif key == "\x1b":
            if screen.terminal:
                screen.text("\b \b" * length)
            pieces, length = [], 0
        elif key == "\n":
            pieces.append("\n")
        elif screen.terminal and length >= INPUT_LINE and (key == "\t" or len(key) == 1):
            screen.beep()                                   # the line is full
        elif key == "\t":
            spaces = " " * (8 - (column + length) % 8)
            pieces.append("\t" + spaces)
            length += len(spaces)
            if screen.terminal:
                screen.text(spaces)
        elif len(key) == 1 and " " <= key != "\x7f":
            pieces.append(key)
            length += 1
            if screen.terminal:
                screen.text(key)


def input_value(typed: str) -> Single | None:
    """What INPUT makes of an answer for one numeric variable, or None for "?Redo from start".
    Spaces are ignored; empty is 0; &H and &O (or &) are 16-bit integers; a decimal number may
    have a sign, points (all but the first ignored), an E or D exponent whose digits may be
    missing, and a ! or # after which anything is ignored (but not after an exponent).
    Overflow prints "Overflow" and gives 1.701412E+38 - twice for a double-precision number
    (eight digits or more, a D exponent or #), which overflows before it is made single."""
    s = typed.replace(" ", "").upper()
    if s.startswith("&"):
        return _input_integer(s[1:])
    # the pattern matches any text: never None
    number, suffix = re.match(r"([^!#]*)(.?)", s).groups()  # type: ignore[union-attr]
    match = re.fullmatch(r"([+-]?)([0-9.]*)(?:([ED])([+-]?)([0-9]*))?", number)
    if match is None or (match[3] and suffix) or "," in s:
        return None
    sign, mantissa, marker, exp_sign, exp_digits = match.groups(default="")
    whole, _, fraction = mantissa.partition(".")
    fraction = fraction.replace(".", "")
    if len(exp_digits) > 8:                 # any exponent this long is far outside the range
        exp_digits = exp_digits.lstrip("0")[:8].rjust(8, "0")
    exponent = f"{marker}{exp_sign}{exp_digits or '0'}" if marker else ""
    negative, n, power, double = decimal_parts(f"{sign}{whole}.{fraction}{exponent}{suffix}")
    if n >= DOUBLE_OVERFLOW:  # ERRATA P7
        # PC-BASIC gathers the digits into one register before it applies the decimal point
        # and the exponent: 39 digits or more can overflow it ("1.5" then 38 zeros; "E-30"
        # after them does not help), and the answer is the largest single, signed.
        if len(number) < INPUT_LINE:
            soft_error(OVERFLOW)
            if double:
                soft_error(OVERFLOW)
            return Single(-MBF_MAX if negative else MBF_MAX)
        soft_error(OVERFLOW)
    if len(number) >= INPUT_LINE:  # ERRATA P7: a number as long as the whole line
        return None
    if n == 0:
        # PC-BASIC reads a zero (or missing) mantissa with an exponent as 2^-129 times its power
        # of ten, whatever the sign: "E5", "-0E5" are 1.469368E-34; "E", "0E-3" are 0.
        if not marker or power <= 0:
            return Single(0.0)
        negative = False
    elif double and _reaches_double_overflow(n, power):
        soft_error(OVERFLOW)
    return Single(scaled_to_single(negative, n, power, double, soft_error))


DOUBLE_OVERFLOW = fractions.Fraction(2**127) * (1 - fractions.Fraction(1, 2**57))


def _reaches_double_overflow(n: int, power: int) -> bool:
    """n * 10**power >= DOUBLE_OVERFLOW (about 1.7E+38), decided from the number of digits where
    that is enough (an exponent of 99999999 is never raised to: GW-BASIC overflows at once)."""
    magnitude = len(str(n)) + power         # 10**(magnitude - 1) <= n * 10**power < 10**magnitude
    if magnitude >= 40:
        return True
    if magnitude <= 38:
        return False
    return fractions.Fraction(n) * fractions.Fraction(10) ** power >= DOUBLE_OVERFLOW


def _input_integer(digits: str) -> Single | None:
    """&Hxxxx, &Oooo or &ooo: a 16-bit two's-complement integer."""
    base = 8
    if digits[:1] == "H":
        base, digits = 16, digits[1:]
    elif digits[:1] == "O":
        digits = digits[1:]
    try:
        n = int(digits, base) if digits else 0
    except ValueError:
        return None
    if n > 0xFFFF:
        return None
    return Single(float(n - 0x10000 if n >= 0x8000 else n))


def key_value(key: str) -> int:
    """VAL of a one-key string: its digit, or 0."""
    return "0123456789".find(key) if len(key) == 1 and key in "0123456789" else 0


MENU = ((6, "1. Plane Four Bar"), (8, "2. Spherical Four Bar"), (10, "3. Skew Four Bar"),
        (12, "4. Plane Slider Crank"), (14, "5. Skew Slider Crank"), (16, "6. Exit"))
BYTES_PER_POINT = 3 * len("-1.234567E+38,-1.234567E+38\r\n")


def run_session(screen: Screen, keys: Keys, directory: str = ".",
                answered: bool = False, derivatives: int = 2) -> int:
    """The whole program, lines 100-1360, driven by `keys`: the menu until a linkage assembles
    (or 6), its sweep, the three files; returns the points written. `answered` (the run command
    and the scenes, see answered_session) turns "Illegal linkage" into a ProgramStop instead of a
    return to the menu; `derivatives` below 2 leaves out ACC.DAT (and VEL.DAT), for a scene that
    does not show them. The session's soft errors go to its screen (Screen.errors)."""
    with soft_errors(screen.errors):
        return _program(screen, keys, directory, answered, derivatives)


def _program(screen: Screen, keys: Keys, directory: str, answered: bool,
             derivatives: int) -> int:
    """run_session's lines 100-1360."""
    v = Variables()
    while True:
        screen.cls()                                                        # 130-190
        for row, item in MENU:
            screen.locate(row, 25)
            screen.line(item)
        screen.locate(23, 25)
        screen.line("Enter Option: _")
        while True:                                                         # 200-240
            key = keys.get()
            if 1 <= key_value(key) <= 5:
                bartype = key_value(key)
                break
            if key == "6":
                return 0                                                    # 1360
            screen.beep()
        screen.cls()                                                        # 260
        if dimensions(v, bartype, lambda prompt: input_number(screen, keys, prompt)):
            break
        if answered:                        # the run command says why (the menu as the original)
            raise ProgramStop("Illegal linkage (impossible to assemble): "
                              + assembly_refusal(v, bartype))
        screen.cls()                                                        # 500
        screen.locate(12, 20)
        screen.line("Illegal linkage (impossible to assemble)")
        screen.locate(23, 25)
        screen.line("Hit any key to continue")
        keys.get()                                                          # 510
    co = coefficients(v, bartype)
    PHI1 = input_number(screen, keys, PROMPTS["from"])                      # 940
    PHI2 = input_number(screen, keys, PROMPTS["to"])                        # 950
    INC = degrees_to_radians(input_number(screen, keys, PROMPTS["step"]))   # 960
    screen.line("Which solution do you need? 1. (A+B)     2. (A-B)")       # 970
    while True:                                                             # 980-990
        SOL = key_value(keys.get())
        if 1 <= SOL <= 2:
            break
        screen.beep()
    return session_sweep(screen, co, degrees_to_radians(PHI1), degrees_to_radians(PHI2), INC,
                         SOL, v.S, directory, derivatives, answered)        # 1000-1350


def answered_session(screen: Screen, key: str, answers: list[str], branch: str,
                     directory: str, derivatives: int = 2) -> int:
    """The program given its menu key, the answers to its prompts in the order it asks them
    (dimensions, first and second bound, increment) and the branch key, as the `run` command
    and the scenes drive it: "Illegal linkage" and a sweep of no point are a ProgramStop (the
    old files kept), a long sweep shows its progress on a terminal. Returns the points written."""
    keystrokes = (key + "".join(a + "\r" for a in answers) + branch).encode("latin-1")
    stream = iter(keystrokes[i:i + 1] for i in range(len(keystrokes)))
    return run_session(screen, Keys(lambda: next(stream, b""), fold_crlf=True), directory,
                       answered=True, derivatives=derivatives)


def session_sweep(screen: Screen, co: tuple[Single, ...], PHI1: Single, PHI2: Single,
                  INC: Single, SOL: int, S: Single, directory: str, derivatives: int = 2,
                  answered: bool = False) -> int:
    """Lines 1020-1350: open the files, sweep PHI, close. Returns the points written."""
    with DatFiles(directory, 1 + derivatives) as files:                     # 1020-1040
        expected = check_sweep(PHI1, PHI2, INC, directory)
        with Progress(expected if answered else 0) as progress:
            point = sweep_points(co, SOL, S, derivatives)
            for PHI in sweep_angles(PHI1, PHI2, INC):                       # 1050, 1340
                files.write(point(PHI))
                screen.show_soft_errors()
                progress()
        if answered and not files.points:
            raise ProgramStop("the sweep has no point: the second bound lies behind the first "
                              "for this increment (the original writes empty files)")
    return files.points                                                     # 1350


def check_sweep(PHI1: Single, PHI2: Single, INC: Single, directory: str) -> float:
    """Refuse the sweeps the original would never finish; the number of points, about."""
    if INC == 0:  # ERRATA P1
        raise ProgramStop("the increment is 0: the original would write points for ever "
                          "(GW-BASIC's FOR never ends with STEP 0)")
    if (INC > 0 and PHI1 > PHI2) or (INC < 0 and PHI1 < PHI2):
        return 0
    far = PHI1 if abs(PHI1.v) > abs(PHI2.v) else PHI2  # ERRATA P2
    if mbf_add(far.v, INC.v) == far.v:
        raise ProgramStop("the increment is too small for single precision: the input angle "
                          "would stop advancing and the original would loop for ever")
    points = (PHI2.v - PHI1.v) / INC.v + 1
    free = shutil.disk_usage(directory).free
    if points * BYTES_PER_POINT > free:
        raise ProgramStop(f"the sweep has about {points:,.0f} points, up to "
                          f"{points * BYTES_PER_POINT:,.0f} bytes of DAT files, and only "
                          f"{free:,} bytes are free in {directory!r}")
    return points


def menu_program(stdin: TextIO | None = None, stdout: TextIO | None = None,
                 directory: str = ".") -> int:
    """`python3 linkage.py`: the original program on this terminal, or driven by the keys on
    standard input (`python3 linkage.py < keys.txt`) with PC-BASIC's screen transcript. A closed
    standard input is no keys; a closed standard output, no transcript."""
    stdin = sys.stdin if stdin is None else stdin
    stdout = sys.stdout if stdout is None else stdout
    if not (is_terminal(stdin) and is_terminal(stdout)):
        return redirected_program(getattr(stdin, "buffer", None),
                                  getattr(stdout, "buffer", None), directory)
    import select
    fd = stdin.fileno()
    screen_out = _Transcript(stdout, encode=False)
    with single_keys(fd, carriage_return=True):    # Enter arrives as CR, as on the PC
        keys = Keys(lambda: os.read(fd, 1), fold_crlf=False,
                    pending=lambda: bool(select.select([fd], [], [], 0.05)[0]))
        status = _run_guarded(Screen(screen_out.write, terminal=True), keys, directory)
    return screen_out.status(status)


def redirected_program(keys_in: BinaryIO | None, screen_out: BinaryIO | None,
                       directory: str = ".") -> int:
    """The menu program reading its keys from the byte stream `keys_in` and writing PC-BASIC's
    screen transcript (CR LF lines) to the byte stream `screen_out` (either may be None: closed).
    The transcript's failures (a closed pipe, a full disk) never cost the DAT files."""
    keys = Keys((lambda: keys_in.read(1)) if keys_in is not None else (lambda: b""),
                fold_crlf=True)
    transcript = _Transcript(screen_out)
    status = _run_guarded(Screen(transcript.write, terminal=False), keys, directory)
    return transcript.status(status)


class _Transcript:
    """The screen's output stream. A failure to write it (a reader that went away, a closed or
    full standard output) is remembered, not raised: the session goes on and writes its files,
    and status() says what happened on standard error and gives the exit status."""

    def __init__(self, out: IO[Any] | None, encode: bool = True) -> None:
        # out: bytes (encode), else text; None: closed, self.error says so and nothing is written
        self.out, self.encode = cast("IO[Any]", out), encode
        self.error: str | None = None
        if out is None:
            self.error = "standard output is closed: no screen transcript"

    def write(self, text: str) -> None:
        if self.error is None:
            try:
                self.out.write(text.encode("utf-8") if self.encode else text)
                if not self.encode:
                    self.out.flush()
            except (OSError, ValueError) as e:
                self._failed(e)

    def _failed(self, e: Exception) -> None:
        self.broken_pipe = isinstance(e, BrokenPipeError)
        self.error = ("the screen transcript's reader stopped reading" if self.broken_pipe
                      else f"cannot write the screen transcript: {getattr(e, 'strerror', e)}")
        with contextlib.suppress(OSError, ValueError, AttributeError):
            # nothing more goes there, not even Python's flush at exit
            os.dup2(os.open(os.devnull, os.O_WRONLY), self.out.fileno())

    def status(self, status: int) -> int:
        if self.error is None:
            try:
                self.out.flush()
            except (OSError, ValueError) as e:
                self._failed(e)
        if self.error is None:
            return status
        say(f"{self.error}; the session went on"
             + ("" if status else " and its DAT files were written"))
        return status or (141 if getattr(self, "broken_pipe", False) else 1)


def _run_guarded(screen: Screen, keys: Keys, directory: str) -> int:
    """Run the session; turn the ways it can stop into a message and an exit status."""
    try:
        run_session(screen, keys, directory)
        screen.show_soft_errors()
        return 0
    except EndOfKeys:
        error, status = "the keystrokes ended before the program did; no DAT file was written", 1
        if keys.line_feeds:
            error += (" (the keys hold line feeds, \\n, but Enter is a carriage return, \\r, "
                      "as on the PC: printf '1\\r2\\r...' types them)")
    except ProgramStop as stop:
        error, status = str(stop), 1
    except KeyboardInterrupt as e:
        error, status = "interrupted; no DAT file was written", interrupted_status(e)
    finally:
        if screen.terminal:
            screen.line()
    say(error)
    return status


# ---- 6. The accurate engine: the closure solved, swept and followed ------------------------------
#
# The five linkages in IEEE double precision, stable where the
# listing is not.
#
# The listing solves one half-tangent quadratic in u = tan(psi/2) (slider-cranks: u = x) for
# t = tan(phi/2); that breaks down at phi = 180 (t infinite), psi = 180 (u infinite), where the
# leading coefficient vanishes, and in the cancellations of its velocity and acceleration
# formulas. The engine solves the same closure written in cos/sin of the angles instead:
#
#   four-bars:      E(phi, psi) = P cos psi + Q sin psi + S = 0
#   slider-cranks:  G(phi, x)   = x^2 - 2 m x + q = 0
#
# where P, Q, S, m, q are each k0 + kc cos phi + ks sin phi with per-linkage constants k
# (computed once, each rounded once from exact rational arithmetic). E and G are positive
# multiples of the listing's displacement polynomial F (eq. (2), lines 1070-1090), so its branch
# choice carries over: the listing's branch 1, U11 + U12 = (-B + sqrt(D)) / 2A, is the root where
# dF/du = +sqrt(D) >= 0, i.e. dE/dpsi > 0 (dG/dx > 0); branch 2 the root where it is negative.
# Velocity and acceleration come from implicit differentiation of E (G) in angle form.
#
# Near a dead-centre the discriminant D = P^2 + Q^2 - S^2 (c^2 - distance^2 for sliders) is a
# small difference of large numbers and double precision loses its digits (the velocity goes as
# 1/sqrt(D)); there, and only there, one point is recomputed in 50-digit decimal arithmetic
# (standard library decimal), so that the results stay correct to double precision until D is
# within 1e-33 of its scale, where the engine says DEAD_CENTRE.
#
# At a change point the two branches cross: D has a double zero in phi, D ~ K delta^2 at delta
# radians from it, and velocity and acceleration are 0/0 limits. There the decimal digits run out
# too (the acceleration's error goes as 10^-digits / delta^3: 4e-6 at 1e-13 degree with 50
# digits), so a point whose D is within 1e-12 of its scale is redone with 110 digits (constants,
# cos and sin included): correct to double precision down to D = 1e-33 of the scale (delta about
# 1e-17 radian). Within that, at the change point itself (or within rounding of it), the engine
# gives the branches' limits: the velocities are the two roots of the second-order expansion of
# the closure, E_phiphi + 2 E_phipsi v + E_psipsi v^2 = 0 (E_phi = E_psi = 0 there), and each
# acceleration follows from the third-order one, E_phiphiphi = -E_phi and E_psipsipsi = -E_psi
# vanishing: psi'' = -v (E_phiphipsi + E_phipsipsi v) / (E_phipsi + E_psipsi v). Status
# CHANGE_POINT; branch k gets the limit of the listing's branch k from above (phi -> phi0+),
# i.e. branch 1 the root with E_phipsi + E_psipsi v = +sqrt(E_phipsi^2 - E_psipsi E_phiphi) > 0,
# the sign dE/dpsi takes on it just past phi0 (sliders: G_x = 2(x - m), v = m' +- sqrt(...)).
#
# Uses: section 2.
# Offers: Motion, Vector, cos_sin_degrees, closure_scale, Closure, FOLLOW.


_PRECISE_BELOW = 2.0 ** -12      # relative discriminant under which a point is done in decimal
_DECIMAL = decimal.Context(prec=50, Emin=-10 ** 6, Emax=10 ** 6)
_DECIMAL_FINE = decimal.Context(prec=110, Emin=-10 ** 6, Emax=10 ** 6)   # near a change point
_DECIMAL_PI = Decimal("3.14159265358979323846264338327950288419716939937510582097494459230781640"
                      "628620899862803482534211706798214808651328230664709384461")
_FINE_BELOW = Decimal("1e-12")           # relative discriminant under which 50 digits give way
#                                          to 110 (a change point loses 3 digits per 2 of D's)
_CHANGE_POINT_SLOPE = Decimal("1e-12")   # |E_phi| over the size at a double root: a change point
_CHANGE_POINT_SPLIT = Decimal("1e-24")   # the velocities' discriminant over the scale: distinct
_DECIMAL_ZERO_BELOW = Decimal("1e-33")   # relative discriminant taken as zero in decimal: above
#                                          it D keeps 17 digits, and so do the results
_DECIMAL_TINY = Decimal("1e-60")


class Motion(NamedTuple):
    """One input angle's output: what the listing writes to ANG, VEL and ACC.DAT, unclipped.

    output is psi in degrees in (-180, 180] for the four-bars (the listing's 2 ATN(u)), the slider
    position x for the slider-cranks; velocity and acceleration are d/dphi and d2/dphi2 of psi
    (radians per radian) or of x (length per radian). A value not asked for, or that does not
    exist (see status), is None: the engine never writes a silent finite number or a NaN.
    """

    phi: float
    output: float | None
    velocity: float | None
    acceleration: float | None
    status: str


Vector = tuple[float, float, float]     # a point or a direction in space, (x, y, z)


# -- cos and sin of degrees, reduced exactly ------------------------------------------------------

# Every path reduces an angle the same way: r = x mod 360, n = round(r / 90), y = r - 90 n
# (|y| <= 45, exact), cos and sin of y, then turned by n quarter turns (exact: products with 0
# and +-1). cos_sin_degrees is the one for a float; _reduced and _turned_quarters serve the exact
# (Fraction) and decimal paths; the scalar sweeps' loops hold one inline copy each (named there),
# the numpy path its array form (_fast_cos_sin).

def _turned_quarters(n: int, c: Any, s: Any) -> tuple[Any, Any]:
    """cos and sin of y + 90 n degrees from c = cos y and s = sin y."""
    return ((c, s), (-s, c), (-c, -s), (s, -c))[n & 3]


def cos_sin_degrees(x: float) -> tuple[float, float]:
    """cos and sin of x degrees (a float), reduced exactly in degrees: exact at multiples of 90."""
    r = math.fmod(x, 360.0)                 # exact
    n = round(r / 90.0)
    y = (r - 90.0 * n) * RAD                # |r - 90 n| <= 45: the subtraction is exact
    return _turned_quarters(n, math.cos(y), math.sin(y))


def _reduced(q: Fraction) -> tuple[int, Fraction]:
    """n and y = r - 90 n of q degrees, r = q mod 360, exactly (|y| <= 45)."""
    r = q % 360
    n = round(r / 90)
    return n, r - 90 * n


def _trig_double(q: Fraction) -> tuple[Fraction, Fraction]:
    """cos and sin of q degrees (a Fraction, reduced exactly) as exact Fractions of the doubles."""
    n, y = _reduced(q)
    y_rad = float(y) * RAD                  # the reduced angle, rounded once
    c, s = _turned_quarters(n, math.cos(y_rad), math.sin(y_rad))
    return Fraction(c), Fraction(s)


def _decimal_cos_sin_deg(q: Fraction, context: decimal.Context = _DECIMAL
                         ) -> tuple[Decimal, Decimal]:
    """cos and sin of q degrees (a Fraction) as Decimals of the context's digits (50, or 110 near
    a change point): exact reduction, Taylor."""
    n, y = _reduced(q)
    with decimal.localcontext(context):
        tiny = _DECIMAL_TINY.scaleb(50 - context.prec)
        x = Decimal(y.numerator) / Decimal(y.denominator) * _DECIMAL_PI / 180
        x2, c, s, tc, ts = x * x, Decimal(1), x, Decimal(1), x
        for k in range(1, 80):               # |x| <= pi/4: the terms fall below 1e-60 by k = 25,
            tc = -tc * x2 / ((2 * k - 1) * (2 * k))              # below 1e-120 by k = 44
            ts = -ts * x2 / ((2 * k) * (2 * k + 1))
            c, s = c + tc, s + ts
            if abs(tc) + abs(ts) < tiny:
                break
        return _turned_quarters(n, c, s)


def _trig_decimal(q: Fraction, context: decimal.Context = _DECIMAL) -> tuple[Fraction, Fraction]:
    """cos and sin of q degrees (a Fraction) as exact Fractions of 50-digit (or 110) values."""
    c, s = _decimal_cos_sin_deg(q, context)
    return Fraction(c), Fraction(s)


# -- the closure's constants ---------------------------------------------------------------------

def _dims_of(kind: str, dims: dict[str, float]) -> dict[str, float]:
    """The dimensions of `kind` from `dims`, as finite floats; a ValueError names what is wrong."""
    if kind not in LINKAGE_DIMENSIONS:
        raise ValueError(f"unknown linkage kind {kind!r}; one of {', '.join(LINKAGE_DIMENSIONS)}")
    names = LINKAGE_DIMENSIONS[kind]
    extra = set(dims) - set(names)
    missing = [n for n in names if n not in dims]
    if extra or missing:
        raise ValueError(f"{kind} linkage takes {', '.join(names)}"
                         + (f"; missing {', '.join(missing)}" if missing else "")
                         + (f"; unknown {', '.join(sorted(extra))}" if extra else ""))
    out = {n: float(dims[n]) for n in names}
    for n, v in out.items():
        if not math.isfinite(v):
            raise ValueError(f"{kind} linkage: {n} = {v} is not finite")
    return out


# The (cos, sin) of q degrees, exact Fractions of the doubles (_trig_double) or of the decimals.
_Trig = Callable[[Fraction], tuple[Fraction, Fraction]]
# The closure's constants (0 an int where it is 0), each term of the closure as (k0, kc, ks) of
# k0 + kc cos phi + ks sin phi: four-bars 9, P = k[0:3], Q = k[3:6], S = k[6:9]; slider-cranks
# 13, m = k[0:3], q = k[3:6], u = k[6:9], v = k[9:12], and the rod c = k[12].
_Constants = tuple[Fraction | int, ...]


def _closure_constants(kind: str, dims: dict[str, float], trig: _Trig) -> _Constants:
    """The closure's constants as exact Fractions, from the typed dimensions and trig(q), the
    (cos, sin) of q degrees. Four-bars: P, Q, S as (k0, kc, ks) of E = P cos psi + Q sin psi + S.
    Slider-cranks: m, q of G = x^2 - 2 m x + q = |B - D|^2 - c^2, the vector (u, v) from the crank
    tip to the slider's line (G = (x - m)^2 - (c^2 - u^2 - v^2)), and the rod c."""
    return _CLOSURES[kind]({k: Fraction(v) for k, v in dims.items()}, trig)


def _plane_closure(n: dict[str, Fraction], trig: _Trig) -> _Constants:
    # E = (|B - D|^2 - c^2) / 2 = lines 880-930 over (1 + t^2)(1 + u^2) / 2
    # (test_physics.plane_four_bar).
    a, b, c, d = n["a"], n["b"], n["c"], n["d"]
    return (d * a, -d * b, 0, 0, 0, -b * d, (a * a + b * b + d * d - c * c) / 2, -a * b, 0)


def _skew_closure(n: dict[str, Fraction], trig: _Trig) -> _Constants:
    # E = (|B - D|^2 - c^2) / 2, lines 650-710 (test_physics.skew_four_bar). Line 430's
    # effective coupler c^2 - f^2 - g^2 + 2fg cos ksi is c^2 - h^2 with h = f tan ksi
    # (g = f / cos ksi): it enters as such, never square-rooted.
    a, b, c, d, f, ksi = n["a"], n["b"], n["c"], n["d"], n["f"], n["ksi"]
    cx, sx = trig(ksi)
    if cx == 0:
        raise ValueError("skew linkage: ksi = 90 degrees (mod 180) makes g = f / cos ksi "
                         "infinite")
    h = f * sx / cx
    return (d * a, -d * b, 0, f * d * sx, 0, -b * d * cx,
            (a * a + b * b + d * d + h * h - c * c) / 2, -a * b, -b * h)


def _spherical_closure(n: dict[str, Fraction], trig: _Trig) -> _Constants:
    # E = cos c - B.D, lines 810-860 over -(1 + t^2)(1 + u^2) / 2
    # (test_physics.spherical_four_bar). The constant of S, cos c - cos a cos b cos d, is
    # (A1 + B1 + C1 + E1) / 2 with A1 = sin p7 sin p8 etc. of exact half-sums p: products of
    # sines keep their relative accuracy for arcs near 0 and 180 degrees, where the cosines
    # would cancel.
    a, b, c, d = n["a"], n["b"], n["c"], n["d"]
    ca, sa = trig(a)
    cb, sb = trig(b)
    cd, sd = trig(d)

    def sin_p(sign_b: int, sign_c: int, sign_d: int) -> Fraction:
        return trig((a + sign_b * b + sign_c * c + sign_d * d) / 2)[1]
    s0 = (sin_p(1, 1, 1) * sin_p(1, -1, 1) + sin_p(-1, 1, -1) * sin_p(-1, -1, -1)
          + sin_p(1, 1, -1) * sin_p(1, -1, -1) + sin_p(-1, 1, 1) * sin_p(-1, -1, 1)) / 2
    return (sd * sa * cb, -sd * ca * sb, 0, 0, 0, -sb * sd, s0, -cd * sa * sb, 0)


def _slider_closure(n: dict[str, Fraction], trig: _Trig) -> _Constants:
    # Lines 740-790 with a = d = 0: the slider on y = e, I1 = -4eb
    # (test_physics.plane_slider_crank); c is the rod c* as typed.
    b, c, e = n["b"], n["c"], n["e"]
    return (0, b, 0, b * b + e * e - c * c, 0, -2 * e * b, e, 0, -b, 0, 0, 0, c)


def _skew_slider_closure(n: dict[str, Fraction], trig: _Trig) -> _Constants:
    # Lines 740-790: the slider's line through (a, 0, f) along (0, sin ksi, -cos ksi)
    # (test_physics.skew_slider_crank); line 430 makes c^2 - f^2.
    a, b, c, f, ksi = n["a"], n["b"], n["c"], n["f"], n["ksi"]
    cx, sx = trig(ksi)
    return (f * cx, 0, b * sx, a * a + b * b + f * f - c * c, -2 * a * b, 0,
            -a, b, 0, -f * sx, 0, b * cx, c)


_CLOSURES = {PLANE_FOUR_BAR: _plane_closure, SKEW_FOUR_BAR: _skew_closure,
             SPHERICAL_FOUR_BAR: _spherical_closure, PLANE_SLIDER_CRANK: _slider_closure,
             SKEW_SLIDER_CRANK: _skew_slider_closure}


def closure_scale(kind: str, k: Sequence[Any]) -> Any:
    """The root of the discriminant's scale, from the closure's constants (_Constants): the
    slider-crank's rod and u, v terms, the four-bar's P, Q, S terms, their magnitudes summed;
    exact (Fractions), in the Decimals' context or in double, as they come."""
    if kind in SLIDER_CRANKS:
        return abs(k[12]) + sum(abs(v) for v in k[6:12])
    return sum(abs(v) for v in k[:9])


def _size_squared(kind: str, k: Sequence[Any]) -> Any:
    """A bound on the discriminant's terms (its scale)."""
    size = closure_scale(kind, k)
    return size * size


class Closure:
    """One linkage's loop closure, its constants computed once, and the output it solves for:
    motion and sweep. Linkage (its own section, below) is this with all that is derived from
    it; the sections between take a Closure.

    Closure(kind, **dims): kind is PLANE_FOUR_BAR ("plane", dims a b c d), SPHERICAL_FOUR_BAR
    ("spherical", a b c d in degrees), SKEW_FOUR_BAR ("skew", a b c d f ksi; ksi in degrees),
    PLANE_SLIDER_CRANK ("slider", b c e; c is the rod c* as typed) or SKEW_SLIDER_CRANK
    ("skew-slider", a b c f ksi). Geometry and signs are the listing's (tests/test_physics.py).
    No assembly check is made here: each position says whether it assembles (Motion.status).
    Lengths are divided by a power of two near the largest (exactly) so that no scale overflows:
    that power is `unit`, the dimensions so divided `scaled` (angles as given; what the sections
    that derive joints and forces from the closure compute with), and `precise_below` the
    discriminant under which a position is solved in 50-digit decimal (decimal_motion; the
    numpy path hands such positions back, with a margin: FAST_MARGIN). `constants` are the
    closure's coefficients in double (_closure_constants of the scaled dimensions: the plane
    four-bar's p0 pc ps q0 qc qs s0 sc ss, each kind's as it lists them), which the numpy path and
    the simulation's scalar evaluations solve with.
    """

    __slots__ = ("kind", "dims", "is_slider", "unit", "scaled", "constants", "precise_below",
                 "_decimal")

    def __init__(self, kind: str, **dims: float) -> None:
        self.dims = _dims_of(kind, dims)
        self.kind = kind
        self.is_slider = kind in SLIDER_CRANKS
        largest = max([abs(v) for k, v in self.dims.items() if k != "ksi"]
                      if kind != SPHERICAL_FOUR_BAR else [0.0])
        self.unit = math.ldexp(1.0, min(math.frexp(largest)[1], 1023)) if largest else 1.0
        self.scaled = {k: v if k == "ksi" or kind == SPHERICAL_FOUR_BAR else v / self.unit
                        for k, v in self.dims.items()}
        exact = _closure_constants(kind, self.scaled, _trig_double)
        self.constants = tuple(float(v) for v in exact)
        self.precise_below = _PRECISE_BELOW * float(_size_squared(kind, exact))
        # the 50-digit (and 110-digit) constants by precision, made at the first use: the
        # closure's constants, the discriminant's zero and the line under which 110 digits serve
        self._decimal: dict[int, tuple[tuple[Decimal, ...], Decimal, Decimal]] | None = None

    def __repr__(self) -> str:
        return "%s(%r, %s)" % (type(self).__name__, self.kind,
                               ", ".join("%s=%r" % kv for kv in self.dims.items()))

    def motion(self, phi: float, branch: int | str = 1, derivatives: int = 2) -> Motion:
        """The output (and its first `derivatives` derivatives) at input angle phi (degrees)."""
        return self.sweep((phi,), branch, derivatives)[0]

    def sweep(self, phis: Iterable[float], branch: int | str = 1, derivatives: int = 2, *,
              start: int | None = None) -> list[Motion]:
        """Motion for each input angle of `phis` (degrees), on the listing's branch 1 (A+B) or 2
        (A-B); derivatives 0 computes the output only, 1 adds the velocity, 2 the acceleration.

        branch=FOLLOW ("follow") follows the physical motion instead: it starts in the listing's
        branch `start` (1 or 2, default 1) at the first angle where the linkage assembles and
        keeps to the same assembly as the crank turns through the angles in their order - through
        phi = 180 and through change points, where it takes the branch that continues psi and
        psi' smoothly, whichever of the listing's labels that is. At a dead centre the crank
        cannot pass (or where the linkage stops assembling, or its output link is free) the
        motion ends: an angle on the dead centre itself is DEAD_CENTRE, with its output, and
        every angle past the end STOPPED. The choice needs
        the derivatives: a followed sweep computes them whatever `derivatives` asks."""
        if derivatives not in (0, 1, 2):
            raise ValueError("derivatives is 0 (output), 1 (and velocity) or 2 (and acceleration)")
        if branch == FOLLOW:
            if start not in (None, 1, 2):
                raise ValueError("start is the branch a followed motion starts in: 1 or 2")
        elif branch not in (1, 2):
            raise ValueError('branch is 1 (the listing\'s A+B), 2 (A-B) or "follow"')
        elif start is not None:
            raise ValueError('start goes with branch="follow"')
        phis = [float(p) for p in phis]
        if not all(math.isfinite(p) for p in phis):
            raise ValueError("input angles must be finite")
        if branch == FOLLOW:
            return _follow(self, phis, start or 1, derivatives)
        sign = 1.0 if branch == 1 else -1.0
        loop = _sweep_slider if self.is_slider else _sweep_four_bar
        return loop(self, phis, sign, derivatives)

    def input_angle(self, output: float, label: int) -> tuple[float, float, float] | None:
        """The closure solved the other way round: the input angle phi (radians) where the
        output is `output` (psi in radians; the slider's x), on label 1 (dE/dphi > 0, dG/dphi)
        or 2, with dphi/doutput and d2phi/doutput2. With the output given, E (G) is
        A cos phi + B sin phi + C, A, B and C each of cos psi, sin psi and 1 (x^2, x and 1),
        solved as the four-bar sweep solves for psi; in double precision, for a coordinate
        away from the output's own dead centres: None where it does not assemble, or at
        dE/dphi = 0."""
        k = self.constants
        if self.is_slider:
            m0, mc, ms, k0, kc, ks = k[:6]
            x = output / self.unit
            a, b, c = kc - 2.0 * mc * x, ks - 2.0 * ms * x, x * x - 2.0 * m0 * x + k0
            a1, b1, c1 = -2.0 * mc, -2.0 * ms, 2.0 * x - 2.0 * m0       # d/dx
            scale = 1.0 / self.unit
        else:
            p0, pc, ps, q0, qc, qs, s0, sc, ss = k
            cq, sq = math.cos(output), math.sin(output)
            a, b, c = pc * cq + qc * sq + sc, ps * cq + qs * sq + ss, p0 * cq + q0 * sq + s0
            a1, b1, c1 = qc * cq - pc * sq, qs * cq - ps * sq, q0 * cq - p0 * sq
            scale = 1.0
        disc = (a * a + b * b) - c * c
        if not disc > 0.0:
            return None
        root, sign, r2 = math.sqrt(disc), 1.0 if label == 1 else -1.0, a * a + b * b
        sp, cp = (-b * c - sign * a * root) / r2, (-a * c + sign * b * root) / r2
        e_phi = sign * root                 # -A sin phi + B cos phi on the root
        e_y = a1 * cp + b1 * sp + c1
        e_phiy = b1 * cp - a1 * sp
        # E_phiphi = -(A cos phi + B sin phi) = C on the root; E_yy = 2 (G), or the constant
        # terms of A, B, C (E less its psi-dependent part, E = 0 on the root)
        e_yy = 2.0 if self.is_slider else sc * cp + ss * sp + s0
        phi1 = -e_y / e_phi
        phi2 = -(e_yy + 2.0 * e_phiy * phi1 + c * phi1 * phi1) / e_phi
        return math.atan2(sp, cp), phi1 * scale, phi2 * scale * scale

    def decimal_motion(self, phi: float, branch: int = 1, finest: bool = False) -> Motion:
        """The Motion at phi on branch 1 or 2 in decimal arithmetic as the engine redoes a point
        near a dead centre (50 digits; 110 near a change point), or in 110 digits throughout
        (finest): what the engine's doubles are measured against (bench accuracy)."""
        if branch not in (1, 2):
            raise ValueError("branch is 1 (the listing's A+B) or 2 (A-B)")
        phi = float(phi)
        if not math.isfinite(phi):
            raise ValueError("input angles must be finite")
        return self._precise(phi, 1.0 if branch == 1 else -1.0, 2,
                             (_DECIMAL_FINE,) if finest else (_DECIMAL, _DECIMAL_FINE))

    def _precise(self, phi: float, sign: float, level: int,
                 contexts: tuple[decimal.Context, ...] = (_DECIMAL, _DECIMAL_FINE)) -> Motion:
        """One point in 50-digit decimal arithmetic (near a dead-centre), as a Motion; in 110
        digits where the discriminant is within 1e-12 of its scale (near a change point)."""
        if self._decimal is None:
            self._decimal = {}
        for context in contexts:
            if context.prec not in self._decimal:
                exact = _closure_constants(self.kind, self.scaled,
                                           functools.partial(_trig_decimal, context=context))
                with decimal.localcontext(context):
                    k = tuple(Decimal(v.numerator) / Decimal(v.denominator) for v in exact)
                    scale = _size_squared(self.kind, k)
                    self._decimal[context.prec] = (k, scale * _DECIMAL_ZERO_BELOW,
                                                   scale * _FINE_BELOW)
            k, zero, fine = self._decimal[context.prec]
            c, s = _decimal_cos_sin_deg(Fraction(phi), context)
            with decimal.localcontext(context):
                more = None if context is _DECIMAL_FINE else fine
                if self.is_slider:
                    m = _slider_point(k, zero, more, phi, c, s, int(sign), level, self.unit)
                else:
                    m = _four_bar_point(k, zero, more, phi, c, s, int(sign), level)
            if m is not None:
                break
        assert m is not None         # in 110 digits (more None) every point is decided
        return m


# -- the double-precision sweeps ------------------------------------------------------------------

def _sweep_four_bar(linkage: Closure, phis: list[float], sign: float, level: int) -> list[Motion]:
    """The four-bar loop: psi on branch `sign` (+1: dE/dpsi > 0) from P cos psi + Q sin psi = -S,
    psi' = -E_phi / E_psi and psi'' = -(E_phiphi + 2 E_phipsi psi' + E_psipsi psi'^2) / E_psi,
    with E_psi = sign sqrt(D), D = P^2 + Q^2 - S^2, and E_psipsi = S on the root."""
    p0, pc, ps, q0, qc, qs, s0, sc, ss = linkage.constants
    precise_below = linkage.precise_below
    hypot, sqrt, atan2 = math.hypot, math.sqrt, math.atan2
    deg, new = DEG, tuple.__new__
    out: list[Motion] = []
    append = out.append
    fmod, cos, sin, rad = math.fmod, math.cos, math.sin, RAD
    for phi in phis:
        # cos_sin_degrees inline, as in _sweep_slider (a helper shared by both loops costs 7-10 %
        # of the sweep: bench engine, side by side)
        r = fmod(phi, 360.0)
        n = round(r / 90.0)
        y = (r - 90.0 * n) * rad
        cy, sy = cos(y), sin(y)
        n &= 3
        if n == 0:
            c, s = cy, sy
        elif n == 1:
            c, s = -sy, cy
        elif n == 2:
            c, s = -cy, -sy
        else:
            c, s = sy, -cy
        xp, xq, xs = pc * c + ps * s, qc * c + qs * s, sc * c + ss * s
        p, q, sv = p0 + xp, q0 + xq, s0 + xs
        rr = hypot(p, q)
        disc = (rr - sv) * (rr + sv)
        if disc <= precise_below:
            if disc < -precise_below:
                append(new(Motion, (phi, None, None, None, NOT_ASSEMBLED)))
            else:
                append(linkage._precise(phi, sign, level))
            continue
        root = sqrt(disc)
        sn = -q * sv - sign * p * root        # (sin psi, cos psi) times P^2 + Q^2
        cn = -p * sv + sign * q * root
        psi = atan2(sn, cn) * deg
        if psi == -180.0:
            psi = 180.0
        if level == 0:
            append(new(Motion, (phi, psi, None, None, ASSEMBLED)))
            continue
        r2 = rr * rr
        cp, sp = cn / r2, sn / r2
        dp, dq, ds = ps * c - pc * s, qs * c - qc * s, ss * c - sc * s
        vel = -sign * (dp * cp + dq * sp + ds) / root
        if level == 1:
            append(new(Motion, (phi, psi, vel, None, ASSEMBLED)))
            continue
        e_ff = -(xp * cp + xq * sp + xs)
        e_fp = dq * cp - dp * sp
        acc = -sign * (e_ff + 2.0 * e_fp * vel + sv * vel * vel) / root
        append(new(Motion, (phi, psi, vel, acc, ASSEMBLED)))
    return out


def _sweep_slider(linkage: Closure, phis: list[float], sign: float, level: int) -> list[Motion]:
    """The slider-crank loop: x = m + sign sqrt(D), D = c^2 - u^2 - v^2, by the stable quadratic
    formula (the root away from zero first, the other as q over it); x' = -G_phi / G_x and x''
    likewise, with G_x = 2 sign sqrt(D)."""
    m0, mc, ms, k0, kc, ks, u0, uc, us, v0, vc, vs, rod = linkage.constants
    precise_below, unit = linkage.precise_below, linkage.unit
    hypot, sqrt = math.hypot, math.sqrt
    new = tuple.__new__
    out: list[Motion] = []
    append = out.append
    fmod, cos, sin, rad = math.fmod, math.cos, math.sin, RAD
    for phi in phis:
        # cos_sin_degrees inline, as in _sweep_four_bar (a helper shared by both loops costs 7-10 %
        # of the sweep: bench engine, side by side)
        r = fmod(phi, 360.0)
        n = round(r / 90.0)
        y = (r - 90.0 * n) * rad
        cy, sy = cos(y), sin(y)
        n &= 3
        if n == 0:
            c, s = cy, sy
        elif n == 1:
            c, s = -sy, cy
        elif n == 2:
            c, s = -cy, -sy
        else:
            c, s = sy, -cy
        xm, xk = mc * c + ms * s, kc * c + ks * s
        m, q = m0 + xm, k0 + xk
        dist = hypot(u0 + uc * c + us * s, v0 + vc * c + vs * s)
        disc = (rod - dist) * (rod + dist)
        if disc <= precise_below:
            if disc < -precise_below:
                append(new(Motion, (phi, None, None, None, NOT_ASSEMBLED)))
            else:
                append(linkage._precise(phi, sign, level))
            continue
        root = sqrt(disc)
        if m >= 0.0:
            big = m + root
            x = big if sign > 0.0 else q / big
        else:
            big = m - root
            x = big if sign < 0.0 else q / big
        if level == 0:
            append(new(Motion, (phi, x * unit, None, None, ASSEMBLED)))
            continue
        dm, dk = ms * c - mc * s, ks * c - kc * s
        vel = sign * (dm * x - 0.5 * dk) / root
        if level == 1:
            append(new(Motion, (phi, x * unit, vel * unit, None, ASSEMBLED)))
            continue
        acc = sign * (0.5 * xk - xm * x + 2.0 * dm * vel - vel * vel) / root
        append(new(Motion, (phi, x * unit, vel * unit, acc * unit, ASSEMBLED)))
    return out


# -- following the physical motion (branch="follow") -------------------------------------------
#
# The listing's labels 1 and 2 are the sign of dE/dpsi (dG/dx), and that sign changes along the
# physical motion wherever the two roots cross: at a change point (a + b = c + d and the like),
# and where the output link is free for an instant (a = b, c = d: the crank tip passes over the
# output pivot; an angle exactly there is INDETERMINATE and ends the motion).
# A followed sweep computes both labels at each angle and takes the root that continues the
# motion: of the two, the one whose step from the last position agrees with the derivatives at
# both ends (the Hermite-corrected trapezoid rule for psi, the trapezoid rule for psi'; error
# O(h^5) and O(h^3) along the right branch, while the other root's psi' differs by a finite
# amount at a crossing). Where neither agrees clearly - a step too long for the curvature, a
# gap where the linkage does not assemble - the step is halved (to 2^-50 of itself), so that a
# dead centre between two angles is found and ends the motion; and so is a step that changes
# the label, until a change point is one of its ends or the two roots are within 1e-9 of each
# other there (then the velocity decides): seen from afar, two branches that pass close by
# without meeting look like a crossing.

FOLLOW = "follow"
_FOLLOW_DEPTH = 50           # at most 50 halvings of one step
_FOLLOW_SPLITS = 400         # and at most 400 steps split in all between two angles of the
#                              sweep (a bisection toward one change point takes 50; positions
#                              that never agree with their neighbours, e.g. lengths of 1e308
#                              beside lengths of 1, would split all 2^50 halves)
_FOLLOW_AGREE = 1e-3         # a step's misfit over |h| (1 + |v0| + |v1|) below this: smooth
_FOLLOW_CLEAR = 0.1          # and below this fraction of the other root's misfit
_FOLLOW_MEET = 1e-9          # two roots this close (radians, or of the size) meet: a crossing
_FOLLOW_CROSS = 1e-6         # if their distance times their velocity is below this (a dead
#                              centre's roots meet with infinite velocity, keeping it finite)


def _follow(linkage: Closure, phis: list[float], start: int, level: int) -> list[Motion]:
    """Linkage.sweep(phis, FOLLOW, level, start=start): see there and the notes above."""
    both = {b: (_sweep_slider if linkage.is_slider else _sweep_four_bar)(
        linkage, phis, 1.0 if b == 1 else -1.0, 2) for b in (1, 2)}
    length = max([abs(v) for k, v in linkage.dims.items() if k != "ksi"] + [0.0]) \
        if linkage.is_slider else 1.0
    out: list[Motion] = []
    state: _Followed | None = None
    ended = False
    for i, phi in enumerate(phis):
        here = (both[1][i], both[2][i])
        if ended:
            out.append(Motion(phi, None, None, None, STOPPED))
            continue
        if state is None:                   # not started: the first assembled angle starts it
            m = here[start - 1]
            if m.status in (ASSEMBLED, CHANGE_POINT):
                state = _follow_state(linkage, m, start)
            out.append(_with_level(m, level))
            continue
        state, last = _follow_step(linkage, state, phi, here, length, 0, [_FOLLOW_SPLITS])
        if state is None:
            ended = True
            out.append(last if last.status == DEAD_CENTRE and last.phi == phi
                       else Motion(phi, None, None, None, STOPPED))
            continue
        out.append(_with_level(last, level))
    return out


# The followed position: (phi, output in radians or length unwrapped, velocity, acceleration, the
# listing's label, whether it is a change point).
_Followed = tuple[float, float, float, float, int, bool]


def _follow_state(linkage: Closure, m: Motion, label: int) -> _Followed:
    """The followed position of a Motion on branch `label`."""
    output, velocity, acceleration = _known(m)
    y = output if linkage.is_slider else output * RAD
    return (m.phi, y, velocity, acceleration, label, m.status == CHANGE_POINT)


def _known(m: Motion) -> tuple[float, float, float]:
    """Output, velocity and acceleration of a position computed with both derivatives that is
    ASSEMBLED or a CHANGE_POINT (all three given)."""
    assert m.output is not None and m.velocity is not None and m.acceleration is not None
    return m.output, m.velocity, m.acceleration


def _with_level(m: Motion, level: int) -> Motion:
    if level == 2 or m.velocity is None:
        return m
    return Motion(m.phi, m.output, m.velocity if level == 1 else None, None, m.status)


def _follow_step(linkage: Closure, state: _Followed, phi: float,
                 here: tuple[Motion, Motion] | None, length: float, depth: int, splits: list[int]
                 ) -> tuple[_Followed | None, Motion]:
    """From the followed position `state` to angle phi, whose two roots are `here` (Motions of
    labels 1, 2, or None to compute them). Returns (state, Motion) of the root that continues the
    motion, or (None, Motion) where it ends (that Motion: the dead centre or the position that
    does not assemble, maybe between the angles). A step that changes the label is halved until
    a change point is one of its ends or the roots meet (to 1e-9): the labels swap only where
    the branches meet, and a near miss (the branches passing close without meeting, or a gap
    between them) looks like a crossing from afar. `splits` ([n]) counts down the halvings
    this step may still make; at 0 a step is taken as at the deepest halving."""
    if here is None:
        here = (linkage.motion(phi, 1), linkage.motion(phi, 2))
    status = here[0].status
    if status not in (ASSEMBLED, CHANGE_POINT):
        return None, here[0]
    phi0, y0, v0, a0, label0, crossing0 = state
    h = (phi - phi0) * RAD
    misfits = []
    for label, m in enumerate(here, 1):
        y1, v1, a1 = _known(m)
        if linkage.is_slider:
            step = y1 - y0
        else:
            step = math.remainder(y1 * RAD - y0, 2.0 * math.pi)
        misfit = (abs(step - 0.5 * h * (v0 + v1) + h * h * (a1 - a0) / 12.0)
                  + abs(h) * abs(v1 - v0 - 0.5 * h * (a0 + a1)))
        misfits.append((misfit, label, step, v1, a1, m))
    misfits.sort(key=lambda t: t[0])
    (best, label, step, v1, a1, m), (other, _, other_step, other_v, _, _) = misfits
    may_switch = crossing0 or status == CHANGE_POINT
    smooth = (best <= _FOLLOW_AGREE * abs(h) * (length + abs(v0) + abs(v1))
              and best <= _FOLLOW_CLEAR * other and (label == label0 or may_switch))
    apart = abs(step - other_step)
    if (not smooth and apart <= _FOLLOW_MEET * length
            and apart * max(abs(v1), abs(other_v)) <= _FOLLOW_CROSS * length * length):
        # the branches cross here, with finite velocities: the outputs cannot tell them apart,
        # the velocities can (at a dead centre, where the roots meet too, apart * velocity
        # stays finite as they meet)
        _, label, step, v1, a1, m = min(misfits, key=lambda t: abs(
            t[3] - v0 - 0.5 * h * (a0 + t[4])))
        smooth = True
    deepest = depth >= _FOLLOW_DEPTH or splits[0] <= 0
    if not smooth and deepest and label != label0 and not may_switch:
        _, label, step, v1, a1, m = next(t for t in misfits if t[1] == label0)
    if smooth or deepest or h == 0.0:
        return (phi, y0 + step, v1, a1, label, status == CHANGE_POINT), m
    splits[0] -= 1
    middle = phi0 + 0.5 * (phi - phi0)
    halfway, last = _follow_step(linkage, state, middle, None, length, depth + 1, splits)
    if halfway is None:
        return None, last
    return _follow_step(linkage, halfway, phi, here, length, depth + 1, splits)


# -- the same formulas, one point at a time in 50-digit decimal (near dead-centres) -------------

def _four_bar_point(k: tuple[Decimal, ...], zero: Decimal, fine: Decimal | None, phi: float,
                    c: Decimal, s: Decimal, sign: int, level: int) -> Motion | None:
    """_sweep_four_bar's formulas for one point in Decimal; decides DEAD_CENTRE, CHANGE_POINT and
    INDETERMINATE. None where the discriminant is under `fine` (more digits are needed)."""
    p0, pc, ps, q0, qc, qs, s0, sc, ss = k
    xp, xq, xs = pc * c + ps * s, qc * c + qs * s, sc * c + ss * s
    p, q, sv = p0 + xp, q0 + xq, s0 + xs
    r2 = p * p + q * q
    disc = r2 - sv * sv
    if disc < -zero:
        return Motion(phi, None, None, None, NOT_ASSEMBLED)
    if r2 <= zero:
        return Motion(phi, None, None, None, INDETERMINATE)
    if fine is not None and disc <= fine:
        return None
    dead = disc <= zero
    root = Decimal(0) if dead else disc.sqrt()
    sn = -q * sv - sign * p * root
    cn = -p * sv + sign * q * root
    psi = math.atan2(float(sn), float(cn)) * DEG
    if psi == -180.0:
        psi = 180.0
    cp, sp = cn / r2, sn / r2
    dp, dq, ds = ps * c - pc * s, qs * c - qc * s, ss * c - sc * s
    e_ff, e_fp = -(xp * cp + xq * sp + xs), dq * cp - dp * sp
    if dead:
        # a double root: a change point where E_phi vanishes too and the branches cross
        e_f = dp * cp + dq * sp + ds
        split = e_fp * e_fp - sv * e_ff
        scale = zero / _DECIMAL_ZERO_BELOW
        if e_f * e_f > _CHANGE_POINT_SLOPE ** 2 * scale or split <= _CHANGE_POINT_SPLIT * scale:
            return Motion(phi, psi, None, None, DEAD_CENTRE)
        if level == 0:
            return Motion(phi, psi, None, None, CHANGE_POINT)
        w = sign * split.sqrt()                  # E_phipsi + S v on this branch
        vel = -e_ff / (e_fp + w) if e_fp * sign >= 0 else (w - e_fp) / sv
        if level == 1:
            return Motion(phi, psi, float(vel), None, CHANGE_POINT)
        e_ffp = xp * sp - xq * cp
        acc = -vel * (e_ffp + ds * vel) / w
        return Motion(phi, psi, float(vel), float(acc), CHANGE_POINT)
    if level == 0:
        return Motion(phi, psi, None, None, ASSEMBLED)
    vel = -sign * (dp * cp + dq * sp + ds) / root
    if level == 1:
        return Motion(phi, psi, float(vel), None, ASSEMBLED)
    acc = -sign * (e_ff + 2 * e_fp * vel + sv * vel * vel) / root
    return Motion(phi, psi, float(vel), float(acc), ASSEMBLED)


def _slider_point(k: tuple[Decimal, ...], zero: Decimal, fine: Decimal | None, phi: float,
                  c: Decimal, s: Decimal, sign: int, level: int, unit: float) -> Motion | None:
    """_sweep_slider's formulas for one point in Decimal; decides DEAD_CENTRE and CHANGE_POINT.
    None where the discriminant is under `fine` (more digits are needed)."""
    m0, mc, ms, k0, kc, ks, u0, uc, us, v0, vc, vs, rod = k
    xm, xk = mc * c + ms * s, kc * c + ks * s
    m, q = m0 + xm, k0 + xk
    u, v = u0 + uc * c + us * s, v0 + vc * c + vs * s
    disc = rod * rod - u * u - v * v
    if disc < -zero:
        return Motion(phi, None, None, None, NOT_ASSEMBLED)
    if fine is not None and disc <= fine:
        return None
    dm, dk = ms * c - mc * s, ks * c - kc * s
    if disc <= zero:
        # a double root x = m: a change point where G_phi vanishes too and the branches cross
        scale = zero / _DECIMAL_ZERO_BELOW
        g_f = dk / 2 - dm * m
        split = dm * dm - xm * m + xk / 2
        if (g_f * g_f > _CHANGE_POINT_SLOPE ** 2 * scale * scale
                or split <= _CHANGE_POINT_SPLIT * scale):
            return Motion(phi, float(m) * unit, None, None, DEAD_CENTRE)
        if level == 0:
            return Motion(phi, float(m) * unit, None, None, CHANGE_POINT)
        w = sign * split.sqrt()                  # v - m' on this branch
        vel = dm + w
        if level == 1:
            return Motion(phi, float(m) * unit, float(vel) * unit, None, CHANGE_POINT)
        acc = -xm * vel / w
        return Motion(phi, float(m) * unit, float(vel) * unit, float(acc) * unit, CHANGE_POINT)
    root = disc.sqrt()
    if m >= 0:
        big = m + root
        x = big if sign > 0 else q / big
    else:
        big = m - root
        x = big if sign < 0 else q / big
    if level == 0:
        return Motion(phi, float(x) * unit, None, None, ASSEMBLED)
    vel = sign * (dm * x - dk / 2) / root
    if level == 1:
        return Motion(phi, float(x) * unit, float(vel) * unit, None, ASSEMBLED)
    acc = sign * (xk / 2 - xm * x + 2 * dm * vel - vel * vel) / root
    return Motion(phi, float(x) * unit, float(vel) * unit, float(acc) * unit, ASSEMBLED)


# ---- 7. What the engine derives: joints, coupler point, transmission angle -----------------------
#
# Holds: what follows from the engine's output angle (or slider position) and its derivatives: where
# every joint is (joint_positions, in the frame the listing's coefficients imply, each kind's
# spelled out in its docstring at the end of this section: the input axis is z, the crank turns
# about it from +x; tests/test_physics.py derives it), the moving pins with their derivatives by
# phi (PINS, joint_kinematics), a point fixed to the coupler (coupler_of) and the transmission
# angle (transmission_of).
#
# The transmission angle mu is the angle between the output pin's velocity and its velocity relative
# to the crank pin A (the review's section 2): for the plane four-bar the angle between coupler and
# output, eq. (1). For the skew kinds it is what the forces decide: their ball-jointed coupler, if
# massless, pushes along its line A->P only, and the output takes the part of that push along its
# pin's path, so mu is the complement of the pressure angle between the line A->P and the pin's
# path P_q: sin mu = |e . P_q| / |P_q| (tests/test_forces_scenes.py holds it to the forces); a skew
# linkage made plane gives eq. (1).
#
# Uses: sections 2 and 6.
# Offers: Real, Vec3, Kinematics, Pins, PINS, COUPLER_REACH, pin_dimensions, weighted_sum,
#   difference, cross, dot, unit_vector, rotated_y, check_coupler_point, joint_kinematics,
#   output_pin_at, coupler_form, transmission_form, CouplerMotion, coupler_of, transmission_of,
#   Pose, joint_positions, pose_at.


# -- the joints, the coupler point and the transmission angle -----------------------------------
#
# Each kind's two moving pins, written once for a float and for a numpy array alike (arithmetic
# only; sqrt and atan2 passed in): the crank pin A(phi) and the output's pin P(q), q the output
# (psi in degrees for the four-bars, the slider's x), each with its first two derivatives by phi
# (radians) and by q (radians, or length), in the frames joint_positions documents. Their total
# derivatives by phi follow from the engine's q' and q'': P' = P_q q', P'' = P_qq q'^2 + P_q q''.
#
# A coupler point is fixed to the coupler, the body from A to P, in the coupler's own frame:
# plane kinds P = A + u e + v n (e the unit vector A->P, n = e turned +90 degrees about z); the
# spherical four-bar P = cos v (cos u A + sin u t) + sin v (A x t) on the unit sphere, t the unit
# tangent at A toward the output pin (u, v in degrees); the skew kinds' coupler has ball joints
# and may spin about A->P, so only the points of that line, A + u e, are fixed. Each form is
# linear in A, P and (spherical) A x P with constant coefficients (|P - A| = c, A.P = cos c along
# the motion), so the derivatives follow by the product rule, exactly.
#
# The transmission angle mu (the review's section 2) is the angle between t_a, the output pin's
# velocity when the output turns (slides) in its positive sense, P_q, and t_r, the pin's velocity
# relative to A when the coupler turns about its joint at A in the positive sense: axis x (P - A),
# the axis z (plane kinds) or OA (the spherical four-bar, whose joint axes meet at the centre).
# In degrees in [0, 180]: the review's eq. (1) for the plane four-bar (the inner angle between
# coupler and output crank), its eq. (3) for the slider-crank (data/SYNTHESIS_ERRATA.md, S9), the
# spherical inner angle at B. The skew kinds' ball joints leave no axis at A: there the size of mu
# is the forces' (90 degrees less the angle between the line A->P and P_q, so sin mu =
# |e . P_q| / |P_q|, e the unit vector A->P) and its side of 90 degrees the sign of P_q . t_r with
# t_r about the input shaft's direction z, so that a skew linkage made plane, f = 0 and ksi = 0,
# is the plane four-bar, mu and all.

# The pins' and the coupler's formulas serve the scalar engine and the numpy path alike: their
# numbers are floats, or numpy arrays of floats (Any: mypy cannot follow one formula over both,
# and "float | numpy.ndarray" would make every scalar caller's float a union).
Real: TypeAlias = Any
Vec3: TypeAlias = "tuple[Real, Real, Real]"
Kinematics: TypeAlias = "tuple[Vec3, Vec3, Vec3]"    # a pin's position, d/d and d2/d2


def _plane_crank_pin(dims: dict[str, float], c: Real, s: Real) -> Kinematics:
    b = dims["b"]
    return (b * c, b * s, 0.0), (-b * s, b * c, 0.0), (-b * c, -b * s, 0.0)


def _spherical_crank_pin(dims: dict[str, float], c: Real, s: Real) -> Kinematics:
    cb, sb = dims["cos b"], dims["sin b"]
    return (sb * c, sb * s, cb), (-sb * s, sb * c, 0.0), (-sb * c, -sb * s, 0.0)


def _plane_output_pin(dims: dict[str, float], cq: Real, sq: Real, x: None) -> Kinematics:
    a, d = dims["a"], dims["d"]
    return (a + d * cq, d * sq, 0.0), (-d * sq, d * cq, 0.0), (-d * cq, -d * sq, 0.0)


def _skew_output_pin(dims: dict[str, float], cq: Real, sq: Real, x: None) -> Kinematics:
    a, d, f = dims["a"], dims["d"], dims["f"]
    cx, sx = dims["cos ksi"], dims["sin ksi"]
    return ((a + d * cq, f * sx / cx + d * sq * cx, d * sq * sx),
            (-d * sq, d * cq * cx, d * cq * sx), (-d * cq, -d * sq * cx, -d * sq * sx))


def _spherical_output_pin(dims: dict[str, float], cq: Real, sq: Real, x: None) -> Kinematics:
    ca, sa, cd, sd = dims["cos a"], dims["sin a"], dims["cos d"], dims["sin d"]
    return (rotated_y(ca, sa, (sd * cq, sd * sq, cd)), rotated_y(ca, sa, (-sd * sq, sd * cq, 0.0)),
            rotated_y(ca, sa, (-sd * cq, -sd * sq, 0.0)))


def _slider_output_pin(dims: dict[str, float], cq: None, sq: None, x: Real) -> Kinematics:
    return (x, dims["e"], 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 0.0)


def _skew_slider_output_pin(dims: dict[str, float], cq: None, sq: None, x: Real) -> Kinematics:
    a, f, cx, sx = dims["a"], dims["f"], dims["cos ksi"], dims["sin ksi"]
    return (a, x * sx, f - x * cx), (0.0, sx, -cx), (0.0, 0.0, 0.0)


class Pins(NamedTuple):
    """One kind's moving pins and coupler: crank_pin(dims, cos phi, sin phi) and
    output_pin(dims, cos q, sin q, x), each (position, d/d, d2/d2) as 3-tuples (dims: see
    pin_dimensions); coupler the form
    of its coupler's frame ("plane", "sphere" or "line"); joint_at_a the axis the coupler turns
    about relative to the crank ("z", or "OA" through the sphere's centre)."""
    crank_pin: Callable[[dict[str, float], Real, Real], Kinematics]
    output_pin: Callable[[dict[str, float], Any, Any, Any], Kinematics]   # see output_pin_at
    coupler: str
    joint_at_a: str
    output_joint: str           # the output pin's name in joint_positions: B, or the slider C


PINS = {
    PLANE_FOUR_BAR: Pins(_plane_crank_pin, _plane_output_pin, "plane", "z", "B"),
    SPHERICAL_FOUR_BAR: Pins(_spherical_crank_pin, _spherical_output_pin, "sphere", "OA", "B"),
    SKEW_FOUR_BAR: Pins(_plane_crank_pin, _skew_output_pin, "line", "z", "B"),
    PLANE_SLIDER_CRANK: Pins(_plane_crank_pin, _slider_output_pin, "plane", "z", "C"),
    SKEW_SLIDER_CRANK: Pins(_plane_crank_pin, _skew_slider_output_pin, "line", "z", "C"),
}
COUPLER_REACH = 1e9      # a coupler point at most this many times the linkage's size from A


def pin_dimensions(dims: dict[str, float]) -> dict[str, float]:
    """dims with the cosines and sines of its angles ("cos a", "sin ksi", ...), computed once for
    the pins of PINS."""
    out = dict(dims)
    for name in ("a", "b", "d", "ksi"):
        if name in dims:
            out[f"cos {name}"], out[f"sin {name}"] = cos_sin_degrees(dims[name])
    return out


def weighted_sum(*terms: tuple[Real, Vec3]) -> Vec3:
    """The sum of (coefficient, 3-vector) terms, componentwise: the one such sum of the
    program's 3-vectors (floats, mpmath's or numpy's numbers alike)."""
    x = y = z = 0.0
    for k, v in terms:
        x, y, z = x + k * v[0], y + k * v[1], z + k * v[2]
    return x, y, z


def difference(p: Vec3, q: Vec3) -> Vec3:
    """p - q, componentwise."""
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


def cross(u: Vec3, v: Vec3) -> Vec3:
    """The cross product of two 3-vectors (floats or numpy arrays alike)."""
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def dot(u: Vec3, v: Vec3) -> Real:
    """The dot product of two 3-vectors."""
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def unit_vector(v: Vector) -> Vector:
    """v divided by its length."""
    return weighted_sum((1.0 / math.sqrt(dot(v, v)), v))


def rotated_y(c: float, s: float, v: Vec3) -> Vec3:
    """v rotated about the y axis by the angle of cosine c, sine s (z turns toward +x)."""
    return (c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2])


def _quarter_turned(w: Vec3) -> Vec3:
    """w turned +90 degrees about z (its z component dropped): n of the plane coupler frame."""
    return (-w[1], w[0], 0.0)


def check_coupler_point(linkage: Closure, u: float, v: float = 0.0) -> tuple[float, float]:
    """(u, v) as floats if they name a point of `linkage`'s coupler (see Linkage.coupler), or a
    ValueError that says why not."""
    try:
        u, v = float(u), float(v)
    except (TypeError, ValueError):
        raise ValueError("a coupler point is two numbers, u and v") from None
    if not (math.isfinite(u) and math.isfinite(v)):
        raise ValueError(f"coupler point ({u:g}, {v:g}): u and v must be finite")
    pins, dims = PINS[linkage.kind], linkage.dims
    if pins.coupler == "line" and v != 0.0:
        raise ValueError(f"coupler point v = {v:g}: the {KIND_NAMES[linkage.kind]}'s coupler "
                         "has ball joints and may spin about the line from A to its output pin, "
                         "so only the points of that line are fixed to it: v must be 0")
    if pins.coupler == "sphere":
        if cos_sin_degrees(dims["c"])[1] == 0.0:
            raise ValueError(f"coupler arc c = {dims['c']:g} degrees: the coupler's great circle "
                             "is not defined (c is 0 or 180 modulo 360)")
        reach = 360.0
    else:
        if dims["c"] == 0.0:
            raise ValueError("coupler c = 0: the coupler has no direction to fix a point to")
        reach = max(abs(x) for k, x in dims.items() if k != "ksi")
    if max(abs(u), abs(v)) > COUPLER_REACH * reach:
        raise ValueError(f"coupler point ({u:g}, {v:g}) is more than {COUPLER_REACH:g} times "
                         f"the linkage's size ({reach:g}) from A")
    return u, v


def joint_kinematics(linkage: Closure, dims: dict[str, float], c: Real, s: Real, out: Real,
                      level: int, q1: Real | None, q2: Real | None,
                      cos_sin: Callable[[Any], tuple[Any, Any]]
                      ) -> tuple[tuple[Vec3, ...], tuple[Vec3, ...], Vec3]:
    """A, P (positions and total derivatives by phi, as many as `level` asks) and P_q, in the
    linkage's scaled lengths (divided by its unit, as the engine computes), from cos and sin of
    phi, the output (degrees, or length) and its derivatives q1, q2; dims is
    pin_dimensions(linkage.scaled); cos_sin is cos_sin_degrees or its array form."""
    a = PINS[linkage.kind].crank_pin(dims, c, s)
    if linkage.is_slider:
        unit = linkage.unit
        out = out / unit
        q1, q2 = (None if q is None else q / unit for q in (q1, q2))
    p = output_pin_at(linkage, dims, out, cos_sin)
    if level == 0:
        return a[:1], p[:1], p[1]
    assert q1 is not None                   # the derivatives `level` asks for are given
    p1 = weighted_sum((q1, p[1]))
    if level == 1:
        return a[:2], (p[0], p1), p[1]
    p2 = weighted_sum((q1 * q1, p[2]), (q2, p[1]))
    return a, (p[0], p1, p2), p[1]


def output_pin_at(linkage: Closure, dims: dict[str, float], out: Real,
                  cos_sin: Callable[[Any], tuple[Any, Any]]) -> Kinematics:
    """The output pin at output `out`: the output angle (degrees; cos_sin gives its cosine and
    sine), or the slider's position (in the lengths of `dims`)."""
    pins = PINS[linkage.kind]
    if linkage.is_slider:
        return pins.output_pin(dims, None, None, out)
    cq, sq = cos_sin(out)
    return pins.output_pin(dims, cq, sq, None)


def coupler_form(linkage: Closure, a: Sequence[Vec3], p: Sequence[Vec3], u: float, v: float,
                  sqrt: Callable[[Any], Any]) -> list[Vec3]:
    """The coupler point and its derivatives (as many as a and p carry) from the pins' (scaled
    lengths: see joint_kinematics), in the linkage's lengths."""
    form = PINS[linkage.kind].coupler
    if form == "sphere":
        cu, su = cos_sin_degrees(u)
        cv, sv = cos_sin_degrees(v)
        k = dot(a[0], p[0])                               # cos c
        n = cross(a[0], p[0])
        sn = sqrt(dot(n, n))                              # sin c
        alpha, beta, gamma = cv * cu - cv * su * k / sn, cv * su / sn, sv / sn
        normal = [n]
        if len(a) > 1:
            normal.append(weighted_sum((1.0, cross(a[1], p[0])), (1.0, cross(a[0], p[1]))))
        if len(a) > 2:
            normal.append(weighted_sum((1.0, cross(a[2], p[0])), (2.0, cross(a[1], p[1])),
                               (1.0, cross(a[0], p[2]))))
        return [weighted_sum((alpha, ai), (beta, pi), (gamma, ni)) for ai, pi, ni in zip(a, p, normal)]
    unit = linkage.unit
    w = difference(p[0], a[0])
    length = sqrt(dot(w, w))                              # c, to rounding
    out = []
    for ai, pi in zip(a, p):
        e = difference(pi, ai)
        terms = [(unit, ai), (u / length, e)]
        if form == "plane" and v:
            terms.append((v / length, _quarter_turned(e)))
        out.append(weighted_sum(*terms))
    return out


def transmission_form(kind: str, a: Vec3, p: Vec3, p_q: Vec3, atan2: Callable[[Any, Any], Any]
                       ) -> Real:
    """mu in degrees from the pins' positions and the output pin's P_q (see the notes above)."""
    t_r = cross(a if PINS[kind].joint_at_a == "OA" else (0.0, 0.0, 1.0), difference(p, a))
    if PINS[kind].coupler == "line":        # the skew kinds: the size from the coupler's line
        line = difference(p, a)
        across = cross(p_q, line)
        sense = (dot(p_q, t_r) >= 0.0) * 2 - 1
        return atan2(abs(dot(p_q, line)), sense * dot(across, across) ** 0.5) * DEG
    normal = cross(p_q, t_r)
    return atan2(dot(normal, normal) ** 0.5, dot(p_q, t_r)) * DEG


class CouplerMotion(NamedTuple):
    """One input angle's coupler point: position, velocity and acceleration as (x, y, z) in the
    frame of joint_positions, the derivatives by the input angle in radians (as Motion's); None
    where not asked for or where there is no position (status, as the Motion's)."""
    phi: float
    position: Vector | None
    velocity: Vector | None
    acceleration: Vector | None
    status: str


def coupler_of(linkage: Closure, motions: Iterable[Motion], u: float, v: float = 0.0
               ) -> list[CouplerMotion]:
    """The coupler point (u, v) (see Linkage.coupler) at each of `motions` (Linkage.sweep's): as
    many derivatives as each Motion carries."""
    u, v = check_coupler_point(linkage, u, v)
    out, dims = [], pin_dimensions(linkage.scaled)
    for m in motions:
        if m.output is None:
            out.append(CouplerMotion(m.phi, None, None, None, m.status))
            continue
        level = 0 if m.velocity is None else 1 if m.acceleration is None else 2
        c, s = cos_sin_degrees(m.phi)
        a, p, _ = joint_kinematics(linkage, dims, c, s, m.output, level, m.velocity,
                                    m.acceleration, cos_sin_degrees)
        point: list[Vector | None] = [*coupler_form(linkage, a, p, u, v, math.sqrt), None, None]
        out.append(CouplerMotion(m.phi, point[0], point[1], point[2], m.status))
    return out


def transmission_of(linkage: Closure, motions: Iterable[Motion]) -> list[float | None]:
    """The transmission angle mu (degrees, [0, 180]) at each of `motions`, None where there is no
    position."""
    out: list[float | None] = []
    dims = pin_dimensions(linkage.scaled)
    for m in motions:
        if m.output is None:
            out.append(None)
            continue
        c, s = cos_sin_degrees(m.phi)
        a, p, p_q = joint_kinematics(linkage, dims, c, s, m.output, 0, None, None,
                                      cos_sin_degrees)
        out.append(transmission_form(linkage.kind, a[0], p[0], p_q, math.atan2))
    return out




class Pose(NamedTuple):
    """Where every joint of a linkage is at one input angle (see joint_positions).

    joints: name -> (x, y, z). Always the ground joints and the crank pin A; the output side (B,
    or the slider C) only where the linkage assembles (status ASSEMBLED, DEAD_CENTRE or
    CHANGE_POINT).
    axes: name -> (point, unit direction): "input" and "output" (the four-bars' shafts),
    "guide" (the slider's line).
    """

    phi: float
    status: str
    output: float | None
    joints: dict[str, Vector]
    axes: dict[str, tuple[Vector, Vector]]


def joint_positions(linkage: Closure, phi: float, branch: int | str = 1) -> Pose:
    """The 3-D position of every joint of `linkage` at input angle phi (degrees) on `branch`.

    plane:        A0 = (0, 0, 0) the input pivot, A the crank pin, B the output crank pin,
                  B0 = (a, 0, 0) the output pivot.
    spherical:    on the unit sphere about O = (0, 0, 0): A0 = (0, 0, 1) where the input axis
                  meets it, B0 = (sin a, 0, cos a) the output axis's, A and B the pins.
    skew:         A0 = (0, 0, 0) on the input axis z; the common perpendicular (length a) runs
                  along x from F0 = (0, 0, f) to F1 = (a, 0, f) on the output axis, of direction
                  w = (0, -sin ksi, cos ksi); B0 = F1 - g w = (a, f tan ksi, 0), g = f / cos ksi,
                  is the centre of the output crank's circle, in the plane z = 0 as the crank's.
    slider:       A0, A; the slider C = (x, e, 0) on the guide y = e.
    skew-slider:  A0, A, F0 = (0, 0, f); the slider C = F1 + x (0, sin ksi, -cos ksi) on the
                  guide through F1 = (a, 0, f).
    """
    motion = linkage.motion(phi, branch, derivatives=0)
    return pose_at(linkage, motion.phi, motion.output, motion.status)


def pose_at(linkage: Closure, phi: float, output: float | None, status: str = ASSEMBLED
            ) -> Pose:
    """The Pose (as joint_positions') with the crank at phi (degrees) and the output at `output`
    as given (degrees, or the slider's position; None: the crank alone), e.g. a simulation's
    row, whose branch the engine's labels do not name through a change point."""
    dims, kind, pins = pin_dimensions(linkage.dims), linkage.kind, PINS[linkage.kind]
    joints, axes = _GROUND_JOINTS[kind](dims)
    joints["A"] = pins.crank_pin(dims, *cos_sin_degrees(phi))[0]
    if output is not None:
        joints[pins.output_joint] = output_pin_at(linkage, dims, output, cos_sin_degrees)[0]
    return Pose(phi, status, output, joints, axes)


_Z_AXIS = (0.0, 0.0, 1.0)
_ORIGIN = (0.0, 0.0, 0.0)
# A kind's ground: its fixed joints and its axes, as Pose has them.
_Ground = tuple[dict[str, Vector], dict[str, tuple[Vector, Vector]]]


def _plane_ground_joints(dims: dict[str, float]) -> _Ground:
    b0 = (dims["a"], 0.0, 0.0)
    return {"A0": _ORIGIN, "B0": b0}, {"input": (_ORIGIN, _Z_AXIS), "output": (b0, _Z_AXIS)}


def _spherical_ground_joints(dims: dict[str, float]) -> _Ground:
    ca, sa = cos_sin_degrees(dims["a"])
    b0 = (sa, 0.0, ca)
    return ({"O": _ORIGIN, "A0": _Z_AXIS, "B0": b0},
            {"input": (_ORIGIN, _Z_AXIS), "output": (_ORIGIN, b0)})


def _skew_ground_joints(dims: dict[str, float]) -> _Ground:
    a, f = dims["a"], dims["f"]
    cx, sx = cos_sin_degrees(dims["ksi"])
    f1 = (a, 0.0, f)
    return ({"A0": _ORIGIN, "F0": (0.0, 0.0, f), "F1": f1, "B0": (a, f * sx / cx, 0.0)},
            {"input": (_ORIGIN, _Z_AXIS), "output": (f1, (0.0, -sx, cx))})


def _slider_ground_joints(dims: dict[str, float]) -> _Ground:
    return {"A0": _ORIGIN}, {"input": (_ORIGIN, _Z_AXIS),
                             "guide": ((0.0, dims["e"], 0.0), (1.0, 0.0, 0.0))}


def _skew_slider_ground_joints(dims: dict[str, float]) -> _Ground:
    a, f = dims["a"], dims["f"]
    cx, sx = cos_sin_degrees(dims["ksi"])
    f1 = (a, 0.0, f)
    return ({"A0": _ORIGIN, "F0": (0.0, 0.0, f), "F1": f1},
            {"input": (_ORIGIN, _Z_AXIS), "guide": (f1, (0.0, sx, -cx))})


_GROUND_JOINTS = {PLANE_FOUR_BAR: _plane_ground_joints, SPHERICAL_FOUR_BAR: _spherical_ground_joints,
                  SKEW_FOUR_BAR: _skew_ground_joints, PLANE_SLIDER_CRANK: _slider_ground_joints,
                  SKEW_SLIDER_CRANK: _skew_slider_ground_joints}


# ---- 8. The linkage analysed: class, ranges, dead centres, transmission extremes -----------------
#
# Holds: analyse, which says what a linkage does over its whole motion: its class (Grashof's
# for the plane four-bar), where the crank turns (crank_limits, the dead centres and change
# points), each circuit's output range, strokes and time ratios, and the transmission angle's
# extremes and the worst of them; analysis_lines, its `name = value` lines.
#
# Uses: sections 2, 6 and 7.
# Offers: ANALYSIS_SAMPLES, extreme_of, crank_limits, Extreme, EQUAL_STROKES, MU_TIE, Circuit,
#   Analysis, unwrapped, LINKS, DEGENERATE_PROBES, degenerate, analyse, value_text, analysis_lines.


# -- the linkage's class and range of motion (analyse) ------------------------------------------
#
# Where the crank can turn is where the closure's discriminant D(phi) (P^2 + Q^2 - S^2 of the
# four-bars, c^2 - u^2 - v^2 of the sliders: section notes above) is not negative. D is a
# trigonometric polynomial of degree two in phi, so it has at most four zeros and four extremes:
# sampled every half degree, its extremes are found by bisection on D', and its zeros between
# samples (and extremes) of opposite sign by bisection on D, to the last bit of phi. A zero where
# D changes sign is a dead centre, the crank's limit; a minimum of D that touches zero (within
# 1e-12 of its scale, the engine's decimal line) is a change point, where the branches cross.
# The motion is then swept circuit by circuit: where the crank turns fully, the branch asked
# (through a change point with branch "follow"); where it rocks, each interval between two dead
# centres is a circuit of its own, run out on the listing's branch and back on the other (the two
# meet at the dead centres), sampled ever closer to each dead centre (_rocking_samples) and with
# each dead centre on both branches (_at_dead_centre). Along each: the output's extremes (every
# zero of its velocity, _velocity_zeros, refined by bisection; and the dead centres) and whether
# it turns fully, the strokes and time ratios, and the transmission angle's extremes (refined by
# extreme_of, their angles rounded by _worth). The class is Grashof's for the plane
# four-bar (exact in the typed lengths), the offset slider-crank's b + |e| against c, and for the
# other kinds the class the motion shows.

ANALYSIS_SAMPLES = 720              # D and the motion sampled every half degree
_TOUCHING = 1e-12                   # |D| over its scale under which a minimum touches zero


def _golden(f: Callable[[float], float], lo: float, hi: float, maximum: bool
            ) -> tuple[float, float]:
    """The extreme of f on [lo, hi] by golden-section search: (x, f(x))."""
    g = (math.sqrt(5) - 1) / 2
    sign = -1.0 if maximum else 1.0
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = sign * f(x1), sign * f(x2)
    for _ in range(80):
        if f1 < f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - g * (hi - lo)
            f1 = sign * f(x1)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + g * (hi - lo)
            f2 = sign * f(x2)
        if hi - lo < 1e-12:
            break
    x = (lo + hi) / 2
    return x, f(x)


def extreme_of(f: Callable[[float], float], lo: float, hi: float, maximum: bool, h: float = 1e-3
               ) -> tuple[float, float]:
    """The extreme of f on [lo, hi]: golden-section search, then the zero of the central
    difference of f (step h) by bisection, which places a smooth extreme to ~1e-10 rather than
    ~1e-8; that one is kept unless its value is worse beyond rounding (a kink, |.|, is better
    left to the first)."""
    x, fx = _golden(f, lo, hi, maximum)

    def slope(z: float) -> float:
        return f(z + h) - f(z - h)
    left, right = x - 1e-4, x + 1e-4
    if left - h < lo or right + h > hi:                        # f is known on [lo, hi] only
        return x, fx
    sl, sr = slope(left), slope(right)
    if sl * sr < 0:
        for _ in range(60):
            mid = (left + right) / 2
            sm = slope(mid)
            if sm == 0:
                left = right = mid
                break
            if (sm > 0) == (sl > 0):
                left, sl = mid, sm
            else:
                right = mid
        z = (left + right) / 2
        fz = f(z)
        noise = 8.0 * math.ulp(abs(fx))         # the values differ by rounding: keep the slope's
        if (fz >= fx - noise) if maximum else (fz <= fx + noise):
            x, fx = z, fz
    return x, fx


def _bisect(f: Callable[[float], float], lo: float, hi: float, f_lo: float) -> float:
    """The point of [lo, hi] where f changes sign (f(lo) = f_lo, f(hi) of the other sign), to the
    last bit."""
    for _ in range(200):
        mid = lo + (hi - lo) / 2
        if mid in (lo, hi):
            break
        f_mid = f(mid)
        if f_mid == 0:
            return mid
        if (f_mid > 0) == (f_lo > 0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid
    return lo + (hi - lo) / 2


def _discriminant(linkage: Closure
                  ) -> tuple[Callable[[float], float], Callable[[float], float]]:
    """D(phi) and D'(phi) (phi in degrees, D' by radians) over the scale of D, in double: each
    term divided by the scale's root before it is squared (no overflow, no underflow)."""
    root = closure_scale(linkage.kind, linkage.constants) or 1.0
    k = tuple(v / root for v in linkage.constants)

    def terms(phi: float) -> tuple[float, float]:
        c, s = cos_sin_degrees(phi)
        if linkage.is_slider:
            u, v = (k[i] + k[i + 1] * c + k[i + 2] * s for i in (6, 9))
            du, dv = (k[i + 2] * c - k[i + 1] * s for i in (6, 9))
            rod = k[12]
            return rod * rod - u * u - v * v, -2.0 * (u * du + v * dv)
        p, q, sv = (k[i] + k[i + 1] * c + k[i + 2] * s for i in (0, 3, 6))
        dp, dq, ds = (k[i + 2] * c - k[i + 1] * s for i in (0, 3, 6))
        return p * p + q * q - sv * sv, 2.0 * (p * dp + q * dq - sv * ds)

    return (lambda phi: terms(phi)[0]), (lambda phi: terms(phi)[1])


def crank_limits(linkage: Closure) -> tuple[list[float], list[float]]:
    """(dead centres, change points): the input angles in [0, 360) where D changes sign, and
    where a minimum of D touches zero. A minimum within the touching line where the engine (in
    50 or 110 digits) finds no position is a gap too narrow for double: its two dead centres
    are found by bisection on whether the engine assembles. ValueError if the linkage assembles
    at no input angle."""
    d, slope = _discriminant(linkage)
    count = ANALYSIS_SAMPLES
    step = 360.0 / count
    phis = [i * step for i in range(count + 1)]
    slopes = [slope(phi) for phi in phis]
    points = set(phis[:-1])
    minima = []
    for i in range(count):
        before, here, after = slopes[i - 1 if i else count - 1], slopes[i], slopes[i + 1]
        if here == 0:
            x, low = phis[i], before < 0 <= after
        elif here * after < 0:
            x, low = _bisect(slope, phis[i], phis[i + 1], here), here < 0
        else:
            continue
        x %= 360.0
        if 360.0 - x < 1e-9:            # found from both ends of the turn: the same point
            x = 0.0
        points.add(x)
        if low and x not in minima:
            minima.append(x)

    def assembles(phi: float) -> float:
        return -1.0 if linkage.motion(phi, 1, 0).status == NOT_ASSEMBLED else 1.0

    changes: list[float] = []
    gaps: set[float] = set()
    for x in minima:
        if abs(d(x)) > _TOUCHING:
            continue
        # the engine's verdict, at the minimum and a few 1e-12 degree about it (D's rounding
        # places the minimum only so well: a gap there may lie beside it)
        h = 1e-12 * max(1.0, abs(x))
        probes = [(x + j * h) % 360.0 for j in (0, -1, 1, -2, 2, -4, 4)]
        gap = next((p for p in probes if assembles(p) < 0), None)
        if gap is None:
            changes.append(x)
        else:
            points.add(gap)
            gaps.add(gap)
    changes.sort()
    signs = [(x, -1.0 if x in gaps else d(x)) for x in sorted(points)]
    if all(v < -_TOUCHING for _, v in signs):
        raise ValueError(f"the {KIND_NAMES[linkage.kind]} assembles at no input angle")
    strict = [(x, v) for x, v in signs
              if abs(v) > _TOUCHING or x in changes or x in gaps or v == 0]
    dead = []
    for (x0, v0), (x1, v1) in zip(strict, strict[1:] + [(strict[0][0] + 360.0, strict[0][1])]):
        if v0 == 0 and x0 not in changes:
            dead.append(x0)
        elif v0 * v1 < 0 and x0 not in changes and x1 % 360.0 not in changes:
            by_engine = x0 in gaps or x1 % 360.0 in gaps
            f = assembles if by_engine else d
            dead.append(_bisect(f, x0, x1, f(x0)) % 360.0)
    return sorted(set(dead)), changes


class Extreme(NamedTuple):
    """An extreme of a quantity along the motion: the input angle (degrees) and its value."""
    phi: float
    value: float


EQUAL_STROKES = 1e-9                # degrees: strokes this close are equal (time ratio 1)
MU_TIE = 1e-9                       # degrees: mu_min and mu_max whose distances from 90 differ
#                                     by no more are equally far (mu_worst: mu_min); mu's rounding
#                                     reaches 190 ulps of 90 (2.7e-12) where it is small, as acos'


class _Strokes:
    """What Circuit and Analysis derive from their strokes and transmission-angle extremes."""
    __slots__ = ()
    forward_stroke: float | None
    return_stroke: float | None
    mu_min: Extreme
    mu_max: Extreme

    @property
    def time_ratio(self) -> float | None:
        """The time ratio as engineers quote it: the slower stroke's crank turn over the faster's
        (>= 1; slower_stroke says which); None without strokes."""
        forward, back = self.forward_stroke, self.return_stroke
        if forward is None or back is None or min(forward, back) <= 0.0:
            return None                     # a stroke of no crank turn (the long fuzz run's find)
        return max(forward, back) / min(forward, back)

    @property
    def time_ratio_review(self) -> float | None:
        """The review's eq. (5): the crank's turn while the output rises over its turn back."""
        if self.forward_stroke is None or self.return_stroke is None:   # given both or neither
            return None
        return self.forward_stroke / self.return_stroke

    @property
    def slower_stroke(self) -> str | None:
        """Which stroke takes the crank longer: "forward" (the output rising), "return", or
        "neither" (equal within EQUAL_STROKES); None without strokes."""
        forward, back = self.forward_stroke, self.return_stroke
        if forward is None or back is None:
            return None
        if abs(forward - back) <= EQUAL_STROKES:
            return "neither"
        return "forward" if forward > back else "return"

    @property
    def mu_worst(self) -> Extreme:
        """Of the transmission angle's extremes, the one further from 90 degrees (mu_min if
        equally far, to rounding: MU_TIE)."""
        further = abs(self.mu_max.value - 90.0) - abs(self.mu_min.value - 90.0)
        return self.mu_max if further > MU_TIE else self.mu_min


class _CircuitFields(NamedTuple):
    """Circuit's fields."""
    crank_range: tuple[tuple[float, float], ...] | None
    output_min: Extreme | None
    output_max: Extreme | None
    forward_stroke: float | None
    return_stroke: float | None
    mu_min: Extreme
    mu_max: Extreme


class Circuit(_CircuitFields, _Strokes):
    """One circuit of the motion (see analyse): crank_range the crank's interval on it (None when
    the crank turns fully: the circuit is the branch's), output_min/max None when the output
    turns fully, the strokes None where the crank rocks or the output turns fully; mu_min and
    mu_max the transmission angle's extremes over the circuit."""
    __slots__ = ()


class _AnalysisFields(NamedTuple):
    """Analysis's fields."""
    linkage: Closure
    branch: int | str
    linkage_class: str
    criterion: str
    crank_range: tuple[tuple[float, float], ...] | None
    output_min: Extreme | None
    output_max: Extreme | None
    forward_stroke: float | None
    return_stroke: float | None
    mu_min: Extreme
    mu_max: Extreme
    dead_centres: tuple[float, ...]
    change_points: tuple[float, ...]
    circuits: tuple[Circuit, ...] = ()


class Analysis(_AnalysisFields, _Strokes):
    """What `analyse` finds (see the notes above and analyse). Angles in degrees; crank_range
    the intervals (from, to) the crank turns through, None when it turns fully; circuits the
    motion's circuits, each analysed on its own; the output's and the transmission angle's
    extremes and the strokes are circuit 1's (circuits[0]): output_min/max None when the output
    turns fully; time_ratio and the strokes None where the crank rocks or the output turns
    fully."""
    __slots__ = ()



def _assembled_near(linkage: Closure, phi: float, branch: int, inward: int) -> Motion:
    """The Motion at phi on `branch`, or where the crank first assembles with a velocity stepping
    `inward` (+1 or -1) from it by a few ulps (phi, a dead centre found in double, may miss by
    one; on it the engine gives no velocity); failing that the first with an output."""
    first = None
    for k in range(60):
        x = phi + inward * k * k * 1e-13 * max(1.0, abs(phi))
        m = linkage.motion(x, branch)
        if m.output is not None and m.velocity is not None:
            return m
        if m.output is not None and first is None:
            first = m
    return first if first is not None else linkage.motion(phi, branch)


def _at_dead_centre(linkage: Closure, phi: float, branch: int, inward: int) -> Motion:
    """The Motion at the dead centre phi on `branch`, for a run: the velocity and acceleration of
    the nearest position with a velocity (_assembled_near), their signs are what the run needs;
    the angle phi; the output the double root there: the engine's where it gives one at phi
    (DEAD_CENTRE), else the mean of the two branches' outputs at the nearest angle where both
    assemble. Each branch's output is off by the square root of phi's rounding (the output goes
    as the square root of the distance to the dead centre: 1e-6 degree for a miss of one ulp);
    their mean by the rounding itself."""
    m = _assembled_near(linkage, phi, branch, inward)
    if m.output is None:
        return m
    for k in range(60):
        x = phi + inward * k * k * 1e-13 * max(1.0, abs(phi))
        one, other = linkage.motion(x, 1, 0), linkage.motion(x, 2, 0)
        if one.output is None or other.output is None:
            continue
        if one.status == DEAD_CENTRE or other.status == DEAD_CENTRE:
            output = one.output if one.status == DEAD_CENTRE else other.output
        else:
            two = other.output
            if not linkage.is_slider:
                two += 360.0 * round((one.output - two) / 360.0)
            output = (one.output + two) / 2.0
        return m._replace(phi=phi, output=output)
    return m


# A run of the motion: (Motion, the listing's branch or FOLLOW) in order.
_Run = list[tuple[Motion, int | str]]


def _rocking_samples(lo: float, hi: float) -> list[float]:
    """Input angles strictly inside the crank interval (lo, hi) (dead centres), spaced evenly in
    u where phi = lo + (hi - lo)(1 - cos(pi u)) / 2: about half a degree apart mid-way and
    closing in on each dead centre as the square of the distance to it, where the output goes
    as the square root of the crank's distance from it (its velocity as the inverse square
    root): evenly spaced in u, the output is smooth through the dead centre, from one branch to
    the other, and an extreme beside it is not stepped over."""
    width = hi - lo
    count = max(16, math.ceil(width * math.pi / (2.0 * (360.0 / ANALYSIS_SAMPLES))))
    inner = [lo + width * (1.0 - math.cos(math.pi * k / count)) / 2.0 for k in range(1, count)]
    return sorted({x for x in inner if lo < x < hi})


def _circuits(linkage: Closure, branch: int | str, start: int | None, dead: list[float]
              ) -> tuple[tuple[tuple[float, float], ...] | None, list[_Run]]:
    """The motion in order, as runs [(Motion, the listing's branch or FOLLOW)], one a circuit:
    one run over a full turn where the crank turns fully, else one a crank interval, out on the
    branch from its first dead centre to its second and back on the other (_rocking_samples),
    each dead centre on both branches (_at_dead_centre) and the run closed on its first
    position."""
    step = 360.0 / ANALYSIS_SAMPLES
    if not dead:
        phis = [i * step for i in range(ANALYSIS_SAMPLES + 1)]
        return None, [[(m, branch) for m in linkage.sweep(phis, branch, 2, start=start)
                       if m.output is not None]]
    ends = dead + [dead[0] + 360.0]
    intervals: list[tuple[float, float]] = []
    for lo, hi in zip(ends, ends[1:]):
        # assembled between them: at two of three points inside (one may fall on a change point
        # that the engine's digits see as a gap)
        inside = [x for x in (lo + (hi - lo) * t for t in (0.25, 0.5, 0.75)) if lo < x < hi]
        if sum(linkage.motion(x, 1, 0).output is not None for x in inside) >= 2:
            intervals.append((lo, hi))
    runs: list[_Run] = []
    out = 1 if branch == FOLLOW else int(branch)
    back = 3 - out
    for lo, hi in intervals:
        inner = _rocking_samples(lo, hi)
        run: _Run = [(_at_dead_centre(linkage, lo, out, 1), out)]
        run += [(m, out) for m in linkage.sweep(inner, out)]
        run.append((_at_dead_centre(linkage, hi, out, -1), out))
        run.append((_at_dead_centre(linkage, hi, back, -1), back))
        run += [(m, back) for m in reversed(linkage.sweep(inner, back))]
        run.append((_at_dead_centre(linkage, lo, back, 1), back))
        run.append((run[0][0], out))
        runs.append([(m, b) for m, b in run if m.output is not None])
    return tuple((lo % 360.0, hi % 360.0 if hi % 360.0 else 360.0) for lo, hi in intervals), runs


def unwrapped(values: Sequence[float], angular: bool) -> list[float]:
    """Values along a path with 360-degree jumps of angles (angular) removed."""
    out = [values[0]]
    for v in values[1:]:
        out.append(v + 360.0 * round((out[-1] - v) / 360.0) if angular else v)
    return out


def _velocity_zeros(linkage: Closure, m0: Motion, m1: Motion, branch: int
                    ) -> list[float]:
    """The input angles between two positions on one branch where the output's velocity is
    zero: one where the velocity changes sign; where it does not but the acceleration does, the
    velocity's extreme between them (the acceleration's zero) and, if the velocity has changed
    sign there, the two zeros either side of it."""
    v0, v1 = m0.velocity, m1.velocity
    assert v0 is not None and v1 is not None

    def velocity(p: float) -> float:
        return linkage.motion(p, branch, 1).velocity or 0.0
    if v0 * v1 < 0:
        return [_bisect(velocity, m0.phi, m1.phi, v0)]
    a0, a1 = m0.acceleration, m1.acceleration
    if v0 == 0 or a0 is None or a1 is None or a0 * a1 >= 0:
        return []

    def acceleration(p: float) -> float:
        return linkage.motion(p, branch, 2).acceleration or 0.0
    x = _bisect(acceleration, m0.phi, m1.phi, a0)
    vx = velocity(x)
    if vx * v0 > 0:
        return []
    if vx == 0:
        return [x]
    return [_bisect(velocity, m0.phi, x, v0), _bisect(velocity, x, m1.phi, vx)]


def _motion_extremes(linkage: Closure, run: _Run, outputs: list[float]
                     ) -> list[tuple[float, float]]:
    """Where the output's velocity is zero along a run (_velocity_zeros between neighbours on
    one branch, or on a sample), refined on that branch, and the ends of each piece on one
    branch: [(phi, output continuous with the run)]."""
    found: list[tuple[float, float]] = []
    angular = not linkage.is_slider
    for i in range(len(run) - 1):
        (m0, b0), (m1, b1) = run[i], run[i + 1]
        if b0 != b1 or b0 == FOLLOW or m0.velocity is None or m1.velocity is None:
            found.append((m0.phi, outputs[i]))
            continue
        if m0.velocity == 0:                          # an extreme on the sample itself
            found.append((m0.phi, outputs[i]))
        for x in _velocity_zeros(linkage, m0, m1, int(b0)):
            value = linkage.motion(x, b0, 0).output
            if value is not None:
                if angular:
                    value += 360.0 * round((outputs[i] - value) / 360.0)
                found.append((x, value))
    return found


def _worth(f: Callable[[float], float], x: float, fx: float, lo: float, hi: float,
           maximum: bool) -> tuple[float, float]:
    """A smooth extreme (x, f(x)) of f on [lo, hi] with x rounded to what it is worth: f is
    flat there, f(x + t) = f(x) -+ k t^2 / 2, so angles within sqrt(2 noise / k) of x (noise:
    64 ulps of f, the rounding of the transmission angle: at phi = 0 exactly it differs from its
    neighbours' by 20; k from a second difference) give f(x) to within rounding; x is rounded to
    the coarsest decimal that is that close and where f is as good within the noise (180.0, not
    180.0000000004339); the value is the better of the two."""
    h = min(1e-2, (hi - lo) / 4.0)
    if not h > 0 or x - h < lo or x + h > hi:
        return x, fx
    k = abs(f(x + h) - 2.0 * fx + f(x - h)) / (h * h)
    noise = 64.0 * math.ulp(max(abs(fx), 1.0))
    if k == 0:
        return x, fx
    reach = math.sqrt(2.0 * noise / k)
    for digits in range(-2, 16):
        r = round(x, digits)
        if r == x:
            break
        if abs(r - x) > reach or not lo <= r <= hi:
            continue
        fr = f(r)
        if (fr >= fx - noise) if maximum else (fr <= fx + noise):
            return r, (max(fx, fr) if maximum else min(fx, fr))
    return x, fx


def _mu_extremes(linkage: Closure, run: _Run, maximum: bool) -> Extreme:
    """The transmission angle's greatest (least) value along a run: each sampled local extreme
    refined on its branch within its neighbours, its angle rounded to what it is worth."""
    # a run holds positions only: mu is never None on it
    mus = cast("list[float]", transmission_of(linkage, [m for m, _ in run]))
    pick = max if maximum else min
    best = pick(zip(mus, range(len(run))))
    candidates = []
    refined = set()
    for i in range(1, len(run) - 1):
        if not all((mus[i] >= mus[j]) if maximum else (mus[i] <= mus[j]) for j in (i - 1, i + 1)):
            continue
        (m0, b0), (_, b), (m1, b1) = run[i - 1], run[i], run[i + 1]
        if not (b0 == b == b1 != FOLLOW):
            continue
        lo, hi = sorted((m0.phi, m1.phi))

        def mu(phi: float, b: int | str = b) -> float:
            value = transmission_of(linkage, [linkage.motion(phi, b, 0)])[0]
            return value if value is not None else (-1.0 if maximum else 361.0)
        x, value = extreme_of(mu, lo, hi, maximum)
        if (value < mus[i]) if maximum else (value > mus[i]):      # the sample is better
            x, value = run[i][0].phi, mus[i]
        x, value = _worth(mu, x, value, lo, hi, maximum)
        candidates.append(Extreme(x % 360.0, value))
        refined.add(i)
    if best[1] not in refined:                     # at an end of the run or of a branch
        candidates.append(Extreme(run[best[1]][0].phi % 360.0, best[0]))
    return pick(candidates, key=lambda e: e.value)


def _linkage_class(linkage: Closure, crank_turns: bool, output_turns: bool, changes: list[float]
                  ) -> tuple[str, str]:
    """(class, criterion): Grashof's rule for the plane four-bar, b + |e| against c for the plane
    slider-crank, else the motion's class."""
    dims = linkage.dims
    if linkage.kind == PLANE_FOUR_BAR:
        lengths = {n: Fraction(abs(dims[n])) for n in "abcd"}
        ordered = sorted(lengths, key=lengths.__getitem__)
        s, p, q, l = (lengths[n] for n in ordered)
        shortest = ordered[0]
        text = (f"Grashof: s + l = {dims[shortest]:g} + {dims[ordered[3]]:g} "
                f"{'<' if s + l < p + q else '=' if s + l == p + q else '>'} p + q = "
                f"{dims[ordered[1]]:g} + {dims[ordered[2]]:g}; shortest {shortest} "
                f"({DIMENSION_NAMES[shortest]})")
        if s + l == p + q:
            return "change-point", text
        if s + l > p + q:
            return "double-rocker", text + " (non-Grashof: no link turns fully)"
        return {"b": "crank-rocker", "a": "double-crank", "d": "rocker-crank",
                "c": "double-rocker"}[shortest], text
    if linkage.kind == PLANE_SLIDER_CRANK:
        reach, rod = Fraction(abs(dims["b"])) + Fraction(abs(dims["e"])), Fraction(abs(dims["c"]))
        sign = "<" if reach < rod else "=" if reach == rod else ">"
        text = f"b + |e| = {float(reach):g} {sign} c = {dims['c']:g}"
        return {"<": "crank-slider", "=": "change-point", ">": "rocker-slider"}[sign], text
    text = "the motion (no closed-form rule for this kind here)"
    if changes:
        return "change-point", text
    if linkage.is_slider:
        return ("crank-slider" if crank_turns else "rocker-slider"), text
    return {(True, False): "crank-rocker", (True, True): "double-crank",
            (False, True): "rocker-crank", (False, False): "double-rocker"}[
        (crank_turns, output_turns)], text


LINKS = {PLANE_FOUR_BAR: "abcd", SPHERICAL_FOUR_BAR: "abcd", SKEW_FOUR_BAR: "abcd",
         PLANE_SLIDER_CRANK: "bc", SKEW_SLIDER_CRANK: "abc"}     # the dimensions that are links
# Input angles at which degenerate() looks for a dead centre: more than the zeros that the
# discriminant (a trigonometric polynomial of degree 2 or 3 in phi) has in a turn unless it is
# zero at every angle, and none of them a special angle (0, 90, 180 ...).
DEGENERATE_PROBES = tuple(17.3 + 47.9 * i for i in range(8))


def degenerate(linkage: Closure) -> str | None:
    """Why the linkage is degenerate, or None: a link of zero length (the output then stands
    still, or turns rigidly with the crank, or is free), or a dead centre at every input angle
    (the discriminant zero everywhere: the linkage lies folded or stretched along a line at
    every turn of the crank, and a search for its dead centres finds one at every sample: 160 of
    them, in seconds). The first needs no computation, the second a sweep of 8 angles."""
    dims = linkage.dims
    zero = [n for n in LINKS[linkage.kind] if dims[n] == 0]
    if "f" in dims and "a" in zero:             # a skew kind: its fixed link is a and f
        zero.remove("a")
        if dims["f"] == 0:
            zero.insert(0, "a = 0 and f")
    if zero:
        return " and ".join(f"{n} = 0 ({DIMENSION_NAMES[n[0]]} has no length)" for n in zero)
    statuses = {m.status for m in linkage.sweep(DEGENERATE_PROBES, 1, 0)}
    if statuses <= {DEAD_CENTRE, INDETERMINATE}:
        return "it is at a dead centre (or its output link is free) at every input angle"
    return None


def _circuit(linkage: Closure, run: _Run, crank_range: tuple[tuple[float, float], ...] | None,
             ends: list[tuple[float, int]]) -> tuple[Circuit, bool]:
    """(the Circuit of a run, whether the output turns fully on it): its output extremes (the
    least brought into [-180, 180) for the four-bars), strokes where the crank turns fully, and
    the transmission angle's extremes, with 0 or 180 at the dead centres of its crank interval
    (`ends`: each with the way into the interval, +1 or -1)."""
    angular = not linkage.is_slider
    outputs = unwrapped([_output_of(m) for m, _ in run], angular)
    turns = angular and abs(outputs[-1] - outputs[0]) > 180.0
    low = high = None
    forward = back = None
    if not turns:
        extremes = _motion_extremes(linkage, run, outputs) + [(run[-1][0].phi, outputs[-1])]
        lowest = min(extremes, key=lambda e: e[1])
        highest = max(extremes, key=lambda e: e[1])
        shift = 360.0 * math.floor(lowest[1] / 360.0 + 0.5) if angular else 0.0
        low, high = (Extreme(p % 360.0, v - shift) for p, v in (lowest, highest))
        if crank_range is None:
            forward = (high.phi - low.phi) % 360.0
            back = 360.0 - forward
    # at a dead centre the coupler lies along the output crank (D = 0: E_psi = 0), mu is 0 or 180
    locked = [Extreme(phi, 180.0 * round(mu / 180.0)) for (phi, _), mu in zip(
        ends, transmission_of(linkage, [_assembled_near(linkage, phi, 1, inward)
                                        for phi, inward in ends])) if mu is not None]
    mu_min = min([_mu_extremes(linkage, run, False)] + locked, key=lambda e: e.value)
    mu_max = max([_mu_extremes(linkage, run, True)] + locked, key=lambda e: e.value)
    return Circuit(crank_range, low, high, forward, back, mu_min, mu_max), turns


def analyse(linkage: Closure, branch: int | str = 1, start: int | None = None) -> Analysis:
    """The linkage's class and range of motion on `branch` (1, 2 or FOLLOW with `start`): an
    Analysis (see the notes above). ValueError if it assembles at no input angle, or if it is
    degenerate (degenerate(): a zero link, a dead centre at every angle).

    Circuits: where the crank turns fully the motion analysed is the branch's, one circuit (the
    other branch is the linkage's other circuit: analyse it with the other branch); where the
    crank rocks, each crank interval between dead centres is a circuit of its own, run out on
    the branch and back on the other (a linkage cannot pass from one circuit to another without
    being taken apart), and each is analysed on its own: Analysis.circuits, in the order of
    crank_range. The top-level output_min, output_max, strokes, time ratio and mu extremes are
    circuit 1's: for a one-circuit linkage what they always were, for a two-circuit one those of
    the circuit whose crank interval crank_range lists first (never a range spanning both).

    The output's extremes are every zero of its velocity along the circuit (a sign change
    between samples, or a change of the acceleration's sign with the velocity's extreme beyond
    zero, each refined by bisection) and the dead centres; beside a dead centre the samples
    close in on it as the square of the distance (_rocking_samples), and each dead centre is
    taken on both branches, so that an extreme next to one is not stepped over. time_ratio is
    the slower stroke's crank turn over the faster's (>= 1, slower_stroke "forward", "return" or
    "neither"); time_ratio_review is the review's eq. (5), forward over return; mu_worst is the
    transmission angle furthest from 90 degrees. Angles of flat extremes of mu are rounded to
    what they are worth (_worth)."""
    if branch not in (1, 2, FOLLOW):
        raise ValueError('branch is 1, 2 or "follow"')
    reason = degenerate(linkage)
    if reason is not None:
        raise ValueError(f"the {KIND_NAMES[linkage.kind]} is degenerate: {reason}; "
                         "nothing to analyse")
    dead, changes = crank_limits(linkage)
    crank_range, runs = _circuits(linkage, branch, start, dead)
    intervals: list[tuple[tuple[float, float], ...] | None] = (
        [None] if crank_range is None else [(interval,) for interval in crank_range])
    circuits: list[Circuit] = []
    turns = False
    for interval, run in zip(intervals, runs):
        if not run:
            continue
        ends = [] if interval is None else [
            (x, inward) for end, inward in zip(interval[0], (1, -1)) for x in dead
            if abs((x - end + 180.0) % 360.0 - 180.0) <= 1e-9]
        circuit, circuit_turns = _circuit(linkage, run, interval, ends)
        circuits.append(circuit)
        turns |= circuit_turns
    if not circuits:
        raise ValueError(f"the {KIND_NAMES[linkage.kind]} assembles at no input angle on "
                         f"branch {branch}")
    linkage_class, criterion = _linkage_class(linkage, crank_range is None, turns, changes)
    first = circuits[0]
    return Analysis(linkage, branch, linkage_class, criterion, crank_range, first.output_min,
                    first.output_max, first.forward_stroke, first.return_stroke, first.mu_min,
                    first.mu_max, tuple(dead), tuple(changes), tuple(circuits))


def _output_of(m: Motion) -> float:
    """The output of a Motion that has one (a run's)."""
    assert m.output is not None
    return m.output


def value_text(x: float) -> str:
    """A number for `name = value` output: up to 10 significant digits."""
    if isinstance(x, bool):
        return str(x).lower()
    if isinstance(x, int):
        return str(x)
    return f"{x:.10g}"


def _motion_rows(motion: Analysis | Circuit, unit: str) -> list[tuple[str, str]]:
    """The rows of an Analysis' or a Circuit's output range, strokes and transmission angle."""
    a = motion
    rows: list[tuple[str, str]] = []
    if a.output_min is None or a.output_max is None:         # given both or neither
        rows.append(("output_range", "full"))
    else:
        rows += [("output_range", f"{value_text(a.output_min.value)} to "
                                  f"{value_text(a.output_max.value)}"),
                 ("swing", value_text(a.output_max.value - a.output_min.value) + unit),
                 ("output_min_phi", value_text(a.output_min.phi)),
                 ("output_max_phi", value_text(a.output_max.phi))]
    if a.time_ratio is not None:                    # forward and return strokes given
        rows += [("time_ratio", value_text(a.time_ratio)),
                 ("slower_stroke", cast(str, a.slower_stroke)),
                 ("time_ratio_review", value_text(cast(float, a.time_ratio_review))),
                 ("forward_stroke", value_text(cast(float, a.forward_stroke))),
                 ("return_stroke", value_text(cast(float, a.return_stroke)))]
    worst = a.mu_worst
    rows += [("mu_min", value_text(a.mu_min.value)), ("mu_min_phi", value_text(a.mu_min.phi)),
             ("mu_max", value_text(a.mu_max.value)), ("mu_max_phi", value_text(a.mu_max.phi)),
             ("mu_worst", value_text(worst.value)),
             ("mu_worst_deviation", value_text(abs(worst.value - 90.0))),
             ("mu_worst_at", value_text(worst.phi))]
    return rows


def _range_text(crank_range: tuple[tuple[float, float], ...] | None) -> str:
    return "full" if crank_range is None else ", ".join(
        f"{value_text(lo)} to {value_text(hi)}" for lo, hi in crank_range)


def analysis_lines(analysis: Analysis, prefix: str = "") -> list[str]:
    """The `name = value` lines of an Analysis, each name after `prefix`: the linkage, its class,
    crank range and number of circuits, circuit 1's motion (see analyse), the dead centres and
    change points; then, where there are two circuits or more, each circuit's crank range and
    motion as circuit_N.name lines."""
    a, linkage = analysis, analysis.linkage
    unit = "" if linkage.is_slider else " deg"
    rows = [("kind", linkage.kind)]
    rows += [(n, value_text(v)) for n, v in linkage.dims.items()]
    rows += [("branch", str(a.branch)), ("class", a.linkage_class), ("criterion", a.criterion),
             ("crank_range", _range_text(a.crank_range)),
             ("circuits", str(max(1, len(a.circuits))))]
    rows += _motion_rows(a, unit)
    rows += [("dead_centres", ", ".join(map(value_text, a.dead_centres)) or "none"),
             ("change_points", ", ".join(map(value_text, a.change_points)) or "none")]
    if len(a.circuits) > 1:
        for i, circuit in enumerate(a.circuits, 1):
            rows += [(f"circuit_{i}.{name}", value) for name, value in
                     [("crank_range", _range_text(circuit.crank_range))]
                     + _motion_rows(circuit, unit)]
    return [f"{prefix}{name} = {value}" for name, value in rows]


# ---- 9. Forces: what it takes to drive the linkage -----------------------------------------------
#
# Kinetostatics: the motion is the engine's (psi, psi' and psi'' at each input angle phi, the crank
# turning at a given speed and acceleration); forces() finds what holds the bodies to it. Newton's
# and Euler's equations of each moving body (its mass times its centre's acceleration; the rate
# of its angular momentum, I dOmega/dt + Omega x I Omega about its centre) against gravity, the
# loads, the driver's torque and the joints' reactions make one linear system in the reactions
# and the torque, solved at each angle by Gaussian elimination with partial pivoting, its rows
# and columns scaled to a largest entry of 1 first. At the engine's DEAD_CENTRE (the output's
# dead centre, mu = 0 or 180) and CHANGE_POINT, and wherever that system is singular (a pivot under
# 1e-12), the forces are unbounded: status UNBOUNDED and None, never an inf or a NaN (approaching
# a dead centre they are finite and grow as psi' psi''); where masses or a speed too large for
# floating point would make one, status OUT_OF_RANGE ("overflow") and None. Nothing here runs
# unless forces() is called.
#
# Units SI: lengths in metres (the dimensions as given; the spherical four-bar's arcs stay in
# degrees, on a sphere of `radius` metres), kg, N, N m; the speed in rpm, omega = 2 pi rpm / 60;
# the crank's acceleration alpha in rad/s^2. A point X(phi) of the engine's moves with velocity
# X' omega and acceleration X'' omega^2 + X' alpha (' = d/dphi, radians). Gravity (Effects.gravity)
# a number g: g along -y for the plane kinds, along -z (the input axis) for the spatial kinds; or
# a 3-vector as given. The plane kinds are analysed in their plane z = 0 (forces with a z
# component are refused there).
#
# Each body's frame (x, y, z orthonormal and right-handed; a centre and inertia are given in it):
#   crank:    origin the pivot A0 (the sphere's centre O for the spherical four-bar), z the input
#             axis, x toward the pin A (perpendicular to z).
#   coupler:  plane kinds: origin A, x toward the output pin, z = (0, 0, 1), so that its centre
#             (u, v) is Linkage.coupler's point (u, v). Skew kinds: origin A, x toward the output
#             pin; with a ball joint at each end it may spin idly about that line, so its mass must
#             lie on it: a centre (u, 0, 0) and an inertia axisymmetric about x (its spin is taken
#             as zero, Omega = AB x (vB - vA) / |AB|^2, so only the transverse moment acts).
#             Spherical: origin O, x toward A, z along A x B, y = z x x (Linkage.coupler's t).
#   output:   four-bars: origin the output's pivot B0 (O for the spherical four-bar), z its axis
#             (psi turns positively about it: (0, 0, 1), w, or OB0), x toward the pin B. Sliders:
#             origin C, x along the guide in the sense of increasing x, y = (0, 1, 0) (plane) or
#             (1, 0, 0) (skew: along the common perpendicular), z = x cross y.
# The plane kinds take a scalar centre for crank and output (the distance from the pivot toward
# the pin; the slider's from C along the guide), (u, v) for the coupler, and a scalar inertia
# about the centre (the z component; the others do not act in the plane); the spatial kinds a
# 3-vector and a symmetric positive semi-definite 3 x 3 tensor about the centre. A Body of a mass
# only is a uniform slender rod between its joints (spherical: the arc of the sphere between
# them; a slider: a point mass at C).
#
# Each joint's reaction is the force (and moment about the joint) that the body before it exerts
# on the body after it, along frame - crank - coupler - output, at a ground joint the frame's on
# the moving link; the unknowns, by kind:
#   plane, slider:  each pin joint a force in the plane (2 unknowns); the slider's guide a normal
#                   force and a moment about z at C (2); the torque: 9 = 3 bodies x 3 equations.
#   skew:           the revolutes A0 and B0 a force (3) and a moment perpendicular to their axis
#                   (2), at A0 and B0; the balls A and B a force (3); the torque: 17 = 6 + 5 + 6
#                   equations, the coupler's about A->B dropped (all its forces meet that line:
#                   0 = 0).
#   skew-slider:    A0 (5), the balls A and C (3 each), the guide a force perpendicular to it (2)
#                   and a moment (3), at C; the torque: 17 = 6 + 5 + 6.
#   spherical:      every joint's axis passes through O, and so every body turns about O: the
#                   linkage is over-constrained (spatially 6 x 3 = 18 equations for 4 x 5 + 1 = 21
#                   unknowns), and the joints' forces can carry a self-balanced system of 3
#                   parameters that rigid bodies leave undetermined (the links' elasticity and fit
#                   decide it). Determinate are each joint's moment about O (perpendicular to its
#                   axis, 2 each), the torque (8 + 1 = 9 = 3 bodies x Euler's 3 equations about
#                   O), and the frame's resultant: the joints report their moments about O only
#                   (force None).
# The shaking force and moment are what the linkage exerts on its frame: minus the ground joints'
# reactions, and minus the driver's torque (its stator sits on the frame), the moment about A0
# (O for the spherical kind); the loads and gravity act from outside. For the spherical kind the
# shaking force is the whole linkage's Newton: sum of (m g - m a_G) plus the loads' forces.
#
#
# Uses: sections 2, 6, 7 and 8.
# Offers: STANDARD_GRAVITY, UNBOUNDED, OUT_OF_RANGE, Matrix, Body, Bodies, Effects, Driver, Spring,
#   Torsion, Reaction, Forces, BodyMass, spin_about_centre, checked_number, checked_numbers,
#   ForcesSetup, RADIUS_RANGE, forces_setup, body_masses, forces, PEAK_TOLERANCE, TorquePeak,
#   torque_peak, ForcesSummary, forces_summary, forces_lines.


STANDARD_GRAVITY = 9.80665      # m/s^2: Effects(gravity=STANDARD_GRAVITY), the kind's "down"
UNBOUNDED = "unbounded"         # Forces.status where the force system is singular
OUT_OF_RANGE = "overflow"       # Forces.status where a number would pass the floats' range
_SINGULAR_BELOW = 1e-12         # a pivot of the scaled system under this: singular
Matrix = tuple[Vector, Vector, Vector]      # a 3 x 3 matrix, by rows
_X, _Y, _Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
_NOUGHT = (0.0, 0.0, 0.0)


class Body(NamedTuple):
    """One moving body: mass (kg), centre of mass and inertia about it (kg m^2) in the body's
    frame (see the notes above); centre and inertia None: a uniform slender rod."""
    mass: float = 0.0
    centre: float | Sequence[float] | None = None
    inertia: float | Sequence[Sequence[float]] | None = None


class Bodies(NamedTuple):
    """The three moving bodies; output is the slider of the slider-cranks. Massless if left out."""
    crank: Body = Body()
    coupler: Body = Body()
    output: Body = Body()


class Effects(NamedTuple):
    """What drives and loads the linkage: the crank's speed (rpm) and acceleration (rad/s^2);
    gravity (None, a number g along the kind's down, or a 3-vector, m/s^2); a torque applied to
    the output about its axis in the sense of psi (N m, four-bars: a load that resists the
    motion where psi increases is negative); a force applied to the slider along its guide in
    the sense of x (N, slider-cranks, likewise); a force (fx, fy, fz) (N) at the coupler point
    (u, v) of Linkage.coupler, as ((u, v), (fx, fy, fz))."""
    speed_rpm: float = 0.0
    crank_acceleration: float = 0.0
    gravity: float | Sequence[float] | None = None
    output_torque: float = 0.0
    output_force: float = 0.0
    coupler_force: tuple[Sequence[float], Sequence[float]] | None = None


class Driver(NamedTuple):
    """What drives the crank: a torque (N m, in the sense of phi), and a motor line that adds
    stall_torque (1 - omega / omega_free) (N m; free_speed_rpm 0: no motor line)."""
    torque: float = 0.0
    stall_torque: float = 0.0
    free_speed_rpm: float = 0.0


class Spring(NamedTuple):
    """A linear spring between two points, each a joint's name (A0, A, B, B0; C the slider) or a
    point (x, y) of the frame (m): stiffness (N/m), free length (m)."""
    point_a: str | tuple[float, float]
    point_b: str | tuple[float, float]
    stiffness: float
    free_length: float


class Torsion(NamedTuple):
    """A torsional spring and damper at a pivot: A0 on the crank's angle phi, B0 on the output's
    psi: the torque -stiffness (angle - free_angle) - damping angle_rate (N m/rad, degrees,
    N m s/rad)."""
    pivot: str
    stiffness: float = 0.0
    free_angle: float = 0.0
    damping: float = 0.0


class Reaction(NamedTuple):
    """A joint's reaction (see the notes above): its force (N) and its moment (N m) where it
    carries one, None where not (a plane pin's moment, the spherical kind's forces)."""
    force: Vector | None
    moment: Vector | None


class Forces(NamedTuple):
    """One input angle's forces: the driver's torque on the crank about its axis, in the sense
    of phi (N m), its power (W), each joint's Reaction, the shaking force (N) and moment (N m)
    on the frame. None where there is no position (status the Motion's) or the forces are
    unbounded (status UNBOUNDED). speed_rpm: the crank's speed they are at (the power's, and
    forces_summary's flywheel's)."""
    phi: float
    torque: float | None
    power: float | None
    joints: dict[str, Reaction] | None
    shaking_force: Vector | None
    shaking_moment: Vector | None
    status: str
    speed_rpm: float            # the crank's speed they were computed at (Effects.speed_rpm)


class BodyMass(NamedTuple):
    """A body's mass (kg), centre and inertia about it (kg m^2) in its frame, as forces() takes
    them (see body_masses)."""
    mass: float
    centre: Vector              # in the body's frame
    inertia: Matrix             # about the centre, in the body's frame


class _State(NamedTuple):
    """A body at one instant: its frame's origin and axes (x, y, z), the origin's acceleration,
    the angular velocity and acceleration."""
    origin: Vector
    axes: Matrix
    acceleration: Vector
    spin: Vector
    spin_rate: Vector


class _Joint(NamedTuple):
    """A joint's unknowns: the force directions (acting at `at`) and the moment directions; the
    bodies it joins (0 crank, 1 coupler, 2 output, None the frame): before acts on after."""
    name: str
    before: int | None
    after: int
    at: Vector
    forces: tuple[Vector, ...]
    moments: tuple[Vector, ...]


def _in_world(axes: Matrix, v: Sequence[float]) -> Vector:
    """A vector given in a body's frame (axes x, y, z), in the fixed frame."""
    return weighted_sum((v[0], axes[0]), (v[1], axes[1]), (v[2], axes[2]))


def _inertia_times(axes: Matrix, inertia: Matrix, w: Vector) -> Vector:
    """The body-frame inertia, turned into the fixed frame, times w."""
    local = [dot(axis, w) for axis in axes]
    return _in_world(axes, [sum(row[j] * local[j] for j in range(3)) for row in inertia])


def _perpendicular_pair(k: Vector) -> tuple[Vector, Vector]:
    """Two unit vectors perpendicular to the unit vector k and to each other."""
    least = min(range(3), key=lambda i: abs(k[i]))
    p = unit_vector(cross(k, (_X, _Y, _Z)[least]))
    return p, cross(k, p)


def spin_about_centre(a: Vector, b: Vector, va: Vector, vb: Vector) -> Vector:
    """The angular velocity Omega of a body turning about the origin whose points a and b (not
    parallel) move with va = Omega x a, vb = Omega x b (in Omega's basis a, b, a x b)."""
    n = cross(a, b)
    nn = dot(n, n)
    return weighted_sum((dot(vb, n) / nn, a), (-dot(va, n) / nn, b), (dot(va, b) / nn, n))


def checked_number(value: Any, what: str) -> float:
    """value as a finite float, or a ValueError that names `what` and says why not."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a number, not {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{what} must be finite, not {x!r}")
    return x


def checked_numbers(values: Any, count: int, what: str) -> tuple[float, ...]:
    """`count` finite floats from values, or a ValueError that names `what`."""
    try:
        items = list(values)
    except TypeError:
        items = []
    if len(items) != count:
        raise ValueError(f"{what} must be {count} numbers, not {values!r}")
    return tuple(checked_number(v, what) for v in items)


def _rod(mass: float, length: float) -> BodyMass:
    """A uniform slender rod along x from the origin, of `length`."""
    side = mass * length * length / 12.0
    return BodyMass(mass, (length / 2.0, 0.0, 0.0), (_NOUGHT, (0.0, side, 0.0), (0.0, 0.0, side)))


def _arc(mass: float, radius: float, arc: float, start: int, toward: int) -> BodyMass:
    """A uniform slender rod on the circle of `radius` about the origin, from the body axis
    `start` toward the axis `toward` through `arc` radians."""
    p, q = (_X, _Y, _Z)[start], (_X, _Y, _Z)[toward]
    half = math.sin(2.0 * arc) / (4.0 * arc)
    cc, ss, cs = 0.5 + half, 0.5 - half, math.sin(arc) ** 2 / (2.0 * arc)   # <cos^2>, <sin^2>, <cs>
    g = weighted_sum((radius * math.sin(arc) / arc, p), (radius * (1.0 - math.cos(arc)) / arc, q))
    k = mass * radius * radius
    gg = dot(g, g)
    rows = []
    for i in range(3):
        row = []
        for j in range(3):
            mean = cc * p[i] * p[j] + ss * q[i] * q[j] + cs * (p[i] * q[j] + q[i] * p[j])
            about_o = k * ((i == j) - mean)
            row.append(about_o - mass * (gg * (i == j) - g[i] * g[j]))
        rows.append(tuple(row))
    return BodyMass(mass, g, cast(Matrix, tuple(rows)))


def _checked_body(kind: str, role: str, body: Body, rod: Callable[[float], BodyMass]) -> BodyMass:
    """body as a BodyMass in its frame, or a ValueError that says what is wrong with it; rod(mass)
    the uniform rod it is when its centre and inertia are None."""
    name = f"the {role}"
    mass = checked_number(body.mass, f"{name}'s mass")
    if mass < 0.0:
        raise ValueError(f"{name}'s mass must not be negative, not {mass:g}")
    if body.centre is None and body.inertia is None:
        return rod(mass)
    if body.centre is None or body.inertia is None:
        raise ValueError(f"{name}: give both its centre and its inertia, or neither (a rod)")
    plane = kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK)
    if plane:
        if role == "coupler":
            u, v = checked_numbers(body.centre, 2, f"{name}'s centre (u, v)")
            centre = (u, v, 0.0)
        else:
            centre = (checked_number(body.centre, f"{name}'s centre"), 0.0, 0.0)
        inertia = checked_number(body.inertia, f"{name}'s inertia")
        if inertia < 0.0:
            raise ValueError(f"{name}'s inertia must not be negative, not {inertia:g}")
        return BodyMass(mass, centre, ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, inertia)))
    centre = cast(Vector, checked_numbers(body.centre, 3, f"{name}'s centre (x, y, z)"))
    try:
        rows = [checked_numbers(row, 3, f"{name}'s inertia") for row in cast(Any, body.inertia)]
    except TypeError:
        rows = []
    if len(rows) != 3:
        raise ValueError(f"{name}'s inertia must be a 3 x 3 tensor (three rows of three numbers)")
    scale = max(abs(x) for row in rows for x in row) or 1.0
    if any(abs(rows[i][j] - rows[j][i]) > 1e-12 * scale for i in range(3) for j in range(i)):
        raise ValueError(f"{name}'s inertia must be a symmetric tensor")
    minors = [rows[i][i] for i in range(3)] + [
        rows[i][i] * rows[j][j] - rows[i][j] ** 2 for i, j in ((0, 1), (0, 2), (1, 2))] + [
        rows[0][0] * (rows[1][1] * rows[2][2] - rows[1][2] ** 2)
        - rows[0][1] * (rows[0][1] * rows[2][2] - rows[1][2] * rows[0][2])
        + rows[0][2] * (rows[0][1] * rows[1][2] - rows[1][1] * rows[0][2])]
    if any(m < -1e-12 * scale ** (1 + (k > 2) + (k > 5)) for k, m in enumerate(minors)):
        raise ValueError(f"{name}'s inertia must be positive semi-definite (no negative moment "
                         "of inertia about any axis)")
    if role == "coupler" and PINS[kind].coupler == "line":
        if centre[1] or centre[2]:
            raise ValueError(f"the {KIND_NAMES[kind]}'s coupler may spin about the line "
                             "from A to its output pin, so its centre must lie on it: (u, 0, 0)")
        if any(rows[i][j] for i in range(3) for j in range(3) if i != j) or \
                abs(rows[1][1] - rows[2][2]) > 1e-12 * scale:
            raise ValueError(f"the {KIND_NAMES[kind]}'s coupler may spin about the line "
                             "from A to its output pin, so its inertia must be axisymmetric "
                             "about it: ((axial, 0, 0), (0, transverse, 0), (0, 0, transverse))")
    return BodyMass(mass, centre, cast(Matrix, tuple(rows)))


class ForcesSetup(NamedTuple):
    """What forces() computes once for a call: the bodies, the loads and the ground (the numpy
    path's forces_of_arrays starts from it too)."""
    linkage: Closure
    speed_rpm: float
    dims: dict[str, float]
    radius: float
    masses: tuple[BodyMass, BodyMass, BodyMass]
    omega: float
    alpha: float
    gravity: Vector
    output_torque: float
    output_force: float
    coupler_point: Vector | None        # (u, v, 0) plane, (u, 0, 0) line, sphere's unit vector
    coupler_force: Vector
    ground: dict[str, Vector]
    axes: dict[str, tuple[Vector, Vector]]


RADIUS_RANGE = (1e-50, 1e100)       # metres: a sphere's radius whose powers the forces can take
#                                     (at 1e-99 a unit vector's length squared underflowed to 0)


def forces_setup(linkage: Closure, bodies: Bodies, effects: Effects, radius: float
                 ) -> ForcesSetup:
    """The checked bodies and effects of a forces() call (a ValueError says what is wrong)."""
    kind = linkage.kind
    spherical, plane = kind == SPHERICAL_FOUR_BAR, kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK)
    radius = checked_number(radius, "the sphere's radius")
    if not RADIUS_RANGE[0] <= radius <= RADIUS_RANGE[1]:       # its square neither 0 nor inf
        raise ValueError(f"the sphere's radius must be {RADIUS_RANGE[0]:g} to "
                         f"{RADIUS_RANGE[1]:g} metres, not {radius:g}")
    if radius != 1.0 and not spherical:
        raise ValueError("radius is the spherical four-bar's: the other kinds' dimensions are "
                         "their lengths in metres")
    dims = pin_dimensions(linkage.dims)
    if spherical:
        arcs = {n: math.acos(max(-1.0, min(1.0, cos_sin_degrees(dims[n])[0]))) for n in "bcd"}
        if min(math.sin(x) for x in arcs.values()) == 0.0:
            raise ValueError("forces need arcs b, c and d that are not 0 or 180 degrees")
        crank: Callable[[float], BodyMass] = functools.partial(_arc, radius=radius, arc=arcs["b"],
                                                            start=2, toward=0)
        coupler: Callable[[float], BodyMass] = functools.partial(_arc, radius=radius,
                                                              arc=arcs["c"], start=0, toward=1)
        output: Callable[[float], BodyMass] = functools.partial(_arc, radius=radius, arc=arcs["d"],
                                                             start=2, toward=0)
    else:
        lengths = [abs(dims[n]) for n in ("b", "c") + (("d",) if "d" in dims else ())]
        if min(lengths) == 0.0:
            raise ValueError("forces need links of non-zero length (b, c and d)")
        crank = functools.partial(_rod, length=abs(dims["b"]))
        coupler = functools.partial(_rod, length=abs(dims["c"]))
        output = (functools.partial(_rod, length=abs(dims["d"])) if not linkage.is_slider
                  else lambda m: BodyMass(m, _NOUGHT, (_NOUGHT, _NOUGHT, _NOUGHT)))
    masses = (_checked_body(kind, "crank", bodies.crank, crank),
              _checked_body(kind, "coupler", bodies.coupler, coupler),
              _checked_body(kind, "slider" if linkage.is_slider else "output", bodies.output,
                            output))
    if effects.gravity is None:
        gravity = _NOUGHT
    elif isinstance(effects.gravity, (int, float)):
        g = checked_number(effects.gravity, "gravity")
        gravity = (0.0, -g, 0.0) if plane else (0.0, 0.0, -g)
    else:
        gravity = cast(Vector, checked_numbers(effects.gravity, 3, "gravity (gx, gy, gz)"))
    output_torque = checked_number(effects.output_torque, "the output torque")
    output_force = checked_number(effects.output_force, "the output force")
    if output_torque and linkage.is_slider:
        raise ValueError("a slider-crank's output is its slider: load it with output_force")
    if output_force and not linkage.is_slider:
        raise ValueError("a four-bar's output is a crank: load it with output_torque")
    point, force = None, _NOUGHT
    if effects.coupler_force is not None:
        try:
            at, given = effects.coupler_force
        except (TypeError, ValueError):
            raise ValueError("coupler_force is ((u, v), (fx, fy, fz))") from None
        u, v = checked_numbers(at, 2, "the coupler force's point (u, v)")
        force = cast(Vector, checked_numbers(given, 3, "the coupler force (fx, fy, fz)"))
        form = PINS[kind].coupler
        if form == "line" and v:
            raise ValueError(f"the {KIND_NAMES[kind]}'s coupler may spin about the line "
                             "from A to its output pin, so a force on it must act at a point of "
                             f"that line: v must be 0, not {v:g}")
        if form == "sphere":
            (cu, su), (cv, sv) = cos_sin_degrees(u), cos_sin_degrees(v)
            point = (radius * cv * cu, radius * cv * su, radius * sv)
        else:
            point = (u, v, 0.0)
    if plane and (gravity[2] or force[2]):
        raise ValueError("the plane kinds are analysed in their plane: gravity and the coupler "
                         "force must have no z component")
    speed = checked_number(effects.speed_rpm, "the speed (rpm)")
    omega = 2.0 * math.pi * speed / 60.0
    alpha = checked_number(effects.crank_acceleration, "the crank's acceleration")
    ground = joint_positions(linkage, 0.0)
    return ForcesSetup(linkage, speed, dims, radius, masses, omega, alpha, gravity, output_torque,
                  output_force, point, force, ground.joints, ground.axes)


def _states(setup: ForcesSetup, m: Motion) -> tuple[tuple[_State, _State, _State], Vector, Vector]:
    """The three bodies at the Motion m, and the pins A and P (the output's, B or C)."""
    linkage, dims, r, w, al = setup.linkage, setup.dims, setup.radius, setup.omega, setup.alpha
    kind = linkage.kind
    assert m.output is not None and m.velocity is not None and m.acceleration is not None
    q1, q2 = m.velocity, m.acceleration
    a = PINS[kind].crank_pin(dims, *cos_sin_degrees(m.phi))
    p = output_pin_at(linkage, dims, m.output, cos_sin_degrees)
    p1, p2 = weighted_sum((q1, p[1])), weighted_sum((q1 * q1, p[2]), (q2, p[1]))
    pa, va, aa = weighted_sum((r, a[0])), weighted_sum((r * w, a[1])), weighted_sum((r * w * w, a[2]), (r * al, a[1]))
    pp, vp, ap = weighted_sum((r, p[0])), weighted_sum((r * w, p1)), weighted_sum((r * w * w, p2), (r * al, p1))
    x = unit_vector((pa[0], pa[1], 0.0))
    crank = _State(_NOUGHT, (x, cross(_Z, x), _Z), _NOUGHT, (0.0, 0.0, w), (0.0, 0.0, al))
    form = PINS[kind].coupler
    if form == "sphere":
        z = unit_vector(cross(pa, pp))
        spin = spin_about_centre(pa, pp, va, vp)
        rate = spin_about_centre(pa, pp, weighted_sum((1.0, aa), (-1.0, cross(spin, va))),
                                  weighted_sum((1.0, ap), (-1.0, cross(spin, vp))))
        x = unit_vector(pa)
        coupler = _State(_NOUGHT, (x, cross(z, x), z), _NOUGHT, spin, rate)
    else:
        ab, dv, da = weighted_sum((1.0, pp), (-1.0, pa)), weighted_sum((1.0, vp), (-1.0, va)), weighted_sum((1.0, ap),
                                                                                      (-1.0, aa))
        squared = dot(ab, ab)
        spin = weighted_sum((1.0 / squared, cross(ab, dv)))
        rate = weighted_sum((1.0 / squared, cross(ab, weighted_sum((1.0, da), (-1.0, cross(spin, dv))))))
        x = unit_vector(ab)
        y, z = (cross(_Z, x), _Z) if form == "plane" else _perpendicular_pair(x)
        coupler = _State(pa, (x, y, z), aa, spin, rate)
    if linkage.is_slider:
        g = setup.axes["guide"][1]
        y = _Y if kind == PLANE_SLIDER_CRANK else _X
        output = _State(pp, (g, y, cross(g, y)), ap, _NOUGHT, _NOUGHT)
    else:
        k = setup.axes["output"][1]
        pivot = setup.ground.get("B0", _NOUGHT) if kind != SPHERICAL_FOUR_BAR else _NOUGHT
        pivot = weighted_sum((r, pivot))
        arm = weighted_sum((1.0, pp), (-1.0, pivot))
        x = unit_vector(weighted_sum((1.0, arm), (-dot(arm, k), k)))
        output = _State(pivot, (x, cross(k, x), k), _NOUGHT, weighted_sum((q1 * w, k)),
                        weighted_sum((q2 * w * w + q1 * al, k)))
    return (crank, coupler, output), pa, pp


def _joints(setup: ForcesSetup, states: tuple[_State, _State, _State], pa: Vector, pp: Vector
            ) -> list[_Joint]:
    """The kind's joints with their unknowns at this position (see the notes above)."""
    kind = setup.linkage.kind
    out = PINS[kind].output_joint
    if kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK):
        pins = [_Joint("A0", None, 0, _NOUGHT, (_X, _Y), ()),
                _Joint("A", 0, 1, pa, (_X, _Y), ()), _Joint(out, 1, 2, pp, (_X, _Y), ())]
        if kind == PLANE_FOUR_BAR:
            return pins + [_Joint("B0", None, 2, states[2].origin, (_X, _Y), ())]
        return pins + [_Joint("guide", None, 2, pp, (_Y,), (_Z,))]
    if kind == SPHERICAL_FOUR_BAR:
        return [_Joint(name, before, after, _NOUGHT, (), _perpendicular_pair(unit_vector(axis)))
                for name, before, after, axis in (("A0", None, 0, _Z), ("A", 0, 1, pa),
                                                  ("B", 1, 2, pp),
                                                  ("B0", None, 2, setup.axes["output"][1]))]
    joints = [_Joint("A0", None, 0, _NOUGHT, (_X, _Y, _Z), _perpendicular_pair(_Z)),
              _Joint("A", 0, 1, pa, (_X, _Y, _Z), ()), _Joint(out, 1, 2, pp, (_X, _Y, _Z), ())]
    if kind == SKEW_FOUR_BAR:
        k = setup.axes["output"][1]
        return joints + [_Joint("B0", None, 2, states[2].origin, (_X, _Y, _Z),
                                _perpendicular_pair(k))]
    return joints + [_Joint("guide", None, 2, pp, _perpendicular_pair(setup.axes["guide"][1]),
                            (_X, _Y, _Z))]


def _equations(kind: str, states: tuple[_State, _State, _State]
               ) -> list[list[tuple[Vector, Vector]]]:
    """Each body's equations as (force, moment) directions its wrench about the origin is
    projected on: the plane's 3, space's 6 (the skew coupler's 5), Euler's 3 about O."""
    if kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK):
        return [[(_X, _NOUGHT), (_Y, _NOUGHT), (_NOUGHT, _Z)]] * 3
    if kind == SPHERICAL_FOUR_BAR:
        return [[(_NOUGHT, _X), (_NOUGHT, _Y), (_NOUGHT, _Z)]] * 3
    full = [(_X, _NOUGHT), (_Y, _NOUGHT), (_Z, _NOUGHT),
            (_NOUGHT, _X), (_NOUGHT, _Y), (_NOUGHT, _Z)]
    return [full, full[:3] + [(_NOUGHT, states[1].axes[1]), (_NOUGHT, states[1].axes[2])], full]


def _solved(rows: list[list[float]], rhs: list[float]) -> list[float] | None:
    """x with rows x = rhs, by Gaussian elimination with partial pivoting on the system scaled
    to a largest entry of 1 in each row and column; None where it is singular (a pivot under
    _SINGULAR_BELOW)."""
    n = len(rows)
    work = [list(row) + [b] for row, b in zip(rows, rhs)]
    for row in work:
        big = max(abs(v) for v in row[:n])
        if big == 0.0:
            return None
        row[:] = [v / big for v in row]
    columns = [max(abs(row[j]) for row in work) for j in range(n)]
    if min(columns) == 0.0:
        return None
    for row in work:
        row[:n] = [v / s for v, s in zip(row, columns)]
    for k in range(n):
        pivot = max(range(k, n), key=lambda i: abs(work[i][k]))
        if abs(work[pivot][k]) < _SINGULAR_BELOW:
            return None
        work[k], work[pivot] = work[pivot], work[k]
        for i in range(k + 1, n):
            f = work[i][k] / work[k][k]
            if f:
                work[i][k:] = [v - f * t for v, t in zip(work[i][k:], work[k][k:])]
    x = [0.0] * n
    for k in reversed(range(n)):
        x[k] = (work[k][n] - sum(work[k][j] * x[j] for j in range(k + 1, n))) / work[k][k]
    return [v / s for v, s in zip(x, columns)]


def _forces_at(setup: ForcesSetup, m: Motion) -> Forces:
    """One position's Forces (see forces)."""
    none = Forces(m.phi, None, None, None, None, None, m.status, setup.speed_rpm)
    if m.output is None:
        return none
    if m.status in (DEAD_CENTRE, CHANGE_POINT) or m.velocity is None or m.acceleration is None:
        return none._replace(status=UNBOUNDED)
    kind = setup.linkage.kind
    states, pa, pp = _states(setup, m)
    joints = _joints(setup, states, pa, pp)
    # each body's wrench about the origin that the reactions and the torque must make up:
    # the rate of its momenta less gravity and the loads
    needed = []
    for body, (mass, state) in enumerate(zip(setup.masses, states)):
        rho = _in_world(state.axes, mass.centre)
        centre = weighted_sum((1.0, state.origin), (1.0, rho))
        a_g = weighted_sum((1.0, state.acceleration), (1.0, cross(state.spin_rate, rho)),
                    (1.0, cross(state.spin, cross(state.spin, rho))))
        net = weighted_sum((mass.mass, a_g), (-mass.mass, setup.gravity))
        turning = weighted_sum((1.0, cross(centre, net)),
                        (1.0, _inertia_times(state.axes, mass.inertia, state.spin_rate)),
                        (1.0, cross(state.spin, _inertia_times(state.axes, mass.inertia,
                                                                state.spin))))
        if body == 1 and setup.coupler_point is not None:
            at = weighted_sum((1.0, state.origin), (1.0, _in_world(state.axes, setup.coupler_point)))
            net = weighted_sum((1.0, net), (-1.0, setup.coupler_force))
            turning = weighted_sum((1.0, turning), (-1.0, cross(at, setup.coupler_force)))
        if body == 2 and setup.output_torque:
            turning = weighted_sum((1.0, turning), (-setup.output_torque, state.axes[2]))
        if body == 2 and setup.output_force:
            load = weighted_sum((setup.output_force, state.axes[0]))
            net = weighted_sum((1.0, net), (-1.0, load))
            turning = weighted_sum((1.0, turning), (-1.0, cross(state.origin, load)))
        needed.append((net, turning))
    # one column per unknown: its unit wrench about the origin on each body it acts on
    columns: list[list[tuple[Vector, Vector]]] = []
    for joint in joints:
        units = [(d, cross(joint.at, d)) for d in joint.forces] + [(_NOUGHT, d)
                                                                   for d in joint.moments]
        for f, t in units:
            on = [(_NOUGHT, _NOUGHT)] * 3
            on[joint.after] = (f, t)
            if joint.before is not None:
                on[joint.before] = (weighted_sum((-1.0, f)), weighted_sum((-1.0, t)))
            columns.append(on)
    columns.append([(_NOUGHT, _Z), (_NOUGHT, _NOUGHT), (_NOUGHT, _NOUGHT)])     # the torque
    rows, rhs = [], []
    for body, equations in enumerate(_equations(kind, states)):
        for f_dir, t_dir in equations:
            rows.append([dot(f_dir, col[body][0]) + dot(t_dir, col[body][1]) for col in columns])
            rhs.append(dot(f_dir, needed[body][0]) + dot(t_dir, needed[body][1]))
    x = _solved(rows, rhs)
    if x is None:
        return none._replace(status=UNBOUNDED)
    torque, i = x[-1], 0
    reactions: dict[str, Reaction] = {}
    shaking_force, shaking_moment = _NOUGHT, (0.0, 0.0, -torque)
    for joint in joints:
        nf, nm = len(joint.forces), len(joint.moments)
        force = weighted_sum(*zip(x[i:i + nf], joint.forces)) if nf else None
        moment = weighted_sum(*zip(x[i + nf:i + nf + nm], joint.moments)) if nm else None
        i += nf + nm
        reactions[joint.name] = Reaction(force, moment)
        if joint.before is None:
            if force is not None:
                shaking_force = weighted_sum((1.0, shaking_force), (-1.0, force))
                shaking_moment = weighted_sum((1.0, shaking_moment), (-1.0, cross(joint.at, force)))
            if moment is not None:
                shaking_moment = weighted_sum((1.0, shaking_moment), (-1.0, moment))
    if kind == SPHERICAL_FOUR_BAR:     # the whole linkage's Newton: the loads less m a_G
        shaking_force = weighted_sum(*((-1.0, net) for net, _ in needed))
    numbers = [torque, torque * setup.omega, *shaking_force, *shaking_moment] + [
        v for r in reactions.values() for part in r if part is not None for v in part]
    if not all(map(math.isfinite, numbers)):     # masses or a speed past the floats' range
        return none._replace(status=OUT_OF_RANGE)
    return Forces(m.phi, torque, torque * setup.omega, reactions, shaking_force, shaking_moment,
                  m.status, setup.speed_rpm)


def body_masses(linkage: Closure, bodies: Bodies, radius: float = 1.0
                ) -> tuple[BodyMass, BodyMass, BodyMass]:
    """The crank's, coupler's and output's BodyMass as forces() takes them (a mass alone: the
    uniform rod, or arc, between the joints), or a ValueError that says what is wrong."""
    return forces_setup(linkage, bodies, Effects(), radius).masses


def forces(linkage: Closure, phis: Iterable[float], branch: int | str = 1,
           bodies: Bodies = Bodies(), effects: Effects = Effects(), *, radius: float = 1.0,
           start: int | None = None) -> list[Forces]:
    """The driving torque, the joints' reactions and the frame's shaking force and moment at
    each input angle of `phis` (degrees) on `branch` (as Linkage.sweep), for the bodies' masses
    and the effects (see the notes above; radius: the spherical four-bar's sphere, metres)."""
    setup = forces_setup(linkage, bodies, effects, radius)
    return [_forces_at(setup, m) for m in linkage.sweep(phis, branch, 2, start=start)]


PEAK_TOLERANCE = 0.01       # degrees: torque_peak closes on the peak to this (golden section)


class TorquePeak(NamedTuple):
    """The driving torque's largest size along a motion: its value (signed, N m) at the input
    angle phi; or the angles where the forces are unbounded (value and phi None: the torque
    grows without bound as the crank nears them); all None where no position is known."""
    value: float | None
    phi: float | None
    unbounded: tuple[float, ...] = ()


def torque_peak(linkage: Closure, phis: Sequence[float], branch: int = 1,
                bodies: Bodies = Bodies(), effects: Effects = Effects(), *, radius: float = 1.0,
                turns: bool = False, dead: frozenset[int] = frozenset(), refined: int = 2
                ) -> tuple[tuple[Forces, ...], TorquePeak]:
    """forces() at each of phis (increasing, degrees; turns: a full turn, the last the first's
    neighbour) on `branch`, the positions `dead` (dead centres) UNBOUNDED, and the torque's
    peak: unbounded where any position is, else the largest |T| of the positions and of each
    of the `refined` largest local peaks closed on between its neighbours by golden section to
    PEAK_TOLERANCE degrees (a peak narrower than the positions' spacing may be missed)."""
    def at(angles: Sequence[float]) -> list[Forces]:
        return forces(linkage, angles, branch, bodies, effects, radius=radius)
    results = tuple(r._replace(torque=None, power=None, joints=None, shaking_force=None,
                               shaking_moment=None, status=UNBOUNDED) if i in dead else r
                    for i, r in enumerate(at(phis)))
    unbounded = tuple(r.phi for r in results if r.status == UNBOUNDED)
    if unbounded:
        return results, TorquePeak(None, None, unbounded)
    count = len(results)
    size = [-1.0 if r.torque is None else abs(r.torque) for r in results]

    def beside(i: int) -> float | None:      # the angle of position i (out of range: None)
        if 0 <= i < count:
            return phis[i]
        return phis[i % count] + (360.0 if i >= count else -360.0) if turns and count else None
    peaks = [i for i in range(count) if size[i] >= 0.0
             and all(size[j % count] <= size[i] for j in (i - 1, i + 1) if beside(j) is not None)]
    best = [(r.torque, r.phi) for r in results if r.torque is not None]

    def found(phi: float) -> float:
        torque = at([phi])[0].torque
        if torque is None:
            return -1.0
        best.append((torque, phi))
        return abs(torque)
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    for i in sorted(peaks, key=lambda i: -size[i])[:refined]:
        lo, hi = (phis[i] if x is None else x for x in (beside(i - 1), beside(i + 1)))
        x1, x2 = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
        f1, f2 = found(x1), found(x2)
        while hi - lo > PEAK_TOLERANCE:
            if f1 >= f2:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - ratio * (hi - lo)
                f1 = found(x1)
            else:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + ratio * (hi - lo)
                f2 = found(x2)
    if not best:
        return results, TorquePeak(None, None)
    value, phi = max(best, key=lambda tp: abs(tp[0]))
    return results, TorquePeak(value, phi)


class ForcesSummary(NamedTuple):
    """The figures of a swept list of Forces: (value, phi) of the largest; None if none."""
    peak_torque: tuple[float, float] | None         # the largest |T|, signed
    rms_torque: float | None
    mean_power: float | None
    peak_joints: dict[str, tuple[float, float]]     # |force| (spherical: |moment about O|)
    peak_shaking_force: tuple[float, float] | None
    peak_shaking_moment: tuple[float, float] | None
    flywheel_inertia: float | None                  # kg m^2, for the speed fluctuation cs


def forces_summary(results: Sequence[Forces], *, cs: float = 0.05) -> ForcesSummary:
    """Peak and RMS torque, mean power, each joint's peak, the peak shaking force and moment,
    and the flywheel inertia ΔE_max / (cs omega^2) that holds the speed within +-cs/2 of its
    mean: ΔE_max the largest swing of the integral of (T - T_mean) dphi along `results` (None
    unless every position is defined; the sweep should be one whole turn, as a flywheel's cycle
    is: that is the caller's to give), means by the trapezoid rule; omega that of the speed the
    results were computed at (their speed_rpm: a ValueError if they differ)."""
    speeds = {r.speed_rpm for r in results}
    if len(speeds) > 1:
        raise ValueError("forces computed at different speeds "
                         f"({', '.join(map(value_text, sorted(speeds)))} rpm) have no one summary")
    known = [r for r in results if r.torque is not None]
    if not known:
        return ForcesSummary(None, None, None, {}, None, None, None)

    def peak(values: Iterable[tuple[float, float]]) -> tuple[float, float]:
        return max(values, key=lambda vp: abs(vp[0]))

    def size(v: Vector | None) -> float:
        return math.sqrt(dot(v, v)) if v is not None else 0.0

    torques = [cast(float, r.torque) for r in known]
    joints: dict[str, tuple[float, float]] = {}
    for r in known:
        for name, reaction in cast(dict, r.joints).items():
            value = size(reaction.force if reaction.force is not None else reaction.moment)
            if name not in joints or value > joints[name][0]:
                joints[name] = (value, r.phi)
    phis = [r.phi * RAD for r in known]
    span = phis[-1] - phis[0]
    if len(known) > 1 and span:
        weights = [((phis[min(i + 1, len(phis) - 1)] - phis[max(i - 1, 0)]) / 2.0) / span
                   for i in range(len(phis))]
    else:
        weights = [1.0 / len(known)] * len(known)
    mean = sum(w * t for w, t in zip(weights, torques))
    rms = math.sqrt(sum(w * t * t for w, t in zip(weights, torques)))
    omega = 2.0 * math.pi * known[0].speed_rpm / 60.0
    flywheel = None
    if (len(known) == len(results) and len(known) > 1 and span and cs > 0.0
            and cs * omega * omega > 0.0):          # a speed whose square does not underflow
        energy, low, high = 0.0, 0.0, 0.0
        for i in range(1, len(known)):
            energy += (torques[i - 1] + torques[i] - 2.0 * mean) / 2.0 * (phis[i] - phis[i - 1])
            low, high = min(low, energy), max(high, energy)
        flywheel = (high - low) / (cs * omega * omega)
    return ForcesSummary(
        peak((t, r.phi) for t, r in zip(torques, known)), rms, mean * omega, joints,
        peak((size(r.shaking_force), r.phi) for r in known),
        peak((size(r.shaking_moment), r.phi) for r in known), flywheel)


def forces_lines(results: Sequence[Forces], *, cs: float = 0.05, prefix: str = ""
                 ) -> list[str]:
    """The `name = value` lines of a swept list of Forces (forces_summary's figures), each name
    after `prefix`: peak and RMS torque with their angles, mean power, each joint's peak force
    (the spherical kind's: its moment about O), the peak shaking force and moment, the flywheel
    for the speed fluctuation cs, and the angles where the forces are unbounded or overflow."""
    s = forces_summary(results, cs=cs)
    rows: list[tuple[str, str]] = []

    def peak(name: str, value: tuple[float, float] | None, unit: str) -> None:
        if value is None:
            rows.append((name, "none (no position whose forces are known)"))
        else:
            rows.extend([(name, f"{value_text(value[0])} {unit}"),
                         (f"{name}_phi", value_text(value[1]))])
    peak("torque_peak", s.peak_torque, "N m")
    rows.append(("torque_rms", "none" if s.rms_torque is None
                 else f"{value_text(s.rms_torque)} N m"))
    rows.append(("power_mean", "none" if s.mean_power is None
                 else f"{value_text(s.mean_power)} W"))
    for name, value in s.peak_joints.items():
        moment = any(r.joints and r.joints[name].force is None for r in results)
        peak(f"joint_{name}_{'moment' if moment else 'force'}_peak", value,
             "N m" if moment else "N")
    peak("shaking_force_peak", s.peak_shaking_force, "N")
    peak("shaking_moment_peak", s.peak_shaking_moment, "N m")
    rows.append(("fluctuation", value_text(cs)))
    rows.append(("flywheel_inertia", f"{value_text(s.flywheel_inertia)} kg m^2"
                 if s.flywheel_inertia is not None else
                 "none (it needs the speed, and the forces bounded at every angle of the sweep)"))
    for status in (UNBOUNDED, OUT_OF_RANGE):
        rows.append((status, ", ".join(value_text(r.phi) for r in results
                                       if r.status == status) or "none"))
    return [f"{prefix}{name} = {value}" for name, value in rows]


# ---- 10. The numpy path: sweeps, coupler points and file lines on arrays -------------------------
#
# Holds: the engine's sweep on numpy arrays (sweep_arrays' work: the same formulas in blocks, a
# point near a dead centre or change point handed to the scalar engine), the coupler point and
# transmission angle on arrays, and numbers formatted as repr formats them a block at once (the DAT
# and CSV lines). numpy is an optional extra: numpy_module raises FastUnavailable without it. No
# section but this and the next (the forces on arrays) uses numpy itself (test_layout).
#
# Uses: sections 1, 2, 6 and 7.
# Offers: STATUS_CODES, FAST_BLOCK, FAST_MARGIN, FastUnavailable, numpy_module, angle_array,
#   MotionArrays, assembled_count, motion_arrays_of, cos_sin_degrees_array, CouplerArrays,
#   coupler_of_arrays, transmission_of_arrays, SweepColumns, NUMBER_ROWS, LINE_ROWS, as_columns,
#   column_texts.


# -- the vectorised path: numpy, a block of angles at a time ------------------------------------
#
# Linkage.sweep_arrays is _sweep_four_bar and _sweep_slider written on numpy arrays: the same
# formulas with the same operations in the same order, so the same numbers: the output within a
# unit in the last place (numpy's arctan2 is not libm's; where numpy's cos and sin are not
# libm's either, a few). hypot is computed as CPython's math.hypot (_fast_hypot) wherever its
# last place matters (the slider's; the four-bar's near a dead centre: _fast_rr_disc), and there
# the velocity and acceleration are the scalar engine's to the bit; well off a dead centre the
# four-bar takes sqrt(p^2 + q^2), within 1e-14 of them. The angles go through in
# blocks of FAST_BLOCK, every operation written into a preallocated array (out=) so that the
# working set stays in the cache; a term whose constant is zero is left out (it adds nothing but
# the sign of a zero). The vectorised path decides only "assembled" and the plainly "not
# assembled": a point the scalar engine would redo in 50-digit decimal (discriminant within
# _precise_below of zero), widened by FAST_MARGIN so that a last-place difference cannot carry a
# point across that line, and any point whose numbers are not finite, is handed to Linkage.sweep
# itself - never approximated here. numpy is imported at the first use only: linkage.py runs on
# the standard library alone, and this path is the optional extra `fast`.

STATUS_CODES = (ASSEMBLED, DEAD_CENTRE, NOT_ASSEMBLED, INDETERMINATE,  # MotionArrays.status,
                CHANGE_POINT, STOPPED)          # SweepColumns.status: every Motion.status
FAST_BLOCK = 16384       # angles a block (of 4096 to 32768 the fastest at 1e4 and 1e5 points here,
#                          2026-11-26; memory: 50 arrays of it, 6.5 MB)
FAST_MARGIN = 2.0        # handed to the scalar engine: |D| <= FAST_MARGIN * its decimal line


class FastUnavailable(RuntimeError):
    """The vectorised path (Linkage.sweep_arrays, run --fast, a scene's fast = true) where numpy
    cannot be imported."""


def numpy_module() -> ModuleType:
    """numpy, imported at the first use; FastUnavailable, saying what to install, without it.
    Imported with SIGINT, SIGTERM and SIGHUP held (held_import): a signal whose handler ran in
    numpy's C initialisation was swallowed there (the import went on, and a run finished as if
    no signal had come), and the threads numpy's BLAS starts then hold them for good."""
    try:
        with held_import("numpy"):
            import numpy
    except ImportError:
        raise FastUnavailable("the vectorised path (--fast, a scene's fast = true) needs numpy, "
                              "which is not installed: python3 -m pip install numpy; "
                              "without it, leave --fast out: the same numbers, computed one "
                              "point at a time") from None
    return numpy


def angle_array(start: float, step: float, first: int, last: int) -> numpy.ndarray:
    """The input angles start + i * step for i from first to last (excluded) as a float64
    array: the same numbers as the scalar path's list (evenly_spaced_angles)."""
    np = numpy_module()
    return np.arange(first, last, dtype=np.float64) * step + start


class MotionArrays(NamedTuple):
    """Linkage.sweep_arrays' answer: Linkage.sweep's Motion fields as numpy arrays, one element an
    input angle. output, velocity and acceleration are float64, NaN where the position does not
    exist (status says why); velocity and acceleration are None when not asked for. status holds
    int8 codes, indices into STATUS_CODES (0 ASSEMBLED, 1 DEAD_CENTRE, 2 NOT_ASSEMBLED,
    3 INDETERMINATE, 4 CHANGE_POINT; 5 STOPPED is a followed motion's, which this path does not
    compute)."""

    phi: numpy.ndarray
    output: numpy.ndarray
    velocity: numpy.ndarray | None          # None: not asked for
    acceleration: numpy.ndarray | None
    status: numpy.ndarray

    def motions(self) -> list[Motion]:
        """The same answer as Linkage.sweep gives it: a list of Motion, None for NaN."""
        columns = [None if a is None else [None if v != v else v for v in a.tolist()]
                   for a in (self.output, self.velocity, self.acceleration)]
        n = len(self.phi)
        output, velocity, acceleration = (c if c is not None else [None] * n for c in columns)
        return [Motion(phi, o, v, a, STATUS_CODES[k]) for phi, o, v, a, k in
                zip(self.phi.tolist(), output, velocity, acceleration, self.status.tolist())]


def assembled_count(arrays: MotionArrays) -> int:
    """How many of a MotionArrays' angles have a position."""
    return len(arrays.output) - int(numpy_module().isnan(arrays.output).sum())


def _fast_lin(np, a, x, b, y, out, spare):
    """a x + b y into out, as the scalar engine rounds it; a term with a zero constant left out."""
    if a and b:
        np.multiply(x, a, out=out)
        np.multiply(y, b, out=spare)
        return np.add(out, spare, out=out)
    if a or b:
        return np.multiply(x if a else y, a or b, out=out)
    out.fill(0.0)
    return out


def _fast_plus(np, k, x, out):
    """k + x into out (x itself when k is zero)."""
    return np.add(x, k, out=out) if k else x


def _fast_cos_sin(np, phi, reduce, w):
    """cos_sin_degrees on an array (the one reduction, in numpy: r = phi mod 360, unless not
    `reduce`; y = r - 90 n, |y| <= 45; cos y and sin y turned by n quarter turns, exact), into
    the work buffers w."""
    r = np.fmod(phi, 360.0, out=w["r"]) if reduce else phi
    n = np.divide(r, 90.0, out=w["n"])
    np.rint(n, out=n)                       # half to even, as round() does
    y = np.multiply(n, 90.0, out=w["y"])
    np.subtract(r, y, out=y)
    np.multiply(y, RAD, out=y)
    cy, sy = np.cos(y, out=w["cy"]), np.sin(y, out=w["sy"])
    lo, hi = n.min(), n.max()
    if lo == hi:                            # one quarter turn for the whole block (the usual)
        q = int(lo) & 3
        if q == 0:
            return cy, sy
        if q == 2:
            return np.negative(cy, out=cy), np.negative(sy, out=sy)
        return (np.negative(sy, out=sy), cy) if q == 1 else (sy, np.negative(cy, out=cy))
    c, s, spare = w["c"], w["s"], w["spare"]
    edges = np.flatnonzero(n[1:] != n[:-1]) if lo == lo else n[:0]      # NaN: lo != lo
    if 0 < 256 * len(edges) < len(n):       # a few runs of one quarter turn (a sweep): each
        ends = [0, *(edges + 1).tolist(), len(n)]    # copied or negated, no table looked up
        for a, b in zip(ends, ends[1:]):
            q = int(n[a]) & 3
            for out, source, negate in ((c, sy if q & 1 else cy, q in (1, 2)),
                                        (s, cy if q & 1 else sy, q >= 2)):
                if negate:
                    np.negative(source[a:b], out=out[a:b])
                else:
                    out[a:b] = source[a:b]
        return c, s
    quarter = w["quarter"]
    np.copyto(quarter, n, casting="unsafe")
    np.bitwise_and(quarter, 3, out=quarter)         # (not take's mode="wrap": it counts a NaN's
    turn_c = np.take(_QUARTER_COS, quarter, out=w["tc"], mode="clip")     # -2^63 up by 4s)
    turn_s = np.take(_QUARTER_SIN, quarter, out=w["ts"], mode="clip")
    np.multiply(cy, turn_c, out=c)
    np.subtract(c, np.multiply(sy, turn_s, out=spare), out=c)
    np.multiply(sy, turn_c, out=s)
    np.add(s, np.multiply(cy, turn_s, out=spare), out=s)
    return c, s


_QUARTER_COS = (1.0, 0.0, -1.0, 0.0)     # cos and sin of n quarter turns
_QUARTER_SIN = (0.0, 1.0, 0.0, -1.0)
_FAST_WELL_OFF = 0.5     # D / (P^2 + Q^2) above which a point is well off a dead centre,
_FAST_TINY = 2.0 ** -900  # D this far above the underflow (_fast_rr_disc)


def _fast_square(np, x, hi, lo, t, u):
    """x^2 = hi + lo exactly (Dekker's split): the double-length square CPython's hypot uses."""
    np.multiply(x, x, out=hi)
    np.multiply(x, 134217729.0, out=t)              # 2^27 + 1
    np.subtract(t, x, out=u)
    np.subtract(t, u, out=t)                        # the high half of x
    np.subtract(x, t, out=u)                        # the low half
    np.multiply(t, t, out=lo)
    np.subtract(lo, hi, out=lo)
    np.multiply(t, 2.0, out=t)
    np.multiply(t, u, out=t)
    np.add(lo, t, out=lo)                           # ((xh xh - hi) + 2 xh xl) + xl xl
    np.multiply(u, u, out=u)
    np.add(lo, u, out=lo)


def _fast_hypot(np, x, y, out, w):
    """math.hypot(x, y) elementwise, bit for bit as CPython 3.11 computes it (vector_norm: scaled
    by a power of two, the squares and their sum carried as double-doubles, one differential
    correction; identical on 3 million random pairs). numpy's hypot is libm's, an ulp away in
    about 0.6% of cases, which the discriminant's cancellation near a dead centre magnifies
    beyond 1e-13 in the output. NaN where x = y = 0 (the caller hands such points over)."""
    ax, ay, hi, lo, t, u = (w[key] for key in ("ax", "ay", "hi", "lo", "t", "t2"))
    csum, f1, f2, exponent = w["csum"], w["f1"], w["f2"], w["exponent"]
    np.abs(x, out=ax)
    np.abs(y, out=ay)
    np.frexp(np.maximum(ax, ay, out=out), out=(t, exponent))
    np.negative(exponent, out=exponent)
    np.ldexp(ax, exponent, out=ax)                  # lossless scaling into [0.5, 1)
    np.ldexp(ay, exponent, out=ay)
    _fast_square(np, ax, hi, f1, t, u)
    np.add(hi, 1.0, out=csum)                       # csum = 1 + x^2, f2 its rounding error
    np.subtract(1.0, csum, out=f2)
    np.add(f2, hi, out=f2)
    _fast_square(np, ay, hi, lo, t, u)
    np.add(f1, lo, out=f1)
    np.add(csum, hi, out=t)                         # csum + y^2, its error into f2
    np.subtract(csum, t, out=csum)
    np.add(csum, hi, out=csum)
    np.add(f2, csum, out=f2)
    csum, t = t, csum
    h = np.subtract(csum, 1.0, out=out)
    np.add(h, np.add(f1, f2, out=lo), out=h)
    np.sqrt(h, out=h)
    _fast_square(np, h, hi, lo, ax, u)              # h^2 = hi + lo
    np.subtract(csum, hi, out=ay)                   # csum - h^2, its error into f2
    np.subtract(csum, ay, out=csum)
    np.subtract(csum, hi, out=csum)
    np.add(f2, csum, out=f2)
    np.subtract(f1, lo, out=f1)
    np.subtract(ay, 1.0, out=ay)
    np.add(ay, np.add(f1, f2, out=f1), out=ay)      # the residual
    np.divide(ay, np.multiply(h, 2.0, out=u), out=ay)
    np.add(h, ay, out=h)                            # the differential correction
    np.negative(exponent, out=exponent)
    return np.ldexp(h, exponent, out=h)


def _fast_rr_disc(np, p, q, sv, line, w, disc):
    """hypot(p, q) and the discriminant D = (rr - sv)(rr + sv) into w["rr"] and disc, as
    _sweep_four_bar has them wherever it matters. rr = sqrt(p^2 + q^2), within 3 units of
    roundoff (3.3e-16) of CPython's hypot, where D is over _FAST_WELL_OFF of p^2 + q^2 (there
    sv <= root, so psi moves by at most 3.3e-16 rad = 1.9e-14 degree, psi' and psi'' by about
    1e-15 of themselves, 1.1e-14 at worst on 600 random linkages) or plainly under -line (not
    assembled either way); CPython's hypot itself (_fast_hypot) at the points between, near a
    dead centre, where rr's last place is magnified (on the whole block where they are more
    than half of it)."""
    h2, rr, spare, doubt, below = w["h2"], w["rr"], w["spare"], w["missing"], w["flag"]
    np.multiply(p, p, out=h2)
    np.add(h2, np.multiply(q, q, out=spare), out=h2)
    np.sqrt(h2, out=rr)
    np.subtract(rr, sv, out=disc)
    np.multiply(disc, np.add(rr, sv, out=spare), out=disc)
    np.multiply(h2, _FAST_WELL_OFF, out=spare)
    np.add(spare, _FAST_TINY, out=spare)
    np.less_equal(disc, spare, out=doubt)                   # not well off a dead centre
    np.greater_equal(disc, -(line + _FAST_TINY), out=below)  # nor plainly not assembled
    np.logical_and(doubt, below, out=doubt)
    if not doubt.any():
        return rr, disc
    where = np.flatnonzero(doubt)
    if 2 * len(where) > len(rr):
        _fast_hypot(np, p, q, rr, w)
    else:
        part = {key: w[key][:len(where)] for key in _HYPOT_WORK}
        x, y = np.take(p, where, out=part["h2"]), np.take(q, where, out=part["spare"])
        rr[where] = _fast_hypot(np, x, y, part["root"], part)
    np.subtract(rr, sv, out=disc)
    np.multiply(disc, np.add(rr, sv, out=spare), out=disc)
    return rr, disc


_HYPOT_WORK = ("h2", "spare", "root", "ax", "ay", "hi", "lo", "t", "t2", "csum", "f1", "f2",
               "exponent")


def _fast_four_bar(np, k, c, s, sign, level, line, res, w):
    """_sweep_four_bar on one block: psi, psi', psi'' into res, the discriminant into
    res["disc"] (exact where it is within `line` of zero: _fast_rr_disc)."""
    p0, pc, ps, q0, qc, qs, s0, sc, ss = k
    spare = w["spare"]
    xp = _fast_lin(np, pc, c, ps, s, w["xp"], spare)
    xq = _fast_lin(np, qc, c, qs, s, w["xq"], spare)
    xs = _fast_lin(np, sc, c, ss, s, w["xs"], spare)
    p, q, sv = _fast_plus(np, p0, xp, w["p"]), _fast_plus(np, q0, xq, w["q"]), \
        _fast_plus(np, s0, xs, w["sv"])
    rr, disc = _fast_rr_disc(np, p, q, sv, line, w, res["disc"])
    root = np.sqrt(disc, out=w["root"])      # NaN where not assembled: found by the caller
    sn, cn = w["sn"], w["cn"]
    np.multiply(q, sv, out=sn)               # sn = -q sv - sign p root
    pr = np.multiply(p, root, out=spare)
    (np.add if sign > 0 else np.subtract)(sn, pr, out=sn)
    np.negative(sn, out=sn)
    np.multiply(p, sv, out=cn)               # cn = -p sv + sign q root
    qr = np.multiply(q, root, out=spare)
    (np.subtract if sign > 0 else np.add)(cn, qr, out=cn)
    np.negative(cn, out=cn)
    psi = np.arctan2(sn, cn, out=res["output"])
    np.multiply(psi, DEG, out=psi)
    if np.equal(psi, -180.0, out=w["flag"]).any():
        np.copyto(psi, 180.0, where=w["flag"])
    if level == 0:
        return
    r2 = np.multiply(rr, rr, out=w["r2"])
    cp, sp = np.divide(cn, r2, out=cn), np.divide(sn, r2, out=sn)
    dp = _fast_lin(np, ps, c, -pc, s, w["dp"], spare)
    dq = _fast_lin(np, qs, c, -qc, s, w["dq"], spare)
    ds = _fast_lin(np, ss, c, -sc, s, w["ds"], spare)
    vel = np.multiply(dp, cp, out=res["velocity"])       # -sign (dp cp + dq sp + ds) / root
    np.add(vel, np.multiply(dq, sp, out=spare), out=vel)
    np.add(vel, ds, out=vel)
    np.divide(vel, root, out=vel)
    if sign > 0:
        np.negative(vel, out=vel)
    if level == 1:
        return
    acc = res["acceleration"]
    e = np.multiply(xp, cp, out=w["e"])                  # -e_ff = xp cp + xq sp + xs
    np.add(e, np.multiply(xq, sp, out=spare), out=e)
    np.add(e, xs, out=e)
    fp = np.multiply(dq, cp, out=w["fp"])                # e_fp = dq cp - dp sp
    np.subtract(fp, np.multiply(dp, sp, out=spare), out=fp)
    np.multiply(fp, 2.0, out=fp)
    np.multiply(fp, vel, out=fp)
    np.subtract(fp, e, out=acc)                          # e_ff + 2 e_fp vel
    np.multiply(sv, vel, out=spare)
    np.multiply(spare, vel, out=spare)
    np.add(acc, spare, out=acc)                          # ... + sv vel vel
    np.divide(acc, root, out=acc)
    if sign > 0:
        np.negative(acc, out=acc)


def _fast_slider(np, k, c, s, sign, level, line, res, w):
    """_sweep_slider on one block, in the linkage's scaled lengths (the caller multiplies by the
    unit): x, x', x'' into res, the discriminant into res["disc"]."""
    m0, mc, ms, k0, kc, ks, u0, uc, us, v0, vc, vs, rod = k
    spare = w["spare"]
    xm = _fast_lin(np, mc, c, ms, s, w["xm"], spare)
    xk = _fast_lin(np, kc, c, ks, s, w["xk"], spare)
    m, q = _fast_plus(np, m0, xm, w["m"]), _fast_plus(np, k0, xk, w["q"])
    u = _fast_affine(np, u0, uc, c, us, s, w["u"], spare)
    if v0 or vc or vs:
        dist = _fast_hypot(np, u, _fast_affine(np, v0, vc, c, vs, s, w["v"], spare), w["dist"],
                           w)
    else:
        dist = np.abs(u, out=w["dist"])                  # hypot(u, 0), exactly
    disc = np.subtract(rod, dist, out=res["disc"])
    np.multiply(disc, np.add(dist, rod, out=spare), out=disc)
    root = np.sqrt(disc, out=w["root"])
    negative = np.less(m, 0.0, out=w["flag"])
    big = w["big"]                                       # m + root, or m - root where m < 0
    np.copyto(big, root)
    np.negative(big, out=big, where=negative)
    np.add(big, m, out=big)
    x = res["output"]
    np.divide(q, big, out=x)                             # the other root, q / big
    if sign < 0:
        np.copyto(x, big, where=negative)
    else:
        np.logical_not(negative, out=negative)
        np.copyto(x, big, where=negative)
    if level == 0:
        return
    dm = _fast_lin(np, ms, c, -mc, s, w["dm"], spare)
    dk = _fast_lin(np, ks, c, -kc, s, w["dk"], spare)
    vel = np.multiply(dm, x, out=res["velocity"])        # sign (dm x - dk / 2) / root
    np.subtract(vel, np.multiply(dk, 0.5, out=spare), out=vel)
    np.divide(vel, root, out=vel)
    if sign < 0:
        np.negative(vel, out=vel)
    if level == 1:
        return
    acc = np.multiply(xk, 0.5, out=res["acceleration"])  # sign (xk/2 - xm x + 2 dm x' - x'^2)
    np.subtract(acc, np.multiply(xm, x, out=spare), out=acc)
    np.multiply(dm, 2.0, out=spare)
    np.add(acc, np.multiply(spare, vel, out=spare), out=acc)
    np.subtract(acc, np.multiply(vel, vel, out=spare), out=acc)
    np.divide(acc, root, out=acc)
    if sign < 0:
        np.negative(acc, out=acc)


def _fast_affine(np, k0, kc, c, ks, s, out, spare):
    """(k0 + kc c) + ks s into out, in _sweep_slider's order; zero terms left out."""
    if kc:
        np.multiply(c, kc, out=out)
        if k0:
            np.add(out, k0, out=out)
    else:
        out.fill(k0)
    if ks:
        np.add(out, np.multiply(s, ks, out=spare), out=out)
    return out


_FAST_WORK = ("r", "n", "y", "cy", "sy", "tc", "ts", "c", "s", "spare", "xp", "xq", "xs", "p",
              "q", "sv", "rr", "root", "sn", "cn", "r2", "dp", "dq", "ds", "e", "fp", "xm", "xk",
              "m", "u", "v", "dist", "big", "dm", "dk", "ax", "ay", "hi", "lo", "t", "t2", "csum",
              "f1", "f2", "disc", "h2")
_FAST_SPARE = tuple(key for key in _FAST_WORK
                    if key not in ("c", "s", "cy", "sy", "cn", "sn", "root"))


def motion_arrays_of(linkage: Closure, phis: Sequence[float] | numpy.ndarray, branch: int,
                     derivatives: int, trig: dict[str, numpy.ndarray] | None = None,
                     each_block: Callable[[int, int, list[Any], numpy.ndarray, list[Any]], object]
                     | None = None
                     ) -> MotionArrays:
    """Linkage.sweep_arrays: see there. trig, where given, receives the cosines and sines the
    sweep computes on its way (for forces_of_arrays): "phi" the (2, n) cos and sin of the input
    angles, "output" a four-bar's of its output angles (derivatives 1 or 2); NaN at a point
    handed to the scalar sweep. each_block, where given, is called with each block's first
    index, the count of angles, its arrays while they are in the cache (the cos and sin of
    phi, a four-bar's of psi, then output, velocity, acceleration (derivatives 2) and the
    square root of the discriminant), its points to be handed to the scalar sweep (True;
    their numbers there not yet known) and the block's work arrays free till the next
    (float64), for Linkage.forces_arrays (forces_arrays_of)."""
    np = numpy_module()
    if branch not in (1, 2):
        raise ValueError("branch is 1 (the listing's A+B) or 2 (A-B)")
    if derivatives not in (0, 1, 2):
        raise ValueError("derivatives is 0 (output), 1 (and velocity) or 2 (and acceleration)")
    try:
        phi = np.array(phis, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError("input angles must be numbers") from None
    if phi.ndim != 1:
        raise ValueError("input angles must be a sequence of numbers (one dimension)")
    low, high = (phi.min(), phi.max()) if len(phi) else (0.0, 0.0)   # NaN if any is NaN
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ValueError("input angles must be finite")
    count, sign, level = len(phi), 1.0 if branch == 1 else -1.0, derivatives
    res = {"output": np.empty(count), "velocity": np.empty(count) if level >= 1 else None,
           "acceleration": np.empty(count) if level >= 2 else None}
    status = np.empty(count, dtype=np.int8)
    block = min(FAST_BLOCK, max(count, 1))
    w = dict(zip(_FAST_WORK, np.empty((len(_FAST_WORK), block))))   # one allocation: the
    #                                     allocator keeps it for the next call, not new pages
    w["flag"], w["missing"], w["redo"] = np.empty((3, block), dtype=bool)
    w["quarter"] = np.empty(block, dtype=np.intp)
    w["exponent"] = np.empty(block, dtype=np.intc)
    reduce = not max(-low, high) <= 360.0      # +-360 itself: fmod's 0 to the same bits
    step = _fast_slider if linkage.is_slider else _fast_four_bar
    k = linkage.constants
    line = FAST_MARGIN * linkage.precise_below
    last = ("output", "velocity", "acceleration")[level]
    not_assembled = np.int8(STATUS_CODES.index(NOT_ASSEMBLED))
    redo = []
    if trig is not None:
        trig.update({key: np.empty((2, count)) for key in ("phi", "output")[
            :1 if linkage.is_slider or not level else 2]})
    with np.errstate(all="ignore"):        # a block at a time: memory bounded, in the cache
        for start in range(0, count, block):
            stop = min(start + block, count)
            n = stop - start
            part = {key: None if a is None else a[start:stop] for key, a in res.items()}
            work = w if n == block else {key: a[:n] for key, a in w.items()}
            part["disc"] = work["disc"]
            c, s = _fast_cos_sin(np, phi[start:stop], reduce, work)
            step(np, k, c, s, sign, level, line, part, work)
            if trig is not None:         # the four-bar's cos and sin of psi: cn, sn (cp, sp)
                for key, pair in (("phi", (c, s)), ("output", (work["cn"], work["sn"]))):
                    if key in trig:
                        trig[key][0, start:stop], trig[key][1, start:stop] = pair
            disc, missing, again = part["disc"], work["missing"], work["redo"]
            np.greater(disc, line, out=again)                # plainly assembled, and finite
            np.logical_and(again, np.isfinite(part[last], out=work["flag"]), out=again)
            np.less(disc, -line, out=missing)                # plainly not assembled
            np.logical_or(again, missing, out=again)
            np.logical_not(again, out=again)                 # neither: the scalar engine's
            np.multiply(missing, not_assembled, out=status[start:stop])
            if again.any():
                redo.append(np.flatnonzero(again) + start)
            if linkage.is_slider:
                for key in ("output", "velocity", "acceleration"):
                    if part[key] is not None:
                        np.multiply(part[key], linkage.unit, out=part[key])
            if each_block is not None:
                given = [c, s] + ([] if linkage.is_slider else [work["cn"], work["sn"]])
                each_block(start, count, given + [part["output"], part["velocity"],
                                                  part["acceleration"], work["root"]], again,
                           [work[key] for key in _FAST_SPARE])
    where = np.concatenate(redo) if redo else np.empty(0, dtype=np.intp)
    if len(where):
        for pairs in (trig or {}).values():
            pairs[:, where] = math.nan
        columns = [res[key] for key in ("output", "velocity", "acceleration")]
        for i, m in zip(where.tolist(), linkage.sweep(phi[where].tolist(), branch, level)):
            for column, value in zip(columns, m[1:4]):
                if column is not None:
                    column[i] = math.nan if value is None else value
            status[i] = STATUS_CODES.index(m.status)
    return MotionArrays(phi, res["output"], res["velocity"], res["acceleration"], status)


def cos_sin_degrees_array(np: ModuleType, x: Any) -> tuple[numpy.ndarray, numpy.ndarray]:
    """cos_sin_degrees elementwise (NaN stays NaN): _fast_cos_sin, with buffers of its own."""
    x = np.asarray(x, dtype=np.float64)
    w = {k: np.empty_like(x) for k in ("r", "n", "y", "cy", "sy", "tc", "ts", "c", "s", "spare")}
    w["quarter"] = np.empty(x.shape, dtype=np.intp)
    with np.errstate(invalid="ignore"):             # NaN's quarter: any, its cos and sin NaN
        return _fast_cos_sin(np, x, True, w)


class CouplerArrays(NamedTuple):
    """Linkage.coupler_arrays' answer: phi, then position, velocity and acceleration as float64
    arrays of shape (n, 3) (NaN where there is no position; velocity and acceleration None when
    not asked for), and the MotionArrays status codes."""
    phi: numpy.ndarray
    position: numpy.ndarray
    velocity: numpy.ndarray | None          # None: not asked for
    acceleration: numpy.ndarray | None
    status: numpy.ndarray


def coupler_of_arrays(linkage: Closure, arrays: MotionArrays, u: float,
                      v: float = 0.0) -> CouplerArrays:
    """coupler_of on a MotionArrays (Linkage.sweep_arrays'): a CouplerArrays."""
    np = numpy_module()
    u, v = check_coupler_point(linkage, u, v)
    level = 0 if arrays.velocity is None else 1 if arrays.acceleration is None else 2
    c, s = cos_sin_degrees_array(np, arrays.phi)
    with np.errstate(all="ignore"):
        a, p, _ = joint_kinematics(linkage, pin_dimensions(linkage.scaled), c, s,
                                    arrays.output, level, arrays.velocity,
                                    arrays.acceleration, functools.partial(cos_sin_degrees_array,
                                                                           np))
        point = coupler_form(linkage, a, p, u, v, np.sqrt)
    count = len(arrays.phi)
    stacked = [np.stack([np.broadcast_to(np.asarray(x, dtype=np.float64), (count,))
                         for x in w], axis=1) for w in point] + [None, None]
    position, velocity, acceleration = stacked[:3]
    return CouplerArrays(arrays.phi, position, velocity, acceleration, arrays.status)


def transmission_of_arrays(linkage: Closure, arrays: MotionArrays,
                           trig: dict[str, numpy.ndarray] | None = None) -> numpy.ndarray:
    """transmission_of on a MotionArrays: a float64 array, NaN where there is no position.
    trig: what motion_arrays_of gave for these arrays, whose cosines and sines of phi are those
    this would compute (the same function), but at a point handed to the scalar sweep (NaN):
    those are computed here, into trig's arrays."""
    np = numpy_module()
    if trig is None:
        c, s = cos_sin_degrees_array(np, arrays.phi)
    else:
        c, s = trig["phi"]
        redo = np.flatnonzero(np.isnan(c))
        if len(redo):
            c[redo], s[redo] = cos_sin_degrees_array(np, arrays.phi[redo])
    with np.errstate(all="ignore"):
        a, p, p_q = joint_kinematics(linkage, pin_dimensions(linkage.scaled), c, s,
                                      arrays.output, 0, None, None,
                                      functools.partial(cos_sin_degrees_array, np))
        mu = transmission_form(linkage.kind, a[0], p[0], p_q, np.arctan2)
    return np.broadcast_to(np.asarray(mu, dtype=np.float64), (len(arrays.phi),)).copy()



class SweepColumns(NamedTuple):
    """A block of a sweep's rows as numpy arrays, for the files: phi, output, velocity,
    acceleration (float64, NaN where there is no value), status (int8 codes, STATUS_CODES),
    extra (the rows' further fields, float64 arrays: the transmission angle, a coupler
    point's nine coordinates)."""
    phi: numpy.ndarray
    output: numpy.ndarray
    velocity: numpy.ndarray
    acceleration: numpy.ndarray
    status: numpy.ndarray
    extra: tuple = ()

    def __len__(self) -> int:
        return len(self.phi)


NUMBER_ROWS = 16384      # numbers formatted at once (numpy's fixed cost a call shared)
LINE_ROWS = 4096         # lines joined at once (their matrices stay in the cache)


def as_columns(rows: list[tuple], vectorised: bool) -> list[tuple] | SweepColumns:
    """SweepColumns of a list of rows (phi, output, velocity, acceleration, status, extra ...),
    or the list itself where not `vectorised` or numpy is not installed."""
    if not vectorised:
        return rows
    try:
        np = numpy_module()
    except FastUnavailable:
        return rows
    codes = {s: i for i, s in enumerate(STATUS_CODES)}
    columns = [np.array([row[i] for row in rows], dtype=np.float64)      # None becomes NaN
               for i in range(len(rows[0])) if i != 4]
    status = np.array([codes[row[4]] for row in rows], dtype=np.int8)
    phi, output, velocity, acceleration = columns[:4]
    return SweepColumns(phi, output, velocity, acceleration, status, tuple(columns[4:]))


def _lines(np, outputs):
    """The lines of each output, (fields, keep), LINE_ROWS rows at a time: a list of bytes (one
    an output) and the number of rows. A field is a float64 array (its numbers as repr writes
    them, _float_texts, NUMBER_ROWS at a time; a column that several outputs share is formatted
    once) or a uint8 matrix (a text a row, NUL-padded); the fields of a row are joined by commas
    and ended by CR LF, and only the rows where `keep` (a bool array, or None: every row) are
    written. A line is a row of a byte matrix: its texts copied in as one void item a row each
    (a copy a text, not a byte), the commas and line ends written once."""
    count = len(outputs[0][0][0])
    for start in range(0, count, NUMBER_ROWS):
        stop = min(start + NUMBER_ROWS, count)
        fields = {id(field): field for fields, _ in outputs for field in fields}
        texts = {key: [field[start:stop]] if field.dtype == np.uint8
                 else _float_texts(np, field[start:stop]) for key, field in fields.items()}
        layouts = []                                       # each output's line matrix, texts
        for fields, keep in outputs:
            places, commas, at = [], [], 0
            for field in fields:
                for text in texts[id(field)]:
                    places.append((text, at, text.shape[1]))
                    at += text.shape[1]
                commas.append(at)
                at += 1
            matrix = np.empty((min(LINE_ROWS, stop - start), at + 1), np.uint8)
            matrix[:, commas[:-1]] = 44                    # written once: the texts' bytes
            matrix[:, at - 1] = 13                         # alone are copied a LINE_ROWS
            matrix[:, at] = 10                             # rows at a time
            layouts.append((matrix, places, keep))
        for first in range(start, stop, LINE_ROWS):
            last = min(first + LINE_ROWS, stop)
            rows, n = slice(first - start, last - start), last - first
            lines = []
            for matrix, places, keep in layouts:
                matrix = matrix[:n]
                for text, at, w in places:
                    matrix[:, at:at + w].view(f"V{w}")[:, 0] = text[rows].view(f"V{w}")[:, 0]
                if keep is not None and not keep[first:last].all():
                    matrix = matrix[keep[first:last]]
                lines.append(matrix.tobytes().translate(None, b"\0"))
            yield lines, n


# -- numbers as text, a block at once ------------------------------------------------------------
#
# repr writes a double as the shortest decimal that reads back as it (David Gay's dtoa, mode 0),
# the nearest to it where two are as short; positional from 1e-4 to 1e16. _float_texts does the
# same for a numpy block at once, exactly, where 1e-3 <= |x| < 1e13 (the other numbers, and the
# few cases it cannot decide, are repr's own). The argument, with ulp the spacing of doubles at x
# and m = 16 - floor(log10 |x|):
# - x 10^m = hi + lo exactly (Dekker's product: 10^m is a double for m <= 22), so d17, the
#   nearest integer to it (17 digits), and the residual f17 are exact; the nearest 16- and
#   15-digit decimals and their residuals follow from d17 and f17 (to 1e-14, so a comparison
#   within 1e-12 of its bound is left to repr).
# - a decimal reads back as x when it lies within ulp/2 of x (to even at exactly ulp/2: left to
#   repr, as is a power of two, whose interval is lopsided).
# - 15 digits are 4.5 ulp apart or more: at most one is within ulp/2, so if the nearest reads
#   back it is the only one of 15 digits or fewer (repr's, its trailing zeros dropped); else the
#   nearest of 16 digits if it reads back; else the nearest of 17, which always does (17 digits
#   are 0.9 ulp apart or less). Two nearest, equally near (16 or 17 digits, both may read back)
#   are left to repr, whose dtoa breaks such ties by rules of its own; at 15 digits, half a unit
#   is more than ulp/2 (0.11 units or less): neither reads back.
# tests/test_fast.py holds it against repr (hypothesis and the hard cases of each step).

_POW10 = tuple(10.0 ** k for k in range(23))      # exact doubles

@functools.cache
def _digit_tables(np: ModuleType) -> dict[str, Any]:
    """numpy's tables, made once: 10^k as doubles with Dekker's halves of each, and as uint64
    (to 10^19); the 10,000 four-digit texts as uint32, with leading zeros and without (NULs for
    them; then -0 to -999 so: 10,000 + i is "-i"); masks of the first k of 20 bytes and of the
    last k of 16, as uint32; "." and three NULs; three NULs and "-"."""
    pow10 = np.array(_POW10)
    big = pow10 * 134217729.0                     # 2^27 + 1
    high = big - (big - pow10)
    return dict(
        pow10=pow10, high=high, low=pow10 - high,
        pow10i=np.array([10 ** k for k in range(20)], dtype=np.uint64),
        quads=np.frombuffer(b"".join(b"%04d" % i for i in range(10_000)), dtype=np.uint32),
        leading=np.frombuffer(b"".join([b"%4d" % i for i in range(10_000)]
                                       + [b"%4s" % (b"-%d" % i) for i in range(1000)]
                                       + [b"    "] * 9000).replace(b" ", b"\0"), dtype=np.uint32),
        first=np.array([[255 * (c < k) for c in range(20)] for k in range(21)],
                       dtype=np.uint8).view(np.uint32),
        last=np.array([[255 * (c >= 16 - k) for c in range(16)] for k in range(17)],
                      dtype=np.uint8).view(np.uint32),
        point=np.frombuffer(b".\0\0\0", dtype=np.uint32)[0],
        minus=np.frombuffer(b"\0\0\0-", dtype=np.uint32)[0])


def _float_texts(np, x) -> list:
    """repr(float(v)) of each element of the float64 array x: uint8 matrices whose rows, joined
    across them and their NUL bytes dropped, are the texts."""
    t = _digit_tables(np)
    n = len(x)
    a = np.abs(x)
    fast = (a >= 1e-3) & (a < 1e13)                        # NaN is not
    np.copyto(a, 1.0, where=~fast)
    m = 16 - np.floor(np.log10(a)).astype(np.intp)
    scale = t["pow10"].take(m)
    hi = a * scale
    s = a * 134217729.0
    ah = s - (s - a)
    al = a - ah
    sh, sl = t["high"].take(m), t["low"].take(m)
    lo = ((ah * sh - hi) + ah * sl + al * sh) + al * sl    # hi + lo = x 10^m exactly
    r = np.rint(lo)
    f17 = lo - r
    d17 = hi.astype(np.int64) + r.astype(np.int64)
    bits = a.view(np.int64)
    half = (((bits >> 52) - 53) << 52).view(np.float64)   # ulp/2: a is normal, >= 2^-969
    q1 = d17 // 10
    t16 = (d17 - q1 * 10) + f17
    up16 = t16 > 5.0
    f16 = np.abs(t16 * 0.1 - up16)                         # residuals, in the last digit's units
    q2 = d17 // 100
    t15 = (d17 - q2 * 100) + f17
    up15 = t15 > 50.0
    f15 = np.abs(t15 * 0.01 - up15)
    h16 = half * t["pow10"].take(m - 1)                    # ulp/2 in the same units
    h15 = h16 * 0.1
    margin = 1e-12
    ok15 = f15 < h15 - margin
    ok16 = f16 < h16 - margin
    good = (fast & (d17 >= 10 ** 16) & (d17 < 10 ** 17) & ((bits & (1 << 52) - 1) != 0)
            & (t16 != 5.0) & (np.abs(f17) != 0.5)
            & (ok15 | (f15 > h15 + margin)) & (ok15 | ok16 | (f16 > h16 + margin)))
    digits = d17.copy()
    np.copyto(digits, q1 + up16, where=ok16)
    np.copyto(digits, q2 + up15, where=ok15)
    places = m - 2 * ok15 - (ok16 & ~ok15)                 # digits after the point
    zero = x == 0.0                                        # 0.0, -0.0
    good |= zero
    blank = ~good | zero
    if blank.any():
        np.copyto(digits, 0, where=blank)
        np.copyto(places, 1, where=blank)
    kept = places.copy()
    short = np.flatnonzero(ok15 & ~blank)                  # less their trailing zeros
    if len(short):
        rest, cut = digits[short], np.zeros(len(short), dtype=np.intp)
        for k in (8, 4, 2, 1):
            q = rest // 10 ** k
            ends = rest == q * 10 ** k
            np.copyto(rest, q, where=ends)
            cut += ends * k
        kept[short] = np.maximum(places[short] - cut, 1)
    np.copyto(a, 0.0, where=blank)
    whole = np.floor(a).astype(np.int64)                   # the decimal's whole part: no whole
    #                                                        number lies within ulp/2 of x
    width = int(places.max()) if n else 1
    fraction = ((digits.view(np.uint64) - whole.view(np.uint64) * t["pow10i"].take(places))
                * t["pow10i"].take(width - places))        # < 10^19: unsigned
    biggest = int(whole.max()) if n else 0
    lead = -(-len(str(biggest)) // 4)
    groups = -(-width // 4)
    text = np.empty((n, 2 + lead + groups), dtype=np.uint32)   # words of 4 bytes: NULs, "-";
    #                                           the whole part; "." and NULs; the fraction
    sign = np.signbit(x)
    text[:, lead + 1] = t["point"]
    start = 4 if biggest < 1000 else 3                     # the text's first byte
    if biggest < 1000:                                     # "  -7" with NULs for the spaces:
        np.add(whole, 10_000, out=whole, where=sign)       # the sign beside the digits
        text[:, 1] = t["leading"].take(whole)
    elif lead == 1:
        np.multiply(sign, t["minus"], out=text[:, 0], casting="unsafe")
        text[:, 1] = t["leading"].take(whole)              # "-", "7000"
    else:
        np.multiply(sign, t["minus"], out=text[:, 0], casting="unsafe")
        count = np.ones(n, dtype=np.intp)                  # the whole part's digits
        for k in range(1, 4 * lead):
            count += whole >= 10 ** k
        for j in range(lead, 0, -1):
            q = whole // 10_000
            text[:, j] = t["quads"].take(whole - q * 10_000)
            whole = q
        text[:, 1:lead + 1] &= t["last"].take(count, axis=0)[:, 4 - lead:]
    skip = 4 * groups - width                              # the first group's leading zeros
    kept += skip
    for g in range(groups - 1, -1, -1):                    # a group's bytes kept: a column of
        q = fraction // 10_000                             # masks taken (not rows of them)
        word = t["quads"].take(fraction - q * 10_000)
        word &= (t["first"][:, g] & ~t["first"][skip, g]).take(kept)
        text[:, lead + 2 + g] = word
        fraction = q
    text = text.view(np.uint8)
    head, tail = text[:, start:4 * lead + 5], text[:, 4 * lead + 8 + skip:]   # the bytes that can
    others = np.flatnonzero(~good)                                         # hold a character
    if len(others):                      # repr's own texts, split across head and tail (their
        #                                  NULs are dropped when joined)
        words = [repr(v).encode("ascii") for v in x[others].tolist()]
        cut = head.shape[1]
        width = max(cut + tail.shape[1], *map(len, words))
        if width > cut + tail.shape[1]:
            tail = np.concatenate([tail, np.zeros((n, width - cut - tail.shape[1]), np.uint8)], 1)
        matrix = np.array(words, dtype=f"S{width}").view(np.uint8).reshape(len(words), width)
        head[others], tail[others] = matrix[:, :cut], matrix[:, cut:]
    return [head, tail]


def column_texts(block: SweepColumns, fields: Sequence[int], clipped: Sequence[bool], zero: bool,
                 csv: bool) -> Iterator[tuple[list[bytes], int]]:
    """_block_texts of SweepColumns, formatted a block at once (the same bytes as a number at a
    time, _float_texts)."""
    np = numpy_module()
    phi = block.phi
    with np.errstate(all="ignore"):
        values = [c + 0.0 for c in block[1:4] + block.extra]  # -0.0 written as 0.0
    outputs = []
    for f, clipped_column in zip(fields, clipped):
        column = values[f - 1 if f < 4 else f - 2]
        if clipped_column:
            column = np.clip(column, -3.0, 3.0)
        if zero:
            outputs.append(((phi, np.where(np.isnan(column), 0.0, column)), None))
        else:
            outputs.append(((phi, column), ~np.isnan(column)))
    if csv:
        status = np.array(STATUS_CODES, dtype="S").take(block.status)
        unsigned = phi + 0.0 if ((phi == 0.0) & np.signbit(phi)).any() else phi   # the CSV's
        outputs.append(((unsigned, *values[:3], status.view(np.uint8).reshape(len(block), -1),
                         *values[3:]), None))
    with np.errstate(all="ignore"):
        yield from _lines(np, outputs)


# ---- 11. The numpy path: formulas traced once, replayed on arrays --------------------------------
#
# Holds: Term and Recipe, which record a formula's operations rather than do them, and Plan, the
# record made into numpy calls (plan_recipe) that run_plan replays on each block of arrays: the
# numpy forces' engine (the next section), a formula written once as plain arithmetic. numpy here
# too (the plan's calls), as in the numpy path's other rooms.
#
# Uses: nothing.
# Offers: Term, Recipe, Plan, plan_recipe, run_plan.


# -- the recipe ------------------------------------------------------------------------------------
#
# forces_of_arrays runs its formulas once a call on Terms, which record each operation rather
# than do it: a float stays a float (the constants fold, a term times 0.0 is 0.0 and drops out of
# its sum, x * 1.0 is x, x - (-y) is x + y), and an operation already recorded is not recorded
# again. plan_recipe makes the record into a Plan, which run_plan replays on each block of
# angles, each operation one numpy call into a buffer kept from block to block (reused once its
# value is no longer needed), the answers straight into the result's arrays: the work is the
# formulas' operations, no more.

class Term:
    """A number of the recipe: an array of the block, known only when the plan runs."""
    __slots__ = ("recipe", "index", "op", "args")

    def __init__(self, recipe: Recipe, index: int, op: str, args: tuple[Any, ...]) -> None:
        self.recipe, self.index, self.op, self.args = recipe, index, op, args

    def __add__(self, other: Any) -> Any:
        return self.recipe.add(self, other)

    __radd__ = __add__

    def __sub__(self, other: Any) -> Any:
        return self.recipe.subtract(self, other)

    def __rsub__(self, other: Any) -> Any:
        return self.recipe.subtract(other, self)

    def __mul__(self, other: Any) -> Any:
        return self.recipe.multiply(self, other)

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> Any:
        return self.recipe.divide(self, other)

    def __rtruediv__(self, other: Any) -> Any:
        return self.recipe.divide(other, self)

    def __neg__(self) -> Any:
        return self.recipe.multiply(self, -1.0)


class Recipe:
    """The operations on Terms in the order made (each one's arguments before it): term() records
    one (or finds it recorded), input() a number given to the plan; add, subtract, multiply,
    divide, sqrt and abs fold what is constant."""

    def __init__(self) -> None:
        self.terms: list[Term] = []
        self.seen: dict[tuple[Any, ...], Term] = {}

    def term(self, op: str, *args: Any) -> Term:
        key = (op,) + args          # a Term is itself (its identity), a float its value
        found = self.seen.get(key)
        if found is None:
            found = self.seen[key] = Term(self, len(self.terms), op, args)
            self.terms.append(found)
        return found

    def input(self) -> Term:
        self.terms.append(Term(self, len(self.terms), "input", ()))
        return self.terms[-1]

    def add(self, x: Any, y: Any) -> Any:
        if type(x) is not Term:
            x, y = y, x
        if type(y) is not Term:
            if x.op == "add" and type(x.args[1]) is not Term:      # (x + k) + h
                return self.add(x.args[0], x.args[1] + y)
            return x if y == 0.0 else self.term("add", x, float(y))
        (u, j), (v, k) = _scaled(x), _scaled(y)
        if u is v:                                                  # j u + k u
            return self.multiply(u, j + k)
        if y.op == "negative":
            return self.subtract(x, y.args[0])
        if x.op == "negative":
            return self.subtract(y, x.args[0])
        return self.term("add", *((x, y) if x.index < y.index else (y, x)))

    def subtract(self, x: Any, y: Any) -> Any:
        if type(y) is not Term:
            return self.add(x, -float(y))
        if type(x) is not Term:
            return self.multiply(y, -1.0) if x == 0.0 else self.term("subtract", float(x), y)
        (u, j), (v, k) = _scaled(x), _scaled(y)
        if u is v:
            return self.multiply(u, j - k)
        if y.op == "negative":
            return self.add(x, y.args[0])
        return self.term("subtract", x, y)

    def multiply(self, x: Any, y: Any) -> Any:
        if type(x) is not Term:
            x, y = y, x
        if type(y) is Term:
            return self.term("multiply", *((x, y) if x.index < y.index else (y, x)))
        if y == 0.0:
            return 0.0
        if y == 1.0:
            return x
        if x.op == "negative" or (x.op == "multiply" and type(x.args[1]) is not Term):
            return self.multiply(x.args[0], (-1.0 if x.op == "negative" else x.args[1]) * y)
        return self.term("negative", x) if y == -1.0 else self.term("multiply", x, float(y))

    def divide(self, x: Any, y: Any) -> Any:
        if type(y) is not Term:
            return self.multiply(x, 1.0 / y)
        if type(x) is not Term and x == 0.0:
            return 0.0
        return self.term("divide", x if type(x) is Term else float(x), y)

    def sqrt(self, x: Any) -> Any:
        return self.term("sqrt", x) if type(x) is Term else math.sqrt(x)

    def abs(self, x: Any) -> Any:
        return self.term("absolute", x) if type(x) is Term else abs(x)


def _scaled(x: Term) -> tuple[Term, float]:
    """x as (term, k) with x = k term: a constant's multiple, or x itself times 1."""
    if x.op == "negative":
        return x.args[0], -1.0
    if x.op == "multiply" and type(x.args[1]) is not Term:
        return x.args[0], x.args[1]
    return x, 1.0


class Plan(NamedTuple):
    """A recipe made into numpy calls: steps (ufunc, argument, argument or -1, result), each an
    index into registers (the inputs', the buffers', the results', the constants' places: the
    buffers' and those of inputs and results None, filled by each call)."""
    steps: tuple[tuple[Any, int, int, int], ...]
    registers: tuple[Any, ...]
    inputs: range
    results: range
    buffers: tuple[int, ...]


def plan_recipe(np: ModuleType, recipe: Recipe, inputs: Sequence[Term], results: Sequence[Term]
          ) -> Plan:
    """The steps that compute `results` (terms, each its own place) from `inputs`: only the
    operations they need, each value's buffer free for another once its last use has run."""
    terms = recipe.terms
    needed = [False] * len(terms)
    for term in results:
        needed[term.index] = True
    for term in reversed(terms):
        if needed[term.index]:
            for a in term.args:
                if type(a) is Term:
                    needed[a.index] = True
    order = [term for term in terms if needed[term.index] and term.op != "input"]
    last = [0] * len(terms)
    for i, term in enumerate(order):
        for a in term.args:
            if type(a) is Term:
                last[a.index] = i
    fixed = len(inputs) + len(results)
    place, owner = [-1] * len(terms), [-1] * len(terms)
    for i, term in enumerate(inputs):
        place[term.index] = i
    for i in reversed(range(len(results))):
        owner[results[i].index] = len(inputs) + i
    registers: list[Any] = [None] * fixed
    buffers: list[int] = []
    free: list[int] = []
    steps = []
    for i, term in enumerate(order):
        args = []
        for a in term.args:
            if type(a) is not Term:
                registers.append(a)
                args.append(len(registers) - 1)
                continue
            at = place[a.index]
            args.append(at)
            if last[a.index] == i and at >= fixed and at not in free:    # x * x: once
                free.append(at)
        if owner[term.index] >= 0:
            place[term.index] = owner[term.index]
        elif free:
            place[term.index] = free.pop()
        else:
            registers.append(None)
            buffers.append(len(registers) - 1)
            place[term.index] = buffers[-1]
        steps.append((getattr(np, term.op), args[0], args[1] if len(args) > 1 else -1,
                      place[term.index]))
    for i, term in enumerate(results):           # a result that is an input, or another's
        if place[term.index] != len(inputs) + i:
            steps.append((np.positive, place[term.index], -1, len(inputs) + i))
    return Plan(tuple(steps), tuple(registers), range(len(inputs)), range(len(inputs), fixed),
                 tuple(buffers))


def run_plan(plan: Plan, registers: list[Any]) -> None:
    """The plan's steps on registers (its own, with the inputs and the results in place)."""
    for ufunc, a, b, out in plan.steps:
        if b < 0:
            ufunc(registers[a], out=registers[out])
        else:
            ufunc(registers[a], registers[b], out=registers[out])


# ---- 12. The numpy path: forces on arrays --------------------------------------------------------
#
# Holds: the forces section's answer on numpy arrays, Linkage.forces_arrays' work: each body's
# wrench as forces() finds it, the reactions by elimination along the chain in closed form, a
# position near a dead centre handed to forces() itself, its formulas traced by section 11's
# Recipe and run beside the sweep, a block at a time. The numpy path's third room: numpy here
# too, and nowhere else but sections 10 and 11 (test_layout).
#
# Uses: sections 2, 6, 7, 9, 10 and 11.
# Offers: FORCES_STATUS_CODES, FORCES_HANDOFF, ReactionArrays, ForcesArrays, forces_of_arrays,
#   forces_arrays_of.


# -- the forces on arrays --------------------------------------------------------------------------
#
# Linkage.forces_arrays is forces() on a sweep_arrays answer: each body's wrench as forces() finds
# it (the same formulas, each body's frame as the forces section's notes give it), but the system
# solved by elimination along the chain, body by body, in closed form, rather than by Gaussian
# elimination on the whole (the same square system, so the same solution to rounding;
# tests/test_forces_numpy.py holds the two together). With R_B the force the coupler exerts on
# the output at its pin P, e = P - A:
#   the plane and skew kinds (_pin_reactions, "in closed form" below): the coupler's moments
#   about A fix R_B = mu e - W, W fixed by the coupler's motion; the output's moment about its
#   axis k through its pivot (a four-bar), or its force along the guide g (a slider), fixes mu,
#   divided by h . e, h = dP/d(output) = k x (P - B0) or g; then the coupler's Newton gives R_A,
#   the output's its ground reaction (force, and moment where it carries one), the crank's the
#   torque about z and A0's reaction.
#   The spherical four-bar (_spherical_arrays, "scalars times known arrays" below; moments
#   about O only): M_B, perpendicular to its axis b, is fixed by what the two other bodies ask:
#   a . M_A = 0 (M_A = T_1 + M_B, T_1 the coupler's wrench) and k . M_B0 = 0 (M_B0 = T_2 -
#   M_B), solved over b . (a x k); then M_A, M_B0, the torque and M_A0 as above.
# What _states measures that the linkage fixes, this takes from its dimensions (|e| = c, the
#   output's arm, the spherical coupler's a . b = cos c), and what is zero by the motion it leaves
#   out: a point of a body accelerates as its axes' second derivatives say (each a fixed
#   combination of its pins' accelerations), so spin x (spin x rho) is not formed; the
#   coupler's rate loses its term in e . (P' - A'), 0 for a rigid coupler; the skew coupler's
#   spin and rate are across its line, where its inertia is the transverse moment. The numbers
#   are forces()' to the last few places (1e-14 of each position's largest on the bench's).
# What it costs (bench forces): Linkage.forces_arrays (forces_arrays_of) runs a four-bar's forces
#   a block at a time as the sweep leaves it (motion_arrays_of's each_block: its arrays in the
#   cache, its free work arrays the plan's buffers; the slider-cranks' on their sweep made whole,
#   measured faster so); the formulas are traced once for a linkage, its bodies, effects and
#   branch (_forces_trace: 0.2 to 1.4 ms); each position takes 41 (slider), 57 (plane), 68 (skew
#   slider-crank), 87 (skew) and 109 (spherical) operations on arrays (the power among them),
#   0.2 to 0.3 ns an element in the cache, 0.5 to 0.8 where one writes an answer's row (blocks
#   of 16,384), then a sum a block of the power's and the shaking's rows (their finite check).
#   With the sweep, at 100,001 points, a rate of 0.50 to 0.53 of sweep_arrays' for the spherical
#   four-bar, 0.52 to 0.56 for the skew, 0.58 to 0.62 for the plane kinds and 0.57 to 0.60 for
#   the skew slider-crank under a load of 2.5 to 2.9 on 2 cores (main then: 0.46 to 0.49, 0.47
#   to 0.50; data/BENCHMARKS.md, 2026-11-28, round four, with where the operations go). Tried
#   and given up: constant factors carried through products to the sums, signs carried, like
#   terms gathered across nested sums by the recipe, blocks of 4,096 to 65,536, the finite
#   check as operations of the plan (7 a position; the block's sum reads the rows once).
# A position whose divisor is small beside its factors (|h . e| under FORCES_HANDOFF |h| |e|:
# near the output's dead centre, where forces() may find its system singular), whose numbers are
# not all finite, or whose motion is neither plainly assembled nor plainly not, is handed to
# forces() itself, which decides its status: the statuses are always the scalar form's.

FORCES_STATUS_CODES = STATUS_CODES + (UNBOUNDED, OUT_OF_RANGE)    # ForcesArrays.status
FORCES_HANDOFF = 1e-6       # handed to forces(): the elimination's divisor under this relative
_ZERO3, _EX, _EY, _EZ = (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)


class ReactionArrays(NamedTuple):
    """A joint's Reaction on arrays: force and moment of shape (n, 3), or None where the joint
    carries none (as Reaction)."""
    force: numpy.ndarray | None
    moment: numpy.ndarray | None


class ForcesArrays(NamedTuple):
    """Linkage.forces_arrays' answer: Forces' fields as numpy arrays, one element (or row) an
    input angle: torque and power float64 of shape (n,), each joint's ReactionArrays (none for
    no angle), the shaking force and moment of shape (n, 3), NaN where the forces are not known
    (status says why: int8 codes, indices into FORCES_STATUS_CODES, the sweep's STATUS_CODES
    then UNBOUNDED and OUT_OF_RANGE); speed_rpm the crank's speed they were computed at."""
    phi: numpy.ndarray
    torque: numpy.ndarray
    power: numpy.ndarray
    joints: dict[str, ReactionArrays]
    shaking_force: numpy.ndarray
    shaking_moment: numpy.ndarray
    status: numpy.ndarray
    speed_rpm: float

    def forces(self) -> list[Forces]:
        """The same answer as Linkage.forces gives it: a list of Forces, None where unknown."""
        def vector(a: Any, i: int) -> Vector | None:
            return None if a is None else cast(Vector, tuple(a[i].tolist()))
        out = []
        for i, (phi, torque, power, code) in enumerate(zip(
                self.phi.tolist(), self.torque.tolist(), self.power.tolist(),
                self.status.tolist())):
            status = FORCES_STATUS_CODES[code]
            if torque != torque:
                out.append(Forces(phi, None, None, None, None, None, status, self.speed_rpm))
                continue
            joints = {name: Reaction(vector(r.force, i), vector(r.moment, i))
                      for name, r in self.joints.items()}
            out.append(Forces(phi, torque, power, joints, vector(self.shaking_force, i),
                              vector(self.shaking_moment, i), status, self.speed_rpm))
        return out


# -- sums of known arrays --------------------------------------------------------------------------
#
# Every kind's formulas are written on numbers of the recipe, each a sum of known arrays (the
# sweep's cosines and sines, the output's rates and products of them) times constants, plus a
# constant: _Sum gathers like terms and folds the constants while tracing, and makes a sum one
# term (one array) only where it is needed whole (_Sum.term) or where a product needs it
# (_Sum.gathered, at the size that spares the next sum a multiplication).

class _Sum:
    """A number of the recipe: its terms times constants, plus a constant, like terms gathered
    while tracing. Each coefficient keeps the size of what made it up (the sum of its parts'
    sizes): one that rounding alone left (under 16 epsilons of that, as I22 - I11 - I00 of an arc)
    is 0."""
    __slots__ = ("recipe", "parts", "constant", "atoms")

    def __init__(self, recipe: Recipe, parts: dict[Term, tuple[float, float]],
                 constant: tuple[float, float] = (0.0, 0.0)) -> None:
        self.recipe = recipe            # (an inf or a NaN is kept: the finite check finds it)
        self.atoms: dict[float | None, _Sum] = {}
        self.parts = {t: km for t, km in parts.items() if not abs(km[0]) <= 3.6e-15 * km[1]
                      < math.inf}
        self.constant = (0.0, 0.0) if abs(constant[0]) <= 3.6e-15 * constant[1] < math.inf \
            else constant

    def __add__(self, other: Any) -> _Sum:
        if not isinstance(other, _Sum):
            if other == 0.0:
                return self
            other = _Sum(self.recipe, {}, (float(other), abs(other)))
        parts = dict(self.parts)
        for t, (k, m) in other.parts.items():
            parts[t] = (parts.get(t, (0.0, 0.0))[0] + k, parts.get(t, (0.0, 0.0))[1] + m)
        return _Sum(self.recipe, parts, (self.constant[0] + other.constant[0],
                                         self.constant[1] + other.constant[1]))

    __radd__ = __add__

    def __sub__(self, other: Any) -> _Sum:
        return self + other * -1.0

    def __rsub__(self, other: Any) -> _Sum:
        return self * -1.0 + other

    def __mul__(self, other: Any) -> _Sum:
        if not isinstance(other, _Sum):
            f = float(other)
            if f == 1.0 or not f:
                return self if f else _Sum(self.recipe, {})
            return _Sum(self.recipe, {t: (k * f, m * abs(f)) for t, (k, m) in self.parts.items()},
                        (self.constant[0] * f, self.constant[1] * abs(f)))
        x, y = (self.gathered(), other.gathered()) if len(self.parts) > 1 < len(other.parts) \
            else (self, other)                  # two sums each one term, lest they multiply out
        (xc, xm), (yc, ym) = x.constant, y.constant
        product = _Sum(self.recipe, {t: (k * yc, m * ym) for t, (k, m) in x.parts.items()},
                       (xc * yc, xm * ym)) + _Sum(self.recipe, {
                           u: (j * xc, n * xm) for u, (j, n) in y.parts.items()})
        for t, (k, m) in x.parts.items():
            product = product + _Sum(self.recipe, {self.recipe.multiply(t, u): (k * j, m * n)
                                                   for u, (j, n) in y.parts.items()})
        return product

    __rmul__ = __mul__

    def gathered(self, scale: float | None = None) -> _Sum:
        """self as one term times `scale` (None: its first largest coefficient, so that a sum
        recurring is the same term)."""
        if not self.parts or (scale is None and len(self.parts) == 1 and not self.constant[0]):
            return self
        if scale not in self.atoms:
            ks = [k for _, (k, _) in sorted(self.parts.items(), key=lambda p: p[0].index)]
            big = max(map(abs, ks))                     # the first of the largest
            k = scale or next((k for k in ks if abs(k) >= big * (1 - 4e-16)), ks[0])
            inner = _Sum(self.recipe, {t: (j / k, m / abs(k)) for t, (j, m) in self.parts.items()},
                         (self.constant[0] / k, self.constant[1] / abs(k))).term()
            self.atoms[scale] = _Sum(self.recipe, {inner: (k, abs(k))}) if type(inner) is Term \
                else _Sum(self.recipe, {}, (inner * k, abs(inner * k)))
        return self.atoms[scale]

    def size(self) -> float:
        """Its one term's coefficient (1 where it has none, or more than one)."""
        return next(iter(self.parts.values()))[0] if len(self.parts) == 1 else 1.0

    def term(self) -> Any:
        """The recipe's term (or a float) for the sum: the terms whose coefficients are of one
        size summed first (in the order made, the same sum wherever it recurs; where the size
        is 1, a - b rather than -(b - a)), then times it."""
        groups: dict[float, list[tuple[Term, float]]] = {}
        for t, (k, _) in sorted(self.parts.items(), key=lambda p: p[0].index):
            size = next((j for j in groups if abs(abs(k) / j - 1.0) < 1e-15), abs(k))
            groups.setdefault(1.0 if abs(size - 1.0) < 1e-15 else size, []).append((t, k))
        total: Any = 0.0
        for size, ts in groups.items():
            if size == 1.0:
                ts.sort(key=lambda p: p[1] < 0.0)
            sign, part = math.copysign(1.0, ts[0][1]), 0.0
            for t, k in ts:
                part = part + t * (sign * math.copysign(1.0, k))
            total = total + part * (sign * size)
        return total + self.constant[0] if type(total) is Term else self.constant[0]


def _term_of(x: Any) -> Any:
    """A _Sum's term (see _Sum.term), or x itself (a term or a number)."""
    return x.term() if isinstance(x, _Sum) else x


# -- what the sweep hands over ---------------------------------------------------------------------
#
# The four-bar's sweep solves its closure F = p cos psi + q sin psi + sv = 0 (p, q and sv fixed
# combinations of cos phi and sin phi: the linkage's constants), and on its way has root, the
# square root of its discriminant: F's derivative in psi is sign root (sign the branch's), and
# psi' = -F_phi / F_psi. The forces' divisor (a . (k x b) for the spherical, v . e for the skew
# and plane) is a constant times F_psi, so it is taken as that constant times sign root, an
# input of the plan, rather than made again from the cosines (4 to 6 operations a position);
# the spherical coupler's n_z, a constant times F_phi = -sign psi' root, as one product rather
# than 7. Each constant is found by evaluating the formula and F's derivatives at _PROBES, and
# kept only where the ratio is the same at all of them; the formula's own is traced elsewhere.

_PROBES = ((0.3, 1.1), (2.0, -0.7), (-1.3, 2.9), (0.9, 0.2))    # (phi, psi), radians


class _Sweep:
    """The sweep's closure for a four-bar's trace: its constants, the branch's sign, and the
    plan's inputs (the cosines and sines, psi', root) as terms of the recipe."""

    def __init__(self, recipe: Recipe, constants: tuple[float, ...], sign: float,
                 cos_sin: Sequence[Term], rate: Term, root: Term) -> None:
        self.recipe, self.constants, self.sign = recipe, constants, sign
        self.cos_sin, self.rate, self.root = cos_sin, rate, root

    def value(self, x: Any, phi: float, psi: float) -> float:
        """x (a term, a _Sum or a number) where phi and psi are these (psi', psi'' and root
        numbers of no meaning: a formula that is F's derivative uses none of them)."""
        given = dict(zip([t.index for t in self.cos_sin], (
            math.cos(phi), math.sin(phi), math.cos(psi), math.sin(psi))))
        values: dict[int, float] = {}

        def of(a: Any) -> float:
            if type(a) is not Term:
                return float(a)
            if a.index not in values:
                if a.op == "input":
                    values[a.index] = given.get(a.index, 0.37)
                else:
                    u, *v = [of(b) for b in a.args]
                    values[a.index] = {
                        "add": lambda: u + v[0], "subtract": lambda: u - v[0],
                        "multiply": lambda: u * v[0], "divide": lambda: u / v[0],
                        "negative": lambda: -u, "sqrt": lambda: math.sqrt(abs(u)),
                        "absolute": lambda: abs(u)}[a.op]()
            return values[a.index]
        if isinstance(x, _Sum):
            return sum(k * of(t) for t, (k, _) in x.parts.items()) + x.constant[0]
        return of(x)

    def partials(self, phi: float, psi: float) -> tuple[float, float]:
        """F's derivatives in psi and in phi there."""
        p0, pc, ps, q0, qc, qs, _, sc, ss = self.constants
        c, s, cq, sq = math.cos(phi), math.sin(phi), math.cos(psi), math.sin(psi)
        return (-(p0 + pc * c + ps * s) * sq + (q0 + qc * c + qs * s) * cq,
                (ps * c - pc * s) * cq + (qs * c - qc * s) * sq + ss * c - sc * s)

    def ratio(self, x: Any, which: int) -> float | None:
        """k where x is k times F's derivative in psi (which 0) or phi (1) at every probe."""
        ks = []
        for phi, psi in _PROBES:
            f = self.partials(phi, psi)[which]
            if abs(f) < 1e-3 * (sum(map(abs, self.constants)) or 1.0):
                return None
            ks.append(self.value(x, phi, psi) / f)
        k = ks[0]
        return k if k and all(abs(j - k) <= 1e-12 * abs(k) for j in ks) else None


# -- the plane and skew kinds in closed form -------------------------------------------------------
#
# Their wrenches are written out rather than built from their bodies' frames: the crank turns about
# z, the four-bar's output about its fixed axis k through B0 and the slider along its guide g, so
# each wrench is a fixed combination of a few arrays, the trace's constants folded in. The
# coupler's centre is at A + lam e + nu z x e (nu 0 for the skew kinds' rod, whose idle spin is
# left out: its spin and rate across e, e x e'' / c^2, where its inertia is the transverse moment;
# the plane coupler's inertia its moment about z), a fixed mix of its pins' accelerations, so its
# wrench about A is e x W, W = w_a A'' + w_b P'' + w_r z x A'' + w0. Its moments fix R_B = mu e -
# W, and the output's moment about k (mu (v . e) = k . T_2 / d + v . W, v = k x u, B = B0 + d u) or
# the slider's force along g (mu (g . e) = g . n2 + g . W) fixes mu; v . e = v . B0 - b G, G = v .
# (cos phi, sin phi, 0) (the same with g), so mu = c_g + ratio with no G in ratio's top, and mu e -
# W = mu P - b ratio (cos phi, sin phi, 0) - (the rest). The four-bar's output is taken along e1 =
# x, m = (0, cos ksi, sin ksi) and k (ksi = 0 in the plane), u = cos psi e1 + sin psi m; its rates
# turn^2 and turn' enter only as BX = turn^2 cos psi + turn' sin psi and Bm = turn' cos psi -
# turn^2 sin psi (B'' = d (-BX e1 + Bm m), its axes' second derivatives likewise). A sum of arrays'
# constant multiples is a _Sum, like terms gathered, made into operations once whole (_term_of).

def _times_plus(x: Term, y: Any, sign: float, z: Any) -> Any:
    """z + sign x y (z a _Sum or a number), z's own multiple of x taken into the factor: one
    product, not two (and k - y rather than -(y - k))."""
    if not isinstance(z, _Sum):
        z = _Sum(x.recipe, {}, (float(z), abs(z)))
    k = z.parts.get(x, (0.0, 0.0))[0]
    product = x * (y + k if sign > 0 else k - y)
    return product + _Sum(x.recipe, {t: km for t, km in z.parts.items() if t is not x},
                          z.constant).term()


def _pin_reactions(recipe: Recipe, setup: ForcesSetup, inputs: Sequence[Term],
                   sweep: _Sweep | None) -> tuple[Any, dict[str, tuple[Vec3 | None,
                                                                      Vec3 | None]], Vec3,
                                                     Vec3, Any, float]:
    """The plane and skew kinds' torque, joints' reactions, shaking force and moment, and the
    elimination's divisor with the size it is measured against (see the notes above), from the
    inputs: the cosine and sine of phi, then the four-bar's cosine
    and sine of psi and psi itself, or the slider's x; the output's first and second
    derivatives."""
    kind, slider = setup.linkage.kind, setup.linkage.is_slider
    plane = PINS[kind].coupler == "plane"
    c, s, *output, q1, q2 = inputs
    dims, w, al, g = setup.dims, setup.omega, setup.alpha, setup.gravity
    (m0, rho0, i0), (m1, rho1, i1), (m2, rho2, i2) = setup.masses
    b, length = dims["b"], abs(dims["c"])
    sb = math.copysign(1.0, b)
    if w:                               # the output's turn^2 = scale s2, turn' = scale rate
        scale, s2, rate = w * w, q1 * q1, q2 + q1 * (al / (w * w))
    else:
        scale, s2, rate = al, 0.0, q1

    def known(t: Term) -> _Sum:
        return _Sum(recipe, {t: (1.0, 1.0)})

    def in_frame(v: Vec3, axes: tuple[Vec3, Vec3, Vec3]) -> Vec3:
        """A vector given by its components along `axes`, in the frame's."""
        return weighted_sum(*zip(v, axes))

    cs, ss, rates = known(c), known(s), known(rate)
    hat_c, hat_s = (cs, ss, 0.0), (ss * -1.0, cs, 0.0)                    # (cos phi, sin phi, 0)
    a2 = weighted_sum((-b * w * w, hat_c), (b * al, hat_s))                   # A''
    # the crank: x = sb hat_c, y = sb hat_s; its wrench about A0 (the rate of its momenta less gravity's moment)
    rx, ry, rz = rho0
    p, q, r = i0[0][2] - m0 * rx * rz, i0[1][2] - m0 * ry * rz, i0[2][2] + m0 * (rx * rx + ry * ry)
    n0 = weighted_sum((m0 * sb * (-w * w * rx - al * ry), hat_c),
                      (m0 * sb * (al * rx - w * w * ry), hat_s), (-m0, g))
    t0 = weighted_sum((sb * (al * p - w * w * q), hat_c), (sb * (al * q + w * w * p), hat_s),
                      (al * r, _EZ), (-m0, cross(weighted_sum(
                          (sb * rx, hat_c), (sb * ry, hat_s), (rz, _EZ)), g)))
    # the coupler: its centre at A + lam e + nu z x e (nu: the plane kinds'), its wrench about A
    # is e x W, W = w_a A'' + w_b P'' + w_r z x A'' + w0, P the output's pin
    lam, nu = rho1[0] / length, rho1[1] / length
    spin = (i1[2][2] if plane else (i1[1][1] + i1[2][2]) / 2.0) / (length * length)
    w_a, w_b = m1 * (lam * (1.0 - lam) - nu * nu) - spin, m1 * (lam * lam + nu * nu) + spin
    w_r, c_g = -nu * m1, w_a * w * w - nu * m1 * al       # c_g: W's part in -b hat_c
    at = weighted_sum((1.0 / length, setup.coupler_point or _ZERO3))
    w0 = weighted_sum((-lam * m1, g), (nu * m1, cross(_EZ, g)), (-at[0], setup.coupler_force),
                      (at[1], cross(_EZ, setup.coupler_force)))
    # the output: its pin P, P'', its force n2 and moment t2 (about its frame's origin); the
    # elimination's mu (v . e) = k . t2 / d + v . W (four-bar), mu (g . e) = g . n2 + g . W
    # (slider, g the guide), each v . e = v . P0 - b v . hat_c (P0 the pin less its motion
    # along v), so that mu = c_g + ratio, ratio = (the rest) / (v . e)
    if slider:
        (x,), guide = output, setup.axes["guide"][1]
        xs, gg = known(x), dot(guide, guide)
        start = PINS[kind].output_pin(dims, None, None, 0.0)[0]              # C at x = 0
        pin = weighted_sum((1.0, start), (xs, guide))
        p2 = weighted_sum((rates * scale, guide))
        n2 = weighted_sum((m2, p2), (-m2, g), (-setup.output_force, guide))
        across = _EY if kind == PLANE_SLIDER_CRANK else _EX
        centre = weighted_sum(*zip(rho2, (guide, across, cross(guide, across))))
        t2 = cross(weighted_sum((m2, p2), (-m2, g)), weighted_sum((-1.0, centre)))
        divisor = _term_of(xs * gg + dot(guide, start) - dot(hat_c, guide) * b)    # g . e
        top = (dot(n2, guide) + dot(hat_s, guide) * (b * (w_a * al - w_r * w * w))
               + rates * (w_b * scale * gg) + xs * (-c_g * gg)
               + (dot(guide, w0) - c_g * dot(guide, start)))
        size = length
    else:
        d, sd = dims["d"], math.copysign(1.0, dims["d"])
        e1, k, b0 = _EX, setup.axes["output"][1], setup.ground["B0"]
        m = (0.0, dims["cos ksi"], dims["sin ksi"]) if "ksi" in dims else _EY   # the plane's
        plane_axes = (e1, m, k)         # the output's axes: its vectors' components along them
        cq, sq = output[:2]
        cqs, sqs = known(cq), known(sq)
        bx, bm = known(s2 * cq + rate * sq), known(rate * cq - s2 * sq)
        u, v = (cqs, sqs, 0.0), (sqs * -1.0, cqs, 0.0)                      # along e1, m, k
        u2, v2 = (bx * -1.0, bm, 0.0), (bm * -1.0, bx * -1.0, 0.0)           # u'', v'' / scale
        pin = weighted_sum((1.0, b0), (d, in_frame(u, plane_axes)))                     # B
        p2 = in_frame(weighted_sum((d * scale, u2)), plane_axes)                       # B''
        rx, ry, rz = rho2               # x = sd u, y = sd v, z = k; about B0, along e1, m, k
        p, q, r = (i2[0][2] - m2 * rx * rz, i2[1][2] - m2 * ry * rz,
                   i2[2][2] + m2 * (rx * rx + ry * ry))
        n2 = weighted_sum((1.0, in_frame(weighted_sum((m2 * sd * scale * rx, u2), (
            m2 * sd * scale * ry, v2)), plane_axes)), (-m2, g))
        t2 = weighted_sum((-sd * scale * p, v2), (sd * scale * q, u2), (scale * r, (
            0.0, 0.0, rates)), (-m2, cross(weighted_sum((sd * rx, u), (sd * ry, v), (
                rz, _EZ)), (dot(g, e1), dot(g, m), dot(g, k)))), (-setup.output_torque, _EZ))
        h = known(cq * _term_of(dot(hat_s, m)) - sq * _term_of(dot(hat_s, e1)))   # v . hat_s
        divisor = cq * _term_of(dot(hat_c, m) - dot(m, b0) / b) - sq * _term_of(
            dot(hat_c, e1) - dot(e1, b0) / b)                                 # v . e / -b
        top = t2[2] * (-1.0 / (b * d)) + (
            h * (b * (w_a * al - w_r * w * w)) + rates * (w_b * d * scale)
            + cqs * (dot(m, w0) - c_g * dot(m, b0)) + sqs * (c_g * dot(e1, b0) - dot(e1, w0))
        ) * (-1.0 / b)
        size = length / abs(b)
        if sweep is not None and (f := sweep.ratio(divisor, 0)) is not None:
            divisor, top, size = sweep.root, top * (1.0 / (f * sweep.sign)), size / abs(f)
    ratio = _term_of(top) / divisor
    mu = ratio + c_g
    # R_B = mu e - W = mu P - b ratio hat_c - (W's other terms)
    rest = weighted_sum((b * (w_a * al - w_r * w * w), hat_s), (w_b, p2), (1.0, w0))
    n1 = weighted_sum((m1 * (1.0 - lam), a2), (m1 * lam, p2), (-nu * m1, cross(weighted_sum(
        (1.0, p2), (-1.0, a2)), _EZ)), (-m1, g), (-1.0, setup.coupler_force))   # z x (P'' - A'')
    where = [_term_of(pin[i]) for i in range(3)]
    big = ratio * b
    r_b = [mu * where[i] - big * _term_of(hat_c[i]) - _term_of(rest[i]) for i in range(3)]
    r_a = [r_b[i] + _term_of(n1[i]) for i in range(3)]
    r_a0 = [r_a[i] + _term_of(n0[i]) for i in range(3)]
    r_g = [_term_of(n2[i]) - r_b[i] for i in range(3)]
    if slider:                          # the guide's moment at C: the slider's about C; its
        m_g = cast(Vec3, tuple(_term_of(t2[i]) for i in range(3)))            # force along
        centred = cast(Vec3, tuple(where))                                     # it: 0
        r_g = [0.0 if abs(guide[i]) == 1.0 else r_g[i] for i in range(3)]
    else:                               # B0's: t2 - d u x R_B, along e1 and m (along k: 0)
        along = sum((r_b[i] * (d * k[i]) for i in range(3) if k[i]), 0.0)      # d k . R_B
        m_g = weighted_sum((_times_plus(sq, along, -1.0, t2[0]), e1),
                           (_times_plus(cq, along, 1.0, t2[1]), m))
        centred = b0
    arm = r_a[2] * b                                                          # A x R_A
    torque = (c * r_a[1] - s * r_a[0]) * b + _term_of(t0[2])
    m_a0 = (_times_plus(s, arm, 1.0, t0[0]), _times_plus(c, arm, -1.0, t0[1]), 0.0)
    v_a0 = (m_a0[0], m_a0[1], torque)
    crossed = cross(cast(Vec3, tuple(r_g)), centred)
    shaking_force = cast(Vec3, tuple((0.0 - r_a0[i]) - r_g[i] for i in range(3)))  # 0, not -0
    shaking_moment = cast(Vec3, tuple(crossed[i] - m_g[i] - v_a0[i] for i in range(3)))
    joints: dict[str, tuple[Vec3 | None, Vec3 | None]] = {
        "A0": (cast(Vec3, tuple(r_a0)), None if plane else m_a0),
        "A": (cast(Vec3, tuple(r_a)), None),
        PINS[kind].output_joint: (cast(Vec3, tuple(r_b)), None),
        "guide" if slider else "B0": (cast(Vec3, tuple(r_g)), m_g if slider or not plane else None)}
    return torque, joints, shaking_force, shaking_moment, recipe.abs(divisor), size


# -- the spherical four-bar: scalars times known arrays --------------------------------------------
#
# Every body of the spherical four-bar turns about O, and only moments about O enter, so its
# formulas are written here as scalars, each a sum of known arrays (the sweep's cosines and sines,
# psi', psi'' and products of them) times constants, a _Sum (above): like terms gathered and the
# constants folded while tracing, a sum made one term (one array) only where a product needs it,
# at the size that spares the next sum a multiplication. A body's moment about O is I spin' +
# spin x I spin in its own axes, I its inertia about O (constant there), less gravity's moment
# and the loads'. The crank's and the output's spins are their speeds about their axes; the
# coupler's (spin = w z + l a, turning about a = OA on the crank) has (spin . a, w y_z, w n_z) on
# its axes a, y, n (y = (b - cos c a) / |sin c|, n = a x y), spin . a = (psi' w Q + cos c w
# (b_z - cos b cos c)) / sin^2 c with Q = k . a - cos d cos c (a' and b' in spin_about_centre),
# and its rate's the same differentiated (the axes turn with it). Its moment's quadratic in
# (spin . a, w y_z) is factored (one product). The elimination: M_B = m1 y2 + m2 (|sin d| k -
# cos d x2) on the output's axes x2, y2 = k x x2, k, fixed by k . M_B = k . T_2 and a . M_B =
# -a . T_1 (the divisor D = a . (k x b)); M_A = T_1 + M_B across a, turned from the coupler's
# y, n onto the crank's u1 = (-sin phi, cos phi, 0), u2 = a x u1 (by the angle of cosine n_z and
# sine y_z over sin b); M_B0 = T_2 - M_B about the output's axes; the shaking moment
# -(M_A0 + torque z + M_B0) = -(T_0 + T_1 + T_2), its force the bodies' m (g - a_G) and the loads.
# The divisor D and n_z are the sweep's (_Sweep: D a constant times root, n_z times psi' root).
# 109 operations, the power among them (282 before round three, 125 before round four: data/
# BENCHMARKS.md): what the notes above gave up for the other kinds (factors carried, like terms
# gathered) pays here.

def _spherical_arrays(recipe: Recipe, setup: ForcesSetup, cos_sin: tuple[Any, ...], q1: Any,
                      q2: Any, sweep: _Sweep) -> tuple[Any, dict[str, tuple[Vec3 | None,
                                                                         Vec3 | None]], Vec3,
                                                        Vec3, Any, float]:
    """The spherical four-bar's answer as _pin_reactions gives the others' (see the notes
    above), from the cosines and sines of phi and psi, psi' and psi'' (and what the sweep hands
    over)."""
    dims, w, al = setup.dims, setup.omega, setup.alpha
    c, s, cq, sq, v1, v2 = (_Sum(recipe, {t: (1.0, 1.0)}) for t in (*cos_sin, q1, q2))
    cb, sb, cd, sd, ca, sa = (dims[f"{f} {n}"] for n in "bda" for f in ("cos", "sin"))
    cc, sc = cos_sin_degrees(dims["c"])
    (m0, m1, m2), g, sc_, sd_ = setup.masses, setup.gravity, abs(sc), abs(sd)

    def vec(*parts: tuple[Any, Vec3]) -> Any:
        return weighted_sum(*parts)

    def euler(mass: BodyMass, spin: Any, rate: Any) -> Any:
        """I spin' + spin x I spin in the body's axes, I its inertia about O (its origin)."""
        rr = dot(mass.centre, mass.centre)
        inertia = [cast(Vec3, tuple(mass.inertia[i][j] + mass.mass * (
            rr * (i == j) - mass.centre[i] * mass.centre[j]) for j in range(3)))
            for i in range(3)]
        gyroscopic = cross(spin, cast(Vec3, [dot(row, spin) for row in inertia]))
        return [dot(row, rate) + gyroscopic[i] for i, row in enumerate(inertia)]

    def world(v: Any) -> Vec3:
        """A vector about the output's axes turned back by a about y (k its z), in the fixed
        axes: each component made one term first."""
        return rotated_y(ca, sa, cast(Vec3, [x.gathered() if isinstance(x, _Sum) else x
                                             for x in v]))

    def factored(z: _Sum, u: _Sum, u_sum: _Sum, v: _Sum) -> _Sum:
        """z with its terms in u^2, u v and v^2 (u, v each one term, u_sum what u is made of)
        as one product, a (u - r1 v)(u - r2 v), where that quadratic has two real roots."""
        if len(u.parts) != 1 or len(v.parts) != 1 or u.constant[0] or v.constant[0]:
            return z
        (ut, (uk, _)), (vt, (vk, _)) = *u.parts.items(), *v.parts.items()
        keys = (recipe.multiply(ut, ut), recipe.multiply(ut, vt), recipe.multiply(vt, vt))
        a, b, c = (z.parts.get(key, (0.0, 0.0))[0] / f for key, f in zip(
            keys, (uk * uk, uk * vk, vk * vk)))
        if not a or b * b <= 4.0 * a * c:
            return z
        h = -0.5 * (b + math.copysign(math.sqrt(b * b - 4.0 * a * c), b))
        rest = _Sum(recipe, {t: km for t, km in z.parts.items() if t not in keys}, z.constant)
        return rest + (u_sum - v * (h / a)) * (u_sum - v * (c / h)) * a

    t, rate = v1 * w, v2 * (w * w) + v1 * al          # the output's speed psi' w and its rate
    a, k = vec((sb, (c, s, 0.0)), (1.0, (0.0, 0.0, cb))), setup.axes["output"][1]
    # the output's axes about k (turned back by a about y: k = z), and b = B / r
    x2, y2 = vec((math.copysign(1.0, sd), (cq, sq, 0.0))), vec((math.copysign(1.0, sd), (
        -1.0 * sq, cq, 0.0)))
    b = rotated_y(ca, sa, b_ := vec((cd, _EZ), (sd_, x2)))
    x0 = vec((math.copysign(1.0, sb), (c, s, 0.0)))    # the crank's axes: x0, z x x0, z
    crank_axes = (x0, cross(_EZ, x0), _EZ)
    rho0 = weighted_sum(*zip(m0.centre, crank_axes))
    t0 = weighted_sum(*zip(euler(m0, (0.0, 0.0, w), (0.0, 0.0, al)), crank_axes),
                      (-m0.mass, cross(rho0, g)))
    a_g0 = weighted_sum((-w * w, (rho0[0], rho0[1], 0.0)), (al, cross(_EZ, rho0)))
    rho2 = weighted_sum(*zip(m2.centre, (x2, y2, _EZ)))
    t2 = weighted_sum(*zip(euler(m2, (0.0, 0.0, t), (0.0, 0.0, rate)), (x2, y2, _EZ)),
                      (-m2.mass, cross(rho2, rotated_y(ca, -sa, g))), (-setup.output_torque, _EZ))
    a_g2 = weighted_sum((-1.0 * (t * t), vec((m2.centre[0], x2), (m2.centre[1], y2))),
                        (1.0, cross(vec((rate, _EZ)), rho2)))
    # the coupler: axes a, y, n, spin (spin . a, w y_z, w n_z)
    y = vec((1.0 / sc_, b), (-cc / sc_, a))
    n = cross(a, y)
    y = (y[0], y[1], y[2].gathered())
    if (f := sweep.ratio(n[2], 1)) is not None:        # n_z = f F_phi = -f sign psi' root
        n = (n[0], n[1], _Sum(recipe, {recipe.multiply(q1, sweep.root): (
            -f * sweep.sign, abs(f))}))
    n = (n[0], n[1], n[2].gathered(y[2].size()))       # at y_z's size
    q = (a[0] * sa + cb * ca - cd * cc).gathered()      # k . a - cos d cos c
    spin_a_sum = (t * q + y[2] * (cc * sc_ * w)) * (1.0 / (sc * sc))
    spin_a = spin_a_sum.gathered()
    relative = spin_a - w * cb                          # l: its spin about a on the crank
    spin_a_rate = ((rate * q + y[2] * (al * cc * sc_) + t * (w * sa) * (b[1] * cc - a[1])
                   .gathered()) * (1.0 / (sc * sc))).gathered()
    spin = (spin_a, y[2] * w, n[2] * w)
    spin_rate = (spin_a_rate, y[2] * al + relative * n[2] * w, n[2] * al - relative * y[2] * w)
    t1 = [x - z for x, z in zip(euler(m1, spin, spin_rate), cross(m1.centre, cast(Vec3, [
        dot(weighted_sum((m1.mass, g)), axis) for axis in (a, y, n)])))]
    at_a, at_b = m1.centre[0] - m1.centre[1] * cc / sc_, m1.centre[1] / sc_   # its centre
    a_g1 = weighted_sum((at_a, ((-w * w) * a[0] - al * a[1], (-w * w) * a[1] + al * a[0], 0.0)))
    if m1.centre[2]:                                    # + w n: n'' on its axes
        a_g1 = weighted_sum((1.0, a_g1), (m1.centre[2], weighted_sum(*zip((
            spin_rate[1] + spin[0] * spin[2], spin[1] * spin[2] - spin_rate[0],
            -1.0 * (spin[0] * spin[0]) - spin[1] * spin[1]), (a, y, n)))))
    loads = weighted_sum((m0.mass + m1.mass + m2.mass, g))
    if setup.coupler_point is not None:
        t1 = [x - z for x, z in zip(t1, cross(setup.coupler_point, cast(Vec3, [
            dot(setup.coupler_force, axis) for axis in (a, y, n)])))]
        loads = weighted_sum((1.0, loads), (1.0, setup.coupler_force))
    b2 = weighted_sum((t * t, difference(vec((cd, _EZ)), b_)), (1.0, cross(vec((rate, _EZ)), b_)))
    shaking_force = weighted_sum((-m0.mass, a_g0), (-m1.mass, a_g1), (1.0, loads), (1.0, world(
        weighted_sum((-m1.mass * at_b, b2), (-m2.mass, a_g2)))))
    # the elimination, each sum at the size that spares the next a multiplication
    divisor = dot(a, cross(k, b)).gathered()            # D, as d D'
    if (f := sweep.ratio(divisor, 0)) is not None:      # f F_psi = f sign root
        divisor = _Sum(recipe, {sweep.root: (f * sweep.sign, abs(f))})
    d = divisor.size()
    d_term = (divisor * (1.0 / d)).term()
    inverse = _Sum(recipe, {recipe.divide(1.0, d_term): (1.0 / d, 1.0 / abs(d))})
    t1[2] = factored(t1[2], spin_a, spin_a_sum, y[2])
    moment_a = t1[0].gathered()
    b1_size = -sd_ * moment_a.size() / d                # m1's, and m2's at it
    moment_k = t2[2].gathered(-sd_ * b1_size / cd if cd else None)
    m_b1 = ((moment_a * sd_ + moment_k * q * (1.0 / sd_)).gathered(sd_ * moment_a.size())
            * inverse * -1.0)
    m_b_ = [x.gathered() for x in weighted_sum((m_b1, y2), (moment_k * (-cd / sd_), x2))[:2]]
    m_b0, m_b = world((t2[0] - m_b_[0], t2[1] - m_b_[1], 0.0)), world((*m_b_, moment_k))
    size = sb / y[2].size()             # M_A . y and M_A . n at the size that makes M_A's x and y
    on_y = (t1[1] + t1[0] * (cc / sc_)).gathered(size)        # two products' sum each
    on_n = (t1[2] - (moment_a * q + moment_k * (sc * sc)).gathered() * inverse
          * (1.0 / sc_)).gathered(size)
    on_u1 = ((on_y * n[2] - on_n * y[2]) * (1.0 / sb)).gathered(-1.0)     # M_A . u1, M_A . u2
    on_u2 = ((on_y * y[2] + on_n * n[2]) * (1.0 / sb)).gathered(-1.0 / cb if cb else None)
    m_a = weighted_sum((on_u1, (-1.0 * s, c, 0.0)), (on_u2, (c * -cb, s * -cb, sb)))
    v = weighted_sum((1.0, t0), (1.0, m_a))
    terms = [_term_of(x) for x in (v[2], *m_a, *m_b, *m_b0, v[0], v[1], *shaking_force)]
    joints: dict[str, tuple[Vec3 | None, Vec3 | None]] = {
        "A0": (None, (terms[10], terms[11], 0.0)), "A": (None, tuple(terms[1:4])),
        "B": (None, tuple(terms[4:7])), "B0": (None, tuple(terms[7:10]))}
    moment = tuple(-1.0 * (x + y) for x, y in zip((terms[10], terms[11], terms[0]), terms[7:10]))
    return (terms[0], joints, tuple(terms[12:15]), cast(Vec3, moment), recipe.abs(d_term),
            1.0 / abs(d))


class _ForcesTrace(NamedTuple):
    """What forces_of_arrays records once for a linkage, its bodies and effects: the plan; the
    answer's rows (the torque, near, the power, the shaking force's three and its moment's, then
    each joint's force and moment where it carries one), each a constant or None where the plan
    computes it (its results in the rows' order); the joints, each with whether it carries a
    force and a moment; near's least to stay (FORCES_HANDOFF times the divisor's factors), and
    the plan's input that is near where one is (the sweep's root: its row then left unmade),
    else -1; the rows of the power and the shaking that the plan makes, as runs (first, end);
    the crank's speed in rpm."""
    plan: Plan
    rows: tuple[float | None, ...]
    joints: tuple[tuple[str, bool, bool], ...]
    handoff: float
    near: int
    checked: tuple[tuple[int, int], ...]
    speed_rpm: float


@functools.lru_cache(maxsize=16)
def _forces_trace(linkage: Closure, bodies: Bodies, effects: Effects, radius: float,
                  branch: int) -> _ForcesTrace:
    """The formulas traced for forces_of_arrays: the same for every call with these (a linkage
    object's dimensions are fixed once it is made; the branch gives the sweep's root its sign),
    so kept; the plan holds no array of a call.
    Tracing took 0.2 to 0.7 ms a call for the plane and skew kinds, 1.4 ms for the spherical
    (bench forces' linkages, bodies and effects, best of 30 by CPU: 4 to 15% of the forces' time
    at 100,001 angles)."""
    setup = forces_setup(linkage, bodies, effects, radius)
    recipe = Recipe()
    inputs = [recipe.input() for _ in range(5 if linkage.is_slider else 8)]
    sweep = None if linkage.is_slider else _Sweep(
        recipe, linkage.constants, 1.0 if branch == 1 else -1.0, inputs[:4], inputs[5], inputs[7])
    if sweep is not None and linkage.kind == SPHERICAL_FOUR_BAR:
        t, reactions, force, moment, apart, size = _spherical_arrays(
            recipe, setup, tuple(inputs[:4]), inputs[5], inputs[6], sweep)
    else:
        t, reactions, force, moment, apart, size = _pin_reactions(recipe, setup, inputs[:7],
                                                                  sweep)
    near = -1           # |root| is root: compared as it is, the plan's input
    if type(apart) is Term and apart.op == "absolute" and apart.args[0] in inputs:
        near, apart = inputs.index(apart.args[0]), 0.0
    values = [t, apart, t * setup.omega, *force, *moment] + [x for pair in reactions.values()
                                           for v in pair if v is not None for x in v]
    plan = plan_recipe(numpy_module(), recipe, inputs, [v for v in values if type(v) is Term])
    made = [i for i in range(2, 9) if type(values[i]) is Term]
    runs = tuple((i, j + 1) for i, j in zip([i for i in made if i - 1 not in made],
                                            [j for j in made if j + 1 not in made]))
    handoff = FORCES_HANDOFF * size if all(
        math.isfinite(v) for v in values[2:9] if type(v) is not Term) else math.inf
    return _ForcesTrace(plan, tuple(None if type(v) is Term else float(v) for v in values),
                        tuple((name, f is not None, m is not None)
                              for name, (f, m) in reactions.items()),
                        handoff, near, runs, setup.speed_rpm)


class _Answer:
    """A forces_of_arrays answer in the making: the answer's arrays (one allocation: freed
    whole, it is the allocator's to reuse at the next call; in parts, glibc gave them back to
    the system and faulted in new pages, 16 MB of them a call, as much again as the forces'
    work: python3 linkage.py bench forces), its constant rows filled, the plan's buffers kept
    from block to block (each its own: freed and made again a call at a time, the allocator's
    reuse, where one block of them all would be new pages, 3.5 MB, each call)."""

    def __init__(self, np: ModuleType, trace: _ForcesTrace, count: int) -> None:
        self.np, self.trace, self.plan = np, trace, trace.plan
        self.whole = np.empty((len(trace.rows), count))
        for i, value in enumerate(trace.rows):
            if value is not None and i != 1:        # near's row: the plan's, or not used
                self.whole[i].fill(value)
        self.unsure = np.empty(count, dtype=bool)       # near's, or a number not finite
        self.results = [i for i, value in enumerate(trace.rows) if value is None]
        self.registers = list(self.plan.registers)
        self.block = min(FAST_BLOCK, max(count, 1))
        for at in self.plan.buffers:
            self.registers[at] = np.empty(self.block)

    def run(self, start: int, sources: Sequence[Any], spare: Sequence[Any] = (),
            whole: Any = None, unsure: Any = None) -> None:
        """The plan on one block (its first index, then the plan's inputs for it): its columns
        of the answer and of unsure (`whole` and `unsure`, if not the answer's own); spare:
        arrays of the block's length for its buffers, if enough. Unsure: near under the
        trace's handoff (or NaN), or a number not finite: every number the elimination makes
        reaches the power and the shaking (an inf or a NaN carries through + and x; the torque
        through the moment's z, less it), so all are finite where those seven are (their sum
        over the block is finite where all are)."""
        np, plan, registers, n = self.np, self.plan, self.registers, len(sources[0])
        whole = self.whole if whole is None else whole
        unsure = self.unsure[start:start + n] if unsure is None else unsure
        if len(spare) >= len(plan.buffers):
            registers = list(registers)
            for at, array in zip(plan.buffers, spare):
                registers[at] = array
        elif n != self.block:                   # a shorter block, the last
            registers = [r[:n] if i in plan.buffers else r for i, r in enumerate(registers)]
        for i, source in zip(plan.inputs, sources):
            registers[i] = source
        for i, row in zip(plan.results, self.results):
            registers[i] = whole[row, start:start + n]
        with np.errstate(all="ignore"):
            run_plan(plan, registers)
            near = whole[1, start:start + n] if self.trace.near < 0 else sources[self.trace.near]
            np.logical_not(np.greater_equal(near, self.trace.handoff, out=unsure), out=unsure)
            for first, end in self.trace.checked:      # the power's and the shaking's
                checked = whole[first:end, start:start + n]
                if not math.isfinite(np.add.reduce(checked, axis=None)):
                    unsure |= ~np.isfinite(checked).all(axis=0)

    def run_at(self, where: Any, sources: Sequence[Any]) -> None:
        """The plan at the points `where` (indices; sources the plan's inputs there), in blocks
        of the answer's."""
        np = self.np
        for start in range(0, len(where), self.block):
            at = where[start:start + self.block]
            part, unsure = np.empty((len(self.whole), len(at))), np.empty(len(at), dtype=bool)
            part[:] = self.whole[:, :1]                 # the constant rows (the rest made)
            self.run(0, [source[start:start + len(at)] for source in sources], whole=part,
                     unsure=unsure)
            self.whole[:, at], self.unsure[at] = part, unsure

    def finished(self, linkage: Closure, arrays: MotionArrays, branch: int, bodies: Bodies,
                 effects: Effects, radius: float) -> ForcesArrays:
        """The answer, each position that is not plainly assembled, or near the output's dead
        centre, or whose numbers are not all finite, handed to forces() (see the notes above)."""
        np, trace, whole = self.np, self.trace, self.whole
        count = whole.shape[1]
        torque, power = whole[0], whole[2]
        shaking = whole[3:9].reshape(2, 3, count)
        parts = iter(range(9, len(whole), 3))
        joints = {name: ReactionArrays(*(whole[(i := next(parts)):i + 3] if kept else None
                                         for kept in pair)) for name, *pair in trace.joints}
        plain, assembled = arrays.status, STATUS_CODES.index(ASSEMBLED)
        unknown = plain != assembled
        redo = (unknown | self.unsure) & (plain != STATUS_CODES.index(NOT_ASSEMBLED))
        status = plain.copy()
        if unknown.any():
            torque[unknown] = power[unknown] = math.nan
            for r in [shaking] + [v for r in joints.values() for v in r if v is not None]:
                r[..., unknown] = math.nan
        where = np.flatnonzero(redo)
        if len(where):
            for i, f in zip(where.tolist(), forces(linkage, arrays.phi[where].tolist(), branch,
                                                     bodies, effects, radius=radius)):
                status[i] = FORCES_STATUS_CODES.index(f.status)
                torque[i] = math.nan if f.torque is None else f.torque
                power[i] = math.nan if f.power is None else f.power
                for name, arrays_of in joints.items():
                    reaction = f.joints[name] if f.joints is not None else Reaction(None, None)
                    for v, column in zip(reaction, arrays_of):
                        if column is not None:
                            column[:, i] = math.nan if v is None else v
                for v, r in zip((f.shaking_force, f.shaking_moment), shaking):
                    r[:, i] = math.nan if v is None else v
        return ForcesArrays(arrays.phi, torque, power,
                            {name: ReactionArrays(*(None if v is None else v.T for v in r))
                             for name, r in joints.items()}, shaking[0].T, shaking[1].T, status,
                            trace.speed_rpm)


def _kept_trace(linkage: Closure, bodies: Bodies, effects: Effects, radius: float,
                branch: int) -> _ForcesTrace:
    """_forces_trace's, kept where bodies and effects can be (not where one holds a list)."""
    try:
        hash((bodies, effects, radius))
    except TypeError:                   # a body's or an effect's list: not to be kept
        return _forces_trace.__wrapped__(linkage, bodies, effects, radius, branch)
    return _forces_trace(linkage, bodies, effects, radius, branch)


def _roots(np: ModuleType, linkage: Closure, branch: int, cos_sin: Sequence[Any]) -> Any:
    """The sweep's root where its cosines and sines are these (a four-bar's; see _Sweep): sign
    F_psi, F = p cos psi + q sin psi + sv, as the sweep's own to rounding."""
    p0, pc, ps, q0, qc, qs, *_ = linkage.constants
    c, s, cq, sq = cos_sin
    return ((q0 + qc * c + qs * s) * cq - (p0 + pc * c + ps * s) * sq) * (
        1.0 if branch == 1 else -1.0)


def forces_of_arrays(linkage: Closure, arrays: MotionArrays, branch: int = 1,
                     bodies: Bodies = Bodies(), effects: Effects = Effects(), *,
                     radius: float = 1.0, trig: dict[str, Any] | None = None) -> ForcesArrays:
    """forces() on a MotionArrays of `branch` with velocity and acceleration (Linkage.sweep_arrays'
    answer): a ForcesArrays (see Linkage.forces_arrays). trig: the sweep's cosines and sines
    (motion_arrays_of's), computed here where not given."""
    np = numpy_module()
    trace = _kept_trace(linkage, bodies, effects, radius, branch)
    if arrays.velocity is None or arrays.acceleration is None:
        raise ValueError("the forces need the sweep's velocity and acceleration (derivatives 2)")
    trig = dict(trig or {})
    keys = (("phi", arrays.phi), ("output", arrays.output))[:1 if linkage.is_slider else 2]
    for key, angles in keys:
        if key not in trig:
            trig[key] = cos_sin_degrees_array(np, angles)
            continue
        stale = np.flatnonzero(np.isnan(trig[key][0]))    # handed to the scalar sweep
        stale = stale[~np.isnan(angles[stale])]
        if len(stale):
            trig[key][0][stale], trig[key][1][stale] = cos_sin_degrees_array(np, angles[stale])
    sources = [trig[key][j] for key, _ in keys for j in (0, 1)] + [
        arrays.output, arrays.velocity, arrays.acceleration]
    if not linkage.is_slider:
        with np.errstate(invalid="ignore"):
            sources.append(_roots(np, linkage, branch, sources[:4]))
    answer = _Answer(np, trace, len(arrays.phi))
    for start in range(0, len(arrays.phi), answer.block):
        answer.run(start, [source[start:start + answer.block] for source in sources])
    return answer.finished(linkage, arrays, branch, bodies, effects, radius)


def forces_arrays_of(linkage: Closure, phis: Sequence[float] | numpy.ndarray, branch: int,
                     bodies: Bodies, effects: Effects, radius: float) -> ForcesArrays:
    """Linkage.forces_arrays: the sweep (motion_arrays_of) and the four-bar's forces together,
    each block of the forces computed as the sweep leaves it, its arrays still in the cache
    (rather than the sweep's cosines and sines kept whole and read again); the points the sweep
    hands to its scalar engine computed after it, as forces_of_arrays computes them. A
    slider-crank's sweep is made whole first (forces_of_arrays): beside it, the skew
    slider-crank's forces measured at 0.55-0.61 of the sweep's rate, so at 0.61-0.64 (bench
    forces, load 2.5-3.6)."""
    if linkage.is_slider:
        trig: dict[str, Any] = {}
        return forces_of_arrays(linkage, motion_arrays_of(linkage, phis, branch, 2, trig),
                                branch, bodies, effects, radius=radius, trig=trig)
    np = numpy_module()
    trace = _kept_trace(linkage, bodies, effects, radius, branch)
    handed: list[Any] = []
    answer: _Answer | None = None

    def each_block(start: int, count: int, sources: list[Any], again: Any, spare: list[Any]
                   ) -> None:
        nonlocal answer
        if answer is None:
            answer = _Answer(np, trace, count)
        answer.run(start, sources, spare)
        if again.any():
            handed.append(np.flatnonzero(again) + start)

    arrays = motion_arrays_of(linkage, phis, branch, 2, each_block=each_block)
    if answer is None:                  # no angles
        answer = _Answer(np, trace, len(arrays.phi))
    where = np.concatenate(handed) if handed else np.empty(0, dtype=np.intp)
    where = where[arrays.status[where] == STATUS_CODES.index(ASSEMBLED)]
    if len(where):
        assert arrays.velocity is not None and arrays.acceleration is not None
        angles = [arrays.phi[where]] + ([] if linkage.is_slider else [arrays.output[where]])
        cos_sin = [x for a in angles for x in cos_sin_degrees_array(np, a)]
        answer.run_at(where, cos_sin + [arrays.output[where], arrays.velocity[where],
                                         arrays.acceleration[where]] + (
            [] if linkage.is_slider else [_roots(np, linkage, branch, cos_sin)]))
    return answer.finished(linkage, arrays, branch, bodies, effects, radius)


# ---- 13. Simulation: the equation of motion in its coordinates -----------------------------------
#
# The linkage has one degree of freedom; in a coordinate q (an angle, radians) every point moves
# with X'(q) q_dot, and Lagrange's equation is
#
#   J(q) q_ddot + 1/2 J'(q) q_dot^2 = Q(q, q_dot, t),   J = sum m |G'|^2 + I theta'^2,
#
# J the reduced inertia, with the same bodies (and frames) as forces(): reduced() sums each body's
# centre velocity G' and angular rate theta' per unit q_dot, and their derivatives by q, by the
# chain rule from the pins' exact derivatives and the engine's psi' and psi''. The torque
# forces() finds is affine in the crank's acceleration and quadratic in its speed, T(phi, omega,
# alpha) = J alpha + 1/2 J' omega^2 - Q_gravity, so forces() at alpha = 1 gives J, at a speed
# gives J', and under gravity alone gives Q_gravity: tests/test_simulate.py holds reduced() to it
# (two forces() calls an evaluation would cost 3.5 to 7 times as much). The other generalised
# forces come by virtual work, each force times its point's (each torque times its body's
# angle's) derivative by q: the driver's torque on the crank (a given torque, or a motor line
# T_stall (1 - omega / omega_free)), the output's torque or the slider's force, a force at a
# coupler point, linear springs between two named points (Spring: the joints A0, A, B, B0, C or a
# point of the frame (x, y)) and torsional springs and dampers at a pivot (Torsion: A0 about the
# crank's angle, B0 about the output's).
#
# The coordinate: the crank's angle phi, except near a dead centre of the input (the crank stops
# and turns back: psi' = d psi / d phi is infinite there, and J with it). There the plane four-bar
# is solved as its inverse, the four-bar with input and output swapped: the plane turned half a
# turn about the frame line's middle maps A0 to B0, its input angle is psi + 180 degrees and its
# output phi + 180, gravity and the coupler's frame turned with it; its crank is the output body.
# The other kinds are solved in their output's coordinate (psi, or the slider's x) as they are:
# the crank's angle and its derivatives by it from the engine's closure solved the other way
# round (Closure.input_angle), the bodies, gravity and loads unchanged. The run changes to the
# other coordinate after a step whose end has |d other / d q| > 2, so the new coordinate's is
# under 1/2 and the change cannot flap. At each evaluation the output (or phi) is the root
# nearest the prediction (output, velocity) from the step's start by Taylor, so that at a change
# point the motion keeps to the branch it follows (as sweep's "follow"), never jumping: the
# branches cross there with different velocities.
#
# Every step costs six evaluations (the last stage's is the next step's first), so the cost is the
# evaluation's: the plane kinds' come in scalars (_four_bar_found, _slider_found: the closure solved
# once for both branches by a copy of the engine's formulas, the pins from its cos and sin, and
# _plane_sums, which reduced() uses too) unless a spring or coupler force asks for the pins as
# points; near the discriminant's zero, at a start and in the slider's x they are the general
# path's (tests/test_simulate.py holds the two to each other). bench simulate's 600 s run-up: 5 to
# 7 CPU seconds on a loaded machine, where the general path took 18 to 21 (data/BENCHMARKS.md).
#
# All five kinds, SI units as the forces section's (the spherical four-bar on a sphere of
# `radius` metres).
#
# Uses: sections 2, 6, 7 and 9.
# Offers: SimPose, SimView, SimPoint, SimModel, views_of, root_near, Reduced, reduced,
#   mean_reduced_inertia, gravity_vector, state_at.


class SimPose(NamedTuple):
    """A position a view found at q: its closure's input angle phi (degrees) and output (degrees,
    or the slider's x), the derivatives by q of the closure's crank angle (radians) and of its
    output (radians, or length), and the other coordinate (radians, or x) with its derivatives."""
    phi: float
    output: float
    crank1: float
    crank2: float
    out1: float
    out2: float
    other: float
    other1: float
    other2: float


class SimView(NamedTuple):
    """The linkage as the run solves it in one coordinate q: its closure, bodies (and the spatial
    kinds' BodyMass), how its frame maps to the linkage's, and how it finds a position."""
    closure: Closure
    bodies: Bodies
    swapped: bool               # q is not the crank's angle: the inverse four-bar's input
    #                             (psi + shift), or the plane slider's x (shift 0)
    shift: float
    gravity: Vector
    names: dict[str, str]       # the linkage's joint names as this view's
    frame: Callable[[Sequence[float]], Vector]     # a point of the linkage's frame in the view's
    ground: dict[str, Vector]   # the view's fixed joints
    axes: dict[str, tuple[Vector, Vector]]         # the view's shafts and guide
    dims: dict[str, float]      # pin_dimensions of the closure's
    radius: float               # the spherical four-bar's sphere (m), else 1
    masses: tuple[BodyMass, BodyMass, BodyMass] | None     # the spatial kinds'
    solve: Callable[[float, int], SimPose | None]    # the position at q on the label 1 or 2
    other_angle: bool           # the other coordinate is an angle (unwrapped by 2 pi)
    ratio: float                # q's scale over the other's: |other'| ratio over 2 changes them
    scale: float                # q's scale (1 rad, or the crank's length), the tolerance's unit


class SimPoint(NamedTuple):
    """The state at one instant in a view: q, q_dot, the other coordinate (radians unwrapped, or
    the slider's x) and its derivatives by q, its label, J, q_ddot, the energy and the power of
    the non-conservative forces."""
    q: float
    rate: float
    other: float
    other1: float
    other2: float
    label: int
    inertia: float
    acceleration: float
    energy: float
    power: float


class SimModel(NamedTuple):
    """What a run keeps fixed: the linkage, its views (coordinates), the driver and the loads."""
    linkage: Closure
    views: tuple[SimView, ...]
    driver: Driver
    springs: tuple[Spring, ...]
    torsions: tuple[Torsion, ...]
    output_torque: float
    output_force: float
    coupler_force: tuple[tuple[float, float], Vector] | None


def _engine_solver(closure: Closure) -> Callable[[float, int], SimPose | None]:
    """A view's positions from the engine: q the closure's input angle (radians)."""
    def solve(q: float, label: int) -> SimPose | None:
        m = closure.motion(q * DEG, label)
        if m.status not in (ASSEMBLED, CHANGE_POINT) or m.output is None:
            return None
        assert m.velocity is not None and m.acceleration is not None
        y = m.output if closure.is_slider else m.output * RAD
        return SimPose(m.phi, m.output, 1.0, 0.0, m.velocity, m.acceleration, y, m.velocity,
                     m.acceleration)
    return solve


def _output_solver(closure: Closure) -> Callable[[float, int], SimPose | None]:
    """A view's positions in the output's coordinate q (psi in radians, or the slider's x): the
    crank's angle by the closure solved the other way round (Closure.input_angle)."""
    def solve(q: float, label: int) -> SimPose | None:
        found = closure.input_angle(q, label)
        if found is None:
            return None
        phi, phi1, phi2 = found
        return SimPose(phi * DEG, q if closure.is_slider else q * DEG, phi1, phi2, 1.0, 0.0, phi,
                     phi1, phi2)
    return solve


def views_of(linkage: Closure, bodies: Bodies, gravity: Vector, radius: float = 1.0
           ) -> tuple[SimView, ...]:
    """The linkage in its crank's angle, and in its output's coordinate: (plane four-bar) as its
    inverse turned half a turn, (the other kinds) in psi or the slider's x (_output_solver)."""
    same = {n: n for n in ("A0", "A", "B", "B0", "C")}
    kind = linkage.kind
    plane = kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK)
    ground = joint_positions(linkage, 0.0)
    joints = {n: cast(Vector, tuple(radius * x for x in p)) for n, p in ground.joints.items()}
    scale = abs(linkage.dims["b"]) if linkage.is_slider else 1.0
    own = SimView(linkage, bodies, False, 0.0, gravity, same,
                (lambda p: (float(p[0]), float(p[1]), 0.0)) if plane else
                (lambda p: (float(p[0]), float(p[1]), float(p[2]))),
                joints, ground.axes, pin_dimensions(linkage.dims), radius,
                None if plane else body_masses(linkage, bodies, radius),
                _engine_solver(linkage), not linkage.is_slider, 1.0 / scale, 1.0)
    if kind != PLANE_FOUR_BAR:
        return own, own._replace(swapped=True, solve=_output_solver(linkage), other_angle=True,
                                 ratio=scale, scale=scale)
    a, b, c, d = (linkage.dims[n] for n in "abcd")
    coupler = bodies.coupler
    if coupler.centre is not None:
        u, v = cast(Sequence[float], coupler.centre)
        coupler = coupler._replace(centre=(abs(c) - u, -v))
    turned = (-gravity[0], -gravity[1], gravity[2])
    closure = Closure(PLANE_FOUR_BAR, a=a, b=d, c=c, d=b)
    inverse = own._replace(
        closure=closure, bodies=Bodies(bodies.output, coupler, bodies.crank), swapped=True,
        shift=math.pi, gravity=turned, names={"A0": "B0", "B0": "A0", "A": "B", "B": "A"},
        frame=lambda p: (a - float(p[0]), -float(p[1]), 0.0),
        ground=joint_positions(closure, 0.0).joints, dims=pin_dimensions(closure.dims),
        solve=_engine_solver(closure))
    return own, inverse


def root_near(view: SimView, q: float, near: tuple[float, float, float, float] | None,
          label: int) -> tuple[SimPose, int] | None:
    """The position at q on the branch the motion follows: the root nearest the prediction from
    near = (q0, other, other', other'') (None: the label `label`); with the other coordinate
    unwrapped, and its label. None where the linkage does not assemble (or its output is free)."""
    best = None
    for branch in (1, 2):
        if near is None and branch != label:
            continue
        pose = view.solve(q, branch)
        if pose is None:
            continue
        if near is None:
            return pose, branch
        q0, y0, v0, a0 = near
        h = q - q0
        guess, slope = y0 + h * v0 + 0.5 * h * h * a0, v0 + h * a0
        if view.other_angle:
            pose = pose._replace(other=guess + math.remainder(pose.other - guess, 2.0 * math.pi))
        misfit = abs(pose.other - guess) + abs(h) * abs(pose.other1 - slope)
        if best is None or misfit < best[0]:
            best = (misfit, pose, branch)
    return None if best is None else best[1:]


class Reduced(NamedTuple):
    """The linkage's dynamics reduced to its input angle phi (radians): the reduced inertia J
    (kg m^2; the kinetic energy is 1/2 J phi_dot^2), dJ/dphi, gravity's generalised force
    Q = -dV/dphi (N m) and potential V (J)."""
    inertia: float
    slope: float
    gravity_force: float
    potential: float


def reduced(linkage: Closure, phi: float, branch: int = 1, bodies: Bodies = Bodies(),
            gravity: float | Sequence[float] | None = None, *, radius: float = 1.0
            ) -> Reduced | None:
    """J, dJ/dphi, gravity's generalised force and potential at input angle phi (degrees) on
    the listing's `branch` (see the section's notes; bodies, gravity and the spherical
    four-bar's radius as forces'; at a change point the branch's limits); None where there is
    no velocity (no position, a dead centre)."""
    return _reduced_along(linkage, [phi], branch, bodies, gravity, radius)[0]


def _reduced_along(linkage: Closure, phis: Iterable[float], branch: int, bodies: Bodies,
                   gravity: float | Sequence[float] | None, radius: float
                   ) -> list[Reduced | None]:
    """reduced() at each of phis, the bodies checked and the view made once."""
    forces(linkage, [], branch, bodies, Effects(gravity=gravity), radius=radius)   # its errors
    view = views_of(linkage, bodies, gravity_vector(gravity, linkage.kind), radius)[0]
    found: list[Reduced | None] = []
    for phi in phis:
        m = linkage.motion(phi, branch)
        if m.velocity is None or m.acceleration is None or m.output is None:
            found.append(None)
            continue
        pose = SimPose(m.phi, m.output, 1.0, 0.0, m.velocity, m.acceleration, 0.0, 0.0, 0.0)
        found.append(_reduced_at(view, pose, *_pins(view, pose)))
    return found


def mean_reduced_inertia(linkage: Closure, phis: Sequence[float], branch: int = 1,
                         bodies: Bodies = Bodies(), *, radius: float = 1.0) -> float | None:
    """The reduced inertia J averaged over the input angles phis (degrees, increasing; the
    trapezoid rule in phi), None where any has none (a dead centre) or phis are fewer than two.
    forces_summary's flywheel_inertia, ΔE_max / (cs omega^2), is the whole inertia at the crank
    that holds the speed: the linkage's own J carries this much of it, and a flywheel of the
    rest holds it to within about cs/2 of cs (tests/test_simulate.py measures it so)."""
    values = _reduced_along(linkage, phis, branch, bodies, None, radius)
    if len(values) < 2 or any(v is None for v in values) or phis[-1] <= phis[0]:
        return None
    inertia = [cast(Reduced, v).inertia for v in values]
    area = sum((inertia[i] + inertia[i + 1]) * (phis[i + 1] - phis[i])
               for i in range(len(phis) - 1))
    return 0.5 * area / (phis[-1] - phis[0])


def gravity_vector(gravity: float | Sequence[float] | None, kind: str) -> Vector:
    """Gravity as forces() takes it: a number g along -y (plane kinds) or -z (spatial)."""
    plane = kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK)
    if gravity is None:
        return (0.0, 0.0, 0.0)
    if isinstance(gravity, (int, float)):
        g = checked_number(gravity, "gravity")
        return (0.0, -g, 0.0) if plane else (0.0, 0.0, -g)
    v = checked_numbers(gravity, 3, "gravity (gx, gy, gz)")
    if plane and v[2]:
        raise ValueError("the plane kinds are simulated in their plane: gravity must have no z "
                         "component")
    return v[0], v[1], v[2]


_Path: TypeAlias = tuple[Vector, Vector, Vector]       # a point and its derivatives by q


def _pins(view: SimView, pose: SimPose) -> tuple[_Path, _Path]:
    """The crank pin A and the output pin (B, or the slider C) with their derivatives by q."""
    closure, dims, r = view.closure, view.dims, view.radius
    a = PINS[closure.kind].crank_pin(dims, *cos_sin_degrees(pose.phi))
    p = output_pin_at(closure, dims, pose.output, cos_sin_degrees)
    k1, k2, o1, o2 = pose.crank1, pose.crank2, pose.out1, pose.out2
    return ((weighted_sum((r, a[0])), weighted_sum((r * k1, a[1])), weighted_sum((r * k1 * k1, a[2]), (r * k2, a[1]))),
            (weighted_sum((r, p[0])), weighted_sum((r * o1, p[1])), weighted_sum((r * o1 * o1, p[2]), (r * o2, p[1]))))


def _reduced_at(view: SimView, pose: SimPose, a: _Path, p: _Path) -> Reduced:
    """Reduced at the position `pose` with pins a and p in `view`, by the kind's table."""
    return _REDUCERS[view.closure.kind](view, pose, a, p)


def _plane_reduced(view: SimView, pose: SimPose, a: _Path, p: _Path) -> Reduced:
    """The plane kinds' Reduced from the pins' paths (_plane_sums)."""
    return _plane_sums(view, a[0][0], a[0][1], a[1][0], a[1][1], a[2][0], a[2][1], p[0][0],
                       p[0][1], p[1][0], p[1][1], p[2][0], p[2][1], pose.crank1, pose.crank2,
                       pose.out1, pose.out2)


def _plane_sums(view: SimView, ax: float, ay: float, ax1: float, ay1: float, ax2: float,
                ay2: float, px: float, py: float, px1: float, py1: float, px2: float, py2: float,
                k1: float, k2: float, o1: float, o2: float) -> Reduced:
    """The plane kinds' Reduced from the crank pin A (ax, ay), the output pin P (B, or the slider
    C) and their first (1) and second (2) derivatives by q, with the crank's angle's (k1, k2) and
    the output's (o1, o2): each body's centre and angle, and their first and second derivatives
    by q, by the chain rule (a body of a mass only is a uniform rod, as forces' bodies; the
    plane's inertia about z). In scalars: every evaluation of the run comes here."""
    gx, gy = view.gravity[0], view.gravity[1]
    crank, coupler, output = view.bodies
    length = math.sqrt(ax * ax + ay * ay)           # the crank: its centre r / |A| along A
    r, moment = _mass_of(crank, length)
    f, m = r / length, crank.mass
    inertia = m * f * f * (ax1 * ax1 + ay1 * ay1) + moment * k1 * k1
    slope = 2.0 * (m * f * f * (ax1 * ax2 + ay1 * ay2) + moment * k1 * k2)
    force = m * f * (gx * ax1 + gy * ay1)
    potential = -m * f * (gx * ax + gy * ay)
    lx, ly, lx1, ly1 = px - ax, py - ay, px1 - ax1, py1 - ay1     # the coupler, A to P
    span = lx * lx + ly * ly
    root = math.sqrt(span)
    ex, ey = lx / root, ly / root                   # e along it, n = (-ey, ex)
    w1 = (lx * ly1 - ly * lx1) / span               # its angle's derivatives
    w2 = (lx * (py2 - ay2) - ly * (px2 - ax2)) / span
    if coupler.centre is None:
        u, v, moment = 0.5 * root, 0.0, coupler.mass * span / 12.0
    else:
        u, v = cast(Sequence[float], coupler.centre)
        moment = float(cast(float, coupler.inertia))
    ox, oy = u * ex - v * ey, u * ey + v * ex       # u e + v n, and its derivative by the angle
    sx, sy = -oy, ox
    cx1, cy1 = ax1 + w1 * sx, ay1 + w1 * sy
    cx2, cy2 = ax2 + w2 * sx - w1 * w1 * ox, ay2 + w2 * sy - w1 * w1 * oy
    m = coupler.mass
    inertia += m * (cx1 * cx1 + cy1 * cy1) + moment * w1 * w1
    slope += 2.0 * (m * (cx1 * cx2 + cy1 * cy2) + moment * w1 * w2)
    force += m * (gx * cx1 + gy * cy1)
    potential -= m * (gx * (ax + ox) + gy * (ay + oy))
    m = output.mass
    if view.closure.is_slider:                      # the slider: its centre offset along x
        inertia += m * (px1 * px1 + py1 * py1)
        slope += 2.0 * m * (px1 * px2 + py1 * py2)
        force += m * (gx * px1 + gy * py1)
        potential -= m * (gx * (px + float(cast(float, output.centre or 0.0))) + gy * py)
    else:                                           # the output crank about B0
        bx, by = view.ground["B0"][0], view.ground["B0"][1]
        length = math.sqrt((px - bx) ** 2 + (py - by) ** 2)
        r, moment = _mass_of(output, length)
        f = r / length
        inertia += m * f * f * (px1 * px1 + py1 * py1) + moment * o1 * o1
        slope += 2.0 * (m * f * f * (px1 * px2 + py1 * py2) + moment * o1 * o2)
        force += m * f * (gx * px1 + gy * py1)
        potential -= m * (gx * (bx + f * (px - bx)) + gy * (by + f * (py - by)))
    return Reduced(inertia, slope, force, potential)


def _spatial_reduced(view: SimView, pose: SimPose, a: _Path, p: _Path) -> Reduced:
    """The spatial kinds' Reduced: each body in forces' frame (see section 10's notes), its
    origin's path, its angular velocity per unit q_dot w' and that's derivative w'', its centre
    G = origin + rho: J = sum m |G'|^2 + w'.I w' and J' = 2 sum (m G'.G'' + w''.I w') (the
    inertia I turning with the body adds w'.(w' x I w' - I (w' x w')) = 0)."""
    g = view.gravity
    crank, coupler, output = cast(tuple[BodyMass, BodyMass, BodyMass], view.masses)
    totals = [0.0, 0.0, 0.0, 0.0]
    nought = (0.0, 0.0, 0.0)

    def body(mass: BodyMass, axes: Sequence[Vector], origin: _Path, w1: Vector, w2: Vector
             ) -> None:
        rho = weighted_sum(*zip(mass.centre, axes))
        g1 = weighted_sum((1.0, origin[1]), (1.0, cross(w1, rho)))
        g2 = weighted_sum((1.0, origin[2]), (1.0, cross(w2, rho)), (1.0, cross(w1, cross(w1, rho))))
        local = (dot(axes[0], w1), dot(axes[1], w1), dot(axes[2], w1))
        iw1 = weighted_sum(*zip((dot(row, local) for row in mass.inertia), axes))
        totals[0] += mass.mass * dot(g1, g1) + dot(w1, iw1)
        totals[1] += 2.0 * (mass.mass * dot(g1, g2) + dot(w2, iw1))
        totals[2] += mass.mass * dot(g, g1)
        totals[3] -= mass.mass * dot(g, weighted_sum((1.0, origin[0]), (1.0, rho)))

    z = (0.0, 0.0, 1.0)
    x = unit_vector((a[0][0], a[0][1], 0.0))
    body(crank, (x, cross(z, x), z), (nought, nought, nought), (0.0, 0.0, pose.crank1),
         (0.0, 0.0, pose.crank2))
    if PINS[view.closure.kind].coupler == "sphere":
        w1 = spin_about_centre(a[0], p[0], a[1], p[1])
        w2 = spin_about_centre(a[0], p[0], difference(a[2], cross(w1, a[1])),
                               difference(p[2], cross(w1, p[1])))
        x, normal = unit_vector(a[0]), unit_vector(cross(a[0], p[0]))
        body(coupler, (x, cross(normal, x), normal), (nought, nought, nought), w1, w2)
    else:                   # a line: no spin about it, and |AB| fixed, so AB . (B' - A') = 0
        ab = difference(p[0], a[0])
        span = dot(ab, ab)
        w1 = weighted_sum((1.0 / span, cross(ab, difference(p[1], a[1]))))
        w2 = weighted_sum((1.0 / span, cross(ab, difference(p[2], a[2]))))
        x = unit_vector(ab)
        least = min(range(3), key=lambda i: abs(x[i]))
        y = unit_vector(cross(x, ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), z)[least]))
        body(coupler, (x, y, cross(x, y)), a, w1, w2)
    if view.closure.is_slider:
        guide = view.axes["guide"][1]
        side = (1.0, 0.0, 0.0)
        body(output, (guide, side, cross(guide, side)), p, nought, nought)
    else:
        k = view.axes["output"][1]
        pivot = view.ground.get("B0", nought) if view.closure.kind == SKEW_FOUR_BAR else nought
        arm = difference(p[0], pivot)
        x = unit_vector(weighted_sum((1.0, arm), (-dot(arm, k), k)))
        body(output, (x, cross(k, x), k), (pivot, nought, nought), weighted_sum((pose.out1, k)),
             weighted_sum((pose.out2, k)))
    return Reduced(*totals)


_REDUCERS: dict[str, Callable[[SimView, SimPose, _Path, _Path], Reduced]] = {
    PLANE_FOUR_BAR: _plane_reduced, PLANE_SLIDER_CRANK: _plane_reduced,
    SPHERICAL_FOUR_BAR: _spatial_reduced, SKEW_FOUR_BAR: _spatial_reduced,
    SKEW_SLIDER_CRANK: _spatial_reduced}


def _mass_of(body: Body, length: float) -> tuple[float, float]:
    """A crank's centre (its distance from the pivot toward the pin) and moment of inertia
    about it: as given, or a uniform rod's of `length`."""
    if body.centre is None:
        return 0.5 * length, body.mass * length * length / 12.0
    return float(cast(float, body.centre)), float(cast(float, body.inertia))


def _coupler_rate(view: SimView, pose: SimPose, a: _Path, p: _Path, u: float, v: float) -> Vector:
    """The coupler point (u, v)'s derivative by q (Linkage.coupler's point)."""
    form = PINS[view.closure.kind].coupler
    if form == "sphere":                # on the unit sphere, by the pins' derivatives by q
        r = view.radius
        a1, p1 = ([weighted_sum((1.0 / r, x)) for x in pin[:2]] for pin in (a, p))
        return weighted_sum((r, coupler_form(view.closure, a1, p1, u, v, math.sqrt)[1]))
    ab, ab1 = difference(p[0], a[0]), difference(p[1], a[1])
    span = dot(ab, ab)
    if form == "line":                  # A + u e, e' = (B' - A') / |AB| (|AB| fixed)
        return weighted_sum((1.0, a[1]), (u / math.sqrt(span), ab1))
    w1 = cross(ab, ab1)[2] / span
    e = weighted_sum((1.0 / math.sqrt(span), ab))
    return weighted_sum((1.0, a[1]), (-w1 * u, (e[1], -e[0], 0.0)), (-w1 * v, e))


_Near: TypeAlias = "tuple[float, float, float, float] | None"     # see root_near
_Found: TypeAlias = "tuple[float, float, float, int, Reduced, tuple[SimPose, _Path, _Path] | None]"


def _found(view: SimView, q: float, near: _Near, label: int) -> _Found | None:
    """The position at q on the branch followed (root_near): the other coordinate and its first two
    derivatives by q, the branch, Reduced there, and the pose with its pins; None where there is
    no position."""
    found = root_near(view, q, near, label)
    if found is None:
        return None
    pose, branch = found
    a, p = _pins(view, pose)
    return pose.other, pose.other1, pose.other2, branch, _reduced_at(view, pose, a, p), \
        (pose, a, p)


def _four_bar_found(view: SimView, q: float, near: _Near, label: int) -> _Found | None:
    """_found for a plane four-bar, the pose and pins left out, in scalars: the closure solved
    once for both branches by the engine's formulas (a copy of _sweep_four_bar's for one angle:
    tests/test_simulate.py holds the two to each other), the root nearest the prediction as
    root_near chooses it, the pins from the closure's cos and sin of phi and psi. Near the
    discriminant's zero (a change point, a dead centre), without a prediction, and at an angle not
    finite (the engine's error), it is _found."""
    p0, pc, ps, q0, qc, qs, s0, sc, ss = view.closure.constants
    if near is None or not math.isfinite(q * DEG):
        return _found(view, q, near, label)
    c, s = cos_sin_degrees(q * DEG)
    xp, xq, xs = pc * c + ps * s, qc * c + qs * s, sc * c + ss * s
    p, k, sv = p0 + xp, q0 + xq, s0 + xs
    rr = math.hypot(p, k)
    disc = (rr - sv) * (rr + sv)
    if disc <= view.closure.precise_below:
        return _found(view, q, near, label)
    root = math.sqrt(disc)
    r2 = rr * rr
    dp, dq, ds = ps * c - pc * s, qs * c - qc * s, ss * c - sc * s
    start, y0, v0, a0 = near
    h = q - start
    guess, slope = y0 + h * v0 + 0.5 * h * h * a0, v0 + h * a0
    best = math.inf
    y = vel = cp = sp = sign = 0.0
    branch = 0
    for one, sg in ((1, 1.0), (2, -1.0)):
        sn, cn = -k * sv - sg * p * root, -p * sv + sg * k * root
        psi = math.atan2(sn, cn) * DEG
        if psi == -180.0:
            psi = 180.0
        other = guess + math.remainder(psi * RAD - guess, 2.0 * math.pi)
        cpi, spi = cn / r2, sn / r2
        v = -sg * (dp * cpi + dq * spi + ds) / root
        misfit = abs(other - guess) + abs(h) * abs(v - slope)
        if misfit < best:
            best, y, vel, cp, sp, sign, branch = misfit, other, v, cpi, spi, sg, one
    acc = -sign * (-(xp * cp + xq * sp + xs) + 2.0 * (dq * cp - dp * sp) * vel + sv * vel * vel) \
        / root
    dims, radius = view.dims, view.radius
    b, d = radius * dims["b"], radius * dims["d"]
    ax, ay, dx, dy = b * c, b * s, d * cp, d * sp
    return y, vel, acc, branch, _plane_sums(
        view, ax, ay, -ay, ax, -ax, -ay, radius * dims["a"] + dx, dy, -dy * vel, dx * vel,
        -dx * vel * vel - dy * acc, -dy * vel * vel + dx * acc, 1.0, 0.0, vel, acc), None


def _slider_found(view: SimView, q: float, near: _Near, label: int) -> _Found | None:
    """_found for the plane slider-crank in its crank's angle, as _four_bar_found (a copy of
    _sweep_slider's formulas for one angle); in its slider's x (view.swapped) it is _found."""
    m0, mc, ms, k0, kc, ks, u0, uc, us, v0, vc, vs, rod = view.closure.constants
    if near is None or view.swapped or not math.isfinite(q * DEG):
        return _found(view, q, near, label)
    c, s = cos_sin_degrees(q * DEG)
    xm, xk = mc * c + ms * s, kc * c + ks * s
    m, k = m0 + xm, k0 + xk
    dist = math.hypot(u0 + uc * c + us * s, v0 + vc * c + vs * s)
    disc = (rod - dist) * (rod + dist)
    if disc <= view.closure.precise_below:
        return _found(view, q, near, label)
    root = math.sqrt(disc)
    big = m + root if m >= 0.0 else m - root
    dm, dk = ms * c - mc * s, ks * c - kc * s
    unit = view.closure.unit
    start, y0, rate0, ahead = near
    h = q - start
    guess, slope = y0 + h * rate0 + 0.5 * h * h * ahead, rate0 + h * ahead
    best = math.inf
    x = vel = sign = 0.0
    branch = 0
    for one, sg in ((1, 1.0), (2, -1.0)):
        xi = big if (sg > 0.0) == (m >= 0.0) else k / big
        v = sg * (dm * xi - 0.5 * dk) / root
        misfit = abs(xi * unit - guess) + abs(h) * abs(v * unit - slope)
        if misfit < best:
            best, x, vel, sign, branch = misfit, xi, v, sg, one
    acc = sign * (0.5 * xk - xm * x + 2.0 * dm * vel - vel * vel) / root * unit
    x, vel = x * unit, vel * unit
    radius = view.radius
    b = radius * view.dims["b"]
    ax, ay = b * c, b * s
    return x, vel, acc, branch, _plane_sums(
        view, ax, ay, -ay, ax, -ax, -ay, radius * x, radius * view.dims["e"], radius * vel, 0.0,
        radius * acc, 0.0, 1.0, 0.0, vel, acc), None


_FAST_FOUND: dict[str, Callable[[SimView, float, _Near, int], _Found | None]] = {
    PLANE_FOUR_BAR: _four_bar_found, PLANE_SLIDER_CRANK: _slider_found}


def state_at(run: SimModel, view: SimView, q: float, rate: float, near: _Near, label: int
        ) -> SimPoint | None:
    """The state (q, rate) in `view`, or None where it cannot be evaluated (in scalars, where
    the kind has a _FAST_FOUND and no spring or coupler force asks for the pins)."""
    fast = _FAST_FOUND.get(view.closure.kind, _found) \
        if not run.springs and run.coupler_force is None else _found
    found = fast(view, q, near, label)
    if found is None:
        return None
    y, y1, y2, branch, dynamics, pins = found
    if not dynamics.inertia > 0.0:
        return None
    # the linkage's angles by q: the crank's phi and the output's psi (or x)
    if view.swapped:
        phi, phi1, psi, psi1 = y - view.shift, y1, q - view.shift, 1.0
    else:
        phi, phi1, psi, psi1 = q, 1.0, y, y1
    applied = dynamics.gravity_force - 0.5 * dynamics.slope * rate * rate
    potential = dynamics.potential
    omega = phi1 * rate
    driver = run.driver
    torque = driver.torque
    if driver.free_speed_rpm:
        torque += driver.stall_torque * (1.0 - omega * 30.0 / math.pi / driver.free_speed_rpm)
    free = torque * phi1 + run.output_torque * psi1 + run.output_force * psi1
    for t in run.torsions:
        angle, angle1 = (phi, phi1) if t.pivot == "A0" else (psi, psi1)
        potential += 0.5 * t.stiffness * (angle - t.free_angle * RAD) ** 2
        applied -= t.stiffness * (angle - t.free_angle * RAD) * angle1
        free -= t.damping * angle1 * angle1 * rate
    if run.springs or run.coupler_force is not None:
        pose, a, p = cast(tuple[SimPose, _Path, _Path], pins)
        still = (0.0, 0.0, 0.0)
        points = {name: (at, still) for name, at in view.ground.items()}
        points.update({"A": (a[0], a[1]), PINS[view.closure.kind].output_joint: (p[0], p[1])})
    for s in run.springs:
        (pa, va), (pb, vb) = (points[view.names[x]] if isinstance(x, str)
                              else (view.frame(x), still) for x in (s.point_a, s.point_b))
        gap = difference(pa, pb)
        length = math.sqrt(dot(gap, gap))
        stretch = length - s.free_length
        potential += 0.5 * s.stiffness * stretch * stretch
        if length:
            applied -= s.stiffness * stretch * dot(gap, difference(va, vb)) / length
    if run.coupler_force is not None:
        (u, v), f = run.coupler_force
        if view.shift:                  # the inverse four-bar: its coupler's frame turned
            u, v, f = abs(view.closure.dims["c"]) - u, -v, (-f[0], -f[1], f[2])
        free += dot(f, _coupler_rate(view, pose, a, p, u, v))
    applied += free
    energy = 0.5 * dynamics.inertia * rate * rate + potential
    return SimPoint(q, rate, y, y1, y2, branch, dynamics.inertia, applied / dynamics.inertia,
                  energy, free * rate)


# ---- 14. Simulation: the run, stepped in time and its events -------------------------------------
#
# The integrator: Dormand and Prince's embedded Runge-Kutta 5(4) with its 4th-order dense output
# (Hairer, Norsett and Wanner, Solving ODE I, II.5 and II.6), on (q, q_dot, W), W the work of the
# driver, the loads and the dampers, the error of q held to `tolerance` radians and q_dot's to
# `tolerance` of its size (at least 1/s) each step. Events, located on the dense output by bisection
# to 2^-60 of a step: the input's dead centre (phi_dot changes sign while psi_dot does not), a
# change point (the engine's labels of the followed branch swap), rest (q_dot = 0: every point
# stops), an angle reached (until_angle). A step whose evaluation fails (no position, J = 0) is
# retried at a quarter of its length. The total energy E = 1/2 J q_dot^2 + potential of gravity and
# springs, from the positions, is written along the run with W: E - W stays E(0) to the tolerance, a
# check (Simulation.energy_error), not an assumption.
#
# Uses: sections 2, 6, 7, 9 and 13.
# Offers: REST, ANGLE_REACHED, COORDINATE, STUCK, END, SimRow, SimEvent, Simulation, simulate.


REST = "rest"                        # SimEvent.kind: every point at rest (q_dot = 0)
ANGLE_REACHED = "angle"              # the crank reached until_angle: the run ends
COORDINATE = "coordinate"            # the run changed its coordinate (text: to which)
STUCK = "stuck"                      # no step could be taken: the run ends
END = "end"                          # the run's time is over
_SWITCH_ABOVE = 2.0                  # |d other / d q| over which the coordinate changes
_CRAWL, _CRAWL_STEPS = 1e-9, 10_000  # so many steps in a row, each under this of the run: STUCK
_SHORTEST = 1e-13                    # a step shorter than this (times 1 + t) fails: STUCK
_LONGEST_RUN = 1e7                   # seconds: a longer run is refused
_ROWS_AT_MOST = 1_000_000            # rows a run may write (time / step)
_EVENT_DIGITS = 60                   # bisections that place an event (to 2^-60 of a step)

# Dormand-Prince 5(4): nodes, the stages' coefficients, the 5th-order weights, the error's
# weights (5th less 4th order), and the dense output's polynomials in theta (rows by stage).
_DP_C = (0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0)
_DP_A = ((), (1 / 5,), (3 / 40, 9 / 40), (44 / 45, -56 / 15, 32 / 9),
         (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729),
         (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656),
         (35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84))
_DP_E = (71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40)
_DP_DENSE = ((1.0, -8048581381 / 2820520608, 8663915743 / 2820520608,
              -12715105075 / 11282082432),
             (0.0, 0.0, 0.0, 0.0),
             (0.0, 131558114200 / 32700410799, -68118460800 / 10900136933,
              87487479700 / 32700410799),
             (0.0, -1754552775 / 470086768, 14199869525 / 1410260304,
              -10690763975 / 1880347072),
             (0.0, 127303824393 / 49829197408, -318862633887 / 49829197408,
              701980252875 / 199316789632),
             (0.0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844),
             (0.0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423))


class SimRow(NamedTuple):
    """One instant of a run: t (s), the crank's phi (degrees, unwrapped), omega (rad/s) and
    alpha (rad/s^2); the output (degrees unwrapped, or the slider's x in m) and its rate and
    acceleration (rad/s and rad/s^2, or m/s and m/s^2); the total energy (J), the work W done
    on it so far (J), and the coordinate it was computed in ("input" phi, or "output" psi)."""
    t: float
    phi: float
    omega: float
    alpha: float
    output: float
    output_rate: float
    output_acceleration: float
    energy: float
    work: float
    coordinate: str


class SimEvent(NamedTuple):
    """What happened at time t (s) with the crank at phi (degrees): kind DEAD_CENTRE,
    CHANGE_POINT, REST, ANGLE_REACHED, COORDINATE, STUCK or END; text says more."""
    t: float
    kind: str
    phi: float
    text: str


class Simulation(NamedTuple):
    """A run: its rows (every `step` seconds and at each event), its events, the steps taken
    and rejected, the model's evaluations, and energy_error: the largest |E - W - E(0)| along
    the accepted steps (J)."""
    rows: list[SimRow]
    events: list[SimEvent]
    steps: int
    rejected: int
    evaluations: int
    energy_error: float


_Phase: TypeAlias = tuple[float, float, float]         # q, q_dot and the work W
_Slopes: TypeAlias = list[_Phase]


def _reference(p: SimPoint) -> tuple[float, float, float, float]:
    return p.q, p.other, p.other1, p.other2


def _slope(p: SimPoint) -> _Phase:
    return p.rate, p.acceleration, p.power


def _dp_step(run: SimModel, view: SimView, y: _Phase, first: SimPoint, h: float
             ) -> tuple[_Phase, _Slopes, SimPoint, float, float] | None:
    """One Dormand-Prince step of length h from y (at the point `first`): the new state, the
    stages' slopes, the new point, and the error estimates of q and q_dot; None where a stage
    cannot be evaluated."""
    slopes = [_slope(first)]
    point, new, near = first, y, _reference(first)
    for a in _DP_A[1:]:
        dq = dr = dw = 0.0
        for ai, k in zip(a, slopes):
            dq, dr, dw = dq + ai * k[0], dr + ai * k[1], dw + ai * k[2]
        new = (y[0] + h * dq, y[1] + h * dr, y[2] + h * dw)
        found = state_at(run, view, new[0], new[1], near, first.label)
        if found is None:
            return None
        point = found
        slopes.append(_slope(point))
    eq = ev = 0.0
    for e, k in zip(_DP_E, slopes):
        eq, ev = eq + e * k[0], ev + e * k[1]
    return new, slopes, point, h * eq, h * ev


def _dense(y: _Phase, slopes: _Slopes, h: float, theta: float) -> _Phase:
    """The state at theta (0 to 1) of the step from y, by the 4th-order dense output."""
    powers = (theta, theta ** 2, theta ** 3, theta ** 4)
    weights = [sum(p * x for p, x in zip(row, powers)) for row in _DP_DENSE]
    return cast(_Phase, tuple(y[j] + h * sum(w * k[j] for w, k in zip(weights, slopes))
                              for j in range(3)))


def _row(view: SimView, t: float, p: SimPoint) -> SimRow:
    """A SimRow of the point p in `view` at time t."""
    if view.swapped:
        phi, phi1, phi2, psi, psi1, psi2 = p.other - view.shift, p.other1, p.other2, \
            p.q - view.shift, 1.0, 0.0
    else:
        phi, phi1, phi2, psi, psi1, psi2 = p.q, 1.0, 0.0, p.other, p.other1, p.other2
    r, a = p.rate, p.acceleration
    return SimRow(t, phi * DEG, phi1 * r, phi1 * a + phi2 * r * r,
                  psi if view.closure.is_slider else psi * DEG, psi1 * r, psi1 * a + psi2 * r * r,
                  p.energy, 0.0, "output" if view.swapped else "input")


def _bisected(within: Callable[[float], bool]) -> float:
    """The theta in [0, 1] where within(theta) turns from True (at 0) to False (at 1)."""
    lo, hi = 0.0, 1.0
    for _ in range(_EVENT_DIGITS):
        middle = 0.5 * (lo + hi)
        if within(middle):
            lo = middle
        else:
            hi = middle
    return hi


def _checked_positive(value: Any, what: str, most: float) -> float:
    x = checked_number(value, what)
    if not 0.0 < x <= most:
        raise ValueError(f"{what} must be above 0 and at most {most:g}, not {x:g}")
    return x


def simulate(linkage: Closure, bodies: Bodies, effects: Effects = Effects(), *,
             driver: Driver | None = None, springs: Sequence[Spring] = (),
             torsions: Sequence[Torsion] = (), initial: tuple[float, float] = (0.0, 0.0),
             time: float = 1.0, step: float = 0.01, tolerance: float = 1e-8, branch: int = 1,
             until_angle: float | None = None, stop_at_rest: bool = False,
             radius: float = 1.0) -> Simulation:
    """The linkage's motion in time from the crank's initial (angle in degrees, speed in rpm)
    on the listing's `branch` there, for `time` seconds, under gravity and the loads of
    `effects` (its speed and acceleration are not used), the driver, springs and torsions:
    rows every `step` seconds, the events, and the energy check (see the section's notes). The
    run ends early at until_angle (degrees, the crank's) or at rest (stop_at_rest); radius is
    the spherical four-bar's sphere (m), as forces'. A ValueError says in one sentence what is
    wrong with the input."""
    time = _checked_positive(time, "the run's time (s)", _LONGEST_RUN)
    step = _checked_positive(step, "the rows' step (s)", time)
    if time / step > _ROWS_AT_MOST:
        raise ValueError(f"time / step asks for {time / step:.3g} rows, more than "
                         f"{_ROWS_AT_MOST:,}: take a longer step")
    tolerance = _checked_positive(tolerance, "the tolerance", 1e-2)
    if tolerance < 1e-14:
        raise ValueError(f"the tolerance must be at least 1e-14, not {tolerance:g}")
    if branch not in (1, 2):
        raise ValueError("branch is the listing's branch the motion starts on: 1 or 2")
    try:
        angle, speed = initial
    except (TypeError, ValueError):
        raise ValueError("initial is (angle in degrees, speed in rpm)") from None
    angle = checked_number(angle, "the initial angle")
    omega = 2.0 * math.pi * checked_number(speed, "the initial speed (rpm)") / 60.0
    target = None if until_angle is None else checked_number(until_angle, "until_angle")
    driver = driver or Driver()
    for value, what in zip(driver, ("the driver's torque", "the stall torque",
                                    "the free speed (rpm)")):
        checked_number(value, what)
    if driver.stall_torque and not driver.free_speed_rpm:
        raise ValueError("a motor line needs its free speed (free_speed_rpm, not 0)")
    plane = linkage.kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK)
    for s in springs:
        for p in (s.point_a, s.point_b):
            if isinstance(p, str):
                if p not in ("A0", "A", PINS[linkage.kind].output_joint) + (
                        () if linkage.is_slider else ("B0",)):
                    raise ValueError(f"a spring's point is a joint (A0, A, B, B0; C the "
                                     f"slider's) or {'(x, y)' if plane else '(x, y, z)'}, "
                                     f"not {p!r}")
            else:
                checked_numbers(p, 2 if plane else 3, "a spring's point " +
                                ("(x, y)" if plane else "(x, y, z)"))
        if checked_number(s.stiffness, "a spring's stiffness") < 0.0 or \
                checked_number(s.free_length, "a spring's free length") < 0.0:
            raise ValueError("a spring's stiffness and free length must not be negative")
    for tz in torsions:
        if tz.pivot not in ("A0", "B0") or (tz.pivot == "B0" and linkage.is_slider):
            raise ValueError(f"a torsion's pivot is A0 (the crank) or B0 (the output crank), "
                             f"not {tz.pivot!r}")
        for value, what in zip(tz[1:], ("stiffness", "free angle", "damping")):
            checked_number(value, f"a torsion's {what}")
    forces(linkage, [], branch, bodies, effects, radius=radius)     # its ValueError: the
    #                                                                   bodies, the effects
    load = None
    if effects.coupler_force is not None:
        at, f = effects.coupler_force
        load = ((float(at[0]), float(at[1])), cast(Vector, tuple(float(x) for x in f)))
    run = SimModel(linkage, views_of(linkage, bodies, gravity_vector(effects.gravity, linkage.kind),
                                 radius), driver,
                 tuple(springs), tuple(torsions), float(effects.output_torque),
                 float(effects.output_force), load)
    view = run.views[0]
    start = linkage.motion(angle, branch)
    if start.status == DEAD_CENTRE:
        raise ValueError(f"the initial angle {angle:g} degrees is a dead centre of the input: "
                         "start beside it")
    if start.velocity is None:
        raise ValueError(f"the linkage does not assemble at the initial angle {angle:g} "
                         f"degrees on branch {branch}")
    first = state_at(run, view, angle * RAD, omega, None, branch)
    if first is None:                   # it assembles: J is zero
        raise ValueError("the reduced inertia at the initial angle is zero: give the crank, "
                         "coupler or output a mass")
    return _integrate(run, first, time, step, tolerance, target, stop_at_rest)


def _switched(run: SimModel, index: int, p: SimPoint) -> tuple[int, SimPoint | None]:
    """The point p of view `index` in the other view (the other coordinate)."""
    to = 1 - index
    shift = run.views[1].shift if to == 1 else -run.views[1].shift
    near = (p.other + shift, p.q + shift, 1.0 / p.other1, -p.other2 / p.other1 ** 3)
    return to, state_at(run, run.views[to], p.other + shift, p.other1 * p.rate, near, 1)


def _integrate(run: SimModel, first: SimPoint, time: float, step: float, tolerance: float,
               target: float | None, stop_at_rest: bool) -> Simulation:
    """simulate's run from the point `first` (see there)."""
    index = 0
    events: list[SimEvent] = []

    def phi_of(v: SimView, p: SimPoint) -> float:
        return (p.other - v.shift if v.swapped else p.q) * DEG

    if abs(first.other1) * run.views[0].ratio > _SWITCH_ABOVE:
        index, moved = _switched(run, index, first)
        if moved is None:
            raise ValueError("the motion cannot start there (a dead centre)")
        first = moved
    view = run.views[index]
    t, y, p = 0.0, (first.q, first.rate, 0.0), first
    energy0 = first.energy
    rows = [_row(view, 0.0, first)]
    next_row = 1
    h = min(time, 0.01 / max(1.0, abs(first.rate)), step)
    steps = rejected = crawl = 0
    evaluations = 1
    worst = 0.0
    while t < time:
        h = min(h, time - t)
        taken = _dp_step(run, view, y, p, h)
        evaluations += 6
        if taken is None:
            rejected += 1
            h *= 0.25
        else:
            new, slopes, p1, eq, ev = taken
            error = max(abs(eq) / (tolerance * view.scale),
                        abs(ev) / (tolerance * max(view.scale, abs(y[1]), abs(new[1]))))
            if error > 1.0:
                rejected += 1
                h *= max(0.2, 0.9 * error ** -0.2)
            else:
                steps += 1
                end, stop = 1.0, False
                near, label0 = _reference(p), p.label

                def at(theta: float) -> SimPoint | None:
                    s = _dense(y, slopes, h, theta)
                    return state_at(run, view, s[0], s[1], near, label0)

                def other_at(theta: float) -> tuple[SimPose, int] | None:
                    return root_near(view, _dense(y, slopes, h, theta)[0], near, label0)

                found: list[tuple[float, str, str]] = []
                if p1.label != p.label:
                    found.append((_bisected(lambda th: (lambda r: r is None or r[1] == label0)(
                        other_at(th))), CHANGE_POINT, "the branches cross: kept to the one "
                                                      "followed"))
                if view.swapped and (p.other1 > 0.0) != (p1.other1 > 0.0):
                    sign = p.other1 > 0.0
                    found.append((_bisected(lambda th: (lambda r: r is None or (
                        r[0].other1 > 0.0) == sign)(other_at(th))), DEAD_CENTRE,
                        "the crank stops and turns back"))
                if (y[1] > 0.0) != (new[1] > 0.0) and y[1] != 0.0:
                    found.append((_bisected(lambda th: (_dense(y, slopes, h, th)[1] > 0.0) ==
                                            (y[1] > 0.0)), REST, "every point at rest"))
                if target is not None:
                    before, after = phi_of(view, p) - target, phi_of(view, p1) - target
                    if before == 0.0 or (before > 0.0) != (after > 0.0):
                        theta = _bisected(lambda th: (lambda q: q is not None and (
                            phi_of(view, q) - target > 0.0) == (before > 0.0))(at(th)))
                        found.append((theta, ANGLE_REACHED, f"the crank at {target:g} degrees"))
                for theta, kind, text in sorted(found):
                    here = at(theta)
                    events.append(SimEvent(t + theta * h, kind,
                                           phi_of(view, here) if here else math.nan, text))
                    if kind == ANGLE_REACHED or (kind == REST and stop_at_rest):
                        end, stop = theta, True
                        break
                while next_row * step <= t + end * h * (1 + 1e-15) and next_row * step <= time:
                    theta = min(1.0, (next_row * step - t) / h)
                    here = at(theta)
                    if here is not None:
                        w = _dense(y, slopes, h, theta)[2]
                        rows.append(_row(view, next_row * step, here)._replace(work=w))
                    next_row += 1
                if stop:
                    last = at(end)
                    w = _dense(y, slopes, h, end)[2]
                    if last is not None:
                        rows.append(_row(view, t + end * h, last)._replace(work=w))
                    break
                t, y, p = t + h, new, p1
                worst = max(worst, abs(p.energy - y[2] - energy0))
                h *= min(5.0, max(0.2, 0.9 * max(error, 1e-10) ** -0.2))
                if abs(p.other1) * view.ratio > _SWITCH_ABOVE:
                    index, moved = _switched(run, index, p)
                    if moved is None:
                        events.append(SimEvent(t, STUCK, phi_of(view, p), "cannot change "
                                               "coordinate here"))
                        break
                    view, p = run.views[index], moved
                    y = (p.q, p.rate, y[2])
                    events.append(SimEvent(t, COORDINATE, phi_of(view, p),
                                           ("the slider's x" if view.closure.is_slider else
                                            "the output's angle") if view.swapped
                                           else "the crank's angle"))
        if h < _SHORTEST * (1.0 + t):
            events.append(SimEvent(t, STUCK, phi_of(view, p), "no step could be taken"))
            break
        crawl = crawl + 1 if h < _CRAWL * time else 0
        if crawl > _CRAWL_STEPS:
            events.append(SimEvent(t, STUCK, phi_of(view, p), f"{_CRAWL_STEPS:,} steps in a "
                                   f"row each under {_CRAWL:g} of the run: it stalls"))
            break
    else:
        events.append(SimEvent(t, END, phi_of(view, p), "the run's time is over"))
    if t - rows[-1].t > 1e-9 * step:        # the last state, unless a row is there already
        rows.append(_row(view, t, p)._replace(work=y[2]))
    return Simulation(rows, events, steps, rejected, evaluations, worst)


# ---- 15. The linkage: one class for all that can be asked of it ----------------------------------
#
# Holds: Linkage, the engine's Closure with a method for each question the sections before answer:
# motion and sweep (the engine), coupler and transmission (what it derives), the same on numpy
# arrays, and forces (what it takes to drive it).
#
# Uses: sections 6, 7, 9, 10 and 12.
# Offers: Linkage.


class Linkage(Closure):
    """One linkage of the listing's five kinds: Linkage(kind, **dims) (see Closure), and all
    that can be asked of it. Each method names a question and the section that answers it: the
    engine's motion and sweep, the coupler point and the transmission angle (what the engine
    derives), the same on numpy arrays (the numpy path), and the forces that drive it."""

    __slots__ = ()

    def sweep_arrays(self, phis: Sequence[float] | numpy.ndarray, branch: int = 1,
                     derivatives: int = 2) -> MotionArrays:
        """sweep on numpy arrays (the optional extra `fast`): a MotionArrays of the output,
        velocity and acceleration (NaN where there is no position) and status codes. The same
        numbers as sweep to 1e-13 (tests/test_fast.py): a point near a dead centre or change
        point, or whose numbers are not finite, is computed by sweep itself. Raises
        FastUnavailable where numpy is not installed."""
        return motion_arrays_of(self, phis, branch, derivatives)

    def coupler(self, phis: Iterable[float], u: float, v: float = 0.0, branch: int | str = 1,
                derivatives: int = 2, *, start: int | None = None) -> list[CouplerMotion]:
        """The coupler point (u, v) at each input angle of `phis`: a CouplerMotion each, its
        position, velocity and acceleration (x, y, z) on the branch (or motion) that sweep takes.
        The point is fixed to the coupler, in its own frame: plane kinds P = A + u e + v n (u, v
        lengths, e the unit vector from A to the output pin, n = e turned +90 degrees about z);
        the spherical four-bar P = cos v (cos u A + sin u t) + sin v (A x t) (u, v degrees, t
        the unit tangent at A toward B); the skew kinds P = A + u e, v = 0 (their coupler may
        spin about that line). A ValueError says why a point is refused."""
        u, v = check_coupler_point(self, u, v)
        return coupler_of(self, self.sweep(phis, branch, derivatives, start=start), u, v)

    def transmission(self, phis: Iterable[float], branch: int | str = 1, *,
                     start: int | None = None) -> list[float | None]:
        """The transmission angle mu (degrees, [0, 180]) at each input angle, None where there
        is no position: the angle between the output pin's velocity and its velocity relative
        to the crank pin A (the review's section 2; see the section's notes)."""
        return transmission_of(self, self.sweep(phis, branch, 0, start=start))

    def coupler_arrays(self, phis: Sequence[float] | numpy.ndarray, u: float, v: float = 0.0,
                       branch: int = 1, derivatives: int = 2) -> CouplerArrays:
        """coupler on numpy arrays (sweep_arrays's numbers): a CouplerArrays."""
        u, v = check_coupler_point(self, u, v)
        return coupler_of_arrays(self, self.sweep_arrays(phis, branch, derivatives), u, v)

    def transmission_arrays(self, phis: Sequence[float] | numpy.ndarray,
                            branch: int = 1) -> numpy.ndarray:
        """transmission on numpy arrays: a float64 array, NaN where there is no position."""
        return transmission_of_arrays(self, self.sweep_arrays(phis, branch, 0))

    def forces(self, phis: Iterable[float], branch: int | str = 1, bodies: Bodies = Bodies(),
               effects: Effects = Effects(), *, radius: float = 1.0,
               start: int | None = None) -> list[Forces]:
        """What it takes to drive the linkage at each input angle: the driving torque, the
        joints' reactions and the frame's shaking, for the bodies and effects given (see the
        forces section's notes: SI units, each body's frame)."""
        return forces(self, phis, branch, bodies, effects, radius=radius, start=start)

    def forces_arrays(self, phis: Sequence[float] | numpy.ndarray, branch: int = 1,
                      bodies: Bodies = Bodies(), effects: Effects = Effects(), *,
                      radius: float = 1.0) -> ForcesArrays:
        """forces on numpy arrays (the optional extra `fast`): a ForcesArrays of the torque, the
        power, each joint's reaction and the shaking, NaN where unknown, with status codes; the
        same numbers as forces to rounding and the same statuses (tests/test_forces_numpy.py): a
        position near a dead centre is computed by forces itself."""
        return forces_arrays_of(self, phis, branch, bodies, effects, radius)


# ---- 16. DAT and CSV files: the sweep's formats, written and read --------------------------------
#
# Holds: the accurate engine's files: ANG.DAT, VEL.DAT, ACC.DAT (and MU.DAT) in the listing's format
# ("phi,value" CR LF lines, the end byte 1A) at full precision, the CSV's columns, a sweep's angles,
# and read_dat, which reads any DAT file back. They are written through DatFiles and written_whole
# (section 1), a block of rows at once where numpy is there (the numpy path), the same bytes
# either way.
#
# Uses: sections 1 and 10.
# Offers: SceneError, angle_count, evenly_spaced_angles, write_dat_files, CSV_HEADER,
#   TRANSMISSION_COLUMN, COUPLER_COLUMNS, csv_line, write_csv, DAT_CHUNK, DAT_LONGEST_LINE,
#   DAT_TEXT, dat_points, read_dat, dat_precision.


class SceneError(ValueError):
    """A scene file, or a DAT file, that cannot be drawn; the message names the file and the key
    (or line) and what was expected."""


# -- angles and files ----------------------------------------------------------------------------

def angle_count(start: float, stop: float, step: float) -> int:
    """How many input angles start, start + step, ... reach stop (within step / 1e9)."""
    if step == 0 or not all(math.isfinite(v) for v in (start, stop, step)):
        raise ValueError("start, stop and step must be finite and step non-zero")
    steps = (stop - start) / step
    if not math.isfinite(steps) or steps > 2.0 ** 62:
        raise ValueError(f"from {start:g} to {stop:g} by {step:g} is too many points")
    return max(math.floor(steps + 1e-9) + 1, 0)


def evenly_spaced_angles(start: float, stop: float, step: float) -> list[float]:
    """The input angles start, start + step, ... up to stop (within step / 1e9), each computed
    as start + i * step: no accumulated rounding (the listing's single-precision FOR drifts,
    quirk K10)."""
    return [start + i * step for i in range(angle_count(start, stop, step))]


def write_dat_files(motions: Iterable[tuple], directory: str = ".", *,
                    clip: bool = False, missing: str = "skip", files: int = 3,
                    transmission: bool | None = None,
                    before_rename: Callable[[], None] | None = None,
                    csv: Any = None) -> int:
    """Write ANG.DAT, VEL.DAT and ACC.DAT (the first `files` of them) in the listing's format
    ("phi,value" lines, CRLF, a 0x1A end byte) at full precision: each number as the shortest
    text that reads back exactly (repr). `motions` may be any iterable of rows (a generator keeps
    a long sweep out of memory) or of SweepColumns (a block of rows as numpy arrays); the files
    are written whole or not at all (DatFiles). Returns the number of rows.

    Unclipped unless clip=True (then VEL and ACC are clipped to +-3 as lines 1200-1300 do). A value
    that is None (see Motion.status) is left out of its file (missing="skip"), or written as 0 as
    the listing writes positions it cannot assemble (missing="zero", quirk K8).

    transmission=True: each row's sixth field (after a Motion's five), the transmission angle,
    goes to MU.DAT too; False: an old MU.DAT there is removed with the old set (DatFiles).
    before_rename: see DatFiles.close. csv: an open binary file to which every row goes too, as
    csv_line writes it (all its fields, unclipped), its numbers formatted once for both.
    """
    if missing not in ("skip", "zero"):
        raise ValueError('missing is "skip" or "zero"')
    fields = (1, 2, 3)[:files] + ((5,) if transmission else ())
    out = DatFiles(directory, files, transmission)
    try:
        for block in _blocks(motions):
            for texts, points in _block_texts(block, fields, clip, missing == "zero",
                                              csv is not None):
                if csv is not None:
                    csv.write(texts.pop())
                out.write(texts, points)
    except BaseException:
        out.discard()
        raise
    out.close(before_rename)
    return out.points


def _block_texts(block, fields, clip, zero, csv):
    """One block's lines (rows, or SweepColumns), in parts: each part's texts (bytes), one for
    each DAT file of `fields` (row indices; "phi,value" CR LF, VEL and ACC (fields 2 and 3)
    clipped to +-3 if `clip`, a missing value left out, or written as 0.0 if `zero`), then if
    `csv` its CSV rows; and its number of rows."""
    clipped = [clip and f in (2, 3) for f in fields]
    if isinstance(block, SweepColumns):
        yield from column_texts(block, fields, clipped, zero, csv)
    else:
        yield _row_texts(block, fields, clipped, zero, csv), len(block)


def _row_texts(rows, fields, clipped, zero, csv) -> list:
    """_block_texts of a list of rows, a number at a time (without numpy)."""
    phis = [repr(float(row[0])) for row in rows]
    zero_value = 0.0 if zero else None

    def line(phi, value, clip):
        if value is None:
            value = zero_value
            if value is None:
                return ""
        elif clip:
            value = min(3.0, max(-3.0, value))
        return f"{phi},{float(value) + 0.0!r}\r\n"           # -0.0 written as 0.0
    return ["".join(line(phi, row[f], clip) for phi, row in zip(phis, rows)).encode("ascii")
            for f, clip in zip(fields, clipped)] + [
        "".join(map(csv_line, rows)).encode("ascii")] * csv


def _blocks(rows):
    """rows in blocks of NUMBER_ROWS (SweepColumns are passed on as they are): a full block becomes
    SweepColumns where numpy is installed (formatted at once: many times faster than a number at
    a time, the same bytes), a shorter one where numpy is imported already."""
    block = []
    for row in rows:
        if isinstance(row, SweepColumns):
            yield row
            continue
        block.append(row)
        if len(block) == NUMBER_ROWS:
            yield as_columns(block, True)
            block = []
    if block:
        yield as_columns(block, "numpy" in sys.modules)


CSV_HEADER = ("phi", "output", "velocity", "acceleration", "status")
TRANSMISSION_COLUMN = ("transmission",)          # run --csv in double precision
COUPLER_COLUMNS = tuple(f"coupler_{q}{axis}" for q in ("", "v", "a") for axis in "xyz")


def csv_line(fields: Iterable[Any]) -> str:
    """One CSV row (CR LF, as the DAT files): numbers as the shortest text that reads back
    exactly (a zero as 0.0, whatever its sign, as in the DAT files), None (no value: see the
    status) as nan, which numpy and pandas read as NaN."""
    return ",".join("nan" if v is None else repr(float(v) + 0.0) if isinstance(v, (int, float))
                    else str(v) for v in fields) + "\r\n"


def write_csv(path: str, rows: Iterable[tuple], header: tuple[str, ...] = CSV_HEADER,
              outputs: WrittenSet | None = None) -> int:
    """Write `rows` (tuples of `header`'s fields) as one CSV file with a header row, whole or not
    at all (written_whole, or with the set `outputs`); the number of rows. Read it with
    csv.DictReader, numpy.loadtxt(path, delimiter=",", skiprows=1, usecols=...) or
    pandas.read_csv(path)."""
    count = 0
    with written(path, outputs) as out:
        out.write(csv_line(header).encode("ascii"))
        for row in rows:
            out.write(csv_line(row).encode("ascii"))
            count += 1
    return count


# -- reading DAT files -------------------------------------------------------------------------

DAT_CHUNK = 1 << 20          # a DAT file is read a mebibyte at a time, whatever its size
DAT_LONGEST_LINE = 1024      # the longest line a DAT file may hold (its lines are < 60 characters)
DAT_TEXT = bytes(range(32, 127)) + b"\t\r\n"      # the bytes a DAT file is made of, before 1A


def dat_points(path: str, warn: Callable[[str], None] | None = None
               ) -> Iterator[tuple[float, float]]:
    """The (input angle, value) pairs of a DAT file as WRITE # writes them (CRLF lines "x,y", the
    end-of-file byte 1A; numbers like .5, -1.713751E-02) or as the engine writes them (repr),
    one at a time: the file is read a chunk at a time, so that memory does not grow with it.
    A file that is not one is refused (SceneError) as soon as it shows it: no regular file (a
    FIFO, a device), a byte that is no printable ASCII text, a line longer than
    DAT_LONGEST_LINE, a line that is not two numbers. warn(message), if given, hears at the end
    of a file that may have been cut short: empty, without its end-of-file byte, or with its
    last line unended."""
    import stat
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise SceneError(f"{path}: not a DAT file: it is no regular file (a FIFO, a device "
                             "or a folder)")
        fh = open(path, "rb")
    except OSError as e:
        raise SceneError(f"{path}: cannot read: {e.strerror}") from None
    with fh:
        number, seen, carry, tail, ended, after_cr = 0, 0, "", "", False, False
        while not ended:
            try:
                chunk = fh.read(DAT_CHUNK)
            except OSError as e:
                raise SceneError(f"{path}: cannot read: {e.strerror}") from None
            if not chunk:
                break
            end = chunk.find(b"\x1a")
            if end >= 0:
                chunk, ended = chunk[:end], True
            other = chunk.translate(None, DAT_TEXT)
            if other:
                raise SceneError(f"{path}: not a DAT file: byte {other[0]:#04x} at offset "
                                 f"{seen + chunk.index(other[:1]):,} (a DAT file is text, "
                                 "\"angle,value\" lines)")
            seen += len(chunk)
            text = chunk.decode("ascii")
            tail = (tail + text)[-2:]
            if after_cr and text.startswith("\n"):       # a CR LF cut between two chunks
                text = text[1:]
            text = carry + text
            if not ended:                                 # the last line may go on
                cut = max(text.rfind("\n"), text.rfind("\r")) + 1
                text, carry = text[:cut], text[cut:]
                after_cr = text.endswith("\r") and not carry
                if len(carry) > DAT_LONGEST_LINE:
                    _dat_point(path, number + len(text.splitlines()) + 1, carry)    # says why
            for line in text.splitlines():
                number += 1
                try:                                      # the common line, at speed
                    x_text, y_text = line.split(",")
                    x, y = float(x_text), float(y_text)
                except ValueError:                        # blank, 1D+02, or no DAT line
                    point = _dat_point(path, number, line)
                    if point is None:
                        continue
                    x, y = point
                if not (math.isfinite(x) and math.isfinite(y)) or len(line) > DAT_LONGEST_LINE:
                    _dat_point(path, number, line)        # says why
                yield x, y
        if carry and not ended:                           # the last line, unended
            number += 1
            point = _dat_point(path, number, carry)
            if point is not None:
                yield point
    if warn is not None and not ended:
        warn(f"{path}: {'empty' if not seen else 'no end-of-file byte (1A)'}: the file may have "
             "been cut short")
    elif warn is not None and seen and tail != "\r\n":
        warn(f"{path}: its last line has no line end: the file may have been cut short")


def _dat_point(path: str, number: int, line: str) -> tuple[float, float] | None:
    """The point of line `number` of a DAT file, None if it is blank; SceneError if it is no
    "angle,value" line of finite numbers (D exponents as E, as GW-BASIC writes doubles)."""
    if len(line) > DAT_LONGEST_LINE:
        raise SceneError(f"{path}: not a DAT file: line {number:,} is longer than "
                         f"{DAT_LONGEST_LINE:,} characters")
    if not line.strip():
        return None
    fields = line.split(",")
    try:
        if len(fields) != 2:
            raise ValueError
        x, y = (float(f.strip().upper().replace("D", "E")) for f in fields)
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ValueError
    except ValueError:
        raise SceneError(f"{path}: line {number}: expected two numbers \"angle,value\", "
                         f"got {line[:40]!r}") from None
    return x, y


def read_dat(path: str, warn: Callable[[str], None] | None = None) -> list[tuple[float, float]]:
    """The (input angle, value) pairs of a DAT file, all of them (dat_points: one at a time)."""
    return list(dat_points(path, warn))


def dat_precision(directory: str) -> str:
    """basic or double from how the numbers are written (GW-BASIC's .5 and 1E-02, or Python's
    repr 0.5, 2.0 and 1e-02), "" if the files do not tell."""
    path = os.path.join(directory, "ANG.DAT")
    try:
        if not os.path.isfile(path):            # a FIFO would hang: dat_points refuses it
            return ""
        with open(path, "rb") as fh:
            text = fh.read(4096).decode("latin-1")
    except OSError:
        return ""
    numbers = re.split(r"[,\r\n\x1a]+", text)
    if any(re.fullmatch(r"-?(0\.\d+|\d+\.0|[\d.]+e[-+]\d+)", n) for n in numbers):
        return "double"
    if any(re.fullmatch(r"-?(\.\d+|\d+|[\d.]+E[-+]\d+)", n) for n in numbers):
        return "basic"
    return ""


# ---- 17. The mechanism drawn: poses projected onto the page --------------------------------------
#
# Holds: mechanism_drawing(), which projects the poses of a sweep onto the page - plane linkages as
# they are, the spherical linkage on its sphere seen obliquely, the skew linkages in a fixed
# isometric view with their two shaft axes - and gives a Drawing: the ground (fixed pivots hatched
# on the side the links cross least, axes), drawn once, and one Frame a pose with its letters. The
# letters go where no mark, link, hatching or other letter covers them (place_labels).
#
# Uses: sections 2, 6, 7, 8 and 15.
# Offers: Point, Box, Stroke, Mark, Label, Letters, Layer, Frame, Drawing, MECHANISM_EXAMPLES,
#   STROKE_STYLES, FAR_SIDE, VIEWS, project, Segment, stroke_segments, place_labels,
#   mechanism_drawing, spread_indices, SVG_WIDTH, SVG_HEIGHT, SVG_MARGIN, SVG_LETTER, svg_scale,
#   svg_radius, svg_letters.


# -- the drawing: what every renderer draws ------------------------------------------------------

Point = tuple[float, float]             # a point on the page, (x, y)
Box = tuple[float, float, float, float]     # a box on the page, (x0, y0, x1, y1)


class Stroke(NamedTuple):
    """A polyline on the page; style is one of STROKE_STYLES."""
    points: tuple[Point, ...]
    style: str


class Mark(NamedTuple):
    """A joint on the page: kind "pivot" (on a fixed axis), "joint" (a moving pin) or "point"
    (a coupler point); name is joint_positions()'s."""
    at: Point
    kind: str
    name: str


class Label(NamedTuple):
    """A letter of the paper (a, b, c, d, e, f, g, ξ, c*) centred at `at`, naming the page
    polyline `names` (its link or dimension line; one point for an angle): place_labels() moves
    it beside what it names, where nothing drawn covers it."""
    at: Point
    text: str
    names: tuple[Point, ...] = ()


class Letters(NamedTuple):
    """How big a renderer draws things, in page units: a letter's box (one character's width,
    its height), a joint's mark (its radius) and a line (half its width)."""
    width: float
    height: float
    mark: float
    line: float


class Layer(NamedTuple):
    strokes: tuple[Stroke, ...]
    marks: tuple[Mark, ...]
    labels: tuple[Label, ...]


class Frame(NamedTuple):
    """One pose drawn: its layer (with every letter of the drawing, placed for this pose), a
    caption (the angles), and a message where the position does not exist or is singular (then
    only the crank is drawn)."""
    pose: Pose
    layer: Layer
    caption: str
    message: str | None


class Drawing(NamedTuple):
    """A linkage drawn at a sequence of poses: the ground (fixed links hatched, shaft axes,
    traced paths), drawn once, and one Frame a pose, all in page units (x to the right, y up)
    within bounds (x0, y0, x1, y1); size is the ground symbols' size, letters how big the SVG
    draws letters and marks (the frames' letters are placed for it)."""
    title: str
    subtitle: str
    kind: str
    ground: Layer
    frames: tuple[Frame, ...]
    bounds: Box
    size: float
    letters: Letters
    chart: tuple[tuple[float, float | None], ...] | None = None   # the transmission angle
    #                                                    along the sweep: ((phi, mu), ...)
    coupler_points: tuple[Vector | None, ...] = ()   # the coupler point in 3-D, a frame each
    seconds: float | None = None    # how long a frame shows when animated (a simulation's rows
    #                                 apart: real time); None: frame_seconds()


# One linkage of each kind that turns fully, as Figs. 1 and 2 draw them (data/scenes/fig1*, fig2*).
MECHANISM_EXAMPLES = {
    PLANE_FOUR_BAR: dict(a=6.0, b=2.0, c=7.0, d=9.0),
    SPHERICAL_FOUR_BAR: dict(a=80.0, b=20.0, c=75.0, d=60.0),
    SKEW_FOUR_BAR: dict(a=4.0, b=1.5, c=4.0, d=2.5, f=2.0, ksi=40.0),
    PLANE_SLIDER_CRANK: dict(b=2.0, c=7.0, e=1.5),
    SKEW_SLIDER_CRANK: dict(a=6.0, b=1.0, c=7.5, f=3.0, ksi=45.0),
}

# link: a moving link; ground: the fixed link and the slider's guide; hatch: the ground's
# hatching; axis: a shaft axis (dash-dot); path: a joint's traced path (dotted); hidden: a link
# behind the sphere (dashed); outline: the sphere; dimension: a dimension line (thin). A line
# style means one thing: dashes are the far side of the sphere (a coupler curve's far side is
# its colour dashed: FAR_SIDE), a curve's branch is its colour.
STROKE_STYLES = ("link", "ground", "hatch", "axis", "path", "hidden", "outline", "dimension",
                 "coupler", "coupler-other", "coupler-follow",   # the coupler curve of the frames'
                 "marked",      # branch, of the other, of the motion followed; a marked position
                 "coupler-far", "coupler-other-far", "coupler-follow-far",   # behind the sphere
                 "force")       # a joint's force, an arrow (mechanism_drawing's forces_at)
FAR_SIDE = {"coupler": "coupler-far", "coupler-other": "coupler-other-far",
            "coupler-follow": "coupler-follow-far"}     # a style behind the sphere; else hidden

# Oblique views (azimuth, elevation in degrees) of the 3-D linkages: the input axis z upright on
# the page, seen from a little above.
VIEWS = {SPHERICAL_FOUR_BAR: (-90.0, 20.0), SKEW_FOUR_BAR: (-60.0, 20.0),
         SKEW_SLIDER_CRANK: (-60.0, 20.0)}


@functools.cache
def _view(kind: str) -> tuple[Vector, Vector, Vector] | None:
    """(right, up, toward the viewer) unit vectors of the kind's view; None for plane ones."""
    if kind not in VIEWS:
        return None
    ca, sa = cos_sin_degrees(VIEWS[kind][0])
    ce, se = cos_sin_degrees(VIEWS[kind][1])
    return (-sa, ca, 0.0), (-se * ca, -se * sa, ce), (ce * ca, ce * sa, se)


def project(kind: str, point: Vector) -> Point:
    """The page position (x, y) of a 3-D point in the kind's view: plane linkages as they lie,
    the others by orthographic projection (VIEWS)."""
    view = _view(kind)
    if view is None:
        return (point[0], point[1])
    return (dot(point, view[0]), dot(point, view[1]))


def _along(p: Point, q: Point, t: float) -> Point:
    return (p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t)


def _page_normal(p: Point, q: Point) -> Point:
    """The unit normal to the left of the page segment p -> q ((0, 1) if it is a point)."""
    dx, dy = q[0] - p[0], q[1] - p[1]
    n = math.hypot(dx, dy)
    return (-dy / n, dx / n) if n else (0.0, 1.0)


def _shifted(p: Point, direction: Point, by: float) -> Point:
    return (p[0] + direction[0] * by, p[1] + direction[1] * by)


def _hatched(p: Point, q: Point, side: int, size: float) -> list[Stroke]:
    """The ground line p -> q (page points) hatched on its `side` (+1 left, -1 right)."""
    normal = _page_normal(p, q)
    length = math.dist(p, q)
    count = max(2, int(length / (0.45 * size)))
    tangent = ((q[0] - p[0]) / length, (q[1] - p[1]) / length) if length else (1.0, 0.0)
    hatch = []
    for i in range(count + 1):
        start = _along(p, q, i / count)
        end = (start[0] + side * normal[0] * 0.5 * size - tangent[0] * 0.5 * size,
               start[1] + side * normal[1] * 0.5 * size - tangent[1] * 0.5 * size)
        hatch.append(Stroke((start, end), "hatch"))
    return [Stroke((p, q), "ground")] + hatch


def _ground_symbol(at: Point, away: Point, size: float) -> list[Stroke]:
    """A fixed pivot as textbooks draw it: a triangle from the pivot `at` (page point) to a base
    `size` away in the unit direction `away`, the base hatched on its far side."""
    normal = (-away[1], away[0])
    base = _shifted(at, away, size)
    left, right = _shifted(base, normal, 0.6 * size), _shifted(base, normal, -0.6 * size)
    wide_left, wide_right = _shifted(base, normal, 0.9 * size), _shifted(base, normal, -0.9 * size)
    return [Stroke((left, at, right), "ground")] + _hatched(wide_left, wide_right, 1, size)


def _label_beside(p: Point, q: Point, text: str, size: float, side: float = 1.0) -> Label:
    """The letter of the link p -> q (page points), beside its middle on `side`."""
    return Label(_shifted(_along(p, q, 0.5), _page_normal(p, q), side * 0.7 * size), text, (p, q))


def _segments_cross(p: Point, q: Point, r: Point, s: Point) -> bool:
    """Whether the page segments p q and r s meet (touching counts)."""
    def turn(a: Point, b: Point, c: Point) -> float:
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    d1, d2, d3, d4 = turn(r, s, p), turn(r, s, q), turn(p, q, r), turn(p, q, s)
    if ((d1 > 0 and d2 < 0) or (d1 < 0 and d2 > 0)) and ((d3 > 0 and d4 < 0)
                                                         or (d3 < 0 and d4 > 0)):
        return True

    def on(a: Point, b: Point, c: Point) -> bool:    # c on the segment a b, given a, b, c in a line
        return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and \
            min(a[1], b[1]) <= c[1] <= max(a[1], b[1])
    return (d1 == 0 and on(r, s, p)) or (d2 == 0 and on(r, s, q)) or \
        (d3 == 0 and on(p, q, r)) or (d4 == 0 and on(p, q, s))


def _clearest(choices: list[list[Stroke]], links: list[Stroke], skip: int = 0) -> list[Stroke]:
    """Of `choices` (each a list of ground strokes: a symbol or a guide drawn one way), the
    first that no more than one more of `links` (the moving links' strokes over the sweep)
    cross than cross the clearest (a link that turns fully crosses equal choices one step more
    or less, as the sweep's steps fall); the first `skip` strokes of a choice not counted."""
    def crossings(strokes: list[Stroke]) -> int:
        counted = [(a, b) for s in strokes[skip:] for a, b in zip(s.points, s.points[1:])]
        x0, y0, x1, y1 = _extent([p for ab in counted for p in ab])
        return sum(any(_segments_cross(a, b, p, q) for p, q in zip(s.points, s.points[1:])
                       if min(p[0], q[0]) <= x1 and max(p[0], q[0]) >= x0
                       and min(p[1], q[1]) <= y1 and max(p[1], q[1]) >= y0
                       for a, b in counted) for s in links)
    counts = [crossings(strokes) for strokes in choices]
    return next(c for c, n in zip(choices, counts) if n <= min(counts) + 1)


def _pivot_symbol(at: Point, aways: Sequence[Point], links: list[Stroke], size: float
                  ) -> list[Stroke]:
    """The ground symbol at the fixed pivot `at` pointing the first of the unit directions
    `aways` whose base and hatching the links cross least: off the links' way where there is
    such a side."""
    return _clearest([_ground_symbol(at, away, size) for away in aways], links, skip=1)


def _guide(p: Point, q: Point, links: list[Stroke], size: float) -> list[Stroke]:
    """The slider's guide under the travel p -> q of the slider's centre (page points): a
    ground line along the block's side, hatched away from it, on the side (left, then right)
    that the links cross least."""
    normal = _page_normal(p, q)
    return _clearest([_hatched(_shifted(p, normal, side * 0.45 * size),
                               _shifted(q, normal, side * 0.45 * size), side, size)
                      for side in (1, -1)], links)


def _great_arc(p: Vector, q: Vector, steps: int = 24) -> list[Vector]:
    """Points along the shorter great-circle arc from p to q (unit vectors)."""
    angle = math.atan2(math.sqrt(sum(c * c for c in cross(p, q))), dot(p, q))
    if angle < 1e-12:
        return [p, q]
    s = math.sin(angle)
    out = []
    for i in range(steps + 1):
        t = i / steps
        wp, wq = math.sin((1 - t) * angle) / s, math.sin(t * angle) / s
        out.append(_vector(wp * a + wq * b for a, b in zip(p, q)))
    return out


def _circle_3d(centre: Vector, u: Vector, v: Vector, radius: float, steps: int = 72
               ) -> list[Vector]:
    """Points of the circle about `centre` in the plane of the unit vectors u, v."""
    out = []
    for i in range(steps + 1):
        c, s = cos_sin_degrees(360.0 * i / steps)
        out.append(_vector(m + radius * (c * a + s * b) for m, a, b in zip(centre, u, v)))
    return out


def _vector(components: Iterable[float]) -> Vector:
    """Three numbers as a Vector."""
    x, y, z = components
    return x, y, z


def _sphere_strokes(kind: str, points: list[Vector], style: str) -> list[Stroke]:
    """3-D points on the unit sphere as page strokes: `style` where they face the viewer, behind
    the sphere its FAR_SIDE style (a coupler curve's), else hidden."""
    view = _view(kind)
    assert view is not None                 # drawn in the spherical four-bar's view
    toward = view[2]
    strokes: list[Stroke] = []
    run: list[Point] = []
    front = None
    for p in points:
        facing = dot(p, toward) >= 0.0
        if run and facing != front:
            if len(run) > 1:                    # a lone point is no stroke
                strokes.append(Stroke(tuple(run), style if front
                                      else FAR_SIDE.get(style, "hidden")))
            run = run[-1:]
        run.append(project(kind, p))
        front = facing
    if len(run) > 1:
        strokes.append(Stroke(tuple(run), style if front else FAR_SIDE.get(style, "hidden")))
    return strokes


def _page_strokes(kind: str, points: list[Vector], style: str) -> list[Stroke]:
    return [Stroke(tuple(project(kind, p) for p in points), style)]


def _slider_block(centre: Point, direction: Point, size: float) -> Stroke:
    """The slider: a rectangle about `centre` (page) with its long side along `direction`."""
    n = math.hypot(*direction)
    t = (direction[0] / n, direction[1] / n) if n else (1.0, 0.0)
    w = (-t[1], t[0])
    corners = [(centre[0] + i * 0.8 * size * t[0] + j * 0.45 * size * w[0],
                centre[1] + i * 0.8 * size * t[1] + j * 0.45 * size * w[1])
               for i, j in ((-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1))]
    return Stroke(tuple(corners), "link")


# -- the five linkages on the page ----------------------------------------------------------------

def _dimension(p: Point, q: Point, text: str, size: float, side: float = 1.0
               ) -> tuple[list[Stroke], Label]:
    """A dimension line beside the page segment p -> q: the line, its end ticks, its letter."""
    normal = _page_normal(p, q)
    p1, q1 = _shifted(p, normal, side * 0.9 * size), _shifted(q, normal, side * 0.9 * size)
    ticks = [Stroke((_shifted(e, normal, -0.25 * size), _shifted(e, normal, 0.25 * size)),
                    "dimension") for e in (p1, q1)]
    return [Stroke((p1, q1), "dimension")] + ticks, _label_beside(p1, q1, text, size, side)


def _unit(v: Vector) -> Vector:
    n = math.sqrt(dot(v, v))
    return _vector(c / n for c in v)


_DOWN, _UP, _LEFT, _RIGHT = (0.0, -1.0), (0.0, 1.0), (-1.0, 0.0), (1.0, 0.0)


def _plane_ground(linkage: Linkage, poses: list[Pose], size: float, links: list[Stroke]) -> Layer:
    a0, b0 = (0.0, 0.0), (linkage.dims["a"], 0.0)
    strokes = _pivot_symbol(a0, (_DOWN, _UP, _LEFT), links, size)         # not across a
    strokes += _pivot_symbol(b0, (_DOWN, _UP, _RIGHT), links, size)
    strokes.append(Stroke((a0, b0), "ground"))
    turned = unwrapped([p.output for p in poses if p.output is not None] or [0.0], True)
    fully = max(turned) - min(turned) >= 359.0         # the output turns: B's path as A's
    for centre, radius in ((0.0, linkage.dims["b"]), (b0[0], linkage.dims["d"]))[:1 + fully]:
        strokes.append(Stroke(tuple(project(PLANE_FOUR_BAR, p) for p in _circle_3d(
            (centre, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), radius)), "path"))
    marks = (Mark(a0, "pivot", "A0"), Mark(b0, "pivot", "B0"))
    return Layer(tuple(strokes), marks, (_label_beside(a0, b0, "a", size, 0.6),))


def _slider_range(poses: list[Pose], linkage: Linkage, size: float) -> tuple[float, float]:
    """The page extent (along the guide) of the slider's travel, and a margin."""
    xs = [p.output for p in poses if p.output is not None] or [-linkage.dims["b"],
                                                                 linkage.dims["b"]]
    return min(xs) - 2.5 * size, max(xs) + 2.5 * size


def _slider_ground(linkage: Linkage, poses: list[Pose], size: float, links: list[Stroke]
                   ) -> Layer:
    e, b = linkage.dims["e"], linkage.dims["b"]
    lo, hi = _slider_range(poses, linkage, size)      # the guide along the slider's travel only:
    strokes = _pivot_symbol((0.0, 0.0), (_DOWN, _UP), links, size)  # not across the axis
    strokes += _guide((lo, e), (hi, e), links, size)
    strokes.append(Stroke(((-b - 2.5 * size, 0.0), (hi, 0.0)), "axis"))
    strokes.append(Stroke(tuple((b * c, b * s) for c, s in (
        cos_sin_degrees(5.0 * i) for i in range(73))), "path"))
    labels: list[Label] = []
    if e:
        left = -b - 0.6 * size                         # beside the crank's circle, lettered
        lines, label = _dimension((left, e), (left, 0.0), "e", size, -1.0)   # outside it
        strokes += lines
        labels.append(label)
    return Layer(tuple(strokes), (Mark((0.0, 0.0), "pivot", "A0"),), tuple(labels))


def _spherical_ground(linkage: Linkage, poses: list[Pose], size: float, links: list[Stroke]
                      ) -> Layer:
    kind = SPHERICAL_FOUR_BAR
    joints = poses[0].joints
    strokes = [Stroke(tuple(cos_sin_degrees(5.0 * i) for i in range(73)), "outline")]
    for name in ("A0", "B0"):
        axis = joints[name]
        strokes.append(Stroke((project(kind, _vector(-1.35 * c for c in axis)),
                               project(kind, _vector(1.35 * c for c in axis))), "axis"))
        at = project(kind, axis)
        out = math.degrees(math.atan2(at[1], at[0])) if math.hypot(*at) > 1e-9 else 90.0
        strokes += _pivot_symbol(at, [cos_sin_degrees(out + turn) for turn in (
            0.0, 40.0, -40.0, 80.0, -80.0)], links, size)     # off the sphere, the links' side
    strokes += _sphere_strokes(kind, _great_arc(joints["A0"], joints["B0"]), "ground")
    cb, sb = cos_sin_degrees(linkage.dims["b"])
    strokes += _sphere_strokes(kind, [(sb * c, sb * s, cb) for c, s in (
        cos_sin_degrees(5.0 * i) for i in range(73))], "path")
    labels = (_arc_label(kind, joints["A0"], joints["B0"], "a"),)
    marks = (Mark((0.0, 0.0), "pivot", "O"), Mark(project(kind, joints["A0"]), "pivot", "A0"),
             Mark(project(kind, joints["B0"]), "pivot", "B0"))
    return Layer(tuple(strokes), marks, labels)


def _arc_label(kind: str, p: Vector, q: Vector, text: str) -> Label:
    """The letter of the arc p q on the sphere: outside the sphere beside its middle."""
    middle = _great_arc(p, q, 2)[1]
    return Label(project(kind, _vector(1.15 * c for c in middle)), text,
                 tuple(project(kind, r) for r in _great_arc(p, q)))


def _skew_ground(linkage: Linkage, poses: list[Pose], size: float, links: list[Stroke]) -> Layer:
    """Both skew linkages: the input axis, the fixed link a (the common perpendicular, hatched),
    f along the input axis, the output axis or the slider's guide, and the angle ksi."""
    kind, dims = linkage.kind, linkage.dims
    joints, axes = poses[0].joints, poses[0].axes
    f, b = dims["f"], dims["b"]
    a0, f0, f1 = (project(kind, joints[n]) for n in ("A0", "F0", "F1"))
    reach = 4.0 * size
    strokes = _page_strokes(kind, [(0.0, 0.0, min(0.0, f) - reach),
                                   (0.0, 0.0, max(0.0, f) + reach)], "axis")
    strokes += _hatched(f0, f1, 1, size)
    lines, f_label = _dimension(a0, f0, "f", size, -1.0)
    strokes += lines
    strokes += _page_strokes(kind, _circle_3d((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0),
                                              b), "path")
    labels = [_label_beside(f0, f1, "a", size, -0.8), f_label]
    marks = [Mark(a0, "pivot", "A0")]
    point, direction = axes["output" if "output" in axes else "guide"]
    if kind == SKEW_FOUR_BAR:
        g = -f / cos_sin_degrees(dims["ksi"])[0]      # B0 = F1 + g w
        ts = (min(0.0, g) - reach, max(0.0, g) + reach)
        strokes += _page_strokes(kind, [_vector(p + t * w for p, w in zip(point, direction))
                                        for t in ts], "axis")
        b0 = project(kind, joints["B0"])
        lines, g_label = _dimension(f1, b0, "g", size, 1.0)
        strokes += lines
        labels.append(g_label)
        cx, sx = cos_sin_degrees(dims["ksi"])
        strokes += _page_strokes(kind, _circle_3d(joints["B0"], (1.0, 0.0, 0.0), (0.0, cx, sx),
                                                  dims["d"]), "path")
        marks.append(Mark(b0, "pivot", "B0"))
        upright = (0.0, 0.0, 1.0)
    else:
        lo, hi = _slider_range(poses, linkage, size)          # from F1 past the travel
        ends = [project(kind, _vector(p + t * w for p, w in zip(point, direction)))
                for t in (min(lo, -size), max(hi, size))]
        strokes.append(Stroke(tuple(ends), "axis"))
        strokes += _guide(ends[0], ends[1], links, size)
        upright = (0.0, 0.0, -1.0)
    # ksi: between the shaft (the guide) and a parallel to the input axis through F1
    strokes += _page_strokes(kind, [joints["F1"], _vector(p + 3.0 * size * u for p, u in zip(
        joints["F1"], upright))], "dimension")
    between = _unit(_vector(u + w for u, w in zip(upright, direction)))
    at = project(kind, _vector(p + 2.2 * size * u for p, u in zip(joints["F1"], between)))
    labels.append(Label(at, "ξ", (at,)))
    return Layer(tuple(strokes), tuple(marks), tuple(labels))


def _links(linkage: Linkage, pose: Pose, size: float) -> Layer:
    """The moving links of one pose: the crank b, the coupler c (c* for the plane slider's rod),
    the output crank d or the slider block, their pins and letters."""
    kind, joints = linkage.kind, pose.joints
    at = {name: project(kind, p) for name, p in joints.items()}
    output = PINS[kind].output_joint
    pairs = [("A0", "A", "b")]
    if output in joints:
        pairs.append(("A", output, "c*" if kind == PLANE_SLIDER_CRANK else "c"))
        if output == "B":
            pairs.append(("B0", "B", "d"))
    strokes: list[Stroke] = []
    labels: list[Label] = []
    for p, q, text in pairs:
        if kind == SPHERICAL_FOUR_BAR:
            strokes += _sphere_strokes(kind, _great_arc(joints[p], joints[q]), "link")
            labels.append(_arc_label(kind, joints[p], joints[q], text))
        else:
            strokes.append(Stroke((at[p], at[q]), "link"))
            labels.append(_label_beside(at[p], at[q], text, size))
    if output == "C" and output in joints:
        guide = pose.axes["guide"][1]
        strokes.append(_slider_block(at["C"], project(kind, guide), size))
    marks = tuple(Mark(at[n], "joint", n) for n in ("A", output) if n in joints)
    return Layer(tuple(strokes), marks, tuple(labels))


_GROUNDS = {PLANE_FOUR_BAR: _plane_ground, PLANE_SLIDER_CRANK: _slider_ground,
            SPHERICAL_FOUR_BAR: _spherical_ground, SKEW_FOUR_BAR: _skew_ground,
            SKEW_SLIDER_CRANK: _skew_ground}


def _frame(linkage: Linkage, pose: Pose, size: float, point: Vector | None = None,
           mu: float | None = None) -> Frame:
    """One pose's Frame; `point` the coupler point there (3-D) and mu the transmission angle, to
    be drawn and told when given. The caption names the crank's position: φ in [0, 360), though
    a sweep may run past a turn (a design's from its first position: 386.517 is 26.517)."""
    turned = pose.phi % 360.0
    where = f"φ = {0.0 if turned == 360.0 else turned:g}°"
    caption = where
    if pose.output is not None:
        caption += (f"  x = {pose.output:.4g}" if linkage.is_slider
                    else f"  ψ = {pose.output:.2f}°")
    if mu is not None:
        caption += f"  μ = {mu:.1f}°"
    message = {NOT_ASSEMBLED: f"not assembled at {where}",
               INDETERMINATE: f"the output link is free at {where} (indeterminate)",
               DEAD_CENTRE: f"dead centre at {where}"}.get(pose.status)
    layer = _links(linkage, pose, size)
    if point is not None:
        layer = _with_coupler_point(linkage, pose, layer, point)
    return Frame(pose, layer, caption, message)


def _with_coupler_point(linkage: Linkage, pose: Pose, layer: Layer, point: Vector) -> Layer:
    """The layer with the coupler point drawn on the coupler: a mark, joined to both pins (the
    coupler as the plate that carries it)."""
    kind = linkage.kind
    output = pose.joints[PINS[kind].output_joint]
    strokes: list[Stroke] = []
    for pin in (pose.joints["A"], output):
        if kind == SPHERICAL_FOUR_BAR:
            strokes += _sphere_strokes(kind, _great_arc(pin, point), "link")
        else:
            strokes.append(Stroke((project(kind, pin), project(kind, point)), "link"))
    return Layer(layer.strokes + tuple(strokes),
                 layer.marks + (Mark(project(kind, point), "point", "P"),), layer.labels)


def _with_marked(linkage: Linkage, ground: Layer, phis: Sequence[float],
                 branches: Sequence[int], size: float) -> Layer:
    """The ground with the linkage's moving links at each input angle of `phis` (on the branch
    of `branches` beside it) drawn faint ("marked") and numbered 1, 2, ... beyond the output
    pin (or the slider's pin)."""
    strokes, labels = list(ground.strokes), list(ground.labels)
    kind = linkage.kind
    for number, (phi, branch) in enumerate(zip(phis, branches), 1):
        pose = joint_positions(linkage, phi, branch)
        links = _links(linkage, pose, size)
        strokes += [s._replace(style="marked") for s in links.strokes]
        output = PINS[kind].output_joint
        if output in pose.joints:
            pin = project(kind, pose.joints[output])
            away = project(kind, pose.joints["A"]) if linkage.is_slider else \
                project(kind, pose.joints["B0"])
            direction = _page_normal(away, pin)          # along away -> pin: its normal's
            labels.append(Label(_shifted(pin, (direction[1], -direction[0]), 0.9 * size),
                                str(number)))
    return Layer(tuple(strokes), ground.marks, tuple(labels))


def _coupler_curves(linkage: Linkage, phis: Sequence[float], coupler: tuple[float, float],
                    motions: list[Motion], branch: int, traced: Sequence[int | str]
                    ) -> tuple[list[Stroke], list[Vector | None]]:
    """The coupler point's curve as page strokes, broken where the linkage does not assemble:
    "coupler" on the frames' `motions` (of `branch`), then "coupler-other" on each branch of
    `traced`, "coupler-follow" for the motion followed from `branch`; and the frames' points
    (3-D, None where there is none)."""
    strokes: list[Stroke] = []
    first: list[Vector | None] | None = None
    for other in (None, *traced):
        swept = motions if other is None else linkage.sweep(
            phis, other, 0, start=branch if other == FOLLOW else None)
        points = [c.position for c in coupler_of(linkage, swept, *coupler)]
        first = points if first is None else first
        style = ("coupler" if other is None else "coupler-follow" if other == FOLLOW
                 else "coupler-other")
        run: list[Vector] = []
        for p in [*points, None]:
            if p is not None:
                run.append(p)
                continue
            if len(run) > 1:
                strokes += (_sphere_strokes(linkage.kind, run, style)
                            if linkage.kind == SPHERICAL_FOUR_BAR
                            else _page_strokes(linkage.kind, run, style))
            run = []
    assert first is not None                # the frames' own motions come first
    return strokes, first


def _extent(points: Sequence[Point]) -> Box:
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return min(xs), min(ys), max(xs), max(ys)


# -- the letters: each beside what it names, where nothing drawn covers it -----------------------

# Strokes no letter may touch (with the marks and the other letters); the rest (axes, paths,
# curves, the sphere) a letter keeps off where it can.
_SOLID_STYLES = ("link", "ground", "hatch", "hidden", *FAR_SIDE.values())
_ALONG = (0.5, 0.38, 0.62, 0.26, 0.74, 0.14, 0.86)   # where along what it names a letter may go
# The spots beside it, cheapest first: (cost, where along, how far out, other side or not).
_BESIDE = sorted((step + 0.4 * other + 3.0 * abs(along - 0.5), along, step, other)
                 for along in _ALONG for step in range(4) for other in (False, True))
_AROUND = tuple((math.cos(math.pi * k / 8), math.sin(math.pi * k / 8)) for k in range(16))


# A stroke's segment for place_labels: its box (left, bottom, right, top), its ends x0, y0, x1,
# y1, and whether it is solid.
Segment = tuple[float, float, float, float, float, float, float, float, bool]


def stroke_segments(strokes: Iterable[Stroke]) -> list[Segment]:
    """The strokes as segments for place_labels: (left, bottom, right, top) of each, its ends
    x0, y0, x1, y1, and whether it is solid."""
    return [(min(p[0], q[0]), min(p[1], q[1]), max(p[0], q[0]), max(p[1], q[1]),
             p[0], p[1], q[0], q[1], s.style in _SOLID_STYLES)
            for s in strokes for p, q in zip(s.points, s.points[1:])]


def _box_meets_segment(box: Box, x0: float, y0: float, x1: float, y1: float) -> bool:
    """Whether the segment (x0, y0) (x1, y1) enters the box (left, bottom, right, top):
    Liang-Barsky clipping."""
    dx, dy, t0, t1 = x1 - x0, y1 - y0, 0.0, 1.0
    for p, q in ((-dx, x0 - box[0]), (dx, box[2] - x0), (-dy, y0 - box[1]), (dy, box[3] - y0)):
        if p == 0.0:
            if q < 0.0:
                return False
        elif p < 0.0:
            t0 = max(t0, q / p)
        else:
            t1 = min(t1, q / p)
        if t0 > t1:
            return False
    return True


def _spots(label: Label, letters: Letters, n: int
           ) -> tuple[Iterator[tuple[float, Point]], tuple[float, float]]:
    """Where the label may go, as (cost, centre) nearest first - beside what it names, on both
    sides of it at points along it, then on rings about its middle - and how far from it the
    nearest (the first rows out) and all of them reach."""
    import heapq
    names = label.names or (label.at,)
    hw, hh = n * letters.width / 2, letters.height / 2
    gap = 0.35 * letters.height + letters.line
    ends: list[tuple[Point, Point]] = []
    if len(names) > 1:
        ends = list(zip(names, names[1:]))
        lengths = [math.dist(p, q) for p, q in ends]
        total = sum(lengths) or 1.0
        middle, first = _along(*ends[len(ends) // 2], 0.5 if len(ends) % 2 else 0.0), 2.0
    else:
        middle, first = names[0], 0.0

    @functools.cache
    def place(along: float) -> tuple[Point, Point, float, float]:
        """The point `along` the way, its normal, the box's reach along it, the first side."""
        left, i = along * total, 0
        while i < len(ends) - 1 and left > lengths[i]:
            left, i = left - lengths[i], i + 1
        p, q = ends[i]
        at = _along(p, q, left / lengths[i] if lengths[i] else 0.0)
        normal = _page_normal(p, q)
        side = 1.0 if (label.at[0] - at[0]) * normal[0] + (label.at[1] - at[1]) * normal[1] \
            >= 0 else -1.0                                     # the side it was put on first
        return at, normal, hw * abs(normal[0]) + hh * abs(normal[1]), side

    def beside() -> Iterator[tuple[float, Point]]:
        for cost, along, step, other in _BESIDE if ends else ():
            at, normal, reach, side = place(along)
            yield cost, _shifted(at, normal, (-side if other else side) * (
                reach + gap * (1 + 1.3 * step)))

    def rings() -> Iterator[tuple[float, Point]]:
        for step in range(8):
            rx, ry = hw + gap * (1 + 1.3 * step), hh + gap * (1 + 1.3 * step)
            yield from ((first + step, (middle[0] + c * rx, middle[1] + s * ry))
                        for c, s in _AROUND)
    return heapq.merge(beside(), rings(), key=lambda spot: spot[0]), (hw + hh + gap * 5.0,
                                                                        hw + hh + gap * 10.2)


def _within(box: Box, region: Box, margin: float) -> bool:
    return (region[0] < box[0] - margin and region[1] < box[1] - margin
            and box[2] + margin < region[2] and box[3] + margin < region[3])


def place_labels(labels: Iterable[Label], segments: list[Segment], marks: Iterable[Mark],
                 letters: Letters, bounds: Box,
                 snap: Callable[[Point, int], Point] | None = None) -> tuple[Label, ...]:
    """The labels placed in turn, each where it touches the fewest things drawn: first no mark,
    solid stroke (link, ground, hatching, a hidden link) or letter placed before it, nor the
    bounds' edge; then the fewest other strokes; then the nearest to what it names (_spots).
    segments from stroke_segments(); snap(centre, n) moves the centre of a box n characters
    wide onto the renderer's grid (the terminal's cells), marks included."""
    snap = snap or _unmoved
    reach = max(letters.mark, letters.line)
    discs = [snap(m.at, 1) for m in marks]
    placed: list[Label] = []
    boxes: list[Box] = []
    for label in labels:
        n = len(label.text)
        hw, hh = n * letters.width / 2, letters.height / 2
        spots, reaches = _spots(label, letters, n)
        x0, y0, x1, y1 = _extent(label.names or (label.at,))
        regions = [(x0 - out, y0 - out, x1 + out, y1 + out) for out in (
            r + hw + hh + 2 * reach + letters.width + letters.height for r in reaches)]
        region: Box = (math.inf, math.inf, math.inf, math.inf)
        near: list[Segment] = []                # the segments near the spots tried so far
        best, best_at, best_box = None, label.at, None
        for cost, at in spots:
            if best is not None and cost >= best:
                break
            cx, cy = snap(at, n)
            box = (cx - hw, cy - hh, cx + hw, cy + hh)
            if not _within(box, region, reach):
                while regions and not _within(box, regions[0], reach):
                    regions.pop(0)
                region = regions.pop(0) if regions else (-math.inf, -math.inf, math.inf, math.inf)
                near = [s for s in segments if s[0] <= region[2] and s[2] >= region[0]
                        and s[1] <= region[3] and s[3] >= region[1]]
            solid = int(box[0] < bounds[0] or box[1] < bounds[1] or box[2] > bounds[2]
                        or box[3] > bounds[3])
            solid += sum(box[0] - letters.mark < mx < box[2] + letters.mark
                         and box[1] - letters.mark < my < box[3] + letters.mark
                         and math.hypot(max(box[0] - mx, 0.0, mx - box[2]),
                                        max(box[1] - my, 0.0, my - box[3])) < letters.mark
                         for mx, my in discs)
            apart = letters.width / 2                   # letters side by side read as a word
            solid += sum(box[0] < b[2] + apart and b[0] < box[2] + apart and box[1] < b[3]
                         and b[1] < box[3] for b in boxes)
            wide = (box[0] - letters.line, box[1] - letters.line, box[2] + letters.line,
                    box[3] + letters.line)
            other = 0
            for left, bottom, right, top, sx0, sy0, sx1, sy1, hard in near:
                if (left <= wide[2] and right >= wide[0] and bottom <= wide[3]
                        and top >= wide[1] and _box_meets_segment(wide, sx0, sy0, sx1, sy1)):
                    if hard:
                        solid += 1
                    else:
                        other += 1
            score = 1000.0 * solid + other + cost
            if best is None or score < best:
                best, best_at, best_box = score, (cx, cy), box
        assert best_box is not None             # the rings' spots never run out
        boxes.append(best_box)
        placed.append(label._replace(at=best_at))
    return tuple(placed)


def _unmoved(p: Point, n: int) -> Point:
    """place_labels' snap where there is no grid."""
    return p


def mechanism_drawing(linkage: Linkage, phis: Sequence[float], branch: int = 1,
                      title: str | None = None, subtitle: str | None = None,
                      coupler: tuple[float, float] | None = None,
                      traced: Sequence[int | str] = (), marked: Sequence[float] = (),
                      marked_branches: Sequence[int] = (),
                      extra: Sequence[tuple[Stroke, ...]] = (),
                      poses: Sequence[Pose] | None = None) -> Drawing:
    """The linkage drawn at each input angle of `phis` (degrees) on `branch`: one Frame a pose
    over the ground, in the kind's view (plane: the xy plane; spherical and skew: VIEWS).

    coupler (u, v): the point of Linkage.coupler drawn on the coupler in each frame, its curve
    traced over the sweep on `branch` and on each branch of `traced` (FOLLOW: the motion
    followed from `branch`), each in a style of its own, and the transmission angle told in each
    caption and charted along the sweep (Drawing.chart). marked: input angles at which the
    linkage is drawn faint under every frame, numbered 1, 2, ... at the output (a design's
    positions), each on its branch of marked_branches (`branch` where none is given). extra:
    strokes drawn on each frame, a tuple a pose (force_arrows'), its letters placed clear of
    them. poses: the poses drawn (pose_at's, one an angle of `phis`) instead of the engine's on
    `branch`."""
    kind = linkage.kind
    if coupler is not None:
        coupler = check_coupler_point(linkage, *coupler)
    for key in ("a", "b", "c", "d"):
        value = linkage.dims.get(key)
        if value is None:
            continue
        if kind == SPHERICAL_FOUR_BAR and not 0 < value < 180:
            raise ValueError(f"the arc {key} = {value:g} degrees cannot be drawn: arcs are "
                             "drawn between 0 and 180 degrees")
        skew_offset = key == "a" and kind in (SKEW_FOUR_BAR, SKEW_SLIDER_CRANK)
        if kind != SPHERICAL_FOUR_BAR and not (
                value != 0 if skew_offset else value > 0):   # a skew linkage's a is signed
            raise ValueError(f"{DIMENSION_NAMES[key]} {key} = {value:g} cannot be drawn: "
                             + ("the fixed link is drawn along the common perpendicular, which "
                                "needs a != 0" if skew_offset else
                                "links are drawn with lengths greater than 0"))
    poses = [joint_positions(linkage, phi, branch) for phi in phis] if poses is None \
        else list(poses)
    if not poses:
        raise ValueError("a drawing needs at least one input angle")
    x0, y0, x1, y1 = _extent([project(kind, p) for pose in poses for p in pose.joints.values()])
    span = max(x1 - x0, y1 - y0, 2.0 if kind == SPHERICAL_FOUR_BAR else 1e-300)
    lengths = [abs(v) for k, v in linkage.dims.items() if k in "abcd" and v]
    size = 0.07 * span if kind == SPHERICAL_FOUR_BAR else max(          # symbols not hiding a
        0.035 * span, min(0.07 * span, 0.6 * min(lengths)))             # short crank
    points: list[Vector | None] = [None] * len(poses)
    mus: list[float | None] = [None] * len(poses)
    chart = None
    curves: list[Stroke] = []
    if coupler is not None:
        motions = [Motion(pose.phi, pose.output, None, None, pose.status) for pose in poses]
        curves, points = _coupler_curves(linkage, phis, coupler, motions, branch, traced)
        mus = transmission_of(linkage, motions)
        chart = tuple((pose.phi, mu) for pose, mu in zip(poses, mus))
    unplaced = [_frame(linkage, pose, size, point, mu)
                for pose, point, mu in zip(poses, points, mus)]
    links = [s for i in spread_indices(len(unplaced), 120) for s in unplaced[i].layer.strokes]
    ground = _GROUNDS[kind](linkage, poses, size, links)
    if marked:
        ground = _with_marked(linkage, ground, marked, list(marked_branches)
                              + [branch] * (len(marked) - len(marked_branches)), size)
    ground = Layer(ground.strokes + tuple(curves), ground.marks, ground.labels)
    unplaced = [f._replace(layer=f.layer._replace(strokes=f.layer.strokes + more))
                for f, more in zip(unplaced, [*extra, *[()] * len(unplaced)])]
    drawn = [p for layer in [ground] + [f.layer for f in unplaced]
             for p in [q for s in layer.strokes for q in s.points]
             + [m.at for m in layer.marks] + [label.at for label in layer.labels]]
    x0, y0, x1, y1 = _extent(drawn)
    bounds = (x0 - size, y0 - size, x1 + size, y1 + size)
    letters = svg_letters(bounds, size)
    ground_segments = stroke_segments(ground.strokes)
    frames = tuple(f._replace(layer=f.layer._replace(labels=place_labels(
        f.layer.labels + ground.labels, ground_segments + stroke_segments(f.layer.strokes),
        ground.marks + f.layer.marks, letters, bounds))) for f in unplaced)
    ground = ground._replace(labels=())
    if title is None:
        title = (KIND_NAMES[kind] + ": "
                 + " ".join(f"{'ξ' if k == 'ksi' else k}={v:g}" for k, v in linkage.dims.items()))
    if subtitle is None:
        subtitle = f"branch {branch} ({'A+B' if branch == 1 else 'A-B'})"
    if coupler is not None:
        others = "".join(", followed" if b == FOLLOW else f", branch {b}" for b in traced)
        subtitle += f"; P({coupler[0]:g}, {coupler[1]:g}) traced on branch {branch}{others}"
    return Drawing(title, subtitle, kind, ground, frames, bounds, size, letters, chart,
                   tuple(points) if coupler is not None else ())


def spread_indices(count: int, wanted: int) -> list[int]:
    """`wanted` indices spread evenly over range(count), from 0 (all of them, if no more)."""
    return list(range(count)) if wanted >= count else [i * count // wanted
                                                       for i in range(wanted)]


# -- the SVG -------------------------------------------------------------------------------------
# One self-contained file a browser plays with no script: each frame a group whose visibility a
# SMIL <animate> switches in turn. Without animation (a static viewer) the first frame with the
# linkage in it is the one visible. Page points are turned into SVG pixels here, y down, so that
# text is never mirrored; the root's data-scale and data-origin say how (svg = origin + scale *
# (x, -y)).

SVG_WIDTH = 800
SVG_HEIGHT = 640                # the most the drawing itself takes, in pixels
SVG_MARGIN = 16
SVG_LETTER = 19                 # the letters' font size, in pixels


def svg_scale(bounds: Box) -> float:
    """SVG pixels a page unit: the bounds fitted in SVG_WIDTH less the margins by SVG_HEIGHT."""
    x0, y0, x1, y1 = bounds
    return min((SVG_WIDTH - 2 * SVG_MARGIN) / max(x1 - x0, 1e-300),
               SVG_HEIGHT / max(y1 - y0, 1e-300))


def svg_radius(size: float, scale: float) -> float:
    """A joint's circle, in pixels, for ground symbols of `size` page units."""
    return max(3.0, min(7.0, 0.16 * size * scale))


def svg_letters(bounds: Box, size: float) -> Letters:
    """How big the SVG of a drawing within `bounds` draws letters, marks and lines, in page
    units: a letter's box 0.6 by 0.8 of its font size, a mark's circle with its edge, the
    links' half width."""
    scale = svg_scale(bounds)
    return Letters(0.6 * SVG_LETTER / scale, 0.8 * SVG_LETTER / scale,
                   (svg_radius(size, scale) + 1.0) / scale, 1.6 / scale)


# ---- 18. The mechanism's renderers: terminal, SVG, PNG and DXF -----------------------------------
#
# Holds: what draws a Drawing: the terminal (Unicode braille, or ASCII; still or animated until a
# key), an animated SVG, a PNG (matplotlib); and the DXF of its linkage for CAD (ezdxf). The SVG's
# letters are those placed in the Drawing; the terminal and the PNG place them again for the sizes
# they draw letters at.
#
# Uses: sections 1, 2, 6, 7, 8 and 17.
# Offers: text_drawing, frame_seconds, show_drawing, svg_drawing, PlotUnavailable,
#   matplotlib_canvas, png_drawing, DXF_LINKS, DXF_POSITIONS, dxf_module, dxf_drawing.


# -- the terminal view ---------------------------------------------------------------------------
# Drawn on a grid of dots: Unicode braille (2 x 4 dots a character, about square on a terminal),
# or plain ASCII where the output cannot take Unicode (a character a dot, twice as tall as wide).
# Marks and letters are characters over the dots. On a terminal the frames are redrawn in place.

# Strokes drawn first to last (later ones win a shared ASCII cell), and each style's dash
# pattern in dots along the stroke (on, off, ...); styles not listed are solid.
_TEXT_ORDER = ("outline", "path", "axis", "dimension", "marked", "hidden", "coupler-follow",
               "coupler-other", "coupler", "hatch", "ground", "link", "force")
_FAR_STYLES = frozenset(FAR_SIDE.values())     # drawn as hidden in text: dots carry no colour


def _text_style(style: str) -> str:
    """The style a stroke is drawn in as text (and ordered by in every renderer)."""
    return "hidden" if style in _FAR_STYLES else style
_TEXT_DASHES = {"outline": (1, 1), "path": (1, 2), "axis": (4, 2, 1, 2), "dimension": (1, 1),
                "coupler-other": (3, 3), "coupler-follow": (1, 2),
                "hidden": (2, 2), "marked": (1, 1)}
_BRAILLE_BITS = ((0x01, 0x02, 0x04, 0x40), (0x08, 0x10, 0x20, 0x80))    # [column][row]
_TEXT_MARKS = {True: {"joint": "●", "pivot": "◉", "point": "◆"},
               False: {"joint": "o", "pivot": "@", "point": "*"}}
_ASCII_TEXT = str.maketrans({"φ": "phi", "ψ": "psi", "ξ": "ksi", "μ": "mu", "°": " deg"})


def _plain(text: str, unicode: bool) -> str:
    """text as the output can show it: ASCII spells the Greek letters out."""
    if unicode:
        return text
    return text.translate(_ASCII_TEXT).encode("ascii", "replace").decode("ascii")


def _dash_on(dashes: tuple[int, ...], distance: float) -> bool:
    """Whether a dash pattern (on, off, on, ...) is on at `distance` dots along its stroke."""
    at = distance % sum(dashes)
    for i, run in enumerate(dashes):
        if at < run:
            return i % 2 == 0
        at -= run
    return False


def _ascii_line(dx: float, dy: float) -> str:
    """The ASCII character of a line going dx right and dy down (in square units)."""
    angle = math.degrees(math.atan2(-dy, dx)) % 180.0
    return "-" if angle < 22.5 or angle > 157.5 else "|" if 67.5 < angle < 112.5 else \
        "/" if angle < 90.0 else "\\"


class _DotGrid:
    """cols x rows characters of dots, the page's bounds fitted in with their aspect kept."""

    def __init__(self, cols: int, rows: int, bounds: Box, unicode: bool) -> None:
        self.cols, self.rows, self.unicode = cols, rows, unicode
        self.per_col, self.per_row = (2, 4) if unicode else (1, 1)
        self.aspect = 1.0 if unicode else 2.0            # a dot's height over its width
        width, height = cols * self.per_col - 1, rows * self.per_row - 1
        x0, y0, x1, y1 = bounds
        self.scale = min(width / max(x1 - x0, 1e-300),
                         height * self.aspect / max(y1 - y0, 1e-300))
        self.left = (width - (x1 - x0) * self.scale) / 2 - x0 * self.scale
        down = self.scale / self.aspect                  # page units to dots, vertically
        self.top = (height - (y1 - y0) * down) / 2 + y1 * down
        self.dots: dict[tuple[int, int], str] = {}     # (x, y) -> the ASCII character there
        self.chars: dict[tuple[int, int], str] = {}    # (col, row) -> a character over the dots

    def dot(self, p: Point) -> Point:
        """The dot (x right, y down, not rounded) of page point p."""
        return p[0] * self.scale + self.left, self.top - p[1] * self.scale / self.aspect

    def stroke(self, stroke: Stroke) -> None:
        style = _text_style(stroke.style)
        dashes = _TEXT_DASHES.get(style)
        travelled = 0.0
        for p, q in zip(stroke.points, stroke.points[1:]):
            (x0, y0), (x1, y1) = self.dot(p), self.dot(q)
            dx, dy = x1 - x0, (y1 - y0) * self.aspect
            length = math.hypot(dx, dy)
            char = {"path": ".", "outline": ".", "coupler": "*", "coupler-other": "+",
                    "coupler-follow": ":"}.get(style) or _ascii_line(dx, dy)
            steps = max(1, math.ceil(2 * max(abs(x1 - x0), abs(y1 - y0))))
            for i in range(steps + 1):
                if dashes is None or _dash_on(dashes, travelled + i / steps * length):
                    self.dots[round(x0 + i / steps * (x1 - x0)),
                              round(y0 + i / steps * (y1 - y0))] = char
            travelled += length

    def cell(self, p: Point, n: int = 1) -> tuple[int, int]:
        """The first (col, row) of the n character cells nearest to centred on page point p."""
        x, y = self.dot(p)
        return (math.floor((x + 0.5) / self.per_col - n / 2 + 0.5),
                math.floor((y + 0.5) / self.per_row))

    def snap(self, p: Point, n: int = 1) -> Point:
        """The page point at the middle of the n cells that cell(p, n) begins."""
        col, row = self.cell(p, n)
        x, y = (col + n / 2) * self.per_col - 0.5, (row + 0.5) * self.per_row - 0.5
        return (x - self.left) / self.scale, (self.top - y) * self.aspect / self.scale

    def letters(self) -> Letters:
        """A character cell as place_labels sees it: a letter fills one, a mark stands in
        one, a line is a dot wide."""
        return Letters(self.per_col / self.scale, self.per_row * self.aspect / self.scale,
                       0.45 * self.per_col / self.scale, 0.5 / self.scale)

    def put(self, p: Point, text: str) -> None:
        """text centred on the character cells of page point p (what falls outside is cut)."""
        col, row = self.cell(p, len(text))
        for i, ch in enumerate(text):
            if 0 <= col + i < self.cols and 0 <= row < self.rows:
                self.chars[col + i, row] = ch

    def lines(self) -> list[str]:
        cells: dict[tuple[int, int], int] = {}
        for (x, y), char in self.dots.items():
            cell = (x // self.per_col, y // self.per_row)
            if self.unicode:
                cells[cell] = cells.get(cell, 0x2800) | _BRAILLE_BITS[x % 2][y % 4]
            else:
                cells[cell] = ord(char)
        cells.update((cell, ord(ch)) for cell, ch in self.chars.items())
        return ["".join(chr(cells.get((col, row), 32)) for col in range(self.cols)).rstrip()
                for row in range(self.rows)]


def text_drawing(drawing: Drawing, index: int = 0, width: int = 80, height: int = 24,
                 unicode: bool = True, footer: str = "") -> str:
    """Frame `index` of the drawing as `height` lines of at most `width` characters: the title
    and subtitle, the linkage over its ground, and the frame's caption (or its message, where
    the linkage is not there to draw) followed by `footer`."""
    width, height = max(width, 20), max(height, 8)
    frame = drawing.frames[index]
    grid = _DotGrid(width, height - 3, drawing.bounds, unicode)
    strokes = [s for s in drawing.ground.strokes + frame.layer.strokes       # hatching too fine
               if s.style != "hatch" or math.dist(*s.points[:2]) * grid.scale >= 3.0]  # is a blot
    for stroke in sorted(strokes, key=lambda s: _TEXT_ORDER.index(_text_style(s.style))):
        grid.stroke(stroke)
    marks = drawing.ground.marks + frame.layer.marks
    labels = [label._replace(text=_plain(label.text, unicode)) for label in frame.layer.labels]
    for label in place_labels(labels, stroke_segments(strokes), marks, grid.letters(),
                              drawing.bounds, grid.snap):
        grid.put(label.at, label.text)
    for mark in marks:
        grid.put(mark.at, _TEXT_MARKS[unicode][mark.kind])
    bottom = frame.message or frame.caption
    lines = [drawing.title, drawing.subtitle] + grid.lines() + [bottom + footer]
    return "\n".join(_plain(line, unicode)[:width] for line in lines)


def _still_frames(drawing: Drawing, frames: int | None) -> list[int]:
    """The frames printed one after another: the first with the linkage there, or `frames`
    spread evenly over the drawing."""
    if frames is None:
        return [next((i for i, f in enumerate(drawing.frames) if f.message is None), 0)]
    return spread_indices(len(drawing.frames), frames)


def frame_seconds(count: int) -> float:
    """How long each of `count` frames shows when animated: 12 a second, but a turn of a few
    positions (a design's) slow enough to see each, up to 0.6 s a frame."""
    return max(1.0 / 12.0, min(0.6, 3.0 / count))


def show_drawing(drawing: Drawing, out: TextIO | None = None, frames: int | None = None,
                 fps: float | None = None, unicode: bool | None = None) -> int:
    """The drawing on `out` (standard output): animated in place on a terminal, at `fps` frames
    a second (1 / the drawing's seconds, else 1 / frame_seconds()), until q (exit status 0) or Ctrl-C (KeyboardInterrupt);
    otherwise, or with `frames`, still frames one after another. ASCII where out's encoding is
    not UTF-8."""
    out = sys.stdout if out is None else out
    if unicode is None:
        unicode = (getattr(out, "encoding", None) or "").lower().replace("-", "") == "utf8"
    if frames is None and len(drawing.frames) > 1 and out.isatty():
        return _animate(drawing, out, fps or 1.0 / (drawing.seconds
                                                    or frame_seconds(len(drawing.frames))),
                        unicode)
    width, height = shutil.get_terminal_size() if out.isatty() else _text_size()
    out.write("\n\n".join(text_drawing(drawing, i, width, height, unicode)
                          for i in _still_frames(drawing, frames)) + "\n")
    out.flush()
    return 0


def _text_size() -> tuple[int, int]:
    """The still frames' size where the output is not a terminal: COLUMNS x LINES, or 80 x 24."""
    sizes = []
    for name, default in (("COLUMNS", 80), ("LINES", 24)):
        text = os.environ.get(name, "")
        sizes.append(int(text) if text.isdigit() and int(text) > 0 else default)
    return sizes[0], sizes[1]


def _animate(drawing: Drawing, out: TextIO, fps: float, unicode: bool,
             clock: Callable[[], float] | None = None,
             key_within: Callable[[int | None, float | None], bytes | None] | None = None) -> int:
    """The frames redrawn in place on the terminal's alternate screen until q (or Ctrl-C), the
    last one shown left on the screen afterwards; the space bar pauses. In real time: each frame
    drawn is the one due at the clock's time, `fps` frames a second from the start (or the
    pause's end), so where drawing falls behind, frames are dropped rather than the motion
    slowed. clock and key_within: time.monotonic and _key_within unless a test gives its own."""
    import time
    clock = clock or time.monotonic
    key_within = key_within or _key_within
    keys = sys.stdin.fileno() if sys.stdin.isatty() else None
    shown, paused = _still_frames(drawing, None)[0], False

    def draw() -> None:
        width, height = shutil.get_terminal_size()
        footer = "   (q quits, space pauses)" if keys is not None else "   (Ctrl-C stops)"
        text = text_drawing(drawing, shown, width, height, unicode, footer)
        out.write("\x1b[H" + text.replace("\n", "\x1b[K\n") + "\x1b[K\x1b[J")
        out.flush()

    start = 0.0                             # when the frame `first` below was due

    def enter() -> None:
        nonlocal start
        out.write("\x1b[?1049h\x1b[?25l")
        start = clock()
        draw()

    def leave() -> None:
        out.write("\x1b[?25h\x1b[?1049l")
        out.flush()

    with single_keys(keys, enter, leave):                # enter() draws the first frame
        index = first = shown               # frames counted on past the last (shown: modulo)
        while True:
            due = start + (index - first + 1) / fps
            key = key_within(keys, None if paused else max(0.0, due - clock()))
            if key in (b"q", b"Q", b""):
                break
            if key == b" ":
                paused = not paused
                start, first = clock(), index
            elif key is None:
                index = max(index + 1, first + math.floor((clock() - start) * fps))
                shown = index % len(drawing.frames)
                draw()
    width, height = shutil.get_terminal_size()
    out.write(text_drawing(drawing, shown, width, height, unicode) + "\n")
    out.flush()
    return 0


def _key_within(fd: int | None, seconds: float | None) -> bytes | None:
    """The next key (one byte; b"" once the terminal is gone) typed on fd within `seconds`
    (None: however long it takes), or None; with no terminal to read, None after `seconds`."""
    import select
    if fd is None:
        import time
        assert seconds is not None          # no terminal, no key: never paused
        time.sleep(seconds)
        return None
    if select.select([fd], [], [], seconds)[0]:
        return os.read(fd, 1)
    return None


_SVG_STYLE = """
polyline{fill:none;stroke-linecap:round;stroke-linejoin:round}
polyline.link{stroke:#1b1b1b;stroke-width:3.2}
polyline.ground{stroke:#1b1b1b;stroke-width:1.8}
polyline.hatch{stroke:#555;stroke-width:1}
polyline.axis{stroke:#2f6db3;stroke-width:1.1;stroke-dasharray:14 4 2 4}
polyline.path{stroke:#8a8a8a;stroke-width:1.2;stroke-dasharray:1 4}
polyline.hidden{stroke:#6a6a6a;stroke-width:2;stroke-dasharray:6 4}
polyline.outline{stroke:#b5b5b5;stroke-width:1.3}
polyline.dimension{stroke:#7a7a7a;stroke-width:0.9}
polyline.coupler{stroke:#c0392b;stroke-width:2}
polyline.coupler-other{stroke:#e67e22;stroke-width:1.6}
polyline.coupler-follow{stroke:#8e44ad;stroke-width:2.4}
polyline.coupler-far{stroke:#c0392b;stroke-width:1.4;stroke-dasharray:6 4}
polyline.coupler-other-far{stroke:#e67e22;stroke-width:1.2;stroke-dasharray:6 4}
polyline.coupler-follow-far{stroke:#8e44ad;stroke-width:1.6;stroke-dasharray:6 4}
polyline.marked{stroke:#2e8b57;stroke-width:2;stroke-opacity:0.7}
polyline.force{stroke:#d35400;stroke-width:2.2}
polyline.chart{stroke:#2f6db3;stroke-width:1.6}
polyline.grid{stroke:#ccc;stroke-width:1}
.joint,.pivot{fill:#fff;stroke:#1b1b1b;stroke-width:2}
.point{fill:#c0392b;stroke:#1b1b1b;stroke-width:1.5}
.tick{font:12px 'DejaVu Sans',Arial,sans-serif;fill:#555}
.pivot{fill:#d8d8d8}
.label{font:italic %dpx 'DejaVu Serif',Georgia,serif;fill:#1b1b1b;text-anchor:middle;
dominant-baseline:central}
.title{font:bold 16px 'DejaVu Sans',Arial,sans-serif;fill:#1b1b1b}
.subtitle{font:13px 'DejaVu Sans',Arial,sans-serif;fill:#555}
.caption{font:15px 'DejaVu Sans',Arial,sans-serif;fill:#1b1b1b;white-space:pre}
.legend{font:12px 'DejaVu Sans',Arial,sans-serif}
.message{font:bold 17px 'DejaVu Sans',Arial,sans-serif;fill:#b3001b}
""" % SVG_LETTER


class _SvgPage(NamedTuple):
    """How page points become SVG pixels: (left + scale x, top - scale y)."""
    scale: float
    left: float
    top: float

    def xy(self, p: Point) -> str:
        return f"{self.left + self.scale * p[0]:.1f},{self.top - self.scale * p[1]:.1f}"

    def attrs(self, p: Point, x: str = "x", y: str = "y") -> str:
        return (f'{x}="{self.left + self.scale * p[0]:.1f}" '
                f'{y}="{self.top - self.scale * p[1]:.1f}"')


def _svg_layer(page: _SvgPage, layer: Layer, size: float) -> list[str]:
    out = [f'<polyline class="{s.style}" points="{" ".join(page.xy(p) for p in s.points)}"/>'
           for s in sorted(layer.strokes,
                           key=lambda s: _TEXT_ORDER.index(_text_style(s.style)))]
    radius = svg_radius(size, page.scale)
    out += [f'<circle class="{m.kind}" data-joint="{m.name}" {page.attrs(m.at, "cx", "cy")} '
            f'r="{radius:.1f}"/>' for m in layer.marks]
    out += [f'<text class="label" {page.attrs(label.at)}>{_xml(label.text)}</text>'
            for label in layer.labels]
    return out


_SVG_CHART_HEIGHT = 170         # pixels under the drawing for the transmission angle's chart


class _SvgChart(NamedTuple):
    """The transmission angle's chart under an SVG drawing: its static lines, and where a
    (phi, mu) point is in pixels."""
    lines: list[str]
    x: Callable[[float], float]
    y: Callable[[float], float]


def _svg_chart(chart: Sequence[tuple[float, float | None]], top: float, width: float,
               margin: float) -> _SvgChart:
    """mu from 0 to 180 degrees against the sweep's input angles, 130 pixels tall from `top`."""
    phis = [phi for phi, _ in chart]
    lo, hi = min(phis), max(phis)
    left, right, bottom = margin + 70, width - margin - 10, top + 130

    def x(phi: float) -> float:
        return left + (right - left) * ((phi - lo) / (hi - lo) if hi > lo else 0.5)

    def y(mu: float) -> float:
        return bottom - (bottom - top) * mu / 180.0

    lines = [f'<polyline class="grid" points="{left},{y(v):.1f} {right},{y(v):.1f}"/>'
             for v in (0.0, 90.0, 180.0)]
    lines += [f'<text class="tick" x="{left - 6}" y="{y(v) + 4:.1f}" text-anchor="end">{v:g}°'
              "</text>" for v in (0.0, 90.0, 180.0)]
    lines.append(f'<text class="tick" x="{margin}" y="{top + 70}">μ</text>')
    lines.append(f'<text class="tick" x="{left}" y="{bottom + 16}">φ = {lo:g}°</text>')
    lines.append(f'<text class="tick" x="{right}" y="{bottom + 16}" text-anchor="end">'
                 f'{hi:g}°</text>')
    for run in _chart_runs(chart):
        if len(run) > 1:
            points = " ".join(f"{x(phi):.1f},{y(mu):.1f}" for phi, mu in run)
            lines.append(f'<polyline class="chart" points="{points}"/>')
    return _SvgChart(lines, x, y)


def _chart_runs(chart: Iterable[tuple[float, float | None]]) -> list[list[tuple[float, float]]]:
    """The runs of a chart's points (phi, mu) between those where mu is None."""
    runs: list[list[tuple[float, float]]] = [[]]
    for phi, mu in chart:
        if mu is None:
            runs.append([])
        else:
            runs[-1].append((phi, mu))
    return [run for run in runs if run]


def _xml(text: str) -> str:
    from xml.sax.saxutils import escape
    return escape(printable(text), {'"': "&quot;"})


def svg_drawing(drawing: Drawing, seconds_per_frame: float | None = None) -> str:
    """The drawing as one animated SVG (SMIL; each frame seconds_per_frame, else the drawing's
    seconds, else frame_seconds())."""
    x0, y0, x1, y1 = drawing.bounds
    margin, head, foot = SVG_MARGIN, 58, 40
    scale = svg_scale(drawing.bounds)
    width = SVG_WIDTH
    height = round(head + foot + (y1 - y0) * scale)
    page = _SvgPage(scale, (width - (x1 - x0) * scale) / 2 - x0 * scale, head + y1 * scale)
    chart = _svg_chart(drawing.chart, height - foot + 10, width, margin) if drawing.chart else None
    mus = [mu for _, mu in drawing.chart or ()]
    if chart:
        height += _SVG_CHART_HEIGHT
    caption_y = height - 14
    legend = _svg_legend(drawing)
    if legend:
        height += 22                              # a line of its own under the caption
    count = len(drawing.frames)
    shown = _still_frames(drawing, None)[0]
    period = (seconds_per_frame or drawing.seconds or frame_seconds(count)) * count
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}" data-kind="{drawing.kind}" data-frames="{count}" '
           f'data-scale="{scale!r}" data-origin="{page.left!r} {page.top!r}">',
           f"<title>{_xml(drawing.title)}</title>", f"<style>{_SVG_STYLE}</style>",
           '<rect width="100%" height="100%" fill="#fff"/>',
           f'<text class="title" x="{margin}" y="24">{_xml(drawing.title)}</text>',
           f'<text class="subtitle" x="{margin}" y="44">{_xml(drawing.subtitle)}</text>',
           '<g class="ground">', *_svg_layer(page, drawing.ground, drawing.size), "</g>",
           *(chart.lines if chart else ())]
    if legend:
        out.append(f'<text class="legend" x="{width - margin}" y="{height - 8}" '
                   'text-anchor="end">' + " · ".join(
                       f'<tspan fill="{colour}">━━ {_xml(words)}</tspan>'
                       for colour, words in legend) + "</text>")
    for i, frame in enumerate(drawing.frames):
        out.append(f'<g class="frame" data-phi="{frame.pose.phi!r}" '
                   f'visibility="{"visible" if i == shown else "hidden"}">')
        if count > 1:                        # visible from i/count to (i + 1)/count of a turn
            values, times = ("visible;hidden", (0, 1)) if i == 0 else (
                "hidden;visible;hidden", (0, i, i + 1))
            out.append(f'<animate attributeName="visibility" values="{values}" keyTimes="'
                       + ";".join(f"{t / count:.6g}" for t in times)
                       + f'" dur="{period:.6g}s" calcMode="discrete" repeatCount="indefinite"/>')
        out += _svg_layer(page, frame.layer, drawing.size)
        mu = mus[i] if chart else None
        if chart and mu is not None:
            out.append(f'<circle class="point" cx="{chart.x(frame.pose.phi):.1f}" '
                       f'cy="{chart.y(mu):.1f}" r="4"/>')
        out.append(f'<text class="caption" x="{margin}" y="{caption_y}">'
                   f"{_xml(frame.caption)}</text>")
        if frame.message:
            out.append(f'<text class="message" x="{width / 2:.0f}" y="{head + 8}" '
                       f'text-anchor="middle">{_xml(frame.message)}</text>')
        out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"


# What a coupler curve's colour and a dashed line mean, said where they are drawn: (style, its
# colour, words); the SVG's legend (the PNG's is _PNG_LEGEND, with the lines themselves).
_SVG_LEGEND = (("coupler", "#c0392b", "P's curve: this branch"),
               ("coupler-other", "#e67e22", "the other branch"),
               ("coupler-follow", "#8e44ad", "the motion followed"),
               ("hidden", "#6a6a6a", "dashed: behind the sphere"))


def _svg_legend(drawing: Drawing) -> list[tuple[str, str]]:
    """The legend of the curves and line styles the drawing uses: (colour, words) each."""
    styles = {s.style for layer in [drawing.ground, *(f.layer for f in drawing.frames[:1])]
              for s in layer.strokes}
    styles |= {"hidden"} if styles & set(FAR_SIDE.values()) else set()
    return [(colour, words) for style, colour, words in _SVG_LEGEND
            if style in styles or FAR_SIDE.get(style) in styles]


# -- the PNG -------------------------------------------------------------------------------------
# The positions overlaid as a textbook draws a linkage's motion: the ground once, the earlier
# positions faint, the last solid with its joints and letters (matplotlib, the `plot` extra).

_PNG_STYLES: dict[str, dict[str, Any]] = {"link": dict(color="#1b1b1b", linewidth=2.4),
               "ground": dict(color="#1b1b1b", linewidth=1.4),
               "hatch": dict(color="#555555", linewidth=0.7),
               "axis": dict(color="#2f6db3", linewidth=0.9, linestyle="-."),
               "path": dict(color="#8a8a8a", linewidth=0.9, linestyle=":"),
               "hidden": dict(color="#6a6a6a", linewidth=1.4, linestyle="--"),
               "outline": dict(color="#b5b5b5", linewidth=1.0),
               "dimension": dict(color="#7a7a7a", linewidth=0.7),
               "coupler": dict(color="#c0392b", linewidth=1.6),
               "coupler-other": dict(color="#e67e22", linewidth=1.2),
               "coupler-follow": dict(color="#8e44ad", linewidth=1.8),
               "coupler-far": dict(color="#c0392b", linewidth=1.1, linestyle="--"),
               "coupler-other-far": dict(color="#e67e22", linewidth=0.9, linestyle="--"),
               "coupler-follow-far": dict(color="#8e44ad", linewidth=1.2, linestyle="--"),
               "marked": dict(color="#7fbf9a", linewidth=1.4),
               "force": dict(color="#d35400", linewidth=1.8)}


_PNG_LETTER, _PNG_MARK = 13, 6          # points: the letters' font size, the marks' size


def _png_layer(ax: matplotlib.axes.Axes, layer: Layer, alpha: float, marks: bool,
               zorder: float = 2.0) -> None:
    for stroke in layer.strokes:
        xs, ys = zip(*stroke.points)
        ax.plot(xs, ys, alpha=alpha, solid_capstyle="round", zorder=zorder,
                **_PNG_STYLES[stroke.style])
    if marks:
        for mark in layer.marks:
            ax.plot(*mark.at, marker="D" if mark.kind == "point" else "o",
                    markersize=_PNG_MARK, markeredgewidth=1.4, zorder=zorder + 4,
                    color="#1b1b1b",
                    markerfacecolor={"pivot": "#d8d8d8", "point": "#c0392b"}.get(mark.kind, "w"))
            if mark.kind == "point":
                ax.annotate("P", mark.at, xytext=(7, 7), textcoords="offset points",
                            fontsize=_PNG_LETTER - 2, fontweight="bold", color="#c0392b",
                            zorder=zorder + 5)


# What each curve's line means, for the PNG's legend: (style, words), shown where drawn.
_PNG_LEGEND = (("coupler", "P's curve, the frames' branch"), ("coupler-other", "P's curve, "
               "the other branch"), ("coupler-follow", "P's curve, the motion followed"),
               ("hidden", "dashed: behind the sphere (a curve in its colour)"), ("path", "a joint's path (dotted)"),
               ("axis", "a shaft's axis (dash-dot)"))
_EXTREME_COLOUR = "#b0307a"


def _png_letters(mpl: matplotlib.figure.Figure, ax: matplotlib.axes.Axes, drawing: Drawing,
                 frame: Frame) -> None:
    """The frame's letters, placed for the size the PNG draws them at (the axes laid out)."""
    mpl.draw_without_rendering()
    (x0, _), (x1, _) = ax.transData.transform([(0.0, 0.0), (1.0, 0.0)])
    points = (x1 - x0) * 72.0 / mpl.dpi                   # typographic points a page unit
    letters = Letters(0.6 * _PNG_LETTER / points, 0.8 * _PNG_LETTER / points,
                      (_PNG_MARK / 2 + 0.7) / points, 1.2 / points)
    for label in place_labels(frame.layer.labels,
                              stroke_segments(drawing.ground.strokes + frame.layer.strokes),
                              drawing.ground.marks + frame.layer.marks, letters, drawing.bounds):
        ax.text(*label.at, label.text, ha="center", va="center", fontsize=_PNG_LETTER,
                fontstyle="italic", family="serif")


def _png_chart(ax: matplotlib.axes.Axes, chart: Sequence[tuple[float, float | None]],
               marked: Sequence[float]) -> None:
    """The transmission angle along the sweep, the drawn positions marked: scaled to its range
    and 90 degrees (the best), the worst (furthest from 90) of the points swept marked."""
    for run in _chart_runs(chart):
        ax.plot(*zip(*run), color="#2f6db3", linewidth=1.4)
    shown = dict(chart)
    dots = [(p, mu) for p in marked if (mu := shown.get(p)) is not None]
    ax.plot([p for p, _ in dots], [mu for _, mu in dots], "o", color="#2f6db3", markersize=3)
    values = [(mu, phi) for phi, mu in chart if mu is not None]
    low = min([90.0] + [mu for mu, _ in values])
    high = max([90.0] + [mu for mu, _ in values])
    pad = max(2.0, 0.08 * (high - low))
    ax.set_ylim(max(0.0, low - pad), min(180.0, high + pad))
    ax.axhline(90.0, color="#1e7b45", linewidth=0.9, linestyle="-.")
    ax.annotate("90° best", (1.0, 90.0), xycoords=("axes fraction", "data"), xytext=(-3, 3),
                textcoords="offset points", ha="right", fontsize=7, color="#1e7b45")
    worst = ""
    if values:                          # the worst as analyse's mu_worst: mu_min on a tie
        lowest, highest = min(values), max(values, key=lambda v: (v[0], -v[1]))
        mu, phi = highest if highest[0] + lowest[0] - 180.0 > MU_TIE else lowest
        ax.plot([phi], [mu], "o", markersize=7, markerfacecolor="none", color="#c0392b",
                markeredgewidth=1.5)
        worst = f"\nworst μ (circled) {mu:.1f}° at {phi:g}°"
    ax.set_xlabel("input angle φ [deg]" + worst, fontsize=8)
    ax.set_ylabel("transmission angle μ [deg]", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, linewidth=0.3)


def _png_scale_bar(ax: matplotlib.axes.Axes, bounds: Box) -> None:
    """A bar of a round length (1, 2 or 5 times a power of ten, about a fifth of the width) at
    the drawing's lower left, in the linkage's lengths (the plane kinds, drawn as they lie)."""
    x0, y0, x1, y1 = bounds
    target = (x1 - x0) / 5.0
    power = 10.0 ** math.floor(math.log10(target))
    length = max((k * power for k in (1.0, 2.0, 5.0) if k * power <= target), default=power)
    y = y0 + 0.03 * (y1 - y0)
    ax.plot([x0, x0 + length], [y, y], color="#1b1b1b", linewidth=2.0, solid_capstyle="butt")
    for x in (x0, x0 + length):
        ax.plot([x, x], [y - 0.01 * (y1 - y0), y + 0.01 * (y1 - y0)], color="#1b1b1b",
                linewidth=1.0)
    ax.text(x0 + length / 2, y + 0.015 * (y1 - y0), f"{length:g} (the lengths' unit)",
            ha="center", va="bottom", fontsize=7)


def _png_extremes(ax: matplotlib.axes.Axes, drawing: Drawing) -> None:
    """The output's extremes among the frames (sampled at the sweep's step): the output pin
    there, and for a four-bar its crank from B0, green, each with its value and angle."""
    kind = drawing.kind
    slider = kind in SLIDER_CRANKS
    posed = [f.pose for f in drawing.frames if f.message is None and f.pose.output is not None]
    if len(posed) < 2:
        return
    name = "x" if slider else "ψ"
    unit = "" if slider else "°"
    along = unwrapped([p.output or 0.0 for p in posed], not slider)   # across +-180 as it moves
    if not slider and max(along) - min(along) >= 359.0:
        return                                  # the output turns fully: no extremes
    low = min(along)
    shift = 0.0 if slider else (low + 180.0) % 360.0 - 180.0 - low    # the min in [-180, 180)
    for i, which in ((along.index(min(along)), "min"), (along.index(max(along)), "max")):
        pose = posed[i]
        pin = project(kind, pose.joints["C" if slider else "B"])
        if not slider and "B0" in pose.joints and kind != SPHERICAL_FOUR_BAR:
            b0 = project(kind, pose.joints["B0"])
            ax.plot([b0[0], pin[0]], [b0[1], pin[1]], color=_EXTREME_COLOUR, linewidth=1.6,
                    alpha=0.8, zorder=3)
        ax.plot(*pin, marker="s", markersize=5, color=_EXTREME_COLOUR, zorder=7)
        ax.annotate(f"{name} {which} {along[i] + shift:.4g}{unit}\n(φ = {pose.phi:g}°)", pin,
                    xytext=(8, -14 if which == "min" else 6), textcoords="offset points",
                    fontsize=7, color=_EXTREME_COLOUR, zorder=7,
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.8))


class PlotUnavailable(RuntimeError):
    """--png without matplotlib (or --dxf without ezdxf)."""


def matplotlib_canvas() -> tuple[type[matplotlib.figure.Figure],
                                 type[matplotlib.backends.backend_agg.FigureCanvasAgg]]:
    """matplotlib's Figure and Agg canvas (no pyplot: no global state), or PlotUnavailable."""
    try:
        with held_import("matplotlib.backends.backend_agg"):    # as numpy_module's
            from matplotlib.figure import Figure as MplFigure
            from matplotlib.backends.backend_agg import FigureCanvasAgg
    except ImportError:
        raise PlotUnavailable("--png needs matplotlib, which is not installed: "
                              "python3 -m pip install matplotlib") from None
    return MplFigure, FigureCanvasAgg


def png_drawing(drawing: Drawing, positions: int = 12, dpi: float | None = None,
                size: tuple[int, int] | None = None) -> bytes:
    """The drawing as a PNG: up to `positions` of its frames spread over the sweep, overlaid
    from faint to solid over the ground; the last one with its joints and letters. 100 dots an
    inch (`dpi`), 800 pixels wide unless `size` (width, height in pixels) says otherwise."""
    import io
    MplFigure, FigureCanvasAgg = matplotlib_canvas()
    placed = [f for f in drawing.frames if f.message is None] or list(drawing.frames)
    chosen = [placed[i] for i in spread_indices(len(placed), positions)]
    x0, y0, x1, y1 = drawing.bounds
    width, dpi = 8.0, dpi or 100
    inches = (width, min(10.0, max(3.0, width * (y1 - y0) / (x1 - x0) + 0.9)))
    mpl = MplFigure(figsize=(size[0] / dpi, size[1] / dpi) if size else inches, dpi=dpi,
                    layout="constrained")
    FigureCanvasAgg(mpl)
    mpl.suptitle(f"{drawing.title}\n{drawing.subtitle}", fontsize=10)
    if drawing.chart:
        ax, chart = mpl.subplots(1, 2, width_ratios=(2.2, 1))
        _png_chart(chart, drawing.chart, [f.pose.phi for f in chosen])
    else:
        ax = mpl.add_subplot()
    for i, frame in enumerate(chosen[:-1]):      # the faint positions under the ground
        _png_layer(ax, frame.layer, 0.12 + 0.5 * i / len(chosen), False, 1.0)
    _png_layer(ax, drawing.ground, 1.0, True, 2.0)   # pivots and their hatching on top of them
    _png_layer(ax, chosen[-1].layer, 1.0, True, 3.0)
    if len(chosen) > 1:
        _png_extremes(ax, drawing)
    caption = chosen[-1].message or chosen[-1].caption
    if len(chosen) > 1:
        caption = f"{len(chosen)} positions, faint to solid; the last at {caption}"
    ax.set_title(caption, fontsize=9, loc="left")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_axis_off()
    if drawing.kind in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK):
        _png_scale_bar(ax, drawing.bounds)
    drawn = {s.style for layer in [drawing.ground, chosen[-1].layer] for s in layer.strokes}
    import matplotlib.lines
    drawn |= {"hidden"} if drawn & set(FAR_SIDE.values()) else set()
    handles = [matplotlib.lines.Line2D([], [], **_PNG_STYLES[style], label=words)
               for style, words in _PNG_LEGEND if style in drawn or FAR_SIDE.get(style) in drawn]
    if handles:
        mpl.legend(handles=handles, fontsize=7, loc="outside lower center",
                   ncols=min(3, len(handles)), frameon=False)
    _png_letters(mpl, ax, drawing, chosen[-1])
    out = io.BytesIO()
    mpl.savefig(out, format="png")
    return out.getvalue()


# -- DXF: the linkage's true geometry for CAD -----------------------------------------------------
#
# Unlike the pictures, a DXF holds the linkage itself: the joints where joint_positions puts them
# (3-D for the spherical and skew kinds, z = 0 for the plane ones), in the linkage's lengths (the
# spherical four-bar on the unit sphere, its links great-circle arcs). Layers: GROUND (the fixed
# links, once), POSITION_1, POSITION_2, ... (the moving links and a label "phi = ..." at the
# crank pin, one layer a position drawn), COUPLER_CURVE (the coupler point's path over the sweep,
# on the frames' branch, where the drawing has a coupler point).

# Each kind's links as pairs of joint names: (fixed, moving).
DXF_LINKS = {
    PLANE_FOUR_BAR: ((("A0", "B0"),), (("A0", "A"), ("A", "B"), ("B0", "B"))),
    SPHERICAL_FOUR_BAR: ((("A0", "B0"), ("O", "A0"), ("O", "B0")),
                         (("A0", "A"), ("A", "B"), ("B0", "B"))),
    SKEW_FOUR_BAR: ((("A0", "F0"), ("F0", "F1"), ("F1", "B0")),
                    (("A0", "A"), ("A", "B"), ("B0", "B"))),
    PLANE_SLIDER_CRANK: ((), (("A0", "A"), ("A", "C"))),
    SKEW_SLIDER_CRANK: ((("A0", "F0"), ("F0", "F1")), (("A0", "A"), ("A", "C"))),
}
DXF_POSITIONS = 12          # positions written at most, spread over the drawing's frames


def dxf_module() -> Any:
    """ezdxf (an optional extra), or PlotUnavailable saying how to install it."""
    try:
        import ezdxf
    except ImportError:
        raise PlotUnavailable("--dxf needs ezdxf, which is not installed: "
                              "python3 -m pip install ezdxf") from None
    return ezdxf


def _dxf_link(kind: str, p: Vector, q: Vector) -> list[Vector]:
    """A link from joint p to joint q: a line, or on the sphere the great-circle arc."""
    if kind != SPHERICAL_FOUR_BAR or p == (0.0, 0.0, 0.0) or q == (0.0, 0.0, 0.0):
        return [p, q]
    angle = math.acos(max(-1.0, min(1.0, dot(p, q))))
    if angle < 1e-12:
        return [p, q]
    steps = max(2, math.ceil(math.degrees(angle) / 3.0))
    arc = []
    for t in (k / steps for k in range(steps + 1)):
        wp, wq = math.sin((1 - t) * angle) / math.sin(angle), math.sin(t * angle) / math.sin(angle)
        arc.append((wp * p[0] + wq * q[0], wp * p[1] + wq * q[1], wp * p[2] + wq * q[2]))
    return arc


def dxf_drawing(drawing: Drawing, positions: int = DXF_POSITIONS) -> bytes:
    """The linkage of the drawing as a DXF (R2010, ezdxf): its fixed links, up to `positions` of
    its frames spread over the sweep (each a layer), its coupler curve (see the notes above)."""
    ezdxf = dxf_module()
    import io
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 0                     # unitless: the lengths as typed
    space = doc.modelspace()
    kind = drawing.kind
    fixed, moving = DXF_LINKS[kind]
    placed = [f for f in drawing.frames if f.message is None]
    chosen = [placed[i] for i in spread_indices(len(placed), positions)]

    def polyline(points: list[Vector], layer: str) -> None:
        if len(points) == 2:
            space.add_line(points[0], points[1], dxfattribs={"layer": layer})
        else:
            space.add_polyline3d(points, dxfattribs={"layer": layer})

    doc.layers.add("GROUND", color=7)
    ground = (chosen or list(drawing.frames))[0].pose.joints
    for p, q in fixed:
        if p in ground and q in ground:
            polyline(_dxf_link(kind, ground[p], ground[q]), "GROUND")
    for i, frame in enumerate(chosen, 1):
        layer = f"POSITION_{i}"
        doc.layers.add(layer, color=1 + i % 6)
        joints = frame.pose.joints
        for p, q in moving:
            if p in joints and q in joints:
                polyline(_dxf_link(kind, joints[p], joints[q]), layer)
        for name, at in joints.items():
            space.add_point(at, dxfattribs={"layer": layer})
        space.add_text(f"phi = {frame.pose.phi:g}", height=0.25 * drawing.size,
                       dxfattribs={"layer": layer}).set_placement(joints["A"])
    if drawing.coupler_points:
        doc.layers.add("COUPLER_CURVE", color=1)
        run: list[Vector] = []
        for point in [*drawing.coupler_points, None]:
            if point is not None:
                run.append(point)
                continue
            if len(run) > 1:
                space.add_polyline3d(run, dxfattribs={"layer": "COUPLER_CURVE"})
            run = []
    text = io.StringIO()
    doc.write(text)
    return text.getvalue().encode("utf-8")


# ---- 19. Synthesis: what a design is, its data and its linkage -----------------------------------
#
# The classical analytical synthesis methods collected by E. Pennestrì and P. P. Valentini, "A
# review of simple analytical methods for the kinematic synthesis of four-bar and slider-crank
# function generators for two and three prescribed finite positions" (2009): the transmission
# angle (eqs. 1-4), the crank-rockers FOURB-CR-1..4 (and Volmer's eqs. 6a-6c), the drag-links
# DRAGLINK-1 and -2, the function generators FOURB-FG2-1, FOURB-FG3-1, SLID-FG2-1, SLID-FG2-2.
#
# Names. The review calls the links by other letters than the analysis paper. In every four-bar
# method of the review (and in its eqs. 1-2, which put a and d beside the input angle)
#
#     review  a = input crank   b = coupler   c = output (rocker)   d = frame
#     paper   b = input crank   c = coupler   d = output            a = frame
#
# and in the slider-crank methods the review's crank r, rod l and offset epsilon are the paper's
# b, c and -e: the review's slider runs on the line y = -epsilon (its eq. 4 has the least
# transmission angle at theta = 90 degrees), the paper's on y = e. Angles are the paper's
# (counter-clockwise from the frame line, the output pivot at (a, 0)) except where a method says
# otherwise: FOURB-FG3-1 measures the output angle from the opposite direction (paper psi =
# review psi - 180, shown by its worked example), SLID-FG2-1/-2 give at the second dead centre the
# direction of the slider pin, not of the crank (crank angle = review theta2 - 180).
# Each design comes converted (FourBar, SliderCrank: the paper's letters and the assembly branch,
# the engine's branch 1 or 2), with the review's numbers under the review's names beside it.
#
# Bad data raise DesignError, naming the condition: data outside the method's valid range (DATA
# below, stated once for the refusals, the command's help and the tests: the message names the
# datum), a link length <= 0, degenerate or complex (a square root with no real value), a design
# of the wrong class (not a crank-rocker, not a drag-link), a branch defect or a dead centre
# between the positions, and inconsistent dead-centre data (SLID-FG2-2). Where the review's
# formulas cancel, the same quantities are computed by identities that do not (ERRATUM S14).
#
# Checking. Every design can be run through `engine_outputs`, the one adapter to the analysis (the
# accurate engine, never the synthesis formulas), and
# `analyze_design` measures on the analysed linkage what it really does: rocker swing, crank
# rotation between the dead centres, the prescribed positions met or missed, the
# transmission-angle extremes. Corrections to the review are marked `# ERRATUM Sn` and justified
# in SYNTHESIS_ERRATA.md.
#
# Uses: section 2.
# Offers: MU_MARGIN, DesignError, require, in_degrees, wrap_degrees, PSI_MIN, LENGTH_MIN,
#   LENGTH_MAX, ANGLE_EPSILON, Data, Bound, Datum, DATA, number_text, range_text, check_data,
#   FourBar, SliderCrank, Designed, four_bar_from_review, four_bar_to_review,
#   slider_crank_from_review, grashof_class, cos_transmission, four_bar_transmission_angle,
#   four_bar_transmission_extremes, slider_transmission_angle, slider_transmission_extremes, Design,
#   Synthesis, scaled_design.


MU_MARGIN = 0.1     # degrees: a design whose transmission angle comes this close to 0 or 180 is
#                     at a dead centre for all practical purposes (and ill-conditioned): refused


class DesignError(ValueError):
    """Data that no design of the method can meet; the message names the condition that failed.
    `design`, when set, is what the formulas give although it does not meet the data."""

    def __init__(self, message: str, design: Design | None = None) -> None:
        super().__init__(message)
        self.design = design


def require(condition: object, message: str, design: Design | None = None) -> None:
    """Raise DesignError(message) unless condition holds."""
    if not condition:
        raise DesignError(message, design)


def in_degrees(x: float) -> float:
    """Radians to degrees."""
    return x / RAD


def wrap_degrees(angle: float) -> float:
    """An angle in degrees brought into (-180, 180]."""
    w = math.fmod(angle, 360.0)
    if w > 180.0:
        w -= 360.0
    elif w <= -180.0:
        w += 360.0
    return w


def _acos_deg(x: float, what: str) -> float:
    """arccos in degrees; a DesignError names `what` when |x| > 1 (the configuration is not
    reached) beyond round-off."""
    require(abs(x) <= 1.0 + 1e-12, f"{what}: cos = {x:.6g} is outside [-1, 1]")
    return in_degrees(math.acos(max(-1.0, min(1.0, x))))


# -- the valid data of each method: stated once, for the refusals, the help and the tests --------

PSI_MIN = 1e-3      # degrees: the least rocker swing; below it the crank is under ~1e-5 of the
#                     frame (a degenerate linkage)
LENGTH_MIN, LENGTH_MAX = 1e-6, 1e6     # a length datum, relative to the method's unit length
ANGLE_EPSILON = 1e-6                   # degrees: an excluded single angle is refused this close


# A method's data: each datum's value by its name, a number (or, with count 3, a list of three).
Data = dict[str, Any]
# An end of a datum's range: a number, or (text, its value from the data) for one that depends on
# a datum listed before.
Bound = float | tuple[str, Callable[[Data], float]]


class Datum(NamedTuple):
    """One datum of a method and its valid range lo < value < hi. An end is a number, or
    (text, function of the data) when it depends on a datum listed before; `closed` names the ends
    included ("lo", "hi"); `excluded`: (reason, function of the data, True when the value is
    refused) for single values the formulas cannot take; `count` 3: a list of three values."""
    name: str
    meaning: str
    lo: Bound = -math.inf
    hi: Bound = math.inf
    closed: tuple[str, ...] = ()
    excluded: tuple[tuple[str, Callable[[Data], bool]], ...] = ()
    count: int = 1          # type: ignore[assignment]  # the field shadows tuple.count, as a
    #                         NamedTuple's field may (Datum.count is the number of values)
    optional: bool = False


def _near(angle: float, target: float, period: float = 360.0) -> bool:
    """Whether an angle (degrees) lies within ANGLE_EPSILON of target, modulo period."""
    w = math.fmod(angle - target, period)
    return min(abs(w), period - abs(w)) < ANGLE_EPSILON


_SWING = Datum("psi", "rocker swing", PSI_MIN, 180.0, ("lo",))
_TIME_RATIO = Datum("theta", "crank rotation is 180 + theta", -180.0, 180.0)
# centric crank-rockers: MU_MARGIN < mu_min < 90 - psi/2 is empty unless psi < 180 - 2 MU_MARGIN
_CENTRIC = (_SWING._replace(hi=180.0 - 2 * MU_MARGIN),
            Datum("mu_min", "least transmission angle (a centric crank-rocker's mu runs from "
                  "mu_min to 180 - mu_min, equally far from 90: analyse prints them as mu_min "
                  "and mu_max, mu_worst = mu_min, mu_worst_deviation = 90 - mu_min)", MU_MARGIN,
                  ("90 - psi/2", lambda d: 90.0 - d["psi"] / 2)))
_LENGTH: dict[str, Any] = dict(lo=LENGTH_MIN, hi=LENGTH_MAX, closed=("lo", "hi"))
_ANGLE: dict[str, Any] = dict(lo=-360.0, hi=360.0, closed=("lo", "hi"))   # a position, not a turn
DATA = {
    "FOURB-CR-1": (
        _TIME_RATIO, _SWING,
        Datum("theta0", "crank angle at the extended dead centre", **_ANGLE, excluded=(
            ("sin(theta0) = 0: the extended dead centre on the frame line",
             lambda d: _near(d["theta0"], 0.0, 180.0)),
            ("sin(theta + theta0) = 0: the folded dead centre on the frame line",
             lambda d: _near(d["theta"] + d["theta0"], 0.0, 180.0))))),
    "FOURB-CR-2": (
        _TIME_RATIO, _SWING,
        Datum("psi0", "rocker angle at the extended dead centre", **_ANGLE, excluded=(
            ("sin(psi0) = 0: the extended dead centre on the frame line",
             lambda d: _near(d["psi0"], 0.0, 180.0)),
            ("sin(psi0 + psi) = 0: the folded dead centre on the frame line",
             lambda d: _near(d["psi0"] + d["psi"], 0.0, 180.0))))),
    "FOURB-CR-3": (
        _TIME_RATIO._replace(excluded=(
            ("theta = 0, the unit time ratio, makes t = tan(90 deg) infinite; use FOURB-CR-4",
             lambda d: _near(d["theta"], 0.0)),)),
        _SWING._replace(excluded=(
            ("psi = 180 + theta makes u = tan((180 + theta - psi)/2) = 0",
             lambda d: _near(d["psi"], 180.0 + d["theta"])),))),
    "FOURB-CR-4": _CENTRIC,
    "FOURB-CR-4 (Volmer)": _CENTRIC,
    "DRAGLINK-1": (
        Datum("dpsi0", "output rotation while the crank turns 180", 0.0, 360.0),
        Datum("mu_min", "transmission angle at the design positions (mu_min at phi = 0, 180 - "
              "mu_min at 180, each 90 - mu_min from 90; analyse's mu_worst_deviation, over the "
              "whole turn, is at least that)", MU_MARGIN, 90.0)),
    "DRAGLINK-2": (   # footnote 5: 0 < dphi - dpsi < 180, 90 + dL/2 <= dphi <= 270 + dL/2
        Datum("dphi", "crank rotation between the unit-ratio positions", 90.0, 360.0, excluded=(
            ("dphi = 180 makes t = tan(dphi/2) infinite (footnote 5)",
             lambda d: _near(d["dphi"], 180.0)),)),
        Datum("dpsi", "output rotation between those positions (footnote 5)",
              ("|dphi - 180|", lambda d: abs(d["dphi"] - 180.0)),
              ("min(dphi, 540 - dphi)", lambda d: min(d["dphi"], 540.0 - d["dphi"])), excluded=(
                  ("dpsi = 180 makes u = tan(dpsi/2) infinite", lambda d: _near(d["dpsi"], 180.0)),
              )),
        Datum("lam", "lambda = b/d, coupler/frame (omitted: optimised)", **_LENGTH,
              optional=True)),
    "FOURB-FG2-1": (
        Datum("phij", "crank rotation", -360.0, 360.0, excluded=(
            ("the crank rotation phij is 0", lambda d: _near(d["phij"], 0.0)),)),
        Datum("psij", "output rotation", -360.0, 360.0, excluded=(
            ("psij = phij (mod 360): sin(xi - epsilon) = 0",
             lambda d: _near(d["psij"], d["phij"])),)),
        Datum("phi0", "initial crank angle", **_ANGLE),
        Datum("a", "the crank over the frame, the review's a/d (run's --b over --a)", **_LENGTH),
        Datum("c", "the output crank over the frame, the review's c/d (run's --d over --a)",
              **_LENGTH)),
    "FOURB-FG3-1": (
        Datum("phi", "three crank angles", **_ANGLE, count=3, excluded=(
            ("a repeated input angle: a four-bar's output is one function of its input",
             lambda d: any(_near(d["phi"][i], d["phi"][j]) for i, j in ((0, 1), (0, 2), (1, 2)))),
        )),
        Datum("psi", "three output angles (the review's)", **_ANGLE, count=3)),
    "SLID-FG2-1": (
        Datum("dtheta", "crank rotation between the dead centres", 0.0, 360.0, excluded=(
            ("dtheta = 180 makes cot(dtheta) infinite", lambda d: _near(d["dtheta"], 180.0)),
            ("dtheta = 0 or 360 makes cot(dtheta) infinite", lambda d: _near(d["dtheta"], 0.0)))),
        Datum("ds", "slider displacement s1 - s2", **_LENGTH),
        Datum("epsilon", "offset (slider on y = -epsilon)",
              (f"-{LENGTH_MAX:g} ds", lambda d: -LENGTH_MAX * d["ds"]),
              (f"{LENGTH_MAX:g} ds", lambda d: LENGTH_MAX * d["ds"]))),
    "SLID-FG2-2": (
        Datum("theta1", "crank angle at the outer dead centre", -90.0, 90.0),
        Datum("theta2", "pin direction at the inner dead centre", **_ANGLE, excluded=(
            ("cos(theta2) = 0", lambda d: _near(d["theta2"], 90.0, 180.0)),)),
        Datum("s1", "slider at the outer dead centre", **_LENGTH),
        Datum("s2", "slider at the inner dead centre", **_LENGTH)),
}


def number_text(x: float) -> str:
    """A number as short as it is exact: 65, not 65.000000000000014 unless it is that."""
    short = f"{x:g}"
    return short if float(short) == x else repr(float(x))


def _bound_value(end: Bound, data: Data) -> float:
    """An end of a range, for the data."""
    return end[1](data) if isinstance(end, tuple) else end


def _bound_text(end: Bound, data: Data | None) -> str:
    """An end of a range as text, with its value when it depends on the data (data None: the
    text alone)."""
    if not isinstance(end, tuple):
        return number_text(end)
    if data is None:
        return end[0]
    return f"{end[0]} = {number_text(end[1](data))}"


def range_text(datum: Datum, data: Data | None = None) -> str:
    """The valid range of a datum as text: '[0.001, 180)', '[0.1, 90 - psi/2 = 65)'; the dependent
    ends evaluated when the data are given."""
    lo, hi = _bound_text(datum.lo, data), _bound_text(datum.hi, data)
    return (("[" if "lo" in datum.closed else "(") + lo + ", " + hi
            + ("]" if "hi" in datum.closed else ")"))


def check_data(method: str, data: Data) -> None:
    """Refuse data outside the method's valid range (DATA): a DesignError naming the datum, its
    value and the range or the reason it is excluded."""
    for datum in DATA[method]:
        value: Any = data.get(datum.name)       # a number, or a list of `count` numbers
        if value is None and datum.optional:
            continue
        values = value if datum.count > 1 else [value]
        require(len(values) == datum.count, f"{method}: {datum.name} takes {datum.count} values")
        for v in values:
            require(isinstance(v, (int, float)) and math.isfinite(v),
                     f"{method}: {datum.name} = {v} is not a finite number")
            lo = _bound_value(datum.lo, data)
            hi = _bound_value(datum.hi, data)
            inside = ((lo <= v if "lo" in datum.closed else lo < v)
                      and (v <= hi if "hi" in datum.closed else v < hi))
            require(inside, f"{method}: {datum.meaning.split(' (')[0]}: {datum.name} = {number_text(v)} "
                             f"is not in {range_text(datum, data)}")
        for reason, test in datum.excluded:
            require(not test(data), f"{method}: {datum.name} = "
                     f"{', '.join(number_text(v) for v in values)}: {reason}")


# -- the designed linkages, in the paper's letters -----------------------------------------------

class FourBar(NamedTuple):
    """A plane four-bar in the analysis paper's letters: frame a (output pivot at (a, 0)), crank b,
    coupler c, output d; branch 1 or 2 as the engine's (1: the coupler B->D turns counter-
    clockwise from the output link, i.e. d(|BD|^2)/d(psi) > 0)."""
    a: float
    b: float
    c: float
    d: float
    branch: int = 1


class SliderCrank(NamedTuple):
    """A plane slider-crank in the paper's letters: crank b about the origin, rod c, slider on the
    line y = e; branch 1 or 2 as the engine's (1: the slider to the right of the crank pin)."""
    b: float
    c: float
    e: float
    branch: int = 1


Designed = FourBar | SliderCrank        # a linkage a method designs


def four_bar_from_review(a: float, b: float, c: float, d: float, branch: int = 1) -> FourBar:
    """The review's crank a, coupler b, output c, frame d as the paper's FourBar(a=d, b=a, c=b,
    d=c)."""
    return FourBar(a=d, b=a, c=b, d=c, branch=branch)


def four_bar_to_review(link: FourBar) -> dict[str, float]:
    """The paper's FourBar as the review's letters: {'a': crank, 'b': coupler, 'c': output,
    'd': frame}."""
    return {"a": link.b, "b": link.c, "c": link.d, "d": link.a}


def slider_crank_from_review(r: float, l: float, epsilon: float, branch: int = 1) -> SliderCrank:
    """The review's crank r, rod l, offset epsilon (slider on y = -epsilon) as the paper's
    SliderCrank(b=r, c=l, e=-epsilon)."""
    return SliderCrank(b=r, c=l, e=-epsilon, branch=branch)


def grashof_class(link: FourBar) -> str:
    """'crank-rocker', 'drag-link', 'double-rocker' (Grashof, coupler shortest), 'rocker-crank',
    'change-point' (s + l = p + q) or 'triple-rocker' (non-Grashof), with the crank as input:
    the review's names, to within 1e-12 of the longest link (analyse's class, exact in the typed
    lengths, calls a drag-link a double-crank and a triple-rocker a non-Grashof double-rocker)."""
    lengths = sorted((link.a, link.b, link.c, link.d))
    excess = lengths[0] + lengths[3] - lengths[1] - lengths[2]
    if abs(excess) <= 1e-12 * lengths[3]:
        return "change-point"
    if excess > 0:
        return "triple-rocker"
    shortest = min(("a", "b", "c", "d"), key=lambda k: getattr(link, k))
    return {"b": "crank-rocker", "a": "drag-link", "c": "double-rocker",
            "d": "rocker-crank"}[shortest]


# -- the transmission angle: eqs. (1)-(4) ---------------------------------------------------------

def cos_transmission(link: FourBar, phi: float) -> float:
    """cos mu by eq. (1), in the review's letters
    cos mu = (b^2 + c^2 - (a^2 + d^2) + 2ad cos phi) / 2bc."""
    a, b, c, d = link.b, link.c, link.d, link.a            # the review's letters
    return (b * b + c * c - (a * a + d * d) + 2 * a * d * math.cos(phi * RAD)) / (2 * b * c)


def four_bar_transmission_angle(link: FourBar, phi: float) -> float:
    """Eq. (1): the angle (degrees) between coupler and output at input angle phi (degrees)."""
    return _acos_deg(cos_transmission(link, phi), f"transmission angle at phi = {phi:g}")


def four_bar_transmission_extremes(link: FourBar) -> tuple[float, float]:
    """Eqs. (2a), (2b): the least and greatest transmission angles (degrees), at the crank on the
    frame line, for linkages that reach both (crank-rockers, drag-links)."""
    a, b, c, d = link.b, link.c, link.d, link.a            # the review's letters (eq. 2: d = 1)
    mu_min = _acos_deg((b * b + c * c - (d - a) ** 2) / (2 * b * c),
                       "eq. (2a): the crank does not reach phi = 0")
    mu_max = _acos_deg((b * b + c * c - (d + a) ** 2) / (2 * b * c),
                       "eq. (2b): the crank does not reach phi = 180")
    return min(mu_min, mu_max), max(mu_min, mu_max)


def slider_transmission_angle(link: SliderCrank, phi: float) -> float:
    """Eq. (3), crank driving: the angle (degrees) between the rod and the normal to the slider's
    line at crank angle phi (degrees). ERRATUM S9: 90 - arctan(...), not arctan(...) - 90."""
    r, l, epsilon = link.b, link.c, -link.e                # the review's letters
    h = abs(epsilon + r * math.sin(phi * RAD))
    require(h <= l, f"eq. (3): the rod cannot reach the slider's line at phi = {phi:g}")
    return 90.0 - in_degrees(math.atan2(h, math.sqrt(l * l - h * h)))


def slider_transmission_extremes(link: SliderCrank) -> tuple[float, float]:
    """Eq. (4) and its counterpart: least and greatest transmission angles (degrees) over a full
    crank turn; eq. (4), printed for epsilon >= 0, takes |epsilon| here."""
    r, l, epsilon = link.b, link.c, abs(link.e)
    require(l > r + epsilon, f"eq. (4): the crank cannot turn fully (l = {l:.6g} <= r + "
                              f"|epsilon| = {r + epsilon:.6g})")
    mu_min = in_degrees(math.atan(math.sqrt((l / (r + epsilon)) ** 2 - 1.0)))
    mu_max = 90.0 if epsilon <= r else 90.0 - in_degrees(math.asin((epsilon - r) / l))
    return mu_min, mu_max


# -- results --------------------------------------------------------------------------------------

class Design(NamedTuple):
    """One linkage a method designs: in the paper's conventions (linkage, positions, travel) and
    in the review's own names and numbers (review), with the data it was designed for."""
    method: str                     # e.g. "FOURB-CR-1"
    data: Data                      # the prescribed data, the review's names (angles in degrees)
    linkage: Designed               # FourBar or SliderCrank: what the analysis takes
    review: dict[str, float]        # the unknowns as the review prints them (ratios, angles)
    positions: tuple[tuple[float, float], ...]   # design positions (phi, output) in the
    #                                              paper's convention
    travel: tuple[float, float] | None    # (phi from, phi to) the method designs for; None: a
    #                                       full turn
    mu_min: float                   # transmission-angle extremes over the travel (degrees),
    mu_max: float                   # from the review's formulas


class Synthesis(NamedTuple):
    """A method's answer: every solution it accepts, the one it prefers, and the roots it rejects
    (each with the reason)."""
    method: str
    solutions: tuple[Design, ...]
    preferred: int = 0
    rejected: tuple[str, ...] = ()     # each: the root, and why it is rejected

    @property
    def design(self) -> Design:
        """The preferred solution."""
        return self.solutions[self.preferred]


def scaled_design(design: Design, factor: float) -> Design:
    """The design with every length multiplied by `factor` (a four-bar's frame a, designed as 1,
    becomes `factor`; a slider-crank's lengths and its slider positions, in its data's units, are
    multiplied by it); angles, the data and the review's own numbers as they were."""
    link = design.linkage
    if isinstance(link, FourBar):
        return design._replace(linkage=link._replace(
            a=link.a * factor, b=link.b * factor, c=link.c * factor, d=link.d * factor))
    return design._replace(
        linkage=link._replace(b=link.b * factor, c=link.c * factor, e=link.e * factor),
        positions=tuple((phi, x * factor) for phi, x in design.positions))


# ---- 20. Synthesis: the review's methods ---------------------------------------------------------
#
# Holds: the review's methods, each a function of its data returning a Synthesis: the crank-rockers
# FOURB-CR-1..4 and Volmer's, the drag-links DRAGLINK-1 and -2, the function generators FOURB-FG2-1,
# FOURB-FG3-1, SLID-FG2-1 and SLID-FG2-2. Corrections to the review are marked `# ERRATUM Sn` and
# justified in data/SYNTHESIS_ERRATA.md.
#
# Uses: sections 2 and 19.
# Offers: fourb_cr_1, fourb_cr_2, fourb_cr_3, fourb_cr_4, volmer_crank_rocker, draglink_1,
#   draglink_2, limit_angles, fourb_fg2_1, fourb_fg3_1, slid_fg2_1, slid_fg2_2.


_P = ParamSpec("_P")                    # a method's parameters, kept by _method


def _method(name: str) -> Callable[[Callable[_P, Synthesis]], Callable[_P, Synthesis]]:
    """Decorator: every DesignError of the method's function starts with the method's name."""
    def decorate(function: Callable[_P, Synthesis]) -> Callable[_P, Synthesis]:
        @functools.wraps(function)
        def method(*args: _P.args, **kwargs: _P.kwargs) -> Synthesis:
            try:
                return function(*args, **kwargs)
            except DesignError as error:
                if str(error).startswith(name + ":"):
                    raise
                raise DesignError(f"{name}: {error}", error.design) from None
        return method
    return decorate


def _require_lengths(**lengths: float) -> None:
    """Every link length positive: above 1e-6 of the longest (less is a degenerate linkage)."""
    longest = max(abs(v) for v in lengths.values())
    for name, value in lengths.items():
        require(value > 1e-6 * longest, f"link length {name.replace('_', ' ')} = {value:.6g} "
                                         f"is not positive" + (" (to 1e-6 of the longest: a "
                                                                "degenerate linkage)"
                                                                if value > 0 else ""))


def _require_margin(mu_min: float, mu_max: float, design: Design | None = None) -> None:
    """Refuse a design whose transmission angle comes within MU_MARGIN of 0 or 180 degrees."""
    require(min(mu_min, 180.0 - mu_max) >= MU_MARGIN - 1e-9,       # mu_min = 0.1 + 1e-16: met
             f"dead centre: the transmission angle comes within {MU_MARGIN:g} degree of 0 or 180 "
             f"(mu from {mu_min:.6g} to {mu_max:.6g})", design)


def _branch_at(link: FourBar, phi: float, psi: float) -> int:
    """The engine's branch of a four-bar position (phi, psi in degrees): 1 when the coupler B->D
    turns counter-clockwise from the output link, 2 when clockwise."""
    bx, by = link.b * math.cos(phi * RAD), link.b * math.sin(phi * RAD)
    ux, uy = math.cos(psi * RAD), math.sin(psi * RAD)
    dx, dy = link.a + link.d * ux, link.d * uy
    return 1 if ux * (dy - by) - uy * (dx - bx) > 0 else 2


def _one(design: Design) -> Synthesis:
    """A Synthesis with a single solution."""
    return Synthesis(design.method, (design,))


def _deviation(design: Design) -> float:
    """The greatest deviation |90 - mu| (degrees) of the design's transmission angle."""
    return max(90.0 - design.mu_min, design.mu_max - 90.0)


# -- crank-rockers: FOURB-CR-1 .. FOURB-CR-4 ------------------------------------------------------

def _crank_rocker(method: str, data: Data, a: float, b: float, c: float, d: float, theta0: float,
                  psi0: float, theta: float, psi: float, review: dict[str, float]) -> Design:
    """Normalise a crank-rocker (review letters, d = frame) to d = 1, convert it, check that it is
    a crank-rocker, and give its dead-centre positions: extended (theta0, psi0), folded (theta0 +
    180 + theta, psi0 + psi), as the data state them (not brought into one turn)."""
    _require_lengths(a_crank=a, b_coupler=b, c_rocker=c, d_frame=d)
    a, b, c = a / d, b / d, c / d
    link = four_bar_from_review(a, b, c, 1.0)
    found = grashof_class(link)
    require(found == "crank-rocker", f"{method}: the linkage a = {a:.6g}, b = {b:.6g}, "
                                      f"c = {c:.6g}, d = 1 is a {found}, not a crank-rocker")
    # ERRATUM S11: both dead centres must lie on one assembly branch: the sine rule also accepts
    # a folded position on the mirror branch, where this linkage's real folded dead centre is
    # elsewhere.
    positions = ((theta0, psi0), (theta0 + 180.0 + theta, psi0 + psi))
    branches = [_branch_at(link, phi, psi_) for phi, psi_ in positions]
    require(branches[0] == branches[1],
             f"{method}: branch defect: the extended and folded dead centres of a = {a:.6g}, "
             f"b = {b:.6g}, c = {c:.6g}, d = 1 lie on different assembly branches")
    link = link._replace(branch=branches[0])
    mu_min, mu_max = four_bar_transmission_extremes(link)
    _require_margin(mu_min, mu_max)
    review = dict(review, a=a, b=b, c=c, d=1.0, mu_min=mu_min, mu_max=mu_max)
    return Design(method, data, link, review, positions, None, mu_min, mu_max)


def _chen_links(method: str, theta: float, psi: float, theta0: float, psi0: float, alpha: float
                ) -> tuple[float, float, float]:
    """Steps 4-5 of FOURB-CR-1/-2: crank a, coupler b, rocker c for frame d = 1 from the two
    dead-centre triangles (alpha = psi0 - theta0, the angle at the rocker pin, degrees).
    ERRATUM S14: the review's a = c (p1 - p2)/2, p1 = sin psi0 / sin theta0,
    p2 = sin(psi + psi0) / sin(theta + theta0), subtracts two nearly equal numbers for a small
    crank; here b + a and b - a are the distances of the rocker pin from the crank pivot at the
    two dead centres, and a = (|P1|^2 - |P2|^2) / 2(|P1| + |P2|) with
    |P1|^2 - |P2|^2 = 4c sin(psi0 + psi/2) sin(psi/2), which cancels nothing."""
    t0, t, p, p0 = theta0 * RAD, theta * RAD, psi * RAD, psi0 * RAD
    require(abs(math.sin(alpha * RAD)) > 1e-12,
             f"{method}: sin(psi0 - theta0) = 0: the extended dead centre is degenerate")
    c = math.sin(t0) / math.sin(alpha * RAD)
    pins = ((1.0 + c * math.cos(p0), c * math.sin(p0), t0),
            (1.0 + c * math.cos(p0 + p), c * math.sin(p0 + p), t0 + t))
    # signed distances along the crank's direction at the extended dead centre and the opposite
    # of it at the folded one: b + a and b - a (both negative for theta0 + 180)
    far, near = (math.copysign(math.hypot(x, y), x * math.cos(u) + y * math.sin(u))
                 for x, y, u in pins)
    if far * near > 0:
        a = 2.0 * c * math.sin(p0 + p / 2) * math.sin(p / 2) / (far + near)
    else:
        a = (far - near) / 2
    return a, (far + near) / 2, c


@_method("FOURB-CR-1")
def fourb_cr_1(theta: float, psi: float, theta0: float) -> Synthesis:
    """FOURB-CR-1 (Chen; Pamidi): crank-rocker with rocker swing psi while the crank turns
    180 + theta, the extended dead centre at crank angle theta0 (degrees)."""
    method = "FOURB-CR-1"
    data = {"theta": theta, "psi": psi, "theta0": theta0}
    check_data(method, data)
    theta0 = wrap_degrees(theta0)
    t, t0 = theta * RAD, theta0 * RAD
    # ERRATUM S14: the review's psi0 = atan(n1 (n3 + n4) / (n2 n3 - n1 n5)), n1..n5 sines and
    # cosines of theta0, theta + theta0, psi - theta - theta0, written as alpha = psi0 - theta0
    # with tan(alpha) = sin(theta0) sin(psi - theta) / (sin(theta + theta0)
    # - sin(theta0) cos(psi - theta)), the denominator as sums of products that do not cancel.
    # ERRATUM S11: alpha is fixed modulo 180; alpha + 180 gives the same a and b and c < 0, so
    # take the one with c = sin(theta0) / sin(alpha) > 0.
    swing_less_theta = (psi - theta) * RAD                  # in degrees first: exact when close
    alpha = in_degrees(math.atan2(math.sin(t0) * math.sin(swing_less_theta),
                            2 * math.cos(math.fsum((theta0, theta / 2)) * RAD) * math.sin(t / 2)
                            + 2 * math.sin(t0) * math.sin(swing_less_theta / 2) ** 2))
    if math.sin(alpha * RAD) * math.sin(t0) < 0:
        alpha = alpha + 180.0 if alpha <= 0 else alpha - 180.0
    psi0 = wrap_degrees(theta0 + alpha)
    a, b, c = _chen_links(method, theta, psi, theta0, psi0, alpha)
    turns = data["theta0"] - theta0                      # whole turns: the position as given
    return _one(_crank_rocker(method, data, a, b, c, 1.0, data["theta0"], psi0 + turns, theta,
                              psi, {"psi0": psi0}))


@_method("FOURB-CR-2")
def fourb_cr_2(theta: float, psi: float, psi0: float) -> Synthesis:
    """FOURB-CR-2 (Chen; Pamidi): crank-rocker with rocker swing psi while the crank turns
    180 + theta, the rocker at angle psi0 at the extended dead centre (degrees)."""
    method = "FOURB-CR-2"
    data = {"theta": theta, "psi": psi, "psi0": psi0}
    check_data(method, data)
    psi0 = wrap_degrees(psi0)
    p = psi * RAD
    # ERRATUM S1: the printed m2 and m0 are exchanged: with x = tan(theta0) the quadratic is
    # m2 x^2 + m1 x + m0 = 0, m2 = cos psi0 cos thetaf - cos y, m0 = -sin psi0 sin thetaf.
    # ERRATUM S14: its coefficients cancel (m2 for a small swing and time ratio); the same
    # equation, sin(theta0) sin(psi + psi0 - theta - theta0) = sin(theta + theta0)
    # sin(psi0 - theta0), is sin(2 theta0 + theta - psi0 - psi/2) = K with
    # K = sin(psi0 + psi/2) sin(theta - psi/2) / sin(psi/2), solved in closed form.
    k = (math.sin(math.fsum((psi0, psi / 2)) * RAD) * math.sin(math.fsum((theta, -psi / 2)) * RAD)
         / math.sin(p / 2))
    require(abs(k) <= 1.0 + 1e-12,
             f"{method}: no extended dead centre: sin(2 theta0 + theta - psi0 - psi/2) = "
             f"{k:.6g} is outside [-1, 1] (the quadratic in tan(theta0) has complex roots)")
    base = in_degrees(math.asin(max(-1.0, min(1.0, k))))
    solutions, rejected = [], []
    # ERRATUM S11: theta0 is fixed modulo 180; theta0 + 180 gives -a, -b and the same c, so
    # both are tried (step 8 keeps the one with all links positive, if any).
    for two in sorted({base, 180.0 - base}):
        for turn in (0.0, 180.0):
            # alpha = psi0 - theta0 as a sum of the data, not a difference of theta0
            alpha = wrap_degrees(math.fsum((psi0, theta, -psi / 2, -two)) / 2 - turn)
            theta0 = wrap_degrees(math.fsum((psi0, -theta, psi / 2, two)) / 2 + turn)
            try:
                a, b, c = _chen_links(method, theta, psi, theta0, psi0, alpha)
                solutions.append(_crank_rocker(method, data, a, b, c, 1.0,
                                               theta0 + data["psi0"] - psi0, data["psi0"], theta,
                                               psi, {"theta0": theta0}))
            except DesignError as error:                  # step 8: only all-positive links
                rejected.append(f"theta0 = {theta0:.6g}: {error}")
    require(solutions, f"{method}: no root gives a crank-rocker ({'; '.join(rejected)})")
    return Synthesis(method, tuple(solutions), 0, tuple(rejected))


def _cubic_real_roots(a2: float, a1: float, a0: float) -> list[float]:
    """The real roots of x^3 + a2 x^2 + a1 x + a0 = 0, each polished by Newton's method."""
    p = a1 - a2 * a2 / 3.0
    q = 2.0 * a2 ** 3 / 27.0 - a2 * a1 / 3.0 + a0
    disc = (q / 2.0) ** 2 + (p / 3.0) ** 3
    if disc > 0:
        s = math.sqrt(disc)
        u, v = -q / 2.0 + s, -q / 2.0 - s
        roots = [math.copysign(abs(u) ** (1 / 3), u) + math.copysign(abs(v) ** (1 / 3), v)]
    else:
        m = 2.0 * math.sqrt(-p / 3.0)
        arg = max(-1.0, min(1.0, 3.0 * q / (p * m))) if m else 0.0
        w = math.acos(arg) / 3.0
        roots = [m * math.cos(w - 2.0 * math.pi * k / 3.0) for k in range(3)]
    out = []
    for x in (r - a2 / 3.0 for r in roots):
        for _ in range(8):
            f = ((x + a2) * x + a1) * x + a0
            df = (3.0 * x + 2.0 * a2) * x + a1
            if df == 0:
                break
            x -= f / df
        out.append(x)
    return sorted(out)


def _transmission_cubic(t: float, u: float) -> list[float]:
    """Step 2 of FOURB-CR-3 and DRAGLINK-2: the positive real roots x of
    x^3 + 2x^2 - t^2 x - t^2 (1 + t^2) / u^2 = 0, as lambda = t / sqrt(x)."""
    roots = _cubic_real_roots(2.0, -t * t, -t * t * (1.0 + t * t) / (u * u))
    return [t / math.sqrt(x) for x in roots if x > 0]


@_method("FOURB-CR-3")
def fourb_cr_3(theta: float, psi: float) -> Synthesis:
    """FOURB-CR-3 (Freudenstein & Primrose): crank-rocker with rocker swing psi while the crank
    turns 180 + theta (degrees), with the least greatest deviation of mu from 90 degrees."""
    method = "FOURB-CR-3"
    data = {"theta": theta, "psi": psi}
    check_data(method, data)
    p = psi * RAD
    # ERRATUM S14: t = tan(theta_f / 2) and u = tan((theta_f - psi) / 2), theta_f = 180 + theta,
    # as -cot(theta/2) and -cot((theta - psi)/2): 180 + theta loses the digits of a small theta;
    # likewise sin(theta_f/2) = cos(theta/2), cos(theta_f/2) = -sin(theta/2) below.
    h, g = theta / 2 * RAD, (theta - psi) / 2 * RAD
    t = -1.0 / math.tan(h)
    u = -math.cos(g) / math.sin(g) if math.sin(g) else math.inf      # theta = psi: u infinite
    solutions, rejected = [], []
    for lam in _transmission_cubic(t, u):
        if not 1.0 <= lam * lam <= u * u * t * t:
            rejected.append(f"lambda = {lam:.6g}: lambda^2 is not in [1, u^2 t^2 = "
                            f"{u * u * t * t:.6g}] (not a crank-rocker)")
            continue
        a = math.sin(p / 2)
        b = abs(lam * a)
        c = math.hypot(math.cos(h), lam * math.sin(h))
        d = math.hypot(math.cos(g), lam * math.sin(g))
        try:
            theta0, psi0 = _extended_dead_centre(a / d, b / d, c / d)
            design = _crank_rocker(method, data, a, b, c, d, theta0, psi0, theta, psi,
                                   {"lambda": lam})
        except DesignError as error:
            rejected.append(f"lambda = {lam:.6g}: {error}")
            continue
        # Step 5: sin(Delta) = |(a +- d)^2 - c^2 - b^2| / 2bc, + for theta < 0, - for theta > 0
        # (d = 1): the deviation at the extreme that is the worse one for the sign of theta.
        ra = design.review
        sign = 1.0 if theta < 0 else -1.0
        delta = in_degrees(math.asin(min(1.0, abs((ra["a"] + sign) ** 2 - ra["c"] ** 2 - ra["b"] ** 2)
                                   / (2 * ra["b"] * ra["c"]))))
        review = dict(ra, Delta=delta, theta0=theta0, psi0=psi0)
        solutions.append(design._replace(review=review))
    require(solutions, f"{method}: no real root lambda of the cubic gives a crank-rocker "
                        f"({'; '.join(rejected) or 'no positive root'})")
    best = min(range(len(solutions)), key=lambda i: _deviation(solutions[i]))
    return Synthesis(method, tuple(solutions), best, tuple(rejected))


def _triangle_angle(x: float, y: float, z: float) -> float:
    """The angle (degrees) between sides x and y of the triangle x, y, z, opposite z, by Kahan's
    formula ("Miscalculating area and angles of a needle-like triangle"), accurate to a few
    roundings of the sides where the law of cosines cancels; DesignError if there is none."""
    x, y = max(x, y), min(x, y)
    require(x <= y + z and z <= x + y, f"no triangle has the sides {x:.6g}, {y:.6g}, {z:.6g}")
    mu = z - (x - y) if y >= z else y - (x - z)
    return in_degrees(2 * math.atan(math.sqrt(max(0.0, ((x - y) + z) * mu)
                                        / ((x + (y + z)) * ((x - z) + y)))))


def _extended_dead_centre(a: float, b: float, c: float) -> tuple[float, float]:
    """Crank angle theta0 and rocker angle psi0 (degrees) at the extended dead centre of the
    crank-rocker (review letters, d = 1), the rocker tip above the frame line: the angles of the
    triangle frame 1, crank and coupler in line a + b, rocker c (ERRATUM S14: the law of cosines
    cancels for a small crank and a rocker near the frame's length)."""
    reach = a + b
    theta0 = _triangle_angle(1.0, reach, c)
    require(0.0 < theta0 < 180.0, "the extended dead centre lies on the frame line")
    return theta0, 180.0 - _triangle_angle(1.0, c, reach)


def _centric(psi: float, mu_min: float) -> tuple[float, float, float, float, float, float]:
    """What FOURB-CR-4 and Volmer's eqs. need of psi and mu_min, without cancellation
    (ERRATUM S14): sin h, cos h (h = psi/2), cos m (m = mu_min),
    D = cos(m - h) cos(m + h) = cos^2 m - sin^2 h, which the review computes as that difference
    (1 - b^2 in FOURB-CR-4, the denominator of eqs. 6a-6b), and the extended dead centre
    (theta0, psi0): the rocker's chord between the dead centres of a centric crank-rocker passes
    through the crank pivot, so tan(theta0) = sqrt(D) / sin h and psi0 = theta0 + 90 - psi/2."""
    h = psi / 2 * RAD
    cos_h = math.sin((90.0 - psi / 2) * RAD)                  # 90 - psi/2 exact for psi near 180
    # m + h near 90 is the degenerate end (rocker c -> 0): sin(90 - psi/2 - mu_min), its
    # argument summed exactly (fsum), not cos(m + h)
    big_d = (math.sin(math.fsum((90.0, -psi / 2, mu_min)) * RAD)
             * math.sin(math.fsum((90.0, -psi / 2, -mu_min)) * RAD))
    require(big_d > 0, f"cos(mu_min - psi/2) cos(mu_min + psi/2) = {big_d:.6g} is not positive")
    theta0 = in_degrees(math.atan2(math.sqrt(big_d), math.sin(h)))
    cos_m = math.sin(math.fsum((90.0, -mu_min)) * RAD)         # keeps its digits near 90
    return math.sin(h), cos_h, cos_m, big_d, theta0, theta0 + 90.0 - psi / 2


@_method("FOURB-CR-4")
def fourb_cr_4(psi: float, mu_min: float) -> Synthesis:
    """FOURB-CR-4 (Brodell & Soni): centric crank-rocker (theta = 0, unit time ratio) with rocker
    swing psi and least transmission angle mu_min (degrees)."""
    method = "FOURB-CR-4"
    data = {"psi": psi, "mu_min": mu_min}
    check_data(method, data)
    sin_h, cos_h, cos_m, big_d, theta0, psi0 = _centric(psi, mu_min)
    # b = sqrt((1 - cos psi) / 2 cos^2 mu_min), c = sqrt((1 - b^2) / (1 - b^2 cos^2 mu_min)),
    # a = sqrt(b^2 + c^2 - 1), rewritten (ERRATUM S14): 1 - cos psi = 2 sin^2 h,
    # 1 - b^2 = D / cos^2 m, 1 - b^2 cos^2 m = cos^2 h, b^2 + c^2 - 1 = (b c cos m)^2.
    b = sin_h / cos_m
    c = math.sqrt(big_d) / (cos_m * cos_h)
    a = c * sin_h
    return _one(_crank_rocker(method, data, a, b, c, 1.0, theta0, psi0, 0.0, psi,
                              {"theta0": theta0, "psi0": psi0}))


@_method("FOURB-CR-4 (Volmer)")
def volmer_crank_rocker(psi: float, mu_min: float) -> Synthesis:
    """FOURB-CR-4 by Volmer's eqs. (6a)-(6c): the same centric crank-rocker from the ratios
    d/a, b/a, c/a (crank a = 1), normalised to d = 1."""
    method = "FOURB-CR-4 (Volmer)"
    data = {"psi": psi, "mu_min": mu_min}
    check_data(method, data)
    sin_h, cos_h, cos_m, big_d, theta0, psi0 = _centric(psi, mu_min)
    # eqs. (6a)-(6c) with the denominator cos^2 mu_min - sin^2(psi/2) as D (ERRATUM S14)
    d_a = cos_m * cos_h / (sin_h * math.sqrt(big_d))
    b_a = cos_h / math.sqrt(big_d)
    c_a = 1 / sin_h
    return _one(_crank_rocker(method, data, 1.0, b_a, c_a, d_a, theta0, psi0, 0.0, psi,
                              {"d/a": d_a, "b/a": b_a, "c/a": c_a, "theta0": theta0,
                               "psi0": psi0}))


# -- drag-links: DRAGLINK-1, DRAGLINK-2 -----------------------------------------------------------

def _drag_link(method: str, data: Data, a: float, b: float, c: float, d: float,
               review: dict[str, float]) -> tuple[FourBar, dict[str, float]]:
    """Normalise a drag-link (review letters: crank a, coupler b, output c, frame d) to d = 1 and
    check that it is one; the branch is settled by the caller."""
    _require_lengths(a_crank=a, b_coupler=b, c_output=c, d_frame=d)
    a, b, c = a / d, b / d, c / d
    link = four_bar_from_review(a, b, c, 1.0)
    found = grashof_class(link)
    require(found == "drag-link", f"{method}: the linkage a = {a:.6g}, b = {b:.6g}, "
                                   f"c = {c:.6g}, d = 1 is a {found}, not a drag-link")
    mu_min, mu_max = four_bar_transmission_extremes(link)
    _require_margin(mu_min, mu_max)
    return link, dict(review, a=a, b=b, c=c, d=1.0, mu_min=mu_min, mu_max=mu_max)


@_method("DRAGLINK-1")
def draglink_1(dpsi0: float, mu_min: float) -> Synthesis:
    """DRAGLINK-1 (Bagci): drag-link whose output turns dpsi0 while the crank turns 180 degrees
    between the crank-on-frame-line positions, with transmission angles mu_min, 180 - mu_min
    there."""
    method = "DRAGLINK-1"
    data = {"dpsi0": dpsi0, "mu_min": mu_min}
    check_data(method, data)
    dp, m = dpsi0 * RAD, mu_min * RAD
    c = 1.0
    # ERRATUM S3: b = c sqrt(sin dpsi0 / sin(dpsi0 - 2 mu_min)); the print has dpsi0 - mu_min.
    ratio = math.sin(dp) / math.sin(dp - 2 * m) if math.sin(dp - 2 * m) else -1.0
    require(ratio > 0, f"{method}: sin(dpsi0) / sin(dpsi0 - 2 mu_min) = {ratio:.6g} is not "
                        f"positive (footnote 4: no solution)")
    b = c * math.sqrt(ratio)
    lam = math.atan(b * math.sin(m) / (c + b * math.cos(m)))
    a1 = b * math.sin(m) / math.sin(lam)
    b1 = (-c * math.cos(dp) + b * math.cos(dp - m)) / math.cos(lam)
    a = (a1 + b1) / 2
    d = a1 - a
    link, review = _drag_link(method, data, a, b, c, d,
                              {"lambda": in_degrees(lam), "a1": a1, "b1": b1, "b_for_c1": b,
                               "a_for_c1": a})
    # The design positions are the crank on the frame line, phi = 0 (diagonal a - d = b1,
    # mu = mu_min) and phi = 180 (diagonal a + d = a1, mu = 180 - mu_min). There the output lies
    # at the triangle's angle at the output pivot (opposite the coupler b: lam2 and lam) from the
    # frame line, on the side that keeps it on one branch; the branch is the one on which the
    # output turns dpsi0 (counter-clockwise, with the crank) from phi = 0 to phi = 180.
    lam2 = in_degrees(math.atan2(b * math.sin(m), c - b * math.cos(m)))
    for branch in (1, 2):
        psi_1 = next(x for x in (lam2, -lam2) if _branch_at(link, 0.0, x) == branch)
        psi_2 = next(x for x in (180.0 - in_degrees(lam), 180.0 + in_degrees(lam))
                     if _branch_at(link, 180.0, x) == branch)
        if abs(wrap_degrees(psi_2 - psi_1 - dpsi0)) < 1e-6:
            break
    else:
        raise DesignError(f"{method}: on neither branch does the output turn dpsi0 = {dpsi0:g}")
    link = link._replace(branch=branch)
    psi_1 = wrap_degrees(psi_1)                 # the second as the first plus the turn (to rounding)
    positions = ((0.0, psi_1), (180.0, psi_1 + dpsi0 + wrap_degrees(psi_2 - psi_1 - dpsi0)))
    return _one(Design(method, data, link, review, positions, None,
                       review["mu_min"], review["mu_max"]))


def _draglink_2_links(dphi: float, dpsi: float, lam: float) -> tuple[float, float, float]:
    """DRAGLINK-2's link ratios a/d, b/d, c/d for lambda = b/d, coupler / frame (ERRATUM S4), by
    step 5 with epsilon = lambda / ut (the same as the procedure without optimisation)."""
    dl = (dphi - dpsi) * RAD
    t, u = math.tan(dphi * RAD / 2), math.tan(dpsi * RAD / 2)
    eps = lam / (u * t)
    a = math.sin(dpsi * RAD / 2) / math.sin(dl / 2) * math.sqrt(1 + t * t * eps * eps)
    b = u * t * eps
    c = math.sin(dphi * RAD / 2) / math.sin(dl / 2) * math.sqrt(1 + u * u * eps * eps)
    return a, b, c


@_method("DRAGLINK-2")
def draglink_2(dphi: float, dpsi: float, lam: float | None = None) -> Synthesis:
    """DRAGLINK-2 (Tsai): drag-link with unit velocity ratio at two positions dphi apart on the
    crank and dpsi on the output (degrees); lambda = b/d given, or chosen for the least greatest
    deviation of mu from 90 degrees (lam=None)."""
    method = "DRAGLINK-2"
    data = {"dphi": dphi, "dpsi": dpsi} if lam is None else {"dphi": dphi, "dpsi": dpsi,
                                                             "lambda": lam}
    check_data(method, dict(data, lam=lam))
    t, u = math.tan(dphi * RAD / 2), math.tan(dpsi * RAD / 2)
    if lam is None:
        # ERRATUM S13: lambda = t / sqrt(x) is negative for dphi > 180 (t < 0), and b/d = lambda
        # with it; the lengths depend on lambda^2 but b: take |lambda| (FOURB-CR-3 takes |b|).
        lambdas = [abs(x) for x in _transmission_cubic(t, u)]
    else:
        lambdas = [lam]
    solutions, rejected = [], []
    for value in lambdas:
        if lam is None and not 1.0 <= value * value <= u * u * t * t:
            rejected.append(f"lambda = {value:.6g}: lambda^2 is not in [1, u^2 t^2 = "
                            f"{u * u * t * t:.6g}]")
            continue
        try:
            solutions.append(_draglink_2_design(method, data, dphi, dpsi, value))
        except DesignError as error:
            rejected.append(f"lambda = {value:.6g}: {error}")
    require(solutions, f"{method}: no drag-link: {'; '.join(rejected) or 'no positive root'}")
    best = min(range(len(solutions)), key=lambda i: solutions[i].review["dmu_max"])
    return Synthesis(method, tuple(solutions), best, tuple(rejected))


def _draglink_2_design(method: str, data: Data, dphi: float, dpsi: float, lam: float) -> Design:
    """One DRAGLINK-2 design for lambda: link ratios, greatest deviation of mu, crank angle phi1
    at the first design position (step 8), the positions and branch."""
    a, b, c = _draglink_2_links(dphi, dpsi, lam)
    link, review = _drag_link(method, data, a, b, c, 1.0, {"lambda": lam})
    a, b, c, d = review["a"], review["b"], review["c"], 1.0
    # ERRATUM S5: sin(dmu_i) = (a^2 + d^2 - b^2 - c^2 +- 2da) / 2bc (the print wraps the quotient
    # in a sine) and dmu_max = max(|dmu_1|, |dmu_2|) (the print: max(mu_1, mu_2)).
    dmu = [in_degrees(math.asin(max(-1.0, min(1.0, (a * a + d * d - b * b - c * c + s * 2 * d * a)
                                        / (2 * b * c))))) for s in (1, -1)]
    dl = (dphi - dpsi) * RAD
    r = -b * math.cos(dpsi * RAD / 2) / (a * math.sin(dl / 2))
    s = -d * math.sin(dpsi * RAD / 2) / (a * math.sin(dl / 2))
    phi1 = (in_degrees(math.atan2(r, s)) - dphi / 2) % 360.0
    review.update(dmu_1=dmu[0], dmu_2=dmu[1], dmu_max=max(abs(x) for x in dmu), phi1=phi1)
    # At a unit-velocity-ratio position the coupler is parallel to the frame: the output pin is
    # the crank pin moved by the coupler along the frame line.
    positions = []
    for phi in (phi1, phi1 + dphi):
        px, py = link.b * math.cos(phi * RAD), link.b * math.sin(phi * RAD)
        pin = min(((px + sign * link.c, py) for sign in (1, -1)),
                  key=lambda q: abs(math.hypot(q[0] - link.a, q[1]) - link.d))
        require(abs(math.hypot(pin[0] - link.a, pin[1]) - link.d) < 1e-9 * link.d,
                 f"{method}: the coupler is not parallel to the frame at phi = {phi:g}")
        psi = in_degrees(math.atan2(pin[1], pin[0] - link.a))
        positions.append((phi, psi, _branch_at(link, phi, psi)))
    require(positions[0][2] == positions[1][2],
             f"{method}: the two design positions lie on different branches")
    require(abs(wrap_degrees(positions[1][1] - positions[0][1] - dpsi)) < 1e-6,
             f"{method}: the output turns {positions[1][1] - positions[0][1]:.6g}, not {dpsi:g}")
    link = link._replace(branch=positions[0][2])
    psi1 = wrap_degrees(positions[0][1])
    return Design(method, data, link, review,
                  ((phi1, psi1), (phi1 + dphi, psi1 + dpsi)), None,
                  review["mu_min"], review["mu_max"])


# -- function generators: FOURB-FG2-1, FOURB-FG3-1 -------------------------------------------------

def limit_angles(link: FourBar) -> list[float]:
    """Input angles (degrees, in [0, 360)) at which the four-bar meets a dead centre of its input
    (coupler and output in line, mu = 0 or 180): the ends of its assembly ranges."""
    out = []
    for reach in (link.c + link.d, abs(link.c - link.d)):
        # |B - O2|^2 = a^2 + b^2 - 2ab cos(phi) = reach^2
        cos_phi = (link.a ** 2 + link.b ** 2 - reach * reach) / (2 * link.a * link.b)
        if abs(cos_phi) <= 1 + 1e-12:
            phi = in_degrees(math.acos(max(-1.0, min(1.0, cos_phi))))
            out += [phi, (360.0 - phi) % 360.0]
    return out


def _travel_problem(link: FourBar, positions: Sequence[tuple[float, float]]) -> str | None:
    """Why the four-bar cannot drive through the positions (phi, psi) in turn on one branch
    without a dead centre, or None: a branch change, a limit angle inside the travel, or a
    transmission angle within MU_MARGIN of one."""
    branches = {_branch_at(link, phi, psi) for phi, psi in positions}
    if len(branches) > 1:
        return "branch defect: the positions lie on different assembly branches"
    lo = min(phi for phi, _ in positions)
    hi = max(phi for phi, _ in positions)
    for limit in limit_angles(link):
        inside = lo + (limit - lo) % 360.0
        if inside <= hi:
            return f"dead centre: the input meets a limit position at phi = {limit:.6g}"
    try:
        _require_margin(*_travel_transmission(link, lo, hi))
    except DesignError as error:
        return str(error)
    return None


def _output_turn(link: FourBar, phi_from: float, phi_to: float, psi_from: float, psi_to: float
                 ) -> float:
    """The output's turn (degrees, signed) while the crank turns from phi_from to phi_to on one
    branch with no dead centre of the input between, the output at psi_from and psi_to: the turn
    of the diagonal from the output pivot to the crank pin (exact: for b >= a it turns with the
    crank, arg(b - a e^-i phi) staying within 90 degrees; for b < a, arg(a - b e^i phi) does),
    plus the change of the angle between diagonal and output, which keeps its sign (it is 0 or
    180 only where coupler and output are in line) and so changes by less than 180."""
    def diagonal(phi: float) -> float:
        """arg(B - O4) less the part that turns with the crank (b >= a) or less 180 (b < a)."""
        x, y = math.cos(phi * RAD), math.sin(phi * RAD)
        if link.b >= link.a:
            return in_degrees(math.atan2(link.a * y, link.b - link.a * x))
        return in_degrees(math.atan2(-link.b * y, link.a - link.b * x))

    turns = phi_to - phi_from if link.b >= link.a else 0.0
    ends = [(phi, diagonal(phi) + (phi if link.b >= link.a else 180.0))
            for phi in (phi_from, phi_to)]
    gamma = [wrap_degrees(psi - direction) for psi, (_, direction) in zip((psi_from, psi_to), ends)]
    return turns + diagonal(phi_to) - diagonal(phi_from) + gamma[1] - gamma[0]


def _travel_transmission(link: FourBar, lo: float, hi: float) -> tuple[float, float]:
    """Transmission-angle extremes (degrees) over input angles lo..hi by eq. (1): at the ends, and
    at phi = 0 or 180 (mod 360) where the travel passes them."""
    phis = [lo, hi] + [lo + (x - lo) % 360.0 for x in (0.0, 180.0)]
    values = [in_degrees(math.acos(max(-1.0, min(1.0, cos_transmission(link, phi)))))
              for phi in phis if phi <= hi]
    return min(values), max(values)


@_method("FOURB-FG2-1")
def fourb_fg2_1(phij: float, psij: float, phi0: float, a: float, c: float) -> Synthesis:
    """FOURB-FG2-1 (Chiang): four-bar whose output turns psij while the crank turns phij from
    phi0 (degrees), for given crank a/d and output c/d; finds b/d and the output's psi0."""
    method = "FOURB-FG2-1"
    data = {"phij": phij, "psij": psij, "phi0": phi0, "a": a, "c": c}
    check_data(method, data)
    xi, ej = phij * RAD / 2, psij * RAD / 2
    r_a = math.sin(ej) / math.sin(xi - ej)
    r_b = math.sin(xi) / math.sin(xi - ej)
    # ERRATUM S12: steps 3-5 multiplied through by cos(phi0), which the printed a1, b1, c1 divide
    # by, so that phi0 = 90 is no singularity: a1 sin psi0 + b1 cos psi0 + c1 = 0 with
    f0 = phi0 * RAD
    a1 = r_a * math.cos(ej) / a + math.cos(f0 + xi - ej)
    b1 = r_a * math.sin(ej) / a - math.sin(f0 + xi - ej)
    c1 = -r_b / c * math.sin(f0 + xi)
    radius = math.hypot(a1, b1)
    # Data for which the coupler's length is the same at both positions for every psi0 (e.g. the
    # crank positions symmetric about the frame line with a matching psij): a1 = b1 = c1 = 0.
    scale = max(1.0, abs(r_a) / a, abs(r_b) / c)
    require(max(radius, abs(c1)) > 1e-9 * scale,
             f"{method}: a1 = b1 = c1 = 0 (to 1e-9 of their terms): every psi0 gives a "
             f"four-bar through both positions; the data do not determine psi0 and b")
    require(radius > 0 and abs(c1) <= radius,
             f"{method}: a1 sin(psi0) + b1 cos(psi0) + c1 = 0 has no real root (|c1| = "
             f"{abs(c1):.6g} > sqrt(a1^2 + b1^2) = {radius:.6g})")
    base = math.atan2(b1, a1)          # a1 sin x + b1 cos x = R sin(x + base)
    alpha = math.asin(max(-1.0, min(1.0, -c1 / radius)))
    solutions, rejected = [], []
    for psi0 in sorted({wrap_degrees(in_degrees(alpha - base)), wrap_degrees(in_degrees(math.pi - alpha - base))}):
        xa, ya = a * math.cos(f0), a * math.sin(f0)
        xb, yb = 1.0 + c * math.cos(psi0 * RAD), c * math.sin(psi0 * RAD)
        b = math.hypot(xb - xa, yb - ya)
        try:
            _require_lengths(b_coupler=b, a_crank=a, c_output=c, d_frame=1.0)
        except DesignError as error:
            rejected.append(f"psi0 = {psi0:.6g}: {error}")
            continue
        link = four_bar_from_review(a, b, c, 1.0)
        positions = ((phi0, psi0), (phi0 + phij, psi0 + psij))
        problem = _travel_problem(link, positions)
        if problem:
            rejected.append(f"psi0 = {psi0:.6g}, b = {b:.6g}: {problem}")
            continue
        link = link._replace(branch=_branch_at(link, phi0, psi0))
        # The equations cannot tell psij from psij -+ 360 (nor phij from phij -+ 360): the root
        # meets the positions; the output's turn along the crank's motion must be psij itself.
        turn = _output_turn(link, phi0, phi0 + phij, psi0, psi0 + psij)
        if abs(turn - psij) > 180.0:
            rejected.append(f"psi0 = {psi0:.6g}, b = {b:.6g}: while the crank turns "
                            f"{number_text(phij)} the output turns {turn:.6g}, not {number_text(psij)}: it meets "
                            f"the position, not the motion")
            continue
        travel = (min(phi0, phi0 + phij), max(phi0, phi0 + phij))
        mu_min, mu_max = _travel_transmission(link, *travel)
        review = {"a": a, "b": b, "c": c, "d": 1.0, "psi0": psi0}
        solutions.append(Design(method, data, link, review, positions, travel, mu_min, mu_max))
    require(solutions, f"{method}: no solution drives through both positions: "
                        f"{'; '.join(rejected)}")
    best = min(range(len(solutions)), key=lambda i: _deviation(solutions[i]))
    return Synthesis(method, tuple(solutions), best, tuple(rejected))


def _solve3(matrix: list[list[float]], rhs: list[float]) -> list[float]:
    """The solution of a 3x3 linear system by Cramer's rule; DesignError when singular."""
    def det(m: list[list[float]]) -> float:
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    d0 = det(matrix)
    scale = max(abs(x) for row in matrix for x in row) ** 3
    require(abs(d0) > 1e-12 * scale, "the system [A]{k} = {B} is singular: the three positions "
                                      "do not determine a four-bar")
    out = []
    for j in range(3):
        m = [list(row) for row in matrix]
        for i in range(3):
            m[i][j] = rhs[i]
        out.append(det(m) / d0)
    return out


@_method("FOURB-FG3-1")
def fourb_fg3_1(phi: Sequence[float], psi: Sequence[float]) -> Synthesis:
    """FOURB-FG3-1 (Freudenstein's equation): four-bar whose output is at psi[i] when the crank
    is at phi[i], three positions (degrees; the review's output angles, see the names above)."""
    method = "FOURB-FG3-1"
    check_data(method, {"phi": list(phi), "psi": list(psi)})
    phis, psis = list(phi), list(psi)
    data = {"phi1": phis[0], "phi2": phis[1], "phi3": phis[2],
            "psi1": psis[0], "psi2": psis[1], "psi3": psis[2]}
    f, p = [x * RAD for x in phis], [x * RAD for x in psis]
    matrix = [[math.cos(f[i]), math.cos(p[i]), -1.0] for i in range(3)]
    rhs = [math.cos(f[i] - p[i]) for i in range(3)]
    try:
        k1, k2, k3 = _solve3(matrix, rhs)
    except DesignError as error:
        raise DesignError(f"{method}: {error}") from None
    require(k1 > 0, f"{method}: k1 = {k1:.6g}: link length c/d = 1/k1 is not positive")
    require(k2 > 0, f"{method}: k2 = {k2:.6g}: link length a/d = 1/k2 is not positive")
    c, a = 1 / k1, 1 / k2
    b2 = a * a + c * c + 1 - 2 * a * c * k3
    require(b2 > 0, f"{method}: b^2 = a^2 + c^2 + d^2 - 2ac k3 = {b2:.6g}: the coupler length "
                     f"is not real and positive")
    b = math.sqrt(b2)
    _require_lengths(a_crank=a, b_coupler=b, c_output=c, d_frame=1.0)
    # at a position on a dead centre cos(mu) may round beyond 1: _travel_problem refuses it
    mus = [in_degrees(math.acos(max(-1.0, min(1.0, cos_transmission(four_bar_from_review(a, b, c, 1.0),
                                                                x)))))
           for x in phis]
    # The review's output angle is measured from the opposite direction (S7): paper psi =
    # psi - 180 (design_lines shows it as given: ASKED_ANGLES).
    positions = tuple((phi, psi - 180.0) for phi, psi in zip(phis, psis))
    link = four_bar_from_review(a, b, c, 1.0)
    problem = _travel_problem(link, positions)
    review = {f"A{i + 1}{j + 1}": matrix[i][j] for i in range(3) for j in range(3)}
    review.update({f"B{i + 1}": rhs[i] for i in range(3)})
    review.update(k1=k1, k2=k2, k3=k3, a=a, b=b, c=c, d=1.0, mu1=mus[0], mu2=mus[1], mu3=mus[2])
    link = link._replace(branch=_branch_at(link, *positions[0]))
    travel = (min(phis), max(phis))
    mu_min, mu_max = _travel_transmission(link, *travel)
    design = Design(method, data, link, review, positions, travel, mu_min, mu_max)
    require(problem is None, f"{method}: the design a = {a:.6g}, b = {b:.6g}, c = {c:.6g}, "
                              f"d = 1 cannot drive through the positions: {problem}", design)
    return _one(design)


# -- slider-cranks: SLID-FG2-1, SLID-FG2-2 -------------------------------------------------------

def _slider_design(method: str, data: Data, s1: float, s2: float, theta1: float, theta2: float,
                   review: dict[str, float]) -> Design:
    """Chen's slider-crank from its dead-centre positions (step 4 of SLID-FG2-1, step 1 of
    SLID-FG2-2): crank r, rod l, checks, conversion to the paper's letters."""
    c1, c2 = math.cos(theta1 * RAD), math.cos(theta2 * RAD)
    require(abs(c1) > 1e-12 and abs(c2) > 1e-12, f"{method}: cos(theta1) or cos(theta2) is 0")
    far, near = s1 / c1, s2 / c2          # pivot-to-pin distances l + r and l - r
    require(far > 0 and near > 0, f"{method}: s1/cos(theta1) = {far:.6g} and s2/cos(theta2) = "
                                   f"{near:.6g} (the distances l + r, l - r) are not both "
                                   f"positive")
    r = (far - near) / 2
    l = (far + near) / 2
    epsilon = review["epsilon"]
    _require_lengths(r_crank=r, l_rod=l)
    require(s1 > 0 and s2 > 0, f"{method}: a slider position s1 = {s1:.6g} or s2 = {s2:.6g} is "
                                f"not positive (the rod would point backwards)")
    link = slider_crank_from_review(r, l, epsilon)
    mu_min, mu_max = slider_transmission_extremes(link)
    _require_margin(mu_min, mu_max)
    review = dict(review, r=r, l=l, theta1=theta1, theta2=theta2, s1=s1, s2=s2, mu_min=mu_min)
    positions = ((theta1, s1), (theta2 - 180.0, s2))      # ERRATUM S10: theta2 is the pin's
    return Design(method, data, link, review, positions, None, mu_min, mu_max)


@_method("SLID-FG2-1")
def slid_fg2_1(dtheta: float, ds: float, epsilon: float) -> Synthesis:
    """SLID-FG2-1 (Chen): slider-crank whose slider moves ds between the dead centres while the
    crank turns dtheta (degrees), for the assumed offset epsilon."""
    method = "SLID-FG2-1"
    data = {"dtheta": dtheta, "ds": ds, "epsilon": epsilon}
    check_data(method, data)
    disc = ds * ds - 4 * (epsilon * ds / math.tan(dtheta * RAD) + epsilon * epsilon)
    require(disc >= 0, f"{method}: s1 is complex (ds^2 - 4(epsilon ds cot(dtheta) + "
                        f"epsilon^2) = {disc:.6g} < 0)")
    s1 = ds / 2 + math.sqrt(disc) / 2
    s2 = s1 - ds
    theta1 = in_degrees(math.atan(-epsilon / s1))
    theta2 = theta1 + dtheta + 180.0
    return _one(_slider_design(method, data, s1, s2, theta1, theta2, {"epsilon": epsilon}))


@_method("SLID-FG2-2")
def slid_fg2_2(theta1: float, theta2: float, s1: float, s2: float, tolerance: float = 1e-9
               ) -> Synthesis:
    """SLID-FG2-2 (Chen): slider-crank with dead centres at crank theta1, slider s1 and (the
    review's theta2: the pin's direction, crank at theta2 - 180) slider s2 (degrees); theta2 may
    differ by `tolerance` degrees from the direction the offset of the first gives."""
    method = "SLID-FG2-2"
    data = {"theta1": theta1, "theta2": theta2, "s1": s1, "s2": s2}
    check_data(method, data)
    epsilon = -s1 * math.tan(theta1 * RAD)
    # ERRATUM S8: both pins lie on the slider's line y = -epsilon, so the data must have
    # s1 tan(theta1) = s2 tan(theta2); the formulas use only the first.
    epsilon_2 = -s2 * math.tan(theta2 * RAD)
    # compared as the pin's direction at the second (an offset that agrees to 1e-9 of s1 can
    # turn the direction by much more when s2 is small)
    if abs(wrap_degrees(theta2 - in_degrees(math.atan2(-epsilon, s2)))) > tolerance:
        try:                                   # what the formulas give, for the error to show
            design = _slider_design(method, data, s1, s2, theta1, theta2, {"epsilon": epsilon})
        except DesignError:
            design = None
        raise DesignError(f"{method}: inconsistent dead centres: the offset from position 1, "
                          f"-s1 tan(theta1) = {epsilon:.6g}, differs from that from position 2, "
                          f"-s2 tan(theta2) = {epsilon_2:.6g} (theta2 = {theta2:.9g} is not "
                          f"the direction {in_degrees(math.atan2(-epsilon, s2)):.9g} of that pin)",
                          design)
    design = _slider_design(method, data, s1, s2, theta1, theta2, {"epsilon": epsilon})
    return _one(design)


# ---- 21. Synthesis: designs measured and checked by the engine -----------------------------------
#
# Holds: every design run through engine_outputs, the one adapter to the analysis (the accurate
# engine, never the synthesis formulas); analyze_design measures on the analysed linkage what it
# really does: rocker swing, crank rotation between the dead centres, the prescribed positions met
# or missed, the transmission-angle extremes. METHODS, the table of the methods, and a design's
# lines of text.
#
# Uses: sections 2, 8, 15, 19 and 20.
# Offers: engine_outputs, kind_and_dimensions, measured_transmission_angle, Measured, measure,
#   output_change, velocity_ratio, Check, analyze_design, ANGLE_TOLERANCE, LENGTH_TOLERANCE,
#   RATIO_TOLERANCE, conditioning, rounding_floor, misses, METHODS, ASKED_ANGLES, REVIEW_LETTERS,
#   letters, design_lines, design_commands, review_lines, whole_motion.


# -- the analysis adapter ------------------------------------------------------------------------

def engine_outputs(kind: str, dims: dict[str, float], phis: Iterable[float], branch: int = 1
                   ) -> list[float | None]:
    """The adapter to the analysis: output angle psi (degrees, (-180, 180]) of the plane
    four-bar (PLANE_FOUR_BAR, dims a b c d) or slider position x (PLANE_SLIDER_CRANK, dims b c
    e) at each input angle phi (degrees) on branch 1 or 2, computed by the accurate engine; None
    where the linkage cannot be assembled."""
    if kind not in (PLANE_FOUR_BAR, PLANE_SLIDER_CRANK):
        raise ValueError(f"engine_outputs: kind {kind!r} is neither {PLANE_FOUR_BAR!r} nor "
                         f"{PLANE_SLIDER_CRANK!r}")
    linkage = _engine_linkage(kind, tuple(dims[name] for name in LINKAGE_DIMENSIONS[kind]))
    return [m.output if m.status in (ASSEMBLED, DEAD_CENTRE, CHANGE_POINT) else None
            for m in linkage.sweep(phis, branch, derivatives=0)]


@functools.lru_cache(maxsize=256)
def _engine_linkage(kind: str, values: tuple[float, ...]) -> Linkage:
    """The engine's Linkage, built once per design (its constants take exact arithmetic)."""
    return Linkage(kind, **dict(zip(LINKAGE_DIMENSIONS[kind], values)))


# -- measuring the analysed linkage ---------------------------------------------------------------

def kind_and_dimensions(link: Designed) -> tuple[str, dict[str, float]]:
    """The adapter's kind and dims of a FourBar or SliderCrank."""
    if isinstance(link, FourBar):
        return PLANE_FOUR_BAR, {"a": link.a, "b": link.b, "c": link.c, "d": link.d}
    return PLANE_SLIDER_CRANK, {"b": link.b, "c": link.c, "e": link.e}


def _outputs(link: Designed, phis: Iterable[float]) -> list[float | None]:
    """The analysed output at each input angle (degrees), None where not assembled."""
    kind, dims = kind_and_dimensions(link)
    return engine_outputs(kind, dims, list(phis), link.branch)


def _output(link: Designed, phi: float) -> float | None:
    """The analysed output at one input angle."""
    return _outputs(link, (phi,))[0]


def measured_transmission_angle(link: Designed, phi: float, output: float) -> float:
    """The transmission angle (degrees) measured on the positions of the analysed linkage: at the
    coupler-output joint (four-bar); between the rod and the normal to the slider's line."""
    bx, by = link.b * math.cos(phi * RAD), link.b * math.sin(phi * RAD)
    if isinstance(link, FourBar):
        dx, dy = link.a + link.d * math.cos(output * RAD), link.d * math.sin(output * RAD)
        u, v = (bx - dx, by - dy), (link.a - dx, -dy)
        return in_degrees(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u[0] * v[0] + u[1] * v[1]))
    wx, wy = output - bx, link.e - by
    return in_degrees(math.atan2(abs(wx), abs(wy)))


class Measured(NamedTuple):
    """What the analysed linkage does over an input range (degrees): whether it assembles
    throughout, the output's and the transmission angle's extremes, the net output change."""
    assembled: bool
    output_min: Extreme
    output_max: Extreme
    output_change: float          # output at the end minus at the start, followed continuously
    mu_min: Extreme
    mu_max: Extreme


def _in_line(link: Designed, phi: float) -> float | None:
    """cross(B, P - B) for the analysed linkage at phi: zero where crank and coupler are in line
    (a dead centre of the output), B the crank pin, P the output pin or slider; None if not
    assembled."""
    out = _output(link, phi)
    if out is None:
        return None
    bx, by = link.b * math.cos(phi * RAD), link.b * math.sin(phi * RAD)
    if isinstance(link, FourBar):
        px, py = link.a + link.d * math.cos(out * RAD), link.d * math.sin(out * RAD)
    else:
        px, py = out, link.e
    return bx * (py - by) - by * (px - bx)


def _dead_centre(link: Designed, lo: float, hi: float) -> float | None:
    """The crank angle in [lo, hi] at which crank and coupler come in line (bisection on the
    analysed positions), or None when they do not change sides there."""
    g_lo, g_hi = _in_line(link, lo), _in_line(link, hi)
    if g_lo is None or g_hi is None or g_lo * g_hi > 0:
        return None
    for _ in range(200):
        mid = (lo + hi) / 2
        if mid in (lo, hi):
            break
        g_mid = _in_line(link, mid)
        if g_mid is None:
            return None
        if (g_mid > 0) == (g_lo > 0):
            lo, g_lo = mid, g_mid
        else:
            hi = mid
    return (lo + hi) / 2


_FULL_TURN_OFFSET = 0.1234567890123     # degrees: where measure starts a full turn


def measure(link: Designed, lo: float = 0.0, hi: float = 360.0, samples: int = 720) -> Measured:
    """Measure the analysed linkage over input angles lo..hi (default: a full turn) by dense
    sampling: the output's extremes at the dead centres (crank and coupler in line, located by
    bisection) or the travel's ends, the transmission angle's refined on the analysis."""
    angular = isinstance(link, FourBar)
    full_turn = abs(hi - lo - 360.0) < 1e-9
    if full_turn:
        # A full turn starts off the round angles, where designs put their dead centres: the
        # first and last samples are the same position, and a dead centre between them (a
        # crossing at 360 - 1e-14, in_line(0) and in_line(360) of opposite signs to rounding)
        # would be lost.
        lo, hi = lo + _FULL_TURN_OFFSET, hi + _FULL_TURN_OFFSET
    step = (hi - lo) / samples
    phis = [lo + step * i for i in range(samples)] + [hi]
    assembled = [o for o in _outputs(link, phis) if o is not None]
    if len(assembled) < len(phis):
        nan = Extreme(math.nan, math.nan)
        return Measured(False, nan, nan, math.nan, nan, nan)
    outputs = unwrapped(assembled, angular)

    def output_at(phi: float) -> float:
        """The output at phi, which assembles: between two samples that do."""
        value = _output(link, phi)
        assert value is not None, f"a gap between the samples at phi = {phi!r}"
        return value

    def output_near(phi: float, reference: float) -> float:
        """The output at phi, continuous with `reference`."""
        value = output_at(phi)
        return value + 360.0 * round((reference - value) / 360.0) if angular else value

    if full_turn and angular and abs(outputs[-1] - outputs[0]) > 180.0:
        out_min = out_max = Extreme(math.nan, math.nan)      # the output turns fully
    else:
        in_line = cast("list[float]", [_in_line(link, phi) for phi in phis])   # they assemble
        candidates = [] if full_turn else [Extreme(phis[0], outputs[0]),
                                           Extreme(phis[-1], outputs[-1])]
        for i in range(samples + 1):
            x: float | None
            if in_line[i] == 0:                                # a sample on a dead centre
                x = phis[i]
            elif i < samples and in_line[i] * in_line[i + 1] < 0:
                x = _dead_centre(link, phis[i], phis[i + 1])
            else:
                continue
            if x is not None:
                candidates.append(Extreme(x % 360.0 if full_turn else x,
                                          output_near(x, outputs[i])))
        if not candidates:                                     # a constant output
            candidates = [Extreme(phi, o) for phi, o in zip(phis, outputs)]
        out_min = min(candidates, key=lambda e: e.value)
        out_max = max(candidates, key=lambda e: e.value)

    def mu_at(phi: float) -> float:
        return measured_transmission_angle(link, phi, output_at(phi))

    def mu_extreme(values: list[float], maximum: bool) -> Extreme:
        """The greatest (least) transmission angle: every sampled local extreme (the ends
        included) refined within its neighbouring samples."""
        candidates = []
        last = len(values) - 1
        for i, v in enumerate(values):
            if full_turn:
                neighbours = [values[i - 1 if i else last - 1], values[i + 1 if i < last else 1]]
            else:
                neighbours = [values[j] for j in (i - 1, i + 1) if 0 <= j <= last]
            if all((v >= n) if maximum else (v <= n) for n in neighbours):
                left = phis[i] - step if full_turn or i > 0 else phis[i]
                right = phis[i] + step if full_turn or i < last else phis[i]
                candidates.append(Extreme(phis[i], v))
                if right > left:
                    x, value = extreme_of(mu_at, left, right, maximum)
                    candidates.append(Extreme(x % 360.0 if full_turn else x, value))
        pick = max if maximum else min
        return pick(candidates, key=lambda e: e.value)

    mus = [measured_transmission_angle(link, phi, o) for phi, o in zip(phis, outputs)]
    return Measured(True, out_min, out_max, outputs[-1] - outputs[0],
                    mu_extreme(mus, False), mu_extreme(mus, True))


def output_change(link: Designed, phi_from: float, phi_to: float, samples: int = 720
                  ) -> float | None:
    """The change of the analysed output while the input turns from phi_from to phi_to (degrees),
    followed continuously; None if the linkage does not assemble throughout."""
    phis = [phi_from + (phi_to - phi_from) * i / samples for i in range(samples + 1)]
    assembled = [v for v in _outputs(link, phis) if v is not None]
    if len(assembled) < len(phis):
        return None
    values = unwrapped(assembled, isinstance(link, FourBar))
    return values[-1] - values[0]


def velocity_ratio(link: Designed, phi: float) -> float | None:
    """d(output)/d(input) of the analysed linkage at phi (degrees per degree, or length per
    degree) from its positions: the velocities of crank and output pins along the coupler agree,
    b sin(phi - theta3) = d sin(psi - theta3) dpsi/dphi (slider: x' cos theta3)."""
    out = _output(link, phi)
    if out is None:
        return None
    bx, by = link.b * math.cos(phi * RAD), link.b * math.sin(phi * RAD)
    if isinstance(link, FourBar):
        px, py = link.a + link.d * math.cos(out * RAD), link.d * math.sin(out * RAD)
        theta3 = math.atan2(py - by, px - bx)
        return (link.b * math.sin(phi * RAD - theta3)) / (link.d * math.sin(out * RAD - theta3))
    theta3 = math.atan2(link.e - by, out - bx)
    return -link.b * math.sin(phi * RAD - theta3) / math.cos(theta3) * RAD


class Check(NamedTuple):
    """One thing the analysed linkage should do: measured against expected; miss is the absolute
    difference (angles: modulo 360), None when it could not be measured."""
    name: str
    measured: float | None
    expected: float
    unit: str = "deg"             # "deg" (modulo 360), "rotation" (degrees), "length", "ratio"

    @property
    def miss(self) -> float:
        if self.measured is None or (isinstance(self.measured, float)
                                     and math.isnan(self.measured)):
            return math.inf
        difference = self.measured - self.expected
        return abs(wrap_degrees(difference)) if self.unit == "deg" else abs(difference)


def analyze_design(design: Design) -> list[Check]:
    """Run the design through the analysis and measure what it really does against what its
    method prescribes and what the design claims: a list of Check."""
    return list(_DESIGN_CHECKS[design.method](design))


def _measured_mu(link: Designed, phi: float) -> float | None:
    """The transmission angle measured at phi, None where the analysed linkage does not
    assemble."""
    out = _output(link, phi)
    return None if out is None else measured_transmission_angle(link, phi, out)


def _crank_rocker_checks(design: Design) -> Iterator[Check]:
    """FOURB-CR-1..4 and Volmer's: over a full turn the rocker's extremes are the dead centres;
    from the extended one (least rocker angle) the crank turns 180 + theta, counter-clockwise, to
    the folded one while the rocker turns with it (the sense in which the review's theta is
    signed)."""
    data = design.data
    m = measure(design.linkage)
    yield Check("assembled", float(m.assembled), 1.0, "ratio")
    yield Check("rocker_swing", m.output_max.value - m.output_min.value, data["psi"])
    yield Check("crank_rotation", (m.output_max.phi - m.output_min.phi) % 360.0,
                180.0 + data.get("theta", 0.0))
    for (phi, psi), extreme, where in ((design.positions[0], m.output_min, "extended"),
                                       (design.positions[1], m.output_max, "folded")):
        yield Check(f"{where}_dead_centre_phi", extreme.phi, phi)
        yield Check(f"{where}_dead_centre_psi", extreme.value, psi)
    yield Check("mu_min", m.mu_min.value, design.mu_min)
    yield Check("mu_max", m.mu_max.value, design.mu_max)
    if "mu_min" in data:
        yield Check("mu_min_prescribed", m.mu_min.value, data["mu_min"])


def _drag_link_checks(design: Design, m: Measured, output_rotation: float) -> Iterator[Check]:
    """What DRAGLINK-1 and -2 check alike: both links turn fully, the design positions are met,
    the output turns `output_rotation` between them."""
    link = design.linkage
    (phi1, psi1), (phi2, psi2) = design.positions
    yield Check("assembled", float(m.assembled), 1.0, "ratio")
    yield Check("output_turn", m.output_change, 360.0, "rotation")
    yield Check("position1_psi", _output(link, phi1), psi1)
    yield Check("position2_psi", _output(link, phi2), psi2)
    yield Check("output_rotation", output_change(link, phi1, phi2), output_rotation, "rotation")
    yield Check("mu_min", m.mu_min.value, design.mu_min)
    yield Check("mu_max", m.mu_max.value, design.mu_max)


def _draglink_1_checks(design: Design) -> Iterator[Check]:
    """DRAGLINK-1: cos(mu_min) = -cos(mu_max) at the design positions: mu_min at one, 180 -
    mu_min at the other."""
    link, data = design.linkage, design.data
    yield from _drag_link_checks(design, measure(link), data["dpsi0"])
    (phi1, _), (phi2, _) = design.positions
    yield Check("position1_mu", _measured_mu(link, phi1), data["mu_min"])
    yield Check("position2_mu", _measured_mu(link, phi2), 180.0 - data["mu_min"])


def _draglink_2_checks(design: Design) -> Iterator[Check]:
    """DRAGLINK-2: the unit velocity ratio at both design positions, dphi apart."""
    link, data = design.linkage, design.data
    m = measure(link)
    yield from _drag_link_checks(design, m, data["dpsi"])
    (phi1, _), (phi2, _) = design.positions
    yield Check("crank_rotation", phi2 - phi1, data["dphi"], "rotation")
    yield Check("position1_velocity_ratio", velocity_ratio(link, phi1), 1.0, "ratio")
    yield Check("position2_velocity_ratio", velocity_ratio(link, phi2), 1.0, "ratio")
    yield Check("dmu_max", max(90.0 - m.mu_min.value, m.mu_max.value - 90.0),
                design.review["dmu_max"])


def _function_generator_checks(design: Design) -> Iterator[Check]:
    """FOURB-FG2-1, FOURB-FG3-1: over the travel only, one branch, no dead centre (the input's
    dead centre is mu = 0 or 180), every prescribed position met."""
    link, data = design.linkage, design.data
    assert design.travel is not None             # a function generator designs for a travel
    lo, hi = design.travel
    m = measure(link, lo, hi, samples=max(60, int(4 * (hi - lo))))
    yield Check("assembled", float(m.assembled), 1.0, "ratio")
    yield Check("no_dead_centre", float(min(m.mu_min.value, 180.0 - m.mu_max.value) > 1e-6), 1.0,
                "ratio")
    first_phi = design.positions[0][0]
    rotations = ([data["psij"]] if "psij" in data
                 else [data["psi2"] - data["psi1"], data["psi3"] - data["psi1"]])
    for i, (phi, psi) in enumerate(design.positions, 1):
        yield Check(f"position{i}_psi", _output(link, phi), psi)
        if i > 1:
            # FOURB-FG2-1 prescribes a motion, psij: the turn itself (its equations cannot
            # tell psij from psij -+ 360, the method checks the turn); FOURB-FG3-1
            # prescribes positions: their differences, modulo 360
            yield Check(f"rotation_1_to_{i}", output_change(link, first_phi, phi),
                        rotations[i - 2], "rotation" if "psij" in data else "deg")
        if f"mu{i}" in design.review:
            yield Check(f"position{i}_mu", _measured_mu(link, phi), design.review[f"mu{i}"])
    yield Check("mu_min", m.mu_min.value, design.mu_min)
    yield Check("mu_max", m.mu_max.value, design.mu_max)


def _slider_crank_checks(design: Design) -> Iterator[Check]:
    """SLID-FG2-1, SLID-FG2-2: the slider's extremes are the dead centres; from the outer one
    the crank turns dtheta counter-clockwise to the inner one."""
    data = design.data
    m = measure(design.linkage)
    yield Check("assembled", float(m.assembled), 1.0, "ratio")
    stroke = m.output_max.value - m.output_min.value
    if "ds" in data:
        yield Check("stroke", stroke, data["ds"], "length")
        yield Check("crank_rotation", (m.output_min.phi - m.output_max.phi) % 360.0,
                    data["dtheta"])
    else:
        yield Check("stroke", stroke, data["s1"] - data["s2"], "length")
    (phi1, s1), (phi2, s2) = design.positions
    yield Check("outer_dead_centre_phi", m.output_max.phi, phi1)
    yield Check("outer_dead_centre_x", m.output_max.value, s1, "length")
    yield Check("inner_dead_centre_phi", m.output_min.phi, phi2)
    yield Check("inner_dead_centre_x", m.output_min.value, s2, "length")
    yield Check("mu_min", m.mu_min.value, design.mu_min)
    yield Check("mu_max", m.mu_max.value, design.mu_max)


# What analyze_design checks, a row a method (DATA's names).
_DESIGN_CHECKS: dict[str, Callable[[Design], Iterator[Check]]] = {
    "FOURB-CR-1": _crank_rocker_checks, "FOURB-CR-2": _crank_rocker_checks,
    "FOURB-CR-3": _crank_rocker_checks, "FOURB-CR-4": _crank_rocker_checks,
    "FOURB-CR-4 (Volmer)": _crank_rocker_checks,
    "DRAGLINK-1": _draglink_1_checks, "DRAGLINK-2": _draglink_2_checks,
    "FOURB-FG2-1": _function_generator_checks, "FOURB-FG3-1": _function_generator_checks,
    "SLID-FG2-1": _slider_crank_checks, "SLID-FG2-2": _slider_crank_checks,
}


ANGLE_TOLERANCE = 1e-7            # degrees
LENGTH_TOLERANCE = 1e-9           # times the largest link
RATIO_TOLERANCE = 1e-6            # velocity ratios


def conditioning(design: Design) -> float:
    """How much the tolerances grow for a near-locking design, whose transmission angle comes
    within 1 degree of 0 or 180: its positions are ill-conditioned, as 1 / sin(mu)."""
    worst = min(design.mu_min, 180.0 - design.mu_max)
    return max(1.0, math.sin(RAD) / max(math.sin(worst * RAD), 1e-300))


def rounding_floor(design: Design, checks: list[Check] | None = None) -> dict[str, float]:
    """Per check name, the miss that rounding the design's lengths to doubles alone can cause:
    the change of the measured value when each length moves by 2^-40 of itself, scaled to one
    rounding (2^-53) and summed over the lengths. Some designs are that ill-conditioned
    (FOURB-CR-4 with psi = 0.0015, mu_min = 0.1: one rounding of a length turns the crank rotation
    1e-4 degree); a formula that cancels misses by orders of magnitude more (erratum S14)."""
    base = {c.name: c for c in (analyze_design(design) if checks is None else checks)}
    floor = dict.fromkeys(base, 0.0)
    link = design.linkage
    for name in link._fields[:-1]:
        if getattr(link, name) == 0:
            continue
        moved = link._replace(**{name: getattr(link, name) * (1 + 2.0 ** -40)})
        for check in analyze_design(design._replace(linkage=moved)):
            was = base[check.name].measured
            if check.measured is None or was is None:
                continue
            change = check.measured - was
            floor[check.name] += abs(wrap_degrees(change) if check.unit == "deg" else change) * 2.0 ** -13
    return floor


def misses(design: Design, checks: list[Check] | None = None) -> list[Check]:
    """The checks of the design that miss beyond tolerance (an empty list: it does what it
    should): the tolerance, widened for a near-locking design (conditioning), or four times what
    rounding its lengths alone causes (rounding_floor), whichever is larger."""
    checks = analyze_design(design) if checks is None else checks
    size = max(abs(x) for x in design.linkage[:-1])
    scale = conditioning(design)
    limits = {"deg": ANGLE_TOLERANCE * scale, "rotation": ANGLE_TOLERANCE * scale,
              "length": LENGTH_TOLERANCE * size * scale, "ratio": RATIO_TOLERANCE * scale}
    over = [check for check in checks if not check.miss <= limits[check.unit]]
    if not over:
        return over
    floor = rounding_floor(design, checks)
    return [check for check in over if not check.miss <= limits[check.unit] + 4 * floor[check.name]]


# -- the command line: python3 linkage.py design METHOD --name value ... -------------------------

# the command's name: (function, the method's name in DATA)
METHODS: dict[str, tuple[Callable[..., Synthesis], str]] = {
    "fourb-cr-1": (fourb_cr_1, "FOURB-CR-1"), "fourb-cr-2": (fourb_cr_2, "FOURB-CR-2"),
    "fourb-cr-3": (fourb_cr_3, "FOURB-CR-3"), "fourb-cr-4": (fourb_cr_4, "FOURB-CR-4"),
    "volmer": (volmer_crank_rocker, "FOURB-CR-4 (Volmer)"),
    "draglink-1": (draglink_1, "DRAGLINK-1"), "draglink-2": (draglink_2, "DRAGLINK-2"),
    "fourb-fg2-1": (fourb_fg2_1, "FOURB-FG2-1"), "fourb-fg3-1": (fourb_fg3_1, "FOURB-FG3-1"),
    "slid-fg2-1": (slid_fg2_1, "SLID-FG2-1"), "slid-fg2-2": (slid_fg2_2, "SLID-FG2-2"),
}


# The angles a method's data measure otherwise than the program (the crank angle phi and the
# output angle psi counter-clockwise from the frame line, the output pivot at (a, 0)): (method,
# coordinate): what the program's angle is added to, to give the data's, and what it means.
ASKED_ANGLES = {
    ("FOURB-FG3-1", "psi"): (180.0, "as given: the review's output angle, measured from the "
                                    "opposite direction; the program's psi is 180 less"),
}
REVIEW_LETTERS = {FourBar: "a crank, b coupler, c output, d frame",
                  SliderCrank: "r crank, l rod, epsilon offset (the slider on y = -epsilon)"}


def letters(link: Designed) -> str:
    """The program's letters of a designed linkage and their meanings, as `run` takes them."""
    names = ("a", "b", "c", "d") if isinstance(link, FourBar) else ("b", "c", "e")
    return ", ".join(f"{n} {DIMENSION_NAMES[n].removeprefix('the ')}" for n in names)


def design_lines(design: Design) -> list[str]:
    """The `name = value` lines of one design, in the program's letters and angles: the lengths,
    the branch, the design positions (angles as the data give them: ASKED_ANGLES) and the
    transmission angle's extremes."""
    link = design.linkage
    names = ("a", "b", "c", "d") if isinstance(link, FourBar) else ("b", "c", "e")
    lines = [f"{n} = {value_text(getattr(link, n))}" for n in names]
    lines.append(f"branch = {link.branch}")
    output = "psi" if isinstance(link, FourBar) else "x"
    for i, position in enumerate(design.positions, 1):
        for name, value in zip(("phi", output), position):
            shift, note = ASKED_ANGLES.get((design.method, name), (0.0, ""))
            lines.append(f"position{i}.{name} = {value_text(value + shift)}"
                         + (f"  # {note}" if note else ""))
    if design.travel is not None:
        lines.append(f"travel.from = {value_text(design.travel[0])}")
        lines.append(f"travel.to = {value_text(design.travel[1])}")
    lines.append(f"mu_min = {value_text(design.mu_min)}")
    lines.append(f"mu_max = {value_text(design.mu_max)}")
    return lines


def design_commands(design: Design) -> list[str]:
    """The commands that take one design further, `name = value` lines to paste: analyse it on
    its branch, and its forces (RPM and KG to fill in); the lengths in full precision (repr),
    so that analyse sees the design itself, not one rounded to 10 digits."""
    kind, dims = kind_and_dimensions(design.linkage)
    letters = " ".join(f"--{n} {v!r}" for n, v in dims.items())
    masses = " ".join(f"--mass-{role} KG" for role in ("crank", "coupler", "output"))
    return [f"command.analyse = python3 linkage.py analyse {kind} {letters} "
            f"--branch {design.linkage.branch}",
            f"command.forces = python3 linkage.py forces {kind} {letters} "
            f"--branch {design.linkage.branch} --speed RPM {masses} --gravity 9.80665"]


def review_lines(design: Design) -> list[str]:
    """The review's own unknowns of one design, under its names and letters: a second block,
    labelled, apart from design_lines."""
    return ([f"review = its own numbers, in its letters: {REVIEW_LETTERS[type(design.linkage)]}"]
            + [f"review.{k} = {value_text(v)}" for k, v in design.review.items()])


def whole_motion(design: Design, step: float = 5.0) -> tuple[float, float, float]:
    """The input angles (from, to, step in degrees) over which the designed linkage moves: a
    full turn from the first design position when its crank turns fully, else from one limit
    of the input to the next across the design's travel (half a step inside each, where the
    position still exists)."""
    link = design.linkage
    first = design.positions[0][0]
    limits = [] if isinstance(link, SliderCrank) else limit_angles(link)
    if not limits or (isinstance(link, FourBar)
                      and grashof_class(link) in ("crank-rocker", "drag-link")):
        return first, first + 360.0 - step, step
    lo = min(phi for phi, _ in design.positions)
    below = max(lo - (lo - x) % 360.0 for x in limits)
    above = min(lo + (x - lo) % 360.0 for x in limits if (x - lo) % 360.0 > 0)
    count = max(24, math.ceil((above - below) / step))
    step = (above - below) / count
    return below + step / 2, above - step / 2, step


# ---- 22. Scenes: a figure's data, read and checked -----------------------------------------------
#
# A scene (data/scenes/*.toml) is one figure: a linkage's kind and its dimensions, the input range,
# the branch(es), the precision and the panels. `scene` computes what the panels need, writes the
# DAT files, and draws the figure as the paper does - (a) displacement, (b) velocity and
# acceleration against the input angle - as a plain-text plot (80 x 24, no dependency) or a PNG
# (matplotlib, the `plot` extra). `plot` draws the same figure from DAT files already written.
#
# A scene with [simulation] is a run in time instead (section 25 runs it): its keys are read
# here, as [dynamics]' are, each value's shape checked where the file is read.
#
# Uses: sections 1, 2, 6, 7, 9, 15 and 16.
# Offers: SCENE_KEYS, REQUIRED_SCENE_KEYS, QUANTITIES, FORCE_QUANTITIES, QUANTITY_FILES,
#   MECHANISM_PANEL, MAX_FRAMES, PRECISIONS, MAX_SCENE_POINTS, SCENE_LARGEST, AXIS_LABELS,
#   INPUT_AXIS, DRAWN_UP_TO, DRAWN_DOWN_TO, DRAWN_CLOSEST, drawable_range, PanelSpec, Scene,
#   scene_error, load_scene, known_scenes, scene_path, scene_list, DYNAMICS_KEYS, BODY_KEYS,
#   Dynamics, scene_dynamics, SIMULATION_KEYS, SIMULATION_QUANTITIES, SimulationSettings,
#   scene_simulation.


SCENE_KEYS = {  # key: what is expected (the error messages quote it)
    "title": "a string (the figure's title)",
    "kind": f"one of {', '.join(LINKAGE_DIMENSIONS)}",
    "dimensions": "a table of the mechanism's dimensions",
    "input": "a table with from, to and step (degrees)",
    "branches": "a list of branches, 1 (A+B) and/or 2 (A-B), and with precision double "
                "\"follow\" (the motion followed from branch 1 through change points)",
    "precision": "basic, double or both",
    "fast": "true or false: the double-precision numbers by the vectorised engine (needs numpy)",
    "panels": "a list of 1 to 3 tables [[panels]], each with quantities and optional limits "
              "and notes; or one [[panels]] with quantities = [\"mechanism\"] and optional "
              "angles",
    "coupler": "[u] or [u, v], a mechanism scene's point of the coupler (as run --coupler): "
               "drawn on the coupler, its curve traced on each branch, the transmission angle "
               "charted",
    "marked": "a list of input angles (degrees): a mechanism scene's positions drawn faint under "
              "every frame and numbered 1, 2, ... (design --scene writes the design positions)",
    "mechanism": "the old name of kind, still taken",
    "dynamics": "a table [dynamics]: the speed, the bodies' masses, gravity and the loads, for "
                "the forces (the panels torque, joint_forces and shaking; the CSV's columns; a "
                "mechanism scene's arrows, with forces = true; the explorer's torque)",
    "forces": "true or false: a mechanism scene draws each joint's force as an arrow (needs "
              "[dynamics]; not the spherical four-bar, whose joints' forces rigid bodies leave "
              "undetermined)",
    "simulation": "a table [simulation]: the motion in time under [dynamics] (its time, step, "
                  "initial angle and speed, driver, springs; data/scenes/simulate-*.toml show "
                  "one), drawn against time or, with panels = [{quantities = [\"mechanism\"]}], "
                  "moving in real time",
}
REQUIRED_SCENE_KEYS = ("kind", "dimensions", "input", "branches", "panels")
QUANTITIES = ("displacement", "velocity", "acceleration", "transmission")
FORCE_QUANTITIES = ("torque", "joint_forces", "shaking")     # a scene with [dynamics]: forces()
QUANTITY_FILES = dict(zip(QUANTITIES, DatFiles.NAMES + (DatFiles.MU,)))
MECHANISM_PANEL = "mechanism"    # the linkage drawn (a scene of its own, mechanism_drawing)
MAX_FRAMES = 3600                # the most poses a mechanism scene draws
PRECISIONS = {"basic": ("basic",), "double": ("double",), "both": ("basic", "double")}
MAX_SCENE_POINTS = 100_000
SCENE_LARGEST = 1 << 20          # bytes: the largest scene file read (the program's: < 4 KB)
# Axis labels (name, symbol, unit) by quantity, for four-bars, slider-cranks and DAT files of an
# unknown kind.
AXIS_LABELS = {
    "four-bar": {"displacement": ("output angle", "psi", "deg"),
                 "velocity": ("velocity", "dpsi/dphi", "rad/rad"),
                 "acceleration": ("acceleration", "d2psi/dphi2", "rad/rad^2")},
    "slider": {"displacement": ("slider position", "x", "length"),
               "velocity": ("velocity", "dx/dphi", "length/rad"),
               "acceleration": ("acceleration", "d2x/dphi2", "length/rad^2")},
    "unknown": {"displacement": ("output", "ANG.DAT", "deg, or length for a slider"),
                "velocity": ("velocity", "VEL.DAT", "per rad"),
                "acceleration": ("acceleration", "ACC.DAT", "per rad^2")},
}
for _labels in AXIS_LABELS.values():
    _labels["transmission"] = ("transmission angle", "mu", "deg")
INPUT_AXIS = ("input angle", "phi", "deg")

DRAWN_UP_TO = 1e100      # the largest value a figure draws (GW-BASIC's numbers end at 1.7E+38)
DRAWN_DOWN_TO = 1e-100   # the least span an axis divides: values closer are drawn as one
DRAWN_CLOSEST = 1e-9     # the least span of a scene's limits, relative to the larger (its ticks
#                          apart in the text they are written in)


def drawable_range(lo: float, hi: float) -> bool:
    """Whether lo..hi (a panel's limits) is an axis a figure can draw: finite, low < high, each
    within +-DRAWN_UP_TO, and far enough apart for its ticks to be computed and told apart."""
    return (math.isfinite(lo) and math.isfinite(hi) and -DRAWN_UP_TO <= lo < hi <= DRAWN_UP_TO
            and hi - lo >= max(DRAWN_DOWN_TO, DRAWN_CLOSEST * max(abs(lo), abs(hi))))


class PanelSpec(NamedTuple):
    quantities: tuple[str, ...]
    limits: tuple[float, float] | None      # the y range, or None: from the data
    angles: tuple[float, ...] | None = None  # a mechanism panel's input angles (None: the sweep)
    notes: tuple[tuple[float, float, str], ...] = ()    # (x, y, text): said on the PNG there


class Scene(NamedTuple):
    path: str
    title: str
    kind: str
    dimensions: dict[str, float]
    start: float
    stop: float
    step: float
    branches: tuple[int | str, ...]        # 1, 2, FOLLOW
    precisions: tuple[str, ...]
    panels: tuple[PanelSpec, ...]
    fast: bool = False               # the double series by Linkage.sweep_arrays
    coupler: tuple[float, float] | None = None   # a mechanism scene's coupler point (u, v)
    marked: tuple[float, ...] = ()   # a mechanism scene's input angles drawn faint and numbered
    dynamics: Dynamics | None = None     # the [dynamics] table: forces computed, else none
    simulation: SimulationSettings | None = None     # the [simulation] table: a run in time
    arrows: bool = False             # a mechanism scene draws the joints' forces (forces = true)

    @property
    def transmission(self) -> bool:
        """Whether a panel shows the transmission angle (MU.DAT, the accurate engine's)."""
        return any("transmission" in panel.quantities for panel in self.panels)

    @property
    def derivatives(self) -> int:
        """How many derivatives the panels show: 0 (displacement only), 1 or 2."""
        shown = {q for panel in self.panels for q in panel.quantities}
        return 2 if "acceleration" in shown else 1 if "velocity" in shown else 0

    @property
    def draws_mechanism(self) -> bool:
        """A mechanism scene: the linkage drawn (and animated) rather than curves plotted."""
        return self.panels[0].quantities == (MECHANISM_PANEL,)

    def angles(self) -> list[float]:
        """The input angles of the sweep (or of a mechanism panel's `angles`)."""
        if self.panels[0].angles is not None:
            return list(self.panels[0].angles)
        return evenly_spaced_angles(self.start, self.stop, self.step)


# -- reading a scene ---------------------------------------------------------------------------

def _is_number(x: object) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _kind_of(x: object) -> str:
    names = {bool: "a boolean", int: "an integer", float: "a number", str: "the string",
             list: "a list", dict: "a table"}
    what = next((n for t, n in names.items() if isinstance(x, t)), type(x).__name__)
    return f"{what} {x!r}" if isinstance(x, (str, int, float)) else what


def scene_error(path: str, key: str, expected: str, got: object = None) -> SceneError:
    return SceneError(f"{path}: key '{key}': expected {expected}"
                      + ("" if got is None else f", got {_kind_of(got)}"))


def _unknown_keys(path: str, table: Iterable[str], allowed: Iterable[str], prefix: str = ""
                  ) -> None:
    for key in table:
        if key not in allowed:
            raise SceneError(f"{path}: unknown key '{prefix}{key}'; expected one of "
                             + ", ".join(f"'{prefix}{k}'" for k in allowed))


def load_scene(path: str) -> Scene:
    """Read and check a scene file; a SceneError names the file, the key and what it expects."""
    import tomllib
    try:        # opened without waiting: a FIFO that no program writes reads as empty
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        os.set_blocking(fd, True)       # then read as usual: a writer's text waited for
        with open(fd, "rb") as fh:
            raw = fh.read(SCENE_LARGEST + 1)   # no more: /dev/zero is not read to the end
    except OSError as e:
        raise SceneError(f"{path}: cannot read the scene: {e.strerror}") from None
    if not raw.strip():
        raise SceneError(f"{path}: the scene is empty")
    if b"\0" in raw:
        raise SceneError(f"{path}: not a TOML file: binary data (a NUL byte at offset "
                         f"{raw.index(0):,})")
    if len(raw) > SCENE_LARGEST:
        raise SceneError(f"{path}: not a scene: larger than {SCENE_LARGEST:,} bytes (a scene "
                         "is a few kilobytes of TOML)")
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as e:
        raise SceneError(f"{path}: not a TOML file: not UTF-8 text (byte {raw[e.start]:#04x} "
                         f"at offset {e.start:,})") from None
    except tomllib.TOMLDecodeError as e:
        raise SceneError(f"{path}: not a TOML file: {e}") from None
    _unknown_keys(path, data, SCENE_KEYS)
    if "kind" in data and "mechanism" in data:
        raise SceneError(f"{path}: key 'mechanism' is the old name of 'kind': give one of them")
    kind_key = "mechanism" if "mechanism" in data else "kind"     # as the file names it
    data = {"kind" if key == "mechanism" else key: value for key, value in data.items()}
    if "simulation" in data:
        return _simulation_scene(path, data, kind_key)
    for key in REQUIRED_SCENE_KEYS:
        if key not in data:
            raise SceneError(f"{path}: key '{key}' is missing: expected {SCENE_KEYS[key]}")

    kind = data["kind"]
    if not isinstance(kind, str) or kind not in LINKAGE_DIMENSIONS:
        raise scene_error(path, kind_key, SCENE_KEYS["kind"], kind)
    dims = _scene_dimensions(path, kind, data["dimensions"])
    start, stop, step = _scene_sweep(path, data["input"])

    branches = data["branches"]
    if (not isinstance(branches, list) or not branches
            or not all(b in (1, 2, FOLLOW) and not isinstance(b, bool) for b in branches)
            or len(set(branches)) != len(branches)):
        raise scene_error(path, "branches", "[1], [2] or [1, 2], and with precision double "
                           "\"follow\" among them", branches)
    branches = [int(b) if b in (1, 2) else b for b in branches]     # 1.0 is branch 1
    panels = data["panels"]
    if (not isinstance(panels, list) or not 1 <= len(panels) <= 3
            or not all(isinstance(p, dict) for p in panels)):
        raise scene_error(path, "panels", SCENE_KEYS["panels"], panels)
    fast = data.get("fast", False)
    if not isinstance(fast, bool):
        raise scene_error(path, "fast", SCENE_KEYS["fast"], fast)
    if any(p.get("quantities") == [MECHANISM_PANEL] for p in panels):
        if fast:
            raise scene_error(path, "fast", "false, or no fast: a mechanism scene's few "
                               "positions are computed one at a time", fast)
        if branches[0] == FOLLOW or (FOLLOW in branches and "coupler" not in data):
            raise scene_error(path, "branches", "[1] or [2]: a mechanism scene draws one of "
                               "the listing's branches (and with a coupler, traces the "
                               "coupler curve of the others given, \"follow\" among them)",
                               branches)
        return _mechanism_scene(path, data, dims, start, stop, step, tuple(branches))
    for key, what in (("coupler", "a coupler point is"), ("marked", "marked positions are"),
                      ("forces", "joint forces as arrows are")):
        if key in data:
            raise scene_error(path, key, f"no {key}: {what} drawn by a mechanism scene "
                               "(panels = [{quantities = [\"mechanism\"]}])", data[key])
    if "precision" not in data:
        raise SceneError(f"{path}: key 'precision' is missing: expected {SCENE_KEYS['precision']}")
    precision = data["precision"]
    if not isinstance(precision, str) or precision not in PRECISIONS:
        raise scene_error(path, "precision", SCENE_KEYS["precision"], precision)
    if fast and "double" not in PRECISIONS[precision]:
        raise scene_error(path, "fast", "false with precision basic: only the engine's numbers "
                           "(double) have a vectorised path", fast)
    if FOLLOW in branches and precision != "double":
        raise scene_error(path, "branches", "1 and 2 only with precision basic or both: "
                           "\"follow\" is the accurate engine's (the original program has "
                           "branches 1 and 2)", branches)
    if fast and FOLLOW in branches:
        raise scene_error(path, "fast", "false with the branch \"follow\": the vectorised path "
                           "computes the listing's branches 1 and 2", fast)
    specs = _scene_panels(path, panels)
    if precision == "basic" and any("transmission" in spec.quantities for spec in specs):
        raise scene_error(path, "precision", "double or both with a transmission panel: the "
                           "transmission angle is the accurate engine's (the original program "
                           "computes the output link only)", precision)
    dynamics = None
    if "dynamics" in data:
        if precision == "basic":
            raise scene_error(path, "precision", "double or both with [dynamics]: the forces "
                               "are the accurate engine's (the original program computes the "
                               "motion only)", precision)
        if fast:
            raise scene_error(path, "fast", "false with [dynamics]: the forces are computed "
                               "one position at a time", fast)
        dynamics = scene_dynamics(path, kind, dims, data["dynamics"])
    if dynamics is None and any(set(spec.quantities) & set(FORCE_QUANTITIES) for spec in specs):
        raise SceneError(f"{path}: key 'dynamics' is missing: expected {SCENE_KEYS['dynamics']} "
                         "with a panel of " + ", ".join(FORCE_QUANTITIES))
    return Scene(path, _scene_title(path, data), kind, dims, start, stop, step,
                 tuple(branches), PRECISIONS[precision], specs, fast, dynamics=dynamics)


def known_scenes() -> dict[str, str]:
    """{name: path} of the scenes that come with the program (a name once: the first folder's)."""
    scenes: dict[str, str] = {}
    for folder in shipped_folders("scenes"):
        for entry in sorted(os.listdir(folder)):
            if entry.endswith(".toml"):
                scenes.setdefault(entry.removesuffix(".toml"), os.path.join(folder, entry))
    return scenes


def scene_path(name: str) -> str:
    """The scene file `name` means: a file that exists, else the scene that comes with the program
    whose name is `name` or starts with it (fig3: fig3-plane-four-bar); SceneError if none or
    several do."""
    if os.path.exists(name) or os.sep in name or name.endswith(".toml"):
        return name
    scenes = known_scenes()
    if name in scenes:
        return scenes[name]
    matches = [n for n in scenes if n.startswith(name)]
    if len(matches) == 1:
        return scenes[matches[0]]
    if matches:
        raise SceneError(f"{name!r} names {len(matches)} scenes: {', '.join(matches)}")
    raise SceneError(f"{name!r} is neither a scene file nor the name of a scene of the program "
                     "(scene --list names them)")


def scene_list() -> list[tuple[str, str]]:
    """(name, title) of each scene that comes with the program."""
    listed = []
    for name, path in known_scenes().items():
        try:
            title = load_scene(path).title
        except SceneError as e:
            title = f"(cannot be read: {e})"
        listed.append((name, title))
    return listed


def _scene_dimensions(path: str, kind: str, given: object) -> dict[str, float]:
    """The scene's `dimensions` table, checked against what the kind takes."""
    names = LINKAGE_DIMENSIONS[kind]
    if not isinstance(given, dict):
        raise scene_error(path, "dimensions", SCENE_KEYS["dimensions"], given)
    takes = f"a {kind} linkage takes {', '.join(names)}"
    for key in given:
        if key not in names:
            raise SceneError(f"{path}: unknown key 'dimensions.{key}': {takes}")
    for key in names:
        if key not in given:
            raise SceneError(f"{path}: key 'dimensions.{key}' is missing: expected a number, "
                             f"{DIMENSION_NAMES[key]} ({takes})")
        if not _is_number(given[key]):
            raise scene_error(path, f"dimensions.{key}",
                               f"a number, {DIMENSION_NAMES[key]}", given[key])
    return {k: float(given[k]) for k in names}


def _scene_sweep(path: str, sweep: object) -> tuple[float, float, float]:
    """The scene's `input` table: from, to, step in degrees, a sweep of at most MAX_SCENE_POINTS."""
    if not isinstance(sweep, dict):
        raise scene_error(path, "input", SCENE_KEYS["input"], sweep)
    _unknown_keys(path, sweep, ("from", "to", "step"), "input.")
    for key in ("from", "to", "step"):
        if key not in sweep:
            raise SceneError(f"{path}: key 'input.{key}' is missing: expected a number (degrees)")
        if not _is_number(sweep[key]):
            raise scene_error(path, f"input.{key}", "a number (degrees)", sweep[key])
    start, stop, step = (float(sweep[k]) for k in ("from", "to", "step"))
    if step == 0 or (stop - start) / step < 0:
        raise scene_error(path, "input.step", f"a step that goes from {start:g} to {stop:g} "
                           "(non-zero, with the sign of to - from)", sweep["step"])
    if (stop - start) / step >= MAX_SCENE_POINTS:
        raise scene_error(path, "input.step", f"a step giving at most {MAX_SCENE_POINTS:,} "
                           "points", sweep["step"])
    return start, stop, step


def _scene_panels(path: str, panels: list[dict[str, Any]],
                  vocabulary: tuple[str, ...] = QUANTITIES + FORCE_QUANTITIES
                  ) -> tuple[PanelSpec, ...]:
    """The panels of a scene of curves: each its quantities (of `vocabulary`) and optional y
    limits."""
    specs = []
    for i, panel in enumerate(panels, 1):
        key = f"panels[{i}]"
        _unknown_keys(path, panel, ("quantities", "limits", "notes"), f"{key}.")
        quantities = panel.get("quantities")
        if (not isinstance(quantities, list) or not quantities
                or not all(q in vocabulary for q in quantities)
                or len(set(quantities)) != len(quantities)):
            raise scene_error(path, f"{key}.quantities", "a list of one or more of "
                               f"{', '.join(vocabulary)}", quantities)
        limits = panel.get("limits")
        expected = (f"[low, high], two numbers, low < high, each within +-{DRAWN_UP_TO:g}, at "
                    f"least {DRAWN_DOWN_TO:g} (and {DRAWN_CLOSEST:g} of the larger) apart")
        if limits is not None and not (isinstance(limits, list) and len(limits) == 2
                                       and all(_is_number(v) for v in limits)):
            raise scene_error(path, f"{key}.limits", expected, limits)
        if limits is not None and not drawable_range(float(limits[0]), float(limits[1])):
            raise SceneError(f"{path}: key '{key}.limits': expected {expected}, got "
                             f"[{limits[0]:g}, {limits[1]:g}]")
        if "joint_forces" in quantities and len(quantities) > 1:
            raise scene_error(path, f"{key}.quantities", "joint_forces in a panel of its own "
                               "(a polar diagram: the joints' forces, y against x; its limits "
                               "bound both axes)", quantities)
        specs.append(PanelSpec(tuple(quantities),
                               None if limits is None else (float(limits[0]), float(limits[1])),
                               notes=_panel_notes(path, f"{key}.notes", panel.get("notes", []))))
    return tuple(specs)


def _panel_notes(path: str, key: str, notes: Any) -> tuple[tuple[float, float, str], ...]:
    """A panel's notes: [{at = [x, y], text = "..."}, ...], each said on the PNG with an arrow
    to the point (x, y) of the panel (e.g. what an artefact of the listing is)."""
    expected = "a list of tables {at = [x, y], text = \"...\"}"
    if not isinstance(notes, list) or len(notes) > 10:
        raise scene_error(path, key, expected, notes)
    out = []
    for note in notes:
        at = note.get("at") if isinstance(note, dict) else None
        text = note.get("text") if isinstance(note, dict) else None
        if (set(note) != {"at", "text"} or not isinstance(at, list) or len(at) != 2
                or not all(_is_number(v) and math.isfinite(v) for v in at)
                or not isinstance(text, str) or not text.strip()):
            raise scene_error(path, key, expected, note)
        out.append((float(at[0]), float(at[1]), printable(text)))
    return tuple(out)


def _scene_title(path: str, data: dict[str, Any]) -> str:
    title = data.get("title", KIND_NAMES[data["kind"]].capitalize())
    if not isinstance(title, str):
        raise scene_error(path, "title", SCENE_KEYS["title"], title)
    return printable(title)


def _mechanism_scene(path: str, data: dict[str, Any], dims: dict[str, float], start: float,
                     stop: float, step: float, branches: tuple[int | str, ...]) -> Scene:
    """The rest of a mechanism scene: one panel, quantities = ["mechanism"], optional angles; the
    positions are the accurate engine's (precision double, or no precision key)."""
    arrows = data.get("forces", False)
    if not isinstance(arrows, bool):
        raise scene_error(path, "forces", SCENE_KEYS["forces"], arrows)
    if arrows and "dynamics" not in data:
        raise scene_error(path, "forces", "forces = true with a [dynamics] table (the forces "
                           "drawn are its), or false", arrows)
    kind = str(data.get("kind", data.get("mechanism")))     # the old name still taken
    if arrows and kind == SPHERICAL_FOUR_BAR:
        raise scene_error(path, "forces", "false for the spherical four-bar: its joints' forces "
                           "are not determined by rigid bodies (its joints' moments about the "
                           "centre are: a scene of curves draws them)", arrows)
    dynamics = scene_dynamics(path, kind, dims, data["dynamics"]) if "dynamics" in data \
        else None
    if len(data["panels"]) != 1:
        raise scene_error(path, "panels", "one [[panels]] only: a mechanism panel is a scene "
                           "of its own", data["panels"])
    panel = data["panels"][0]
    _unknown_keys(path, panel, ("quantities", "angles"), "panels[1].")
    if data.get("precision", "double") != "double":
        raise scene_error(path, "precision", "double, or no precision: a mechanism scene draws "
                           "the accurate engine's positions", data["precision"])
    angles = panel.get("angles")
    if angles is not None and not (isinstance(angles, list) and 1 <= len(angles) <= MAX_FRAMES
                                   and all(_is_number(v) for v in angles)):
        raise scene_error(path, "panels[1].angles", f"a list of 1 to {MAX_FRAMES:,} input "
                           "angles (degrees)", angles)
    if angles is None and (stop - start) / step >= MAX_FRAMES:
        raise scene_error(path, "input.step", f"a step giving at most {MAX_FRAMES:,} positions "
                           "to draw (or a list panels[1].angles)", data["input"]["step"])
    spec = PanelSpec((MECHANISM_PANEL,), None,
                     None if angles is None else tuple(float(v) for v in angles))
    coupler = data.get("coupler")
    if coupler is not None:
        if not (isinstance(coupler, list) and len(coupler) in (1, 2)
                and all(_is_number(v) for v in coupler)):
            raise scene_error(path, "coupler", SCENE_KEYS["coupler"], coupler)
        try:
            coupler = check_coupler_point(Linkage(data["kind"], **dims), *coupler)
        except ValueError as e:
            raise scene_error(path, "coupler", f"a point of this coupler: {e}", data["coupler"]) \
                from None
    marked = data.get("marked", [])
    if not (isinstance(marked, list) and len(marked) <= MAX_FRAMES
            and all(_is_number(v) for v in marked)):
        raise scene_error(path, "marked", SCENE_KEYS["marked"], marked)
    return Scene(path, _scene_title(path, data), data["kind"], dims, start, stop, step,
                 branches, ("double",), (spec,), coupler=coupler,
                 marked=tuple(float(v) for v in marked), dynamics=dynamics, arrows=arrows)


# -- a scene's [dynamics]: the bodies and effects that forces() takes ------------------------------

DYNAMICS_KEYS = {  # key: what is expected (the error messages quote it)
    "speed": "a number, the crank's speed (rpm)",
    "crank_acceleration": "a number, the crank's angular acceleration (rad/s^2)",
    "gravity": "a number, m/s^2 along the kind's down (-y for the plane kinds, -z for the "
               "spatial ones), or [gx, gy, gz]",
    "radius": "a positive number, the spherical four-bar's sphere (metres)",
    "output_torque": "a number, the load on the output about its axis (N m, four-bars)",
    "output_force": "a number, the load on the slider along its guide (N, slider-cranks)",
    "coupler_force": "a table { at = [u, v], force = [fx, fy, fz] }: a force (N) at the coupler "
                     "point (u, v)",
}
BODY_KEYS = {  # a body's table { mass, centre, inertia }: what is expected
    "mass": "a number, kg (not negative)",
    "centre": "the centre of mass in the body's frame: a number (the plane kinds' crank, output "
              "and slider), [u, v] (the plane coupler) or [x, y, z] (the spatial kinds)",
    "inertia": "the inertia about the centre, kg m^2: a number (the plane kinds) or a 3 x 3 "
               "tensor [[..], [..], [..]] (the spatial kinds)",
}


class Dynamics(NamedTuple):
    """A scene's [dynamics]: what forces() takes besides the linkage and the angles."""
    bodies: Bodies
    effects: Effects
    radius: float


def _numbers(x: object, count: int) -> bool:
    return isinstance(x, list) and len(x) == count and all(_is_number(v) for v in x)


def _body_of(path: str, key: str, table: object) -> Body:
    """The body table at `key`, its values' shapes checked (forces() checks what they mean)."""
    if not isinstance(table, dict):
        raise scene_error(path, key, "a table { mass, centre, inertia } (centre and inertia "
                          "both, or neither: a uniform rod between its joints)", table)
    _unknown_keys(path, table, BODY_KEYS, f"{key}.")
    if not _is_number(table.get("mass", 0.0)):
        raise scene_error(path, f"{key}.mass", BODY_KEYS["mass"], table["mass"])
    centre, inertia = table.get("centre"), table.get("inertia")
    if centre is not None and not (_is_number(centre) or _numbers(centre, 2)
                                   or _numbers(centre, 3)):
        raise scene_error(path, f"{key}.centre", BODY_KEYS["centre"], centre)
    if inertia is not None and not (_is_number(inertia) or (
            isinstance(inertia, list) and len(inertia) == 3
            and all(_numbers(row, 3) for row in inertia))):
        raise scene_error(path, f"{key}.inertia", BODY_KEYS["inertia"], inertia)
    return Body(float(table.get("mass", 0.0)), centre, inertia)


def scene_dynamics(path: str, mechanism: str, dims: dict[str, float], table: object
                   ) -> Dynamics:
    """The [dynamics] table of a scene as (Bodies, Effects, radius), every value checked by
    forces() itself; a SceneError names the file, the key and what it expects. Keys left out
    are effects left out (a massless body, no load, no gravity, the crank at rest)."""
    if not isinstance(table, dict):
        raise scene_error(path, "dynamics", "a table [dynamics] (data/scenes/forces-*.toml "
                          "show one)", table)
    output = "slider" if mechanism in SLIDER_CRANKS else "output"
    _unknown_keys(path, table, (*DYNAMICS_KEYS, "crank", "coupler", output), "dynamics.")
    for key in ("speed", "crank_acceleration", "radius", "output_torque", "output_force"):
        if key in table and not _is_number(table[key]):
            raise scene_error(path, f"dynamics.{key}", DYNAMICS_KEYS[key], table[key])
    gravity = table.get("gravity")
    if gravity is not None and not (_is_number(gravity) or _numbers(gravity, 3)):
        raise scene_error(path, "dynamics.gravity", DYNAMICS_KEYS["gravity"], gravity)
    load = table.get("coupler_force")
    coupler_force = None
    if load is not None:
        if not isinstance(load, dict):
            raise scene_error(path, "dynamics.coupler_force", DYNAMICS_KEYS["coupler_force"],
                              load)
        _unknown_keys(path, load, ("at", "force"), "dynamics.coupler_force.")
        if not _numbers(load.get("at"), 2):
            raise scene_error(path, "dynamics.coupler_force.at", "[u, v], the coupler point "
                              "(as Linkage.coupler's)", load.get("at"))
        if not _numbers(load.get("force"), 3):
            raise scene_error(path, "dynamics.coupler_force.force", "[fx, fy, fz], newtons",
                              load.get("force"))
        coupler_force = (tuple(load["at"]), tuple(load["force"]))
    bodies = {role: _body_of(path, f"dynamics.{key}", table[key])
              for role, key in (("crank", "crank"), ("coupler", "coupler"), ("output", output))
              if key in table}
    dynamics = Dynamics(Bodies(**bodies), Effects(
        float(table.get("speed", 0.0)), float(table.get("crank_acceleration", 0.0)), gravity,
        float(table.get("output_torque", 0.0)), float(table.get("output_force", 0.0)),
        coupler_force), float(table.get("radius", 1.0)))
    try:
        linkage = Linkage(mechanism, **dims)
    except ValueError as e:
        raise scene_error(path, "dimensions", f"dimensions the engine accepts: {e}") from None
    checks = [(key, Bodies(**{role: bodies[role]}), Effects(), 1.0)
              for role, key in (("crank", "crank"), ("coupler", "coupler"), ("output", output))
              if role in bodies]
    checks += [(key, Bodies(), Effects(**{field: dynamics.effects._asdict()[field]}), 1.0)
               for key, field in (("gravity", "gravity"), ("output_torque", "output_torque"),
                                  ("output_force", "output_force"),
                                  ("coupler_force", "coupler_force")) if key in table]
    checks += [("radius", Bodies(), Effects(), dynamics.radius)] * ("radius" in table)
    checks.append(("dynamics", dynamics.bodies, dynamics.effects, dynamics.radius))
    for key, bodies_, effects, radius in checks:
        try:
            forces(linkage, [], 1, bodies_, effects, radius=radius)
        except ValueError as e:
            where = key if key == "dynamics" else f"dynamics.{key}"
            raise scene_error(path, where, f"what the forces can take: {e}") from None
    return dynamics


# -- a scene's [simulation]: what simulate() takes besides the linkage and its bodies -------------

SIMULATION_KEYS = {  # key: what is expected (the error messages quote it)
    "time": "a number, the run's length (s)",
    "step": "a number, the time between the rows written (s; default 0.01)",
    "tolerance": "a number, the error the integrator allows a step (radians; default 1e-8)",
    "initial": "a table { angle = degrees, speed = rpm }: the crank at the start",
    "torque": "a number, a torque driving the crank (N m, in the sense of phi)",
    "motor": "a table { stall_torque = N m, free_speed = rpm }: a motor line driving the crank, "
             "stall_torque (1 - speed / free_speed)",
    "spring": "a table { between = [P, Q], k = N/m, free_length = m }, or a list of them; P and "
              "Q a joint (A0, A, B, B0; C the slider) or a point [x, y] of the frame (m)",
    "torsion": "a table { at = \"A0\" or \"B0\", k = N m/rad, free_angle = degrees, damping = "
               "N m s/rad }, or a list of them: a torsional spring and damper at that pivot",
    "until_angle": "a number, the crank's angle (degrees) at which the run ends",
}
SIMULATION_QUANTITIES = ("phi", "omega", "speed", "alpha", "output", "energy", "work", "drift")
_SIMULATION_REFUSED = {  # a scene key a simulation scene does not take: why
    "input": "the run's angles are its own (simulation.initial gives the first)",
    "precision": "a simulation is the accurate engine's",
    "fast": "a simulation is computed one step at a time",
    "coupler": "a simulation scene draws the links only",
    "marked": "a simulation scene draws the links only",
    "forces": "a simulation scene draws the links only",
}


class SimulationSettings(NamedTuple):
    """A scene's [simulation]: simulate()'s arguments besides the linkage, bodies and effects."""
    time: float
    step: float
    tolerance: float
    initial: tuple[float, float]        # (degrees, rpm)
    driver: Driver
    springs: tuple[Spring, ...]
    torsions: tuple[Torsion, ...]
    until_angle: float | None


def _table_numbers(path: str, key: str, table: object, names: dict[str, float | None],
                   expected: str) -> dict[str, float]:
    """The numbers of an inline table at `key` (names: each key's default, None: required)."""
    if not isinstance(table, dict):
        raise scene_error(path, key, expected, table)
    _unknown_keys(path, table, names, f"{key}.")
    got = {}
    for name, default in names.items():
        value = table.get(name, default)
        if value is None:
            raise SceneError(f"{path}: key '{key}.{name}' is missing: expected {expected}")
        if not _is_number(value):
            raise scene_error(path, f"{key}.{name}", f"a number ({expected})", value)
        got[name] = float(value)
    return got


def _listed(value: object) -> list[object]:
    return value if isinstance(value, list) else [value]


def scene_simulation(path: str, table: object) -> SimulationSettings:
    """The [simulation] table of a scene, each value's shape checked (simulate() checks what the
    values mean, when the scene is run); a SceneError names the file, the key and what it
    expects."""
    if not isinstance(table, dict):
        raise scene_error(path, "simulation", SCENE_KEYS["simulation"], table)
    _unknown_keys(path, table, SIMULATION_KEYS, "simulation.")
    for key in ("time", "initial"):
        if key not in table:
            raise SceneError(f"{path}: key 'simulation.{key}' is missing: expected "
                             f"{SIMULATION_KEYS[key]}")
    for key in ("time", "step", "tolerance", "torque", "until_angle"):
        if key in table and not _is_number(table[key]):
            raise scene_error(path, f"simulation.{key}", SIMULATION_KEYS[key], table[key])
    initial = _table_numbers(path, "simulation.initial", table["initial"],
                             {"angle": None, "speed": 0.0}, SIMULATION_KEYS["initial"])
    motor = _table_numbers(path, "simulation.motor", table.get("motor", {}),
                           {"stall_torque": 0.0, "free_speed": 0.0}, SIMULATION_KEYS["motor"])
    springs = []
    for spring in _listed(table.get("spring", [])):
        ends = spring.get("between") if isinstance(spring, dict) else None
        if not (isinstance(ends, list) and len(ends) == 2 and all(
                isinstance(p, str) or _numbers(p, 2) for p in ends)):
            raise scene_error(path, "simulation.spring.between", "[P, Q], each a joint (A0, A, "
                              "B, B0; C the slider) or a point [x, y] of the frame", ends)
        numbers = _table_numbers(path, "simulation.spring", {
            k: v for k, v in cast(dict, spring).items() if k != "between"},
            {"k": None, "free_length": None}, SIMULATION_KEYS["spring"])
        p, q = (e if isinstance(e, str) else (float(e[0]), float(e[1])) for e in ends)
        springs.append(Spring(p, q, numbers["k"], numbers["free_length"]))
    torsions = []
    for torsion in _listed(table.get("torsion", [])):
        at = torsion.get("at") if isinstance(torsion, dict) else None
        if at not in ("A0", "B0"):
            raise scene_error(path, "simulation.torsion.at", "\"A0\" (the crank's pivot) or "
                              "\"B0\" (the output crank's)", at)
        numbers = _table_numbers(path, "simulation.torsion", {
            k: v for k, v in cast(dict, torsion).items() if k != "at"},
            {"k": 0.0, "free_angle": 0.0, "damping": 0.0}, SIMULATION_KEYS["torsion"])
        torsions.append(Torsion(cast(str, at), numbers["k"], numbers["free_angle"],
                                numbers["damping"]))
    return SimulationSettings(
        float(table["time"]), float(table.get("step", 0.01)), float(table.get("tolerance", 1e-8)),
        (initial["angle"], initial["speed"]),
        Driver(float(table.get("torque", 0.0)), motor["stall_torque"], motor["free_speed"]),
        tuple(springs), tuple(torsions),
        None if "until_angle" not in table else float(table["until_angle"]))


def _simulation_scene(path: str, data: dict[str, Any], kind_key: str) -> Scene:
    """A scene with [simulation]: its linkage, [dynamics] (the bodies, gravity and loads; no
    speed: the motion is the run's), the branch it starts on, and panels of quantities against
    time or one mechanism panel (the linkage moving in real time)."""
    for key, why in _SIMULATION_REFUSED.items():
        if key in data:
            raise scene_error(path, key, f"no {key} with [simulation]: {why}", data[key])
    for key in ("kind", "dimensions", "branches", "panels", "dynamics"):
        if key not in data:
            raise SceneError(f"{path}: key '{key}' is missing: expected {SCENE_KEYS[key]}"
                             + " (a simulation needs its bodies' masses)" * (key == "dynamics"))
    kind = data["kind"]
    if not isinstance(kind, str) or kind not in LINKAGE_DIMENSIONS:
        raise scene_error(path, kind_key, SCENE_KEYS["kind"], kind)
    dims = _scene_dimensions(path, kind, data["dimensions"])
    if not (data["branches"] in ([1], [2])):
        raise scene_error(path, "branches", "[1] or [2]: the listing's branch the run starts "
                          "on (the run follows the motion through change points, as \"follow\")",
                          data["branches"])
    dynamics = scene_dynamics(path, kind, dims, data["dynamics"])
    for key in ("speed", "crank_acceleration"):
        if key in data["dynamics"]:
            raise scene_error(path, f"dynamics.{key}", f"no {key} with [simulation]: the motion "
                              "is the run's (its first speed: simulation.initial)",
                              data["dynamics"][key])
    settings = scene_simulation(path, data["simulation"])
    panels = data["panels"]
    if (not isinstance(panels, list) or not 1 <= len(panels) <= 3
            or not all(isinstance(p, dict) for p in panels)):
        raise scene_error(path, "panels", SCENE_KEYS["panels"], panels)
    if panels[0].get("quantities") == [MECHANISM_PANEL]:
        if len(panels) != 1 or set(panels[0]) != {"quantities"}:
            raise scene_error(path, "panels", "one [[panels]] of quantities [\"mechanism\"] "
                              "alone: the linkage drawn at each row of the run", panels)
        specs: tuple[PanelSpec, ...] = (PanelSpec((MECHANISM_PANEL,), None),)
    else:
        specs = _scene_panels(path, panels, SIMULATION_QUANTITIES)
    angle = settings.initial[0]
    return Scene(path, _scene_title(path, data), kind, dims, angle, angle, 1.0,
                 (int(data["branches"][0]),), ("double",), specs, dynamics=dynamics,
                 simulation=settings)


# ---- 23. Scenes computed: their DAT files, forces and CSV ----------------------------------------
#
# A scene read (section 22) computed: the DAT files its panels need, its forces along the sweep
# for [dynamics], and its numbers as one CSV.
#
# The numbers come from the two places that already make them, never from a copy of a formula:
# `basic` runs the menu program's own session (run_session, as the `run` command does) and reads
# back the files it wrote; `double` asks the engine. Each computes only what the panels show: a
# displacement-only scene runs lines 1060-1150 of the listing and no further
# (sweep_points(..., derivatives=0)), and the engine's Linkage.sweep(..., derivatives=0); only
# those files are written.
#
# Uses: sections 1, 2, 5, 6, 7, 9, 10, 15, 16 and 22.
# Offers: check_assembles, Series, branch_text, compute_scene, scene_forces, forces_columns,
#   FORCES_COLUMNS, forces_row, scene_csv, csv_forces_series.


# -- computing a scene: the DAT files ----------------------------------------------------------

def _faithful_files(scene: Scene, branch: int | str, directory: str) -> list[str]:
    """The menu program's session with the scene's answers (as `run` gives them): it writes the
    DAT files the panels need in `directory`. Returns the soft errors it printed."""
    key, answers = typed_dimensions(scene.kind, scene.dimensions)
    answers += [typed_number(v) for v in (scene.start, scene.stop, scene.step)]
    soft_errors: list[str] = []
    screen = Screen(lambda s: None, terminal=False, soft_errors=soft_errors.append)
    try:
        answered_session(screen, key, answers, str(branch), directory, scene.derivatives)
    except WriteError as e:
        raise SceneError(str(e)) from None
    except ProgramStop as stop:
        where = "dimensions" if "Illegal linkage" in str(stop) else "input"
        raise scene_error(scene.path, where, "what the original program accepts (precision "
                           f"basic): it says \"{stop}\"") from None
    screen.show_soft_errors()
    return [e.strip() for e in soft_errors]


def _accurate_motions(scene: Scene, branch: int | str, derivatives: int) -> list[Motion]:
    try:
        linkage = Linkage(scene.kind, **scene.dimensions)
        angles = evenly_spaced_angles(scene.start, scene.stop, scene.step)
        if scene.fast:
            return linkage.sweep_arrays(angles, int(branch), derivatives).motions()
        return linkage.sweep(angles, branch, derivatives)
    except ValueError as e:
        raise scene_error(scene.path, "dimensions", f"dimensions the engine accepts: {e}") \
            from None
    except FastUnavailable as e:
        raise SceneError(f"{scene.path}: key 'fast': {e}") from None


def check_assembles(scene: Scene, positions: Sequence[Motion | Pose]) -> None:
    """A SceneError unless the linkage assembles at one of `positions` (the engine's Motions,
    or a drawing's Poses) at least."""
    if not any(m.output is not None for m in positions):
        dims = " ".join(f"{k}={v:g}" for k, v in scene.dimensions.items())
        raise scene_error(scene.path, "dimensions",
                           "a linkage that can be assembled somewhere from "
                           f"{scene.start:g} to {scene.stop:g} degrees; the {scene.kind} "
                           f"linkage {dims} assembles at none of those {len(positions)} input "
                           "angles")


class Series(NamedTuple):
    """One curve family of a figure: the DAT files in `directory`, made at `precision` (basic,
    double, or "" if unknown) on `branch` (1, 2, FOLLOW, or None if unknown)."""
    name: str
    precision: str
    branch: int | str | None
    directory: str
    forces: tuple[Forces, ...] = ()      # a double series of a scene with [dynamics]


def branch_text(branch: int | str) -> str:
    return ("follow (the motion followed from branch 1)" if branch == FOLLOW
            else f"{branch} ({'A+B' if branch == 1 else 'A-B'})")


def compute_scene(scene: Scene, directory: str, report: Callable[[str], None] | None = None
                  ) -> list[Series]:
    """Write the scene's DAT files under `directory` (in it for one series, else one folder a
    series); `report(message)` hears the original's soft errors. Returns the series. Nothing is
    written for a linkage that assembles nowhere in the range."""
    accurate = {b: _accurate_motions(scene, b, scene.derivatives) for b in scene.branches
                if "double" in scene.precisions}
    check_assembles(scene, accurate.get(scene.branches[0])
                     or _accurate_motions(scene, scene.branches[0], 0))
    plan = [(p, b) for b in scene.branches for p in scene.precisions]
    series = []
    for precision, branch in plan:
        name = f"{precision}-branch{branch}"
        where = directory if len(plan) == 1 else os.path.join(directory, name)
        try:
            os.makedirs(where, exist_ok=True)
        except OSError as e:
            raise SceneError(f"cannot make the folder {where!r}: {e.strerror}") from None
        if precision == "double":
            rows: Sequence[tuple] = accurate[branch]
            if scene.transmission:
                linkage = Linkage(scene.kind, **scene.dimensions)
                rows = [m + (mu,) for m, mu in zip(accurate[branch],
                                                   transmission_of(linkage, accurate[branch]))]
            try:
                write_dat_files(rows, where, files=1 + scene.derivatives,
                                transmission=scene.transmission)
            except WriteError as e:
                raise SceneError(str(e)) from None
        else:
            errors = _faithful_files(scene, branch, where)
            if errors and report is not None:
                counts = {e: errors.count(e) for e in dict.fromkeys(errors)}
                report("the original printed " + ", ".join(f'"{e}" {n} time{"s" * (n > 1)}'
                                                           for e, n in counts.items())
                       + f" ({name})")
        series.append(Series(name, precision, branch, where, scene_forces(scene, branch)
                             if precision == "double" else ()))
    return series


def scene_forces(scene: Scene, branch: int | str) -> tuple[Forces, ...]:
    """forces() along the scene's sweep on `branch`, for its [dynamics]; () without one (and
    then forces() is not called)."""
    if scene.dynamics is None:
        return ()
    bodies, effects, radius = scene.dynamics
    return tuple(forces(Linkage(scene.kind, **scene.dimensions),
                        evenly_spaced_angles(scene.start, scene.stop, scene.step), branch,
                        bodies, effects, radius=radius))


def forces_columns(results: Sequence[Forces]) -> tuple[str, ...]:
    """The CSV's columns of forces (FORCES_COLUMNS, then each joint's components it carries:
    A0_fx, A0_fy, A0_fz where it carries a force, A0_mx, ... where a moment), from the first
    position whose forces are bounded; FORCES_COLUMNS alone if none is."""
    known = next((r for r in results if r.joints is not None), None)
    joints = [] if known is None else [
        f"{name}_{q}{axis}" for name, reaction in cast(dict, known.joints).items()
        for q, part in (("f", reaction.force), ("m", reaction.moment)) if part is not None
        for axis in "xyz"]
    return FORCES_COLUMNS + tuple(joints)


FORCES_COLUMNS = ("torque", "power", "shaking_fx", "shaking_fy", "shaking_fz", "shaking_mx",
                  "shaking_my", "shaking_mz", "forces_status")


def forces_row(result: Forces | None, columns: Sequence[str]) -> tuple:
    """A position's values for `columns` (forces_columns): None (nan) where its forces are
    not known, and then forces_status says why (unbounded, or the position's status)."""
    if result is None:
        return (None,) * 8 + ("no forces (precision basic)",) + (None,) * (len(columns) - 9)
    values: list[Any] = [result.torque, result.power]
    values += list(result.shaking_force or (None,) * 3) + list(result.shaking_moment
                                                               or (None,) * 3)
    values.append(result.status)
    for column in columns[9:]:
        name, part = column.rsplit("_", 1)
        reaction = (result.joints or {}).get(name)
        vector = None if reaction is None else reaction.force if part[0] == "f" \
            else reaction.moment
        values.append(None if vector is None else vector["xyz".index(part[1])])
    return tuple(values)


def scene_csv(scene: Scene, series: list[Series], path: str,
              outputs: WrittenSet | None = None) -> int:
    """The scene's numbers as one CSV file, a row a point of each series (header: series, then
    CSV_HEADER): the engine's motions for a double series, every point with its status; the
    original's numbers for a basic one, with the engine's status of each position. A scene with
    [dynamics] adds forces_columns (a basic series' rows: nan, and forces_status says so).
    Returns the rows written."""
    joint_columns = forces_columns([f for s in series for f in s.forces]) \
        if scene.dynamics is not None else ()

    def rows() -> Iterator[tuple]:
        for s in series:
            assert s.branch is not None         # compute_scene's series know their branch
            if s.precision == "double":
                motions = _accurate_motions(scene, s.branch, scene.derivatives)
                for i, m in enumerate(motions):
                    extra = forces_row(s.forces[i], joint_columns) if joint_columns else ()
                    yield (s.name,) + tuple(m) + extra
                continue
            columns = [read_dat(os.path.join(s.directory, n))
                       for n in DatFiles.NAMES[:1 + scene.derivatives]]
            motions = _accurate_motions(scene, s.branch, 0)
            statuses = {m.phi: m.status for m in motions}
            for i, (phi, output) in enumerate(columns[0]):
                values = [c[i][1] if i < len(c) else None for c in columns[1:]]
                values += [None] * (2 - len(values))
                status = statuses.get(phi) or Linkage(scene.kind, **scene.dimensions) \
                    .motion(phi, s.branch, 0).status
                yield (s.name, phi, output, *values, status) + (forces_row(None, joint_columns)
                                                                 if joint_columns else ())
    return write_csv(path, rows(), ("series",) + CSV_HEADER + joint_columns, outputs)


def csv_forces_series(path: str) -> list[Series]:
    """The forces of a scene's CSV (scene_csv's, with [dynamics]) read back: a Series for each
    series name it holds (its precision and branch from the name), whose forces are its rows'
    (the speed from power over torque); a SceneError, naming the file and its line, for a file
    that is not such a CSV."""
    try:
        with open(path, encoding="utf-8", newline="") as file:
            lines = [line.rstrip("\r\n") for line in file]
    except (OSError, UnicodeDecodeError) as e:
        raise SceneError(f"{path}: cannot be read ({getattr(e, 'strerror', None) or e})") \
            from None
    header = lines[0].split(",") if lines else []
    fixed = ["series", *CSV_HEADER, *FORCES_COLUMNS]
    joints = list(dict.fromkeys(column.rpartition("_")[0] for column in header[len(fixed):]))
    parts = {name: [q for q in "fm" if f"{name}_{q}x" in header] for name in joints}
    if header[:len(fixed)] != fixed or header[len(fixed):] != [
            f"{name}_{q}{axis}" for name in joints for q in parts[name] for axis in "xyz"]:
        raise SceneError(f"{path}: not the CSV of a scene with [dynamics] (its first line names "
                         f"series, {', '.join(CSV_HEADER)}, torque, power, shaking_fx .. "
                         "shaking_mz, forces_status, then each joint's A0_fx .. B0_mz)")
    words = {"series", "status", "forces_status"}
    rows: dict[str, list[Forces]] = {}
    omega: dict[str, float] = {}
    for number, line in enumerate(lines[1:], 2):
        texts = line.split(",")
        try:
            if len(texts) != len(header):
                raise ValueError(f"{len(texts)} fields, not {len(header)}")
            x = {c: float(t) for c, t in zip(header, texts) if c not in words}
        except ValueError as e:
            raise SceneError(f"{path}, line {number}: not a row of the scene's CSV ({e})") \
                from None

        def vector(prefix: str) -> Vector:
            return (x[f"{prefix}x"], x[f"{prefix}y"], x[f"{prefix}z"])
        name, torque, power = texts[0], x["torque"], x["power"]
        if math.isfinite(torque) and torque and math.isfinite(power):
            omega.setdefault(name, power / torque)
        force, moment = vector("shaking_f"), vector("shaking_m")
        known = all(map(math.isfinite, (torque, power, *force, *moment)))
        reactions = {j: Reaction(*(vector(f"{j}_{q}") if q in parts[j] else None for q in "fm"))
                     for j in joints}
        status = texts[len(fixed) - 1]          # forces_status
        rows.setdefault(name, []).append(
            Forces(x["phi"], torque, power, reactions, force, moment, status, 0.0) if known
            else Forces(x["phi"], None, None, None, None, None, status, 0.0))
    series = []
    for name, results in rows.items():
        found = re.fullmatch(r"(basic|double)-branch(1|2|follow)", name)
        branch = None if not found else FOLLOW if found[2] == FOLLOW else int(found[2])
        speed = omega.get(name, 0.0) * 60.0 / (2.0 * math.pi)
        series.append(Series(name, found[1] if found else "", branch, "",
                             tuple(f._replace(speed_rpm=speed) for f in results)))
    if not any(f.torque is not None for s in series for f in s.forces):
        raise SceneError(f"{path}: holds no position whose forces are known")
    return series


# ---- 24. Plots: a figure drawn as text or PNG ----------------------------------------------------
#
# Holds: a figure built from DAT files (scene_figure, dat_figure: its panels and curves) and drawn
# as a plain-text plot (80 x 24, no dependency) or a PNG (matplotlib, the `plot` extra); a mechanism
# scene's drawing; a scene written back as TOML.
#
# Every figure is drawn from DAT files, so `scene` and `plot` draw alike: one series a folder (the
# scene's DIR itself, or DIR/<precision>-branch<n> when it overlays several; n is "follow" for the
# motion followed through change points). A curve breaks where the input angle skips a step (the
# engine leaves out positions that do not exist). Output angles are drawn unwrapped: whole turns are
# added so that a curve is continuous across +-180 degrees, and so that the curves of a panel lie
# within half a turn of the first one.
#
# Uses: sections 1, 2, 6, 7, 9, 15, 16, 17, 18, 22 and 23.
# Offers: dat_series, Curve, Panel, Figure, PLOT_POINTS, PLOT_BINS, FORCE_LABELS, POLAR_MOMENTS,
#   CLIPPED, build_figure, scene_figure, dat_figure, csv_figure, TEXT_WIDTH, TEXT_HEIGHT, MARKERS,
#   OVERLAP, ANGLE_STEPS, text_figure, png_figure, force_arrows, scene_drawing, scene_text.


def dat_series(directory: str) -> list[Series]:
    """The DAT files of `directory`: one series, or (if it holds none) one for each folder in it
    that does, named after the folder ("basic-branch1" tells its precision and branch)."""
    def has_dat(d: str) -> bool:
        return any(os.path.exists(os.path.join(d, n)) for n in QUANTITY_FILES.values())
    if has_dat(directory):
        return [Series(os.path.basename(os.path.abspath(directory)), dat_precision(directory),
                       None, directory)]
    try:
        folders = sorted(e.path for e in os.scandir(directory) if e.is_dir() and has_dat(e.path))
    except OSError as e:
        raise SceneError(f"{directory}: cannot read: {e.strerror}") from None
    if not folders:
        raise SceneError(f"{directory}: no ANG.DAT, VEL.DAT or ACC.DAT here, nor in a folder "
                         "in it")
    series = []
    for folder in folders:
        name = os.path.basename(folder)
        match = re.fullmatch(r"(basic|double)-branch([12]|follow)", name)
        branch = None if not match else FOLLOW if match[2] == FOLLOW else int(match[2])
        series.append(Series(name, match[1] if match else dat_precision(folder), branch,
                             folder))
    order = {1: 1, 2: 2, FOLLOW: 3}
    return sorted(series, key=lambda s: (order.get(s.branch, 4), s.precision != "basic",
                                         s.name))


# -- the figure: what both renderers draw ------------------------------------------------------

class Curve(NamedTuple):
    label: str
    quantity: str
    precision: str
    branch: int | str | None
    runs: tuple[tuple[tuple[float, float], ...], ...]   # unbroken pieces of (x, y)


class Panel(NamedTuple):
    letter: str
    quantities: tuple[str, ...]
    labels: tuple[tuple[str, str, str], ...]             # (name, symbol, unit) per quantity
    curves: tuple[Curve, ...]
    limits: tuple[float, float] | None
    notes: tuple[tuple[float, float, str], ...] = ()       # (x, y, text): said on the PNG


class Figure(NamedTuple):
    title: str
    subtitle: str
    xlabel: tuple[str, str, str]
    panels: tuple[Panel, ...]


def _runs(points: Sequence[tuple[float, float]], angles: bool
          ) -> tuple[tuple[tuple[float, float], ...], ...]:
    """Split (x, y) points where x skips more than 1.5 typical steps (the median step); angles
    unwrapped (_unbroken)."""
    runs: list[list[tuple[float, float]]] = []
    for x, y, first in _unbroken(points, _typical_step(points), angles):
        if first:
            runs.append([])
        runs[-1].append((x, y))
    return tuple(map(tuple, runs))


def _typical_step(points: Sequence[tuple[float, float]]) -> float:
    """The median of the steps in x between neighbouring points (0 for fewer than two)."""
    steps = sorted(abs(b[0] - a[0]) for a, b in zip(points, points[1:]))
    return steps[len(steps) // 2] if steps else 0.0


def _unbroken(points: Iterable[tuple[float, float]], typical: float, angles: bool
              ) -> Iterator[tuple[float, float, bool]]:
    """(x, y, whether it starts a run) of each point: a run breaks where x skips more than 1.5
    `typical` steps. Angles (angles=True) are unwrapped: whole turns added so that each point
    is within 180 degrees of the point before it, across a break too."""
    gap, px, py, first = 1.5 * typical, 0.0, 0.0, True
    for x, y in points:
        if not first:
            first = abs(x - px) > gap
            if angles:
                y += 360.0 * round((py - y) / 360.0)
        yield x, y, first
        px, py, first = x, y, False


PLOT_POINTS = 1 << 17   # a curve of more points than this is thinned to PLOT_BINS (_drawn_runs)
PLOT_BINS = 1 << 14     # bins of neighbouring points: 25 to a pixel of a 648-pixel-wide PNG


def _drawn_runs(path: str, points: Iterable[tuple[float, float]], angles: bool
                ) -> tuple[tuple[tuple[tuple[float, float], ...], ...], bool]:
    """The runs (_runs) of a DAT file's points as the figure draws them, and whether a value
    is +-3 (where the original clips). A file of up to PLOT_POINTS points is drawn as it is;
    a longer one, read a point at a time, is thinned to the figure's resolution: its points
    in at most PLOT_BINS bins of neighbouring points (a run's breaks kept, the typical step
    that of its first PLOT_POINTS), each bin drawn as its first, lowest, highest, leftmost,
    rightmost and last point, in their order, so that its lines cover the pixels the whole
    file's would. A value
    beyond +-DRAWN_UP_TO is refused as soon as it is read."""
    touches_3 = False

    def drawable() -> Iterator[tuple[float, float]]:
        nonlocal touches_3
        top = DRAWN_UP_TO
        for x, y in points:
            if not (-top <= x <= top and -top <= y <= top):
                big = x if abs(x) > top else y
                raise SceneError(f"{path}: a value of {big:.3g} is too large to draw (the "
                                 f"figures go up to +-{top:g})")
            if y == 3.0 or y == -3.0:
                touches_3 = True
            yield x, y
    stream = drawable()
    head = list(itertools.islice(stream, PLOT_POINTS + 1))
    if len(head) <= PLOT_POINTS:
        return _runs(head, angles), touches_3
    typical, rest = _typical_step(head), iter(head)
    del head                            # the iterator lets go of the list once through it
    return _thinned(path, _unbroken(itertools.chain(rest, stream), typical, angles)), touches_3


def _thinned(path: str, points: Iterable[tuple[float, float, bool]]
             ) -> tuple[tuple[tuple[float, float], ...], ...]:
    """The runs of `points` ((x, y, whether it starts a run), _unbroken) kept in at most about
    2 PLOT_BINS bins of neighbouring points of one run: each bin its first point, its lowest and
    highest y, its leftmost and rightmost x (a curve whose x turns back, a rocking crank against
    time, keeps its extremes too) and its last point (their index in the stream, x, y); when the
    bins reach 2 PLOT_BINS, neighbours of a run are merged, two into one. More than PLOT_BINS
    runs: SceneError."""
    bins: list[list[Any]] = []  # [starts a run, first, lowest, highest, leftmost, rightmost, last]
    per, count, runs = 1, 0, 0
    bin_: list[Any] = []
    for i, (x, y, first) in enumerate(points):
        point = (i, x, y)
        if first or count == per:
            if bin_:
                bins.append(bin_)
            if len(bins) >= 2 * PLOT_BINS:
                bins, per = _merged(bins), 2 * per
            runs += first
            if runs > PLOT_BINS:
                raise SceneError(f"{path}: its curve breaks into more than {PLOT_BINS:,} "
                                 "pieces (where the input angle skips): too many to draw")
            bin_, count = [first, point, point, point, point, point, point], 1
            continue
        if y < bin_[2][2]:
            bin_[2] = point
        elif y > bin_[3][2]:
            bin_[3] = point
        if x < bin_[4][1]:
            bin_[4] = point
        elif x > bin_[5][1]:
            bin_[5] = point
        bin_[6] = point
        count += 1
    if bin_:
        bins.append(bin_)
    kept: list[list[tuple[float, float]]] = []
    for first, *ends in bins:
        if first:
            kept.append([])
        kept[-1] += [(x, y) for _, x, y in sorted(set(ends))]
    return tuple(map(tuple, kept))


def _merged(bins: list[list[Any]]) -> list[list[Any]]:
    """The bins of _thinned, each two neighbours of a run as one (a bin that starts a run is
    never merged into the one before it)."""
    merged: list[list[Any]] = []
    single = False                      # the last bin of `merged` is one of `bins` as it was
    for b in bins:
        if single and not b[0]:
            a = merged[-1]
            merged[-1] = [a[0], a[1], min(a[2], b[2], key=lambda p: p[2]),
                          max(a[3], b[3], key=lambda p: p[2]), min(a[4], b[4], key=lambda p: p[1]),
                          max(a[5], b[5], key=lambda p: p[1]), b[6]]
            single = False
        else:
            merged.append(b)
            single = True
    return merged


FORCE_LABELS = {  # (name, symbol, unit) of a force quantity's panel
    "torque": ("driving torque", "T", "N m"),
    "shaking": ("shaking force", "|F|", "N"),
    "joint_forces": ("joint forces, polar", "Fy against Fx", "N"),
}
POLAR_MOMENTS = ("joint moments about O, polar", "My against Mx", "N m")   # spherical


def _pieces(values: Iterable[tuple[float, float] | None]
            ) -> tuple[tuple[tuple[float, float], ...], ...]:
    """The unbroken runs of points, broken where a value is None (forces unbounded)."""
    runs: list[tuple[tuple[float, float], ...]] = []
    run: list[tuple[float, float]] = []
    for point in list(values) + [None]:
        if point is None:
            if run:
                runs.append(tuple(run))
            run = []
        else:
            run.append(point)
    return tuple(runs)


def _force_curves(quantity: str, s: Series, label: str) -> list[Curve]:
    """A force quantity's curves of the series: the torque and the shaking force's size
    against phi; each joint's force (the spherical kind's: its moment about O) as the polar
    diagram of its tip (x, y) as the crank turns, a curve a joint."""
    if quantity == "torque":
        return [Curve(label or "torque", quantity, s.precision, s.branch, _pieces(
            None if f.torque is None else (f.phi, f.torque) for f in s.forces))]
    if quantity == "shaking":
        return [Curve(label or "shaking", quantity, s.precision, s.branch, _pieces(
            None if f.shaking_force is None else (f.phi, math.sqrt(dot(f.shaking_force,
                                                                       f.shaking_force)))
            for f in s.forces))]
    names = next((list(f.joints) for f in s.forces if f.joints), [])
    curves = []
    for name in names:
        def tip(f: Forces) -> tuple[float, float] | None:
            if f.joints is None:
                return None
            reaction = f.joints[name]
            vector = reaction.force if reaction.force is not None else reaction.moment
            return None if vector is None else (vector[0], vector[1])
        curves.append(Curve(f"{name}, {label}" if label else name, quantity, s.precision,
                            s.branch, _pieces(tip(f) for f in s.forces)))
    return curves


def _turned(curve: Curve, reference: Curve) -> Curve:
    """The angle curve moved by whole turns to lie nearest `reference` (so that two branches
    that meet at psi = 180 are drawn meeting, not one at +180 and the other at -180)."""
    def mean(c: Curve) -> float:
        ys = [y for r in c.runs for _, y in r]
        return sum(ys) / len(ys) if ys else 0.0
    turn = 360.0 * round((mean(reference) - mean(curve)) / 360.0)
    if not turn:
        return curve
    return curve._replace(runs=tuple(tuple((x, y + turn) for x, y in r) for r in curve.runs))


def _series_label(series: Series, several_precisions: bool, several_branches: bool) -> str:
    parts = []
    if several_precisions or series.precision == "" or series.branch is None:
        parts.append(series.precision or series.name)
    if several_branches and series.branch is not None:
        parts.append("followed" if series.branch == FOLLOW else f"branch {series.branch}")
    return ", ".join(parts)


CLIPPED = " (clipped at +-3)"       # a basic VEL or ACC curve that touches 3, as the original clips


def build_figure(title: str, subtitle: str, group: str, specs: Sequence[PanelSpec],
                 series: list[Series]) -> Figure:
    """The figure of `specs` (PanelSpecs) from the DAT files of `series`; group is "four-bar",
    "slider" or "unknown" (the axis labels, and whether outputs are angles)."""
    several_precisions = len({s.precision for s in series}) > 1
    several_branches = len({s.branch for s in series}) > 1
    panels = []
    for letter, spec in zip("abc", specs):
        curves: list[Curve] = []
        for quantity in spec.quantities:
            if quantity in FORCE_QUANTITIES:
                for s in series:
                    if s.forces:
                        label = _series_label(s, several_precisions, several_branches)
                        curves += _force_curves(quantity, s, label)
                continue
            name = QUANTITY_FILES[quantity]
            for s in series:
                path = os.path.join(s.directory, name)
                if not os.path.exists(path):
                    continue
                label = _series_label(s, several_precisions, several_branches)
                if len(spec.quantities) > 1 or not label:
                    label = f"{quantity}, {label}" if label else quantity
                angles = quantity == "displacement" and group != "slider"
                runs, touches_3 = _drawn_runs(path, dat_points(path, warn=say), angles)
                if s.precision == "basic" and quantity != "displacement" and touches_3:
                    label += CLIPPED                                        # ERRATA K9
                curve = Curve(label, quantity, s.precision, s.branch, runs)
                reference = next((c for c in curves if c.quantity == quantity), None)
                curves.append(_turned(curve, reference) if angles and reference else curve)
        moments = any(f.joints and next(iter(f.joints.values())).force is None
                      for s in series for f in s.forces)
        labels = tuple(POLAR_MOMENTS if q == "joint_forces" and moments else FORCE_LABELS[q]
                       if q in FORCE_LABELS else AXIS_LABELS[group][q] for q in spec.quantities)
        panels.append(Panel(letter, spec.quantities, labels, tuple(curves), spec.limits,
                            spec.notes))
    return Figure(title, subtitle, INPUT_AXIS, tuple(panels))


def scene_figure(scene: Scene, series: list[Series]) -> Figure:
    dims = " ".join(f"{k}={v:g}" for k, v in scene.dimensions.items())
    branches = ", ".join(branch_text(b) for b in scene.branches)
    precision = {("basic",): "basic (GW-BASIC single precision)",
                 ("double",): "double (the accurate engine)",
                 ("basic", "double"): "basic and double, overlaid"}[scene.precisions]
    subtitle = (f"{KIND_NAMES[scene.kind]}; "
                f"branch{'es' * (len(scene.branches) > 1)} {branches}; precision {precision}")
    group = "slider" if scene.kind in SLIDER_CRANKS else "four-bar"
    return build_figure(f"{scene.title}: {dims}", subtitle, group, scene.panels, series)


def dat_figure(directory: str, kind: str | None = None) -> Figure:
    """The figure of the DAT files in `directory` (see dat_series): (a) ANG.DAT, (b) VEL.DAT and
    ACC.DAT, the panels of the files there are."""
    series = dat_series(directory)
    present = {q for q, n in QUANTITY_FILES.items()
               for s in series if os.path.exists(os.path.join(s.directory, n))}
    specs = [PanelSpec(tuple(q for q in qs if q in present), None)
             for qs in (("displacement",), ("velocity", "acceleration"), ("transmission",))
             if present & set(qs)]
    group = ("unknown" if kind is None else
             "slider" if kind in SLIDER_CRANKS else "four-bar")
    precisions = " and ".join(dict.fromkeys(s.precision or "unknown" for s in series))
    branches = sorted({s.branch for s in series if s.branch}, key=str)
    what = (f"precision {precisions}" + (" (from the number format)" if len(series) == 1 else "")
            + (f"; branch{'es' * (len(branches) > 1)} {', '.join(map(str, branches))}"
               if branches else ", branch not recorded"))
    if kind:
        what = f"{KIND_NAMES[kind]}; {what}"
    figure = build_figure(f"The DAT files in {directory}", what, group, specs, series)
    if not any(run for panel in figure.panels for curve in panel.curves for run in curve.runs):
        raise SceneError(f"{directory}: its DAT files hold no point to draw (no \"angle,value\" "
                         "line)")
    return figure


def csv_figure(path: str) -> Figure:
    """The force panels of a scene's CSV (csv_forces_series): (a) the torque, (b) the shaking
    force, (c) each joint's force as a polar diagram, as the scene draws them."""
    series = csv_forces_series(path)
    specs = [PanelSpec((q,), None) for q in ("torque", "shaking", "joint_forces")]
    branches = ", ".join(str(s.branch) for s in series if s.branch is not None)
    what = f"{len(series)} series" + (f"; branch{'es' * (len(series) > 1)} {branches}"
                                     if branches else "")
    return build_figure(f"The forces in {path}", what, "unknown", specs, series)


# -- the plain-text plot -----------------------------------------------------------------------

TEXT_WIDTH, TEXT_HEIGHT = 80, 24
MARKERS = "*o+x@%&$"
OVERLAP = "#"                           # a cell two curves pass through


class _Axis(NamedTuple):
    low: float          # the value at cell 0, a tick
    step: float         # the value between ticks
    ticks: int          # intervals between ticks
    per: int            # cells per interval

    @property
    def cells(self) -> int:
        return self.ticks * self.per + 1

    def cell(self, v: float) -> float:
        """The fractional cell of value v (cell 0 is `low`)."""
        return (v - self.low) / self.step * self.per

    def tick_values(self) -> list[float]:
        return [self.low + i * self.step for i in range(self.ticks + 1)]


ANGLE_STEPS = (15.0, 30.0, 45.0, 60.0, 90.0, 180.0, 360.0)     # tick steps for input angles


def _nice_axis(lo: float, hi: float, cells: int, spacing: int, angles: bool = False) -> _Axis:
    """An axis over lo..hi in at most `cells` cells: ticks 1, 2 or 5 times a power of ten apart
    (or, for angles, also 15, 30, 45 ... degrees), each on a cell, at least `spacing` apart."""
    if hi - lo <= max(1e-12 * max(abs(lo), abs(hi)), DRAWN_DOWN_TO):     # drawn as one value
        pad = abs(lo) * 0.1 if abs(lo) > DRAWN_DOWN_TO else 1.0
        lo, hi = lo - pad, hi + pad
    most = max(2, (cells - 1) // spacing)
    exponent = math.floor(math.log10((hi - lo) / most))
    steps = {m * 10.0 ** e for e in range(exponent, exponent + 3) for m in (1, 2, 5)}
    for step in sorted(steps | set(ANGLE_STEPS if angles else ())):
        if step * most < (hi - lo) * (1 - 1e-9):
            continue
        first = math.floor(lo / step + 1e-9)
        ticks = max(1, math.ceil(hi / step - 1e-9) - first)
        if ticks <= most:
            return _Axis(first * step, step, ticks, max(1, (cells - 1) // ticks))
    raise AssertionError("unreachable: with most >= 2, a step of 10 ** (exponent + 2) fits")


def _tick_text(v: float, step: float) -> str:
    decimals = max(0, -math.floor(math.log10(step) + 1e-9))
    if decimals > 6 or abs(v) >= 1e7:
        return f"{v:.3g}"
    return f"{abs(v) if abs(v) < step / 2 else v:.{decimals}f}"


def _wrapped(text: str, width: int, indent: str = "") -> list[str]:
    import textwrap
    return textwrap.wrap(text, width, subsequent_indent=indent, break_on_hyphens=False) or [""]


def _panel_lines(panel: Panel, width: int) -> list[str]:
    """The panel's header: its quantities and units, and which marker is which curve (before
    each quantity when there is one curve of each, else in a legend)."""
    labels = [f"{n} {s} [{u}]" for n, s, u in panel.labels]
    legend = "  ".join(f"{MARKERS[i % len(MARKERS)]} {c.label.replace(CLIPPED, '')}"
                       for i, c in enumerate(panel.curves)) if len(panel.curves) > 1 else ""
    if len(panel.curves) > 1 and [c.quantity for c in panel.curves] == list(panel.quantities):
        labels = [f"{MARKERS[i]} {text}" for i, text in enumerate(labels)]
        legend = ""
    header = f"({panel.letter}) " + ", ".join(labels)
    if len(header) + 3 + len(legend) <= width:
        return [header + " " * (width - len(header) - len(legend)) + legend if legend else header]
    return _wrapped(header, width, "    ") + (_wrapped(legend, width, "  ") if legend else [])


def _draw(grid, x_axis: _Axis, y_axis: _Axis, runs, marker: str, drawn=None,
          key=None) -> None:
    """Put `marker` in the cells the curve passes through: at each point, and between two
    points of a run at steps of at most half a cell. Where `drawn` (the cells earlier curves
    took, with their keys) has a curve of another `key` (another quantity or branch: one the
    marker would hide), OVERLAP; one of the same key (the same curve in the other precision)
    is covered, which shows that the two agree there."""
    drawn = {} if drawn is None else drawn
    rows, columns = len(grid), len(grid[0])
    for run in runs:
        cells = [(x_axis.cell(x), y_axis.cell(y)) for x, y in run]
        for (c0, r0), (c1, r1) in zip(cells, cells[1:] + cells[-1:]):
            n = min(math.ceil(2 * max(abs(c1 - c0), abs(r1 - r0))), 4 * (rows + columns))
            for i in range(max(n, 1) + 1):
                t = i / max(n, 1)
                c = math.floor(c0 + (c1 - c0) * t + 0.5)
                r = math.floor(r0 + (r1 - r0) * t + 0.5)
                if 0 <= c < columns and 0 <= r < rows:
                    cell = (rows - 1 - r, c)
                    before = drawn.setdefault(cell, key)
                    grid[cell[0]][c] = marker if before == key else OVERLAP
                    if before != key:
                        drawn[cell] = OVERLAP


def text_figure(figure: Figure, width: int = TEXT_WIDTH, height: int = TEXT_HEIGHT) -> str:
    """The figure in plain text, at most `width` x `height` characters: the title; each panel's
    header (quantities, units, legend) and plot, tick values on the y axis; the shared x axis's
    tick values under the last panel, and its label."""
    top = _wrapped(figure.title, width)[:2] + _wrapped(figure.subtitle, width, "  ")[:2]
    name, symbol, unit = figure.xlabel
    bottom = [f"x axes: {name} {symbol} [{unit}]"[:width]]
    headers = [_panel_lines(panel, width) for panel in figure.panels]
    polar = [panel.quantities == ("joint_forces",) for panel in figure.panels]
    fixed = len(top) + sum(len(h) + 1 + p for h, p in zip(headers, polar)) + 1 + len(bottom)
    rows = (height - fixed) // len(figure.panels)
    if rows < 3:
        raise SceneError(f"the text plot does not fit in {width} x {height} characters: show "
                         "fewer panels or series, or draw a PNG (--png)")

    y_axes = []
    for panel in figure.panels:
        ys = [y for c in panel.curves for r in c.runs for _, y in r if math.isfinite(y)]
        lo, hi = panel.limits or (min(ys, default=0.0), max(ys, default=0.0))
        y_axes.append(_nice_axis(lo, hi, rows, 2 if rows >= 5 else 1))
    y_texts = [[_tick_text(v, a.step) for v in a.tick_values()] for a in y_axes]
    margin = max(len(t) for texts in y_texts for t in texts) + 1   # the y axis's column
    def x_axis_of(xs: list[float], angles: bool) -> tuple[_Axis, list[str]]:
        spacing, right = 6, 4              # cells between x ticks; room for the last tick value
        while True:
            axis = _nice_axis(min(xs), max(xs), width - margin - right, spacing, angles)
            texts = [_tick_text(v, axis.step) for v in axis.tick_values()]
            longest = max(len(t) for t in texts)
            if axis.per > longest and (longest - 1) // 2 < right or spacing > width:
                return axis, texts
            spacing, right = longest + 2, max(right, longest // 2 + 1)

    def tick_row(axis: _Axis, texts: list[str]) -> str:
        labels = [" "] * (width + 8)
        for i, text in enumerate(texts):
            start = max(0, margin + i * axis.per - (len(text) - 1) // 2)
            labels[start:start + len(text)] = text
        return "".join(labels).rstrip()

    x_axis, x_texts = x_axis_of([x for p, po in zip(figure.panels, polar) if not po
                                 for c in p.curves for r in c.runs for x, _ in r] or [0.0],
                                figure.xlabel == INPUT_AXIS)

    out, overlaps = list(top), False
    for k, (panel, header, y_axis, texts) in enumerate(zip(figure.panels, headers, y_axes,
                                                          y_texts)):
        out += header
        own_x = x_axis
        if polar[k]:                # its own x axis, and its limits bound both axes
            own_x, own_texts = x_axis_of(list(panel.limits or ()) or [
                x for c in panel.curves for r in c.runs for x, _ in r] or [0.0], False)
        grid = [[" "] * own_x.cells for _ in range(y_axis.cells)]
        for r, row in enumerate(grid):
            row[0] = "+" if (y_axis.cells - 1 - r) % y_axis.per == 0 else "|"
        drawn: dict = {}
        for i, curve in enumerate(panel.curves):
            _draw(grid, own_x, y_axis, curve.runs, MARKERS[i % len(MARKERS)], drawn,
                  (curve.quantity, curve.branch)
                  + ((curve.label,) if curve.quantity in FORCE_QUANTITIES else ()))
        overlaps = overlaps or OVERLAP in drawn.values()
        for r, row in enumerate(grid):
            tick, off = divmod(y_axis.cells - 1 - r, y_axis.per)
            out.append(f"{texts[tick] if off == 0 else '':>{margin - 1}} " + "".join(row).rstrip())
        out.append(" " * margin + "".join("+" if c % own_x.per == 0 else "-"
                                          for c in range(own_x.cells)))
        if polar[k]:
            out.append(tick_row(own_x, own_texts))
    out.append(tick_row(x_axis, x_texts))
    clipped = any(CLIPPED in c.label for p in figure.panels for c in p.curves)  # ERRATA K9
    notes = [f"{OVERLAP} = two curves"] * overlaps + ["basic clipped at +-3"] * clipped
    if notes and len(bottom[0]) + 2 + len("  ".join(notes)) <= width:
        bottom[0] += "  " + "  ".join(notes)
    out += bottom
    return "\n".join(out) + "\n"


# -- the PNG -----------------------------------------------------------------------------------

def _pretty(text: str) -> str:
    """Greek letters and superscripts for the PNG's labels."""
    for ascii_, shown in (("dphi2", "dφ²"), ("d2", "d²"), ("^2", "²"), ("psi", "ψ"),
                          ("phi", "φ"), ("ksi", "ξ"), ("+-", "±"), ("mu [", "μ [")):
        text = text.replace(ascii_, shown)
    return text


def png_figure(figure: Figure, path: str, dpi: float | None = None,
               size: tuple[int, int] | None = None, outputs: WrittenSet | None = None) -> None:
    """Render the figure with matplotlib (the `plot` extra) into the PNG file `path`: 90 dots an
    inch (`dpi`), 648 pixels wide unless `size` (width, height in pixels) says otherwise."""
    import textwrap
    MplFigure, FigureCanvasAgg = matplotlib_canvas()
    from matplotlib.ticker import MultipleLocator
    polar = [panel.quantities == ("joint_forces",) for panel in figure.panels]
    xs_all = [x for p, po in zip(figure.panels, polar) if not po for c in p.curves
              for r in c.runs for x, _ in r]
    x_step = _nice_axis(min(xs_all), max(xs_all), 73, 8, angles=figure.xlabel == INPUT_AXIS
                        ).step if xs_all else 1.0
    colours: dict[tuple[str, int | str], str] = {
               ("displacement", 1): "black", ("displacement", 2): "tab:gray",
               ("velocity", 1): "tab:blue", ("velocity", 2): "tab:cyan",
               ("acceleration", 1): "tab:red", ("acceleration", 2): "tab:orange"}
    colours.update({(q, b): c for q, c in (("omega", "tab:blue"), ("speed", "tab:blue"),
                                           ("alpha", "tab:red"), ("work", "tab:orange"),
                                           ("drift", "tab:red")) for b in (1, 2)})
    n = len(figure.panels)
    dpi = dpi or 90
    mpl = MplFigure(figsize=(size[0] / dpi, size[1] / dpi) if size else (7.2, 0.7 + 2.6 * n),
                    dpi=dpi, layout="constrained")
    FigureCanvasAgg(mpl)
    mpl.suptitle(_pretty(f"{figure.title}\n{figure.subtitle}"), fontsize=10)
    name, symbol, unit = figure.xlabel
    for i, panel in enumerate(figure.panels):
        ax = mpl.add_subplot(n, 1, i + 1)
        for curve in panel.curves:
            xs, ys = [], []
            for run in curve.runs:
                xs += [x for x, _ in run] + [math.nan]
                ys += [y for _, y in run] + [math.nan]
            style = (dict(linewidth=0.8, marker="o", markersize=2.2, zorder=3)
                     if curve.precision == "basic" else dict(linewidth=1.6, zorder=2))
            if curve.quantity in FORCE_QUANTITIES:
                line, = ax.plot(xs, ys, label=_pretty(curve.label), **style)
                if polar[i] and curve.runs:             # where the crank starts: phi = from
                    ax.plot(*curve.runs[0][0], "o", color=line.get_color(), markersize=4)
            else:
                ax.plot(xs, ys, color=colours.get((curve.quantity, curve.branch or 1),
                                                  "black"), label=_pretty(curve.label), **style)
        if polar[i]:
            _, symbol_, unit_ = panel.labels[0]
            y_symbol, _, x_symbol = symbol_.split()
            ax.set_title(f"({panel.letter}) {panel.labels[0][0]} as the crank turns (a dot: "
                         "the first angle)", loc="left", fontsize=10)
            ax.set_xlabel(f"{x_symbol} [{unit_}]", fontsize=9)
            ax.set_ylabel(f"{y_symbol} [{unit_}]", fontsize=9)
            ax.axhline(0.0, color="grey", linewidth=0.5)
            ax.axvline(0.0, color="grey", linewidth=0.5)
            if panel.limits:
                ax.set_xlim(*panel.limits)
                ax.set_ylim(*panel.limits)
            ax.set_aspect("equal", adjustable="box" if panel.limits else "datalim")
            ax.grid(True, linewidth=0.4, alpha=0.5)
            ax.tick_params(labelsize=8)
            ax.legend(fontsize=7, loc="best")
            continue
        ax.set_title(f"({panel.letter}) " + " and ".join(n_ for n_, _, _ in panel.labels)
                     + f" vs {name}", loc="left", fontsize=10)
        ax.set_ylabel(_pretty(", ".join(f"{s} [{u}]" for _, s, u in panel.labels)), fontsize=9)
        ax.set_xlabel(_pretty(f"{name} {symbol} [{unit}]"), fontsize=9)
        if panel.limits:
            ax.set_ylim(*panel.limits)
        if xs_all:
            x_lo, x_hi = min(xs_all), max(xs_all)
            if x_lo == x_hi:                    # one angle: a span of one step about it
                x_lo, x_hi = x_lo - x_step / 2, x_hi + x_step / 2
            ax.set_xlim(x_lo, x_hi)
            ax.xaxis.set_major_locator(MultipleLocator(x_step))
        ax.grid(True, linewidth=0.4, alpha=0.5)
        ax.tick_params(labelsize=8)
        if len(panel.curves) > 1:
            ax.legend(fontsize=7, loc="best")
        for x, y, text in panel.notes:
            ax.annotate(textwrap.fill(_pretty(text), 46), (x, y), xytext=(0.03, 0.06),
                        textcoords="axes fraction", ha="left", va="bottom", fontsize=7.5,
                        color="#8b0000",
                        bbox=dict(boxstyle="round,pad=0.3", fc="#fff8e7", ec="#8b0000", lw=0.6),
                        arrowprops=dict(arrowstyle="->", color="#8b0000", lw=0.8))
    import io
    image = io.BytesIO()
    mpl.savefig(image, format="png")
    with written(path, outputs) as out:         # whole or not at all, as every file written
        out.write(image.getvalue())


# -- the commands ------------------------------------------------------------------------------


def force_arrows(linkage: Linkage, phis: Sequence[float], branch: int | str,
                 results: Sequence[Forces]) -> tuple[list[tuple[Stroke, ...]], float]:
    """Each joint's force at each of `phis` as an arrow from the joint ("force" strokes on the
    page of mechanism_drawing: the force on the body after it, the frame's on the crank at A0,
    the crank's on the coupler at A, the coupler's on the output at B or C, the frame's on the
    output at B0 and the guide), to one scale: the largest a quarter of the linkage's span long;
    and that largest force (N)."""
    kind = linkage.kind
    poses = [joint_positions(linkage, phi, branch) for phi in phis]
    page = [project(kind, p) for pose in poses for p in pose.joints.values()]
    span = max(max(p[i] for p in page) - min(p[i] for p in page) for i in (0, 1))
    biggest = max((math.sqrt(dot(r.force, r.force)) for f in results
                   for r in (f.joints or {}).values() if r.force is not None), default=0.0)
    arrows: list[tuple[Stroke, ...]] = []
    for pose, f in zip(poses, results):
        strokes: list[Stroke] = []
        for name, reaction in (f.joints or {}).items():
            at = pose.joints.get("C" if name == "guide" else name)
            if reaction.force is None or at is None or not biggest:
                continue
            tail = project(kind, at)
            step = project(kind, cast(Vector, tuple(0.25 * span / biggest * x
                                                    for x in reaction.force)))
            length = math.hypot(*step)
            if length < 1e-9 * span:
                continue
            tip = (tail[0] + step[0], tail[1] + step[1])
            head = min(0.35 * length, 0.04 * span) / length
            ux, uy = step[0] * head, step[1] * head
            c, s = 0.906, 0.423                 # the head's sides 25 degrees off the shaft
            strokes += [Stroke((tail, tip), "force"), Stroke((
                (tip[0] - ux * c + uy * s, tip[1] - uy * c - ux * s), tip,
                (tip[0] - ux * c - uy * s, tip[1] - uy * c + ux * s)), "force")]
        arrows.append(tuple(strokes))
    return arrows, biggest


def scene_drawing(scene: Scene) -> Drawing:
    """A mechanism scene's drawing: the linkage at each of its angles on its first branch."""
    dims = " ".join(f"{'ξ' if k == 'ksi' else k}={v:g}" for k, v in scene.dimensions.items())
    branch = scene.branches[0]
    assert isinstance(branch, int)      # load_scene: a mechanism scene draws branch 1 or 2
    arrows: list[tuple[Stroke, ...]] = []
    note = ""
    if scene.arrows and scene.dynamics is not None:
        linkage, (bodies, effects, radius) = (Linkage(scene.kind, **scene.dimensions),
                                              scene.dynamics)
        arrows, biggest = force_arrows(linkage, scene.angles(), branch, forces(
            linkage, scene.angles(), branch, bodies, effects, radius=radius))
        note = f"; arrows: joint forces, the longest {biggest:.4g} N"
    try:
        drawing = mechanism_drawing(
            Linkage(scene.kind, **scene.dimensions), scene.angles(), branch,
            f"{scene.title}: {dims}", f"{KIND_NAMES[scene.kind]}; branch {branch} "
            f"({'A+B' if branch == 1 else 'A-B'})"
            + ("" if scene.coupler else "; positions by the accurate engine")
            + (f"; marked: {len(scene.marked)} positions, faint and numbered" if scene.marked
               else "") + note,
            scene.coupler, scene.branches[1:], scene.marked, extra=arrows)
    except ValueError as e:
        raise scene_error(scene.path, "dimensions", f"dimensions that can be drawn: {e}") \
            from None
    check_assembles(scene, [frame.pose for frame in drawing.frames])
    return drawing


def _toml_value(value: Any) -> str:
    """A number, or a list (of lists) of numbers, as TOML."""
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return repr(float(value))


def _dynamics_text(kind: str, dynamics: Dynamics) -> list[str]:
    """The [dynamics] table's lines that scene_dynamics reads back into `dynamics`: each
    effect that is not its default, each body that has a mass or a shape."""
    effects = dynamics.effects
    lines = ["[dynamics]", f"speed = {_toml_value(effects.speed_rpm)}"]
    lines += [f"{key} = {_toml_value(value)}" for key, value, default in (
        ("crank_acceleration", effects.crank_acceleration, 0.0),
        ("gravity", effects.gravity, None), ("radius", dynamics.radius, 1.0),
        ("output_torque", effects.output_torque, 0.0),
        ("output_force", effects.output_force, 0.0)) if value != default]
    if effects.coupler_force is not None:
        at, force = effects.coupler_force
        lines.append(f"coupler_force = {{ at = {_toml_value(at)}, force = {_toml_value(force)} }}")
    output = "slider" if kind in SLIDER_CRANKS else "output"
    for key, body in zip(("crank", "coupler", output), dynamics.bodies):
        if body != Body():
            shape = "".join(f", {name} = {_toml_value(value)}" for name, value in
                            (("centre", body.centre), ("inertia", body.inertia))
                            if value is not None)
            lines.append(f"{key} = {{ mass = {_toml_value(body.mass)}{shape} }}")
    return lines


def _toml_string(text: str) -> str:
    """A TOML basic string of text (its escapes are JSON's, and DEL too)."""
    import json                         # here: the menu program starts without it
    return json.dumps(text).replace("\x7f", "\\u007f")


def scene_text(scene: Scene, comment: str = "") -> str:
    """A mechanism scene as the TOML that load_scene reads back into the same scene: the file
    a user can edit and run (`scene FILE`); `comment` (one line) heads it."""
    if not scene.draws_mechanism:
        raise ValueError("scene_text writes mechanism scenes")

    def numbers(values: Iterable[float]) -> str:
        return ", ".join(repr(float(v)) for v in values)
    dims = ", ".join(f"{k} = {float(v)!r}" for k, v in scene.dimensions.items())
    lines = [f"# {printable(comment)}"] if comment else []
    lines += [f"title = {_toml_string(scene.title)}", f"kind = {_toml_string(scene.kind)}",
              f"dimensions = {{ {dims} }}",
              f"input = {{ from = {scene.start!r}, to = {scene.stop!r}, step = {scene.step!r} }}",
              "branches = [" + ", ".join(_toml_string(b) if isinstance(b, str) else str(b)
                                         for b in scene.branches) + "]"]
    if scene.coupler is not None:
        lines.append(f"coupler = [{numbers(scene.coupler)}]")
    if scene.marked:
        lines.append(f"marked = [{numbers(scene.marked)}]")
    if scene.arrows:
        lines.append("forces = true")
    if scene.dynamics is not None:
        lines += [""] + _dynamics_text(scene.kind, scene.dynamics)
    lines += ["", "[[panels]]", 'quantities = ["mechanism"]']
    if scene.panels[0].angles is not None:
        lines.append(f"angles = [{numbers(scene.panels[0].angles)}]")
    return "\n".join(lines) + "\n"


# ---- 25. Simulation scenes: a run written, plotted against time and drawn moving -----------------
#
# A scene with a [simulation] table (read by scene_simulation) is one run of simulate(): its
# linkage and [dynamics] (bodies, gravity, the output's load, a coupler force; no speed: the motion
# is the run's) and these keys of [simulation], each an argument:
#
#   time, step, tolerance             time, step, tolerance (s, s, radians)
#   initial = { angle, speed }        initial = (angle, speed) (degrees, rpm)
#   torque; motor = { stall_torque,   driver = Driver(torque, stall_torque, free_speed_rpm)
#     free_speed }
#   spring = { between = [P, Q], k,   springs = [Spring(P, Q, k, free_length), ...]
#     free_length } (or a list)
#   torsion = { at, k, free_angle,    torsions = [Torsion(at, k, free_angle, damping), ...]
#     damping } (or a list)
#   until_angle                       until_angle (degrees)
#   branches = [1] or [2]             branch (the run follows the motion from there, as "follow")
#
# The run's rows go to the CSV (SIMULATION_COLUMNS: phi and output in degrees as everywhere, or
# the slider's x; the energy with the work done and the drift E - W - E0, the check that the
# integrator kept to its tolerance), its events to the user in a few lines (simulation_report),
# its quantities against time to a figure (a scene of curves: text or PNG, as section 24 draws),
# and its positions to a Drawing whose frames are the rows every 1/ANIMATION_FPS s or more
# (a mechanism panel: the terminal, SVG and PNG of section 18), each shown for the time between
# them: the linkage moves in real time.
#
# Uses: sections 1, 2, 7, 14, 15, 16, 17, 22 and 24.
# Offers: scene_run, SIMULATION_COLUMNS, simulation_rows, simulation_csv, EVENT_WORDS,
#   simulation_report, SIMULATION_LABELS, simulation_figure, ANIMATION_FPS, simulation_drawing.


def scene_run(scene: Scene) -> Simulation:
    """The scene's run (its [simulation] as simulate()'s arguments: see the section's notes); a
    SceneError names the file and says what simulate() refused."""
    assert scene.simulation is not None and scene.dynamics is not None
    settings, (bodies, effects, _) = scene.simulation, scene.dynamics
    branch = scene.branches[0]
    assert isinstance(branch, int)          # load_scene: [1] or [2]
    try:
        return simulate(Linkage(scene.kind, **scene.dimensions), bodies, effects,
                        driver=settings.driver, springs=settings.springs,
                        torsions=settings.torsions, initial=settings.initial,
                        time=settings.time, step=settings.step, tolerance=settings.tolerance,
                        branch=branch, until_angle=settings.until_angle)
    except ValueError as e:
        raise SceneError(f"{scene.path}: key 'simulation': the run cannot be made: {e}") \
            from None


SIMULATION_COLUMNS = ("t", "phi", "omega", "alpha", "output", "output_rate",
                      "output_acceleration", "energy", "work", "drift", "coordinate")


def simulation_rows(run: Simulation) -> Iterator[tuple]:
    """The run's rows as SIMULATION_COLUMNS: SimRow's, and the drift E - W - E(0) (J)."""
    first = run.rows[0].energy
    for r in run.rows:
        yield r[:9] + (r.energy - r.work - first, r.coordinate)


def simulation_csv(run: Simulation, path: str, outputs: WrittenSet | None = None) -> int:
    """The run's rows as one CSV file (SIMULATION_COLUMNS), whole or not at all; the rows."""
    return write_csv(path, simulation_rows(run), SIMULATION_COLUMNS, outputs)


EVENT_WORDS = {DEAD_CENTRE: "dead centre of the input", CHANGE_POINT: "change point",
               REST: "at rest", COORDINATE: "coordinate changed", ANGLE_REACHED: "angle reached",
               STUCK: "stuck", END: "end"}


def simulation_report(run: Simulation) -> list[str]:
    """What happened in the run, in a few lines: each kind of event (how many times, the first),
    how it ended, and the energy check."""
    lines = []
    ends = (END, STUCK, ANGLE_REACHED)
    for kind, words in EVENT_WORDS.items():
        seen = [e for e in run.events if e.kind == kind]
        if not seen or kind in ends:
            continue
        first = seen[0]
        text = "to the output's angle and back" if kind == COORDINATE else first.text
        lines.append(f"{words}: {len(seen):,} time{'s' * (len(seen) > 1)}, the first at "
                     f"t = {first.t:.6g} s, phi = {first.phi:.6g} deg ({text})")
    for e in run.events:
        if e.kind in ends:
            lines.append(f"{EVENT_WORDS[e.kind]} at t = {e.t:.6g} s, phi = {e.phi:.6g} deg: "
                         f"{e.text}")
    drift = max(abs(row[9]) for row in simulation_rows(run))
    lines.append(f"energy: {run.rows[0].energy:.6g} J at the start, {run.rows[-1].energy:.6g} J "
                 f"at the end, the work done on it {run.rows[-1].work:.6g} J; the drift "
                 f"|E - W - E0| at most {drift:.3g} J ({run.steps:,} steps, {run.rejected:,} "
                 "rejected)")
    return lines


SIMULATION_LABELS = {  # a quantity's (name, symbol, unit) against time; output: see _labels
    "phi": ("crank angle", "phi", "deg"),
    "omega": ("crank speed", "omega", "rad/s"),
    "speed": ("crank speed", "n", "rpm"),
    "alpha": ("crank acceleration", "alpha", "rad/s^2"),
    "output": ("output angle", "psi", "deg"),
    "energy": ("total energy", "E", "J"),
    "work": ("work done on it", "W", "J"),
    "drift": ("energy drift", "E - W - E0", "J"),
}
_SLIDER_OUTPUT = ("slider position", "x", "m")
_VALUES: dict[str, Callable[[SimRow, float], float]] = {   # a quantity of a row (and E(0))
    "phi": lambda r, e0: r.phi, "omega": lambda r, e0: r.omega,
    "speed": lambda r, e0: r.omega * 30.0 / math.pi, "alpha": lambda r, e0: r.alpha,
    "output": lambda r, e0: r.output, "energy": lambda r, e0: r.energy,
    "work": lambda r, e0: r.work, "drift": lambda r, e0: r.energy - r.work - e0}


def _setting_text(scene: Scene) -> str:
    """The run's start and driver, in a few words (the figure's and drawing's subtitle)."""
    settings = scene.simulation
    assert settings is not None
    angle, rpm = settings.initial
    driver = settings.driver
    drives = [f"torque {driver.torque:g} N m"] * bool(driver.torque) + [
        f"motor {driver.stall_torque:g} N m to {driver.free_speed_rpm:g} rpm"
    ] * bool(driver.stall_torque)
    return (f"from phi = {angle:g} deg, {rpm:.4g} rpm, branch {scene.branches[0]}; "
            f"{', '.join(drives) or 'no driver'}")


def simulation_figure(scene: Scene, run: Simulation) -> Figure:
    """The scene's panels drawn against time from the run's rows."""
    dims = " ".join(f"{k}={v:g}" for k, v in scene.dimensions.items())
    e0 = run.rows[0].energy
    panels = []
    for letter, spec in zip("abc", scene.panels):
        labels = tuple(_SLIDER_OUTPUT if q == "output" and scene.kind in SLIDER_CRANKS
                       else SIMULATION_LABELS[q] for q in spec.quantities)
        curves = tuple(Curve(q, q, "double", scene.branches[0], (tuple(
            (r.t, _VALUES[q](r, e0)) for r in run.rows),)) for q in spec.quantities)
        panels.append(Panel(letter, spec.quantities, labels, curves, spec.limits))
    return Figure(f"{scene.title}: {dims}", f"{KIND_NAMES[scene.kind]}; {_setting_text(scene)}",
                  ("time", "t", "s"), tuple(panels))


ANIMATION_FPS = 25.0        # the most frames a second a run is drawn at (its rows spread)


def simulation_drawing(scene: Scene, run: Simulation) -> Drawing:
    """The linkage at the run's rows (every row, or every k-th: at most ANIMATION_FPS a second
    and MAX_FRAMES in all), each frame shown for the time between them (Drawing.seconds)."""
    settings = scene.simulation
    assert settings is not None
    timed = [r for r in run.rows if abs(r.t / settings.step - round(r.t / settings.step)) < 1e-6]
    every = max(1, math.ceil(1.0 / (ANIMATION_FPS * settings.step) - 1e-9),
                math.ceil(len(timed) / MAX_FRAMES))
    rows = timed[::every]
    linkage = Linkage(scene.kind, **scene.dimensions)
    dims = " ".join(f"{k}={v:g}" for k, v in scene.dimensions.items())
    try:
        drawing = mechanism_drawing(
            linkage, [r.phi for r in rows], 1, f"{scene.title}: {dims}",
            f"{KIND_NAMES[scene.kind]}; {_setting_text(scene)}; in real time",
            poses=[pose_at(linkage, r.phi, r.output) for r in rows])
    except ValueError as e:
        raise scene_error(scene.path, "dimensions", f"dimensions that can be drawn: {e}") \
            from None
    out = "x = {:.4g} m" if linkage.is_slider else "ψ = {:.1f}°"
    frames = tuple(f._replace(caption=f"t = {r.t:.2f} s  φ = {r.phi:.1f}°  "
                              + out.format(r.output) + f"  ω = {r.omega:.3g} rad/s")
                   for f, r in zip(drawing.frames, rows))
    return drawing._replace(frames=frames, seconds=every * settings.step)


# ---- 26. The explorer: a linkage changed and watched in the terminal -----------------------------
#
# Holds: `python3 linkage.py explore`: a full-screen view of the linkage moving, its coupler curve
# traced, and beside it its dimensions and what analyse answers, all following each key. The
# state is a value (Explorer) and each key makes the next one (explore_key); the screen is drawn
# from the state alone (explore_screen). The terminal loop (explore_terminal) and a replayed key
# file (explore_replay) run the same two functions, so that what the tests replay is what a user
# sees. What a state shows (ExploreView: the analysis, the drawing of the motion, the
# transmission angle at each position) is computed once for each linkage, by the caller's cache.
#
# A linkage that does not assemble at every crank angle is drawn over the crank's reachable range
# only, and playing stops at its dead centres; one that assembles nowhere is drawn and said so.
# A change that cannot be drawn (a length of 0, an arc of 180 degrees) is refused on the status
# line, the state as it was.
#
# Uses: sections 1, 2, 6, 7, 8, 9, 15, 17, 18, 19, 22 and 24.
# Offers: EXPLORE_HELP, EXPLORE_KEY_NAMES, EXPLORE_POSITIONS, EXPLORE_SPEEDS, Explorer, explorer_of,
#   ExploreView, analysis_drawing, explore_view, explore_glance, ExploreViews, explore_steps,
#   explore_key, explore_screen, explore_scene, terminal_keys, key_file, explore_saved,
#   explore_replay, explore_terminal.


# The keys, as the help screen lists them (the footer shows the first words of each).
EXPLORE_HELP = (
    ("Tab  S-Tab  Up  Down", "select the next or previous dimension"),
    ("A B C D E F X U V", "select that one (X: the skew angle ξ, U V: coupler)"),
    ("Left  Right", "change the selected dimension by a small step:"),
    ("", "a length 1 % of the longest other link, up to 1, 2"),
    ("", "or 5 times a power of ten; an angle 1 degree (the"),
    ("", "footer shows the steps of the selected one)"),
    ("S-Left  S-Right  [  ]", "change it by a large step: ten small ones"),
    ("=  Enter", "type its value (Enter takes it, Esc leaves it)"),
    ("b", "the other branch (A+B or A-B)"),
    ("f", "follow: analyse the motion through change points"),
    ("Space", "play or pause"),
    (",  .", "step back or forward one position"),
    ("+  -", "faster or slower"),
    ("c", "the coupler point and its curve on or off"),
    ("k", "the next kind of linkage"),
    ("u", "undo the last change"),
    ("s", "save as a scene file (TOML): name it, Enter"),
    ("?", "this help (any key leaves it)"),
    ("q", "quit (Ctrl-C too)"),
)
# The names of keys that are not a character (a key file's lines); Tick is the timer's.
EXPLORE_KEY_NAMES = ("Tab", "S-Tab", "Up", "Down", "Left", "Right", "S-Left", "S-Right",
                     "Enter", "Esc", "Backspace", "Space", "Tick")
EXPLORE_POSITIONS = 36          # positions drawn over the crank's range (10 degrees, a full turn)
EXPLORE_SPEEDS = (1, 2, 4, 8, 12, 24)       # positions a second
_TERMINAL_SEQUENCES = {b"\x1b[A": "Up", b"\x1b[B": "Down", b"\x1b[C": "Right", b"\x1b[D": "Left",
                       b"\x1bOA": "Up", b"\x1bOB": "Down", b"\x1bOC": "Right", b"\x1bOD": "Left",
                       b"\x1b[1;2C": "S-Right", b"\x1b[1;2D": "S-Left", b"\x1b[Z": "S-Tab",
                       b"\t": "Tab", b"\r": "Enter", b"\n": "Enter", b"\x7f": "Backspace",
                       b"\x08": "Backspace", b" ": "Space"}     # a lone ESC is Esc
_ASCII_PANEL = str.maketrans({"φ": "phi", "ψ": "psi", "ξ": "ksi", "μ": "mu", "°": " deg"})
_STEP_KEYS = ("Left", "Right", "S-Left", "S-Right", "[", "]")
_UNDO_DEPTH = 100
_INSIDE = 1e-9          # degrees: a rocking crank's motion ends this far inside its dead centres


class Explorer(NamedTuple):
    """What the explorer shows and where the user is: the linkage (kind, dims in
    LINKAGE_DIMENSIONS' order, branch, follow), the coupler point (u, v) and whether it is
    traced, the shown position (index into ExploreView.phis) and the motion, what is being
    typed (a value, a file name, an answer), the status line, the states undo goes back to,
    and the scene's dynamics (the bodies and effects whose driving torque is shown)."""
    kind: str
    dims: tuple[tuple[str, float], ...]
    branch: int = 1
    follow: bool = False
    coupler: tuple[float, float] = (0.0, 0.0)
    traced: bool = True
    selected: int = 0
    position: int = 0
    direction: int = 1
    playing: bool = True
    speed: int = 4                     # index into EXPLORE_SPEEDS
    typing: str | None = None          # the value typed so far
    naming: str | None = None          # the file name typed so far (save)
    confirm: str | None = None         # the file to overwrite, asked
    save_to: str | None = None         # a scene to write (for the caller), then None
    overwrite: bool = False            # save_to may be overwritten (the user said yes)
    help: bool = False
    status: str = ""
    undo: tuple[Explorer, ...] = ()
    done: bool = False
    dynamics: Dynamics | None = None   # a scene's [dynamics]: the driving torque shown

    @property
    def names(self) -> tuple[str, ...]:
        """What can be selected: the dimensions, then u (and v) of a traced coupler point."""
        point = (("u",) if PINS[self.kind].coupler == "line" else ("u", "v")) if self.traced \
            else ()
        return tuple(n for n, _ in self.dims) + point

    @property
    def linkage(self) -> Linkage:
        return Linkage(self.kind, **dict(self.dims))

    def value(self, name: str) -> float:
        return dict(self.dims + (("u", self.coupler[0]), ("v", self.coupler[1])))[name]


def _default_coupler(kind: str, dims: dict[str, float]) -> tuple[float, float]:
    """A point of the coupler that shows its curve well: half along it, a quarter across."""
    c = dims["c"]
    return (0.5 * c, 0.0 if PINS[kind].coupler == "line" else 0.25 * c)


def explorer_of(kind: str, dims: dict[str, float] | None = None, branch: int = 1,
                follow: bool = False, coupler: tuple[float, float] | None = None,
                dynamics: Dynamics | None = None) -> Explorer:
    """The explorer's first state: the linkage given (its dimensions the kind's example's where
    not given), coupler the point traced (None: one half along the coupler), dynamics a
    scene's (None: no forces shown)."""
    given = dict(MECHANISM_EXAMPLES[kind], **(dims or {}))
    values = tuple((n, float(given[n])) for n in LINKAGE_DIMENSIONS[kind])
    return Explorer(kind, values, branch, follow,
                    coupler or _default_coupler(kind, dict(values)), dynamics=dynamics)


class ExploreView(NamedTuple):
    """What a linkage looks like: its analysis (None where it assembles nowhere, message then
    says so), the drawing of its motion at the input angles phis, the transmission angle at
    each, and whether the crank turns fully (else it rocks between dead centres); settled False
    for a glance (explore_glance: one position, not analysed yet). With dynamics: forces() at
    each of phis (UNBOUNDED at a dead centre) and the torque's peak (torque_peak; None in a
    glance)."""
    analysis: Analysis | None
    message: str
    drawing: Drawing
    phis: tuple[float, ...]
    mus: tuple[float | None, ...]
    turns: bool
    settled: bool = True
    forces: tuple[Forces, ...] = ()
    peak: TorquePeak | None = None


def _motion_angles(analysis: Analysis | None, count: int = EXPLORE_POSITIONS
                   ) -> tuple[list[float], bool]:
    """`count` input angles over a full turn, or count + 1 over the crank's first reachable
    range end to end (dead centre to dead centre, each _INSIDE it: there the two branches
    meet, and exactly there rounding may leave no pose); whether the crank turns fully."""
    if analysis is None or analysis.crank_range is None:
        return [360.0 * i / count for i in range(count)], True
    lo, hi = analysis.crank_range[0]
    hi += 360.0 if hi <= lo else 0.0
    lo, hi = lo + _INSIDE, hi - _INSIDE
    return [lo + (hi - lo) * i / count for i in range(count + 1)], False


def analysis_drawing(analysis: Analysis, coupler: tuple[float, float] | None = None,
                     positions: int = 72) -> Drawing:
    """The linkage moving over its motion (a full turn of the crank, or its first reachable
    range: `positions` poses), with the positions analyse finds drawn faint and numbered: the
    output's extremes, the dead centres and the transmission angle furthest from 90 degrees
    (the subtitle says which number is which); coupler (u, v): its curve traced and the
    transmission angle charted. A ValueError says why it cannot be drawn."""
    a = analysis
    linkage = Linkage(a.linkage.kind, **a.linkage.dims)
    branch = a.branch if isinstance(a.branch, int) else 1
    worst = a.mu_worst
    angular = not linkage.is_slider

    def off(x: float | None, value: float, angle: bool) -> float:
        if x is None:
            return math.inf
        return abs(wrap_degrees(x - value)) if angle else abs(x - value)

    def output_on(b: int, phi: float) -> float | None:
        return linkage.sweep([phi], b, 0)[0].output

    def mu_on(b: int, phi: float) -> float | None:
        return linkage.transmission([phi], b)[0]
    named: list[tuple[Extreme, str, Callable[[int, float], float | None] | None, bool]] = (
        [(e, "out min" if e is a.output_min else "out max", output_on, angular)
         for e in (a.output_min, a.output_max)]
        if a.output_min is not None and a.output_max is not None else [])
    named += [(Extreme(phi, 0.0), "dead centre", None, False) for phi in a.dead_centres]
    named.append((worst, f"μ {worst.value:.4g}° worst", mu_on, True))
    marked: list[float] = []
    branches: list[int] = []
    texts: list[list[str]] = []
    for extreme, text, value_on, angle in named:    # one number for what shares a position
        phi = extreme.phi
        on = branch if value_on is None else min(     # the branch where the value is
            (branch, 3 - branch), key=lambda b: off(value_on(b, phi), extreme.value, angle))
        same = next((i for i, (m, b) in enumerate(zip(marked, branches))
                     if abs(wrap_degrees(m - phi)) < 1e-6 and (b == on or value_on is None)),
                    None)
        if same is None:
            marked.append(phi)
            branches.append(on)
            texts.append([text + ("" if on == branch else f" (branch {on})")])
        else:
            texts[same].append(text)
    subtitle = ", ".join(f"{n} {' + '.join(t)} φ={phi % 360.0:.4g}"
                         for n, (t, phi) in enumerate(zip(texts, marked), 1))
    phis, turns = _motion_angles(a, positions)
    end = phis[0] + 360.0 if turns else phis[-1]       # the output's extremes on this branch
    exact = [phis[0] + (e.phi - phis[0]) % 360.0 for e in (a.output_min, a.output_max)  # drawn
             if e is not None and off(output_on(branch, e.phi), e.value, angular) < 1e-6]
    phis = sorted(set(phis) | {phi for phi in exact if phi < end or phi == phis[-1]})
    dims = " ".join(f"{'ξ' if k == 'ksi' else k}={v:g}" for k, v in linkage.dims.items())
    return mechanism_drawing(linkage, phis, branch, f"{KIND_NAMES[linkage.kind]}: {dims}; "
                             f"{a.linkage_class}, crank {'full' if a.crank_range is None else 'rocks'}",
                             subtitle, coupler, (), marked, branches)


def explore_view(state: Explorer) -> ExploreView:
    """The view of the state's linkage; a ValueError says why it cannot be drawn."""
    linkage = state.linkage
    coupler = state.coupler if state.traced else None
    if coupler is not None:
        check_coupler_point(linkage, *coupler)
    branch: int | str = FOLLOW if state.follow else state.branch
    try:
        analysis: Analysis | None = analyse(linkage, branch, state.branch if state.follow
                                            else None)
        message = ""
    except ValueError as e:
        if "assembles at no" not in str(e):
            raise
        analysis, message = None, "does not assemble at any crank angle"
    phis, turns = _motion_angles(analysis)
    if not turns and analysis is not None:
        lo, hi = phis[0], phis[-1]
        message = f"the crank rocks from {lo % 360:.4g} to {hi % 360:.4g} (dead centres)"
    traced = (FOLLOW,) if state.follow and coupler is not None else ()
    name = KIND_NAMES[state.kind]
    drawing = mechanism_drawing(linkage, phis, state.branch,
                                f"{name}: " + (message or "the crank turns fully"), None,
                                coupler, traced)
    mus = tuple(linkage.transmission(phis, state.branch))
    if state.dynamics is None:
        return ExploreView(analysis, message, drawing, tuple(phis), mus, turns)
    stops = () if analysis is None else analysis.dead_centres + analysis.change_points
    dead = frozenset(i for i, phi in enumerate(phis) if (not turns and i in (0, len(phis) - 1))
                     or any(abs(wrap_degrees(phi - x)) < 1e-6 for x in stops))
    bodies, effects, radius = state.dynamics
    results, peak = torque_peak(linkage, phis, state.branch, bodies, effects, radius=radius,
                                turns=turns, dead=dead)
    return ExploreView(analysis, message, drawing, tuple(phis), mus, turns, True, results, peak)


def explore_glance(state: Explorer, phi: float, bounds: Box) -> ExploreView:
    """The state's linkage at the one input angle phi, not analysed, drawn over `bounds` and its
    own: what a key shows at once while keys come faster than analyse answers. A ValueError
    says why it cannot be drawn."""
    linkage = state.linkage
    coupler = state.coupler if state.traced else None
    drawing = mechanism_drawing(linkage, [phi], state.branch,
                                f"{KIND_NAMES[state.kind]}: ...", None, coupler)
    x0, y0, x1, y1 = drawing.bounds
    drawing = drawing._replace(bounds=(min(x0, bounds[0]), min(y0, bounds[1]),
                                       max(x1, bounds[2]), max(y1, bounds[3])))
    mus = tuple(linkage.transmission([phi], state.branch))
    now = () if state.dynamics is None else tuple(
        forces(linkage, [phi], state.branch, *state.dynamics[:2], radius=state.dynamics.radius))
    return ExploreView(None, "", drawing, (phi,), mus, True, False, now)


class ExploreViews:
    """explore_view's answers kept for the linkages seen lately (each key asks again). quick:
    a linkage not seen yet is first a glance (explore_glance), made whole by settled."""

    def __init__(self, quick: bool = False, keep: int = 64) -> None:
        self.kept: dict[tuple[Any, ...], ExploreView] = {}
        self.glances: dict[tuple[Any, ...], ExploreView] = {}
        self.quick, self.keep = quick, keep

    @staticmethod
    def _key(state: Explorer) -> tuple[Any, ...]:
        return (state.kind, state.dims, state.branch, state.follow,
                state.coupler if state.traced else None, repr(state.dynamics))

    def __call__(self, state: Explorer) -> ExploreView:
        key = self._key(state)
        if key in self.kept:
            return self.kept[key]
        if key in self.glances:
            return self.glances[key]
        if len(self.kept) >= self.keep:
            self.kept.clear()
        self.kept[key] = explore_view(state)
        return self.kept[key]

    def changed(self, state: Explorer, phi: float, bounds: Box) -> ExploreView:
        """The view of a state just changed to, shown near phi: a glance if quick."""
        key = self._key(state)
        if not self.quick or key in self.kept:
            return self(state)
        if key not in self.glances:
            if len(self.glances) >= self.keep:
                self.glances.clear()
            self.glances[key] = explore_glance(state, phi, bounds)
        return self.glances[key]

    def settled(self, state: Explorer) -> Explorer:
        """The state with its view whole (analysed, its motion drawn), at the position nearest
        the one its glance showed; the state itself if its view was whole."""
        glance = self(state)
        if glance.settled:
            return state
        key = self._key(state)
        del self.glances[key]
        try:
            whole = self.kept[key] = explore_view(state)
        except ValueError as e:         # drawn at one position but not over the motion: undone
            if not state.undo:
                raise
            back = state.undo[0]._replace(undo=state.undo[1:], status=f"refused: {e}")
            return self.settled(back._replace(position=min(back.position,
                                                           len(self(back).phis) - 1)))
        return state._replace(position=_nearest(whole.phis, glance.phis[state.position]),
                              status=state.status or whole.message)


def _nearest(phis: Sequence[float], phi: float) -> int:
    """The index of the angle of phis nearest phi (modulo a turn)."""
    return min(range(len(phis)), key=lambda i: abs(wrap_degrees(phis[i] - phi)))


def _degrees(kind: str, name: str) -> bool:
    """Whether the explorer's dimension `name` (or u, v) of `kind` is an angle."""
    return name == "ksi" or (kind == SPHERICAL_FOUR_BAR and name in "abcduv")


def explore_steps(state: Explorer, name: str) -> tuple[float, float]:
    """A dimension's small and large steps: an angle's 1 and 10 degrees; a length's the 1-2-5
    step (1, 2 or 5 times a power of ten) at or above 1 % of the longest of the other links,
    and ten times that: a linkage in metres steps by millimetres, not by 0.1 m, and a key held
    keeps its step (the length it changes is not the one measured), so Right then Left is back."""
    if _degrees(state.kind, name):
        return 1.0, 10.0
    longest = max([abs(x) for n, x in state.dims if n != name and not _degrees(state.kind, n)]
                  or [0.0])
    size = 0.01 * (longest or 1.0)
    power = 10.0 ** math.floor(math.log10(size))
    small = next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= size * (1 - 1e-12))
    return small, 10.0 * small


def _changed(state: Explorer, views: ExploreViews, **changes: Any) -> Explorer:
    """The state with `changes` to its linkage or coupler point, undo-able, shown at the
    position nearest the one shown; the state as it was, with the reason on the status line, if
    the new one cannot be drawn."""
    new = state._replace(**changes, status="", typing=None)
    old_view = views(state)
    old_phi = old_view.phis[state.position]
    try:
        new_view = views.changed(new, old_phi, old_view.drawing.bounds)
    except ValueError as e:
        return state._replace(status=f"refused: {e}", typing=None)
    position = _nearest(new_view.phis, old_phi)
    undo = (state._replace(undo=(), status="", typing=None),) + state.undo[:_UNDO_DEPTH - 1]
    return new._replace(position=position, undo=undo,
                        selected=min(new.selected, len(new.names) - 1),
                        status=new_view.message)


def _set_value(state: Explorer, name: str, value: float,
               views: ExploreViews) -> Explorer:
    value = float(f"{value:.12g}") + 0.0                # 0.1 + 0.2 stays 0.3
    if name in ("u", "v"):
        u, v = state.coupler
        return _changed(state, views, coupler=(value, v) if name == "u" else (u, value))
    return _changed(state, views, dims=tuple((n, value if n == name else x)
                                             for n, x in state.dims))


def _typed_key(state: Explorer, key: str, views: ExploreViews
               ) -> Explorer:
    """A key while a value is typed: characters add, Backspace takes back, Enter takes the
    value (or refuses it), Esc leaves it."""
    typed = cast(str, state.typing)
    name = state.names[state.selected]
    if key == "Esc":
        return state._replace(typing=None, status="")
    if key == "Backspace":
        return state._replace(typing=typed[:-1])
    if key == "Enter":
        if not DECIMAL.fullmatch(typed) or not math.isfinite(float(typed)):
            return state._replace(typing=None, status=f"refused: {name} = {typed!r} is not a "
                                                      "number (e.g. 6.5, -2, 1e-3)")
        return _set_value(state, name, float(typed), views)
    if len(key) == 1 and key in "0123456789.-+eE" and len(typed) < 24:
        return state._replace(typing=typed + key)
    return state


def _named_key(state: Explorer, key: str) -> Explorer:
    """A key while the scene's file name is typed (save), or an overwrite answered."""
    if state.confirm is not None:
        if key in ("y", "Y"):
            return state._replace(confirm=None, save_to=state.confirm, overwrite=True)
        return state._replace(confirm=None, status="not saved")
    typed = cast(str, state.naming)
    if key == "Esc":
        return state._replace(naming=None, status="not saved")
    if key == "Backspace":
        return state._replace(naming=typed[:-1])
    if key == "Enter":
        if not typed.strip():
            return state._replace(naming=None, status="not saved: no file name")
        return state._replace(naming=None, save_to=typed.strip())
    if len(key) == 1 and key.isprintable() and len(typed) < 200:
        return state._replace(naming=typed + key)
    if key == "Space":
        return state._replace(naming=typed + " ")
    return state


def _moved(state: Explorer, view: ExploreView, by: int) -> Explorer:
    """The shown position moved by `by`: round a full turn, or up to a dead centre, where the
    motion stops (and turns back at the next play)."""
    count = len(view.phis)
    if view.turns:
        return state._replace(position=(state.position + by) % count)
    position = state.position + by
    if 0 <= position < count:
        return state._replace(position=position)
    end = 0 if position < 0 else count - 1
    return state._replace(position=end, playing=False, direction=-state.direction,
                          status=f"stopped at a dead centre, crank {view.phis[end] % 360:.4g} "
                                 "deg (Space plays back)")


def explore_key(state: Explorer, key: str, views: ExploreViews) -> Explorer:
    """The state after `key` (a character, or a name of EXPLORE_KEY_NAMES); views(state) is the
    state's view. A key that means nothing here changes nothing."""
    state = state._replace(save_to=None)
    if key == "Tick":                       # the motion goes on under help and prompts
        return _moved(state, views(state), state.direction) if state.playing else state
    if state.help:
        return state._replace(help=False)
    if state.typing is not None:
        return _typed_key(state, key, views)
    if state.naming is not None or state.confirm is not None:
        return _named_key(state, key)
    names = state.names
    view = views(state)
    state = state._replace(status="" if view.turns or not view.message else view.message)
    if key in ("q", "Q"):
        return state._replace(done=True)
    if key == "?":
        return state._replace(help=True)
    if key in ("Tab", "Down", "S-Tab", "Up"):
        by = 1 if key in ("Tab", "Down") else -1
        return state._replace(selected=(state.selected + by) % len(names))
    letter = {"X": "ksi"}.get(key, key.lower())
    if key.isupper() and letter in names:
        return state._replace(selected=names.index(letter))
    name = names[state.selected]
    if key in _STEP_KEYS:                   # Left, Right: small steps; the others large ones
        small, large = explore_steps(state, name)
        size = small if key in ("Left", "Right") else large
        sign = 1.0 if key in ("Right", "S-Right", "]") else -1.0
        return _set_value(state, name, state.value(name) + sign * size, views)
    if key in ("=", "Enter"):
        return state._replace(typing="")
    if key == "b":
        return _changed(state, views, branch=3 - state.branch)
    if key == "f":
        return _changed(state, views, follow=not state.follow)
    if key == "c":
        return _changed(state, views, traced=not state.traced)
    if key == "k":
        kinds = list(LINKAGE_DIMENSIONS)
        first = explorer_of(kinds[(kinds.index(state.kind) + 1) % len(kinds)])
        new = _changed(state, views, kind=first.kind, dims=first.dims, coupler=first.coupler,
                       selected=0, dynamics=None)
        return new._replace(status=new.status or "the forces stay with the "
                            f"{KIND_NAMES[state.kind]} (u brings it back)") \
            if state.dynamics is not None and new.kind != state.kind else new
    if key == "u":
        if not state.undo:
            return state._replace(status="nothing to undo")
        back = state.undo[0]
        return back._replace(undo=state.undo[1:], status="undone", playing=state.playing,
                             speed=state.speed, position=min(back.position,
                                                             len(views(back).phis) - 1))
    if key == "Space":
        return state._replace(playing=not state.playing)
    if key in (",", "."):
        return _moved(state._replace(playing=False), view, 1 if key == "." else -1)
    if key in ("+", "-"):
        speed = max(0, min(len(EXPLORE_SPEEDS) - 1, state.speed + (1 if key == "+" else -1)))
        return state._replace(speed=speed, status=f"{EXPLORE_SPEEDS[speed]} positions a second")
    if key == "s":
        return state._replace(naming=f"explore-{state.kind}.toml")
    return state


def _number(x: float | None, unit: str = "") -> str:
    return "-" if x is None else f"{x:.6g}{unit}"


def _analysis_rows(view: ExploreView, mu: float | None, unit: str, more: bool
                   ) -> list[tuple[str, str]]:
    """The side panel's answers of analyse: the class, crank range, swing, time ratio and the
    transmission angle now, at its extremes and furthest from 90 degrees; more: the output's
    range, the dead centres and change points too."""
    a = view.analysis
    if not view.settled:
        return [("class", "..."), ("μ now", _number(mu and round(mu, 4)))]
    if a is None:
        return [("class", "none"), ("", view.message), ("μ now", "-")]
    crank = "full" if a.crank_range is None else ", ".join(
        f"{lo:.5g} to {hi:.5g}" for lo, hi in a.crank_range)
    swing = ("full turn" if a.output_min is None or a.output_max is None
             else _number(a.output_max.value - a.output_min.value, unit))
    worst = a.mu_worst
    rows = [("class", a.linkage_class), ("crank", crank)]
    if len(a.circuits) > 1:
        rows.append(("circuits", str(len(a.circuits))))
    if more:
        rows += [("output", "full turn" if a.output_min is None or a.output_max is None else
                  f"{_number(a.output_min.value)} to {_number(a.output_max.value)}{unit}"),
                 ("dead centres", ", ".join(f"{x:.6g}" for x in a.dead_centres) or "none"),
                 ("change pts", ", ".join(f"{x:.6g}" for x in a.change_points) or "none")]
    return rows + [("swing", swing), ("time ratio", _number(a.time_ratio)),
                   ("μ now", _number(mu and round(mu, 4))),
                   ("μ min", f"{_number(a.mu_min.value)} at {_number(a.mu_min.phi)}"),
                   ("μ max", f"{_number(a.mu_max.value)} at {_number(a.mu_max.phi)}"),
                   ("worst |μ-90|", f"{_number(abs(worst.value - 90.0))} at "
                                    f"{_number(worst.phi)}")]


def _torque_rows(state: Explorer, view: ExploreView, more: bool) -> list[tuple[str, str]]:
    """The side panel's driving torque, with dynamics: now (at the position shown) and its
    peak over the motion with its crank angle, or where it is unbounded; more: the speed and
    how the peak was found too."""
    if state.dynamics is None or not view.forces:
        return []
    now = view.forces[state.position]
    said = {UNBOUNDED: "unbounded", OUT_OF_RANGE: "overflow"}
    rows = [("torque now", f"{now.torque:.6g} N m" if now.torque is not None
             else said.get(now.status, "-"))]
    peak = view.peak
    if peak is None:
        rows.append(("torque peak", "..."))
    elif peak.unbounded:
        rows.append(("torque peak", "unbounded: " + ", ".join(f"{phi % 360.0:.4g}"
                                                              for phi in peak.unbounded)))
    else:
        rows.append(("torque peak", "-" if peak.value is None or peak.phi is None else
                     f"{peak.value:.6g} N m at {peak.phi % 360.0:.5g}"))
    if more:
        rows += [("speed", f"{state.dynamics.effects.speed_rpm:g} rpm"),
                 ("peak of", f"{len(view.phis)} positions, refined")]
    return rows


def _side_panel(state: Explorer, view: ExploreView, width: int, height: int, unicode: bool
                ) -> tuple[list[str], int]:
    """The side panel's lines, and which one is the selected dimension's."""
    unit = "" if state.kind in SLIDER_CRANKS else " deg"
    lines = [KIND_NAMES[state.kind],
             f"branch {state.branch} ({'A+B' if state.branch == 1 else 'A-B'})"
             + ("  follow" if state.follow else ""), ""]
    selected = 0
    for i, name in enumerate(state.names):
        if i == state.selected:
            selected = len(lines)
        shown = ("ξ" if unicode else "X") if name == "ksi" else name
        what = "coupler point" if name in ("u", "v") else DIMENSION_NAMES[name].removeprefix(
            "the ").replace(", degrees", "")
        value = (state.typing + "_" if i == state.selected and state.typing is not None
                 else f"{state.value(name):g}")
        lines.append(f"{'>' if i == state.selected else ' '}{shown:>3} = {value:<9} {what}")
    lines.append("")
    phi = view.phis[state.position] % 360.0
    mu = view.mus[state.position]
    more = height >= 32
    lines += [f"{name if unicode else name.translate(_ASCII_PANEL):<12} {value}" if name
              else f"  {value}" for name, value in _analysis_rows(view, mu, unit, more)
              + _torque_rows(state, view, more)]
    speed = EXPLORE_SPEEDS[state.speed]
    lines += ["", f"φ = {phi:.4g} deg  " + (f"playing {speed}/s" if state.playing
                                            else "paused")]
    excess = len(lines) - (height - 2)
    if excess > 0:                      # more than the screen holds: blank lines go first
        dropped = [i for i, line in enumerate(lines) if not line][:excess]
        selected -= sum(1 for i in dropped if i < selected)
        lines = [line for i, line in enumerate(lines) if i not in dropped]
    return [line[:width] for line in lines], selected


def _footer(width: int, unicode: bool, steps: tuple[float, float]) -> str:
    """The keys line: the most used keys, all of them where the screen is wide enough; the
    arrows' and [ ]'s steps of the selected dimension (explore_steps)."""
    arrows, sign = ("←→", "±") if unicode else ("<>", "+-")
    small, large = (f"{sign}{step:g}" for step in steps)
    wide = (f"Tab/ABC select  {arrows} {small}  [] {large}  = type  b branch  f follow  "
            "Space play  ,. step  +- speed  c coupler  k kind  u undo  s save  ? help  q quit")
    narrow = (f"Tab select {arrows}{small} []{large} = type b branch Space play c k u s ? help "
              "q quit")
    return wide if len(wide) <= width else narrow[:width]


def _help_lines() -> list[str]:
    return ["The explorer's keys", ""] + [f"  {keys:<24} {what}" for keys, what in EXPLORE_HELP]


def _status_line(state: Explorer) -> str:
    if state.typing is not None:
        return f"{state.names[state.selected]} = {state.typing}_   (Enter takes it, Esc leaves)"
    if state.naming is not None:
        return f"save as: {state.naming}_   (Enter saves, Esc leaves)"
    if state.confirm is not None:
        return f"{state.confirm} exists: overwrite it? (y/n)"
    return state.status


def explore_screen(state: Explorer, view: ExploreView, width: int = 80, height: int = 24,
                   unicode: bool = True) -> tuple[list[str], int | None, int]:
    """The screen of `height` lines of at most `width` characters: the linkage drawn at the
    shown position on the left, the side panel on the right, then the keys and the status line;
    with the row of the selected dimension (None on the help screen) and the side panel's
    first column (for the terminal to highlight)."""
    width, height = max(width, 40), max(height, 12)
    side = 36 if width < 120 else 44
    left = width - side - 1
    if state.help:
        body = _help_lines()
        rows: int | None = None
    else:
        drawn = text_drawing(view.drawing, state.position, left, height - 2, unicode).split("\n")
        panel, selected = _side_panel(state, view, side, height, unicode)
        body = [f"{d:<{left}} {p}" for d, p in zip(drawn + [""] * (height - 2 - len(drawn)),
                                                   panel + [""] * (height - 2 - len(panel)))]
        rows = selected
    body = (body + [""] * height)[:height - 2] + [_footer(width, unicode, explore_steps(state, state.names[state.selected])),
                                              _status_line(state)]
    if not unicode:                     # as text_drawing's lines: anything else a '?'
        body = [line.translate(_ASCII_PANEL).encode("ascii", "replace").decode("ascii")
                for line in body]
    return [line[:width].rstrip() for line in body], rows, left + 1


def explore_scene(state: Explorer, view: ExploreView, path: str) -> Scene:
    """The state as a mechanism scene (scene_text writes it; explore SCENE reads it back): the
    linkage, its branch, the motion drawn, the coupler point traced, and followed (a scene
    follows the motion only with a coupler point: given where follow is on), and its
    [dynamics]."""
    phis = view.phis
    step = (phis[-1] - phis[0]) / max(1, len(phis) - 1)
    branches: tuple[int | str, ...] = (state.branch,) + ((FOLLOW,) if state.follow else ())
    return Scene(path, f"{KIND_NAMES[state.kind]}, as explored", state.kind,
                 dict(state.dims), phis[0], phis[-1], step, branches, ("double",),
                 (PanelSpec((MECHANISM_PANEL,), None),),
                 coupler=state.coupler if state.traced or state.follow else None,
                 dynamics=state.dynamics)


def terminal_keys(data: bytes) -> list[str]:
    """The keys in bytes read from a terminal: escape sequences as EXPLORE_KEY_NAMES' names,
    other characters as themselves (Ctrl-C never reaches here: it interrupts)."""
    keys = []
    text = data
    while text:
        known = next((s for s in _TERMINAL_SEQUENCES if text.startswith(s)), None)
        if known is not None:
            keys.append(_TERMINAL_SEQUENCES[known])
            text = text[len(known):]
            continue
        if text[:1] == b"\x1b":
            other = re.match(rb"\x1b(\[[0-9;?]*[ -/]*[@-~]|O[@-~])", text)   # a key not used here
            if other is None:
                keys.append("Esc")
            text = text[other.end() if other else 1:]
            continue
        length = next((n for n in range(1, 5) if _decodes(text[:n])), 1)
        char = text[:length].decode("utf-8", "replace")
        if char.isprintable():
            keys.append(char)
        text = text[length:]
    return keys


def _decodes(data: bytes) -> bool:
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return False
    return True


def key_file(text: str) -> list[str]:
    """The keys of a key file: one a line, a name of EXPLORE_KEY_NAMES or one character (a space
    or a tab as Space and Tab); lines empty or starting with "# " are skipped. A ValueError
    names a line that is neither."""
    keys = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line or line.startswith("# "):
            continue
        if line in EXPLORE_KEY_NAMES or len(line) == 1:
            keys.append({" ": "Space", "\t": "Tab"}.get(line, line))
        else:
            raise ValueError(f"line {number}: {line!r} is no key: one character, or one of "
                             f"{', '.join(EXPLORE_KEY_NAMES)}")
    return keys


def explore_saved(state: Explorer, views: ExploreViews) -> Explorer:
    """The save a key asked for (save_to): the scene written whole (written_whole), or first
    asked about where the file exists, or the reason it could not be written."""
    path = state.save_to
    if path is None:
        return state
    state = views.settled(state)
    asked, state = state.overwrite, state._replace(save_to=None, overwrite=False)
    if os.path.lexists(path) and not asked:
        return state._replace(confirm=path)
    try:
        with written_whole(path) as fh:
            fh.write(scene_text(explore_scene(state, views(state), path),
                                "made by python3 linkage.py explore").encode("utf-8"))
    except OSError as e:
        return state._replace(status=f"not saved: {path}: {e.strerror or e}")
    return state._replace(status=f"saved {path}")


def explore_replay(state: Explorer, keys: Iterable[str], width: int = 80, height: int = 24,
                   unicode: bool = True) -> tuple[Explorer, list[str]]:
    """The state after each of `keys` in turn, until q, and the last screen (the selected
    dimension marked by '>'). The keys are taken as the terminal takes keys typed faster than
    it analyses: steps of a dimension (the arrows, [ and ]) one after another as glances, the
    view made whole before any other key (Tick: a tick of the timer) and at the end."""
    views = ExploreViews(quick=True)
    for key in keys:
        if key not in _STEP_KEYS:
            state = views.settled(state)
        state = explore_saved(explore_key(state, key, views), views)
        if state.done:
            break
    state = views.settled(state)
    lines, _, _ = explore_screen(state, views(state), width, height, unicode)
    return state, lines


def explore_terminal(state: Explorer, unicode: bool = True) -> Explorer:
    """The explorer on the terminal of standard input and output, until q (or Ctrl-C, or
    SIGTERM: KeyboardInterrupt): single keys, the alternate screen, redrawn at each key, each
    tick of the motion and each resize (SIGWINCH); the terminal is given back as it was."""
    import select
    import signal
    import time
    keys_fd, out = sys.stdin.fileno(), sys.stdout
    views = ExploreViews(quick=True)
    woken, wake = os.pipe()
    shown: list[str] = []

    def draw(again: bool = False) -> None:
        try:                                # the terminal's own size, whatever COLUMNS says
            width, height = os.get_terminal_size(out.fileno())
        except OSError:
            width, height = shutil.get_terminal_size()
        lines, row, column = explore_screen(state, views(state), width, height, unicode)
        if row is not None:
            lines[row] = lines[row][:column] + "\x1b[7m" + lines[row][column:] + "\x1b[27m"
        if lines != shown or again:
            out.write("\x1b[H" + "\x1b[K\n".join(lines) + "\x1b[K\x1b[J")
            out.flush()
            shown[:] = lines

    def resized(signum: int, frame: object) -> None:
        with contextlib.suppress(OSError):
            os.write(wake, b"r")

    def enter() -> None:
        out.write("\x1b[?1049h\x1b[?25l")
        draw(again=True)

    def leave() -> None:
        out.write("\x1b[?25h\x1b[?1049l")
        out.flush()

    before = signal.signal(signal.SIGWINCH, resized)
    try:
        with single_keys(keys_fd, enter, leave):
            due = time.monotonic()
            while not state.done:
                settled = views(state).settled
                wait = max(0.0, due - time.monotonic()) if state.playing else None
                ready = select.select([keys_fd, woken], [], [], wait if settled else 0.0)[0]
                if woken in ready:
                    os.read(woken, 64)
                    draw(again=True)
                elif keys_fd in ready:
                    data = os.read(keys_fd, 64)
                    if not data:                            # the terminal is gone
                        break
                    for key in terminal_keys(data):
                        state = explore_saved(explore_key(state, key, views), views)
                    draw()
                elif not settled:                           # no key waiting: analyse now
                    state = views.settled(state)
                    draw()
                else:
                    state = explore_key(state, "Tick", views)
                    due = max(due + 1.0 / EXPLORE_SPEEDS[state.speed], time.monotonic())
                    draw()
                if not state.playing:
                    due = time.monotonic()
    finally:
        signal.signal(signal.SIGWINCH, before)
        os.close(woken)
        os.close(wake)
    return state


# ---- 27. Benchmarks of the program itself --------------------------------------------------------
#
# Holds: what `python3 linkage.py bench` measures, each bench a function of BENCHMARKS. What
# accuracy costs is measured by tests/support/bench_accuracy.py, with the tests' instruments;
# the engine beside other programs (a C loop, pylinkage) by tests/support/bench_peers.py.
#
# Uses: sections 1, 2, 3, 4, 5, 6, 7, 9, 10, 14, 15, 16, 17, 18, 22, 23, 24 and 26.
# Offers: BENCH_KEYS, QUICK_KEYS, ONE_POINT_KEYS, bench_mbf, bench_scene, bench_port, bench_startup,
#   ENGINE_TARGET, FAST_TARGETS, BENCH_LINKAGES, bench_engine, bench_coupler, FORCES_ARRAYS_TARGET,
#   bench_forces, FILES_TARGET, bench_files, ACCURACY_POINTS, ACCURACY_SWEEP, ACCURACY_RUNGS, Rung,
#   measure_accuracy, bench_accuracy, EXPLORE_TARGET, bench_explore, SIMULATION_TOLERANCES,
#   bench_simulate, BENCHMARKS, machine.


BENCH_KEYS = b"12\r7\r9\r6\r0\r360\r.1\r1"     # the 3601-point session of data/golden
QUICK_KEYS = b"12\r7\r9\r6\r0\r360\r10\r1"     # bench --quick: 37 points
ONE_POINT_KEYS = b"12\r7\r9\r6\r0\r0\r1\r1"     # bench startup: one point


def _timed(repeats: int, function: Callable[[], Any]) -> tuple[float, Any]:
    """The fastest of `repeats` runs of function(), in seconds, and what the last run returned."""
    import time
    best, result = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result


def _best_of(repeats: int, function: Callable[[], object]) -> float:
    """The fastest of `repeats` runs of function(), in seconds."""
    return _timed(repeats, function)[0]


def bench_mbf(out: TextIO, quick: bool = False) -> str:
    """Time each single-precision operation and one sweep point of lines 1060-1330."""
    import random
    rng, count, repeats = random.Random(1), 20 if quick else 1000, 1 if quick else 5
    xs = [mbf_parse(f"{rng.uniform(-100, 100):.6g}") for _ in range(count)]
    ys = [mbf_parse(f"{rng.uniform(0.5, 100):.6g}") for _ in range(count)]
    pairs = list(zip(xs, ys))
    operations = {
        "X+Y": lambda: [mbf_add(x, y) for x, y in pairs],
        "X-Y": lambda: [mbf_sub(x, y) for x, y in pairs],
        "X*Y": lambda: [mbf_mul(x, y) for x, y in pairs],
        "X/Y": lambda: [mbf_div(x, y) for x, y in pairs],
        "X^2": lambda: [mbf_ipower(x, 2) for x in xs],
        "Y^.5": lambda: [mbf_power(y, 0.5) for y in ys],
        "INT(X)": lambda: [mbf_int(x) for x in xs],
        "SIN(X)": lambda: [mbf_sin(x) for x in xs],
        "COS(X)": lambda: [mbf_cos(x) for x in xs],
        "TAN(X)": lambda: [mbf_tan(x) for x in xs],
        "ATN(X)": lambda: [mbf_atn(x) for x in xs],
        "WRITE # text": lambda: [mbf_write_text(x) for x in xs],
        "PRINT text": lambda: [mbf_print_text(x) for x in xs],
    }
    print("operation        microseconds", file=out)
    for name, function in operations.items():
        print(f"{name:16} {_best_of(repeats, function) / len(xs) * 1e6:12.2f}", file=out)
    v = Variables()
    answers = iter(["2", "7", "9", "6"])
    dimensions(v, 1, lambda prompt: Single(mbf_parse(next(answers))))
    co = coefficients(v, 1)
    angles = list(sweep_angles(ZERO, degrees_to_radians(Single(360.0)),
                               degrees_to_radians(Single(90.0 if quick else 1.0))))
    with soft_errors():
        point = sweep_points(co, 1, v.S)
        seconds = _best_of(repeats, lambda: [point(phi) for phi in angles])
    print(f"{'sweep point':16} {seconds / len(angles) * 1e6:12.2f}   (lines 1060-1330 with "
          f"the three WRITE #, plane four-bar a=6 b=2 c=7 d=9)", file=out)
    return f"{seconds / len(angles) * 1e6:.0f} us a sweep point"


def bench_scene(out: TextIO, quick: bool = False) -> str:
    """A displacement-only scene against the same scene drawing velocity and acceleration."""
    import tempfile
    step, many, few = (10.0, 1, 1) if quick else (0.01, 15, 5)
    panels = {"displacement only": (PanelSpec(("displacement",), None),),
              "all three": (PanelSpec(("displacement",), None),
                            PanelSpec(("velocity", "acceleration"), None))}
    print(f"plane four-bar a=6 b=2 c=7 d=9, branch 1, precision double, 0 to 360 by {step:g} "
          f"degree ({angle_count(0.0, 360.0, step):,} points); seconds, best of {many} (engine) "
          f"or {few}", file=out)
    print(f"{'panels':18} {'engine':>8} {'+ DAT files':>12} {'+ text plot':>12}", file=out)
    times = {}
    for name, specs in panels.items():
        scene = Scene("bench", "bench", PLANE_FOUR_BAR, dict(a=6.0, b=2.0, c=7.0, d=9.0),
                      0.0, 360.0, step, (1,), ("double",), specs)
        angles = evenly_spaced_angles(scene.start, scene.stop, scene.step)
        linkage = Linkage(scene.kind, **scene.dimensions)
        with tempfile.TemporaryDirectory() as directory:
            times[name] = (
                _best_of(many, lambda: linkage.sweep(angles, 1, scene.derivatives)),
                _best_of(few, lambda: compute_scene(scene, directory)),
                _best_of(few, lambda: text_figure(scene_figure(scene,
                                                             compute_scene(scene, directory)))))
        print(f"{name:18} {times[name][0]:8.3f} {times[name][1]:12.3f} {times[name][2]:12.3f}",
              file=out)
    saved = [1 - d / a for d, a in zip(times["displacement only"], times["all three"])]
    print(f"{'time saved':18} {saved[0]:8.0%} {saved[1]:12.0%} {saved[2]:12.0%}", file=out)
    _bench_mechanism_view(out, few)
    return f"displacement only saves {saved[2]:.0%} of a scene with its text plot"


def _bench_mechanism_view(out: TextIO, repeats: int) -> None:
    """What drawing the mechanism costs: 72 poses of each kind (the Figs. 1-2 scenes' sweep)."""
    angles = evenly_spaced_angles(30.0, 385.0, 5.0)
    print(f"\nthe mechanism view, {len(angles)} positions (30 to 385 by 5 degrees, the Figs. 1-2 "
          f"scenes); milliseconds, best of {repeats}", file=out)
    print(f"{'linkage':12} {'engine':>8} {'+ joints':>9} {'drawing':>9} {'text frame':>11} "
          f"{'SVG':>8} {'SVG bytes':>10}", file=out)
    for kind, dims in MECHANISM_EXAMPLES.items():
        linkage = Linkage(kind, **dims)
        drawing = mechanism_drawing(linkage, angles)
        times = (_best_of(repeats, lambda: linkage.sweep(angles, 1, 0)),
                 _best_of(repeats, lambda: [joint_positions(linkage, phi) for phi in angles]),
                 _best_of(repeats, lambda: mechanism_drawing(linkage, angles)),
                 _best_of(repeats, lambda: text_drawing(drawing, 0, 80, 24, True)),
                 _best_of(repeats, lambda: svg_drawing(drawing)))
        print(f"{kind:12} " + " ".join(f"{1e3 * t:{w}.2f}" for t, w in zip(times, (8, 9, 9, 11, 8)))
              + f" {len(svg_drawing(drawing).encode()):10,}", file=out)


def bench_port(out: TextIO, quick: bool = False, basic_command: list[str] | None = None) -> str:
    """The port against PC-BASIC, both started as programs on the same keys, same bytes.
    The keys are the 3601-point session's (0 to 360 degrees by 0.1), PC-BASIC runs
    legacy_basic/LINKAGE.BAS; measured: CPU time (user and system of the child process:
    getrusage RUSAGE_CHILDREN), wall time, and whether they wrote the same bytes (the three DAT
    files and the screen). The port runs as `python3 -m linkage` from cached bytecode, as the
    installed `linkage` command does, and as `python3 linkage.py`, compiled every run; beside
    them, its session alone in this process. basic_command: how PC-BASIC is started (python3 -m
    pcbasic)."""
    import io
    import resource
    import statistics
    import subprocess
    import tempfile
    import time
    keys, points, repeats = (QUICK_KEYS, 37, 1) if quick else (BENCH_KEYS, 3601, 3)
    here = os.path.dirname(os.path.abspath(__file__))
    env = dict(os.environ, PYTHONPATH=here)
    env.pop("PYTHONDONTWRITEBYTECODE", None)         # as where bytecode is kept, the default
    ports = {"python3 -m linkage": [sys.executable, "-m", "linkage"],
             "python3 linkage.py": [sys.executable, os.path.join(here, "linkage.py")]}

    def child(command: list[str], folder: str, **options: Any) -> tuple[float, float, bytes]:
        """Run a program to its end: wall and CPU seconds, and its standard output."""
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        run = subprocess.run(command, cwd=folder, capture_output=True, check=True, **options)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        return wall, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, run.stdout

    def in_process(folder: str) -> float:
        cpu = time.process_time()
        redirected_program(io.BytesIO(keys), io.BytesIO(), folder)
        return time.process_time() - cpu

    def written(folder: str, screen: bytes) -> dict[str, bytes]:
        return {n: open(os.path.join(folder, n), "rb").read() for n in DatFiles.NAMES} | {
            "the screen": screen}

    rows: dict[str, list[tuple[float, float, bytes]]] = {name: [] for name in ports}
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([sys.executable, "-c", "import linkage"], env=env, cwd=folder, check=True)
        for _ in range(repeats):                       # alternated, so that drift hits all alike
            for name, command in ports.items():
                rows[name].append(child(command, folder, input=keys, env=env))
        port = written(folder, rows["python3 -m linkage"][-1][2])
        inside = statistics.median(in_process(folder) for _ in range(repeats))
    times = {name: (statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs))
             for name, runs in rows.items()}
    basic = None
    with tempfile.TemporaryDirectory() as folder:
        with open(os.path.join(folder, "keys.txt"), "wb") as f:
            f.write(keys)
        command = (basic_command or [sys.executable, "-m", "pcbasic"]) + [
            os.path.join(here, "legacy_basic", "LINKAGE.BAS"), "--interface=none", "-q",
            "--input=keys.txt", "--output=STDOUT", "--sound=False"]
        with contextlib.suppress(OSError, subprocess.CalledProcessError):
            wall, cpu, screen = child(command, folder, stdin=subprocess.DEVNULL)
            basic = written(folder, screen) if all(
                os.path.exists(os.path.join(folder, n)) for n in DatFiles.NAMES) else {}
            times["PC-BASIC"] = (wall, cpu)
    print(f"{points} points (0 to 360 degrees by {360 / (points - 1):g}), the same keys; CPU "
          f"time: user and system of the child process; the port: median of {repeats} "
          f"alternated runs each, PC-BASIC: one run", file=out)
    if basic is not None:
        wall, cpu = times["PC-BASIC"]
        port_wall, port_cpu = times["python3 -m linkage"]
        differ = [n for n in port if basic.get(n) != port[n]]
        print(f"the port (python3 -m linkage) is {cpu / port_cpu:.0f} times faster than PC-BASIC "
              f"by CPU time ({wall / port_wall:.0f} by wall time; in this process, "
              f"{cpu / inside:.0f}); the DAT files and the screen are "
              + ("identical" if not differ else f"DIFFERENT: {', '.join(differ)}"), file=out)
    print(f"{'':24} {'CPU s':>8} {'wall s':>8} {'CPU ms a point':>15}", file=out)
    for name, (wall, cpu) in times.items():
        print(f"{name:24} {cpu:8.3f} {wall:8.3f} {cpu / points * 1e3:15.4f}", file=out)
    print(f"{'in this process':24} {inside:8.3f} {'':8} {inside / points * 1e3:15.4f}   (the "
          "session alone: redirected_program, no start-up)", file=out)
    if basic is None:
        print("PC-BASIC: not installed (pip install pcbasic==2.0.8)", file=out)
        return "PC-BASIC not installed"
    wall, cpu = times["PC-BASIC"]
    return (f"{cpu / times['python3 -m linkage'][1]:.0f}x by CPU as python3 -m linkage, "
            f"{cpu / times['python3 linkage.py'][1]:.0f}x as python3 linkage.py "
            f"({wall / times['python3 -m linkage'][0]:.0f}x and "
            f"{wall / times['python3 linkage.py'][0]:.0f}x by wall time), "
            + ("same bytes" if not differ else "DIFFERENT bytes"))


def bench_startup(out: TextIO, quick: bool = False) -> str:
    """Start-up: a one-point session by the installed `linkage` command, the module and the script.
    Each (python3 -m linkage and the `linkage` command from cached bytecode, python3 linkage.py
    compiled every run) beside Python starting alone, runs alternated: the CPU time of the child
    process (getrusage RUSAGE_CHILDREN) and the wall time, medians; and what compiling the
    module costs in this process."""
    import resource
    import statistics
    import subprocess
    import sysconfig
    import tempfile
    import time
    here = os.path.dirname(os.path.abspath(__file__))
    runs, repeats = (2, 1) if quick else (21, 5)
    env = dict(os.environ, PYTHONPATH=here)
    env.pop("PYTHONDONTWRITEBYTECODE", None)         # as where bytecode is kept, the default
    commands = {"python3 -c pass": [sys.executable, "-c", "pass"]}
    installed = os.path.join(sysconfig.get_path("scripts"), "linkage")
    if os.path.isfile(installed):                    # pip install . made it (it imports linkage)
        commands["linkage (the command)"] = [sys.executable, installed]
    commands |= {"python3 -m linkage": [sys.executable, "-m", "linkage"],
                 "python3 linkage.py": [sys.executable, os.path.join(here, "linkage.py")]}
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in commands}
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([sys.executable, "-c", "import linkage"], env=env, cwd=folder, check=True)
        for _ in range(runs):                      # alternated, so that drift hits all alike
            for name, command in commands.items():
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                start = time.perf_counter()
                subprocess.run(command, input=ONE_POINT_KEYS, cwd=folder,
                               env=env, capture_output=True, check=True)
                wall = time.perf_counter() - start
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                times[name].append((after.ru_utime - before.ru_utime
                                    + after.ru_stime - before.ru_stime, wall))
    with open(os.path.join(here, "linkage.py"), encoding="utf-8") as f:
        source = f.read()
    compiling = _best_of(repeats, lambda: compile(source, "linkage.py", "exec"))
    cpu = {name: statistics.median(c for c, _ in t) for name, t in times.items()}
    print(f"a one-point session (plane four-bar, 0 to 0 degrees); milliseconds, median of {runs} "
          f"runs each, alternated; CPU: user and system of the child process", file=out)
    print(f"{'':22} {'CPU':>7} {'wall':>7} {'CPU / python3 -c pass':>22}", file=out)
    for name, t in times.items():
        print(f"{name:22} {cpu[name] * 1e3:7.1f} {statistics.median(w for _, w in t) * 1e3:7.1f} "
              f"{cpu[name] / cpu['python3 -c pass']:22.2f}", file=out)
    print(f"{'compiling linkage.py':22} {compiling * 1e3:7.1f}   ({len(source.encode()):,} bytes, "
          f"in this process, best of {repeats}; the script pays it every run)", file=out)
    ratio = {name: cpu[name] / cpu["python3 -c pass"] for name in cpu}
    first = "linkage (the command)" if "linkage (the command)" in ratio else "python3 -m linkage"
    return (f"{ratio[first]:.2f}x by CPU ({first}; python3 -m linkage {ratio['python3 -m linkage']:.2f}x, "
            f"python3 linkage.py {ratio['python3 linkage.py']:.2f}x), median of {runs} alternated")


ENGINE_TARGET = 100_000    # points per second, displacement, velocity and acceleration, one core
FAST_TARGETS = {PLANE_FOUR_BAR: 10_000_000, "others": 5_000_000}   # the numpy path, likewise
BENCH_LINKAGES = ((PLANE_FOUR_BAR, dict(a=6, b=2, c=7, d=9)),
                  (SPHERICAL_FOUR_BAR, dict(a=80, b=20, c=75, d=60)),
                  (SKEW_FOUR_BAR, dict(a=6, b=2, c=7, d=9, f=1.5, ksi=25)),
                  (PLANE_SLIDER_CRANK, dict(b=2, c=7, e=1.5)),
                  (SKEW_SLIDER_CRANK, dict(a=6, b=1, c=7.5, f=3, ksi=45)))


def _bench_angles(points: int) -> tuple[list[float], Any]:
    """`points` input angles from 0 to 360 degrees: as a list, and as a numpy array (None
    without numpy)."""
    step = 360.0 / (points - 1)
    try:
        array = angle_array(0.0, step, 0, points)
    except FastUnavailable:
        array = None
    return evenly_spaced_angles(0.0, 360.0, step), array


def bench_engine(out: TextIO, quick: bool = False, points: int = 100_001) -> str:
    """The accurate engine's speed, scalar and vectorised (numpy). Beside other programs (a C
    loop of the same formulas, pylinkage): tests/support/bench_peers.py."""
    if quick:
        points = 1001
    angles, array = _bench_angles(points)
    print(f"{points:,} input angles, 0 to 360 degrees, branch 1; points per second, best of 5, "
          "the scalar engine and the numpy path alternated (this machine's speed drifts 2x "
          "within an hour: compare within one run, the ratios first)", file=out)
    print(f"{'linkage':12} {'numpy/scalar':>12} {'scalar disp':>12} {'scalar +v,a':>12} "
          f"{'numpy disp':>12} {'numpy +v,a':>12}", file=out)
    scalar: dict[str, dict[int, float]] = {}
    fast: dict[str, dict[int, float]] = {}
    for kind, dims in BENCH_LINKAGES:
        linkage = Linkage(kind, **dims)
        runs = {(way, level): math.inf for way in ("scalar", "numpy")[:1 + (array is not None)]
                for level in (0, 2)}
        for _ in range(5):
            for way, level in runs:
                runs[way, level] = min(runs[way, level], _best_of(1, (
                    lambda: linkage.sweep(angles, 1, level)) if way == "scalar" else (
                    lambda: linkage.sweep_arrays(array, 1, level))))
        rates = [len(angles) / runs["scalar", level] for level in (0, 2)]
        scalar[kind] = {0: rates[0], 2: rates[1]}
        if array is not None:
            fast_rates = [len(angles) / runs["numpy", level] for level in (0, 2)]
            fast[kind] = {0: fast_rates[0], 2: fast_rates[1]}
            print(f"{kind:12} {fast_rates[1] / rates[1]:11,.0f}x {rates[0]:12,.0f} "
                  f"{rates[1]:12,.0f} {fast_rates[0]:12,.0f} {fast_rates[1]:12,.0f}", file=out)
        else:
            print(f"{kind:12} {'':>12} {rates[0]:12,.0f} {rates[1]:12,.0f} "
                  f"{'numpy not installed':>25}", file=out)
    ratios = [fast[k][2] / scalar[k][2] for k in fast]
    figure = (f"numpy {min(ratios):.0f}-{max(ratios):.0f}x the scalar engine with velocity and "
              "acceleration" if fast else "numpy not installed")
    if quick:
        return figure
    slowest = min(r[2] for r in scalar.values())
    print(f"target: scalar >= {ENGINE_TARGET:,} points/s with velocity and acceleration on one "
          f"core (one Python thread): {'met' if slowest >= ENGINE_TARGET else 'NOT MET'}, "
          f"slowest {slowest:,.0f}", file=out)
    if fast:
        full = {k: r[2] for k, r in fast.items()}          # with velocity and acceleration
        short = [k for k, r in full.items()
                  if r < FAST_TARGETS.get(k, FAST_TARGETS["others"])]
        print(f"target: numpy path >= {FAST_TARGETS[PLANE_FOUR_BAR]:,} (plane), "
              f">= {FAST_TARGETS['others']:,} (the others) with velocity and acceleration: "
              + (f"NOT MET for {', '.join(short)}" if short else "met")
              + f", plane {full[PLANE_FOUR_BAR]:,.0f}, slowest other "
              f"{min(r for k, r in full.items() if k != PLANE_FOUR_BAR):,.0f}", file=out)
    return figure


def bench_coupler(out: TextIO, quick: bool = False, points: int = 100_001) -> str:
    """What the coupler point (with velocity and acceleration) and the transmission angle add
    to a sweep with velocity and acceleration, scalar and numpy: the time of the sweep with them
    over the sweep alone."""
    if quick:
        points = 101
    angles, array = _bench_angles(points)
    print(f"{points:,} input angles, 0 to 360 degrees, branch 1, velocity and acceleration; the "
          "time with the coupler point (u = c/2, v = c/4: the skew kinds v = 0) and mu over the "
          "time without; best of 3 (numpy: of 9), one run", file=out)
    print(f"{'linkage':12} {'scalar sweep':>13} {'+coupler':>9} {'+mu':>6} {'+both':>6} "
          f"{'numpy sweep':>12} {'+coupler':>9} {'+mu':>6} {'+both':>6}", file=out)
    both = []
    for kind, dims in BENCH_LINKAGES:
        linkage = Linkage(kind, **dims)
        u, v = dims["c"] / 2, 0.0 if PINS[kind].coupler == "line" else dims["c"] / 4
        base = _best_of(3, lambda: linkage.sweep(angles))
        row = [base, _best_of(3, lambda: coupler_of(linkage, linkage.sweep(angles), u, v)),
               _best_of(3, lambda: transmission_of(linkage, linkage.sweep(angles))),
               _best_of(3, lambda: (lambda m: (coupler_of(linkage, m, u, v),
                                               transmission_of(linkage, m)))(
                   linkage.sweep(angles)))]
        text = (f"{kind:12} {len(angles) / base:10,.0f}/s " + " ".join(
            f"{t / base:{w}.2f}x" for t, w in zip(row[1:], (8, 5, 5))))
        both.append(row[3] / base)
        if array is not None:
            fast = _best_of(9, lambda: linkage.sweep_arrays(array))
            times = [_best_of(9, lambda: coupler_of_arrays(linkage, linkage.sweep_arrays(array),
                                                           u, v)),
                     _best_of(9, lambda: transmission_of_arrays(linkage,
                                                                linkage.sweep_arrays(array))),
                     _best_of(9, lambda: (lambda a: (coupler_of_arrays(linkage, a, u, v),
                                                     transmission_of_arrays(linkage, a)))(
                         linkage.sweep_arrays(array)))]
            text += f" {len(angles) / fast:9,.0f}/s " + " ".join(
                f"{t / fast:{w}.2f}x" for t, w in zip(times, (8, 5, 5)))
        print(text, file=out)
    return f"the scalar sweep with the coupler point and mu {min(both):.1f}-{max(both):.1f}x without"


FORCES_ARRAYS_TARGET = 0.5     # forces_arrays' rate over sweep_arrays' (with v and a), at least


def bench_forces(out: TextIO, quick: bool = False, points: int = 3_601,
                 array_points: int = 100_001) -> str:
    """What the forces add to a sweep, scalar and numpy, per kind.

    Scalar: forces() over the sweep alone; numpy: forces_arrays' rate beside sweep_arrays' with
    velocity and acceleration (the target: FORCES_ARRAYS_TARGET of it), each timed in this
    process's CPU time: on a shared machine the wall time of a run that outlasts a time slice
    (forces_arrays, 10-25 ms) counts the other processes' turns too, where a shorter one (the
    sweep, 4-8 ms) often runs between them, and the ratio showed 0.3 where the work was 0.5.

    The torque, every joint's reaction and the shaking at each angle of a sweep with velocity and
    acceleration, each link a rod of 1 kg, at 100 rpm under gravity."""
    if quick:
        points, array_points = 37, 1001
    angles, _ = _bench_angles(points)
    _, array = _bench_angles(array_points)
    bodies, effects = Bodies(Body(1.0), Body(1.0), Body(1.0)), Effects(100.0, gravity=9.80665)
    import time
    print(f"scalar: {points:,} input angles, 0 to 360 degrees, branch 1, velocity and "
          "acceleration; forces() (the sweep, then one linear system a position) over the sweep "
          f"alone, best of 3. numpy: {array_points:,} angles, sweep_arrays (derivatives 2) and "
          "forces_arrays (the sweep, then the forces) alternated, best of 9 by CPU time; one "
          "run, compare the ratios", file=out)

    def cpu_seconds(function: Callable[[], object]) -> float:
        start = time.process_time()
        function()
        return time.process_time() - start
    print(f"{'linkage':12} {'sweep':>12} {'forces':>12} {'ratio':>7}   {'sweep_arrays':>13} "
          f"{'forces_arrays':>14} {'rate ratio':>10}", file=out)
    ratios, slowdowns, rates = {}, [], []
    for kind, dims in BENCH_LINKAGES:
        linkage = Linkage(kind, **dims)
        base = _best_of(3, lambda: linkage.sweep(angles))
        with_forces = _best_of(3, lambda: forces(linkage, angles, 1, bodies, effects))
        text = (f"{kind:12} {len(angles) / base:10,.0f}/s {len(angles) / with_forces:10,.0f}/s "
                f"{with_forces / base:6.1f}x")
        if array is not None:
            sweep_time = forces_time = math.inf
            for _ in range(9):
                sweep_time = min(sweep_time, cpu_seconds(lambda: linkage.sweep_arrays(array)))
                forces_time = min(forces_time, cpu_seconds(lambda: linkage.forces_arrays(
                    array, 1, bodies, effects)))
            ratios[kind] = sweep_time / forces_time
            text += (f"   {len(array) / sweep_time:11,.0f}/s {len(array) / forces_time:12,.0f}/s "
                     f"{ratios[kind]:10.2f}")
        else:
            text += "   numpy not installed"
        print(text, file=out)
        slowdowns.append(with_forces / base)
        rates.append(len(angles) / with_forces)
    if ratios and not quick:
        short = [k for k, r in ratios.items() if r < FORCES_ARRAYS_TARGET]
        print(f"target: forces_arrays at >= {FORCES_ARRAYS_TARGET} of sweep_arrays' rate with "
              "velocity and acceleration: " + (f"NOT MET for {', '.join(short)}" if short
                                                 else "met")
              + f", lowest {min(ratios.values()):.2f}", file=out)
    figure = (f"{min(slowdowns):.0f}-{max(slowdowns):.0f}x the sweep alone: {min(rates):,.0f}-"
              f"{max(rates):,.0f} positions a second")
    if ratios:
        figure += (f"; forces_arrays at {min(ratios.values()):.2f}-{max(ratios.values()):.2f} of "
                   "sweep_arrays' rate")
    return figure


FILES_TARGET = 1_000_000   # points a second of CPU: run --precision double --fast, DAT and CSV


def bench_files(out: TextIO, quick: bool = False) -> str:
    """run --precision double to the DAT files and a CSV, as a process: CPU time, with --fast.

    The CPU time is the process's (user and system, from getrusage); --fast by the README's
    `python3 linkage.py` (which compiles the module every run) and by `python3 -m linkage` (from
    cached bytecode, as the installed `linkage` command runs), and without --fast; alternated."""
    import resource
    import subprocess
    import tempfile
    import time
    points, repeats = (10_001, 1) if quick else (1_000_001, 3)
    step = 360.0 / (points - 1)
    here = os.path.dirname(os.path.abspath(__file__))
    words = ["run", "plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9", "--from", "0",
             "--to", "360", "--step", repr(step), "--branch", "1", "--precision", "double"]
    script, module = [sys.executable, os.path.join(here, "linkage.py")], [sys.executable, "-m",
                                                                          "linkage"]
    forms = {"--fast": script + words + ["--fast"], "-m --fast": module + words + ["--fast"],
             "scalar": script + words}
    env = dict(os.environ, PYTHONPATH=here)
    env.pop("PYTHONDONTWRITEBYTECODE", None)         # as where bytecode is kept, the default
    best: dict[str, tuple[float, float]] = {}
    with tempfile.TemporaryDirectory() as folder:
        subprocess.run([sys.executable, "-c", "import linkage"], env=env, cwd=folder, check=True)
        for _ in range(repeats):
            for form, command in forms.items():
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                start = time.perf_counter()
                subprocess.run(command + ["--dir", folder, "--csv", os.path.join(folder, "o.csv")],
                               check=True, capture_output=True, cwd=folder, env=env)
                wall = time.perf_counter() - start
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
                best[form] = min(best.get(form, (math.inf, math.inf)), (cpu, wall))
        size = sum(os.path.getsize(os.path.join(folder, n)) for n in DatFiles.NAMES + ("o.csv",))
    print(f"python3 linkage.py run plane --a 6 --b 2 --c 7 --d 9 --from 0 --to 360 --step "
          f"{step!r} --branch 1 --precision double --dir D --csv D/o.csv [--fast]: {points:,} "
          f"points, {size / 1e6:,.1f} MB of files; CPU time of the process (its start-up, "
          f"numpy's import and the files' flushing to the disk included), best of {repeats}; "
          "-m --fast: the same by python3 -m linkage (the installed command's way: cached "
          "bytecode, where the script compiles the module every run)", file=out)
    for form, (cpu, wall) in best.items():
        print(f"{form:10} {cpu:7.2f} s CPU {wall:7.2f} s wall {points / cpu:12,.0f} "
              f"points/s of CPU {size / cpu / 1e6:8.1f} MB/s", file=out)
    rate, module_rate = (points / best[form][0] for form in ("--fast", "-m --fast"))
    if not quick:
        print(f"target: --fast >= {FILES_TARGET:,} points/s of CPU: " + ", ".join(
            f"{'met' if r >= FILES_TARGET else 'NOT MET'} by {how}, {r:,.0f}" for how, r in (
                ("python3 linkage.py", rate), ("python3 -m linkage", module_rate))), file=out)
    return (f"--fast {rate / 1e6:.2f} M points a second of CPU ({best['--fast'][0]:.2f} s; by "
            f"python3 -m linkage {module_rate / 1e6:.2f} M, {best['-m --fast'][0]:.2f} s), "
            f"without {best['scalar'][0]:.2f} s: {best['scalar'][0] / best['--fast'][0]:.1f}x; "
            f"{points:,} points")

ACCURACY_POINTS = 100           # random points a kind (the 110-digit reference: ~1 ms each)
ACCURACY_SWEEP = 2001           # the engine's and numpy's time a point: a sweep of this many angles
ACCURACY_RUNGS = ("GW-BASIC single (the port)", "double (the engine)",
                  "numpy (the engine on arrays)", "50 digits (decimal)")


class Rung(NamedTuple):
    """One rung's errors against 110 digits over a set of points, and its time a point."""
    name: str
    kind: str
    errors: list[tuple[float, float, float]]     # output, velocity, acceleration
    failed: int                                  # points it gives no number for, or a wrong one
    seconds: float                               # a point, best of 3


def _accuracy_draw(rng: Any, kind: str) -> dict[str, float]:
    """A linkage of `kind` as tests/test_engine.py draws them: lengths 0.2 to 10, offsets -5 to
    5, spherical arcs 2 to 178 degrees, skew angles within 75 (89 for the skew slider-crank)."""
    length, signed = (lambda: rng.uniform(0.2, 10.0)), (lambda: rng.uniform(-5.0, 5.0))
    if kind == SPHERICAL_FOUR_BAR:
        return {k: rng.uniform(2.0, 178.0) for k in "abcd"}
    if kind == PLANE_SLIDER_CRANK:
        return dict(b=length(), c=length(), e=signed())
    if kind == SKEW_SLIDER_CRANK:
        return dict(a=signed(), b=length(), c=length(), f=signed(), ksi=rng.uniform(-89.0, 89.0))
    dims = dict(a=length(), b=length(), c=length(), d=length())
    return dims | (dict(f=signed(), ksi=rng.uniform(-75.0, 75.0)) if kind == SKEW_FOUR_BAR else {})


def _accuracy_points(kind: str, count: int, seed: int) -> list[tuple[Linkage, float, int, Motion]]:
    """`count` random points of `kind` (a linkage, an input angle, a branch) where the linkage
    assembles clear of a dead centre, each with its 110-digit Motion; every fifth at phi = 180
    (where the listing's t = tan(phi/2) is infinite)."""
    import random
    rng = random.Random(f"{seed}-{kind}")
    out: list[tuple[Linkage, float, int, Motion]] = []
    while len(out) < count:
        link = Linkage(kind, **_accuracy_draw(rng, kind))
        phi = 180.0 if len(out) % 5 == 4 else rng.uniform(0.0, 360.0)
        branch = rng.choice((1, 2))
        reference = link.decimal_motion(phi, branch, finest=True)
        if reference.status == ASSEMBLED:
            out.append((link, phi, branch, reference))
    return out


def _accuracy_error(kind: str, size: float, got: Motion | tuple, want: Motion
                    ) -> tuple[float, float, float]:
    """The errors of (output, velocity, acceleration) against the reference: the output angle's
    in degrees (a slider's position relative to the linkage's size), the derivatives' relative
    to 1 + their size; inf where a number is missing."""
    out, vel, acc = got[1:4]
    if out is None or vel is None or acc is None or want.output is None:
        return (math.inf,) * 3
    d = out - want.output
    if kind in SLIDER_CRANKS:
        d /= size
    else:
        d = (d + 180.0) % 360.0 - 180.0
    assert want.velocity is not None and want.acceleration is not None
    return (abs(d), abs(vel - want.velocity) / (1.0 + abs(want.velocity)),
            abs(acc - want.acceleration) / (1.0 + abs(want.acceleration)))


def _port_motions(points: list[tuple[Linkage, float, int, Motion]]) -> Callable[[], list[Any]]:
    """The port's numbers at the points (lines 250-930 and 1060-1330 in GW-BASIC's single
    precision, each angle typed as `run --from PHI --to PHI` types it): a function that computes
    them, as (phi, output, velocity, acceleration) or None where the listing refuses the linkage,
    gives a soft error or writes its 0, 0, 0 of a position that does not assemble. Velocity and
    acceleration are clipped to +-3 as the listing writes them (K9)."""
    jobs: list[Any] = []
    for link, phi, branch, _ in points:
        key, typed = typed_dimensions(link.kind, link.dims)
        with soft_errors() as errors:
            v, answers = Variables(), iter(typed)
            legal = dimensions(v, int(key),
                               lambda prompt: cast(Single, input_value(next(answers))))
            job = None
            if legal and not errors:
                job = (coefficients(v, int(key)), v.S,
                       degrees_to_radians(cast(Single, input_value(typed_number(phi)))), branch)
        jobs.append(job)

    def compute() -> list[Any]:
        out: list[Any] = []
        for job in jobs:
            if job is None:
                out.append(None)
                continue
            co, s, angle, branch = job
            with soft_errors() as errors:
                lines = sweep_point(co, angle, branch, s)
            values = [float(str(line).split(",")[1]) for line in lines]
            out.append(None if errors or values == [0.0, 0.0, 0.0] else (0.0, *values))
        return out
    return compute


def measure_accuracy(count: int = ACCURACY_POINTS, seed: int = 1) -> list[Rung]:
    """Each rung of ACCURACY_RUNGS on `count` random points of each kind: its errors against 110
    digits (the port's velocity and acceleration only where the reference is within the +-3 it
    clips to) and its time a point."""
    rungs: list[Rung] = []
    for kind in LINKAGE_DIMENSIONS:
        points = _accuracy_points(kind, count, seed)
        size = {id(p[0]): max(abs(v) for k, v in p[0].dims.items() if k != "ksi") for p in points}
        ways: list[tuple[str, Callable[[], list[Any]]]] = [
            (ACCURACY_RUNGS[0], _port_motions(points)),
            (ACCURACY_RUNGS[1], lambda: [link.sweep((phi,), branch)[0]
                                         for link, phi, branch, _ in points])]
        try:
            angles = [angle_array(phi, 0.0, 0, 1) for _, phi, _, _ in points]
            ways.append((ACCURACY_RUNGS[2], lambda: [link.sweep_arrays(a, branch)
                                                     for (link, _, branch, _), a in
                                                     zip(points, angles)]))
        except FastUnavailable:
            pass
        ways.append((ACCURACY_RUNGS[3], lambda: [link.decimal_motion(phi, branch)
                                                 for link, phi, branch, _ in points]))
        sweep = evenly_spaced_angles(0.0, 360.0, 360.0 / (ACCURACY_SWEEP - 1))
        first = points[0][0]
        swept: dict[str, Callable[[], object]] = {
            ACCURACY_RUNGS[1]: lambda: first.sweep(sweep, 1)}     # as a sweep runs them
        if len(ways) == 4:
            array = angle_array(0.0, 360.0 / (ACCURACY_SWEEP - 1), 0, ACCURACY_SWEEP)
            swept[ACCURACY_RUNGS[2]] = lambda: first.sweep_arrays(array, 1)
        for name, compute in ways:
            seconds, answers = _timed(3 if name != ACCURACY_RUNGS[3] else 1, compute)
            seconds /= len(points)
            if name in swept:
                seconds = _best_of(3, swept[name]) / ACCURACY_SWEEP
            errors, failed = [], 0
            for (link, phi, branch, want), got in zip(points, answers):
                if isinstance(got, MotionArrays):                # of one point
                    assert got.velocity is not None and got.acceleration is not None
                    got = (phi, float(got.output[0]), float(got.velocity[0]),
                           float(got.acceleration[0]))
                if got is None:
                    failed += 1
                    continue
                e = _accuracy_error(kind, size[id(link)], got, want)
                if name == ACCURACY_RUNGS[0]:                   # clipped to +-3 (K9)
                    assert want.velocity is not None and want.acceleration is not None
                    e = (e[0], e[1] if abs(want.velocity) < 3.0 else 0.0,
                         e[2] if abs(want.acceleration) < 3.0 else 0.0)
                if math.isinf(e[0]):
                    failed += 1
                    continue
                errors.append(e)
            rungs.append(Rung(name, kind, errors, failed, seconds))
    return rungs


def _typical(values: list[float]) -> float:
    ordered = sorted(values)
    return ordered[len(ordered) // 2] if ordered else math.nan


def bench_accuracy(out: TextIO, quick: bool = False, png: str | None = None) -> str:
    """What accuracy costs in time: each rung's error against 110 digits and its time a point."""
    count = 5 if quick else ACCURACY_POINTS
    rungs = measure_accuracy(count)
    print(f"{count} random points a kind (every fifth at phi = 180), seed 1, each assembled clear "
          "of a dead centre; errors against the same point in 110-digit decimal arithmetic: the "
          "output angle in degrees (a slider's position over the linkage's size), velocity and "
          "acceleration relative to 1 + their size; worst (typical, the median); the time a "
          f"point in this process, best of 3: the engine's and numpy's in a sweep of "
          f"{ACCURACY_SWEEP:,} angles (the first linkage of the kind), the port's and decimal's "
          "one point at a time (as they run). The tests' own ladder, against an mpmath reference "
          "written from the geometry: PYTHONPATH=tests python3 -m support.bench_accuracy", file=out)
    print(f"{'rung':30} {'kind':12} {'output':>17} {'velocity':>9} {'accel.':>9} {'failed':>6} "
          f"{'us a point':>11}", file=out)
    for r in rungs:
        worst = [max((e[i] for e in r.errors), default=math.nan) for i in range(3)]
        typical = _typical([e[0] for e in r.errors])
        print(f"{r.name:30} {r.kind:12} {worst[0]:8.1e} ({typical:6.0e}) {worst[1]:9.1e} "
              f"{worst[2]:9.1e} {r.failed:6} {r.seconds * 1e6:11.1f}", file=out)
    if png:
        _accuracy_png(rungs, png)
        print(f"wrote {png}", file=out)
    return "; ".join(_rung_figure([r for r in rungs if r.name == name])
                     for name in ACCURACY_RUNGS if any(r.name == name for r in rungs))


def _rung_figure(rungs: list[Rung]) -> str:
    """One rung's worst output error over the kinds and its time a point, as a range."""
    worst = [max((e[0] for e in r.errors), default=math.nan) for r in rungs]
    us = [r.seconds * 1e6 for r in rungs]
    return (f"{rungs[0].name} {min(worst):.1e} to {max(worst):.1e} ({min(us):.3g}-{max(us):.3g} "
            "us a point)")


def _accuracy_png(rungs: list[Rung], path: str) -> None:
    """Accuracy against cost, log-log: one marker a rung and kind (the worst output error)."""
    MplFigure, FigureCanvasAgg = matplotlib_canvas()
    mpl = MplFigure(figsize=(7.2, 4.8), dpi=100)
    FigureCanvasAgg(mpl)
    ax = mpl.add_subplot()
    markers = dict(zip(LINKAGE_DIMENSIONS, "os^Dv"))
    colours = dict(zip(ACCURACY_RUNGS, ("#b2182b", "#2166ac", "#1b7837", "#762a83")))
    for r in rungs:
        worst = max((e[0] for e in r.errors), default=math.nan)
        if math.isfinite(worst):
            ax.loglog(r.seconds * 1e6, max(worst, 1e-17), markers[r.kind], color=colours[r.name],
                      label=f"{r.name}" if r.kind == PLANE_FOUR_BAR else None)
    ax.set_xlabel("time a point (us, this process)")
    ax.set_ylabel("worst output error (deg; slider: of the size)")
    ax.set_title("What accuracy costs: markers o plane, s spherical, ^ skew, D slider, "
                 "v skew-slider (an error of 0 drawn at 1e-17)", fontsize=8)
    ax.grid(True, which="both", linewidth=0.4, alpha=0.5)
    ax.legend(fontsize=7, loc="best")
    import io
    image = io.BytesIO()
    mpl.savefig(image, format="png")
    with written_whole(path) as f:
        f.write(image.getvalue())


EXPLORE_TARGET = 0.050     # seconds from a key to the next frame (issue 32)


def bench_explore(out: TextIO, quick: bool = False) -> str:
    """The explorer's latency: a key to its frame, then the view made whole.

    A key's frame is explore_key then explore_screen at 80 x 24, each key changing a dimension
    or the branch or the coupler point (so that each is a linkage not seen yet: a glance), then
    the view made whole when the keys stop (ExploreViews.settled: analyse and the motion
    drawn); for each kind's example, and each scene with [dynamics] (data/scenes/forces-*:
    the torque now at each key, its peak in the view made whole)."""
    import time
    keys = (["Right"] if quick else ["Right", "Left", "S-Right", "S-Left", "Tab"] * 4) + ["b", "c"]
    print(f"the explorer, {len(keys)} keys a kind (a dimension changed, the next one selected, "
          "the branch, the coupler), the 80 x 24 frame drawn after each; milliseconds; target: "
          f"a key to its frame under {1e3 * EXPLORE_TARGET:.0f} ms", file=out)
    print(f"{'linkage':26} {'key median':>11} {'key worst':>10} {'whole median':>13} "
          f"{'whole worst':>12}", file=out)
    worst_keys, worst_wholes = [], []
    scenes = [load_scene(scene_path(name)) for name in known_scenes()
              if name.startswith("forces-") and "arrows" not in name]
    starts = [(kind, explorer_of(kind)) for kind in LINKAGE_DIMENSIONS] + [
        (os.path.basename(s.path).removesuffix(".toml"),
         explorer_of(s.kind, s.dimensions, dynamics=s.dynamics)) for s in scenes
        if s.dynamics is not None and isinstance(s.branches[0], int)]
    for name, state in starts:
        views = ExploreViews(quick=True)
        views(state)
        key_times, whole_times = [], []
        for key in keys:
            start = time.perf_counter()
            state = explore_key(state, key, views)
            explore_screen(state, views(state), 80, 24)
            key_times.append(time.perf_counter() - start)
            start = time.perf_counter()
            state = views.settled(state)
            explore_screen(state, views(state), 80, 24)
            whole_times.append(time.perf_counter() - start)
        key_times.sort()
        whole_times.sort()
        print(f"{name:26} {1e3 * key_times[len(keys) // 2]:11.1f} {1e3 * key_times[-1]:10.1f} "
              f"{1e3 * whole_times[len(keys) // 2]:13.1f} {1e3 * whole_times[-1]:12.1f}"
              + ("" if key_times[-1] < EXPLORE_TARGET else "   over the target"), file=out)
        worst_keys.append(1e3 * key_times[-1])
        worst_wholes.append(1e3 * whole_times[-1])
    return (f"a key's frame worst {min(worst_keys):.0f}-{max(worst_keys):.0f} ms, target "
            f"{1e3 * EXPLORE_TARGET:.0f} (the whole view {min(worst_wholes):.0f}-"
            f"{max(worst_wholes):.0f} ms)")


SIMULATION_TOLERANCES = (1e-6, 1e-8, 1e-10, 1e-12)


def bench_simulate(out: TextIO, quick: bool = False) -> str:
    """simulate's cost in CPU seconds: steps per CPU second by tolerance, and a motor's run-up.

    Times are this process's CPU time (time.process_time), the run-up's against the seconds
    simulated.

    The double-rocker released from rest at 320 degrees swings across its input's dead centres
    (the energy's error beside each tolerance); the crank-rocker runs up from rest."""
    seconds, run_up = (2.0, 5.0) if quick else (20.0, 600.0)
    tolerances = SIMULATION_TOLERANCES[1:3] if quick else SIMULATION_TOLERANCES
    rods = Bodies(Body(1.0), Body(0.5), Body(1.0))
    rocker = Linkage(PLANE_FOUR_BAR, a=3.0, b=2.5, c=1.0, d=2.0)
    print(f"the double-rocker a=3 b=2.5 c=1 d=2, 1/0.5/1 kg rods, g = 9.81, released at 320 "
          f"degrees on branch 1, {seconds:g} s simulated (about {seconds / 1.9:.0f} swings, "
          "each across two dead centres); times are this process's CPU seconds", file=out)
    print(f"{'tolerance':>10} {'steps':>8} {'rejected':>9} {'evaluations':>12} {'CPU s':>8} "
          f"{'steps/CPU s':>12} {'energy error / E':>17}", file=out)
    rates, drifts = [], []
    for tolerance in tolerances:
        cpu, sim = _cpu_timed(lambda: simulate(
            rocker, rods, Effects(gravity=9.81), initial=(320.0, 0.0), time=seconds,
            step=seconds, tolerance=tolerance, branch=1))
        drift = sim.energy_error / abs(sim.rows[0].energy)
        print(f"{tolerance:10.0e} {sim.steps:8,} {sim.rejected:9,} {sim.evaluations:12,} "
              f"{cpu:8.2f} {sim.steps / cpu:12,.0f} {drift:17.2e}", file=out)
        rates.append(sim.steps / cpu)
        drifts.append(drift)
    crank_rocker = Linkage(PLANE_FOUR_BAR, a=4.0, b=1.0, c=4.0, d=3.0)
    motor = Driver(stall_torque=40.0, free_speed_rpm=120.0)
    cpu, sim = _cpu_timed(lambda: simulate(
        crank_rocker, Bodies(Body(2.0), Body(3.0), Body(2.5)), Effects(gravity=9.81),
        driver=motor, initial=(0.0, 0.0), time=run_up, step=run_up / 10.0, tolerance=1e-8))
    last = sim.rows[-1]
    balance = abs(last.energy - sim.rows[0].energy - last.work) / last.work
    print(f"a motor's run-up (40 N m stall, 120 rpm free) of the crank-rocker a=4 b=1 c=4 d=3 "
          f"with 2/3/2.5 kg rods, {run_up:g} s simulated at tolerance 1e-8: "
          f"{last.phi / 360.0:,.0f} turns, {sim.steps:,} steps in {cpu:.2f} CPU seconds of this "
          f"process ({sim.steps / cpu:,.0f} steps per CPU second; {run_up / cpu:.0f} simulated "
          f"seconds per CPU second), |E - E(0) - W| / W = {balance:.1e}", file=out)
    return (f"{min(rates):,.0f}-{max(rates):,.0f} steps a second of CPU, the energy's error "
            f"{max(drifts):.1e} to {min(drifts):.1e} of E; the run-up ({run_up:g} s) in "
            f"{cpu:.0f} s CPU")


def _cpu_timed(function: Callable[[], Simulation]) -> tuple[float, Simulation]:
    """The process's CPU time of one call, and its result."""
    import time
    start = time.process_time()
    result = function()
    return time.process_time() - start, result


BENCHMARKS = {"mbf": bench_mbf, "port": bench_port, "engine": bench_engine, "scene": bench_scene,
              "startup": bench_startup, "coupler": bench_coupler, "forces": bench_forces,
              "files": bench_files, "accuracy": bench_accuracy, "simulate": bench_simulate,
              "explore": bench_explore}


def machine() -> str:
    """This machine, as the README quotes it: CPU model (/proc/cpuinfo), the CPUs this process may
    use (what nproc prints), Python's version."""
    import platform
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as cpuinfo:
            model = next((line.split(":", 1)[1].strip() for line in cpuinfo
                          if line.startswith("model name")), model)
    except OSError:
        pass
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    load = f", load average {os.getloadavg()[0]:.2f}" if hasattr(os, "getloadavg") else ""
    return (f"{model} ({platform.machine()}), nproc {usable}, "
            f"{platform.python_implementation()} {platform.python_version()}{load}")


# ---- 28. The speed table: every bench run, the README's figures beside the load ------------------
#
# Holds: `bench all` (run_benchmarks): every bench of BENCHMARKS run, each one's log, then the
# README's speed table (data/BENCHMARKS.md, "Summary") from their figures, a row of SPEED_TABLE
# each, with the load average before and after its bench; the rows the tests' scripts measure
# (a C loop, pylinkage, mpmath) name their command.
#
# Uses: section 27.
# Offers: PEERS_COMMAND, ACCURACY_COMMAND, SPEED_TABLE, run_benchmarks.


PEERS_COMMAND = "PYTHONPATH=tests python3 -m support.bench_peers"          # from the root
ACCURACY_COMMAND = "PYTHONPATH=tests python3 -m support.bench_accuracy"    # likewise
# The README's speed table (data/BENCHMARKS.md, "Summary"), a row a figure: what is measured, the
# bench of BENCHMARKS that measures it as the README says (None: a script of the tests, which
# measures the program beside a C loop, pylinkage or mpmath: the program compiles no C and
# imports no peer), and the command that makes the figure.
SPEED_TABLE = (
    ("the faithful port against PC-BASIC 2.0.8, both as programs, 3,601 points, same bytes",
     "port", "python3 linkage.py bench port"),
    ("the numpy path against the scalar engine, 100,001 points, velocity and acceleration",
     "engine", "python3 linkage.py bench engine"),
    ("the numpy path against a C loop of its own formulas (`cc -O2`, CPython's correctly rounded "
     "hypot copied), 1e4 to 1e7 points; against a plain C loop of the same half-tangent formula "
     "(`cc -O2`, libm's hypot), the angle alone and with velocity and acceleration", None,
     PEERS_COMMAND),
    ("against pylinkage 1.3 with numba (without), the plane four-bar: positions, and with "
     "velocity and acceleration", None, PEERS_COMMAND),
    ("1e6 points to the DAT files and a CSV, `python3 linkage.py run --precision double --fast` "
     "as a process (the same by `python3 -m linkage`; without `--fast`)", "files",
     "python3 linkage.py bench files"),
    ("the installed `linkage` command's start-up (a one-point session) against "
     "`python3 -c pass`", "startup", "python3 linkage.py bench startup"),
    ("what accuracy costs: the worst output error against 110 digits on 100 random points a kind "
     "(every fifth at phi = 180), and the time a point", "accuracy",
     "python3 linkage.py bench accuracy"),
    ("`explore`: a key to its frame at 80 x 24, each kind (the whole view, analysed, when the "
     "keys stop)", "explore", "python3 linkage.py bench explore"),
    ("the forces (torque, joints, shaking: one linear system a position) over the sweep alone, "
     "3,601 points", "forces", "python3 linkage.py bench forces"),
    ("the engine's output angle against 50-digit roots (mpmath), the hard catalogue and random "
     "points", None, f"{ACCURACY_COMMAND} [--screen 20000 3]"),
    ("the motion in time (`simulate`): 20 s of a double-rocker across its dead centres, "
     "tolerance 1e-6 to 1e-12; a motor's 600 s run-up", "simulate",
     "python3 linkage.py bench simulate"),
)


def run_benchmarks(out: TextIO, names: Sequence[str] = (), quick: bool = False,
                   png: str | None = None) -> None:
    """The benches `names` (all where none), each's log under `== NAME: ...`; then the rows of
    SPEED_TABLE they measure, each with its figure and the load average (1 minute) before and
    after it ran; with every bench, the whole table (the rows of the tests' scripts say so)."""
    import time
    every = not names
    figures: dict[str, tuple[str, str]] = {}
    for name in names or list(BENCHMARKS):
        print(f"\n== {name}: {(BENCHMARKS[name].__doc__ or '').splitlines()[0]}", file=out,
              flush=True)
        before = _load_average()
        figure = (bench_accuracy(out, quick=quick, png=png) if name == "accuracy"
                  else BENCHMARKS[name](out, quick=quick))
        figures[name] = (figure, f"{before}-{_load_average()}")
    if not any(bench in figures for _, bench, _ in SPEED_TABLE):
        return
    print(f"\n== the README's speed table: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"{machine()}" + ("; --quick: its numbers mean nothing" if quick else ""), file=out)
    print("| what | figure | load average | command |\n|---|---|---|---|", file=out)
    for what, bench, command in SPEED_TABLE:
        if bench in figures:
            figure, load = figures[bench]
            print(f"| {what} | {figure} | {load} | `{command}` |", file=out)
        elif bench is None and every:
            print(f"| {what} | not measured by the program (it compiles no C, imports no peer "
                  f"and no mpmath): run the command | | `{command}` |", file=out)


def _load_average() -> str:
    return f"{os.getloadavg()[0]:.1f}" if hasattr(os, "getloadavg") else "?"


# ---- 29. Commands run, analyse and forces: their typed values and handlers -----------------------
#
# Holds: the parsers of what is typed (numbers in each precision, kinds); what every command is
# given (its one typed value, made of the parsed options once its "goes with" rules hold: Rule,
# broken_rule) and the refusals (UsageError, CommandError); the output checks and folders every
# command shares; then run, analyse and forces, each its typed value, the function that makes it
# (run_options, ...) and its handler (run_command, ...), and the drawing every command shares.
#
# Uses: sections 1, 2, 4, 5, 6, 7, 8, 9, 10, 13, 15, 16, 17, 18, 22, 23, 24 and 26.
# Offers: LONGEST_NUMBER, decimal_number, basic_answer, kind_named, UsageError, CommandError, Rule,
#   goes_with, broken_rule, Pictures, pictures_typed, unwritten, reported, printed,
#   dimensions_typed, typed_value, check_outputs, MADE_FOLDERS, output_folder, unmake_folders,
#   RunOptions, run_options, run_command, CSV_CLIPPED, AnalyseOptions, analyse_options,
#   analyse_command, ForcesOptions, forces_options, forces_command, FORCES_OPTIONS, figure_command,
#   drawing_command.


# -- what is typed: one parser a kind of value, shared by every command -------------------------

LONGEST_NUMBER = 100        # characters of an ordinary decimal (a typed answer: INPUT_LINE)


def decimal_number(text: str, what: str, basic_hint: bool = True) -> float:
    """An ordinary decimal number (2, -0.5, 1e-3) as a finite double, or ValueError whose
    message names `what` (e.g. "--b") and says why (and, with basic_hint, that GW-BASIC's forms
    are for --precision basic)."""
    if not isinstance(text, str) or not text.strip():        # argparse gives [] for --b=--
        raise ValueError(f"{what}: no number given")
    typed = text.strip()
    if len(typed) > LONGEST_NUMBER:
        raise ValueError(f"{what}: a number of {len(typed):,} characters is too long "
                         f"(at most {LONGEST_NUMBER})")
    if not DECIMAL.fullmatch(typed):
        hint = (" (GW-BASIC's forms such as 1D3, 2#, &H10 are for --precision basic)"
                if basic_hint and input_value(typed) is not None else "")
        raise ValueError(f"{what}: {text!r} is not a number{hint}")
    value = float(typed)
    if not math.isfinite(value):
        raise ValueError(f"{what}: {text} is out of range")
    return value


def basic_answer(text: str, what: str) -> str:
    """An answer for the original's INPUT prompt, as INPUT takes it (GW-BASIC's syntax: 1D3,
    .5, &H10, an empty answer is 0), or ValueError naming `what`."""
    if not isinstance(text, str):                             # argparse gives [] for --b=--
        raise ValueError(f"{what}: no number given")
    if len(text) > INPUT_LINE:
        raise ValueError(f"{what}: an answer of {len(text):,} characters is longer than the "
                         f"{INPUT_LINE} of GW-BASIC's line")
    if any(c in text for c in "\r\n\x1a") or not text.isprintable():
        raise ValueError(f"{what}: {text!r} holds a control character")
    with soft_errors():                         # "Overflow": the session says it again
        if input_value(text) is None:
            raise ValueError(f"{what}: {text!r} is not a number the original's INPUT takes")
    return text


def kind_named(text: str) -> str | None:
    """The kind `text` names (one of KIND_MENU, or its menu key 1-5), or None."""
    name = {key: name for name, (key, _) in KIND_MENU.items()}.get(text, text)
    return name if name in KIND_MENU else None


# -- what a command is given: one typed value, validated once ------------------------------------
#
# The command line parsed (argparse, in the last section) is a dict of what each option holds;
# each command's rules ("goes with" rows of its COMMANDS entry: broken_rule) are checked on it,
# then its typed function (run_options, ...) makes of it the one value its handler takes, every
# number converted and every refusal said (UsageError: exit 2, with the command's usage;
# CommandError: exit 1) before the handler does any work. The values are NamedTuples: no field
# is rebound on the way.

class UsageError(Exception):
    """A command line the command cannot take: said as argparse says its own (the command's
    usage, then the message), exit status 2."""


class CommandError(Exception):
    """A command given what it cannot work on (a scene without what it needs, a linkage that
    cannot be built): the message, exit status 1."""


class Rule(NamedTuple):
    """A "goes with" row of a command: where option `given` is typed (with one of the values
    after its flag, if the row names any: "--branch follow", "--fast"), one of `needs` must hold
    ("--precision double": the option holds that value, its default counting; "--csv": the
    option is typed); else the command line is refused, "GIVEN goes with NEEDS (why)"."""

    given: str
    needs: tuple[str, ...]
    why: str = ""


def goes_with(given: str, *needs: str, why: str = "") -> Rule:
    return Rule(given, needs, why)


def _rule_part(text: str) -> tuple[str, tuple[str, ...]]:
    """A side of a Rule: its flag, and the values named after it ("--branch 1 or 2")."""
    flag, _, values = text.partition(" ")
    return flag, tuple(values.split(" or ")) if values else ()


def broken_rule(rules: Iterable[Rule], values: dict[str, Any], typed: set[str]) -> str | None:
    """The message of the first of `rules` the command line breaks, or None: `values` {flag:
    what the option holds, its default if not typed}, `typed` the flags typed (holding other
    than their default)."""
    def holds(text: str, given: bool) -> bool:
        flag, named = _rule_part(text)
        if named:
            return str(values.get(flag)) in named and (flag in typed or not given)
        return flag in typed
    for rule in rules:
        if holds(rule.given, True) and not any(holds(n, False) for n in rule.needs):
            needs = (", ".join(rule.needs[:-1]) + " or " if len(rule.needs) > 1 else "") \
                + rule.needs[-1]
            return f"{rule.given} goes with {needs}" + (f" ({rule.why})" if rule.why else "")
    return None


class Pictures(NamedTuple):
    """Where a command's pictures go: the files (None: not written), the terminal's view or text
    plot (text), the still frames of a piped view, the PNG's scale."""

    svg: str | None = None
    png: str | None = None
    dxf: str | None = None
    text: bool = False
    frames: int | None = None
    dpi: float | None = None
    size: tuple[int, int] | None = None


def pictures_typed(given: dict[str, Any]) -> Pictures:
    """The Pictures of a command line (its options of them that the command has)."""
    return Pictures(given.get("svg"), given.get("png"), given.get("dxf"),
                    bool(given.get("text")), given.get("frames"), given.get("dpi"),
                    given.get("size"))


# -- the sub-commands: each takes its typed value and gives the exit status ------------------------

def unwritten(e: OSError) -> str:
    """The message of a write that failed: the file it names, or else standard output (the one
    output the program writes without naming it)."""
    return f"{e.filename or 'standard output'}: {e.strerror}"


def reported(work: Callable[[], int | None]) -> int:
    """work()'s exit status (0 for None), or, where it fails, a message on standard error and
    status 1 (130 for Ctrl-C)."""
    try:
        return work() or 0
    except (SceneError, PlotUnavailable) as e:
        return said(e, 1)
    except OSError as e:
        if reader_gone(e):
            raise                               # main's to end quietly (141)
        return said(unwritten(e), 1)
    except KeyboardInterrupt as e:
        return said("interrupted", interrupted_status(e))


def printed(text: str) -> None:
    """text on standard output, flushed: a command says what it wrote only after this, so that a
    reader who leaves (`--csv - | head -c 10`) hears nothing said of it (main: quiet, 141)."""
    if sys.stdout is not None:
        sys.stdout.write(text)
        sys.stdout.flush()


def _check_dimensions(kind: str, given: dict[str, Any]) -> None:
    """Refuse (UsageError) a command line that misses one of the kind's dimensions or gives one
    it has no use for; `given`: the dimension options typed, by letter."""
    needed = KIND_MENU[kind][1]
    missing = [f"--{n}" for n in needed if n not in given]
    extra = [f"--{n}" for n in sorted(set(given) - set(needed))]
    if missing or extra:
        what = ("missing " + " ".join(missing)) if missing else ("no use for " + " ".join(extra))
        raise UsageError(f"{kind} needs {' '.join('--' + n for n in needed)}: {what}")


def dimensions_typed(given: dict[str, Any]) -> dict[str, str]:
    """The dimension options of a command line (--a ... --ksi) typed, by letter, as typed."""
    return {n: given[n] for n in DIMENSION_NAMES if given.get(n) is not None}


def _coupler_typed(texts: Sequence[str] | None) -> tuple[float, ...]:
    """--coupler's U (and V) as numbers: () where not given."""
    if texts is None:
        return ()
    if not 1 <= len(texts) <= 2:
        raise UsageError("--coupler takes U, or U and V")
    return tuple(typed_value(decimal_number, text, "--coupler") for text in texts)


def typed_value(convert: Callable[[str, str], Any], text: str, what: str) -> Any:
    """convert(text, what), its ValueError a UsageError (the command line's to refuse)."""
    try:
        return convert(text, what)
    except ValueError as e:
        raise UsageError(str(e)) from None


def check_outputs(files: dict[str, str | None], folder: str | None = None,
                   names: Iterable[str] = ()) -> None:
    """Refuse (UsageError), before anything is written, a command whose outputs name one file
    twice: `files` {option: path} given, and `names` the files it writes in `folder` (one would
    overwrite the other, exit 0: `--csv cf/ANG.DAT` with `--dir cf`)."""
    seen: dict[str, str] = {}             # a real path: the option (or --dir's file) naming it
    if folder is not None:
        seen.update((os.path.realpath(os.path.join(folder, n)), f"--dir's {os.path.normpath(n)}")
                    for n in names)
    for option, path in files.items():
        if not path or path == "-":
            continue
        real = os.path.realpath(path)
        if real in seen:
            raise UsageError(f"{option} {path!r} is {seen[real]}: the same file twice")
        seen[real] = option


MADE_FOLDERS: list[str] = []     # the folders this command made (output_folder), deepest first


def output_folder(option: str, path: str) -> None:
    """The one rule of every command's output folder (run's and scene's --dir, design's --dat):
    made if missing, with its parents, before any work; refused (UsageError, exit status 2)
    where it cannot be, e.g. a file in the way. Those it makes are in MADE_FOLDERS: a command that
    fails leaves none of them behind (unmake_folders)."""
    missing, head = [], os.path.abspath(path)
    while not os.path.lexists(head) and os.path.dirname(head) != head:
        missing.append(head)
        head = os.path.dirname(head)
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        MADE_FOLDERS.extend(m for m in missing if os.path.isdir(m))
        raise UsageError(f"{option} {path!r}: cannot make the folder: {e.strerror}") from None
    MADE_FOLDERS.extend(missing)


def unmake_folders() -> None:
    """Remove the folders output_folder made for a command that failed, those still empty,
    deepest first (one that holds a file, put there by anyone, stays)."""
    while MADE_FOLDERS:
        with contextlib.suppress(OSError):
            os.rmdir(MADE_FOLDERS.pop(0))


class RunOptions(NamedTuple):
    """run's command line, validated: the kind; its dimensions and the sweep (from, to, step) by
    name, as numbers (double precision) or as the answers the menu takes (basic: basic_answer's
    text); the branch (1, 2 or follow, with start_branch); where the files go; the options."""

    kind: str
    answers: dict[str, Any]
    branch: str
    start_branch: int
    folder: str
    precision: str
    csv: str | None
    coupler: tuple[float, ...]
    clip: bool
    fast: bool


def run_options(given: dict[str, Any]) -> RunOptions:
    """run's typed value (see RunOptions), or UsageError."""
    kind = given["kind"]
    dims = dimensions_typed(given)
    if given["old_skew"] is not None:           # the spelling before 0.2.0
        say("--skew is now --ksi (the skew angle's name in the paper, the API and the scenes)")
        dims.setdefault("ksi", given["old_skew"])
    _check_dimensions(kind, dims)
    number = decimal_number if given["precision"] == "double" else basic_answer
    texts = {**{n: dims[n] for n in KIND_MENU[kind][1]},
             "from": given["start"], "to": given["stop"], "step": given["step"]}
    answers = {name: typed_value(number, text, f"--{name}") for name, text in texts.items()}
    check_outputs({"--csv": given["csv"]}, given["dir"], DatFiles.NAMES)
    return RunOptions(kind, answers, given["branch"], int(given["start_branch"] or 1),
                      given["dir"], given["precision"], given["csv"],
                      _coupler_typed(given["coupler"]), given["clip"], given["fast"])


def run_command(args: RunOptions) -> int:
    """`python3 linkage.py run KIND ...`: the menu program given these answers."""
    key = KIND_MENU[args.kind][0]
    output_folder("--dir", args.folder)
    if args.precision == "double":
        return _run_double(args)
    answers = list(args.answers.values())
    screen = Screen(lambda s: None, terminal=False,
                    soft_errors=lambda s: sys.stderr.write(s.replace("\r\n", "\n")))
    try:
        if not args.csv:
            points = answered_session(screen, key, answers, args.branch, args.folder)
        else:                                   # the DAT files and the CSV as one set
            with staging_folder(args.folder) as where, WrittenSet() as outputs:
                points = answered_session(screen, key, answers, args.branch, where)
                for name in DatFiles.NAMES:
                    outputs.adopt(os.path.join(where, name), os.path.join(args.folder, name))
                rows = _basic_csv(args, args.csv, answers, where, outputs)
    except ProgramStop as stop:
        return said(stop, 1)
    except KeyboardInterrupt as e:
        return said("interrupted; the DAT files there are as they were", interrupted_status(e))
    except OSError as e:
        if reader_gone(e):
            raise                               # --csv -: main's to end quietly (141)
        return said(f"{unwritten(e)}; the DAT files there are as they were", 1)
    screen.show_soft_errors()
    say(f"wrote {_dat_names(3)} in {args.folder} ({points:,} point{'s' * (points != 1)})")
    if args.csv:
        say(f"wrote {args.csv} ({rows:,} rows)")
    return 0


CSV_CLIPPED = "clipped"     # run --csv in basic precision: VEL or ACC written as +-3 (ERRATA K9)


def _basic_csv(args: RunOptions, path: str, answers: list[str], where: str,
               outputs: WrittenSet) -> int:
    """run --csv, basic precision: the rows of the DAT files just written in `where`, as the file
    `path` of the set `outputs`; the rows written. The original's numbers (zeros where it finds no
    position, VEL and ACC clipped to +-3), each with the accurate engine's status of that
    position, so that a written zero that is no position can be told apart; an assembled row
    whose VEL or ACC the original wrote as +-3, its clip (ERRATA K9), is `clipped`."""
    # every answer passed basic_answer: input_value gives a Single, never None
    dims = {n: input_value(a).v  # type: ignore[union-attr]
            for n, a in zip(KIND_MENU[args.kind][1], answers)}
    ang, vel, acc = (read_dat(os.path.join(where, n)) for n in DatFiles.NAMES)
    try:
        statuses = [m.status for m in Linkage(args.kind, **dims).sweep(
            [phi for phi, _ in ang], int(args.branch), derivatives=0)]
    except ValueError:                          # dimensions the engine refuses (a 0 link)
        statuses = ["unknown"] * len(ang)
    rows = ((phi, psi, v, a, CSV_CLIPPED if status == ASSEMBLED and 3.0 in (abs(v), abs(a))
             else status) for (phi, psi), (_, v), (_, a), status in zip(ang, vel, acc, statuses))
    return write_csv(path, rows, outputs=outputs)


def _run_double(args: RunOptions) -> int:
    """`run ... --precision double`: the accurate engine's numbers in the same three files,
    shortest round-trip text, unclipped unless --clip; positions that do not exist are left out
    (the original writes zeros there, ERRATA K8), and so are those after a followed motion ended
    (--branch follow); the message counts them. --fast: the same numbers by the vectorised path
    (Linkage.sweep_arrays, numpy)."""
    dims = {n: args.answers[n] for n in KIND_MENU[args.kind][1]}
    start, stop, step = args.answers["from"], args.answers["to"], args.answers["step"]
    try:
        linkage = Linkage(args.kind, **dims)
        count = angle_count(start, stop, step)
        if args.fast:
            numpy_module()                            # fail before any work
        coupler = check_coupler_point(linkage, *args.coupler) if args.coupler else None
    except (ValueError, FastUnavailable) as e:
        return said(e, 1)
    # in blocks, to keep a long sweep out of memory; a followed motion in one, as it goes on
    # from each position to the next
    block = count if args.branch == FOLLOW else 65536 if args.fast else 4096
    if not count:
        return said(f"the sweep from {start:g} to {stop:g} by {step:g} has no point", 1)
    if count > 10**8:
        return said(f"{count:,} points is more than 100 million: choose a larger step", 1)
    assembled, points = 0, None

    def extra_columns(swept, arrays, trig=None):
        """The CSV's columns after the Motion's: mu, and the coupler point's if asked; for the
        vectorised path as arrays (trig: the sweep's, see motion_arrays_of), else a tuple a
        row."""
        if arrays is not None:
            point = coupler_of_arrays(linkage, arrays, *coupler)[1:4] if coupler else ()
            return (transmission_of_arrays(linkage, arrays, trig),) + tuple(
                a[:, axis] for a in point if a is not None for axis in range(3))   # all asked
        mus = transmission_of(linkage, swept)
        if not coupler:
            return [(mu,) for mu in mus]
        return [(mu, *(v for w in (c.position, c.velocity, c.acceleration)
                       for v in (w or (None,) * 3)))
                for mu, c in zip(mus, coupler_of(linkage, swept, *coupler))]

    def motions(table: Any) -> Iterator[Any]:
        """The sweep in blocks: SweepColumns by the vectorised path, else rows (a Motion, and
        with a CSV its further columns)."""
        nonlocal assembled
        if table:
            table.write(csv_line(CSV_HEADER + TRANSMISSION_COLUMN
                                 + (COUPLER_COLUMNS if coupler else ())).encode("ascii"))
        with Progress(count) as progress:
            for first in range(0, count, block):
                last = min(first + block, count)
                if args.fast:                  # start + i * step, as below, in numpy
                    trig: dict[str, Any] = {}    # the sweep's cosines of phi, for mu
                    arrays: MotionArrays = motion_arrays_of(
                        linkage, angle_array(start, step, first, last), int(args.branch), 2,
                        trig if table else None)
                    assembled += assembled_count(arrays)
                    assert arrays.velocity is not None and arrays.acceleration is not None
                    yield SweepColumns(arrays.phi, arrays.output, arrays.velocity,
                                       arrays.acceleration, arrays.status,
                                       extra_columns(None, arrays, trig) if table else ())
                else:
                    angles = [start + i * step for i in range(first, last)]
                    swept = (linkage.sweep(angles, FOLLOW, start=args.start_branch)
                             if args.branch == FOLLOW else linkage.sweep(angles, int(args.branch)))
                    assembled += sum(m.output is not None for m in swept)
                    yield from (map(tuple.__add__, swept, extra_columns(swept, None)) if table
                                else swept)
                progress(last - first)
        if not assembled:
            raise ProgramStop(f"Illegal linkage (impossible to assemble): it assembles at none "
                              f"of the {count:,} input angles")
    try:                            # the CSV file, if asked, is on the disk before the DATs are
        #                             renamed into place, and renamed after them
        with written_whole(args.csv) if args.csv else contextlib.nullcontext() as table:
            points = write_dat_files(motions(table), args.folder, clip=args.clip,
                                     before_rename=getattr(table, "finish", None), csv=table)
    except ProgramStop as stop:
        return said(stop, 1)
    except OSError as e:
        if reader_gone(e):
            raise                               # --csv -: main's to end quietly (141)
        return said(f"cannot write {e.filename or args.csv}: {e.strerror}"
                     + ("; the DAT files are written" if points is not None
                        else "; the DAT files there are as they were"), 1)
    except KeyboardInterrupt as e:
        return said("interrupted; the DAT files there are as they were", interrupted_status(e))
    left_out = (f"; {points - assembled:,} without a position, left out"
                if points > assembled else "")
    say(f"wrote {_dat_names(3)} in {args.folder} ({points:,} point{'s' * (points != 1)}"
         f"{left_out})")
    if args.csv:
        say(f"wrote {args.csv} ({points:,} rows)")
    return 0


class AnalyseOptions(NamedTuple):
    """analyse's command line, validated: the linkage, its branch (1, 2 or follow, from
    start_branch), the coupler point to trace ((U, V) checked, or None) and the pictures."""

    kind: str
    dims: dict[str, float]
    branch: int | str
    start_branch: int | None
    coupler: tuple[float, float] | None
    pictures: Pictures


def analyse_options(given: dict[str, Any]) -> AnalyseOptions:
    """analyse's typed value (see AnalyseOptions), or UsageError."""
    kind, typed = given["kind"], dimensions_typed(given)
    _check_dimensions(kind, typed)
    dims = {n: typed_value(decimal_number, text, f"--{n}") for n, text in typed.items()}
    pictures = pictures_typed(given)
    check_outputs({"--svg": pictures.svg, "--png": pictures.png, "--dxf": pictures.dxf})
    coupler = None
    if given["coupler"] is not None:
        u_v = _coupler_typed(given["coupler"])
        try:
            coupler = check_coupler_point(Linkage(kind, **dims), *u_v)
        except ValueError as e:
            raise UsageError(str(e)) from None
    branch = given["branch"]
    return AnalyseOptions(kind, dims, branch if branch == FOLLOW else int(branch),
                          None if given["start_branch"] is None else int(given["start_branch"]),
                          coupler, pictures)


def analyse_command(args: AnalyseOptions) -> int:
    """`python3 linkage.py analyse KIND ...`: the linkage's class and range of motion, one
    `name = value` a line (analysis_lines)."""
    try:
        analysis = analyse(Linkage(args.kind, **args.dims), args.branch, args.start_branch)
    except ValueError as e:
        return said(f"Illegal linkage (impossible to assemble): {e}"
                    if "assembles at no" in str(e) else e, 1)
    sys.stdout.write("".join(line + "\n" for line in analysis_lines(analysis)))
    sys.stdout.flush()
    if not (args.pictures.svg or args.pictures.png or args.pictures.dxf):
        return 0
    return drawing_command(args.pictures, lambda: analysis_drawing(analysis, args.coupler))


class ForcesOptions(NamedTuple):
    """forces' command line, validated: the scene (a file's, or one made of a KIND's options),
    the branches computed, the speed the forces are at (rpm) and the speed fluctuation Cs."""

    scene: Scene
    branches: tuple[int | str, ...]
    speed: float
    fluctuation: float


def forces_options(given: dict[str, Any]) -> ForcesOptions:
    """forces' typed value (see ForcesOptions): UsageError for a command line it cannot take,
    CommandError (or SceneError) for a scene or linkage it cannot compute."""
    if not 0.0 < given["fluctuation"] < 2.0:
        raise UsageError(f"--fluctuation {given['fluctuation']:g}: expected a speed fluctuation "
                         "Cs between 0 and 2 ((max - min) / mean speed, e.g. 0.05)")
    kind = kind_named(given["target"])
    options = {name: given[dest] for name, dest in FORCES_OPTIONS.items()
               if given[dest] is not None}
    sweep = {"--from": given["start"], "--to": given["stop"], "--step": given["step"]}
    typed = dimensions_typed(given)
    if kind is None:
        named = sorted(f"--{n}" for n in typed)
        named += [n for n, v in (*options.items(), *sweep.items(), ("--branch", given["branch"]))
                  if v is not None]
        if named:
            raise UsageError(f"{' '.join(named)}: a scene gives its dimensions, sweep, branches "
                             "and [dynamics]; these options go with a KIND")
        scene = load_scene(scene_path(given["target"]))
        if scene.dynamics is None:
            raise CommandError(f"{scene.path}: key 'dynamics' is missing: expected "
                               f"{SCENE_KEYS['dynamics']}")
        return ForcesOptions(scene, tuple(b for b in scene.branches if "double" in
                                          scene.precisions),
                             scene.dynamics.effects.speed_rpm, given["fluctuation"])
    _check_dimensions(kind, typed)
    dims = {n: typed_value(decimal_number, typed[n], f"--{n}") for n in LINKAGE_DIMENSIONS[kind]}
    numbers = {name: typed_value(decimal_number, v, name) for name, v in options.items()}
    start, stop, step = (typed_value(decimal_number, v if v is not None else default, flag)
                         for (flag, v), default in zip(sweep.items(), ("0", "360", "1")))
    table: dict[str, Any] = {"speed": numbers.get("--speed", 0.0)}
    for name, key in (("--gravity", "gravity"), ("--output-torque", "output_torque"),
                      ("--output-force", "output_force"), ("--radius", "radius")):
        if name in numbers:
            table[key] = numbers[name]
    output = "slider" if kind in SLIDER_CRANKS else "output"
    for role, key in (("crank", "crank"), ("coupler", "coupler"), ("output", output)):
        if f"--mass-{role}" in numbers:
            table[key] = {"mass": numbers[f"--mass-{role}"]}
    if step == 0 or (stop - start) / step < 0 or (stop - start) / step >= MAX_SCENE_POINTS:
        raise UsageError(f"--step {step:g}: expected a step that goes from {start:g} to "
                         f"{stop:g} in at most {MAX_SCENE_POINTS:,} points")
    try:
        Linkage(kind, **dims)
        dynamics = scene_dynamics("the options", kind, dims, table)
    except (SceneError, ValueError) as e:
        named_key = re.fullmatch(r"the options: key 'dynamics\.(\w+)': expected (.*)", str(e))
        if named_key is None:
            raise CommandError(str(e)) from None
        flag = next(f for f, dest in FORCES_OPTIONS.items()
                    if dest in (named_key[1], "mass_" + named_key[1].replace("slider", "output")))
        raise CommandError(f"{flag}: {named_key[2]}") from None
    branch = FOLLOW if given["branch"] == FOLLOW else int(given["branch"] or 1)
    scene = Scene("the options", "", kind, dims, start, stop, step, (branch,), ("double",),
                  (), dynamics=dynamics)
    return ForcesOptions(scene, (branch,), numbers.get("--speed", 0.0), given["fluctuation"])


def forces_command(args: ForcesOptions) -> int:
    """`python3 linkage.py forces SCENE` (a scene with [dynamics]) or `forces KIND --a ...
    --speed RPM ...`: what it takes to drive the linkage, one `name = value` a line
    (forces_lines), for each of the scene's branches the engine computes."""
    scene, speed = args.scene, args.speed
    lines = [f"kind = {scene.kind}"]
    lines += [f"{n} = {value_text(v)}" for n, v in scene.dimensions.items()]
    lines += [f"speed = {value_text(speed)} rpm",
              f"sweep = {value_text(scene.start)} to {value_text(scene.stop)} by "
              f"{value_text(scene.step)}"]
    for branch in args.branches:
        results = scene_forces(scene, branch)
        if all(r.status in (NOT_ASSEMBLED, INDETERMINATE, STOPPED) for r in results):
            return said(f"{scene.path}: the {scene.kind} linkage assembles at none of "
                        "the sweep's input angles", 1)
        prefix = f"branch_{branch}." if len(args.branches) > 1 else ""
        lines += [f"{prefix}branch = {branch}"] + forces_lines(results, cs=args.fluctuation,
                                                               prefix=prefix)
        lines += _flywheel_added(scene, branch, results, args.fluctuation, prefix)
    sys.stdout.write("".join(line + "\n" for line in lines))
    sys.stdout.flush()
    return 0


def _flywheel_added(scene: Scene, branch: int | str, results: Sequence[Forces], cs: float,
                    prefix: str) -> list[str]:
    """forces' two lines after flywheel_inertia (the whole inertia at the crank): the linkage's
    own mean reduced inertia (mean_reduced_inertia) and the flywheel to add, the rest; none
    where either cannot be known (no flywheel figure, a followed branch, a dead centre)."""
    whole = forces_summary(results, cs=cs).flywheel_inertia
    if whole is None or not isinstance(branch, int) or scene.dynamics is None:
        return []
    bodies, _, radius = scene.dynamics
    own = mean_reduced_inertia(Linkage(scene.kind, **scene.dimensions),
                               [r.phi for r in results], branch, bodies, radius=radius)
    if own is None:
        return []
    return [f"{prefix}inertia_mean = {value_text(own)} kg m^2",
            f"{prefix}flywheel_added = {value_text(max(0.0, whole - own))} kg m^2"]


FORCES_OPTIONS = {"--speed": "speed", "--gravity": "gravity", "--radius": "radius",
                  "--mass-crank": "mass_crank",
                  "--mass-coupler": "mass_coupler", "--mass-output": "mass_output",
                  "--output-torque": "output_torque", "--output-force": "output_force"}


def _dat_names(count: int) -> str:
    return ", ".join(DatFiles.NAMES[:count])


def figure_command(args: Pictures, make_figure: Callable[[], Figure]) -> int:
    """Make the figure and draw it: the PNG with --png, the text plot with --text or without
    --png (reported: every way it can fail is a message and a non-zero status)."""
    def draw() -> None:
        if args.png:
            matplotlib_canvas()                       # fail before any work
        figure = make_figure()
        text = text_figure(figure) if args.text or not args.png else ""
        if args.png:
            png_figure(figure, args.png, args.dpi, args.size)
        printed(text)
        if args.png:
            say(f"wrote {args.png}")
    return reported(draw)


def _check_frames(frames: int | None) -> None:
    if frames is not None and not 1 <= frames <= MAX_FRAMES:
        raise SceneError(f"--frames {frames}: expected 1 to {MAX_FRAMES:,} frames")


def drawing_command(args: Pictures, make_drawing: Callable[[], Drawing]) -> int:
    """Draw the mechanism: an animated SVG with --svg, a PNG with --png, the terminal view with
    --text or neither (animated on a terminal; piped, --frames N stills). Files are written
    whole or not at all (reported: every way it can fail is a message and a non-zero status)."""
    def draw() -> int | None:
        _check_frames(args.frames)
        if args.png:
            matplotlib_canvas()                       # fail before any work
        if args.dxf:
            dxf_module()
        drawing = make_drawing()
        files = [(path, render) for path, render in (
            (args.svg, lambda: svg_drawing(drawing).encode("utf-8")),
            (args.png, lambda: png_drawing(drawing, dpi=args.dpi, size=args.size)),
            (args.dxf, lambda: dxf_drawing(drawing))) if path]
        with WrittenSet() as outputs:                 # the SVG, PNG and DXF: all or none
            for path, render in files:
                with outputs.opened(path) as fh:
                    fh.write(render())
        for path, _ in files:
            count = len(drawing.frames) if path != args.dxf else min(
                DXF_POSITIONS, sum(f.message is None for f in drawing.frames))
            say(f"wrote {path} ({count} position{'s' * (count != 1)})")
        if args.text or not (args.svg or args.png or args.dxf):
            return show_drawing(drawing, frames=args.frames)
        return None
    return reported(draw)


# ---- 30. Commands scene, plot, design, listing, explore and bench --------------------------------
#
# Holds: the other commands, each as the last section's: its typed value, the function that makes
# it, its handler.
#
# Uses: sections 1, 2, 6, 8, 14, 15, 16, 17, 18, 19, 21, 22, 23, 24, 25, 26, 27, 28 and 29.
# Offers: SceneOptions, scene_options, scene_command, PlotOptions, plot_options, plot_command,
#   design_scene, DesignOptions, design_options, design_command, ERRATUM, KEPT_BUG, SCAN_LINE,
#   scan_lines, erratum_reason, kept_bug_lines, annotated_listing, ListingOptions, listing_command,
#   ExploreOptions, explore_options, explore_command, BenchOptions, bench_options, bench_command.


class SceneOptions(NamedTuple):
    """scene's command line, validated: --list, or the scene (loaded from `path`) with its CSV,
    its folder for the DAT files and its pictures."""

    listing: bool
    path: str
    scene: Scene | None
    csv: str | None
    folder: str | None
    pictures: Pictures


def scene_options(given: dict[str, Any]) -> SceneOptions:
    """scene's typed value (see SceneOptions): UsageError, or SceneError for a scene that cannot
    be loaded."""
    pictures = pictures_typed(given)
    if given["list"]:
        if given["file"] is not None:
            raise UsageError("--list takes no scene")
        named = [f"--{o}" for o in ("svg", "png", "csv", "dir", "frames", "text", "dpi", "size")
                 if given.get(o) not in (None, False)]
        if named:
            raise UsageError("--list writes no file and draws nothing: no use for "
                             + " ".join(named))
        return SceneOptions(True, "", None, None, None, pictures)
    if given["file"] is None:
        raise UsageError("give a scene: a file, or a name of scene --list (e.g. fig3)")
    path = scene_path(given["file"])
    scene = load_scene(path)
    csv, folder = given["csv"], given["dir"]
    _check_not_inputs({"--svg": pictures.svg, "--png": pictures.png, "--csv": csv}, [path])
    if scene.simulation is not None and folder is not None:
        raise UsageError(f"--dir keeps DAT files, against the input angle; {path} is a run in "
                         "time: its rows go to --csv")
    if scene.draws_mechanism:
        if csv or folder is not None:
            raise UsageError(f"--csv and --dir go with a scene of curves; {path} draws the "
                             "mechanism (--svg, --png, --dxf, --text, --frames)")
        check_outputs({"--svg": pictures.svg, "--png": pictures.png, "--dxf": pictures.dxf})
    else:
        if pictures.svg or pictures.dxf or pictures.frames is not None:
            raise UsageError(f"--svg, --dxf and --frames draw a mechanism scene; {path} plots "
                             "curves (--png, --text)")
        plan = [f"{p}-branch{b}" for b in scene.branches for p in scene.precisions]
        check_outputs({"--csv": csv, "--png": pictures.png}, folder,
                       [os.path.join(d, n) for d in (plan if len(plan) > 1 else ["."])
                        for n in DatFiles.NAMES + (DatFiles.MU,)])
    return SceneOptions(False, path, scene, csv, folder, pictures)


def scene_command(args: SceneOptions) -> int:
    """`python3 linkage.py scene FILE`: compute the scene and draw it, keeping its DAT files in
    --dir if given; a mechanism scene is drawn (and animated) instead, and writes no DAT file."""
    if args.listing:
        for name, title in scene_list():
            print(f"{name:34} {printable(title)}")
        return 0
    scene = args.scene
    assert scene is not None                            # scene_options loaded it
    if scene.draws_mechanism:
        return drawing_command(args.pictures, lambda: scene_drawing(scene)
                               if scene.simulation is None
                               else simulation_drawing(scene, _simulated(scene)))
    if scene.simulation is not None:
        return reported(lambda: _simulation_outputs(scene, args))
    if args.folder is not None:
        output_folder("--dir", args.folder)
    return reported(lambda: _scene_outputs(scene, args))


def _scene_outputs(scene: Scene, args: SceneOptions) -> None:
    """A scene of curves: computed in a hidden folder (in --dir, or a temporary one), then its DAT
    files (with --dir), its CSV and its PNG put in place as one set (WrittenSet: all or none),
    then the text plot printed."""
    if args.pictures.png:
        matplotlib_canvas()                             # fail before any work
    try:
        staging = staging_folder(args.folder)
    except OSError as e:
        raise SceneError(f"cannot write the DAT files in {args.folder!r}: {e.strerror}") from None
    with staging as where:
        series = compute_scene(scene, where, say)
        figure = scene_figure(scene, series)
        text = (text_figure(figure) if args.pictures.text or not args.pictures.png
                else "")                                # may not fit
        with WrittenSet() as outputs:
            if args.folder is not None:
                for s in series:
                    family = DatFiles.NAMES + ((DatFiles.MU,) if s.precision == "double" else ())
                    target = os.path.join(args.folder, os.path.relpath(s.directory, where))
                    for name in family:
                        staged = os.path.join(s.directory, name)
                        if os.path.exists(staged):
                            outputs.adopt(staged, os.path.join(target, name))
                        else:
                            outputs.removed(os.path.join(target, name))
            rows = scene_csv(scene, series, args.csv, outputs) if args.csv else 0
            if args.pictures.png:
                png_figure(figure, args.pictures.png, args.pictures.dpi, args.pictures.size,
                           outputs)
    printed(text)                       # before a word of what was written (--csv - too)
    if args.folder is not None:
        say(f"wrote the DAT files of {', '.join(s.name for s in series)} in {args.folder}")
    if args.csv:
        say(f"wrote {args.csv} ({rows:,} rows)")
    if args.pictures.png:
        say(f"wrote {args.pictures.png}")


def _simulated(scene: Scene) -> Simulation:
    """The simulation scene's run, what happened in it said (standard error)."""
    run = scene_run(scene)
    for line in simulation_report(run):
        say(line)
    return run


def _simulation_outputs(scene: Scene, args: SceneOptions) -> None:
    """A simulation scene of curves: the run, its CSV and PNG as one set (all or none), then the
    text plot printed."""
    if args.pictures.png:
        matplotlib_canvas()                             # fail before any work
    run = _simulated(scene)
    figure = simulation_figure(scene, run)
    text = text_figure(figure) if args.pictures.text or not args.pictures.png else ""
    with WrittenSet() as outputs:
        rows = simulation_csv(run, args.csv, outputs) if args.csv else 0
        if args.pictures.png:
            png_figure(figure, args.pictures.png, args.pictures.dpi, args.pictures.size, outputs)
    printed(text)                       # before a word of what was written (--csv - too)
    if args.csv:
        say(f"wrote {args.csv} ({rows:,} rows)")
    if args.pictures.png:
        say(f"wrote {args.pictures.png}")


class PlotOptions(NamedTuple):
    """plot's command line: the folder of the DAT files, the kind (None: not given) and the
    pictures."""

    directory: str
    kind: str | None
    pictures: Pictures


def plot_options(given: dict[str, Any]) -> PlotOptions:
    """plot's typed value (see PlotOptions), or UsageError: a --png that is one of its inputs."""
    pictures = pictures_typed(given)
    if os.path.isfile(given["directory"]):      # a scene's CSV: its force panels
        _check_not_inputs({"--png": pictures.png}, [given["directory"]])
        return PlotOptions(given["directory"], given["kind"], pictures)
    with contextlib.suppress(SceneError):        # no DAT file there: dat_figure's to say
        _check_not_inputs({"--png": pictures.png}, [
            os.path.join(s.directory, name) for s in dat_series(given["directory"])
            for name in QUANTITY_FILES.values()])
    return PlotOptions(given["directory"], given["kind"], pictures)


def plot_command(args: PlotOptions) -> int:
    """`python3 linkage.py plot [DIR]`: the figure of the DAT files in DIR; `plot FILE.csv`: the
    force panels of a scene's CSV."""
    if os.path.isfile(args.directory):
        return figure_command(args.pictures, lambda: csv_figure(args.directory))
    return figure_command(args.pictures, lambda: dat_figure(args.directory, args.kind))


def _check_not_inputs(files: dict[str, str | None], inputs: Iterable[str]) -> None:
    """Refuse (UsageError), before anything is read or written, an output of `files` {option:
    path} that is one of the command's `inputs` (`plot . --png ANG.DAT` wrote its figure over
    the file it drew, exit 0), or would become one."""
    real = {os.path.realpath(p): p for p in inputs}
    for option, path in files.items():
        if path and path != "-" and os.path.realpath(path) in real:
            raise UsageError(f"{option} {path!r} is {real[os.path.realpath(path)]!r}, a file "
                             "the command reads: it is not written over")


def design_scene(result: Synthesis, path: str = "design") -> Scene:
    """The preferred design of a Synthesis as a mechanism scene: its whole motion (whole_motion)
    on its branch, its design positions marked; `path` names it in messages."""
    design = result.design
    kind, dims = kind_and_dimensions(design.linkage)
    start, stop, step = whole_motion(design)
    data = ", ".join(f"{k} = {value_text(v)}" for k, v in design.data.items())
    return Scene(path, f"{result.method} ({data})", kind, dims, start, stop, step,
                 (design.linkage.branch,), ("double",), (PanelSpec((MECHANISM_PANEL,), None),),
                 marked=tuple(phi for phi, _ in design.positions))


class DesignOptions(NamedTuple):
    """design's command line, validated: the method (a key of METHODS) and its data by datum
    name (those given), --analyse, the files (--dat's folder, --scene) and the pictures; the
    command line's words, which the scene quotes."""

    method: str
    data: dict[str, Any]
    analyze: bool
    dat: str | None
    scene: str | None
    pictures: Pictures
    words: tuple[str, ...]
    scale: float | None = None      # every length multiplied by it (scaled_design); None: 1


def design_options(given: dict[str, Any]) -> DesignOptions:
    """design's typed value (see DesignOptions), or UsageError: outputs naming one file twice."""
    pictures = pictures_typed(given)
    check_outputs({"--scene": given["scene"], "--svg": pictures.svg, "--png": pictures.png,
                    "--dxf": pictures.dxf}, given["dat"], DatFiles.NAMES)
    method = METHODS[given["method"]][1]
    data = {datum.name: given[datum.name] for datum in DATA[method]
            if given.get(datum.name) is not None}
    scale = given.get("scale")
    if scale is not None:
        scale = typed_value(decimal_number, scale, "--scale")
        if not 0.0 < scale < math.inf:
            raise UsageError(f"--scale {scale:g}: expected a length > 0 (the fixed link's, in "
                             "your units)")
    return DesignOptions(given["method"], data, given["analyze"], given["dat"], given["scene"],
                         pictures, tuple(given["words"]), scale)


def design_command(args: DesignOptions) -> int:
    """`python3 linkage.py design METHOD --name value ... [--analyze] [--dat DIR] [--svg OUT]
    [--png OUT] [--text] [--scene OUT]`: print the design, `name = value` a line, and draw it;
    exit 0, 1 bad data, 2 usage, 3 a miss."""
    if args.dat is not None:
        output_folder("--dat", args.dat)
    function, method = METHODS[args.method]
    try:
        designed = function(**args.data)
    except DesignError as error:
        say(f"error: {error}", f"{PROG} design")
        return 1
    except (ArithmeticError, ValueError) as error:      # data check_data let through
        say(f"error: {method}: the data cannot be computed in double precision ({error})",
            f"{PROG} design")
        return 1
    result = designed._replace(solutions=tuple(scaled_design(design, args.scale or 1.0)
                                               for design in designed.solutions))
    print(f"method = {result.method}")
    for key, value in result.design.data.items():
        print(f"data.{key} = {value_text(value)}")
    print(f"letters = {letters(result.design.linkage)} (as run takes them)")
    if args.scale is not None:
        print(f"scale = {value_text(args.scale)}  # every length multiplied by it"
              + (": the fixed link a" if isinstance(result.design.linkage, FourBar) else ""))
    print(f"solutions = {len(result.solutions)}")
    print(f"preferred = {result.preferred + 1}")
    for reason in result.rejected:
        print(f"rejected = {reason}")
    code = 0
    for number, (design, unscaled) in enumerate(zip(result.solutions, designed.solutions), 1):
        print(f"solution = {number}")
        for line in design_lines(design):
            print(line)
        if args.analyze:
            checks = analyze_design(unscaled)        # against the data, in the data's units
            bad = misses(unscaled, checks)
            for check in checks:
                measured = "none" if check.measured is None else value_text(check.measured)
                print(f"measured.{check.name} = {measured}  # expected {value_text(check.expected)}"
                      f", miss {check.miss:.2g}")
            print(f"verdict = {'meets' if not bad else 'misses ' + ', '.join(c.name for c in bad)}")
            code = code or (3 if bad else 0)
            kind, dims = kind_and_dimensions(design.linkage)
            try:
                analysis = analyse(Linkage(kind, **dims), design.linkage.branch)
                print("\n".join(analysis_lines(analysis, "analysis.")))
            except ValueError as error:
                print(f"analysis = none  # {error}")
        for line in design_commands(design) + review_lines(unscaled):
            print(line)
    pictures = args.pictures
    if (args.dat is not None or args.scene or pictures.svg or pictures.png or pictures.dxf
            or pictures.text):
        sys.stdout.flush()
        status = reported(lambda: _design_outputs(result, args))
        return status or code
    return code


def _design_outputs(result: Synthesis, args: DesignOptions) -> int:
    """design's files - the DAT files (--dat), the scene (--scene), the drawings (--svg, --png,
    --dxf) - put in place as one set (WrittenSet: all or none), then --text's terminal drawing.
    The status (1: a DAT file that cannot be written)."""
    pictures = args.pictures
    if pictures.png:
        matplotlib_canvas()                               # fail before any work
    if pictures.dxf:
        dxf_module()
    link = result.design.linkage
    kind, dims = kind_and_dimensions(link)
    drawing = (scene_drawing(design_scene(result)) if pictures.svg or pictures.png
               or pictures.dxf or pictures.text else None)
    with contextlib.ExitStack() as stack:
        outputs = WrittenSet()
        if args.dat is not None:
            try:
                where = stack.enter_context(staging_folder(args.dat))
                write_dat_files(Linkage(kind, **dims).sweep(
                    evenly_spaced_angles(0.0, 360.0, 1.0), link.branch), where)
            except ProgramStop as error:
                return said(f"error: {error}", 1)
            for name in DatFiles.NAMES:
                outputs.adopt(os.path.join(where, name), os.path.join(args.dat, name))
        with outputs:
            if args.scene:
                with outputs.opened(args.scene) as fh:
                    fh.write(scene_text(design_scene(result, args.scene),
                                        f"python3 linkage.py {' '.join(args.words)}")
                             .encode("utf-8"))
            if drawing is not None and pictures.svg:
                with outputs.opened(pictures.svg) as fh:
                    fh.write(svg_drawing(drawing).encode("utf-8"))
            if drawing is not None and pictures.png:
                with outputs.opened(pictures.png) as fh:
                    fh.write(png_drawing(drawing, dpi=pictures.dpi, size=pictures.size))
            if drawing is not None and pictures.dxf:
                with outputs.opened(pictures.dxf) as fh:
                    fh.write(dxf_drawing(drawing))
    if args.dat is not None:
        print(f"dat = {args.dat}  # ANG.DAT, VEL.DAT, ACC.DAT of the preferred solution, "
              f"0 to 360 by 1 degree, branch {link.branch}, double precision")
    if args.scene and args.scene != "-":
        say(f"wrote {args.scene} (a scene: python3 linkage.py scene {args.scene})")
    if drawing is None:                                   # no --svg, --png, --dxf or --text
        return 0
    status = 0
    if pictures.text and not sys.stdout.isatty():        # printed before a word of the files
        status = show_drawing(_positions_drawing(result), frames=len(result.design.positions))
        printed("")
    for path in (pictures.svg, pictures.png, pictures.dxf):
        if path:
            count = len(drawing.frames) if path != pictures.dxf else min(
                DXF_POSITIONS, sum(f.message is None for f in drawing.frames))
            say(f"wrote {path} ({count} position{'s' * (count != 1)})")
    if pictures.text and sys.stdout.isatty():
        return show_drawing(drawing)                      # the whole motion, until q
    return status


def _positions_drawing(result: Synthesis) -> Drawing:
    """The preferred design drawn at its design positions, one frame each: the still frames that
    design --text prints where its output is not a terminal."""
    scene = design_scene(result)
    branch = scene.branches[0]
    assert isinstance(branch, int)                        # a design's branch: 1 or 2
    return mechanism_drawing(Linkage(scene.kind, **scene.dimensions), scene.marked, branch,
                             scene.title, f"{KIND_NAMES[scene.kind]}; branch {branch}; "
                             f"the {len(scene.marked)} design positions")


ERRATUM = re.compile(r"^### ([EL]\d+)\. Lines? ([0-9, ]+): `(.+)` → `(.+)`$", re.MULTILINE)
KEPT_BUG = re.compile(r"^### (K\d+)\. (.+)$((?:\n(?!#).*)*?)^On lines? ([0-9, –]+)\.$",
                      re.MULTILINE)
SCAN_LINE = re.compile(r"^(\d+|B30)\s")   # a line of the scan starts so (ERRATA.md L3, E22)


def _squeezed(text: str) -> str:
    return "".join(text.split())


def scan_lines(scan: str, renumbered: dict[str, int]) -> dict[int, str]:
    """{line number: text} of the scan (LINKAGE.OCR.txt): a line that does not start with a
    number continues the one before (ERRATA.md L3), the later of two copies is kept, and a
    number the scan misread is the one `renumbered` gives it."""
    lines: dict[int, str] = {}
    number = None
    for raw in scan.splitlines():
        start = SCAN_LINE.match(raw)
        if start:
            label = start[1]
            number = renumbered.get(label) or int(label)
            lines[number] = raw
        elif number is not None:
            lines[number] += " " + raw.strip()
    return {n: " ".join(t.replace("\t", " ").split()) for n, t in lines.items()}


def erratum_reason(errata: str, name: str) -> str:
    """The one-line reason for correction `name` (E1, L4): what the program would do with the
    scan's text left in (its `Left in:` clause), else the entry's first sentence."""
    entry = re.search(rf"^### {name}\. .*$((?:\n(?!#).*)*)", errata, re.MULTILINE)
    body = " ".join((entry[1] if entry else "").split()).replace("*", "")
    left_in = re.search(r"Left in: (.*?)(?: Caught by:|$)", body)
    if left_in:
        return "left in: " + left_in[1]
    return body.split(". ")[0].removesuffix(".") + "." if body else ""


def kept_bug_lines(errata: str, numbers: Iterable[int]) -> dict[int, list[str]]:
    """{listing line: ["K6: its title", ...]}: the bugs of the original kept (ERRATA.md Part 2),
    on the lines of `numbers` (the listing's) each entry's `On lines ...` names (N–M: every
    line from N to M)."""
    kept: dict[int, list[str]] = {}
    numbers = sorted(numbers)
    for name, title, _, where in KEPT_BUG.findall(errata):
        for low, high in re.findall(r"(\d+)(?:–(\d+))?", where):
            for n in numbers:
                if int(low) <= n <= int(high or low):
                    kept.setdefault(n, []).append(f"{name}: {title}")
    return kept


def annotated_listing(listing: str, errata: str, scan: str | None = None,
                      errata_path: str = "legacy_basic/ERRATA.md") -> list[str]:
    """The corrected listing (LINKAGE.BAS), each line that corrects the scan marked `*` in the
    margin and followed by its errata (ERRATA.md's headings, `### E1. Line 210: ...`) and each
    one's reason (erratum_reason), each line of a bug of the original kept marked `K` and
    followed by its name (kept_bug_lines); with `scan` (LINKAGE.OCR.txt), each line whose text
    the scan prints otherwise (white space aside) followed by the scan's text. errata_path is
    where the reader finds ERRATA.md."""
    import textwrap
    numbered = [(int(line.split(" ", 1)[0]), line) for line in listing.splitlines()]
    corrections: dict[int, list[str]] = {}
    renumbered = {}
    for name, where, printed, corrected in ERRATUM.findall(errata):
        numbers = [int(n) for n in re.findall(r"\d+", where)]
        lines = [n for n, text in numbered if _squeezed(corrected) in _squeezed(text)]
        on = [n for n in lines if n in numbers] or lines
        for n in on:
            corrections.setdefault(n, []).extend([
                f"{name}: the scan printed `{printed}`, corrected `{corrected}`",
                *textwrap.wrap(erratum_reason(errata, name), 88, initial_indent="    ",
                               subsequent_indent="    ")])
    kept = kept_bug_lines(errata, (n for n, _ in numbered))
    for name, where, printed, corrected in ERRATUM.findall(errata):
        if printed.split()[0] != corrected.split()[0] and corrected.split()[0].isdigit():
            renumbered[printed.split()[0]] = int(corrected.split()[0])
    scanned = scan_lines(scan, renumbered) if scan is not None else {}
    out = [f"LINKAGE.BAS as corrected; * marks a line that corrects the scan, K a bug of the "
           f"original kept ({errata_path})" + ("; scan: the scan's text where it differs"
                                                if scan is not None else ""), ""]
    for number, text in numbered:
        mark = "*" if number in corrections else "K" if number in kept else " "
        out.append(f"{mark} {text}")
        out += [f"        {note}" for note in corrections.get(number, ())]
        out += [f"        kept, {note}" for note in kept.get(number, ())]
        if scan is not None and _squeezed(scanned.get(number, "")) != _squeezed(text):
            out.append(f"        scan: {scanned.get(number, '(not in the scan)')}")
    count = len({note.split(":")[0] for notes in corrections.values() for note in notes
                 if not note.startswith(" ")})
    bugs = sorted({note.split(":")[0] for notes in kept.values() for note in notes},
                  key=lambda k: int(k[1:]))
    out += ["", *textwrap.wrap(
        f"{count} corrections on {len(corrections)} lines; the bugs of the original kept "
        f"({bugs[0]}-{bugs[-1]}) marked K where they live. Each explained, and where this port "
        f"deviates (P1-P7): {errata_path}", 100, break_on_hyphens=False, break_long_words=False)]
    return out


class ListingOptions(NamedTuple):
    """listing's command line: --ocr, the scan's text shown too."""

    ocr: bool


def listing_command(args: ListingOptions) -> int:
    """`python3 linkage.py listing [--ocr]`: the corrected listing with its errata."""
    def show() -> None:
        listing, errata = (open(shipped_file("legacy_basic", name), encoding="utf-8").read()
                           for name in ("LINKAGE.BAS", "ERRATA.md"))
        scan = (open(shipped_file("legacy_basic", "LINKAGE.OCR.txt"), encoding="utf-8").read()
                if args.ocr else None)
        shown = annotated_listing(listing, errata, scan,
                                  os.path.abspath(shipped_file("legacy_basic", "ERRATA.md")))
        sys.stdout.write("".join(f"{printable(line)}\n" for line in shown))
    return reported(show)


class ExploreOptions(NamedTuple):
    """explore's command line, validated: the explorer's first state, and the key file to
    replay (None: the terminal's keys) with the replay's screen size."""

    state: Explorer
    keys: str | None
    size: tuple[int, int]


def explore_options(given: dict[str, Any]) -> ExploreOptions:
    """explore's typed value: the kind and dimensions given (the kind's example's where not), or
    a scene's linkage, branch, coupler point and [dynamics], or the plane four-bar's example;
    --branch the branch it starts on (else 1, or the scene's). UsageError, or CommandError
    (SceneError) for a scene or linkage it cannot show."""
    typed = dimensions_typed(given)
    target = given["target"] or PLANE_FOUR_BAR
    kind = kind_named(target)
    if kind is None and typed:
        raise UsageError(f"--{next(iter(typed))} goes with a kind ({', '.join(KIND_MENU)}), not "
                         "with a scene")
    if kind is not None:
        unknown = [n for n in typed if n not in LINKAGE_DIMENSIONS[kind]]
        if unknown:
            raise UsageError(f"--{unknown[0]}: the {KIND_NAMES[kind]} takes "
                             + ", ".join("--" + n for n in LINKAGE_DIMENSIONS[kind]))
        dims = {n: typed_value(decimal_number, text, f"--{n}") for n, text in typed.items()}
    try:
        if kind is None:
            scene = load_scene(scene_path(target))
            branch = next((b for b in scene.branches if isinstance(b, int)), 1)
            state = explorer_of(scene.kind, scene.dimensions, int(given.get("branch") or branch),
                                FOLLOW in scene.branches, scene.coupler, scene.dynamics)
        else:
            state = explorer_of(kind, dims, int(given.get("branch") or 1))
        ExploreViews()(state)                           # a linkage that can be drawn
    except ValueError as e:
        raise CommandError(str(e)) from None
    return ExploreOptions(state, given["keys"], given["size"])


def explore_command(args: ExploreOptions) -> int:
    """`python3 linkage.py explore [KIND --a ... | SCENE]`: the explorer on the terminal
    (explore_terminal); with --keys FILE the keys of the file replayed instead and the last
    screen printed (explore_replay)."""
    state = args.state
    unicode = (getattr(sys.stdout, "encoding", None) or "").lower().replace("-", "") == "utf8"
    if args.keys is not None:
        try:
            with open(args.keys, encoding="utf-8") as fh:
                keys = key_file(fh.read())
        except OSError as e:
            return said(f"{args.keys}: cannot read the keys: {e.strerror}", 1)
        except (ValueError, UnicodeDecodeError) as e:
            return said(f"{args.keys}: {e}", 1)
        width, height = args.size
        _, lines = explore_replay(state, keys, width, height, unicode)
        sys.stdout.write("".join(line + "\n" for line in lines))
        sys.stdout.flush()
        return 0
    if (not (is_terminal(sys.stdin) and is_terminal(sys.stdout))
            or os.environ.get("TERM", "dumb") in ("", "dumb")):
        return said("explore needs a terminal: standard input and output a terminal whose TERM "
                    "is not dumb (--keys FILE replays keys without one and prints the last "
                    "screen)", 1)
    state = explore_terminal(state, unicode)
    print(f"{PROG} analyse {state.kind} "
          + " ".join(f"--{n} {v:g}" for n, v in state.dims)
          + ("" if state.branch == 1 else f" --branch {state.branch}"))
    return 0


class BenchOptions(NamedTuple):
    """bench's command line, validated: the benchmarks' names (all where none, or `all`),
    --quick's tiny sizes, and bench accuracy's --png."""

    names: tuple[str, ...]
    quick: bool
    png: str | None


def bench_options(given: dict[str, Any]) -> BenchOptions:
    """bench's typed value (see BenchOptions), or UsageError."""
    names = tuple(n for n in given["names"] if n != "all")
    if given["png"] and "accuracy" not in names:
        raise UsageError("--png goes with bench accuracy")
    if names and len(names) < len(given["names"]):
        raise UsageError(f"bench all runs every bench: name it alone, not with {names[0]}")
    return BenchOptions(names, given["quick"], given["png"])


def bench_command(args: BenchOptions) -> int:
    """`python3 linkage.py bench [NAME ...]`: print the benchmarks' numbers and how they ran."""
    print(f"$ python3 linkage.py bench {' '.join(args.names)}".rstrip())
    print(f"{PROG} {__version__} on {machine()}")
    if args.quick:
        print("--quick: a check that each runs, on tiny sizes; its numbers mean nothing")
    try:
        run_benchmarks(sys.stdout, args.names, args.quick, args.png)
    except (PlotUnavailable, WriteError) as e:
        return said(e, 1)
    return 0


# ---- 31. The command line: argparse from the table of commands -----------------------------------
#
# Holds: the command line's words parsed (argparse): the parsers of what is typed in an option
# (a number of a design's data, a kind, PNG sizes), the commands' help, and COMMANDS, the table of
# every sub-command: its help, its options, its "goes with" rules and the functions that make its
# typed value and do its work (sections 29 and 30); build_parser turns it into argparse; main() last.
#
# Uses: sections 1, 2, 5, 6, 16, 18, 19, 21, 26, 27, 29 and 30.
# Offers: ANGLES_HELP, METHOD_HELP, DESIGN_OUTPUT_HELP, datum_help, HIDDEN, Option, option, Command,
#   DIMENSION_HELP, KINDS_HELP, DIMENSIONS_HELP, DATUM_FLAGS, DXF_HELP, PNG_OPTIONS, COMMANDS,
#   command_parser, add_options, build_parser, main.


ANGLES_HELP = ("Angles in degrees, counter-clockwise from the frame line (the crank pivot A0 "
               "towards the output pivot B0)")
METHOD_HELP = {  # each method's --help: what it designs from what (the data: DATA)
    "FOURB-CR-1": "A crank-rocker (Chen; Pamidi) whose rocker swings through psi while the crank "
                  "turns 180 + theta from the extended dead centre (crank and coupler in line) to "
                  "the folded one, the crank at theta0 at the extended one.",
    "FOURB-CR-2": "A crank-rocker (Chen; Pamidi) whose rocker swings through psi while the crank "
                  "turns 180 + theta from the extended dead centre (crank and coupler in line) to "
                  "the folded one, the rocker at psi0 at the extended one; up to two linkages.",
    "FOURB-CR-3": "A crank-rocker (Freudenstein & Primrose) whose rocker swings through psi "
                  "while the crank turns 180 + theta from the extended dead centre to the folded "
                  "one, with the least greatest deviation of the transmission angle from 90 "
                  "degrees.",
    "FOURB-CR-4": "A centric crank-rocker (Brodell & Soni: theta = 0, the crank turning 180 "
                  "degrees each way) whose rocker swings through psi, with least transmission "
                  "angle mu_min.",
    "FOURB-CR-4 (Volmer)": "The centric crank-rocker of FOURB-CR-4 by Volmer's equations (6a-c): "
                           "rocker swing psi, least transmission angle mu_min.",
    "DRAGLINK-1": "A drag-link (Bagci: frame shortest, crank and output turning fully) whose "
                  "output turns dpsi0 while the crank turns 180 degrees from the frame line "
                  "(phi = 0) to its extension (phi = 180), with transmission angle mu_min at "
                  "phi = 0 and 180 - mu_min at phi = 180.",
    "DRAGLINK-2": "A drag-link (Tsai: frame shortest) with unit velocity ratio (output as fast as "
                  "the crank) at two positions dphi apart on the crank and dpsi on the output; "
                  "lambda = coupler / frame given, or chosen for the transmission angle closest "
                  "to 90 degrees.",
    "FOURB-FG2-1": "A four-bar function generator (Chiang): while the crank turns through phij "
                   "from phi0 the output turns through psij (signed, counter-clockwise positive: "
                   "the motion itself, not only the end position), for a given crank a and "
                   "output c, ratios to the frame d = 1 (--crank-ratio, --output-ratio); finds "
                   "the coupler and the output's start psi0. Up to two linkages.",
    "FOURB-FG3-1": "A four-bar function generator (Freudenstein's equation) through three "
                   "positions: the output at psi1, psi2, psi3 when the crank is at phi1, phi2, "
                   "phi3. The output angles are the review's: measured from the opposite "
                   "direction to the program's, which are 180 less.",
    "SLID-FG2-1": "A slider-crank (Chen) whose slider moves ds between its dead centres while the "
                  "crank turns dtheta from the outer to the inner one, for a chosen offset "
                  "epsilon (the slider's line is y = -epsilon: the program's e = -epsilon).",
    "SLID-FG2-2": "A slider-crank (Chen) through its two dead centres: the crank at theta1 with "
                  "the slider at s1 (outer), the crank pin in the direction theta2 with the "
                  "slider at s2 (inner; the crank itself at theta2 - 180). The two must agree: "
                  "s1 tan(theta1) = s2 tan(theta2).",
}
DESIGN_OUTPUT_HELP = (
    "Prints, a `name = value` line each: the data; per solution the linkage in the program's "
    "letters, as `run` takes them (four-bars: a the fixed link = 1, b the input crank, c the "
    "coupler, d the output crank; slider-cranks: b the crank, c the rod, e the offset of the "
    "slider's line y = e; each length times --scale's L where it is given), its branch (run "
    "--branch; analyse, forces and explore take branch 1 unless told), the design positions "
    "(phi the crank, psi the output, x the slider; angles as the data give them), the transmission angle's extremes mu_min and "
    "mu_max (analyse's mu_worst is the one further from 90); command.analyse and command.forces,"
    " the next commands with the lengths in full precision and the branch, to paste (forces: "
    "fill in RPM and each KG); then, labelled review, the review's own numbers in its letters. "
    "Exit 0, 1 for data no design meets, 2 for a usage error, 3 when --analyse finds a miss.")


def datum_help(datum: Datum) -> str:
    """The help of a datum: what it is, its valid range, the values refused in it (DATA)."""
    refused = "".join(f"; refused: {reason}" for reason, _ in datum.excluded)
    return f"{datum.meaning}; in {range_text(datum)}{refused}"


# -- what is typed in an option: argparse's types --------------------------------------------------

def _refused(message: str) -> Exception:
    """argparse's refusal of what is typed (argparse is imported only where a command is parsed:
    the menu program starts without it)."""
    import argparse
    return argparse.ArgumentTypeError(message)


def _design_number(flag: str) -> Callable[[str], float]:
    """The argparse type of a datum: an ordinary decimal (decimal_number), its refusal naming
    the option."""
    def number(text: str) -> float:
        try:
            return decimal_number(text, flag, basic_hint=False)
        except ValueError as e:
            raise _refused(str(e).removeprefix(f"{flag}: ")) from None
    number.__name__ = "number"
    return number


def _kind_argument(text: str) -> str:
    name = kind_named(text)
    if name is None:
        raise _refused(
            f"{text!r} is not one of {', '.join(KIND_MENU)} (or 1-5)")
    return name


def _png_dpi(text: str) -> float:
    try:
        dpi = decimal_number(text, "--dpi")
    except ValueError as e:
        raise _refused(str(e)) from None
    if not 10 <= dpi <= 1200:
        raise _refused(f"{text} dots an inch: expected 10 to 1200")
    return dpi


def _png_size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"([0-9]{1,5})[xX]([0-9]{1,5})", text.strip())
    if not match or not all(100 <= int(v) <= 20000 for v in match.groups()):
        raise _refused(f"{text!r}: expected WIDTHxHEIGHT in pixels, each 100 "
                                         "to 20000, e.g. 1600x1200")
    return int(match[1]), int(match[2])


def _benchmark_name(text: str) -> str:
    if text not in BENCHMARKS and text != "all":
        raise _refused(f"{text!r} is not one of all, {', '.join(BENCHMARKS)}")
    return text


def _screen_size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"([0-9]{1,4})[xX]([0-9]{1,4})", text.strip())
    if not match or not (40 <= int(match[1]) <= 1000 and 12 <= int(match[2]) <= 1000):
        raise _refused(f"{text!r}: expected COLUMNSxLINES, at least 40x12, "
                                         "e.g. 80x24")
    return int(match[1]), int(match[2])



# -- the table: every sub-command, its help and its options -------------------------------------

HIDDEN = "(hidden)"     # an option's help that leaves it out of --help (argparse.SUPPRESS)


class Option(NamedTuple):
    """One argument of a sub-command: its name or flags, and what argparse's add_argument takes."""

    names: tuple[str, ...]
    settings: dict[str, Any]


def option(*names: str, **settings: Any) -> Option:
    return Option(names, settings)


class Command(NamedTuple):
    """A sub-command: typed(given) makes its one typed value of what its options hold (given:
    {dest: value}), once its rules hold, and handler(value) does its work and gives the exit
    status; help is its line in the program's --help, description its own --help; aliases its
    other spellings."""

    typed: Callable[[dict[str, Any]], Any]
    handler: Callable[[Any], int]
    help: str
    description: str
    options: tuple[Option, ...]
    rules: tuple[Rule, ...] = ()
    aliases: tuple[str, ...] = ()


DIMENSION_HELP = {   # each letter's option: what it is, in the drawing's pivot names
    "a": "a, the fixed link (ground): crank pivot A0 to output pivot B0 (the skew kinds: the "
         "shafts' common perpendicular, the fixed link's horizontal sector); the spherical "
         "kind: an arc, degrees",
    "b": "b, the input crank: A0 to the crank pin A, at angle phi",
    "c": "c, the coupler (connecting rod): A to the output pin B, or to the slider C",
    "d": "d, the output crank: B0 to B, at angle psi",
    "e": "e, the slider's offset: its guide is the line y = e",
    "f": "f, the fixed link's vertical sector: along the crank's shaft, from the crank's plane "
         "to the common perpendicular",
    "ksi": "ksi, the skew angle between the two shafts, degrees",
}
KINDS_HELP = (f"the kind: {', '.join(KIND_NAMES)} (or 1-5: "
              f"{', '.join(KIND_NAMES.values())})")
DIMENSIONS_HELP = ("Each kind's dimensions, in the order the menu asks for them: " + "; ".join(
    f"{kind}: {letters_defined(kind)}" for kind in KIND_MENU) + ".")
# The design data whose option is not --name: lambda (a word of Python), and the review's letters
# that run takes for lengths (FOURB-FG2-1's a and c are ratios to the frame: --a there is not
# run's fixed link), each under a name that says what it is, the letter still taken.
DATUM_FLAGS = {"lam": ("--lambda",), "a": ("--crank-ratio", "--a"),
               "c": ("--output-ratio", "--c")}
DXF_HELP = (f"write the linkage for CAD as a DXF: its true geometry in the lengths typed (3-D "
            f"for the spherical and skew kinds), the fixed links, up to {DXF_POSITIONS} of the "
            "positions drawn each on a layer of its own, the coupler point's curve (needs "
            "ezdxf: python3 -m pip install ezdxf)")
PNG_OPTIONS = (
    option("--png", metavar="OUT",
           help="write the figure as a PNG (needs matplotlib: python3 -m pip install matplotlib)"),
    option("--text", action="store_true",
           help="draw the plain-text plot (the default without --png)"),
    option("--dpi", type=_png_dpi, metavar="N",
           help="the PNG's dots an inch: its scale (default 90; a mechanism 100)"),
    option("--size", type=_png_size, metavar="WxH",
           help="the PNG's width and height in pixels, e.g. 1600x1200"),
)
COMMANDS = {
    "run": Command(
        run_options, run_command,
        "the original program driven by options",
        "The original program given these answers: writes ANG.DAT, VEL.DAT and ACC.DAT exactly "
        "as the menu would. Dimensions are typed as in the menu (degrees for the spherical "
        "linkage's arcs). " + DIMENSIONS_HELP,
        (option("kind", type=_kind_argument, metavar="KIND", help=KINDS_HELP),
         *(option(f"--{name}", metavar="X", help=text) for name, text in DIMENSION_HELP.items()),
         option("--skew", dest="old_skew", metavar="X", help=HIDDEN),
         option("--from", dest="start", required=True, metavar="P1",
                help="first bound of the input angle, degrees"),
         option("--to", dest="stop", required=True, metavar="P2",
                help="second bound of the input angle, degrees"),
         option("--step", required=True, metavar="INC", help="increment, degrees"),
         option("--branch", required=True, choices=("1", "2", FOLLOW),
                help="1: the (A+B) solution, 2: the (A-B) solution; follow (with --precision "
                     "double): the assembly the sweep starts in, followed through phi = 180 and "
                     "change points as the linkage moves, ending at a dead centre the crank "
                     "cannot pass"),
         option("--start-branch", choices=("1", "2"), metavar="1|2",
                help="with --branch follow: the branch the motion starts in (default 1)"),
         option("--dir", default=".", metavar="OUT", help="where to write the DAT files"),
         option("--precision", choices=("basic", "double"), default="basic",
                help="basic: the original's GW-BASIC single precision, byte for byte (default); "
                     "double: the accurate engine"),
         option("--csv", metavar="OUT",
                help="also write one CSV file: a header row phi,output,velocity,acceleration,"
                     "status (with --precision double: and transmission, the transmission "
                     "angle in degrees) and a row a point, every point (a position that does "
                     "not exist: its status, values nan; in basic precision a velocity or "
                     "acceleration the original clipped to +-3: status clipped)"),
         option("--coupler", nargs="+", metavar=("U", "V"),
                help="with --precision double and --csv: add the columns coupler_x, coupler_y, "
                     "coupler_z, coupler_vx, ..., coupler_az of the point (U, V) fixed to the "
                     "coupler: plane kinds U along A->B (A->C) and V across it, lengths; the "
                     "spherical linkage U along the coupler's great circle and V off it, "
                     "degrees; the skew kinds U along A->B only (their coupler may spin about "
                     "that line). Velocity and acceleration by the input angle in radians"),
         option("--clip", action="store_true",
                help="with --precision double: clip VEL and ACC to +-3 as the original does"),
         option("--fast", action="store_true",
                help="with --precision double: the same numbers by the vectorised engine (needs "
                     "numpy: python3 -m pip install numpy)")),
        (goes_with("--branch follow", "--precision double",
                   why="the original program has branches 1 and 2 only"),
         goes_with("--start-branch", "--branch follow"),
         goes_with("--fast", "--branch 1 or 2",
                   why="the vectorised path computes the listing's branches"),
         goes_with("--coupler", "--precision double",
                   why="the original program computes the output link only"),
         goes_with("--coupler", "--csv", why="it adds columns to the CSV: give --csv OUT too"),
         goes_with("--clip", "--precision double", why="the original always clips VEL and ACC"),
         goes_with("--fast", "--precision double",
                   why="the original's numbers are computed one point at a time"))),
    "analyse": Command(
        analyse_options, analyse_command,
        "the linkage's class, range of motion and transmission angle",
        "The linkage's class (Grashof's for the plane four-bar, b + |e| against c for the "
        "plane slider-crank, the class its motion shows for the other kinds), the crank's range "
        "(full, or between its dead centres), the output's range and swing, the time ratio "
        "(the slower stroke's crank turn over the faster's, >= 1; time_ratio_review: the "
        "review's eq. (5)), the transmission angle's extremes with the crank angles where they "
        "occur and the worst (furthest from 90), and the dead centres and change points: one "
        "`name = value` a line (also spelt analyze). " + DIMENSIONS_HELP,
        (option("kind", type=_kind_argument, metavar="KIND", help=KINDS_HELP),
         *(option(f"--{name}", metavar="X", help=text) for name, text in DIMENSION_HELP.items()),
         option("--branch", choices=("1", "2", FOLLOW), default="1",
                help="the assembly: 1 (A+B, the default), 2 (A-B), or follow (the motion "
                     "followed through change points from --start-branch)"),
         option("--start-branch", choices=("1", "2"), metavar="1|2",
                help="with --branch follow: the branch the motion starts in (default 1)"),
         option("--svg", metavar="OUT",
                help="also draw the linkage moving over its motion as an animated SVG, the "
                     "output's extremes, the dead centres and the transmission angle furthest "
                     "from 90 degrees drawn faint and numbered"),
         option("--png", metavar="OUT",
                help="the same as a PNG, the positions overlaid (needs matplotlib: python3 -m "
                     "pip install matplotlib)"),
         option("--dxf", metavar="OUT", help=DXF_HELP),
         option("--coupler", nargs="+", metavar=("U", "V"),
                help="with --svg, --png or --dxf: the coupler point (U, V) drawn and its curve "
                     "traced (as run --coupler)"),
         option("--dpi", type=_png_dpi, metavar="N", help="the PNG's dots an inch"),
         option("--size", type=_png_size, metavar="WxH", help="the PNG's size in pixels")),
        (goes_with("--start-branch", "--branch follow"),
         goes_with("--coupler", "--svg", "--png", "--dxf", why="it draws the coupler curve")),
        ("analyze",)),
    "forces": Command(
        forces_options, forces_command,
        "what it takes to drive the linkage: torque, power, joint forces, shaking, flywheel",
        "The forces along a sweep (SI units: lengths in metres, masses in kg; the spherical "
        "four-bar's arcs in degrees on a sphere of the scene's radius, or --radius), the crank "
        "turning at a constant speed, a positive one counter-clockwise (phi increasing): the "
        "torque T the driver applies to the crank (N m, positive in the sense of phi), "
        "torque_peak the largest |T| with its sign, and T's RMS, with their input angles; the "
        "mean power (T omega, W; omega = 2 pi rpm / 60, rad/s), each joint's peak force (N; the"
        " spherical four-bar's joints: their moment about the sphere's centre O, N m), the "
        "frame's peak shaking force and moment, and flywheel_inertia (kg m^2): the whole "
        "inertia at the crank that holds the speed within +-Cs/2 of its mean, Cs the speed "
        "fluctuation (max - min) / mean (--fluctuation; within +-5 % is Cs = 0.10): the "
        "largest swing of the energy T puts in, over Cs omega^2, over a sweep of one turn; "
        "inertia_mean, the linkage's own inertia reduced to the crank and averaged over the "
        "sweep, carries part of it, and flywheel_added is the rest, the flywheel to fit. No "
        "gravity unless "
        "asked (--gravity, a scene's gravity key). Given a scene (data/scenes/forces-*.toml), "
        "its [dynamics] table; given a KIND, its dimensions as for run and the options below, "
        "each link a uniform rod of its mass. One `name = value` a line, as analyse prints.",
        (option("target", metavar="SCENE|KIND",
                help="a scene with [dynamics] (a file, or the name of one that comes with the "
                     "program), or a kind: " + ", ".join(KIND_NAMES) + " (or 1-5)"),
         *(option(f"--{name}", metavar="X", help=text) for name, text in DIMENSION_HELP.items()),
         option("--speed", metavar="RPM",
                help="a KIND: the crank's speed, revolutions a minute, positive counter-"
                     "clockwise: phi increasing (default 0: static)"),
         option("--mass-crank", metavar="KG", help="a KIND: the crank's mass, kg"),
         option("--mass-coupler", metavar="KG", help="a KIND: the coupler's mass, kg"),
         option("--mass-output", metavar="KG",
                help="a KIND: the output crank's mass (a slider-crank: the slider's), kg"),
         option("--gravity", metavar="G",
                help="a KIND: gravity, m/s^2 along the kind's down (-y for the plane kinds, -z "
                     "for the spatial ones), e.g. 9.80665 (default none: no gravity unless "
                     "asked)"),
         option("--radius", metavar="M",
                help="a KIND (spherical): the sphere's radius, metres (default 1)"),
         option("--output-torque", metavar="N_M",
                help="a KIND (four-bars): a load on the output about its axis, N m, in the "
                     "sense of psi"),
         option("--output-force", metavar="N",
                help="a KIND (slider-cranks): a load on the slider along its guide, N, in the "
                     "sense of x"),
         option("--branch", choices=("1", "2", FOLLOW),
                help="a KIND: the assembly, 1 (A+B, the default), 2 (A-B) or follow"),
         option("--from", dest="start", metavar="P1",
                help="a KIND: the first input angle, degrees (default 0)"),
         option("--to", dest="stop", metavar="P2",
                help="a KIND: the last input angle, degrees (default 360)"),
         option("--step", metavar="INC",
                help="a KIND: the step, degrees (default 1)"),
         option("--fluctuation", type=float, default=0.05, metavar="CS",
                help="the speed fluctuation Cs = (max - min) / mean speed the flywheel holds "
                     "(default 0.05: within +-2.5 %% of the mean; +-5 %% is 0.10)"))),
    "scene": Command(
        scene_options, scene_command,
        "draw a scene of data/scenes: the paper's figures, the hard cases, the "
                       "linkage moving",
        "Compute a scene (a TOML file, see data/scenes), keep its DAT files (with --dir) and draw "
        "its figure: a plain-text plot of 80 x 24 characters unless --png is given. A mechanism "
        "scene (panels = [{quantities = [\"mechanism\"]}], e.g. "
        "data/scenes/fig1a-plane-four-bar.toml) draws the linkage itself at each input angle of "
        "its sweep (or its panel's angles) and writes no DAT file: on a terminal it moves until "
        "you press q; piped, one still frame (--frames N: N frames); --svg OUT an animated SVG; "
        "--png OUT the positions overlaid.",
        (option("file", nargs="?", metavar="SCENE",
                help="the scene: a TOML file, or the name of a scene that comes with the "
                     "program, or its start (fig3: fig3-plane-four-bar; scene --list)"),
         option("--list", action="store_true",
                help="list the scenes that come with the program, with their titles"),
         option("--svg", metavar="OUT", help="a mechanism scene: write it as one animated SVG"),
         option("--dxf", metavar="OUT", help=DXF_HELP),
         option("--frames", type=int, metavar="N",
                help="a mechanism scene: print N still frames spread evenly over the sweep "
                     "instead of the animation (piped, the default is 1)"),
         option("--csv", metavar="OUT",
                help="also write the scene's numbers as one CSV file: a header row series,phi,"
                     "output,velocity,acceleration,status and a row a point of each series, "
                     "every point (one without a position: its status); a scene with "
                     "[dynamics] adds torque (N m), power (W), shaking_fx .. shaking_fz (N), "
                     "shaking_mx .. shaking_mz (N m), forces_status (unbounded where the "
                     "forces are: their values nan) and each joint's force A0_fx .. (N) and "
                     "moment A0_mx .. (N m) where it carries one"),
         option("--dir", metavar="DIR",
                help="also keep the scene's DAT files, in DIR (without it none is written); a "
                     "scene that overlays several series writes one folder each"),
         *PNG_OPTIONS)),
    "plot": Command(
        plot_options, plot_command,
        "draw the figure of ANG.DAT, VEL.DAT and ACC.DAT already written",
        "Draw the figure of the DAT files in DIR (the menu program's, run's or a scene's): a "
        "plain-text plot of 80 x 24 characters unless --png is given. To see the linkage itself "
        "move, draw a mechanism scene: python3 linkage.py scene "
        "data/scenes/fig1a-plane-four-bar.toml (scene --help).",
        (option("directory", nargs="?", default=".", metavar="DIR",
                help="the folder of the DAT files, or of folders of them (default: here); or "
                     "a scene's CSV with forces (scene FILE --csv OUT): its torque, shaking and "
                     "joint-force panels"),
         option("--kind", "--mechanism", dest="kind", type=_kind_argument,
                metavar="KIND", help=f"{KINDS_HELP}: gives the axes their units (--mechanism: "
                                     "the old spelling, still taken)"),
         *PNG_OPTIONS)),
    "design": Command(
        design_options, design_command,
        "synthesise a linkage by one of the review's methods (python3 "
                        "linkage.py design --help)",
        "Synthesis of four-bar and slider-crank function generators (Pennestri & Valentini's "
        "review); angles in degrees.",
        (option("--analyse", "--analyze", dest="analyze", action="store_true",
                help="run the design through the analysis and print what it does (--analyze "
                     "too)"),
         option("--dat", metavar="DIR",
                help="write ANG.DAT, VEL.DAT, ACC.DAT of the preferred solution there (engine, 0 "
                     "to 360 by 1 degree)"),
         option("--svg", metavar="OUT",
                help="draw the preferred solution moving through its whole motion (a full turn "
                     "of a crank that turns fully, else from one limit of the input to the "
                     "other) as an animated SVG, its design positions drawn faint and numbered"),
         option("--png", metavar="OUT",
                help="draw that motion as a PNG, the positions overlaid (needs matplotlib: "
                     "python3 -m pip install matplotlib)"),
         option("--dxf", metavar="OUT", help=DXF_HELP),
         option("--text", action="store_true",
                help="draw that motion in the terminal (animated until q; piped, the design "
                     "positions as still frames)"),
         option("--scene", metavar="OUT",
                help="write that motion as a scene file (TOML) to edit and draw with python3 "
                     "linkage.py scene OUT"),
         option("--scale", metavar="L",
                help="every length multiplied by L, in what it prints, its commands, --scene, "
                     "--svg, --png, --dxf and --dat: a four-bar (designed with the fixed link a "
                     "= 1) gets the fixed link L, e.g. --scale 0.2 for a 0.2 m frame; a "
                     "slider-crank (designed in its data's units: ds, epsilon, s1, s2) has its "
                     "lengths and slider positions multiplied, e.g. --scale 0.001 from mm to m. "
                     "Angles, the data and the review's own numbers are not scaled"))),
    "listing": Command(
        lambda given: ListingOptions(given["ocr"]), listing_command,
        "the original BASIC listing as corrected, with its errata",
        "The program of the paper's appendix as it must have run (legacy_basic/LINKAGE.BAS): "
        "each line that corrects the scan of the printed listing is marked * and followed by "
        "its erratum and the reason for it, each line where a bug of the original lives, kept "
        "as it ran (K1-K14), marked K and followed by its name; the last line names the "
        "ERRATA.md that explains each one, where it was installed. --ocr also shows the scan's "
        "own text of every line it prints otherwise.",
        (option("--ocr", action="store_true",
                help="show the scan's text (legacy_basic/LINKAGE.OCR.txt) under each line it "
                     "prints otherwise (white space aside)"),)),
    "explore": Command(
        explore_options, explore_command,
        "change a dimension and watch the linkage answer, in the terminal",
        "A full-screen view of the linkage moving, its coupler curve traced, and beside it its "
        "dimensions and what analyse answers (type, crank range, swing, time ratio, the "
        "transmission angle now, at its extremes and furthest from 90 degrees), all following "
        "each key: Tab or a capital letter selects a dimension, the arrows change it, = types "
        "it; ? lists every key. Needs a terminal; --keys FILE replays keys without one.",
        (option("target", nargs="?", metavar="KIND|SCENE",
                help=f"{', '.join(KIND_NAMES)} (or 1-5), with any of its dimensions (the "
                     "rest the kind's example's); or a scene (a TOML file, or the name of one "
                     "of scene --list); default: the plane four-bar"),
         *(option(f"--{name}", metavar="X", help=text) for name, text in DIMENSION_HELP.items()),
         option("--branch", choices=("1", "2"), metavar="1|2",
                help="the assembly it starts on: 1 (A+B, the default; a scene: its own) or 2 "
                     "(A-B), as analyse --branch and design's branch (b toggles it)"),
         option("--keys", metavar="FILE",
                help="replay the keys of FILE and print the last screen, no terminal needed: "
                     "one key a line, a character or one of " + ", ".join(EXPLORE_KEY_NAMES)
                     + " (Tick: a tick of the motion's timer); lines starting '# ' are skipped"),
         option("--size", type=_screen_size, default=(80, 24), metavar="COLSxLINES",
                help="with --keys: the screen's size (default 80x24)")),
        (goes_with("--size", "--keys",
                   why="it sets the screen of a replay; the terminal's is its own"),)),
    "bench": Command(
        bench_options, bench_command,
        "measure speed, and what accuracy costs in time",
        "Run the benchmarks and print their numbers (port runs PC-BASIC for minutes; accuracy, "
        "what each rung of the ladder - GW-BASIC single precision, the double engine, numpy, 50 "
        "digits - errs against 110 digits and costs a point). With no NAME, or all: every "
        "bench, then the README's speed table from their figures, each with the load average. "
        "The tests' own ladder, against an mpmath reference: PYTHONPATH=tests python3 -m "
        "support.bench_accuracy; beside a C loop and pylinkage: PYTHONPATH=tests python3 -m "
        "support.bench_peers.",
        (option("names", nargs="*", type=_benchmark_name, metavar="NAME",
                help=f"which: all, {', '.join(BENCHMARKS)} (default: all, and the README's "
                     "speed table)"),
         option("--quick", action="store_true",
                help="tiny sizes: a check that each runs (its numbers mean nothing)"),
         option("--png", metavar="OUT",
                help="bench accuracy: also draw accuracy against cost (log-log), one marker a "
                     "rung and kind"))),
}


def command_parser() -> type[argparse.ArgumentParser]:
    """The class of the program's parsers, made where a command is parsed (argparse is imported
    there, not when the menu program starts)."""
    import argparse

    class CommandParser(argparse.ArgumentParser):
        """argparse, taking a negative number in any form (-1e3, -.5, -1D3) as an option's value
        (argparse before Python 3.13 takes -1e3 for an option and says "expected one
        argument")."""

        def __init__(self, *args: Any, **kwargs: Any) -> None:
            super().__init__(*args, **kwargs)
            self._negative_number_matcher = re.compile(r"-\.?\d")

        def _print_message(self, message: str, file: Any = None) -> None:
            """As argparse's, but a failure of standard output (--help, --version into `| head`)
            is raised, for main's one rule (reader_gone: 141), where argparse drops it (exit 0,
            or Python's "Exception ignored" at exit, 120); standard error's is dropped, as
            argparse's."""
            if message and file is not None and file is sys.stdout:
                file.write(message)
                file.flush()
                return
            super()._print_message(message, file)
    return CommandParser


def add_options(parser: argparse.ArgumentParser, options: Iterable[Option]) -> None:
    """A command's options added to its parser; an option whose help is HIDDEN is left out of
    --help."""
    import argparse
    for o in options:
        hidden = {"help": argparse.SUPPRESS} if o.settings.get("help") is HIDDEN else {}
        parser.add_argument(*o.names, **(o.settings | hidden))


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The program's parser, from COMMANDS; design has one sub-parser a method, its data from
    DATA (each an ordinary decimal, required unless optional), then design's own options.

    argv: the command line it will parse. Every sub-command is there with its help, but only
    those whose name is a word of argv get their options (and design its methods, the one
    named its data): argparse hands the words after a sub-command's name to that sub-parser
    alone, and adding every option of every one took 6 ms a start. None: all of them."""
    CommandParser = command_parser()
    parser = CommandParser(prog=PROG, description=__doc__.split("\n\n")[0],
                           epilog="With no command: the original menu program.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", parser_class=CommandParser)
    words = None if argv is None else set(argv)
    for name, command in COMMANDS.items():
        if name != "design":
            sub = commands.add_parser(name, help=command.help, description=command.description,
                                      aliases=command.aliases)
            if words is None or not words.isdisjoint((name, *command.aliases)):
                add_options(sub, command.options)
            sub.set_defaults(command_row=command, parser=sub)
            continue
        design = commands.add_parser(name, help=command.help, description=command.description)
        if words is not None and name not in words:
            continue
        methods = design.add_subparsers(dest="method", metavar="METHOD",
                                        parser_class=CommandParser)
        methods.required = True
        for method_name, (_, method) in METHODS.items():
            sub = methods.add_parser(method_name, help=METHOD_HELP[method],
                                     description=f"{method}: {METHOD_HELP[method]} "
                                                 f"{ANGLES_HELP}.", epilog=DESIGN_OUTPUT_HELP)
            sub.set_defaults(command_row=command, parser=sub)
            if words is not None and method_name not in words:
                continue
            for datum in DATA[method]:
                flags = DATUM_FLAGS.get(datum.name, ("--" + datum.name.replace("_", "-"),))
                counted: dict[str, Any] = {"nargs": 3} if datum.count == 3 else {}
                sub.add_argument(*flags, dest=datum.name, type=_design_number(flags[0]),
                                 required=not datum.optional, help=datum_help(datum), **counted)
            add_options(sub, command.options)
    return parser


def main(argv: Iterable[str] | None = None) -> int:
    """The command line (COMMANDS): the exit status. Every way a run can fail is a line on
    standard error and a non-zero status, never a traceback. argv None: this process's own
    command line, the process the program's: what is alive now (the module and what it
    imported) lives to its end, so the cyclic collector is told not to walk it again (gc.freeze):
    Python's exit collects once more, and a collection of these 16,000 objects took a fifth of
    `python3 -c pass`. And its numpy, if it imports one, starts no BLAS threads where the user
    has not asked for them (OPENBLAS_NUM_THREADS): the program multiplies no matrices, and
    OpenBLAS's pool of a thread a core cost 55 ms of CPU an import here (median of 25
    alternated, a third of numpy's import)."""
    if argv is None:
        import gc
        gc.freeze()
        os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    argv = sys.argv[1:] if argv is None else list(argv)
    _reopen_closed_streams()
    MADE_FOLDERS.clear()
    with signals_caught(), whole_stdout():
        status = 1
        try:
            status = _command(argv)
        finally:
            if status != 0:                     # failed (or argparse's exit): no folder made
                unmake_folders()
        return status


def _command(argv: list[str]) -> int:
    """main's work: the menu program, or the sub-command argv names."""
    try:
        if not argv:
            return menu_program()
        parser = build_parser(argv)
        given = vars(parser.parse_args(argv))
        if given.pop("command") is None:
            parser.error("give a command, or none for the menu program")
        command, sub = given.pop("command_row"), given.pop("parser")
        given["words"] = argv                   # the command line, for what quotes it
        try:
            broken = broken_rule(command.rules, *_options_given(command.options, given))
            if broken is not None:
                raise UsageError(broken)
            status = command.handler(command.typed(given))
        except UsageError as e:
            sub.error(str(e))
        except (CommandError, SceneError) as e:
            return said(e, 1)
        if sys.stdout is not None:
            sys.stdout.flush()                  # here, not at exit: its failure is a status
        return status
    except KeyboardInterrupt as e:
        return said("interrupted", interrupted_status(e))
    except BrokenPipeError as e:                # the reader (head, less) stopped reading
        if e.filename is not None:
            return said(unwritten(e), 1)
        with contextlib.suppress(OSError, ValueError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except OSError as e:                        # standard output full or gone (> /dev/full)
        with contextlib.suppress(OSError, ValueError):
            sys.stdout = None                   # nothing more to flush into it at exit
        return said(unwritten(e), 1)
    except RecursionError as e:
        return said(f"too deeply nested: {e}", 1)
    except MemoryError:
        return said("out of memory", 1)


def _options_given(options: Iterable[Option], given: dict[str, Any]
                   ) -> tuple[dict[str, Any], set[str]]:
    """What each flag of `options` holds in `given` (its default where not typed), and the
    flags typed: holding other than their default (broken_rule's two arguments)."""
    values: dict[str, Any] = {}
    typed: set[str] = set()
    for o in options:
        if not o.names[0].startswith("-"):
            continue
        dest = o.settings.get("dest", o.names[0].lstrip("-").replace("-", "_"))
        value = given.get(dest)
        for flag in o.names:
            values[flag] = value
            if value not in (None, False) and value != o.settings.get("default"):
                typed.add(flag)
    return values, typed


def _reopen_closed_streams() -> None:
    """A standard stream that was closed (`>&-`) is /dev/null at the descriptor, so that no file
    the program opens can take its number and receive what was meant for the screen; Python
    has already made it None, which the program reads as closed."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            with contextlib.suppress(OSError):
                opened = os.open(os.devnull, os.O_RDWR)
                if opened != fd:
                    os.dup2(opened, fd)
                    os.close(opened)


if __name__ == "__main__":
    try:
        sys.exit(main())
    except BrokenPipeError:                      # the reader (head, less) stopped reading
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(141)
