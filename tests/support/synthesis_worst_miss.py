"""Per synthesis method, the worst miss between what the analysed linkage does and what the method
prescribes (or the design claims): over the review's worked example, over random feasible
designs, and over data drawn log-uniformly across each method's valid range (linkage.DATA; the
long, unseeded run of the test test_synthesis.test_every_method_meets_its_targets_in_range).
Every number is measured through linkage.analyze (the accurate engine).

    PYTHONPATH=tests python3 -m support.synthesis_worst_miss (from the repository's root)
        [designs per method, default 200] [seed, default 1; "random": a new one]
        [--log-uniform-only] [--module PATH/linkage.py: design and analyse with another version of
        the module (the data ranges stay this one's)]
"""

from __future__ import annotations

import importlib.util
import math
import random
import sys

import linkage as s
import test_synthesis as t


def random_designs(method, rng, count):
    """Up to `count` designs of `method` for random feasible data: data measured on random real
    linkages where the method can take any linkage, else random data the method accepts."""
    u = rng.random
    made, tries = [], 0
    while len(made) < count and tries < 50 * count:
        tries += 1
        try:
            if method == "FOURB-CR-1" or method == "FOURB-CR-2":
                found = t.crank_rocker_data(u(), u(), u())
                if found is None:
                    continue
                _, d = found
                result = (s.fourb_cr_1(d["theta"], d["psi"], d["theta0"]) if method == "FOURB-CR-1"
                          else s.fourb_cr_2(d["theta"], d["psi"], d["psi0"]))
            elif method == "FOURB-CR-3":
                result = s.fourb_cr_3(rng.choice([-1, 1]) * rng.uniform(1, 60),
                                      rng.uniform(10, 160))
            elif method == "FOURB-CR-4":
                psi = rng.uniform(5, 170)
                result = s.fourb_cr_4(psi, rng.uniform(1, 89 - psi / 2))
            elif method == "VOLMER":
                psi = rng.uniform(5, 170)
                result = s.volmer_crank_rocker(psi, rng.uniform(1, 89 - psi / 2))
            elif method == "DRAGLINK-1":
                result = s.draglink_1(rng.uniform(10, 350), rng.uniform(5, 85))
            elif method == "DRAGLINK-2":
                if u() < 0.5:
                    found = t.drag_link_data(u(), u(), u())
                    if found is None:
                        continue
                    d = found[1]
                    result = s.draglink_2(d["dphi"], d["dpsi"], d["lam"])
                else:
                    result = s.draglink_2(rng.uniform(95, 265), rng.uniform(20, 250))
            elif method == "FOURB-FG2-1":
                result = s.fourb_fg2_1(rng.uniform(-150, 150), rng.uniform(-150, 150),
                                       rng.uniform(-180, 180), rng.uniform(0.2, 4),
                                       rng.uniform(0.2, 4))
            elif method == "FOURB-FG3-1":
                link = s.FourBar(1.0, rng.uniform(0.3, 3.3), rng.uniform(0.3, 3.3),
                                 rng.uniform(0.3, 3.3), rng.choice([1, 2]))
                phi1 = rng.uniform(-180, 180)
                phis = [phi1, phi1 + rng.uniform(5, 60)]
                phis.append(phis[1] + rng.uniform(5, 60))
                outs = [s._output(link, p) for p in phis]
                if None in outs:
                    continue
                result = s.fourb_fg3_1(phis, [o + 180 for o in outs])
            else:
                found = t.slider_data(u(), u(), u())
                if found is None:
                    continue
                link, epsilon, m = found
                if method == "SLID-FG2-1":
                    if abs(epsilon) < 1e-6:
                        continue
                    result = s.slid_fg2_1((m.output_min.phi - m.output_max.phi) % 360,
                                          m.output_max.value - m.output_min.value, epsilon)
                else:
                    result = s.slid_fg2_2(s.wrap_degrees(m.output_max.phi),
                                          s.wrap_degrees(m.output_min.phi + 180),
                                          m.output_max.value, m.output_min.value, 1e-7)
        except s.DesignError:
            continue
        made.extend(result.solutions)
    return made[:count]


def worst(designs):
    """The worst miss per unit over the designs' checks: {unit: (miss, check name)}, and how many
    designs were near-locking (tolerance widened)."""
    out, near = {}, 0
    for design in designs:
        near += s.conditioning(design) > 1
        size = max(abs(x) for x in design.linkage[:-1])
        for check in s.analyze_design(design):
            unit = "angle" if check.unit in ("deg", "rotation") else check.unit
            miss = check.miss / size if unit == "length" else check.miss
            if unit not in out or miss > out[unit][0]:
                out[unit] = (miss, check.name)
    return out, near


def main(argv):
    module = s
    if "--module" in argv:
        at = argv.index("--module")
        spec = importlib.util.spec_from_file_location("linkage_other", argv[at + 1])
        module = sys.modules["linkage_other"] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        argv = argv[:at] + argv[at + 2:]
    only = "--log-uniform-only" in argv
    argv = [a for a in argv if a != "--log-uniform-only"]
    count = int(argv[1]) if len(argv) > 1 else 200
    seed = (random.randrange(10 ** 6) if argv[2] == "random" else int(argv[2])) \
        if len(argv) > 2 else 1
    if not only:
        worst_feasible(count, seed)
    log_uniform_table(module, count, seed)
    return 0


def worst_feasible(count, seed):
    """Print the table of the worked examples and random feasible designs."""
    rng = random.Random(seed)
    examples = {name: run() for name, run in t.RUNS.items() if name != "SLID-FG2-2"}
    examples["SLID-FG2-2"] = None                          # its example data are inconsistent (S8)
    print(f"# Worst miss per method: measured on the analysed linkage (synthesis.analyze) against "
          f"the prescription\n# random: {count} designs per method, seed {seed}; angles in degrees,"
          f" lengths relative to the longest link\n")
    print("| method | example: worst angle miss (check) | random designs | worst angle miss (check)"
          " | worst length miss | worst velocity-ratio miss | near-locking |")
    print("|---|---|---|---|---|---|---|")
    total = 0.0
    for method in t.RUNS:
        result = examples[method]
        if result is None:
            example = "refused (S8)"
        else:
            w, _ = worst(result.solutions)
            example = f"{w['angle'][0]:.1e} ({w['angle'][1]})"
        designs = random_designs(method, rng, count)
        w, near = worst(designs)
        angle = w.get("angle", (math.nan, ""))
        length = f"{w['length'][0]:.1e}" if "length" in w else "-"
        ratio = f"{w['ratio'][0]:.1e}" if "ratio" in w and method == "DRAGLINK-2" else "-"
        total = max(total, angle[0])
        print(f"| {method} | {example} | {len(designs)} | {angle[0]:.1e} ({angle[1]}) | {length} "
              f"| {ratio} | {near} |")
    print(f"\nworst angle miss over all methods: {total:.1e} degree "
          f"(tolerance {s.ANGLE_TOLERANCE:g}, widened as 1/sin(mu) for near-locking designs)")


def log_uniform(module, method, rng, count):
    """`count` draws of data log-uniform across the method's valid range (test_synthesis.
    data_in_range): how many were designed, refused and crashed (any exception but DesignError,
    with the first one), and the worst misses of the designs."""
    function = getattr(module, t.FUNCTIONS[method].__name__)
    designed = refused = 0
    beyond = []
    crashes, worst_ = [], {"angle": (0.0, "", None), "length": (0.0, "", None),
                           "ratio": (0.0, "", None)}
    for _ in range(count):
        data = t.data_in_range(method, [rng.random() for _ in range(t.units_needed(method))])
        try:
            result = function(*data.values())
        except module.DesignError:
            refused += 1
            continue
        except Exception as error:                                      # noqa: BLE001
            crashes.append(f"{data}: {type(error).__name__}: {error}")
            continue
        designed += 1
        for design in result.solutions:
            if module is s:
                try:
                    t.assert_meets_targets(design)
                except AssertionError:
                    beyond.append(data)
            for unit, (miss, name) in t.design_misses(design, module).items():
                if miss > worst_[unit][0]:
                    worst_[unit] = (miss, name, data)
    return designed, refused, crashes, worst_, beyond


def log_uniform_table(module, count, seed):
    """Print the log-uniform table: per method, the worst misses and the data that give them."""
    rng = random.Random(seed)
    print(f"\n# Log-uniform data across each method's valid range (linkage.DATA), {count} draws a "
          f"method, seed {seed}, module {module.__file__}\n")
    print("| method | designed | refused | crashed | worst angle miss (check) | worst length miss |"
          " worst velocity-ratio miss | beyond the targets |")
    print("|---|---|---|---|---|---|---|---|")
    notes, total = [], 0.0
    for method in s.DATA:
        designed, refused, crashes, w, beyond = log_uniform(module, method, rng, count)
        angle, length, ratio = w["angle"], w["length"], w["ratio"]
        total = max(total, angle[0])
        print(f"| {method} | {designed} | {refused} | {len(crashes)} | {angle[0]:.1e} ({angle[1]})"
              f" | {length[0]:.1e} | {ratio[0]:.1e} | {len(beyond) if module is s else '-'} |")
        if angle[2] is not None:
            notes.append(f"{method}: worst angle miss {angle[0]:.3g} at {angle[2]}")
        notes += [f"{method}: crash {c}" for c in crashes[:2]]
        notes += [f"{method}: beyond the targets at {b}" for b in beyond[:3]]
    print(f"\nworst angle miss over all methods: {total:.1e} degree; beyond the targets: a miss "
          f"over 1e-9 degree (lengths 1e-12) and over 4 times what rounding the lengths alone "
          f"causes (test_synthesis.assert_meets_targets)")
    for note in notes:
        print(note)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
