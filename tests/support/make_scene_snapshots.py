"""Rewrite the stored text plots of the scenes: data/scenes/snapshots/<scene>.txt.

    PYTHONPATH=tests python3 -m support.make_scene_snapshots           # every scene of data/scenes
    PYTHONPATH=tests python3 -m support.make_scene_snapshots NAME ...  # only these scenes

Each snapshot is what `python3 linkage.py scene data/scenes/<scene>.toml --text` prints into a
pipe (80 x 24). A mechanism scene has two: its still frame in Unicode (<scene>.txt, UTF-8) and
in ASCII (<scene>.ascii.txt), as printed where the output's encoding is UTF-8 and where it is
ASCII. tests/test_scenes.py and tests/test_mechanism_text.py compare the plots with them; this
script is the only thing that writes them - run it when a change to a plot is intended, and look
at the diff before committing.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
from pathlib import Path

import linkage

ROOT = Path(__file__).resolve().parents[2]

SCENES = ROOT / "data" / "scenes"
SNAPSHOTS = SCENES / "snapshots"


def snapshot_path(scene: Path, encoding: str = "ascii") -> Path:
    """Where the scene's text plot is kept; a mechanism scene's ASCII frame has a path of its
    own (encoding "ascii" names it; its Unicode frame is the one named by "utf-8")."""
    mechanism = linkage.load_scene(str(scene)).draws_mechanism
    return SNAPSHOTS / f"{scene.stem}{'.ascii' * (mechanism and encoding == 'ascii')}.txt"


def encodings(scene: Path) -> tuple[str, ...]:
    return ("utf-8", "ascii") if linkage.load_scene(str(scene)).draws_mechanism else ("ascii",)


def text_plot(scene: Path, encoding: str = "ascii") -> str:
    """`scene FILE --text` printed into a pipe of this encoding, 80 x 24."""
    raw, err = io.BytesIO(), io.StringIO()
    out = io.TextIOWrapper(raw, encoding=encoding, newline="\n")
    size = {k: os.environ.pop(k, None) for k in ("COLUMNS", "LINES")}
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = linkage.main(["scene", str(scene), "--text"])     # writes no DAT file
            out.flush()
    finally:
        os.environ.update({k: v for k, v in size.items() if v is not None})
    if status:
        raise SystemExit(f"{scene.name}: {err.getvalue().strip()}")
    return raw.getvalue().decode(encoding)


def main(names) -> None:
    SNAPSHOTS.mkdir(exist_ok=True)
    scenes = [SCENES / f"{n}.toml" for n in names] or sorted(SCENES.glob("*.toml"))
    for scene in scenes:
        for encoding in encodings(scene):
            path = snapshot_path(scene, encoding)
            text = text_plot(scene, encoding)
            old = path.read_text(encoding=encoding) if path.exists() else None
            path.write_text(text, encoding=encoding, newline="\n")
            print(f"{path.relative_to(ROOT)}: {'unchanged' if old == text else 'written'}")


if __name__ == "__main__":
    main(sys.argv[1:])
