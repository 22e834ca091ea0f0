"""How the tests start the program, in one place.

SCRIPT is the user's own command, `python3 linkage.py` (the README's). Python compiles a script
anew at every start (its 350 kB take a tenth of a second), so the hundreds of command-line tests
use PROGRAM instead: this file run as a script starts this checkout's linkage.py as `__main__`,
as the script does (same sys.argv[0], sys.path[0] and exit status), but through the import system,
which reads the bytecode that conftest.py compiles once a run (`compile_once`). The bytecode is
checked against the source's hash at every start, so an edited linkage.py is never run stale.
"""

import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SOURCE = os.path.join(ROOT, "linkage.py")
SCRIPT = [sys.executable, SOURCE]
PROGRAM = [sys.executable, os.path.abspath(__file__)]


def compile_once() -> None:
    """Write linkage.py's bytecode where the import system looks for it (__pycache__), checked by
    the source's hash; where that cannot be written, each start compiles the source instead."""
    import py_compile
    try:
        py_compile.compile(SOURCE, doraise=True,
                           invalidation_mode=py_compile.PycInvalidationMode.CHECKED_HASH)
    except OSError:
        pass


if __name__ == "__main__":
    import runpy
    sys.path[0] = ROOT                    # where `python3 linkage.py` puts the script's folder
    runpy.run_module("linkage", run_name="__main__", alter_sys=True)
