"""Redraw the PNGs the README shows from data/scenes: data/scenes/<scene>.png.

    PYTHONPATH=tests python3 -m support.make_scene_pngs           # every stored PNG
    PYTHONPATH=tests python3 -m support.make_scene_pngs NAME ...  # only these scenes

Each PNG is what `python3 linkage.py scene data/scenes/<scene>.toml --png <scene>.png` draws, at
the options PNG_OPTIONS gives it (the README's two-column pictures are 720 x 500; the rest take the
scene's own size). This script is the only thing that writes them: run it when a drawing changes,
and look at every PNG it rewrote before committing (matplotlib is needed; the tests check only
that every stored PNG has its row here and its scene beside it).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "data" / "scenes"

# The stored PNGs, each with the options it is drawn with (none: the scene's own size).
PNG_OPTIONS: dict[str, tuple[str, ...]] = {
    "coupler-plane-four-bar": ("--size", "720x500"),
    "coupler-plane-slider-crank": ("--size", "720x500"),
    "coupler-skew-four-bar": ("--size", "720x500"),
    "coupler-skew-slider-crank": ("--size", "720x500"),
    "coupler-spherical-four-bar": ("--size", "720x500"),
    "fig3-plane-four-bar": (),
    "forces-arrows-crank-rocker": ("--size", "720x500", "--dpi", "72"),
    "forces-follow-change-point": (),
    "forces-plane-crank-rocker": (),
    "forces-skew-four-bar": (),
    "forces-slider-crank-engine": (),
    "forces-spherical-four-bar": (),
    "simulate-engine-flywheel": (),
    "simulate-engine-run-up": (),
    "simulate-released-four-bar": (),
    "simulate-released-spherical": (),
    "simulate-rhombus": (),
}


def command(name: str) -> list[str]:
    """The command that draws the scene's stored PNG, as a user would type it."""
    return ([sys.executable, str(ROOT / "linkage.py"), "scene", str(SCENES / f"{name}.toml"),
             "--png", str(SCENES / f"{name}.png"), *PNG_OPTIONS[name]])


def main(names: list[str]) -> int:
    unknown = [name for name in names if name not in PNG_OPTIONS]
    if unknown:
        print(f"no stored PNG for: {', '.join(unknown)}", file=sys.stderr)
        return 2
    for name in names or list(PNG_OPTIONS):
        print(" ".join(command(name)[1:]), flush=True)
        subprocess.run(command(name), check=True, stdout=subprocess.DEVNULL)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
