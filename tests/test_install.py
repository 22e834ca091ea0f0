"""The project as a newcomer installs it: a wheel built from the clone, installed in a fresh venv
(no site packages, so nothing of the test environment helps), then run from an empty folder
that has no data/ beside it. The install hint that `--png` prints without matplotlib is run as
printed (the package index is reachable wherever the test set-up could install the test
dependencies), and then the PNG is written."""

import os
import re
import subprocess
import sys
import venv

import pytest

from support.basic_runner import ROOT

pytestmark = pytest.mark.slow       # --quick leaves the whole module out (conftest.py)

# the venv's Python sees none of the test environment's modules, even where PYTHONPATH names the
# clone (whose build leaves a fmb_linkage.egg-info there, and pip would call the wheel installed)
CLEAN = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(the venv's python, the `linkage` command, an empty folder) with the built wheel installed."""
    where = tmp_path_factory.mktemp("install")
    wheels = where / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps",
                    "-q", "-w", str(wheels), str(ROOT)], check=True)
    (wheel,) = wheels.glob("*.whl")
    assert wheel.name.startswith("fmb_linkage-")
    # no pip in the venv: ensurepip's install of pip costs 3.5 s of CPU; this Python's pip
    # installs into the venv instead (`pip --python`), the same pip, the same wheel, the same paths
    venv.EnvBuilder(with_pip=False, clear=True).create(where / "venv")
    python = where / "venv" / "bin" / "python"
    subprocess.run(_pip_for(python, "install", "-q", "--no-deps", str(wheel)),
                   check=True, env=CLEAN)
    empty = where / "empty"
    empty.mkdir()
    return python, where / "venv" / "bin" / "linkage", empty


def _pip_for(python, *args):
    """The command line of pip installing into the venv whose Python is `python`."""
    return [sys.executable, "-m", "pip", "--python", str(python), *args]


def _run(command, folder, *args):
    return subprocess.run([str(command), *args], cwd=folder, capture_output=True, text=True,
                          timeout=300, env=CLEAN)


def test_the_installed_command_lists_the_scenes_by_name_and_title(installed):
    _, linkage, empty = installed
    got = _run(linkage, empty, "scene", "--list")
    assert got.returncode == 0, got.stderr
    names = dict(line.split(None, 1) for line in got.stdout.splitlines())
    scenes = sorted(p.stem for p in (ROOT / "data" / "scenes").glob("*.toml"))
    assert sorted(names) == scenes
    assert names["fig3-plane-four-bar"] == "Fig. 3  Plane four-bar linkage"


def test_the_installed_command_draws_a_design(installed):
    _, linkage, empty = installed
    got = _run(linkage, empty, "design", "fourb-cr-4", "--psi", "60", "--mu-min", "40",
               "--svg", "d.svg")
    assert got.returncode == 0, got.stderr
    assert (empty / "d.svg").read_text().startswith("<svg")


def test_the_png_hint_installs_what_the_png_needs(installed):
    python, linkage, empty = installed
    got = _run(linkage, empty, "scene", "fig3", "--png", "x.png")
    assert got.returncode == 1 and not (empty / "x.png").exists()
    hint = re.search(r"python3 -m pip install (\S+)$", got.stderr.strip())
    assert hint, got.stderr
    assert "linkage" not in hint[1]            # "linkage" on the index is somebody else's
    # as printed, pip told not to compile the packages' bytecode (the PNG's run compiles what it
    # imports: 4 s of pip's 8 s of CPU saved); pip reads PIP_NO_COMPILE as --compile's value,
    # so 0 is --no-compile
    subprocess.run(_pip_for(python, "install", "-q", hint[1]), check=True,
                   timeout=600, env=dict(CLEAN, PIP_NO_COMPILE="0"))
    got = _run(linkage, empty, "scene", "fig3", "--png", "x.png")
    assert got.returncode == 0, got.stderr
    assert "wrote x.png" in got.stderr
    assert (empty / "x.png").read_bytes().startswith(b"\x89PNG")


def test_the_installed_command_prints_the_listing_with_the_scan(installed):
    _, linkage, empty = installed
    got = _run(linkage, empty, "listing", "--ocr")
    assert got.returncode == 0, got.stderr
    assert "* 1265 IF S=1 THEN" in got.stdout and "        scan: 1245 IF S=1 THEN" in got.stdout


def test_the_installed_listing_names_the_installed_errata(installed):
    """`linkage listing` names the ERRATA.md it read, installed under the prefix's
    share/fmb-linkage/legacy_basic (pyproject's data-files), by a path that holds from anywhere:
    not `legacy_basic/ERRATA.md`, relative to a clone the user is not in."""
    python, linkage, empty = installed
    got = _run(linkage, empty, "listing")
    assert got.returncode == 0, got.stderr
    text = " ".join(got.stdout.split())
    named = re.findall(r"([^\s()]*ERRATA\.md)", text)
    assert named, got.stdout[-500:]
    expected = python.parent.parent / "share" / "fmb-linkage" / "legacy_basic" / "ERRATA.md"
    for path in named:
        assert os.path.isabs(path) and os.path.samefile(path, expected), (path, expected)
    assert "kept, K6: The spike at φ = 180°" in got.stdout
