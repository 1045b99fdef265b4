"""The cause catalog of stick-slip-diagnosis/1: what each cause is, which parameters of the C
model (ss_effects.h) it fits, their ranges and starting points, and the base parameters that
calibration fits for every model."""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Param:
    """One fitted parameter. The optimiser works on a dimensionless theta of order 1:
    value = ref * exp(theta) for "log" (scales: positive, spanning decades), value = theta * ref
    for "lin" (signed, zero = off)."""

    name: str
    kind: str  # "log" | "lin"
    ref: float
    lo: float
    hi: float
    grid: tuple[float, ...] = ()  # starting values tried before the local fit (nonconvex scales)

    def value(self, theta: float) -> float:
        return self.ref * math.exp(theta) if self.kind == "log" else theta * self.ref

    def theta(self, value: float) -> float:
        return math.log(value / self.ref) if self.kind == "log" else value / self.ref

    def bounds(self) -> tuple[float, float]:
        return self.theta(self.lo), self.theta(self.hi)


# Base calibration: the friction levels Fc = mu_d N and Fs = mu_s N, through normal_force_n and
# mu_s. The piezo gain stays at its nominal value: the model is invariant (up to the Stribeck
# velocity) under scaling gain, normal force and every length by one factor, so a gain error and
# a sensor scale error cannot be told apart from position data; the catalog names it
# sensor_scale_error. Masses and stiffnesses are datasheet values a lab can weigh and measure.
BASE_PARAMS = (
    Param("normal_force_n", "log", 10.0, 1.0, 100.0),
    # mu_s enters as the Stribeck excess mu_s - mu_d (kept > 0: Fs >= Fc), ref set per dataset
    Param("stribeck_excess", "log", 0.06, 1e-3, 1.0),
)

CAUSES: dict[str, str] = {
    "piezo_hysteresis": "rate-independent hysteresis between drive voltage and piezo strain",
    "piezo_creep": "slow drift of piezo strain after a voltage change",
    "external_load": "a constant force on the slider (gravity on a tilt, a cable, a spring)",
    "position_dependent_friction": "friction (normal force) varies with slider position",
    "asymmetric_friction": "friction differs between the two sliding directions",
    "amplifier_slew_limit": "the piezo voltage cannot follow the commanded fast edge",
    "thermal_drift": "friction changes as frictional heat accumulates during a run",
    "base_compliance": "the piezo's base is not rigid: an extra resonance between piezo and ground",
    "sensor_scale_error": "the position sensor's gain is off",
}

# Effects fields fitted for each cause (names of stickslip.model.Effects), and fixed companions.
CAUSE_PARAMS: dict[str, tuple[Param, ...]] = {
    "piezo_hysteresis": (
        Param("hysteresis_alpha", "lin", 0.1, 0.0, 0.9),
        Param("hysteresis_width_m", "log", 1e-6, 5e-8, 1e-4, grid=(2e-7, 5e-7, 1e-6, 2e-6, 5e-6)),
    ),
    "piezo_creep": (
        Param("creep_ratio", "lin", 0.05, 0.0, 1.0),
        Param("creep_tau_s", "log", 0.02, 2e-4, 10.0, grid=(1e-3, 3e-3, 1e-2, 3e-2, 0.1)),
    ),
    "external_load": (Param("load_n", "lin", 0.1, -3.0, 3.0),),
    "position_dependent_friction": (Param("friction_gradient_per_m", "lin", 300.0, -2e4, 2e4),),
    "asymmetric_friction": (Param("friction_asymmetry", "lin", 0.05, -0.8, 0.8),),
    "amplifier_slew_limit": (
        Param("slew_v_per_s", "log", 1e6, 1e4, 1e10, grid=(1e5, 2e5, 4e5, 8e5, 1.6e6, 3.2e6, 1e7)),
    ),
    "thermal_drift": (
        Param("thermal_coeff_per_j", "lin", 300.0, -3e4, 3e4, grid=(-500.0, 300.0, 1000.0)),
        Param("thermal_tau_s", "log", 0.1, 1e-3, 100.0, grid=(0.03, 0.1, 0.3, 1.0)),
    ),
    "base_compliance": (
        Param("base_mass_kg", "log", 0.02, 1e-3, 1.0, grid=(0.01, 0.04)),
        Param(
            "base_freq_hz",
            "log",
            4000.0,
            300.0,
            5e4,
            grid=(
                1000.0,
                1300.0,
                1700.0,
                2200.0,
                2900.0,
                3800.0,
                5000.0,
                6500.0,
                8500.0,
                11000.0,
                15000.0,
            ),
        ),
    ),
    "sensor_scale_error": (Param("sensor_scale_error", "lin", 0.01, -0.4, 0.4),),
}

# Values an effect needs besides its fitted parameters (fixed, documented in docs/diagnosis.md).
CAUSE_FIXED: dict[str, dict[str, float]] = {
    "base_compliance": {"base_damping_ratio": 0.05},
}

# Starting values (lin params start at zero = off, so a fit starts from the baseline).
CAUSE_START: dict[str, dict[str, float]] = {
    "piezo_hysteresis": {"hysteresis_alpha": 0.05, "hysteresis_width_m": 1e-6},
    "piezo_creep": {"creep_ratio": 0.02, "creep_tau_s": 0.01},
    "amplifier_slew_limit": {"slew_v_per_s": 1e7},
    "thermal_drift": {"thermal_coeff_per_j": 100.0, "thermal_tau_s": 0.2},
    "base_compliance": {"base_mass_kg": 0.02, "base_freq_hz": 4000.0},
}

assert set(CAUSES) == set(CAUSE_PARAMS)
