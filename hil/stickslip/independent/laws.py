"""Friction laws of the independent truth generator: LuGre, GMS and ls_b (an outside reading of
the LS paper). Equations, units and the reasons for every choice: docs/independent-generator.md.

Every law is written as continuous states q with rates dq/dt = f(v, q) plus discrete switches
(GMS stick/slip, the ls_b reversal memory) applied between integration steps. The same kernels
drive the two-mass plant (plant.py) and the prescribed-motion driver below (tests, Stribeck and
hysteresis curves). Shares no code with lib/ and does not load the C library.
"""

from __future__ import annotations

import math

import numpy as np

from ._jit import kernel

LUGRE, GMS, LS_B = 0, 1, 2
LAWS: tuple[str, ...] = ("lugre", "gms", "ls_b")
LAW_CODES = {"lugre": LUGRE, "gms": GMS, "ls_b": LS_B}

# GMS element distribution (docs/independent-generator.md, "GMS"): element i has stiffness
# k_i = GMS_STIFFNESS_SHARE[i] * sigma0 and slip weight alpha_i = GMS_WEIGHT[i]; its break-away
# displacement alpha_i Fs / k_i is (0.5, 1, 2, 3) Fs / sigma0, so the virgin curve is piecewise
# linear with initial slope sigma0 and reaches Fs at 3 Fs / sigma0 (1.08 um for Table I).
N_GMS = 4
GMS_STIFFNESS_SHARE = (0.5, 0.3, 0.15, 0.05)
GMS_WEIGHT = (0.25, 0.3, 0.3, 0.15)
# Attraction parameter C of the slipping elements (N/s): a slipping element relaxes to
# alpha_i g(v) with time constant g / C, 2.4 us at Fs = 3.6 N, short against the 15 us fast edge.
GMS_ATTRACTION_N_PER_S = 1.5e6

# Friction block of the parameter vector P (the plant appends its own block after it).
P_FS = 0  # static friction level Fs, N (before position, heat and direction factors)
P_FC = 1  # Coulomb level Fc, N
P_VS = 2  # Stribeck velocity, m/s
P_SIGMA0 = 3  # contact stiffness, N/m
P_SIGMA1 = 4  # micro-damping, N s/m
P_SIGMA2 = 5  # viscous coefficient, N s/m
P_ASYM = 6  # asymmetric_friction: levels times 1 + a sgn(v)
P_GMS_C = 7  # GMS attraction parameter, N/s
P_GMS_K = 8  # N_GMS element stiffnesses, N/m
P_GMS_ALPHA = P_GMS_K + N_GMS  # N_GMS element weights
N_P_FRICTION = P_GMS_ALPHA + N_GMS

# Friction block of the discrete state vector D (held constant within an integration step).
D_DIR = 0  # direction of the last nonzero relative velocity: +1, -1, 0 before any motion
D_OMEGA_R = 1  # ls_b: |Omega| at the last reversal, N
D_MODE = 2  # GMS: N_GMS element modes, 0 stick, 1 slip
N_D_FRICTION = D_MODE + N_GMS

# Continuous friction states per law, stored from an offset in the state vector.
N_Q = {LUGRE: 1, GMS: N_GMS, LS_B: 2}
N_Q_MAX = N_GMS

EV_NONE, EV_REVERSAL, EV_BREAKAWAY = 0, 1, 2


def friction_parameters(params: dict, asymmetry: float = 0.0) -> np.ndarray:
    """The friction block of P from actuator parameters named as in stick-slip-dataset/1."""
    p = np.zeros(N_P_FRICTION)
    n = params["normal_force_n"]
    p[P_FS] = params["mu_s"] * n
    p[P_FC] = params["mu_d"] * n
    p[P_VS] = params["stribeck_velocity_m_per_s"]
    p[P_SIGMA0] = params["sigma0_n_per_m"]
    p[P_SIGMA1] = params["sigma1_ns_per_m"]
    p[P_SIGMA2] = params["sigma2_ns_per_m"]
    p[P_ASYM] = asymmetry
    p[P_GMS_C] = params.get("gms_attraction_n_per_s", GMS_ATTRACTION_N_PER_S)
    for i in range(N_GMS):
        p[P_GMS_K + i] = GMS_STIFFNESS_SHARE[i] * params["sigma0_n_per_m"]
        p[P_GMS_ALPHA + i] = GMS_WEIGHT[i]
    return p


def initial_discrete(p: np.ndarray, size: int = N_D_FRICTION) -> np.ndarray:
    """Discrete states of a virgin contact: no direction yet, the ls_b virgin branch spans Fs."""
    d = np.zeros(size)
    d[D_OMEGA_R] = p[P_FS]
    return d


@kernel
def copy_into(dst, src):
    """dst[:] = src without numba's temporary (kernels run without its allocator)."""
    for j in range(src.shape[0]):
        dst[j] = src[j]


@kernel
def sgn(v: float) -> float:
    if v > 0.0:
        return 1.0
    if v < 0.0:
        return -1.0
    return 0.0


@kernel
def stribeck(v: float, fs: float, fc: float, vs: float) -> float:
    """g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2), N."""
    r = v / vs
    return fc + (fs - fc) * math.exp(-r * r)


@kernel
def directional(level: float, p: np.ndarray, direction: float) -> float:
    """A friction level for sliding in `direction` (asymmetric_friction)."""
    return level * (1.0 + p[P_ASYM] * direction)


@kernel
def friction_rates(law, v, scale, kscale, p, y, dy, q0, d):
    """Friction force on the slider (N) for relative velocity v = rod - slider (m/s), and the
    rates of the friction states y[q0:] written to dy[q0:]. scale multiplies Fs and Fc (position
    and heat), kscale the contact stiffness (position); the direction factor of asymmetric
    friction is applied here from sgn(v)."""
    sv = sgn(v)
    fs = directional(p[P_FS] * scale, p, sv)
    fc = directional(p[P_FC] * scale, p, sv)
    g = stribeck(v, fs, fc, p[P_VS])
    s0 = p[P_SIGMA0] * kscale
    s1 = p[P_SIGMA1]
    av = abs(v)
    force = p[P_SIGMA2] * v
    if law == LUGRE:
        z = y[q0]
        dz = v - s0 * av * z / g
        dy[q0] = dz
        return force + s0 * z + s1 * dz
    if law == GMS:
        # A slipping element slips in the direction it broke away in (d[D_DIR], frozen over the
        # step): the same as sgn(v) while it slips, but an RK stage that lands just past a
        # reversal (located to O(h^2)) cannot flip the attraction target by 2 alpha_i g.
        c = p[P_GMS_C]
        slip_dir = d[D_DIR]
        gs = stribeck(v, directional(p[P_FS] * scale, p, slip_dir),
                      directional(p[P_FC] * scale, p, slip_dir), p[P_VS])  # fmt: skip
        for i in range(N_GMS):
            k = p[P_GMS_K + i] * kscale
            fi = y[q0 + i]
            sticking = d[D_MODE + i] == 0.0
            # sticking: the element deforms with the contact; slipping: attracted to alpha_i g
            rate = k * v if sticking else c * (p[P_GMS_ALPHA + i] * slip_dir - fi / gs)
            dy[q0 + i] = rate
            # micro-damping sigma_i dz_i/dt with z_i = F_i / k_i, sigma_i = sigma1 k_i / sigma0
            force += fi + s1 / s0 * rate
        return force
    # LS_B: F1 relaxes towards sgn(v) g(v) per unit displacement, normalised by the force span
    # |Omega_r| of the branch started at the last reversal; z is LuGre's bristle.
    f1 = y[q0]
    z = y[q0 + 1]
    df1 = s0 * (v * g - av * f1) / d[D_OMEGA_R]
    dz = v - s0 * av * z / g
    dy[q0] = df1
    dy[q0 + 1] = dz
    return force + f1 + s1 * dz


@kernel
def breakaway_margin(i, v, direction, scale, p, y, q0):
    """GMS element i: direction * F_i - alpha_i g(v) (N); it breaks away where this reaches 0."""
    fs = directional(p[P_FS] * scale, p, direction)
    fc = directional(p[P_FC] * scale, p, direction)
    g = stribeck(v, fs, fc, p[P_VS])
    return direction * y[q0 + i] - p[P_GMS_ALPHA + i] * g


@kernel
def reverse(law, new_direction, scale, p, y, q0, d):
    """The relative velocity changed sign: GMS elements stick again, ls_b starts a new branch
    whose span is the distance from F1 to the new direction's static level."""
    d[D_DIR] = new_direction
    if law == GMS:
        for i in range(N_GMS):
            d[D_MODE + i] = 0.0
    elif law == LS_B:
        target = new_direction * directional(p[P_FS] * scale, p, new_direction)
        d[D_OMEGA_R] = max(abs(target - y[q0]), 1e-6 * p[P_FS])


@kernel
def detect_event(law, v0, v1, scale0, scale1, p, y0, y1, q0, d):
    """First switch inside a step from state y0 (velocity v0) to y1 (v1), located by linear
    interpolation of its switching function: (fraction of the step, kind, element)."""
    if law == LUGRE:
        return 1.0, EV_NONE, -1
    direction = d[D_DIR]
    if direction != 0.0 and v1 * direction < 0.0:
        theta = v0 / (v0 - v1) if v0 != v1 else 0.0
        return min(max(theta, 0.0), 1.0), EV_REVERSAL, -1
    if law == GMS:
        s = sgn(v1)
        if s == 0.0:
            return 1.0, EV_NONE, -1
        best, which = 2.0, -1
        for i in range(N_GMS):
            if d[D_MODE + i] != 0.0:
                continue
            e1 = breakaway_margin(i, v1, s, scale1, p, y1, q0)
            if e1 < 0.0:
                continue
            e0 = breakaway_margin(i, v0, s, scale0, p, y0, q0)
            theta = e0 / (e0 - e1) if e0 < 0.0 else 0.0
            if theta < best:
                best, which = theta, i
        if which >= 0:
            return best, EV_BREAKAWAY, which
    return 1.0, EV_NONE, -1


@kernel
def break_away(i, v, d):
    """GMS element i starts to slip, in the direction of v (the contact's first motion sets
    the direction if none is known yet)."""
    if d[D_DIR] == 0.0:
        d[D_DIR] = sgn(v)
    d[D_MODE + i] = 1.0


@kernel
def apply_switches(law, v, scale, p, y, q0, d):
    """Switches due at a step boundary that no located event handled: a reversal, GMS elements
    that reached their slip level. Returns True when a discrete state changed."""
    if law == LUGRE:
        return False
    changed = False
    s = sgn(v)
    if s != 0.0 and s != d[D_DIR]:
        if d[D_DIR] == 0.0:
            d[D_DIR] = s  # first motion: the virgin branch needs no reset
        else:
            reverse(law, s, scale, p, y, q0, d)
        changed = True
    if law == GMS and s != 0.0:
        for i in range(N_GMS):
            if d[D_MODE + i] == 0.0 and breakaway_margin(i, v, s, scale, p, y, q0) >= 0.0:
                d[D_MODE + i] = 1.0
                changed = True
    return changed


@kernel
def _rk4_const_v(law, v, p, q, d, h, k1, k2, k3, k4, tmp):
    """One RK4 step of the friction states alone at a constant relative velocity v."""
    n = q.shape[0]
    friction_rates(law, v, 1.0, 1.0, p, q, k1, 0, d)
    for j in range(n):
        tmp[j] = q[j] + 0.5 * h * k1[j]
    friction_rates(law, v, 1.0, 1.0, p, tmp, k2, 0, d)
    for j in range(n):
        tmp[j] = q[j] + 0.5 * h * k2[j]
    friction_rates(law, v, 1.0, 1.0, p, tmp, k3, 0, d)
    for j in range(n):
        tmp[j] = q[j] + h * k3[j]
    friction_rates(law, v, 1.0, 1.0, p, tmp, k4, 0, d)
    for j in range(n):
        q[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])


@kernel
def _prescribed(law, p, x, dt, substeps, q, d, out, work):
    """Friction force along a prescribed relative displacement x (one value per dt): the
    velocity is constant on each interval, so reversals fall on interval boundaries exactly and
    GMS break-aways are located inside an interval by linear interpolation. work: (7, len(q))."""
    k1, k2, k3, k4 = work[0], work[1], work[2], work[3]
    tmp, q_old, dummy = work[4], work[5], work[6]
    h = dt / substeps
    out[0] = friction_rates(law, 0.0, 1.0, 1.0, p, q, dummy, 0, d)
    for j in range(1, x.shape[0]):
        v = (x[j] - x[j - 1]) / dt
        apply_switches(law, v, 1.0, p, q, 0, d)
        for _ in range(substeps):
            copy_into(q_old, q)
            _rk4_const_v(law, v, p, q, d, h, k1, k2, k3, k4, tmp)
            theta, kind, i = detect_event(law, v, v, 1.0, 1.0, p, q_old, q, 0, d)
            if kind == EV_BREAKAWAY:
                copy_into(q, q_old)
                _rk4_const_v(law, v, p, q, d, theta * h, k1, k2, k3, k4, tmp)
                break_away(i, v, d)  # located: switch even if the margin is a rounding short
                _rk4_const_v(law, v, p, q, d, (1.0 - theta) * h, k1, k2, k3, k4, tmp)
            apply_switches(law, v, 1.0, p, q, 0, d)
        out[j] = friction_rates(law, v, 1.0, 1.0, p, q, dummy, 0, d)


def friction_along(
    law: str,
    params: dict,
    x_m: np.ndarray,
    dt_s: float,
    asymmetry: float = 0.0,
    max_step_s: float = 1e-6,
) -> np.ndarray:
    """Friction force (N) of a virgin contact moved along x_m (relative displacement rod -
    slider, one sample per dt_s, piecewise linear in between). For curves and tests: the
    Stribeck curve from ramps, presliding virgin curves and hysteresis loops from slow cycles.
    RK4 steps are at most max_step_s: a slipping GMS element relaxes in g / C = 2 us."""
    code = LAW_CODES[law]
    p = friction_parameters(params, asymmetry)
    q = np.zeros(N_Q[code])
    d = initial_discrete(p)
    out = np.zeros(len(x_m))
    x = np.ascontiguousarray(x_m, dtype=np.float64)
    substeps = max(1, int(np.ceil(dt_s / max_step_s - 1e-9)))
    _prescribed(code, p, x, dt_s, substeps, q, d, out, np.zeros((7, len(q))))
    return out
