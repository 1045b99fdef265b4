"""Parameters, waveforms and simulation runs of the stick-slip actuator, on the C core."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from . import _native as N

MODELS = tuple(N.FRICTION_KINDS)  # the friction laws of docs/model.md: ls, lugre, gms
# the float core and the fixed-point core (docs/fixed-point.md); the one vocabulary of variants,
# in the order of the protocol's variant byte (0 float, 1 fixed point)
VARIANTS = ("f32", "q")


def _model_id(model: str) -> int:
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}, got {model!r}")
    return N.FRICTION_KINDS[model]


def _c_literal(x: float) -> float:
    """The decimal a float32 constant of the C library was written as (the shortest that rounds
    to it: 0.36f gives 0.36), so the defaults below are the C table's values, not their float32
    approximations, and a float32 of them is the C value again."""
    return float(str(np.float32(x)))


# Table I and the paper's drive have one home, the C library: the defaults below are read from it
_TABLE1 = N.table1_actuator()
_TABLE1_MU = N.table1_friction_mu()
_PAPER = N.paper_sawtooth()
DT_S = _c_literal(_TABLE1.dt_s)  # Table I's step, 1 us
# The GMS law's presliding stiffness decay exponent (ss_friction.h gms_decay), the C library's
# default: 1, a parabolic virgin curve, unless a calibration says otherwise. Not a dataset
# parameter (LS has no such).
GMS_DECAY = _c_literal(_TABLE1.friction.gms_decay)
# ... and the stiffness of each of its elements over the one before (gms_stiffness_ratio): 1,
# equal stiffnesses, unless a calibration says otherwise.
GMS_STIFFNESS_RATIO = _c_literal(_TABLE1.friction.gms_stiffness_ratio)


# names of the recorded state columns state_a, state_b (ss_actuator_trace_f32_t)
STATE_NAMES = {
    "ls": ("level_n", "presliding_n"),  # break-away level s, Masing presliding force F_M
    "lugre": ("z_m", "zdot_m_per_s"),  # bristle deflection and its rate
    "gms": ("level_n", "elastic_n"),  # slip level s, sum of the element forces
}


@dataclass(frozen=True)
class Effects:
    """The optional physical effects of the C model (ss_effects.h; docs/effects.md), zero = off.
    friction_asymmetry goes to the friction config, the rest to the effects config."""

    hysteresis_alpha: float = 0.0
    hysteresis_width_m: float = 0.0
    creep_ratio: float = 0.0
    creep_tau_s: float = 0.0
    load_n: float = 0.0
    friction_gradient_per_m: float = 0.0
    friction_asymmetry: float = 0.0
    slew_v_per_s: float = 0.0
    amp_bandwidth_hz: float = 0.0
    thermal_coeff_per_j: float = 0.0
    thermal_tau_s: float = 0.0
    base_mass_kg: float = 0.0
    base_freq_hz: float = 0.0
    base_damping_ratio: float = 0.0
    sensor_scale_error: float = 0.0

    def config(self) -> N.EffectsConfig:
        e = N.EffectsConfig()
        for f in fields(self):
            if f.name != "friction_asymmetry":
                setattr(e, f.name, getattr(self, f.name))
        return e

    def active(self) -> dict[str, float]:
        return {k: v for k, v in asdict(self).items() if v != 0.0}


@dataclass(frozen=True)
class ActuatorParams:
    """Actuator and friction parameters, named as in stick-slip-dataset/1 (SI units)."""

    mu_s: float = _c_literal(_TABLE1_MU.mu_s)
    mu_d: float = _c_literal(_TABLE1_MU.mu_d)
    normal_force_n: float = _c_literal(_TABLE1_MU.normal_force_n)
    piezo_stiffness_n_per_m: float = _c_literal(_TABLE1.piezo_stiffness_n_per_m)
    piezo_damping_kg_per_s: float = _c_literal(_TABLE1.piezo_damping_kg_per_s)
    rod_mass_kg: float = _c_literal(_TABLE1.rod_mass_kg)
    slider_mass_kg: float = _c_literal(_TABLE1.slider_mass_kg)
    stribeck_velocity_m_per_s: float = _c_literal(_TABLE1_MU.vs_m_per_s)
    sigma0_n_per_m: float = _c_literal(_TABLE1_MU.sigma0_n_per_m)
    sigma1_ns_per_m: float = _c_literal(_TABLE1_MU.sigma1_ns_per_m)
    sigma2_ns_per_m: float = _c_literal(_TABLE1_MU.sigma2_ns_per_m)
    piezo_gain_m_per_v: float = _c_literal(_TABLE1.piezo_gain_m_per_v)

    @classmethod
    def table1(cls) -> ActuatorParams:
        """Table I of the LS paper (the defaults, from the C library's
        ss_actuator_config_table1_f32 and ss_friction_mu_table1_f32), with 44 nm/V so 100 V
        gives 4.4 um."""
        return cls()

    @classmethod
    def from_dict(cls, d: dict, where: str = "actuator") -> ActuatorParams:
        names = {f.name for f in fields(cls)}
        unknown = sorted(set(d) - names)
        missing = sorted(names - set(d))
        if unknown or missing:
            raise ValueError(f"{where}: unknown keys {unknown}, missing keys {missing}")
        vals = {}
        for k in names:
            v = d[k]
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"{where}.{k}: expected a finite number, got {v!r}")
            vals[k] = float(v)
        return cls(**vals)

    def to_dict(self) -> dict:
        return asdict(self)

    @property
    def fs_n(self) -> float:
        return self.mu_s * self.normal_force_n

    @property
    def fc_n(self) -> float:
        return self.mu_d * self.normal_force_n

    def friction_config(self) -> N.FrictionConfig:
        # Fs = mu_s N is formed in float by the C library, exactly as firmware forms it
        return N.friction_config_from_mu(
            self.mu_s,
            self.mu_d,
            self.normal_force_n,
            self.stribeck_velocity_m_per_s,
            self.sigma0_n_per_m,
            self.sigma1_ns_per_m,
            self.sigma2_ns_per_m,
        )

    def actuator_config(
        self,
        model: str = "ls",
        dt_s: float = DT_S,
        effects: Effects | None = None,
        gms_decay: float = GMS_DECAY,
        gms_stiffness_ratio: float = GMS_STIFFNESS_RATIO,
    ) -> N.ActuatorConfig:
        """The C config; gms_decay and gms_stiffness_ratio shape the GMS law's presliding curve
        (the other laws ignore them; docs/model.md, "GMS (third law)")."""
        effects = effects or Effects()
        fcfg = self.friction_config()
        fcfg.asymmetry = effects.friction_asymmetry
        fcfg.gms_decay = gms_decay
        fcfg.gms_stiffness_ratio = gms_stiffness_ratio
        return N.ActuatorConfig(
            self.piezo_stiffness_n_per_m,
            self.piezo_damping_kg_per_s,
            self.rod_mass_kg,
            self.slider_mass_kg,
            self.piezo_gain_m_per_v,
            dt_s,
            _model_id(model),
            fcfg,
            effects.config(),
        )


@dataclass(frozen=True)
class Sawtooth:
    """The sawtooth of stick-slip-dataset/1: slow edge for rise_fraction of the period. The
    defaults are the LS paper's drive (ss_waveform_paper_f32 of the C library): 4.4 um at 500 Hz
    with a 100 us fall, forward, 20 cycles."""

    frequency_hz: float = _c_literal(_PAPER.frequency_hz)
    amplitude_v: float = _c_literal(_PAPER.amplitude_v)
    offset_v: float = _c_literal(_PAPER.offset_v)
    rise_fraction: float = _c_literal(_PAPER.rise_fraction)
    direction: int = int(_PAPER.direction)
    cycles: int = int(_PAPER.cycles)

    @classmethod
    def from_dict(cls, d: dict, where: str = "waveform") -> Sawtooth:
        if d.get("shape") != "sawtooth":
            raise ValueError(f"{where}.shape: only 'sawtooth' is defined, got {d.get('shape')!r}")
        kw: dict[str, Any] = {}
        for f in fields(cls):
            if f.name not in d:
                raise ValueError(f"{where}: missing key {f.name!r}")
            v = d[f.name]
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"{where}.{f.name}: expected a finite number, got {v!r}")
            kw[f.name] = v
        if kw["direction"] not in (1, -1):
            raise ValueError(f"{where}.direction: must be 1 or -1, got {kw['direction']!r}")
        if int(kw["cycles"]) != kw["cycles"] or kw["cycles"] < 0:
            raise ValueError(f"{where}.cycles: must be a whole number >= 0, got {kw['cycles']!r}")
        kw["direction"], kw["cycles"] = int(kw["direction"]), int(kw["cycles"])
        return cls(**kw)

    def to_dict(self) -> dict:
        return {"shape": "sawtooth", **asdict(self)}

    @property
    def period_s(self) -> float:
        return 1.0 / self.frequency_hz

    @property
    def fall_time_s(self) -> float:
        """Duration of the fast edge."""
        return (1.0 - self.rise_fraction) / self.frequency_hz

    @property
    def duration_s(self) -> float:
        return self.cycles / self.frequency_hz

    def with_fall_time(self, fall_time_s: float) -> Sawtooth:
        return replace(self, rise_fraction=1.0 - fall_time_s * self.frequency_hz)

    def config(self) -> N.WaveformConfig:
        w = N.WaveformConfig()
        w.kind = N.SS_WAVE_SAWTOOTH
        w.frequency_hz = self.frequency_hz
        w.amplitude_v = self.amplitude_v
        w.offset_v = self.offset_v
        w.rise_fraction = self.rise_fraction
        w.direction = self.direction
        w.cycles = self.cycles
        return w


@dataclass
class SimResult:
    """One simulated run. Arrays are float64 copies of the C model's outputs (float32, or the
    fixed-point variant's integers scaled to SI)."""

    model: str
    dt_s: float
    t_s: np.ndarray
    drive_v: np.ndarray
    x_p_m: np.ndarray
    x_rod_m: np.ndarray
    x_slider_m: np.ndarray
    v_rod_m_per_s: np.ndarray
    v_slider_m_per_s: np.ndarray
    force_n: np.ndarray
    state_a: np.ndarray
    state_b: np.ndarray
    x_meas_m: np.ndarray
    waveform: Sawtooth | None = None
    meta: dict = field(default_factory=dict)
    variant: str = "f32"
    heat_end_j: float = 0.0  # thermal_drift: the frictional heat stored at the end (J)

    @property
    def state_names(self) -> tuple[str, str]:
        return STATE_NAMES[self.model]

    def cycle_boundaries(self) -> np.ndarray:
        """Indices of the samples nearest to t = k / f, k = 0..cycles."""
        if self.waveform is None:
            raise ValueError("per-cycle figures need a periodic waveform")
        k = np.arange(self.waveform.cycles + 1)
        idx = np.rint(k * self.waveform.period_s / (self.t_s[1] - self.t_s[0])).astype(int)
        return np.clip(idx, 0, len(self.t_s) - 1)

    def per_cycle_steps(self) -> np.ndarray:
        """Slider displacement over each period (m), between its positions at the period
        boundaries t = k / f, interpolated between samples, as a measured run's figure is taken
        (cli.py, hil/session.py). A model step that does not divide the period puts no sample on
        a boundary, and the nearest sample, up to half a step off, moved a 500 Hz cycle's step by
        up to 1.2 % at 1.5 us (docs/model.md, "Per-cycle error over the drive matrix"). A cycle
        whose end the record does not reach (a run that stops within a step of its drive's end,
        or a decimated record) is left out: no sample holds its end."""
        if self.waveform is None:
            raise ValueError("per-cycle figures need a periodic waveform")
        t = self.t_s - self.t_s[0]
        k = np.arange(self.waveform.cycles + 1) * self.waveform.period_s
        slack = 1e-3 * (t[1] - t[0]) if len(t) > 1 else 0.0  # float rounding of the times
        k = k[k <= t[-1] + slack]
        return np.diff(np.interp(k, t, self.x_slider_m))

    @property
    def mean_step_m(self) -> float:
        steps = self.per_cycle_steps()
        return float(np.mean(steps)) if len(steps) else 0.0

    def summary(self) -> dict:
        s = {
            "model": self.model,
            "variant": self.variant,
            "dt_s": self.dt_s,
            "duration_s": float(self.t_s[-1]),
            "final_slider_position_m": float(self.x_slider_m[-1]),
        }
        if self.waveform is not None:
            steps = self.per_cycle_steps()
            s["waveform"] = self.waveform.to_dict()
            s["fall_time_s"] = self.waveform.fall_time_s
            s["mean_step_per_cycle_m"] = self.mean_step_m
            s["steady_step_per_cycle_m"] = float(np.median(steps[1:])) if len(steps) > 1 else None
            s["per_cycle_steps_m"] = [float(v) for v in steps]
        return s

    def to_csv(self, path: str | Path) -> None:
        a, b = self.state_names
        cols = [
            self.t_s,
            self.drive_v,
            self.x_p_m,
            self.x_rod_m,
            self.x_slider_m,
            self.force_n,
            self.state_a,
            self.state_b,
        ]
        header = f"t_s,drive_v,x_p_m,x_rod_m,x_slider_m,friction_n,{a},{b}"
        np.savetxt(
            path, np.column_stack(cols), delimiter=",", header=header, comments="", fmt="%.9g"
        )


def major_loop_gain(params: ActuatorParams, effects: Effects, stroke_v: float) -> ActuatorParams:
    """The parameters with the ideal strain's gain raised so that a piezo with the hysteresis of
    `effects` strokes the nominal gain x stroke_v over its major loop (0 -> stroke_v -> 0).

    A stack's gain is known from the stroke it makes at its rated voltage, and that stroke is
    measured through the hysteresis. The C model's Bouc-Wen loop on the ideal strain (docs/
    effects.md) costs the loop's full width in stroke, 2 h_top with h_top = alpha width
    tanh(S / 2 width) on a symmetric loop of ideal stroke S: without this, the same nominal gain
    describes a stack that strokes less by that width at every amplitude. stroke_v <= 0, or no
    hysteresis: params as they are."""
    a, w = effects.hysteresis_alpha, effects.hysteresis_width_m
    g = params.piezo_gain_m_per_v
    if stroke_v <= 0 or a <= 0 or w <= 0:
        return params
    target = g * stroke_v
    s = target
    for _ in range(50):  # Newton on S - 2 a w tanh(S / 2w) = target (slope >= 1 - a > 0)
        t = math.tanh(s / (2.0 * w))
        step = (s - 2.0 * a * w * t - target) / (1.0 - a * (1.0 - t * t))
        s -= step
        if abs(step) <= 1e-13 * target:
            break
    return replace(params, piezo_gain_m_per_v=s / stroke_v)


def _si_from_q(cols: dict[str, np.ndarray], model: str) -> dict[str, np.ndarray]:
    """The q core's integer columns in SI (float64), each times its Q format's scale."""
    state_a, state_b = N.TRACE_Q_STATES[model]
    signal = {"state_a": state_a, "state_b": state_b}
    names = {"drive_q16": "drive_v", "x_p_q40": "x_p_m", "x_rod_q40": "x_rod_m"}
    names |= {"x_slider_q40": "x_slider_m", "v_rod_q28": "v_rod_m_per_s", "force_q24": "force_n"}
    names |= {"v_slider_q28": "v_slider_m_per_s", "x_meas_q40": "x_meas_m"}
    res = {"step": cols["step"].astype(np.float64)}
    for k, v in cols.items():
        if k != "step":
            res[names.get(k, k)] = v.astype(np.float64) * N.q_scale(signal.get(k, k))
    return res


@dataclass
class _Setup:
    """A simulation's arguments, checked and turned into the C configs (simulate's first half)."""

    model: str
    dt_s: float
    decimation: int
    x0_m: float
    heat0_j: float
    variant: str
    cfg: Any
    wave_cfg: Any
    n_steps: int
    waveform: Sawtooth | None
    samples: np.ndarray | None  # a sampled drive: the C config points into it


def _setup(
    waveform: Sawtooth | None = None,
    params: ActuatorParams | None = None,
    model: str = "ls",
    dt_s: float = DT_S,
    hold_s: float = 0.0,
    decimation: int = 1,
    drive_v: np.ndarray | None = None,
    drive_interval_s: float | None = None,
    effects: Effects | None = None,
    x0_m: float = 0.0,
    variant: str = "f32",
    heat0_j: float = 0.0,
    gms_decay: float = GMS_DECAY,
    gms_stiffness_ratio: float = GMS_STIFFNESS_RATIO,
) -> _Setup:
    if variant not in VARIANTS:
        raise ValueError(f"variant must be one of {VARIANTS}, got {variant!r}")
    params = params or ActuatorParams.table1()
    cfg = params.actuator_config(model, dt_s, effects, gms_decay, gms_stiffness_ratio)
    N.check_config(cfg)
    if drive_v is None:
        waveform = waveform or Sawtooth()
        wave_cfg = waveform.config()
        duration = waveform.duration_s + hold_s
        samples = None
    else:
        if drive_interval_s is None:
            raise ValueError("drive_interval_s is required with drive_v")
        samples = np.ascontiguousarray(drive_v, dtype=np.float32)
        wave_cfg = N.sampled_waveform(samples, drive_interval_s)
        duration = (len(samples) - 1) * drive_interval_s + hold_s
        waveform = None
    if decimation < 1:
        raise ValueError(f"decimation must be >= 1, got {decimation}")
    # let the C library judge the waveform before its duration is trusted
    N.check_waveform(wave_cfg, dt_s)
    if not (math.isfinite(hold_s) and hold_s >= 0):
        raise ValueError(f"hold_s must be >= 0, got {hold_s}")
    n_steps = int(round(duration / dt_s))
    if n_steps > 2**31:
        raise ValueError(f"run too long: {n_steps} steps")
    if not math.isfinite(x0_m):
        raise ValueError(f"x0_m must be finite, got {x0_m}")
    if not (math.isfinite(heat0_j) and heat0_j >= 0):
        raise ValueError(f"heat0_j must be finite and >= 0, got {heat0_j}")
    if variant == "q":
        if heat0_j != 0.0:
            raise ValueError("the q variant has no thermal_drift (heat0_j must be 0)")
        if drive_v is not None:
            if hold_s != 0.0:
                raise ValueError("the q variant holds no sampled drive (hold_s must be 0)")
            q_dt_s = N.config_to_q(cfg).dt_q40 * 2.0**-40
            if not math.isclose(drive_interval_s or 0.0, q_dt_s, rel_tol=1e-6):
                raise ValueError(
                    f"the q variant takes a sampled drive one sample a step: drive_interval_s "
                    f"must be its step, {q_dt_s!r} s, got {drive_interval_s!r}"
                )
        if x0_m != 0.0:
            raise ValueError("the q variant starts the slider at 0 (x0_m must be 0)")
    return _Setup(
        model, dt_s, decimation, x0_m, heat0_j, variant, cfg, wave_cfg, n_steps, waveform, samples
    )


def _result(s: _Setup, f64: dict[str, np.ndarray], heat_end_j: float) -> SimResult:
    return SimResult(
        model=s.model,
        dt_s=s.dt_s,
        t_s=f64["step"] * s.dt_s,
        drive_v=f64["drive_v"],
        x_p_m=f64["x_p_m"],
        x_rod_m=f64["x_rod_m"],
        x_slider_m=f64["x_slider_m"],
        v_rod_m_per_s=f64["v_rod_m_per_s"],
        v_slider_m_per_s=f64["v_slider_m_per_s"],
        force_n=f64["force_n"],
        state_a=f64["state_a"],
        state_b=f64["state_b"],
        x_meas_m=f64["x_meas_m"],
        waveform=s.waveform,
        variant=s.variant,
        heat_end_j=heat_end_j,
    )


def _f64(cols: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {k: v.astype(np.float64) for k, v in cols.items()}


def simulate(
    waveform: Sawtooth | None = None,
    params: ActuatorParams | None = None,
    model: str = "ls",
    dt_s: float = DT_S,
    hold_s: float = 0.0,
    decimation: int = 1,
    drive_v: np.ndarray | None = None,
    drive_interval_s: float | None = None,
    effects: Effects | None = None,
    x0_m: float = 0.0,
    variant: str = "f32",
    heat0_j: float = 0.0,
    coarse_steps: int = 1,
    gms_decay: float = GMS_DECAY,
    gms_stiffness_ratio: float = GMS_STIFFNESS_RATIO,
    stick_steps: int = 0,
) -> SimResult:
    """Simulate the actuator under a sawtooth, or under sampled drive voltages (drive_v at
    drive_interval_s, linearly interpolated), with the C model; effects switch on optional
    physics, x0_m is where the slider starts, heat0_j the frictional heat the contact holds at the
    start (thermal_drift: what the run before left; SimResult.heat_end_j is what this one leaves);
    gms_decay and gms_stiffness_ratio the GMS law's presliding shape.
    variant "q" runs the fixed-point core (a sawtooth, or a drive sampled at its step taken one
    sample a step, as a q node's lock-step; the slider starting at 0; of the effects,
    the load, the slew limit, the sensor scale, the asymmetric friction, the hysteresis and the
    base: the converter refuses the others by name). coarse_steps > 1 (LuGre, LS; the q variant's
    n dt at most 8.6 us on Table I's rod, but for LS's split steps) takes up to that many steps as
    one where the contact sticks and the rod is quiet, 2 where the contact rings (docs/model.md,
    "Coarse steps while the contact sticks" and "The split step"; issue 17's 0.1 % holds with
    LuGre's 8 at 1 us and LS's 8 at 1.5 us): the same rows, fewer model steps
    (meta["model_steps"]). stick_steps > 0 (LuGre, with coarse_steps > 1; no
    effect but the load and the sensor's scale) also takes that many as one where the contact has
    stopped ringing, by the stuck contact's linear flow (docs/model.md, "Stick steps"); a stick step
    never crosses a row either, so it needs decimation of stick_steps or a multiple."""
    if not isinstance(coarse_steps, int) or coarse_steps < 1:
        raise ValueError(f"coarse_steps must be an integer >= 1, got {coarse_steps!r}")
    if isinstance(stick_steps, bool) or not isinstance(stick_steps, int) or stick_steps < 0:
        raise ValueError(f"stick_steps must be an integer >= 0, got {stick_steps!r}")
    if stick_steps and coarse_steps < 2:
        raise ValueError("stick_steps: with coarse_steps > 1 (a stick step is a coarse run's)")
    if stick_steps and decimation % stick_steps:
        raise ValueError(
            f"stick_steps {stick_steps}: decimation {decimation} is not a multiple of it (a stick "
            "step never crosses a row, so none would fit)"
        )
    if coarse_steps > 1 and variant == "q" and drive_v is not None:
        raise ValueError(
            "coarse_steps: the q variant's sawtooth only (a sampled drive bends each step)"
        )
    s = _setup(
        waveform,
        params,
        model,
        dt_s,
        hold_s,
        decimation,
        drive_v,
        drive_interval_s,
        effects,
        x0_m,
        variant,
        heat0_j,
        gms_decay,
        gms_stiffness_ratio,
    )
    if variant == "q" and coarse_steps > 1:
        cols, taken = N.run_q_coarse(
            s.cfg, s.wave_cfg, s.n_steps, decimation, coarse_steps, stick_steps
        )
        r = _result(s, _si_from_q(cols, model), 0.0)
        r.meta["model_steps"] = taken
        return r
    if variant == "q":
        if s.samples is not None:
            cols = N.run_q_samples(s.cfg, s.samples, decimation)
        else:
            cols = N.run_q(s.cfg, s.wave_cfg, s.n_steps, decimation)
        return _result(s, _si_from_q(cols, model), 0.0)
    if coarse_steps > 1:
        cols, heat_end, taken = N.run_f32_coarse(
            s.cfg, s.wave_cfg, s.n_steps, decimation, coarse_steps, x0_m, heat0_j, stick_steps
        )
        r = _result(s, _f64(cols), heat_end)
        r.meta["model_steps"] = taken
        return r
    cols, heat_end = N.run_f32(s.cfg, s.wave_cfg, s.n_steps, decimation, x0_m, heat0_j)
    return _result(s, _f64(cols), heat_end)


def simulate_many(requests: list[dict[str, Any]]) -> list[SimResult | ValueError]:
    """simulate(**r) for each request r, float variant only, with the same results, as one batch
    of the C core (four simulations stepped side by side, phase by phase: on one core 0.53 (LuGre)
    to 0.94 (GMS) x the time of the same runs one after the other, BENCHMARKS.md). A request that
    fails gives its ValueError in its place; the others still run."""
    out: list[SimResult | ValueError] = []
    setups: list[tuple[int, _Setup]] = []
    for i, r in enumerate(requests):
        try:
            s = _setup(**r)
            if s.variant != "f32":
                raise ValueError("simulate_many runs the float variant only")
            setups.append((i, s))
            out.append(ValueError("not run"))
        except ValueError as e:
            out.append(e)
    done = N.run_f32_many(
        [(s.cfg, s.wave_cfg, s.n_steps, s.decimation, s.x0_m, s.heat0_j) for _, s in setups]
    )
    for (i, s), d in zip(setups, done):
        out[i] = d if isinstance(d, ValueError) else _result(s, _f64(d[0]), d[1])
    return out


def drive_samples(waveform: Sawtooth, dt_s: float, n_steps: int) -> np.ndarray:
    """The drive at t = 0 and after each of n_steps steps, float32, from the C library's waveform
    player: exactly what the batch simulator feeds the actuator (for lock-step peers and
    controllers)."""
    return N.drive_samples(waveform.config(), dt_s, n_steps)


def friction_response(
    x_m: np.ndarray,
    dt_s: float,
    model: str = "ls",
    params: ActuatorParams | None = None,
    gms_decay: float = GMS_DECAY,
    gms_stiffness_ratio: float = GMS_STIFFNESS_RATIO,
) -> np.ndarray:
    """Friction force (N) of the C model under a prescribed relative displacement x_m, sampled
    every dt_s, starting from the virgin state at x_m[0]; gms_decay and gms_stiffness_ratio the
    GMS law's shape."""
    params = params or ActuatorParams.table1()
    _model_id(model)  # a ValueError naming the laws for an unknown one
    fcfg = params.friction_config()
    fcfg.gms_decay = gms_decay
    fcfg.gms_stiffness_ratio = gms_stiffness_ratio
    N.check_config(fcfg, "friction")
    dx = np.ascontiguousarray(np.diff(np.asarray(x_m, np.float64), prepend=x_m[0]), np.float32)
    return N.friction_run(model, fcfg, dx, dt_s).astype(np.float64)


def stribeck(v_m_per_s: np.ndarray, params: ActuatorParams | None = None) -> np.ndarray:
    """The Stribeck curve g(v) of the C library (N)."""
    return N.stribeck((params or ActuatorParams.table1()).friction_config(), v_m_per_s)
