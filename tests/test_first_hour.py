"""An engineer's first hour (issue 34): every letter defined where it is first met - the README's
first example and each command's --help - the conventions in one README table, one word a thing
(issue 33: `kind`, `class`), design's ratios under names that cannot be taken for run's lengths,
and the listing's reasons beside its corrections."""

from __future__ import annotations

import contextlib
import io
import re

import pytest

import linkage
from support.basic_runner import ROOT

README = (ROOT / "README.md").read_text(encoding="utf-8")
# what each letter of run's dimensions is, in the words a definition must use
ROLES = {"a": "fixed link", "b": "input crank", "c": "coupler", "d": "output crank",
         "e": "offset", "f": "vertical sector", "ksi": "skew angle"}


def help_text(*argv: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit) as done:
        linkage.main([*argv, "--help"])
    assert done.value.code == 0
    return " ".join(out.getvalue().split())          # argparse's wrapping undone


def test_the_readme_defines_the_letters_of_its_first_example():
    """The first `--a` the README shows has a, b, c, d defined within a few lines of it (before
    this, "a is the fixed link" came some 400 lines further down)."""
    lines = README.splitlines()
    first = next(i for i, line in enumerate(lines) if "--a " in line)
    near = " ".join(" ".join(lines[max(0, first - 12):first + 12]).split()).replace("**", "")
    for letter in "abcd":
        assert re.search(rf"\b{letter}\b[^.;]*?{ROLES[letter]}", near), (letter, near)


@pytest.mark.parametrize("command", ["run", "analyse"])
@pytest.mark.parametrize("kind", list(linkage.MECHANISM_TYPES))
def test_the_help_of_a_command_that_takes_dimensions_defines_each_kinds_letters(command, kind):
    """`run --help` and `analyse --help` say, for each kind, which letters it takes and what each
    is (before: `plane: --b --c --d --a`, the letters alone), and each option defines its letter."""
    text = help_text(command)
    said = re.search(rf"\b{re.escape(kind)}: (.*?)[;.](?: |$)", text)
    assert said, (kind, text)
    for letter in linkage.MECHANISM_TYPES[kind][1]:
        assert re.search(rf"--{letter} [^,]*{ROLES[letter]}", said.group(1)), (kind, letter)
        assert re.search(rf"--{letter} X {letter}, [^-]*{ROLES[letter]}", text), letter
