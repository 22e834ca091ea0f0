"""Rewrite the explorer's stored sessions: data/explore/<session>.keys and <session>.screen.

    PYTHONPATH=tests python3 -m support.make_explore_screens              # every session
    PYTHONPATH=tests python3 -m support.make_explore_screens NAME ...     # only these

SESSIONS is the one table of them: each a command line of `explore` and the keys it is given
(a key file: one key a line, a character or a key's name). The screen is what
`python3 linkage.py explore ARGS --keys NAME.keys` prints into a UTF-8 pipe, run in an empty
folder (a session that saves writes there). tests/test_explore.py replays every session and
compares; this script is the only thing that writes the stored screens - run it when a change
to the screen is intended, and look at the diff before committing.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import tempfile
from pathlib import Path

import linkage

ROOT = Path(__file__).resolve().parents[2]
SESSIONS_FOLDER = ROOT / "data" / "explore"
PLANE = ["plane", "--a", "6", "--b", "2", "--c", "7", "--d", "9"]


def _each_dimension(kind: str) -> list[str]:
    """Every dimension of the kind and the coupler point selected in turn (Tab) and changed by
    small and large steps both ways, then one selected by its letter and typed."""
    names = list(linkage.LINKAGE_DIMENSIONS[kind]) + (["u"] if kind in ("skew", "skew-slider")
                                                      else ["u", "v"])
    keys = []
    for i, _ in enumerate(names):
        keys += ["Right", "Right", "S-Right", "Left", "["] + ["Tab"] * (i + 1 < len(names))
    return keys + ["Tab", "B", "=", "2", ".", "5", "Enter", "Tick", "Tick", "Tick"]


SESSIONS: dict[str, tuple[list[str], list[str]]] = {
    **{f"change-{kind}": ([kind], _each_dimension(kind)) for kind in linkage.LINKAGE_DIMENSIONS},
    "help": (PLANE, ["?"]),
    "help-closed": (PLANE, ["?", "x"]),
    "help-while-playing": (PLANE, ["?", "Tick", "Tick"]),
    "not-assembling": (PLANE, ["B", "=", "3", "0", "Enter", "Tick", "Tick"]),
    "not-assembling-and-back": (PLANE, ["B", "=", "3", "0", "Enter", "Tick", "u", "Tick"]),
    "stops-at-dead-centre": (PLANE, ["B", "=", "5", "Enter"] + ["Tick"] * 40),
    "stops-then-plays-back": (PLANE, ["B", "=", "5", "Enter"] + ["Tick"] * 40
                              + ["Space"] + ["Tick"] * 5),
    "steps-to-not-assembling": (PLANE, ["B"] + ["S-Right"] * 25),
    "undo": (PLANE, ["A", "Right", "C", "S-Right", "b", "u", "u", "Tick"]),
    "undo-nothing": (PLANE, ["u"]),
    "refused-typed": (PLANE, ["=", "1", "e", "Enter"]),
    "refused-zero": (PLANE, ["B", "=", "0", "Enter"]),
    "refused-typing-left": (PLANE, ["=", "7", "Esc"]),
    "branch": (PLANE, ["b", "Tick", "Tick"]),
    "follow": (["plane", "--a", "6", "--b", "3", "--c", "6", "--d", "3"], ["f", "Tick"]),
    "coupler": (PLANE, ["U", "S-Right", "V", "Left", "Tick", "Tick"]),
    "coupler-off": (PLANE, ["c"]),
    "kinds": (PLANE, ["k", "k", "Tick"]),
    "kinds-round": (PLANE, ["k"] * 5),
    "play-step-speed": (PLANE, ["Space", ".", ".", ".", ",", "+", "+", "-"]),
    "save": (PLANE, ["C", "Right", "s", "Enter"]),
    "save-asks": (PLANE, ["s", "Enter", "s", "Enter", "n", "s", "Enter", "y"]),
    "save-named": (PLANE, ["s", "Backspace", "Backspace", "Backspace", "Backspace", "Backspace",
                           "x", ".", "t", "o", "m", "l", "Enter"]),
    "scene": (["fig1c"], ["Tick"]),
    "wide-160x48": (PLANE + ["--size", "160x48"], ["D", "S-Right", "Tick", "Tick", "Tick"]),
    "spherical-typed": (["spherical"], ["B", "=", "5", "0", "Enter"] + ["Tick"] * 3),
    "dynamics": (["forces-plane-crank-rocker"], ["Tick"] * 3 + ["B", "=", "0", ".", "2", "5",
                                                                "Enter", "Tick"]),
    "dynamics-wide": (["forces-skew-four-bar", "--size", "160x48"], ["Tick"] * 5),
}


def screen(args: list[str], keys_file: Path, folder: str) -> str:
    """What `explore ARGS --keys FILE` prints into a UTF-8 pipe, run in `folder`."""
    raw, err = io.BytesIO(), io.StringIO()
    out = io.TextIOWrapper(raw, encoding="utf-8", newline="\n")
    here = os.getcwd()
    try:
        os.chdir(folder)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = linkage.main(["explore", *args, "--keys", str(keys_file)])
            out.flush()
    finally:
        os.chdir(here)
    if status:
        raise SystemExit(f"{keys_file.name}: {err.getvalue().strip()}")
    return raw.getvalue().decode("utf-8")


def keys_text(keys: list[str]) -> str:
    return "".join(key + "\n" for key in keys)


def main(names: list[str]) -> None:
    SESSIONS_FOLDER.mkdir(exist_ok=True)
    for name in names or list(SESSIONS):
        args, keys = SESSIONS[name]
        keys_path = SESSIONS_FOLDER / f"{name}.keys"
        keys_path.write_text(keys_text(keys), encoding="utf-8", newline="\n")
        with tempfile.TemporaryDirectory() as folder:
            text = screen(args, keys_path, folder)
        path = SESSIONS_FOLDER / f"{name}.screen"
        old = path.read_text(encoding="utf-8") if path.exists() else None
        path.write_text(text, encoding="utf-8", newline="\n")
        print(f"{path.relative_to(ROOT)}: {'unchanged' if old == text else 'written'}")


if __name__ == "__main__":
    main(sys.argv[1:])
