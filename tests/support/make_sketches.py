"""Draw the README's sketches of the five kinds, their letters on their links:
data/sketches/<kind>.svg.

    PYTHONPATH=tests python3 -m support.make_sketches

Each is the program's own drawing (`python3 linkage.py scene FILE --svg OUT`) of the paper's
Fig. 1 or 2 scene (data/scenes/fig1a-... to fig2b-...) at one input angle, ANGLES below: the
scene file is copied with `angles = [PHI]` in its mechanism panel, so that the drawing is one
still position rather than the animation.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import linkage

ROOT = Path(__file__).resolve().parents[2]
SKETCHES = ROOT / "data" / "sketches"
# kind: (its scene, the input angle drawn: one where the letters stand clear of each other)
ANGLES = {
    "plane": ("fig1a-plane-four-bar", 300),
    "spherical": ("fig1b-spherical-four-bar", 60),
    "skew": ("fig1c-skew-four-bar", 60),
    "slider": ("fig2a-plane-slider-crank", 60),
    "skew-slider": ("fig2b-skew-slider-crank", 60),
}
PANEL = 'quantities = ["mechanism"]'


def main() -> None:
    SKETCHES.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        for kind, (scene, phi) in ANGLES.items():
            text = (ROOT / "data" / "scenes" / f"{scene}.toml").read_text(encoding="utf-8")
            if text.count(PANEL) != 1:
                raise SystemExit(f"{scene}: not one mechanism panel")
            copy = Path(folder) / f"{scene}.toml"
            copy.write_text(text.replace(PANEL, f"{PANEL}\nangles = [{phi}]"), encoding="utf-8")
            out = SKETCHES / f"{kind}.svg"
            if linkage.main(["scene", str(copy), "--svg", str(out)]):
                raise SystemExit(f"{scene}: not drawn")


if __name__ == "__main__":
    main()
