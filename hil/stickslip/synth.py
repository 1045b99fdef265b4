"""Synthetic measured data: the experiment design a lab should record, and a generator that plays
it through the C model with hidden effects, sensor noise and quantisation (stick-slip-dataset/1).

The design is what makes each cause of the catalog identifiable (docs/diagnosis.md): both
directions (load, asymmetry), two amplitudes (hysteresis against gain), frequencies from 100 Hz to
2 kHz (slew limit, base resonance), a hold after the last period (creep relaxes), runs recorded one
after another along the travel (position dependence) and long enough for heat to build (thermal).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from . import dataset as D
from .model import ActuatorParams, Effects, Sawtooth, major_loop_gain, simulate

SAMPLE_INTERVAL_S = 20e-6  # 50 kS/s: 5 samples on a 100 us fast edge
HOLD_S = 0.01  # recorded after the last period, drive at offset: creep and ringing settle


@dataclass(frozen=True)
class RunDesign:
    id: str
    frequency_hz: float
    amplitude_v: float
    direction: int
    cycles: int

    def waveform(self) -> Sawtooth:
        return Sawtooth(self.frequency_hz, self.amplitude_v, 0.0, 0.95, self.direction, self.cycles)


def standard_design() -> list[RunDesign]:
    """The 12 runs of the minimum design, in the order a lab records them: each pair goes forward
    then back, so the slider covers the travel and returns near its start."""
    runs = []
    for f, a, n in (
        (500.0, 100.0, 20),
        (100.0, 100.0, 8),
        (1000.0, 100.0, 30),
        (2000.0, 100.0, 40),
        (500.0, 50.0, 20),
        (300.0, 75.0, 15),
    ):
        for d in (1, -1):
            tag = "fwd" if d > 0 else "rev"
            runs.append(RunDesign(f"f{int(f)}_a{int(a)}_{tag}", f, a, d, n))
    return runs


@dataclass
class Truth:
    """What a generated dataset hides: the true parameters and effects."""

    params: ActuatorParams
    effects: Effects = field(default_factory=Effects)
    causes: tuple[str, ...] = ()
    law: str = "ls"  # the friction law of the C library that plays the contact


# Physically plausible ranges of each hidden effect (the generator draws uniformly, log-uniformly
# for scales) and the Effects fields it sets. Sizes are chosen so the effect is a few per cent of
# the step or more: smaller ones are below what 20 cycles at 2 nm noise can separate reliably.
def draw_effect(cause: str, rng: np.random.Generator) -> dict[str, float]:
    def logu(lo: float, hi: float) -> float:
        return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))

    sign = 1.0 if rng.random() < 0.5 else -1.0
    if cause == "piezo_hysteresis":
        return {
            "hysteresis_alpha": rng.uniform(0.08, 0.2),
            "hysteresis_width_m": logu(0.5e-6, 2e-6),
        }
    if cause == "piezo_creep":
        return {"creep_ratio": rng.uniform(0.05, 0.15), "creep_tau_s": logu(5e-3, 50e-3)}
    if cause == "external_load":
        return {"load_n": sign * rng.uniform(0.1, 0.4)}
    if cause == "position_dependent_friction":
        return {"friction_gradient_per_m": sign * rng.uniform(400.0, 1200.0)}
    if cause == "asymmetric_friction":
        return {"friction_asymmetry": sign * rng.uniform(0.04, 0.12)}
    if cause == "amplifier_slew_limit":
        return {"slew_v_per_s": logu(3e5, 1.5e6)}
    if cause == "thermal_drift":
        # the standard design's runs, back to back, store up to about 1-5 mJ (tau 0.05-0.5 s):
        # at its warmest the friction falls by about 4-40 % (seeds 100-104: 9-25 %), as a
        # contact some kelvin warmer would; the former 300-900 /J took it to the model's 10 %
        # floor in the long run
        return {"thermal_coeff_per_j": rng.uniform(20.0, 80.0), "thermal_tau_s": logu(0.05, 0.5)}
    if cause == "base_compliance":
        return {
            "base_mass_kg": logu(0.01, 0.05),
            "base_freq_hz": logu(2000.0, 8000.0),
            "base_damping_ratio": 0.05,
        }
    if cause == "sensor_scale_error":
        return {"sensor_scale_error": sign * rng.uniform(0.02, 0.06)}
    raise ValueError(f"unknown cause {cause!r}")


def draw_truth(
    causes: tuple[str, ...], rng: np.random.Generator, miscalibrate: bool = False
) -> Truth:
    """Nominal Table I parameters with the given effects drawn at random; with miscalibrate, the
    true normal force and mu_s are off their nominal values (what calibration must find)."""
    p = ActuatorParams.table1()
    if miscalibrate:
        n = p.normal_force_n * rng.uniform(0.8, 1.25)
        mu_s = p.mu_d + (p.mu_s - p.mu_d) * rng.uniform(0.5, 1.5)
        p = replace(p, normal_force_n=n, mu_s=mu_s)
    kw: dict[str, float] = {}
    for c in causes:
        kw.update(draw_effect(c, rng))
    return Truth(p, Effects(**kw), tuple(causes))


def generate(
    path: str | Path,
    truth: Truth,
    seed: int,
    design: list[RunDesign] | None = None,
    noise_rms_m: float = 2e-9,
    resolution_m: float = 1e-9,
    nominal: ActuatorParams | None = None,
    sensor_distortion_m: float = 0.0,
    description: str = "",
) -> Path:
    """Write a dataset: every run of the design simulated with the true parameters and effects,
    the slider and the contact's heat carried from run to run, sensor noise and quantisation
    added. dataset.json carries the nominal parameters (Table I unless given), never the truth.
    sensor_distortion_m adds a periodic sensor error (20 um pitch) that no catalog cause
    describes."""
    rng = np.random.default_rng(seed)
    design = design or standard_design()
    runs = []
    x_start, heat = 0.0, 0.0
    # the nominal gain is the stroke over the largest amplitude's major loop, hysteresis and all
    params = major_loop_gain(truth.params, truth.effects, max(rd.amplitude_v for rd in design))
    for rd in design:
        w = rd.waveform()
        sim = simulate(
            w,
            params,
            hold_s=HOLD_S,
            decimation=int(round(SAMPLE_INTERVAL_S / 1e-6)),
            effects=truth.effects,
            x0_m=x_start,
            model=truth.law,
            heat0_j=heat,
        )
        # the first sample is the state before the run (t = 0)
        t = sim.t_s
        x_true = sim.x_slider_m
        x_meas = sim.x_meas_m
        x_start, heat = float(x_true[-1]), sim.heat_end_j
        if sensor_distortion_m:
            x_meas = x_meas + sensor_distortion_m * np.sin(2 * np.pi * x_true / 20e-6)
        x_noisy = x_meas + rng.normal(0.0, noise_rms_m, size=len(x_meas))
        if resolution_m > 0:
            x_noisy = np.round(x_noisy / resolution_m) * resolution_m
        runs.append(D.Run(rd.id, Path(f"{rd.id}.csv"), t, sim.drive_v, x_noisy, w))
    sensor = D.Sensor(resolution_m=resolution_m, noise_rms_m=noise_rms_m)
    return D.write(path, nominal or ActuatorParams.table1(), runs, description, sensor)
