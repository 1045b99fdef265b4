"""The two-mass stick-slip actuator of the independent generator: drive chain (amplifier slew
limit, Prandtl-Ishlinskii hysteresis, Kelvin-Voigt creep), rod, slider, compliant base, heat,
integrated by fixed-step RK4 in float64 with located switches. Equations and the convergence
study: docs/independent-generator.md. Shares no code with lib/ and does not load the C library.
"""

from __future__ import annotations

import math

import numpy as np

from . import laws as L
from ._jit import kernel
from .effects import SENSOR_EFFECTS

# Plant block of the parameter vector P, after the friction block of laws.py.
_B = L.N_P_FRICTION
P_K = _B + 0  # piezo stiffness k, N/m
P_C = _B + 1  # piezo damping c, kg/s (on the stack's strain rate)
P_MR = _B + 2  # rod mass, kg
P_MC = _B + 3  # slider mass, kg
P_GAIN = _B + 4  # piezo gain, m/V
P_LOAD = _B + 5  # external_load: force on the slider, N (+ along +x)
P_GRAD = _B + 6  # position_dependent_friction: N(x)/N = 1 + grad x + curv x^2, 1/m
P_CURV = _B + 7  # 1/m^2
P_HYST_LIN = _B + 8  # piezo_hysteresis: weight of the linear part of the PI operator
P_HYST_PLAY = _B + 9  # weight of each play operator (0 = off)
P_HYST_VREF = _B + 10  # reference amplitude that sets the play thresholds, V
N_CREEP = 3
P_CREEP_R = _B + 11  # piezo_creep: N_CREEP retarded-strain ratios
P_CREEP_TAU = P_CREEP_R + N_CREEP  # and their time constants, s (0 = off)
P_SLEW = P_CREEP_TAU + N_CREEP  # amplifier_slew_limit: V/s (0 = off)
P_AMP_TAU = P_SLEW + 1  # amplifier small-signal time constant, s
P_BETA = P_SLEW + 2  # thermal_drift: friction levels times 1 - beta T, 1/K (0 = off)
P_CTH = P_SLEW + 3  # heat capacity of the contact node, J/K
P_RTH = P_SLEW + 4  # thermal resistance to ambient, K/W
P_MB = P_SLEW + 5  # base_compliance: base mass, kg (0 = off)
P_KB = P_SLEW + 6  # base spring to ground, N/m
P_CB = P_SLEW + 7  # base damper to ground, kg/s
P_HERTZ = P_SLEW + 8  # position_dependent_friction: contact stiffness times (N(x)/N)^this
NP = P_SLEW + 9

N_PLAY = 6
D_PLAY = L.N_D_FRICTION  # play operator outputs, V
ND = D_PLAY + N_PLAY

# Continuous state vector.
IXR, IVR, IXC, IVC, IXB, IVB = 0, 1, 2, 3, 4, 5  # rod, slider, base: position m, velocity m/s
IVA = 6  # voltage on the piezo behind a slew-limited amplifier, V
IW = 7  # N_CREEP creep element states, V
IT = IW + N_CREEP  # temperature rise of the contact above ambient, K
IQ = IT + 1  # friction states (laws.py)
NY = IQ + L.N_Q_MAX

# Recorded channels (plant.run returns them by name).
CHANNELS = ("x_slider_m", "x_rod_m", "v_slider_m_per_s", "v_rod_m_per_s", "friction_n",
            "x_piezo_m", "v_piezo_v", "drive_v", "temperature_k", "x_base_m")  # fmt: skip
_XC, _XR, _VC, _VR, _F, _XP, _VPZ, _VCMD, _T, _XB = range(len(CHANNELS))

MIN_LEVEL = 0.05  # friction level factors never fall below this (a normal force stays positive)
DT_S = 0.2e-6  # default integration step (docs/independent-generator.md, convergence)


@kernel
def normal_force_scale(y, p):
    """N(x) / N at the slider position (position_dependent_friction)."""
    x = y[IXC]
    return max(1.0 + p[P_GRAD] * x + p[P_CURV] * x * x, MIN_LEVEL)


@kernel
def friction_scale(y, p):
    """Factor on Fs and Fc from the slider position (normal force) and the contact temperature."""
    s = 1.0
    if p[P_GRAD] != 0.0 or p[P_CURV] != 0.0:
        s = normal_force_scale(y, p)
    if p[P_BETA] != 0.0:
        s *= max(1.0 - p[P_BETA] * y[IT], MIN_LEVEL)
    return s


@kernel
def stiffness_scale(y, p):
    """Factor on the contact stiffness: a Hertzian contact's tangential stiffness grows with the
    contact radius, as N^(1/3) (Mindlin), so it follows the normal force along the rod."""
    if p[P_HERTZ] == 0.0 or (p[P_GRAD] == 0.0 and p[P_CURV] == 0.0):
        return 1.0
    return normal_force_scale(y, p) ** p[P_HERTZ]


@kernel
def play_threshold(j, p):
    """Thresholds spread evenly over half the reference amplitude, V."""
    return (j + 0.5) / N_PLAY * 0.5 * p[P_HYST_VREF]


@kernel
def piezo_input(vpz, p, d):
    """Prandtl-Ishlinskii operator: the hysteretic voltage that the piezo strains by, V."""
    if p[P_HYST_PLAY] == 0.0:
        return vpz
    u = p[P_HYST_LIN] * vpz
    for j in range(N_PLAY):
        r = play_threshold(j, p)
        u += p[P_HYST_PLAY] * min(max(d[D_PLAY + j], vpz - r), vpz + r)
    return u


@kernel
def commit_plays(vpz, p, d):
    """Plays are rate independent: their outputs depend on the voltage path only, so they are
    advanced once per step from the voltage at its end (monotone within a step)."""
    if p[P_HYST_PLAY] == 0.0:
        return
    for j in range(N_PLAY):
        r = play_threshold(j, p)
        d[D_PLAY + j] = min(max(d[D_PLAY + j], vpz - r), vpz + r)


@kernel
def rhs(law, t, y, d, p, t0, v0, rate, dy, aux):
    """dy/dt at time t; aux gets the friction force, piezo strain, piezo and command voltage."""
    vcmd = v0 + rate * (t - t0)
    if p[P_SLEW] > 0.0:
        vpz = y[IVA]
        s = p[P_SLEW]
        dy[IVA] = min(max((vcmd - vpz) / p[P_AMP_TAU], -s), s)
    else:
        vpz = vcmd
        dy[IVA] = 0.0
    u = piezo_input(vpz, p, d)
    strain_v = u
    for j in range(N_CREEP):
        tau = p[P_CREEP_TAU + j]
        if tau > 0.0:
            dy[IW + j] = (u - y[IW + j]) / tau
            strain_v += p[P_CREEP_R + j] * y[IW + j]
        else:
            dy[IW + j] = 0.0
    xp = p[P_GAIN] * strain_v
    v = y[IVR] - y[IVC]
    for j in range(L.N_Q_MAX):
        dy[IQ + j] = 0.0
    f = L.friction_rates(law, v, friction_scale(y, p), stiffness_scale(y, p), p, y, dy, IQ, d)
    # the stack sits between base and rod: its force on the rod, and the reaction on the base
    fpz = p[P_K] * (y[IXB] + xp - y[IXR]) - p[P_C] * (y[IVR] - y[IVB])
    dy[IXR] = y[IVR]
    dy[IVR] = (fpz - f) / p[P_MR]
    dy[IXC] = y[IVC]
    dy[IVC] = (f + p[P_LOAD]) / p[P_MC]
    if p[P_MB] > 0.0:
        dy[IXB] = y[IVB]
        dy[IVB] = -(p[P_KB] * y[IXB] + p[P_CB] * y[IVB] + fpz) / p[P_MB]
    else:
        dy[IXB] = 0.0
        dy[IVB] = 0.0
    if p[P_BETA] != 0.0:
        dy[IT] = (f * v - y[IT] / p[P_RTH]) / p[P_CTH]  # power into the contact, minus losses
    else:
        dy[IT] = 0.0
    aux[0] = f
    aux[1] = xp
    aux[2] = vpz
    aux[3] = vcmd


@kernel
def rk4(law, t, h, y, d, p, t0, v0, rate, k1, k2, k3, k4, tmp, yout, aux):
    """Classical RK4 from (t, y) over h with k1 = rhs(t, y) given; discrete states frozen."""
    n = y.shape[0]
    for j in range(n):
        tmp[j] = y[j] + 0.5 * h * k1[j]
    rhs(law, t + 0.5 * h, tmp, d, p, t0, v0, rate, k2, aux)
    for j in range(n):
        tmp[j] = y[j] + 0.5 * h * k2[j]
    rhs(law, t + 0.5 * h, tmp, d, p, t0, v0, rate, k3, aux)
    for j in range(n):
        tmp[j] = y[j] + h * k3[j]
    rhs(law, t + h, tmp, d, p, t0, v0, rate, k4, aux)
    for j in range(n):
        yout[j] = y[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])


@kernel
def piezo_voltage(y, p, t, t0, v0, rate):
    return y[IVA] if p[P_SLEW] > 0.0 else v0 + rate * (t - t0)


N_WORK = 10  # rows of the work array integrate() needs
MAX_EVENTS = 8  # switches located inside one step; any further ones apply at its end


@kernel
def advance(law, t, h, y, d, p, t0, v0, rate, k1, work, aux):
    """Advance y over [t, t + h]. On entry k1 = rhs(t, y); on exit k1 = rhs(t + h, y) and aux
    holds the channels at t + h. A switch inside the step (velocity reversal, GMS break-away) is
    located by linear interpolation of its switching function, the step is split there and the
    switch applied at the split, so the frozen discrete state is never wrong for a whole step."""
    k2, k3, k4, tmp, y1, ym = work[0], work[1], work[2], work[3], work[4], work[5]
    tc = t
    left = h
    for _ in range(MAX_EVENTS):
        rk4(law, tc, left, y, d, p, t0, v0, rate, k1, k2, k3, k4, tmp, y1, aux)
        va = y[IVR] - y[IVC]
        vb = y1[IVR] - y1[IVC]
        theta, kind, which = L.detect_event(
            law, va, vb, friction_scale(y, p), friction_scale(y1, p), p, y, y1, IQ, d
        )
        if kind == L.EV_NONE:
            break
        h1 = theta * left
        if h1 > 0.0:
            rk4(law, tc, h1, y, d, p, t0, v0, rate, k1, k2, k3, k4, tmp, ym, aux)
            L.copy_into(y, ym)
        if kind == L.EV_REVERSAL:
            L.reverse(law, -d[L.D_DIR], friction_scale(y, p), p, y, IQ, d)
        else:
            L.break_away(which, vb, d)
        tc += h1
        left -= h1
        commit_plays(piezo_voltage(y, p, tc, t0, v0, rate), p, d)
        rhs(law, tc, y, d, p, t0, v0, rate, k1, aux)
    else:
        rk4(law, tc, left, y, d, p, t0, v0, rate, k1, k2, k3, k4, tmp, y1, aux)
    L.copy_into(y, y1)
    commit_plays(piezo_voltage(y, p, t + h, t0, v0, rate), p, d)
    L.apply_switches(law, y[IVR] - y[IVC], friction_scale(y, p), p, y, IQ, d)
    rhs(law, t + h, y, d, p, t0, v0, rate, k1, aux)


@kernel
def _record(out, js, a, b, ya, yb, auxa, auxb, h):
    """Channels at fraction b of a step (a = 1 - b): cubic Hermite for the positions (from their
    velocities, error O(h^4)), linear for the rest."""
    b2 = b * b
    b3 = b2 * b
    h00 = 2.0 * b3 - 3.0 * b2 + 1.0
    h10 = (b3 - 2.0 * b2 + b) * h
    h01 = -2.0 * b3 + 3.0 * b2
    h11 = (b3 - b2) * h
    out[js, _XC] = h00 * ya[IXC] + h10 * ya[IVC] + h01 * yb[IXC] + h11 * yb[IVC]
    out[js, _XR] = h00 * ya[IXR] + h10 * ya[IVR] + h01 * yb[IXR] + h11 * yb[IVR]
    out[js, _XB] = h00 * ya[IXB] + h10 * ya[IVB] + h01 * yb[IXB] + h11 * yb[IVB]
    out[js, _VC] = a * ya[IVC] + b * yb[IVC]
    out[js, _VR] = a * ya[IVR] + b * yb[IVR]
    out[js, _T] = a * ya[IT] + b * yb[IT]
    out[js, _F] = a * auxa[0] + b * auxb[0]
    out[js, _XP] = a * auxa[1] + b * auxb[1]
    out[js, _VPZ] = a * auxa[2] + b * auxb[2]
    out[js, _VCMD] = a * auxa[3] + b * auxb[3]


@kernel
def integrate(law, p, y, d, seg_t0, seg_t1, seg_v0, seg_v1, dt_max, ts, out, work):
    """Integrate over piecewise-linear drive segments (each corner a step boundary, each segment
    cut into equal steps <= dt_max); record the channels at the times ts into out. y and d are
    advanced in place, so consecutive calls continue the same experiment. work: (N_WORK, NY)."""
    k1 = work[6]
    y_prev = work[7]
    aux = work[8, :4]
    aux_prev = work[9, :4]
    ns = ts.shape[0]
    js = 0
    span0 = seg_t1[0] - seg_t0[0]
    rate0 = (seg_v1[0] - seg_v0[0]) / span0 if span0 > 0.0 else 0.0
    rhs(law, seg_t0[0], y, d, p, seg_t0[0], seg_v0[0], rate0, k1, aux)
    while js < ns and ts[js] <= seg_t0[0]:
        _record(out, js, 1.0, 0.0, y, y, aux, aux, 0.0)
        js += 1
    for s in range(seg_t0.shape[0]):
        t0 = seg_t0[s]
        span = seg_t1[s] - t0
        if span <= 0.0:
            continue
        rate = (seg_v1[s] - seg_v0[s]) / span
        nsteps = max(1, int(math.ceil(span / dt_max - 1e-9)))
        h = span / nsteps
        for k in range(nsteps):
            t = t0 + k * h
            L.copy_into(y_prev, y)
            L.copy_into(aux_prev, aux)
            advance(law, t, h, y, d, p, t0, seg_v0[s], rate, k1, work, aux)
            t_end = seg_t1[s] if k == nsteps - 1 else t + h
            while js < ns and ts[js] <= t_end + 1e-9 * h:
                b = min(max((ts[js] - t) / h, 0.0), 1.0)
                _record(out, js, 1.0 - b, b, y_prev, y, aux_prev, aux, h)
                js += 1
    while js < ns:
        _record(out, js, 1.0, 0.0, y, y, aux, aux, 0.0)
        js += 1


MECHANICAL_EFFECTS = (
    "external_load",
    "asymmetric_friction",
    "position_dependent_friction",
    "piezo_hysteresis",
    "piezo_creep",
    "amplifier_slew_limit",
    "thermal_drift",
    "base_compliance",
)


def build_parameters(law: str, params: dict, effects: dict | None = None) -> np.ndarray:
    """The parameter vector P from actuator parameters (stick-slip-dataset/1 names) and the
    mechanical effects (effects.py names; sensor effects act after the plant and are ignored)."""
    effects = effects or {}
    unknown = sorted(set(effects) - set(MECHANICAL_EFFECTS) - set(SENSOR_EFFECTS))
    if unknown:
        raise ValueError(f"unknown effects {unknown}; the plant knows {MECHANICAL_EFFECTS}")
    asym = effects.get("asymmetric_friction", {}).get("asymmetry", 0.0)
    p = np.zeros(NP)
    p[: L.N_P_FRICTION] = L.friction_parameters(params, asym)
    p[P_K] = params["piezo_stiffness_n_per_m"]
    p[P_C] = params["piezo_damping_kg_per_s"]
    p[P_MR] = params["rod_mass_kg"]
    p[P_MC] = params["slider_mass_kg"]
    p[P_GAIN] = params["piezo_gain_m_per_v"]
    p[P_LOAD] = effects.get("external_load", {}).get("load_n", 0.0)
    pos = effects.get("position_dependent_friction", {})
    p[P_GRAD] = pos.get("gradient_per_m", 0.0)
    p[P_CURV] = pos.get("curvature_per_m2", 0.0)
    p[P_HERTZ] = pos.get("stiffness_exponent", 1.0 / 3.0)
    hy = effects.get("piezo_hysteresis")
    p[P_HYST_LIN] = 1.0
    if hy:
        p[P_HYST_LIN], p[P_HYST_PLAY] = play_weights(hy["hysteresis_ratio"])
        p[P_HYST_VREF] = hy.get("reference_v", 100.0)
    cr = effects.get("piezo_creep")
    if cr:
        for j, (share, tau_share) in enumerate(zip(CREEP_SHARES, CREEP_TAU_SHARES)):
            p[P_CREEP_R + j] = share * cr["creep_ratio"]
            p[P_CREEP_TAU + j] = tau_share * cr["creep_tau_s"]
    sl = effects.get("amplifier_slew_limit")
    if sl:
        p[P_SLEW] = sl["slew_v_per_s"]
        p[P_AMP_TAU] = 1.0 / (2.0 * math.pi * sl.get("bandwidth_hz", 160e3))
    th = effects.get("thermal_drift")
    if th:
        p[P_BETA] = th["beta_per_k"]
        p[P_CTH] = th["heat_capacity_j_per_k"]
        p[P_RTH] = th["tau_s"] / th["heat_capacity_j_per_k"]
    ba = effects.get("base_compliance")
    if ba:
        w = 2.0 * math.pi * ba["base_freq_hz"]
        p[P_MB] = ba["base_mass_kg"]
        p[P_KB] = ba["base_mass_kg"] * w * w
        p[P_CB] = 2.0 * ba["damping_ratio"] * ba["base_mass_kg"] * w
    return p


# piezo_creep: three Kelvin-Voigt elements with equal shares of the creep ratio and time
# constants tau/9, tau/3, tau: a strain that grows about linearly in log t from tau/20 to tau
# (the logarithmic creep law) and has gained 86 % of the ratio at t = tau.
CREEP_SHARES = (1 / 3, 1 / 3, 1 / 3)
CREEP_TAU_SHARES = (1 / 9, 1 / 3, 1.0)


def play_weights(hysteresis_ratio: float) -> tuple[float, float]:
    """Linear weight and per-play weight of the PI operator such that a 0 -> Vref -> 0 cycle
    keeps the stroke gain * Vref and its loop is hysteresis_ratio * stroke wide at the widest
    (mid-voltage). Per unit play weight the plays add sum(1 - 2 rho_j) of stroke and
    sum(min(2 rho_j, 1 - 2 rho_j)) of width (rho_j = r_j / Vref)."""
    rho = (np.arange(N_PLAY) + 0.5) / N_PLAY * 0.5
    stroke = float(np.sum(1.0 - 2.0 * rho))
    width = float(np.sum(np.minimum(2.0 * rho, 1.0 - 2.0 * rho)))
    w_play = hysteresis_ratio / width
    return 1.0 - w_play * stroke, w_play


def sawtooth_segments(
    frequency_hz: float,
    amplitude_v: float,
    offset_v: float,
    rise_fraction: float,
    direction: int,
    cycles: int,
    hold_s: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Corners of the stick-slip-dataset/1 sawtooth (and a hold at offset_v after the last
    period) as segments (t0_s, t1_s, v0_v, v1_v); time from the start of the run."""
    period = 1.0 / frequency_hz
    first = rise_fraction if direction > 0 else 1.0 - rise_fraction
    n = np.arange(cycles)
    t_start = n * period
    t_mid = t_start + first * period
    t_end = (n + 1) * period
    top = offset_v + amplitude_v
    t0 = np.column_stack([t_start, t_mid]).ravel()
    t1 = np.column_stack([t_mid, t_end]).ravel()
    v0 = np.tile([offset_v, top], cycles)
    v1 = np.tile([top, offset_v], cycles)
    if hold_s > 0.0:
        end = cycles * period
        t0 = np.append(t0, end)
        t1 = np.append(t1, end + hold_s)
        v0 = np.append(v0, offset_v)
        v1 = np.append(v1, offset_v)
    return t0, t1, v0.astype(float), v1.astype(float)


class Plant:
    """One actuator with its friction law and mechanical effects, at rest and virgin at x = 0.
    run() plays drive segments from the current state, so consecutive runs continue one
    experiment (the slider, the friction memory, heat, creep and hysteresis carry over)."""

    def __init__(self, law: str, params: dict, effects: dict | None = None, dt_s: float = DT_S):
        if law not in L.LAW_CODES:
            raise ValueError(f"law must be one of {L.LAWS}, got {law!r}")
        self.law = law
        self.code = L.LAW_CODES[law]
        self.dt_s = float(dt_s)
        self.p = build_parameters(law, params, effects)
        self.y = np.zeros(NY)
        self.d = np.zeros(ND)
        self.d[: L.N_D_FRICTION] = L.initial_discrete(self.p)

    def run(self, segments, sample_times_s) -> dict[str, np.ndarray]:
        """Play segments (t0_s, t1_s, v0_v, v1_v) and return CHANNELS at sample_times_s."""
        t0, t1, v0, v1 = (np.ascontiguousarray(a, dtype=np.float64) for a in segments)
        ts = np.ascontiguousarray(sample_times_s, dtype=np.float64)
        out = np.zeros((len(ts), len(CHANNELS)))
        work = np.zeros((N_WORK, NY))
        integrate(self.code, self.p, self.y, self.d, t0, t1, v0, v1, self.dt_s, ts, out, work)
        res = {name: out[:, j].copy() for j, name in enumerate(CHANNELS)}
        res["t_s"] = ts.copy()
        return res

    def hold(self, duration_s: float, voltage_v: float = 0.0) -> None:
        """Let the actuator rest at a constant drive for a while, unrecorded."""
        seg = ([0.0], [duration_s], [voltage_v], [voltage_v])
        self.run(seg, np.zeros(0))


def run_sawtooth(
    law: str,
    params: dict,
    frequency_hz: float,
    amplitude_v: float = 100.0,
    direction: int = 1,
    cycles: int = 10,
    fall_time_s: float = 15e-6,
    effects: dict | None = None,
    dt_s: float = DT_S,
) -> np.ndarray:
    """Slider position (m) at the start of each period and at the end of the last one, from a
    virgin actuator at rest: the staircase, for per-cycle steps and convergence checks."""
    plant = Plant(law, params, effects, dt_s)
    rise = 1.0 - fall_time_s * frequency_hz
    seg = sawtooth_segments(frequency_hz, amplitude_v, 0.0, rise, direction, cycles)
    ts = np.arange(cycles + 1) / frequency_hz
    return plant.run(seg, ts)["x_slider_m"]
