"""linkage: Freudenstein and Mohammad Beigi's microcomputer kinematic analysis of the basic
linkage mechanisms (plane, spherical and skew four-bar; plane and skew slider-crank), ported
from the IBM-PC BASIC program of their paper (Mechanism and Machine Theory, 1980s).

Not written yet. What exists today is the reference it will be held against:
legacy_basic/LINKAGE.BAS (the paper's listing with its scan errors corrected, see
legacy_basic/ERRATA.md) and the golden files that PC-BASIC 2.0.8 writes when running it
(data/golden/). The port itself is the subject of the project's next issues.
"""

import sys

__version__ = "0.1.0"


def main(argv=None) -> int:
    print("linkage.py: the port is not written yet; run legacy_basic/LINKAGE.BAS under "
          "PC-BASIC (see README.md)", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
