"""What the tests use and what regenerates their data; none of it is a test. A map, one line a file:

basic_runner.py          the one place that runs PC-BASIC (single runs, batched runs, DEFDBL variant)
program.py               the one place that starts linkage.py (as typed, or from cached bytecode)
terminal.py              a program in a pseudo-terminal, for the pty tests
peers.py                 the optional test dependencies, imported where used (need, Peer)
engine_harness.py        the engine's sweeps, the hard catalogue and the scoring rules
engine_reference.py      the 50-digit mpmath reference, written from the geometry
forces_reference.py      the driving torque by the energy balance, the loop closed in mpmath
listing_model.py         the listing's formulas in double precision (or mpmath)
mbf_reference.py         GW-BASIC's arithmetic and number text step by step (test_mbf_fast's reference)
make_golden.py           generator: data/golden/ from PC-BASIC
make_scene_snapshots.py  generator: data/scenes/snapshots/
make_sketches.py         generator: data/sketches/, the README's drawings of the five kinds
make_text_table.py       generator: data/mbf/text_table.tsv from PC-BASIC
bench_accuracy.py        study: what accuracy costs in time, six methods against the reference
bench_peers.py           study: the engine beside a C loop of the same formulas and pylinkage
pylinkage_worst.py       study: the worst pylinkage-engine differences test_pylinkage quotes
synthesis_worst_miss.py  study: each design method's worst miss over log-uniform data

The tests import these as `from support import basic_runner` (pyproject's pytest `pythonpath`
puts tests/ on the path; no module finds another by editing sys.path: only program.py's child,
which is the program, sets its sys.path[0] as `python3 linkage.py` would). The generators and
studies run from the repository's root with the same path the tests have:

    PYTHONPATH=tests python3 -m support.make_golden [CASE ...]
"""
