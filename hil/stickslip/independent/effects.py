"""The effects the independent generator can hide in a dataset: their parameters, the physical
ranges they are drawn from, and the sensor models (which act on the true slider position after
the plant). Equations: docs/independent-generator.md, "Effects".
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

# The diagnosis catalog (stick-slip-diagnosis/1 names), and two sensor errors outside it.
EFFECTS: tuple[str, ...] = (
    "external_load",
    "asymmetric_friction",
    "position_dependent_friction",
    "piezo_hysteresis",
    "piezo_creep",
    "amplifier_slew_limit",
    "thermal_drift",
    "base_compliance",
    "sensor_scale_error",
)
OUTSIDE_EFFECTS: tuple[str, ...] = ("sensor_periodic_error", "sensor_cubic")
SENSOR_EFFECTS = ("sensor_scale_error", "sensor_periodic_error", "sensor_cubic")

HE_NE_WAVELENGTH_M = 632.8e-9


def _logu(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _sign(rng: np.random.Generator) -> float:
    return 1.0 if rng.random() < 0.5 else -1.0


# name -> (draw(rng) -> parameters, keys a caller may set). Scales are drawn log-uniformly,
# signed sizes uniformly in magnitude with a random sign.
_DRAWS: dict[str, Callable[[np.random.Generator], dict]] = {
    # a constant force on the slider (tilt, cable, preload spring), N, + along +x
    "external_load": lambda r: {"load_n": _sign(r) * r.uniform(0.1, 0.4)},
    # Fs and Fc times 1 + a sgn(v_rod - v_slider)
    "asymmetric_friction": lambda r: {"asymmetry": _sign(r) * r.uniform(0.04, 0.12)},
    # N(x) = N (1 + gradient x + curvature x^2), x the slider position from the start; Fs, Fc
    # follow N, the contact stiffness follows N^stiffness_exponent (Hertz-Mindlin: 1/3)
    "position_dependent_friction": lambda r: {
        "gradient_per_m": _sign(r) * r.uniform(400.0, 1200.0),
        "curvature_per_m2": r.uniform(-1e5, 1e5),
        "stiffness_exponent": 1.0 / 3.0,
    },
    # Prandtl-Ishlinskii loop width at mid-voltage over the stroke of a 0-reference_v cycle
    "piezo_hysteresis": lambda r: {"hysteresis_ratio": r.uniform(0.05, 0.15), "reference_v": 100.0},
    # generalised Kelvin-Voigt creep: strain grows by creep_ratio after a step, 86 % by tau
    "piezo_creep": lambda r: {
        "creep_ratio": r.uniform(0.03, 0.10),
        "creep_tau_s": _logu(r, 5e-3, 50e-3),
    },
    # current-limited amplifier on the piezo capacitance: |dV/dt| <= slew
    "amplifier_slew_limit": lambda r: {
        "slew_v_per_s": _logu(r, 0.3e6, 1.5e6),
        "bandwidth_hz": 160e3,
    },
    # lumped contact node heated by the friction power; friction levels times 1 - beta T
    "thermal_drift": lambda r: {
        "beta_per_k": r.uniform(3e-3, 6e-3),
        "heat_capacity_j_per_k": _logu(r, 1.5e-5, 4e-5),
        "tau_s": _logu(r, 0.03, 0.06),
    },
    # the piezo's base on a spring-damper to ground; base_freq_hz = sqrt(k_b / m_b) / 2 pi
    "base_compliance": lambda r: {
        "base_mass_kg": _logu(r, 0.01, 0.05),
        "base_freq_hz": _logu(r, 2000.0, 8000.0),
        "damping_ratio": r.uniform(0.02, 0.1),
    },
    # the sensor reports (1 + e) x
    "sensor_scale_error": lambda r: {"scale_error": _sign(r) * r.uniform(0.02, 0.06)},
    # interferometer periodic nonlinearity: A sin(4 pi x / lambda + phase)
    "sensor_periodic_error": lambda r: {
        "amplitude_m": r.uniform(5e-9, 20e-9),
        "wavelength_m": HE_NE_WAVELENGTH_M,
        "phase_rad": r.uniform(0.0, 2.0 * math.pi),
    },
    # a cubic sensor nonlinearity over the travel, A (s^3 - 0.6 s), s in [-1, 1] over the
    # travel (center and half span from the dataset's true travel unless given)
    "sensor_cubic": lambda r: {
        "amplitude_m": r.uniform(40e-9, 100e-9),
        "center_m": None,
        "half_span_m": None,
    },
}


def draw_effect(name: str, rng: np.random.Generator) -> dict:
    """Parameters of one effect drawn from its documented physical range."""
    if name not in _DRAWS:
        raise ValueError(f"unknown effect {name!r}; known: {EFFECTS + OUTSIDE_EFFECTS}")
    return _DRAWS[name](rng)


def resolve(effects: dict | None, rng: np.random.Generator) -> dict[str, dict]:
    """Complete parameter dicts: keys the caller gave are kept, the rest drawn from the ranges
    (so effects={"external_load": {}} or None draws the whole effect)."""
    out: dict[str, dict] = {}
    for name, given in (effects or {}).items():
        drawn = draw_effect(name, rng)
        given = dict(given or {})
        unknown = sorted(set(given) - set(drawn))
        if unknown:
            raise ValueError(f"{name}: unknown parameters {unknown}; known: {sorted(drawn)}")
        drawn.update(given)
        out[name] = drawn
    return out


def sensor_reading(effects: dict[str, dict], x_true_m: np.ndarray) -> np.ndarray:
    """What the position sensor reports for the true slider position (before noise)."""
    x = np.asarray(x_true_m, dtype=float)
    out = x.copy()
    if "sensor_scale_error" in effects:
        out += effects["sensor_scale_error"]["scale_error"] * x
    if "sensor_periodic_error" in effects:
        e = effects["sensor_periodic_error"]
        out += e["amplitude_m"] * np.sin(4.0 * np.pi * x / e["wavelength_m"] + e["phase_rad"])
    if "sensor_cubic" in effects:
        e = effects["sensor_cubic"]
        s = (x - e["center_m"]) / e["half_span_m"]
        out += e["amplitude_m"] * (s**3 - 0.6 * s)  # orthogonal to a scale error over [-1, 1]
    return out
