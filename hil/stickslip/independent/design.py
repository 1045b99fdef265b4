"""Run designs and the dataset writer of the independent generator: play a design through the
plant (plant.py) with hidden effects, add sensor errors, noise and quantisation, and write a
stick-slip-dataset/1 folder (../shared/data-format.md) plus its truth beside it.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from . import effects as E
from . import laws as L
from .plant import DT_S, Plant, sawtooth_segments

FORMAT = "stick-slip-dataset/1"
TRUTH_FORMAT = "stick-slip-independent-truth/1"
GENERATOR = "stickslip.independent 1"

# Table I of the LS paper, with the stick-slip-dataset/1 names.
TABLE_I: dict[str, float] = {
    "mu_s": 0.36,
    "mu_d": 0.30,
    "normal_force_n": 10.0,
    "piezo_stiffness_n_per_m": 2.08e8,
    "piezo_damping_kg_per_s": 6.2,
    "rod_mass_kg": 1.1e-3,
    "slider_mass_kg": 1.38e-2,
    "stribeck_velocity_m_per_s": 4.0e-4,
    "sigma0_n_per_m": 1.0e7,
    "sigma1_ns_per_m": 80.0,
    "sigma2_ns_per_m": 8.0,
    "piezo_gain_m_per_v": 4.4e-8,
}

FALL_TIME_S = 15e-6  # the fast edge of every run
HOLD_S = 0.01  # at 0 V after each run, recorded: creep relaxes, ringing dies
SETTLE_S = 0.02  # unrecorded rest before the first run: a load deflects the contact, not run 1


@dataclass(frozen=True)
class RunSpec:
    """One run of a design: a sawtooth from 0 V with a 15 us fast edge."""

    id: str
    frequency_hz: float
    amplitude_v: float
    direction: int
    cycles: int

    @property
    def rise_fraction(self) -> float:
        return 1.0 - FALL_TIME_S * self.frequency_hz

    def waveform(self) -> dict:
        """The run's waveform block, exactly as stick-slip-dataset/1 defines it."""
        return {
            "shape": "sawtooth",
            "frequency_hz": float(self.frequency_hz),
            "amplitude_v": float(self.amplitude_v),
            "offset_v": 0.0,
            "rise_fraction": self.rise_fraction,
            "direction": int(self.direction),
            "cycles": int(self.cycles),
        }


def _run(f: float, a: float, d: int, n: int, tag: str = "") -> RunSpec:
    name = f"f{int(f)}_a{int(a)}_{'fwd' if d > 0 else 'rev'}{tag}"
    return RunSpec(name, f, a, d, n)


def _outside13() -> tuple[RunSpec, ...]:
    """Each frequency forward then back (load, asymmetry, slew limit, base resonance), two lower
    amplitudes (hysteresis against gain and sensor scale), one long run (heat, creep, travel)."""
    runs = [_run(f, 100.0, d, 20) for f in (100.0, 300.0, 500.0, 1000.0, 2000.0) for d in (1, -1)]
    runs += [_run(500.0, 50.0, 1, 20), _run(500.0, 75.0, 1, 20)]
    runs.append(_run(1000.0, 100.0, 1, 150, "_long"))
    return tuple(runs)


def _ci6() -> tuple[RunSpec, ...]:
    """The fewest runs that still separate the catalog (docs/independent-generator.md): two
    frequencies both ways, a second amplitude, one long run; the diagnosis holds out runs 3 and
    6 (2 kHz forward, the long run), so training keeps both directions, both amplitudes and both
    frequencies."""
    return (
        _run(500.0, 100.0, 1, 20),
        _run(500.0, 100.0, -1, 20),
        _run(2000.0, 100.0, 1, 20),
        _run(2000.0, 100.0, -1, 20),
        _run(500.0, 50.0, 1, 20),
        _run(1000.0, 100.0, 1, 60, "_long"),
    )


DESIGNS: dict[str, tuple[RunSpec, ...]] = {"outside13": _outside13(), "ci6": _ci6()}
DEFAULT_DESIGN = "outside13"


def _params(base: dict, overrides: dict | None, what: str) -> dict[str, float]:
    out = dict(base)
    for k, v in (overrides or {}).items():
        if k not in TABLE_I:
            raise ValueError(f"{what}: unknown parameter {k!r}; known: {sorted(TABLE_I)}")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ValueError(f"{what}.{k}: expected a finite number, got {v!r}")
        out[k] = float(v)
    return out


def _sample_times(duration_s: float, rate_hz: float) -> np.ndarray:
    n = int(math.floor(duration_s * rate_hz + 1e-9)) + 1
    return np.arange(n) / rate_hz


def _write_csv(path: Path, t: np.ndarray, drive: np.ndarray, x: np.ndarray, extra: dict) -> None:
    cols = [t, drive, x, *extra.values()]
    header = ",".join(["t_s", "drive_v", "x_m", *extra])
    fmt = ["%.10g", "%.10g", "%.12g"] + ["%.12g"] * len(extra)
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=header, comments="", fmt=fmt)


def truth_path(out_dir: str | Path) -> Path:
    """Where the truth of a dataset folder is written: beside it, <folder>.truth.json."""
    p = Path(out_dir)
    return p.parent / (p.name + ".truth.json")


def generate(
    out_dir: str | Path,
    law: str = "gms",
    effects: dict | None = None,
    seed: int = 0,
    sample_rate_hz: float = 250e3,
    design: str | tuple[RunSpec, ...] | list[RunSpec] = DEFAULT_DESIGN,
    noise_rms_m: float = 2e-9,
    resolution_m: float = 1e-9,
    true_params: dict | None = None,
    nominal_params: dict | None = None,
    dt_s: float = DT_S,
    hold_s: float = HOLD_S,
    rod_column: bool = False,
    description: str = "",
) -> dict:
    """Simulate every run of the design one after another along the travel (the slider, the
    friction memory, heat, creep and hysteresis carry over) and write the dataset folder.

    dataset.json gets the nominal parameters (Table I updated by nominal_params); the plant runs
    with the true ones (nominal updated by true_params, absolute values). effects maps effect
    names to parameter dicts; missing parameters are drawn from their ranges with a generator
    seeded by seed, and so is the sensor noise. Returns the truth (json-able) and writes it to
    truth_path(out_dir). rod_column adds the true rod position as x_rod_m."""
    t_start = time.perf_counter()
    if law not in L.LAWS:
        raise ValueError(f"law must be one of {L.LAWS}, got {law!r}")
    if isinstance(design, str) and design not in DESIGNS:
        raise ValueError(f"design must be one of {sorted(DESIGNS)} or a list of RunSpec")
    runs = DESIGNS[design] if isinstance(design, str) else tuple(design)
    if not runs:
        raise ValueError("design has no runs")
    if not 1e3 <= sample_rate_hz <= 10e6:
        raise ValueError(f"sample_rate_hz out of range: {sample_rate_hz!r}")
    nominal = _params(TABLE_I, nominal_params, "nominal_params")
    true = _params(nominal, true_params, "true_params")
    draw_rng, noise_rng = (np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(2))
    eff = E.resolve(effects, draw_rng)
    mechanical = {k: v for k, v in eff.items() if k not in E.SENSOR_EFFECTS}

    plant = Plant(law, true, mechanical, dt_s)
    plant.hold(SETTLE_S)
    records = []
    for rs in runs:
        seg = sawtooth_segments(
            rs.frequency_hz, rs.amplitude_v, 0.0, rs.rise_fraction, rs.direction, rs.cycles, hold_s
        )
        records.append(plant.run(seg, _sample_times(float(seg[1][-1]), sample_rate_hz)))

    if "sensor_cubic" in eff:
        c = eff["sensor_cubic"]
        lo = min(float(r["x_slider_m"].min()) for r in records)
        hi = max(float(r["x_slider_m"].max()) for r in records)
        if c.get("center_m") is None:
            c["center_m"] = 0.5 * (lo + hi)
        if c.get("half_span_m") is None:
            c["half_span_m"] = max(0.5 * (hi - lo), 1e-6)

    root = Path(out_dir)
    root.mkdir(parents=True, exist_ok=True)
    meta_runs = []
    for rs, rec in zip(runs, records):
        x = E.sensor_reading(eff, rec["x_slider_m"])
        x = x + noise_rng.normal(0.0, noise_rms_m, size=x.shape)
        if resolution_m > 0:
            x = np.round(x / resolution_m) * resolution_m
        extra = {"x_rod_m": rec["x_rod_m"]} if rod_column else {}
        _write_csv(root / f"{rs.id}.csv", rec["t_s"], rec["drive_v"], x, extra)
        meta_runs.append({"id": rs.id, "file": f"{rs.id}.csv", "waveform": rs.waveform()})
    meta = {
        "format": FORMAT,
        "description": description or f"independent generator ({GENERATOR}), law {law}",
        "actuator": nominal,
        "sensor": {"resolution_m": resolution_m, "noise_rms_m": noise_rms_m},
        "runs": meta_runs,
    }
    (root / "dataset.json").write_text(json.dumps(meta, indent=2) + "\n")

    all_x = np.concatenate([r["x_slider_m"] for r in records])
    truth = {
        "format": TRUTH_FORMAT,
        "generator": GENERATOR,
        "dataset": str(root),
        "law": law,
        "true_params": true,
        "nominal_params": nominal,
        "effects": eff,
        "causes": sorted(eff),
        "design": design if isinstance(design, str) else "custom",
        "runs": [asdict(r) for r in runs],
        "seed": int(seed),
        "sample_rate_hz": float(sample_rate_hz),
        "dt_s": float(dt_s),
        "hold_s": float(hold_s),
        "noise_rms_m": float(noise_rms_m),
        "resolution_m": float(resolution_m),
        "travel_m": [float(all_x.min()), float(all_x.max())],
        "run_end_positions_m": [float(r["x_slider_m"][-1]) for r in records],
        "wall_time_s": time.perf_counter() - t_start,
    }
    truth_path(root).write_text(json.dumps(truth, indent=2) + "\n")
    return truth
