"""The worst differences between pylinkage and the engine over many random sweeps, as
tests/test_pylinkage.py compares them (its compare_four_bar and compare_slider): the numbers its
docstring quotes.

    PYTHONPATH=tests python3 -m support.pylinkage_worst [four-bars, default 1500] [seed, default 1]
"""

from __future__ import annotations

import random
import sys

import test_pylinkage as t


def main(count=1500, seed=1):
    rng = random.Random(seed)

    def length():
        return rng.choice([rng.uniform(0.3, 10), float(rng.randint(1, 10)), rng.uniform(0.3, 1.5)])
    worst, counts, sweeps, disagree = {}, {}, 0, []
    for _ in range(count):
        a, b, c, d = length(), length(), length(), length()
        if rng.random() < 0.2:
            c, d = a, b                                   # a parallelogram: change points
        phi0 = rng.choice([rng.uniform(-180, 180), float(rng.randint(-180, 180))])
        if not t.startable(a, b, c, d, phi0):
            continue
        for pylinkage_branch in (0, 1):
            compared, disagreements = t.compare_four_bar(a, b, c, d, phi0, pylinkage_branch)
            sweeps += 1
            disagree += [((a, b, c, d), phi, what) for phi, what in disagreements]
            for what, phi, error, k in compared:
                counts[what] = counts.get(what, 0) + 1
                if error >= worst.get(what, (-1,))[0]:
                    worst[what] = (error, (a, b, c, d), phi, k)
    print(f"four-bars: {sweeps:,} sweeps of {t.STEPS} points, seed {seed}")
    for what, (error, dims, phi, k) in worst.items():
        print(f"  {what:12} {counts[what]:9,} points, worst {error:.1e} at a, b, c, d = {dims}, "
              f"phi {phi:.6g} (K {k:.3g})")
    print(f"  one assembles, the other not: {len(disagree)} {disagree[:5]}")
    worst, points = {}, 0
    for _ in range(400):
        b, e, margin = rng.uniform(0.3, 10), rng.uniform(-5, 5), rng.uniform(0.1, 2)
        for what, phi, error in t.compare_slider(b, e, margin, rng.uniform(-180, 180)):
            points += what == "output"
            worst[what] = max(worst.get(what, 0.0), error)
    print(f"slider-cranks: {points:,} points, worst "
          + ", ".join(f"{what} {error:.1e}" for what, error in worst.items()))


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
