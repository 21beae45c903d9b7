"""Side-by-side timing of jointwear against the SciPy model a researcher would write.

The SciPy side integrates the scene's slider-crank in minimal coordinates with the explicit
Runge-Kutta pairs of `scipy.integrate.solve_ivp` (RK45 = Dormand-Prince 5(4), DOP853 =
Hairer's 8(5,3)), at the paper's largest step of 1e-5 s and at the scene's. It implements
the same model as jointwear (src/laws/contact.rs, src/laws/friction.rs, src/laws/wear.rs,
src/simulation/run.rs), read from the same scene TOML:

Kinematics (minimal coordinates). The crank angle is prescribed, θ(t) = θ0 + ω t. The state
is y = (φ, s, φ̇, ṡ): φ the rod's body angle, s the slider's position along its guide (unit
vector u). With P(t) the crank pin, the journal centre is J = P + R(φ) d (d: pin to journal in
the rod frame), the bearing centre B = G + s u (+ the slider's fixed offset), e = J − B. The
rod's centre of mass is P + a(φ), a = −R(φ) A (A: the pin in the rod frame), a' = ∂a/∂φ.
Lagrange's equations (the paper's eq. 10 with the constraints eliminated):

    (J_rod + m_rod |a|²) φ̈ = (contact point − P) × F_c + m_rod (g − P̈) · a'
    m_slider s̈ = (m_slider g − F_c) · u

Contact (eq. 1-3, 11, 12). n = e/|e|, t = (−n_y, n_x), contact angle θ_c = angle of n in the
slider frame, worn gap δ = |e| − c − h(θ_c), δ̇ = n·ė − h'(θ_c) θ̇_c,

    F_n = K δ^n (1 + 3(1 − c_e²) e^{2(1 − c_e)} δ̇ / (4 max(δ̇⁻, v_graze)))   δ ≥ 0   (1, 3)
    K   = (π/8) E* sqrt(2δ (3ΔR + 2δ)² / (ΔR + δ)³),  ΔR = c + h(θ_c)                (2)

clamped at F_n ≥ 0, with 1/E* = Σ (1 − ν²)/E. δ̇⁻, the normal velocity at the onset of the
current contact, is captured at an event: after every accepted step whose gap changes sign
from negative to non-negative, the onset time is located by Brent's method on the step's
dense output (as solve_ivp locates events; to jointwear's time tolerance), the step is cut
there, δ̇⁻ is captured and the solver restarts from the onset, as solve_ivp does after a
terminal event. Before the first contact δ̇⁻ = 0 (the floor v_graze applies), as in jointwear.

Friction (eq. 4). F_t = −μ(v) F_n sign(v) along t, v = ė·t + φ̇ R_j (the sliding velocity of
the material points in contact), μ = μ_s sin(π|v|/(2V_s)) below V_s, μ_d above V_d and the
cosine blend (μ_s + μ_d)/2 + (μ_s − μ_d)/2 cos(π(|v| − V_s)/(V_d − V_s)) between.

Wear (eq. 5-9, eq. 7 with the pressure it drops). Archard on N equal sectors of the bearing:
h_i ← h_i + (k/H) P Δs (eq. 9) with Hertz line-contact pressure, R* = R_i R_j/(R_i − R_j),
b = sqrt(4 F_n R*/(π L E*)), P = 2 F_n/(π b L), semi-elliptic over the arc half-angle b/R_i;
each sector gets the mean of p(φ) over its span (exact integral of the semi-ellipse), so the
Archard volume is conserved however narrow the arc. h(θ) between sector centres is the
periodic Catmull-Rom spline (C¹, so the gap has no jumps).

The wear is updated once per ACCEPTED step, evaluated at the step midpoint (Δs = |v| Δt, the
state from the step's dense output), and the worn profile enters the gap of every later step.
This is jointwear's scheme, so both sides integrate the same model, and it is the only
placement that keeps the right-hand side one fixed function during a step (wear added inside
the right-hand side would also accrue on rejected steps and intermediate stages; wear added
per output step would lag the gap by a whole output interval). solve_ivp has no hook between
accepted steps, so `simulate` writes solve_ivp's loop itself around the same solver classes
(scipy.integrate.RK45 and DOP853, `step()` and `dense_output()`). The alternative, one
solve_ivp call per output interval, would restart the solver thousands of times per rotation,
each time paying its initial-step selection and losing the first-same-as-last stage: the
loop used here is the faster choice for SciPy. SciPy's DOP853 builds its 7th-order dense
output with 3 extra evaluations per step (needed every step for the wear midpoint); the
evaluation counts include them.

Matched accuracy. Impacts make single trajectories chaotic (eq. 3 remembers δ̇⁻, and any
perturbation leads to another onset sequence), so the error is measured on the first crank
rotation, before integrations part: the largest distance, over the 1e-5 s grid, between the
journal orbit e(t) and the reference run's, with the scene as timed (wear included). The
reference is jointwear's Dopri5 at rtol 1e-12, atol 1e-15 and steps of at most 1e-5 s (the
model check finds this script's DOP853 at rtol 1e-11 within 5e-6 µm of it without wear).
Errors below a few 0.01 µm are not resolved: a near-grazing contact late in the first
rotation amplifies small differences, and the wear fed back per accepted step makes the gap
depend on the step sequence, so tight settings scatter from 4e-4 µm (the "second reference"
row: jointwear's DOP853 at rtol 1e-12 with steps up to 1e-4 s, paper.md's work-precision
reference) to 0.02 µm. The criterion of paper.md section 5, which chose the scenes'
tolerance, is an orbit error of at most 0.1 µm (0.5 % of the clearance). A SciPy row's
speed ratio (`speed_ratio_wall`, `speed_ratio_cpu`) is taken against the fastest jointwear
row that is at least as accurate, so it never credits jointwear with an accuracy it did not
reach.

A second, coarser error is the wear volume per unit length (Σ h_i R_i Δθ) after the N timed
rotations against the reference's. It integrates the whole run, but after the first rotations
the impact sequences of different integrations split apart: its floor is the "second
reference" row's value (0.4 % after the default 4 rotations), below which it says nothing.

Timing. Each setting runs N rotations with wear (default 4: the whole comparison then takes a
few minutes), each run in its own process: whole-process wall time (median, min, max over the
repeats), the processes' CPU time (robust against other load on a shared machine), and for
SciPy the CPU time of the integration loop alone (`integration_cpu_s`, without interpreter
start and imports). SciPy runs at the paper's largest step, 1e-5 s, and at the scene's
(1e-3 s, jointwear's), where its tolerance rather than the step cap sets the cost; atol =
1e-3 rtol throughout (jointwear's convention, paper.md section 5).

Usage (from the crate root; `compare` builds jointwear with cargo):

    python3 benches/scipy_compare.py compare [--rotations 4] [--repeats 3]
    python3 benches/scipy_compare.py simulate data/scenes/standard.toml --method DOP853 \\
        --rtol 1e-8 --rotations 2 --out result.json

`compare` writes data/scipy_comparison.csv (one row per implementation, method, tolerance and
largest step) and data/scipy_model_check.csv (the SciPy model against jointwear over the
first rotation at tight tolerances: the orbit without wear, the wear profile with it); it
stops before timing anything if the two models disagree.
"""

import argparse
import csv
import json
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

try:
    import numpy as np
    from scipy.integrate import DOP853, RK45
    from scipy.optimize import brentq
except ImportError as missing:
    print(f"scipy_compare: skipped, {missing.name} is not importable (pip install numpy scipy)")
    sys.exit(0)

SOLVERS = {"RK45": RK45, "DOP853": DOP853}
PAPER_MAX_STEP = 1e-5  # s, the paper's largest step
ORBIT_INTERVAL = 1e-5  # s, grid of the first-rotation orbit
ROOT = Path(__file__).resolve().parent.parent

# --- scene ---------------------------------------------------------------------------------


def read_scene(path):
    """The scene document of `path` with `extends` and `[overrides]` resolved as jointwear
    does (src/scene/layering.rs): the base's tables, then this file's top-level keys, then each
    dotted override path, which must exist in the base."""
    path = Path(path)
    doc = tomllib.loads(path.read_text())
    base = doc.pop("extends", None)
    if base is None:
        return doc
    merged = read_scene(path.parent / base)
    overrides = doc.pop("overrides", {})
    merged.update(doc)
    for key, value in overrides.items():
        *parents, last = [int(p) if p.isdigit() else p for p in key.split(".")]
        node = merged
        for p in parents:
            node = node[p]
        if isinstance(node, dict) and last not in node:
            raise KeyError(f"override {key}: no such key in the base scene")
        node[last] = value
    return merged


def rotation(angle, v):
    """R(angle) v for a 2-vector."""
    c, s = math.cos(angle), math.sin(angle)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


class SliderCrank:
    """The scene's slider-crank with its clearance joint, in minimal coordinates.

    Expects the topology of data/scenes/standard.toml: a driven crank pinned to the ground,
    a rod pinned to the crank, a slider on a translational joint to the ground, and one
    clearance joint with the journal on the rod and the bearing on the slider.
    """

    def __init__(self, scene):
        bodies = {b["name"]: b for b in scene["bodies"]}

        def point(spec):
            body, name = spec.split(".")
            pts = scene["ground"]["points_mm"] if body == "ground" else bodies[body]["points_mm"]
            return body, (pts[name][0] * 1e-3, pts[name][1] * 1e-3)

        def pin(between):
            for joint in scene["revolute"]:
                ends = dict(point(joint[k]) for k in ("a", "b"))
                if set(ends) == between:
                    return ends
            raise ValueError(f"the scene has no revolute joint between {sorted(between)}")

        (joint,) = scene["clearance"]
        (guide,) = scene["translational"]
        crank = scene["driver"]["body"]
        rod, journal = point(joint["journal"])
        slider, bearing = point(joint["bearing"])
        guide_body, guide_point = point(guide["a"])
        if point(guide["b"])[0] != "ground" or guide_body != slider:
            raise ValueError("expected the slider on a translational joint to the ground")
        ground_pin, crank_pin = pin({"ground", crank}), pin({crank, rod})

        # crank: pin P(t) = G + R(θ) k
        self.omega = scene["driver"]["speed_rpm"] * 2 * math.pi / 60
        self.theta0 = math.radians(scene["driver"]["angle_deg"])
        self.ground_pivot = ground_pin["ground"]
        self.crank_arm = (crank_pin[crank][0] - ground_pin[crank][0],
                          crank_pin[crank][1] - ground_pin[crank][1])
        # rod: pin to journal d, pin to centre of mass −A (rod frame)
        self.rod_journal = (journal[0] - crank_pin[rod][0], journal[1] - crank_pin[rod][1])
        self.rod_pin = crank_pin[rod]
        self.rod_mass = bodies[rod]["mass_kg"]
        self.rod_inertia = bodies[rod]["inertia_kg_m2"]
        self.rod_guess = math.radians(bodies[rod]["angle_deg"])
        # slider: bearing centre B = G_guide + s u + R(φ_slider)(bearing − guide point)
        self.slider_angle = math.radians(bodies[slider]["angle_deg"])
        axis = math.radians(guide["axis_deg"])
        self.axis = (math.cos(axis), math.sin(axis))
        offset = rotation(self.slider_angle,
                          (bearing[0] - guide_point[0], bearing[1] - guide_point[1]))
        origin = point(guide["b"])[1]
        self.bearing_origin = (origin[0] + offset[0], origin[1] + offset[1])
        self.slider_mass = bodies[slider]["mass_kg"]
        guess = rotation(self.slider_angle, guide_point)  # the guide point's guessed s
        guess = (bodies[slider]["position_mm"][0] * 1e-3 + guess[0] - origin[0],
                 bodies[slider]["position_mm"][1] * 1e-3 + guess[1] - origin[1])
        self.slider_guess = guess[0] * self.axis[0] + guess[1] * self.axis[1]
        self.gravity = tuple(scene["gravity_m_s2"])

        # clearance joint (SI)
        contact, friction = joint["contact"], joint["friction"]
        if contact["model"] != "hybrid" or friction["model"] != "modified":
            raise ValueError("this model implements the hybrid contact law with the modified "
                             "Coulomb friction of the paper (eq. 1-4)")
        mat = scene["materials"]
        self.e_star = 1 / sum((1 - mat[m]["poisson_ratio"] ** 2)
                              / (mat[m]["youngs_modulus_gpa"] * 1e9)
                              for m in (joint["journal_material"], joint["bearing_material"]))
        self.r_bearing = joint["bearing_radius_mm"] * 1e-3
        self.clearance = joint["clearance_mm"] * 1e-3
        self.r_journal = self.r_bearing - self.clearance
        ce = contact["restitution"]
        self.exponent = contact["exponent"]
        self.damping = 0.75 * (1 - ce * ce) * math.exp(2 * (1 - ce))
        self.v_graze = contact["grazing_velocity_m_s"]
        self.mu_s, self.mu_d = friction["mu_s"], friction["mu_d"]
        self.v_s, self.v_d = friction["v_s"], friction["v_d"]
        wear = joint.get("wear")
        if wear is not None and wear["pressure"] != "hertz-line":
            raise ValueError("this model implements the Hertz line-contact pressure")
        self.k_over_h = wear["k_over_h_per_pa"] if wear else 0.0
        self.length = wear["length_mm"] * 1e-3 if wear else 1.0
        self.depth = [0.0] * (wear["sectors"] if wear else 8)
        self.width = 2 * math.pi / len(self.depth)
        self.impact_velocity = 0.0

    # kinematics -------------------------------------------------------------------------

    def pin(self, t):
        """Crank pin position, velocity and acceleration at time t."""
        kx, ky = rotation(self.theta0 + self.omega * t, self.crank_arm)
        w = self.omega
        return ((self.ground_pivot[0] + kx, self.ground_pivot[1] + ky),
                (-w * ky, w * kx), (-w * w * kx, -w * w * ky))

    def initial_state(self):
        """Ideal-joint configuration at t = 0 (journal centred, e = ė = 0), the branch
        nearest the scene's guess, as jointwear assembles it."""
        p, v, _ = self.pin(0.0)
        u, length = self.axis, math.hypot(*self.rod_journal)
        w = (p[0] - self.bearing_origin[0], p[1] - self.bearing_origin[1])
        uw = u[0] * w[0] + u[1] * w[1]
        root = math.sqrt(uw * uw - (w[0] ** 2 + w[1] ** 2) + length * length)
        s = min((uw - root, uw + root), key=lambda x: abs(x - self.slider_guess))
        phi = (math.atan2(s * u[1] - w[1], s * u[0] - w[0])
               - math.atan2(self.rod_journal[1], self.rod_journal[0]))
        phi += 2 * math.pi * round((self.rod_guess - phi) / (2 * math.pi))
        # journal velocity v + φ̇ perp(R(φ) d) equals the bearing's ṡ u
        jx, jy = rotation(phi, self.rod_journal)
        det = jy * u[1] + jx * u[0]
        dphi = (v[0] * u[1] - u[0] * v[1]) / det
        ds = (jy * v[1] + jx * v[0]) / det
        return np.array([phi, s, dphi, ds])

    def contact(self, t, y):
        """Contact geometry at (t, y): e = (e_x, e_y), normal n = (n_x, n_y), contact angle
        θ_c, penetration δ, its rate δ̇, local clearance c + h and sliding velocity v."""
        phi, s, dphi, ds = y
        p, v, _ = self.pin(t)
        jx, jy = rotation(phi, self.rod_journal)
        ex = p[0] + jx - self.bearing_origin[0] - s * self.axis[0]
        ey = p[1] + jy - self.bearing_origin[1] - s * self.axis[1]
        vx = v[0] - dphi * jy - ds * self.axis[0]
        vy = v[1] + dphi * jx - ds * self.axis[1]
        dist = math.hypot(ex, ey)
        if dist == 0.0:  # exactly centred (the initial state): no direction, no contact
            return ex, ey, 0.0, 0.0, 0.0, -self.clearance, 0.0, self.clearance, 0.0
        nx, ny = ex / dist, ey / dist
        theta = (math.atan2(ny, nx) - self.slider_angle) % (2 * math.pi)
        tangential = -ny * vx + nx * vy
        h, dh = self.depth_at(theta)
        delta = dist - self.clearance - h
        delta_dot = nx * vx + ny * vy - dh * tangential / dist
        return (ex, ey, nx, ny, theta, delta, delta_dot, self.clearance + h,
                tangential + dphi * self.r_journal)

    def gap(self, t, y):
        """Penetration δ (negative in free flight): the event function of contact onset."""
        return self.contact(t, y)[5]

    # forces -----------------------------------------------------------------------------

    def normal_force(self, delta, delta_dot, local_clearance):
        """Eq. 1-3 with the captured onset velocity, clamped at zero (no adhesion)."""
        a = 3 * local_clearance + 2 * delta
        b = local_clearance + delta
        k = math.pi / 8 * self.e_star * math.sqrt(2 * delta * a * a / (b * b * b))
        onset = max(self.impact_velocity, self.v_graze)
        return max(k * delta ** self.exponent * (1 + self.damping * delta_dot / onset), 0.0)

    def friction_coefficient(self, v):
        """Eq. 4."""
        v = abs(v)
        if v > self.v_d:
            return self.mu_d
        if v < self.v_s:
            return self.mu_s * math.sin(0.5 * math.pi * v / self.v_s)
        return (0.5 * (self.mu_s + self.mu_d) + 0.5 * (self.mu_s - self.mu_d)
                * math.cos(math.pi * (v - self.v_s) / (self.v_d - self.v_s)))

    def rhs(self, t, y):
        """y' = f(t, y): Lagrange's equations of the rod angle and the slider position."""
        phi, s, dphi, ds = y.tolist()
        ex, ey, nx, ny, _, delta, delta_dot, local_c, v_slide = self.contact(t, (phi, s, dphi, ds))
        fx = fy = torque = 0.0
        if delta >= 0.0:
            f_n = self.normal_force(delta, delta_dot, local_c)
            f_t = -self.friction_coefficient(v_slide) * f_n * math.copysign(1.0, v_slide)
            fx, fy = -f_n * nx - f_t * ny, -f_n * ny + f_t * nx
            jx, jy = rotation(phi, self.rod_journal)
            arm_x, arm_y = jx + self.r_journal * nx, jy + self.r_journal * ny
            torque = arm_x * fy - arm_y * fx
        _, _, acc = self.pin(t)
        ax, ay = rotation(phi, self.rod_pin)  # −a, the pin seen from the centre of mass
        g = self.gravity
        # a' = perp(a) = (ay, −ax) with a = (−ax, −ay)
        drive = (g[0] - acc[0]) * ay - (g[1] - acc[1]) * ax
        ddphi = (torque + self.rod_mass * drive) / (
            self.rod_inertia + self.rod_mass * (ax * ax + ay * ay))
        dds = ((self.slider_mass * g[0] - fx) * self.axis[0]
               + (self.slider_mass * g[1] - fy) * self.axis[1]) / self.slider_mass
        return (dphi, ds, ddphi, dds)

    # wear -------------------------------------------------------------------------------

    def depth_at(self, theta):
        """Wear depth h(θ) and dh/dθ: periodic Catmull-Rom spline through sector centres."""
        n, d = len(self.depth), self.depth
        u = theta / self.width - 0.5
        i = math.floor(u)
        t = u - i
        p0, p1, p2, p3 = (d[(i + k) % n] for k in (-1, 0, 1, 2))
        c1 = p2 - p0
        c2 = 2 * p0 - 5 * p1 + 4 * p2 - p3
        c3 = -p0 + 3 * (p1 - p2) + p3
        h = 0.5 * (2 * p1 + t * (c1 + t * (c2 + t * c3)))
        return h, 0.5 * (c1 + t * (2 * c2 + 3 * t * c3)) / self.width

    def add_wear(self, t, y, dt):
        """Archard wear of an interval dt at state y (eq. 9), spread over the sectors under
        the Hertz semi-elliptic pressure arc by its exact sector integrals."""
        _, _, _, _, theta, delta, delta_dot, local_c, v_slide = self.contact(t, y)
        if delta < 0.0 or self.k_over_h == 0.0:
            return
        f_n = self.normal_force(delta, delta_dot, local_c)
        if f_n == 0.0:
            return
        r_star = self.r_bearing * self.r_journal / (self.r_bearing - self.r_journal)
        b = math.sqrt(4 * f_n * r_star / (math.pi * self.length * self.e_star))
        peak = 2 * f_n / (math.pi * b * self.length)
        half = min(b / self.r_bearing, math.pi)

        def primitive(phi):  # ∫_0^φ sqrt(1 − (x/half)²) dx, odd in φ
            x = max(-1.0, min(1.0, phi / half))
            return 0.5 * half * (x * math.sqrt(1 - x * x) + math.asin(x))

        scale = self.k_over_h * peak * abs(v_slide) * dt / self.width
        n = len(self.depth)
        first = math.floor((theta - half) / self.width)
        last = math.floor((theta + half) / self.width)
        lo = primitive(first * self.width - theta)
        for k in range(first, last + 1):
            hi = primitive((k + 1) * self.width - theta)
            self.depth[k % n] += scale * (hi - lo)
            lo = hi


def wear_volume(depth, r_bearing):
    """Wear volume per unit bearing length of a sector profile, Σ h_i R_i Δθ (m²)."""
    return sum(depth) * r_bearing * 2 * math.pi / len(depth)


def simulate(model, method, rtol, atol, max_step, rotations, record_orbit=False):
    """Integrates `rotations` crank rotations: contact onsets as terminal events (Brent's
    method on the step's dense output), wear per accepted step at its midpoint. Returns the
    run's counters, its wear profile and, with `record_orbit`, the journal orbit e(t) of the
    first rotation on the ORBIT_INTERVAL grid."""
    period = 2 * math.pi / abs(model.omega)
    t_end = rotations * period
    grid = [i * ORBIT_INTERVAL for i in range(int(period / ORBIT_INTERVAL * (1 + 1e-12)) + 1)]
    orbit, next_sample = [], 0
    wears = model.k_over_h > 0.0
    y = model.initial_state()
    counters = {"rhs_evaluations": 0, "steps": 0, "onsets": 0}

    def start(t, y):
        return SOLVERS[method](model.rhs, t, y, t_end, rtol=rtol, atol=atol, max_step=max_step)

    clock = time.process_time()
    solver = start(0.0, y)
    gap_prev = model.gap(0.0, y)
    while solver.status == "running":
        message = solver.step()
        if solver.status == "failed":
            raise RuntimeError(f"{method} failed at t = {solver.t:.6e} s: {message}")
        counters["steps"] += 1
        ta, tb = solver.t_old, solver.t
        gap = model.gap(tb, solver.y)
        onset = gap_prev < 0.0 <= gap
        recording = record_orbit and next_sample < len(grid)
        dense = solver.dense_output() if wears or onset or recording else None
        t_stop = tb
        if onset:
            t_stop = brentq(lambda t: model.gap(t, dense(t)), ta, tb, xtol=1e-12 * max(tb, 1.0))
        if wears:
            t_mid = 0.5 * (ta + t_stop)
            model.add_wear(t_mid, dense(t_mid), t_stop - ta)
        while record_orbit and next_sample < len(grid) and grid[next_sample] <= t_stop:
            e = model.contact(grid[next_sample], dense(grid[next_sample]))
            orbit.append((e[0], e[1]))
            next_sample += 1
        if onset:
            y_onset = dense(t_stop)
            model.impact_velocity = model.contact(t_stop, y_onset)[6]
            counters["onsets"] += 1
            counters["rhs_evaluations"] += solver.nfev
            solver = start(t_stop, y_onset)
            gap = 0.0  # the journal is at the wall: the next onset needs a flight first
        gap_prev = gap
    counters["rhs_evaluations"] += solver.nfev
    return {
        "method": method, "rtol": rtol, "atol": atol, "max_step_s": max_step,
        "rotations": rotations, "integration_cpu_s": time.process_time() - clock, **counters,
        "wear_volume_m2": wear_volume(model.depth, model.r_bearing),
        "wear_depth_m": model.depth, "orbit_m": orbit,
    }


# --- comparison ----------------------------------------------------------------------------

REFERENCE = ("dopri5", 1e-12, 1e-15, 1e-5)  # jointwear: method, rtol, atol, largest step (s)
SECOND_REFERENCE = ("dop853", 1e-12, 1e-15, 1e-4)  # paper.md's work-precision reference
WEAR_KEY = "clearance.0.wear.k_over_h_per_pa"


def toml_value(v):
    """A TOML literal for the scalars and lists of an override."""
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return repr(v)


def variant(directory, scene, name, overrides):
    """A scene file extending `scene` with dotted-key `overrides`, read by both sides."""
    path = Path(directory) / f"{name}.toml"
    lines = [f"extends = {json.dumps(str(Path(scene).resolve()))}", "[overrides]"]
    lines += [f'"{k}" = {toml_value(v)}' for k, v in overrides.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def orbit_error(orbit, reference):
    """Largest distance between two orbits sampled on the same grid (m)."""
    if len(orbit) != len(reference):
        raise ValueError(f"orbits of {len(orbit)} and {len(reference)} samples")
    return max(math.hypot(a[0] - b[0], a[1] - b[1]) for a, b in zip(orbit, reference))


def timed(command):
    """Runs `command`: its whole-process wall time and CPU time (s), and its stdout."""
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
    clock = time.perf_counter()
    done = subprocess.run(command, check=True, capture_output=True, text=True)
    wall = time.perf_counter() - clock
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, after.ru_utime + after.ru_stime - cpu.ru_utime - cpu.ru_stime, done.stdout


class Comparison:
    """Runs both sides on variants of one scene, written to directory `tmp`."""

    def __init__(self, scene, tmp):
        self.scene, self.tmp = Path(scene), Path(tmp)
        joint = read_scene(scene)["clearance"][0]
        self.joint, self.r_bearing = joint["name"], joint["bearing_radius_mm"] * 1e-3
        subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "jointwear"],
                       cwd=ROOT, check=True)
        meta = subprocess.run(["cargo", "metadata", "--format-version", "1", "--no-deps"],
                              cwd=ROOT, check=True, capture_output=True, text=True)
        self.binary = Path(json.loads(meta.stdout)["target_directory"]) / "release" / "jointwear"

    def rust(self, setting, rotations, repeats=1, wear=True):
        """jointwear runs of `setting` = (method, rtol, atol, max_step) over `rotations`
        (a single rotation is recorded on the orbit grid): wall and CPU times, RHS
        evaluations, orbit and wear profile."""
        method, rtol, atol, max_step = setting
        overrides = {"run.rotations": rotations, "run.record_rotations": int(rotations == 1),
                     "run.record_interval_s": ORBIT_INTERVAL, "run.wear_snapshots": [],
                     "run.method": method, "run.rtol": rtol, "run.atol": atol,
                     "run.max_step_s": max_step}
        if not wear:
            overrides[WEAR_KEY] = 0.0
        name = f"rust_{method}_{rtol:g}_{max_step:g}_{rotations}_{wear}"
        out = self.tmp / name
        command = [str(self.binary), "run", str(variant(self.tmp, self.scene, name, overrides)),
                   "--out", str(out)]
        walls, cpus = [], []
        for _ in range(repeats):
            wall, cpu, stdout = timed(command)
            walls.append(wall)
            cpus.append(cpu)
        with open(out / "timeseries.csv") as f:
            orbit = [(float(r[f"{self.joint}.ex_m"]), float(r[f"{self.joint}.ey_m"]))
                     for r in csv.DictReader(f)]
        with open(out / f"wear_{self.joint}.csv") as f:
            depth = [float(r["depth_m"]) for r in csv.DictReader(f)]
        evaluations = int(stdout.split(" evaluations")[0].split()[-1])
        return {"wall": walls, "cpu": cpus, "rhs_evaluations": evaluations, "orbit_m": orbit,
                "wear_volume_m2": wear_volume(depth, self.r_bearing), "wear_depth_m": depth}

    def python(self, method, rtol, max_step, rotations, repeats=1, wear=True):
        """`simulate` runs, each in its own process: wall, CPU and integration CPU times and
        the last run's result."""
        scene = self.scene if wear else variant(self.tmp, self.scene, "no_wear", {WEAR_KEY: 0.0})
        out = self.tmp / "scipy.json"
        command = [sys.executable, __file__, "simulate", str(scene), "--method", method,
                   "--rtol", repr(rtol), "--max-step", repr(max_step),
                   "--rotations", str(rotations), "--out", str(out)]
        if rotations == 1:
            command.append("--orbit")
        walls, cpus, integrations = [], [], []
        for _ in range(repeats):
            wall, cpu, _ = timed(command)
            result = json.loads(out.read_text())
            walls.append(wall)
            cpus.append(cpu)
            integrations.append(result["integration_cpu_s"])
        return {**result, "wall": walls, "cpu": cpus, "integration": integrations}


def model_check(cmp, args):
    """The SciPy model against jointwear, both at tight tolerances over the first rotation:
    the journal orbit without wear, and the wear profile with it."""
    print("model check, first rotation ...", flush=True)
    rust_orbit = cmp.rust(REFERENCE, 1, wear=False)["orbit_m"]
    rust_worn = cmp.rust(REFERENCE, 1)
    setting = (args.check_method, args.check_rtol, PAPER_MAX_STEP)
    free = cmp.python(*setting, 1, wear=False)
    worn = cmp.python(*setting, 1)
    orbit = orbit_error(free["orbit_m"], rust_orbit)
    peak = max(rust_worn["wear_depth_m"])
    depth = max(abs(a - b) for a, b in zip(worn["wear_depth_m"], rust_worn["wear_depth_m"]))
    volume = abs(worn["wear_volume_m2"] / rust_worn["wear_volume_m2"] - 1)
    with open(args.model_check_out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["quantity", "value"])
        w.writerow(["jointwear_setting", "{} rtol={:g} atol={:g} max_step_s={:g}".format(
            *REFERENCE)])
        w.writerow(["scipy_setting", "{} rtol={:g} atol={:g} max_step_s={:g}".format(
            args.check_method, args.check_rtol, 1e-3 * args.check_rtol, PAPER_MAX_STEP)])
        w.writerow(["orbit_samples_first_rotation", len(rust_orbit)])
        w.writerow(["orbit_max_difference_um_without_wear", f"{orbit * 1e6:.3e}"])
        w.writerow(["wear_peak_um_after_first_rotation", f"{peak * 1e6:.4e}"])
        w.writerow(["wear_profile_max_difference_over_peak", f"{depth / peak:.3e}"])
        w.writerow(["wear_volume_relative_difference", f"{volume:.3e}"])
    print(f"  orbit without wear: largest difference {orbit * 1e6:.3e} um over "
          f"{len(rust_orbit)} samples; wear profile: {depth / peak:.2e} of its peak, "
          f"volume {volume:.2e}", flush=True)
    if orbit > args.check_orbit or depth / peak > args.check_wear:
        sys.exit(f"scipy_compare: the SciPy model disagrees with jointwear (orbit "
                 f"{orbit:.3e} m, limit {args.check_orbit:g} m; wear {depth / peak:.3e} of "
                 f"the peak, limit {args.check_wear:g}): not timing a different model")


def compare(args):
    with tempfile.TemporaryDirectory(prefix="scipy_compare_") as tmp:
        cmp = Comparison(args.scene, tmp)
        model_check(cmp, args)
        rows = timings(cmp, args)
    # the speed ratio against the fastest jointwear setting that is at least as accurate
    rust_rows = [r for r in rows if r["implementation"] == "jointwear"]
    for r in rows:
        for kind in ("wall", "cpu"):
            matched = [float(q[f"{kind}_s_median"]) for q in rust_rows
                       if float(q["error_vs_reference"]) <= float(r["error_vs_reference"])]
            r[f"speed_ratio_{kind}"] = (
                f"{float(r[f'{kind}_s_median']) / min(matched):.0f}"
                if matched and r["implementation"] == "scipy" else "")
    with open(args.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {args.out} and {args.model_check_out}")
    for threshold in (1.0, 0.1):
        print(f"fastest settings with a first-rotation orbit error <= {threshold} um:")
        for implementation, method in dict.fromkeys((r["implementation"], r["method"])
                                                    for r in rows):
            passing = [r for r in rows if (r["implementation"], r["method"]) == (
                implementation, method) and float(r["error_vs_reference"]) <= threshold]
            if passing:
                r = min(passing, key=lambda r: float(r["cpu_s_median"]))
                print(f"  {implementation:9} {method:7} rtol {r['rtol']:6} max_step "
                      f"{r['max_step_s']:6} wall {r['wall_s_median']} s, cpu "
                      f"{r['cpu_s_median']} s")


def timings(cmp, args):
    """Times every setting over `args.rotations` and measures its errors: one CSV row each."""
    n = args.rotations
    print("references ...", flush=True)
    ref_orbit = cmp.rust(REFERENCE, 1)["orbit_m"]
    ref_volume = cmp.rust(REFERENCE, n)["wear_volume_m2"]
    rows = []

    def add(implementation, setting, note, first, timed_runs):
        method, rtol, atol, max_step = setting
        load = os.getloadavg()[0]
        integration = timed_runs.get("integration")
        rows.append({
            "implementation": implementation, "method": method, "rtol": f"{rtol:g}",
            "atol": f"{atol:g}", "max_step_s": f"{max_step:g}", "note": note, "rotations": n,
            "repeats": len(timed_runs["wall"]),
            "wall_s_median": f"{statistics.median(timed_runs['wall']):.4f}",
            "wall_s_min": f"{min(timed_runs['wall']):.4f}",
            "wall_s_max": f"{max(timed_runs['wall']):.4f}",
            "cpu_s_median": f"{statistics.median(timed_runs['cpu']):.4f}",
            "integration_cpu_s_median": (f"{statistics.median(integration):.4f}"
                                         if integration else ""),
            "load_average": f"{load:.1f}",
            "rhs_evaluations": timed_runs["rhs_evaluations"],
            "accuracy_metric": "first-rotation journal orbit, max |e - e_ref| (um)",
            "error_vs_reference": f"{orbit_error(first['orbit_m'], ref_orbit) * 1e6:.3e}",
            "wear_volume_err_rel": f"{abs(timed_runs['wear_volume_m2'] / ref_volume - 1):.3e}",
        })
        r = rows[-1]
        print(f"  {implementation:9} {method:7} rtol {r['rtol']:6} max_step {r['max_step_s']:6} "
              f"wall {r['wall_s_median']:>8} s  cpu {r['cpu_s_median']:>8} s  orbit error "
              f"{r['error_vs_reference']} um  wear volume error {r['wear_volume_err_rel']}",
              flush=True)

    print(f"jointwear, {n} rotations x {args.rust_repeats} ...", flush=True)
    scene_max_step = read_scene(args.scene)["run"]["max_step_s"]
    for setting, note, repeats in [(REFERENCE, "reference", args.repeats),
                                   (SECOND_REFERENCE, "second reference", args.repeats)] + [
            (("dopri5", r, 1e-3 * r, scene_max_step), "", args.rust_repeats)
            for r in args.rust_rtols]:
        add("jointwear", setting, note, cmp.rust(setting, 1), cmp.rust(setting, n, repeats))

    print(f"scipy, {n} rotations x {args.repeats} ...", flush=True)
    for method in ("RK45", "DOP853"):
        for max_step, note in ((PAPER_MAX_STEP, "the paper's largest step"),
                               (scene_max_step, "the scene's largest step")):
            for rtol in args.python_rtols:
                add("scipy", (method, rtol, 1e-3 * rtol, max_step), note,
                    cmp.python(method, rtol, max_step, 1),
                    cmp.python(method, rtol, max_step, n, args.repeats))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    c = sub.add_parser("compare", help="time jointwear and SciPy side by side, write the CSVs")
    c.add_argument("--scene", default=ROOT / "data/scenes/standard.toml",
                   help="a slider-crank scene (default: the standard one)")
    c.add_argument("--rotations", type=int, default=4, help="rotations of the timed runs")
    c.add_argument("--repeats", type=int, default=3,
                   help="timed runs of each SciPy setting and of the references")
    c.add_argument("--rust-repeats", type=int, default=7,
                   help="timed runs of each other jointwear setting")
    c.add_argument("--rust-rtols", type=float, nargs="+",
                   default=[1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9],
                   help="jointwear Dopri5 tolerances (largest step: the scene's)")
    c.add_argument("--python-rtols", type=float, nargs="+", default=[1e-4, 1e-6, 1e-8],
                   help="SciPy tolerances, each at the paper's and the scene's largest step")
    c.add_argument("--check-method", choices=sorted(SOLVERS), default="DOP853",
                   help="SciPy method of the model check")
    c.add_argument("--check-rtol", type=float, default=1e-11,
                   help="SciPy tolerance of the model check")
    c.add_argument("--check-orbit", type=float, default=1e-10,
                   help="largest orbit difference (m) the model check accepts")
    c.add_argument("--check-wear", type=float, default=2e-3,
                   help="largest wear-profile difference (over its peak) it accepts")
    c.add_argument("--out", default=ROOT / "data/scipy_comparison.csv", help="timing CSV")
    c.add_argument("--model-check-out", default=ROOT / "data/scipy_model_check.csv",
                   help="model check CSV")
    s = sub.add_parser("simulate", help="one SciPy run of a scene, as JSON")
    s.add_argument("scene")
    s.add_argument("--method", choices=sorted(SOLVERS), default="DOP853")
    s.add_argument("--rtol", type=float, default=1e-6)
    s.add_argument("--atol", type=float, help="absolute tolerance (default 1e-3 rtol)")
    s.add_argument("--max-step", type=float, default=PAPER_MAX_STEP)
    s.add_argument("--rotations", type=int, help="crank rotations (default: the scene's)")
    s.add_argument("--orbit", action="store_true", help="record the first-rotation orbit")
    s.add_argument("--out", help="JSON result file (default: stdout)")
    args = parser.parse_args()
    if args.command == "compare":
        compare(args)
        return
    scene = read_scene(args.scene)
    result = simulate(SliderCrank(scene), args.method, args.rtol,
                      args.atol if args.atol is not None else 1e-3 * args.rtol, args.max_step,
                      args.rotations or scene["run"]["rotations"], args.orbit)
    text = json.dumps(result)
    if args.out:
        Path(args.out).write_text(text)
    else:
        print(text)


if __name__ == "__main__":
    main()
