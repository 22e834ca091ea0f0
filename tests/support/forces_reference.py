"""An engine-independent reference for linkage.forces: each linkage's loop closed in mpmath (50
digits) from the joint geometry linkage.joint_positions documents, by its own closed-form roots;
the bodies' positions, velocities and accelerations by central differences in time (5-point
stencils, step 1e-12 of 1/omega: truncation ~1e-48, rounding ~1e-26), the kinetic and potential
energy by their definitions (a uniform rod's by integrating along it), and the driving torque by
the energy balance T omega = dE/dt - (the loads' power), the crank at phi0 + omega t + alpha t^2/2.

The engine is asked for nothing but its output at phi0, to pick which of the two roots of the
closure is the branch."""

from __future__ import annotations

import mpmath
from mpmath import mp, mpf

import linkage

DIGITS = 50
STENCIL = range(-4, 5)      # the time grid t_j = j h: velocities at j = -2..2, E's rate at 0


def vec(*xs):
    return [mpf(x) for x in xs]


def add(*terms):
    """The sum of (coefficient, vector) terms."""
    out = [mpf(0)] * 3
    for k, v in terms:
        out = [o + k * x for o, x in zip(out, v)]
    return out


def sub(p, q):
    return [a - b for a, b in zip(p, q)]


def dotp(u, v):
    return sum(a * b for a, b in zip(u, v))


def crossp(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def unit(v):
    n = mpmath.sqrt(dotp(v, v))
    return [x / n for x in v]


def cos_sin(deg):
    r = mpmath.radians(mpf(deg))
    return mpmath.cos(r), mpmath.sin(r)


class Geometry:
    """A linkage's joints in mpmath, as joint_positions documents them (lengths in metres; the
    spherical four-bar on a sphere of `radius`)."""

    def __init__(self, kind, dims, radius=1):
        with mp.workdps(DIGITS):
            self.kind, self.radius = kind, mpf(radius)
            d = {k: mpf(v) for k, v in dims.items()}
            self.d = d
            z = vec(0, 0, 1)
            if kind == "plane":
                self.pivot, self.axis = vec(d["a"], 0, 0), z
                self.e1, self.e2 = vec(1, 0, 0), vec(0, 1, 0)
            elif kind == "skew":
                cx, sx = cos_sin(d["ksi"])
                self.pivot, self.axis = vec(d["a"], d["f"] * sx / cx, 0), vec(0, -sx, cx)
                self.e1, self.e2 = vec(1, 0, 0), vec(0, cx, sx)
            elif kind == "spherical":
                ca, sa = cos_sin(d["a"])
                self.pivot, self.axis = vec(0, 0, 0), vec(sa, 0, ca)
                self.e1, self.e2 = vec(ca, 0, -sa), vec(0, 1, 0)
            elif kind == "slider":
                self.start, self.guide = vec(0, d["e"], 0), vec(1, 0, 0)
            else:
                cx, sx = cos_sin(d["ksi"])
                self.start, self.guide = vec(d["a"], 0, d["f"]), vec(0, sx, -cx)
            self.sliding = kind in ("slider", "skew-slider")

    def crank_pin(self, phi):
        """A at phi radians."""
        c, s = mpmath.cos(phi), mpmath.sin(phi)
        if self.kind == "spherical":
            cb, sb = cos_sin(self.d["b"])
            return [self.radius * x for x in (sb * c, sb * s, cb)]
        return [self.d["b"] * c, self.d["b"] * s, mpf(0)]

    def output_pin(self, q):
        """B at psi = q radians, or the slider C at x = q."""
        if self.sliding:
            return add((1, self.start), (q, self.guide))
        if self.kind == "spherical":
            cd, sd = cos_sin(self.d["d"])
            return [self.radius * x for x in add((cd, self.axis), (sd * mpmath.cos(q), self.e1),
                                                 (sd * mpmath.sin(q), self.e2))]
        return add((1, self.pivot), (self.d["d"] * mpmath.cos(q), self.e1),
                   (self.d["d"] * mpmath.sin(q), self.e2))

    def output(self, a, near):
        """The root of the loop closure for the crank pin a nearest `near` (radians, or x)."""
        if self.sliding:
            w = sub(self.start, a)
            beta, gamma = dotp(self.guide, w), dotp(w, w) - self.d["c"] ** 2
            root = mpmath.sqrt(beta * beta - gamma)
            return min((-beta + root, -beta - root), key=lambda x: abs(x - near))
        if self.kind == "spherical":
            cd, sd = cos_sin(self.d["d"])
            u = [x / self.radius for x in a]
            k1, k2 = sd * dotp(u, self.e1), sd * dotp(u, self.e2)
            k3 = cos_sin(self.d["c"])[0] - cd * dotp(u, self.axis)
        else:
            w = sub(self.pivot, a)
            k1, k2 = 2 * self.d["d"] * dotp(w, self.e1), 2 * self.d["d"] * dotp(w, self.e2)
            k3 = self.d["c"] ** 2 - self.d["d"] ** 2 - dotp(w, w)
        mid, half = mpmath.atan2(k2, k1), mpmath.acos(k3 / mpmath.hypot(k1, k2))
        roots = [mid + half, mid - half]
        return min((r - 2 * mpmath.pi * mpmath.nint((r - near) / (2 * mpmath.pi)) for r in roots),
                   key=lambda r: abs(r - near))


def frames(g, a, p):
    """Each body's frame (origin, (x, y, z)) as forces' notes document them."""
    z = vec(0, 0, 1)
    x = unit([a[0], a[1], mpf(0)])
    crank = (vec(0, 0, 0), (x, crossp(z, x), z))
    if g.kind == "spherical":
        x, zc = unit(a), unit(crossp(a, p))
        coupler = (vec(0, 0, 0), (x, crossp(zc, x), zc))
    else:
        x = unit(sub(p, a))
        if g.kind in ("plane", "slider"):
            coupler = (a, (x, crossp(z, x), z))
        else:       # any axes square to the line: its mass is on the line, axisymmetric
            y = unit(crossp(x, vec(1, 2, 3)))
            coupler = (a, (x, y, crossp(x, y)))
    if g.sliding:
        side = vec(0, 1, 0) if g.kind == "slider" else vec(1, 0, 0)
        output = (p, (g.guide, side, crossp(g.guide, side)))
    else:
        arm = sub(p, g.pivot)
        x = unit(add((1, arm), (-dotp(arm, g.axis), g.axis)))
        output = (g.pivot, (x, crossp(g.axis, x), g.axis))
    return crank, coupler, output


def in_world(axes, v):
    return add(*((mpf(k), e) for k, e in zip(v, axes)))


def first(values, h):
    """d/dt at the middle of five equally spaced values (vectors or numbers)."""
    k = [mpf(1), mpf(-8), mpf(0), mpf(8), mpf(-1)]
    if isinstance(values[0], list):
        return [sum(c * v[i] for c, v in zip(k, values)) / (12 * h) for i in range(3)]
    return sum(c * v for c, v in zip(k, values)) / (12 * h)


def second(values, h):
    k = [mpf(-1), mpf(16), mpf(-30), mpf(16), mpf(-1)]
    if isinstance(values[0], list):
        return [sum(c * v[i] for c, v in zip(k, values)) / (12 * h * h) for i in range(3)]
    return sum(c * v for c, v in zip(k, values)) / (12 * h * h)


def local_body(kind, role, body):
    """(mass, centre, inertia rows) in the body's frame from a linkage.Body with a centre and an
    inertia, as forces' notes document them (plane: scalar centres, (u, v), scalar inertia)."""
    m = mpf(body.mass)
    if kind in ("plane", "slider"):
        centre = (list(body.centre) + [0] if role == "coupler" else [body.centre, 0, 0])
        inertia = [[0, 0, 0], [0, 0, 0], [0, 0, body.inertia]]
    else:
        centre, inertia = list(body.centre), [list(row) for row in body.inertia]
    return m, [mpf(c) for c in centre], [[mpf(x) for x in row] for row in inertia]


class Motion:
    """The linkage's bodies on the time grid about t = 0: positions and frames at each t_j."""

    def __init__(self, kind, dims, phi0_deg, output0, omega, alpha, radius=1):
        with mp.workdps(DIGITS):
            g = self.g = Geometry(kind, dims, radius)
            self.omega, self.alpha = mpf(omega), mpf(alpha)
            self.h = mpf("1e-12") / max(abs(self.omega), 1)
            near = mpf(output0) if g.sliding else mpmath.radians(mpf(output0))
            phi0 = mpmath.radians(mpf(phi0_deg))
            self.poses = []
            for j in STENCIL:
                t = j * self.h
                a = g.crank_pin(phi0 + self.omega * t + self.alpha * t * t / 2)
                q = g.output(a, near)
                p = g.output_pin(q)
                self.poses.append((q, a, p, frames(g, a, p)))

    def series(self, f):
        """f(pose) at every t_j."""
        return [f(pose) for pose in self.poses]

    def velocities(self, f):
        """d/dt of f(pose) at j = -2..2 (five values)."""
        values = self.series(f)
        return [first(values[i - 2:i + 3], self.h) for i in range(2, 7)]

    def body_point(self, body, local):
        """A point fixed in body (0 crank, 1 coupler, 2 output) at its local coordinates."""
        def at(pose):
            origin, axes = pose[3][body]
            return add((1, origin), (1, in_world(axes, local)))
        return at

    def spin(self, body):
        """The body's angular velocity at j = -2..2: 1/2 sum e_i x de_i/dt; the skew kinds'
        coupler turning square to its line (no spin about it): r x dr/dt / |r|^2."""
        if body == 1 and self.g.kind in ("skew", "skew-slider"):
            r = self.series(lambda pose: sub(pose[2], pose[1]))
            out = []
            for i in range(2, 7):
                rate = first(r[i - 2:i + 3], self.h)
                out.append([x / dotp(r[i], r[i]) for x in crossp(r[i], rate)])
            return out
        rates = [self.velocities(lambda pose, i=i: pose[3][body][1][i]) for i in range(3)]
        axes = [pose[3][body][1] for pose in self.poses[2:7]]
        return [add(*((mpf(1) / 2, crossp(axes[j][i], rates[i][j])) for i in range(3)))
                for j in range(5)]


def _energy(motion, kind, bodies, gravity):
    """KE and PE at j = -2..2."""
    g = motion.g
    kinetic, potential = [mpf(0)] * 5, [mpf(0)] * 5
    if kind == "spherical":      # the pivots where the axes meet the sphere
        a0, b0 = vec(0, 0, g.radius), [g.radius * x for x in g.axis]
    else:
        a0, b0 = vec(0, 0, 0), getattr(g, "pivot", None)
    joints = {0: (lambda pose: a0, lambda pose: pose[1]),
              1: (lambda pose: pose[1], lambda pose: pose[2]),
              2: (lambda pose: b0, lambda pose: pose[2])}
    for body, role in enumerate(("crank", "coupler", "output")):
        spec = getattr(bodies, role)
        m = mpf(spec.mass)
        if spec.centre is None:
            one, two = joints[body]
            if body == 2 and g.sliding:
                v = motion.velocities(two)
                pos = motion.series(two)[2:7]
                ke = [m * dotp(x, x) / 2 for x in v]
                pe = [-m * dotp(gravity, x) for x in pos]
            elif kind == "spherical":
                ke, pe = _arc_energy(motion, m, one, two, gravity)
            else:
                v1, v2 = motion.velocities(one), motion.velocities(two)
                mid = [add((mpf(1) / 2, p), (mpf(1) / 2, q))
                       for p, q in zip(motion.series(one), motion.series(two))][2:7]
                ke = [m * (dotp(a, a) + dotp(a, b) + dotp(b, b)) / 6 for a, b in zip(v1, v2)]
                pe = [-m * dotp(gravity, x) for x in mid]
        else:
            m, centre, inertia = local_body(kind, role, spec)
            point = motion.body_point(body, centre)
            v = motion.velocities(point)
            pos = motion.series(point)[2:7]
            spins = motion.spin(body)
            axes = [pose[3][body][1] for pose in motion.poses[2:7]]
            ke = []
            for vg, w, e in zip(v, spins, axes):
                local = [dotp(axis, w) for axis in e]
                rot = sum(inertia[i][j] * local[i] * local[j] for i in range(3) for j in range(3))
                ke.append(m * dotp(vg, vg) / 2 + rot / 2)
            pe = [-m * dotp(gravity, x) for x in pos]
        kinetic = [t + k for t, k in zip(kinetic, ke)]
        potential = [t + p for t, p in zip(potential, pe)]
    return kinetic, potential


def arc_means(arc):
    """The means of cos^2, sin^2, cos sin, cos and sin over [0, arc] ("cc", "ss", "cs", "c",
    "s"): their integrals in closed form (tests/test_forces.py holds them to mpmath.quad)."""
    c, s = mpmath.cos(arc), mpmath.sin(arc)
    return {"cc": (arc + s * c) / 2 / arc, "ss": (arc - s * c) / 2 / arc, "cs": s * s / 2 / arc,
            "c": s / arc, "s": (1 - c) / arc}


def _arc_energy(motion, m, one, two, gravity):
    """A uniform rod along the shorter great-circle arc between two joints of the sphere:
    KE = m/2 mean |v|^2 and PE = -m g . mean position, the means along the arc by quadrature."""
    ends = list(zip(motion.series(one), motion.series(two)))
    u0, u1 = (unit(x) for x in ends[4])
    mean = arc_means(mpmath.acos(dotp(u0, u1)))
    radius = motion.g.radius

    def basis(pose_ends):
        p, q = (unit(x) for x in pose_ends)
        return p, unit(add((1, q), (-dotp(p, q), p)))

    bases = [basis(e) for e in ends]
    starts = [[radius * x for x in b[0]] for b in bases]
    sides = [[radius * x for x in b[1]] for b in bases]
    ke, pe = [], []
    for i in range(2, 7):
        vs, vq = first(starts[i - 2:i + 3], motion.h), first(sides[i - 2:i + 3], motion.h)
        ke.append(m / 2 * (mean["cc"] * dotp(vs, vs) + 2 * mean["cs"] * dotp(vs, vq)
                           + mean["ss"] * dotp(vq, vq)))
        centre = add((mean["c"], starts[i]), (mean["s"], sides[i]))
        pe.append(-m * dotp(gravity, centre))
    return ke, pe


def gravity_vector(kind, gravity):
    if gravity is None:
        return vec(0, 0, 0)
    if isinstance(gravity, (int, float)):
        return vec(0, -gravity, 0) if kind in ("plane", "slider") else vec(0, 0, -gravity)
    return vec(*gravity)


def coupler_local(kind, radius, at):
    """A coupler point's coordinates in the coupler's frame (Linkage.coupler's u, v)."""
    u, v = at
    if kind == "spherical":
        (cu, su), (cv, sv) = cos_sin(u), cos_sin(v)
        return [radius * cv * cu, radius * cv * su, radius * sv]
    return [mpf(u), mpf(v), mpf(0)]


def loads_power(motion, kind, effects, radius=1):
    """The power of the output torque, the slider's force and the coupler force at t = 0."""
    power = mpf(0)
    rate = first([pose[0] for pose in motion.poses[2:7]], motion.h)
    if effects.output_torque:
        power += mpf(effects.output_torque) * rate
    if effects.output_force:
        power += mpf(effects.output_force) * rate
    if effects.coupler_force is not None:
        at, force = effects.coupler_force
        point = motion.body_point(1, coupler_local(kind, radius, at))
        power += dotp(vec(*force), motion.velocities(point)[2])
    return power


def linkage_motion(lk, phi, branch, effects, radius=1):
    """The reference Motion for an engine linkage at phi (degrees) on branch."""
    m = lk.motion(phi, branch)
    omega = 2 * mpmath.pi * mpf(effects.speed_rpm) / 60
    return Motion(lk.kind, lk.dims, phi, m.output, omega, effects.crank_acceleration, radius)


def energy_torque(lk, phi, branch, bodies, effects, radius=1):
    """The driving torque by the energy balance (needs a speed), (dE/dt - loads' power) / omega,
    and the scale of its terms (the largest of dKE/dt, dPE/dt and the loads' power over omega)."""
    with mp.workdps(DIGITS):
        motion = linkage_motion(lk, phi, branch, effects, radius)
        kinetic, potential = _energy(motion, lk.kind, bodies,
                                     gravity_vector(lk.kind, effects.gravity))
        terms = [first(kinetic, motion.h), first(potential, motion.h),
                 -loads_power(motion, lk.kind, effects, radius)]
        return (float(sum(terms) / motion.omega),
                float(max(abs(t) for t in terms) / abs(motion.omega)))


def ratios(lk, phi, branch, radius=1):
    """d(output)/dphi and the bodies' motion per radian of crank (a Motion at unit speed)."""
    return linkage_motion(lk, phi, branch, linkage.Effects(speed_rpm=60 / (2 * mpmath.pi)),
                          radius)


class BodyState:
    """A body's centre, its acceleration, angular velocity and acceleration, and its axes at
    t = 0 (mpmath)."""

    def __init__(self, motion, body, centre):
        point = motion.body_point(body, centre)
        values = motion.series(point)
        self.centre = values[4]
        self.acceleration = second(values[2:7], motion.h)
        spins = motion.spin(body)
        self.spin = spins[2]
        self.spin_rate = first(spins, motion.h)
        self.axes = motion.poses[4][3][body][1]


def states(lk, phi, branch, bodies, effects, radius=1):
    """BodyState of crank, coupler and output for explicit bodies, and the joints' positions."""
    with mp.workdps(DIGITS):
        motion = linkage_motion(lk, phi, branch, effects, radius)
        out = []
        for body, role in enumerate(("crank", "coupler", "output")):
            _, centre, _ = local_body(lk.kind, role, getattr(bodies, role))
            out.append(BodyState(motion, body, centre))
        q, a, p, _ = motion.poses[4]
        return out, a, p, motion
