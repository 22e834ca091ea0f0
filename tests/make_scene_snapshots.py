"""Rewrite the stored text plots of the scenes: data/scenes/snapshots/<scene>.txt.

    python3 tests/make_scene_snapshots.py           # every scene of data/scenes
    python3 tests/make_scene_snapshots.py NAME ...  # only these scenes

Each snapshot is what `python3 linkage.py scene data/scenes/<scene>.toml --text` prints.
tests/test_scenes.py compares the plots with them; this script is the only thing that writes
them - run it when a change to a plot is intended, and look at the diff before committing.
"""

from __future__ import annotations

import contextlib
import io
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
import linkage  # noqa: E402

SCENES = ROOT / "data" / "scenes"
SNAPSHOTS = SCENES / "snapshots"


def snapshot_path(scene: Path) -> Path:
    return SNAPSHOTS / f"{scene.stem}.txt"


def text_plot(scene: Path) -> str:
    out, err = io.StringIO(), io.StringIO()
    with tempfile.TemporaryDirectory() as directory, contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        status = linkage.main(["scene", str(scene), "--dir", directory, "--text"])
    if status:
        raise SystemExit(f"{scene.name}: {err.getvalue().strip()}")
    return out.getvalue()


def main(names) -> None:
    SNAPSHOTS.mkdir(exist_ok=True)
    scenes = [SCENES / f"{n}.toml" for n in names] or sorted(SCENES.glob("*.toml"))
    for scene in scenes:
        path = snapshot_path(scene)
        text = text_plot(scene)
        old = path.read_text(encoding="ascii") if path.exists() else None
        path.write_text(text, encoding="ascii", newline="\n")
        print(f"{path.relative_to(ROOT)}: {'unchanged' if old == text else 'written'}")


if __name__ == "__main__":
    main(sys.argv[1:])
