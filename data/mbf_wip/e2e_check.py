"""Compare the model's ANG/VEL/ACC lines with PC-BASIC's (e2e/*.DAT)."""
import os
import mbf
from bench_mbf import sweep_point, PI, K180

d = os.path.join(os.path.dirname(os.path.abspath(__file__)), "e2e")
real = [open(os.path.join(d, n), "rb").read().decode("latin-1").rstrip("\x1a").split("\r\n")
        for n in ("ANG.DAT", "VEL.DAT", "ACC.DAT")]
lo = mbf.mul(mbf.div(0.0, K180), PI)
hi = mbf.mul(mbf.div(mbf.parse("360"), K180), PI)
inc = mbf.mul(mbf.div(1.0, K180), PI)
model = [[], [], []]
for phi in mbf.for_values(lo, hi, inc):
    for i, line in enumerate(sweep_point(phi)):
        model[i].append(line)
for name, r, m in zip(("ANG", "VEL", "ACC"), real, model):
    r = [l for l in r if l]
    same = sum(1 for a, b in zip(r, m) if a == b)
    print(name, "lines real %d model %d identical %d (%.1f%%)" % (len(r), len(m), same, 100.0 * same / max(len(r), 1)))
