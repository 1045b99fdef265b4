"""The LS paper's figures reproduced from the C core: each figure is computed into a result
object holding the curves and the numbers that back the paper's claim; plots are drawn from those
objects only. `make_all` writes the PNGs and figures.json."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .model import ActuatorParams, Sawtooth, friction_response, simulate, stribeck

PARAMS = ActuatorParams.table1()


def _sine_path(amplitude_m: float, f_hz: float, periods: int, per_period: int = 4000):
    dt = 1.0 / (f_hz * per_period)
    t = np.arange(periods * per_period + 1) * dt
    return t, amplitude_m * np.sin(2 * np.pi * f_hz * t), dt


@dataclass
class StribeckFigure:
    """Fig. 3: friction against velocity."""

    v_m_per_s: np.ndarray  # steady sliding velocities
    force_steady_n: np.ndarray  # LS in steady sliding
    force_expected_n: np.ndarray  # g(v) + sigma2 v
    ramp_v: np.ndarray  # constant-acceleration run from rest
    ramp_f: np.ndarray
    claims: dict = field(default_factory=dict)


def stribeck_figure(p: ActuatorParams = PARAMS) -> StribeckFigure:
    v = np.logspace(-6, -1.5, 28)
    steady_list = []
    for vi in v:
        # slide 30 presliding lengths at constant speed: the level settles to g(v)
        dist = 30 * p.fs_n / p.sigma0_n_per_m
        n = 3000
        x = np.linspace(0, dist, n + 1)
        steady_list.append(friction_response(x, dist / n / vi, "ls", p)[-1])
    steady = np.array(steady_list)
    expected = stribeck(v, p) + p.sigma2_ns_per_m * v
    # constant acceleration from rest (the paper's quasi-static ramp): presliding, break-away,
    # Stribeck dip, viscous rise
    a, dt = 0.02, 5e-6
    t = np.arange(int(0.5 / dt) + 1) * dt
    f_ramp = friction_response(0.5 * a * t**2, dt, "ls", p)
    rel = np.abs(steady / expected - 1)
    i_min = int(np.argmin(steady))
    claims = {
        "max_rel_error_vs_g_plus_sigma2_v": float(rel.max()),
        "static_force_n": float(steady[0]),
        "minimum_force_n": float(steady[i_min]),
        "velocity_at_minimum_m_per_s": float(v[i_min]),
        "force_at_highest_velocity_n": float(steady[-1]),
        "ramp_peak_n": float(f_ramp.max()),
    }
    return StribeckFigure(v, steady, expected, a * t, f_ramp, claims)


@dataclass
class HysteresisFigure:
    """Fig. 4: friction under a sinusoidal displacement (and velocity) input."""

    x_m: np.ndarray
    v_m_per_s: np.ndarray
    f_n: np.ndarray
    claims: dict = field(default_factory=dict)


def hysteresis_figure(
    p: ActuatorParams = PARAMS, amplitude_m: float = 0.3e-6, f_hz: float = 10.0
) -> HysteresisFigure:
    t, x, dt = _sine_path(amplitude_m, f_hz, 2)
    f = friction_response(x, dt, "ls", p)
    last = slice(len(t) // 2, None)
    xs, fs = x[last], f[last]
    v = np.gradient(x, dt)[last]
    area = float(abs(np.sum(0.5 * (fs[1:] + fs[:-1]) * np.diff(xs))))
    # force at x = 0 on the rising and the falling branch
    up = fs[np.argmin(np.abs(xs) + (v[: len(xs)] < 0) * 1e9)]
    down = fs[np.argmin(np.abs(xs) + (v[: len(xs)] > 0) * 1e9)]
    claims = {
        "loop_area_j": area,
        "force_gap_at_x0_n": float(up - down),
        "amplitude_m": amplitude_m,
    }
    return HysteresisFigure(xs, v, fs, claims)


@dataclass
class MemoryFigure:
    """Figs. 5-7: random periodic displacement; LuGre's friction-displacement curve drifts from
    period to period, LS closes its loops (nonlocal memory, no drift)."""

    t_s: np.ndarray
    x_m: np.ndarray
    f_ls: np.ndarray
    f_lugre: np.ndarray
    period_samples: int
    claims: dict = field(default_factory=dict)


def random_periodic_path(seed: int = 3, periods: int = 4, n: int = 4000, amp: float = 0.35e-6):
    """Sum of 5 harmonics with random amplitudes and phases, periodic in 10 ms, with a
    positive bias so the path sits off-centre (the drift case)."""
    rng = np.random.default_rng(seed)
    f0, dt = 100.0, 1.0 / (100.0 * n)
    t = np.arange(periods * n + 1) * dt
    x = np.zeros_like(t)
    for k in range(1, 6):
        x += rng.uniform(0.3, 1.0) / k * np.sin(2 * np.pi * k * f0 * t + rng.uniform(0, 2 * np.pi))
    x = amp * (0.5 + 0.5 * x / np.max(np.abs(x)))
    x[0:] -= x[0]
    return t, x, dt, n


def _minor_loops(x: np.ndarray) -> list[tuple[int, int, int]]:
    """(a, b, c): a reversal a, the next reversal b, and the first sample c where the path
    passes x[a] again, for loops nested inside the excursion before them (b does not pass the
    reversal before a, which would wipe a out) and not left in between: closed minor loops."""
    d = np.sign(np.diff(x))
    ext = [i for i in range(1, len(d)) if d[i] != 0 and d[i] != d[i - 1]]
    loops = []
    for p, a, b in zip(ext[:-2], ext[1:-1], ext[2:]):
        s = 1.0 if x[a] > x[b] else -1.0  # a is a maximum when s > 0
        if s * (x[b] - x[p]) <= 0:
            continue  # a was wiped out on the way to b
        past = np.nonzero(s * (x[b:] - x[a]) >= 0)[0]
        if not past.size:
            continue
        c = b + int(past[0])
        if np.all(s * (x[b:c] - x[b]) >= 0):
            loops.append((a, b, c))
    return loops


def minor_loop_closure_error(x: np.ndarray, f: np.ndarray) -> float:
    """Largest force mismatch where a minor loop closes (interpolated at the reversal's x).
    Zero for a model with the wiping-out property."""
    worst = 0.0
    for a, _b, c in _minor_loops(x):
        w = (x[a] - x[c - 1]) / (x[c] - x[c - 1]) if x[c] != x[c - 1] else 1.0
        fc = f[c - 1] + w * (f[c] - f[c - 1])
        worst = max(worst, abs(fc - f[a]))
    return float(worst)


def memory_figure(p: ActuatorParams = PARAMS) -> MemoryFigure:
    t, x, dt, n = random_periodic_path()
    f_ls = friction_response(x, dt, "ls", p)
    f_lg = friction_response(x, dt, "lugre", p)

    def period_change(f):  # largest change of the force between the last two periods
        return float(np.max(np.abs(f[-n:] - f[-2 * n : -n])))

    start = n  # the first period runs up the virgin curve
    claims = {
        "ls_period_to_period_change_n": period_change(f_ls),
        "lugre_period_to_period_change_n": period_change(f_lg),
        "ls_minor_loop_closure_error_n": minor_loop_closure_error(x[start:], f_ls[start:]),
        "lugre_minor_loop_closure_error_n": minor_loop_closure_error(x[start:], f_lg[start:]),
        "minor_loops": len(_minor_loops(x[start:])),
        "viscous_bound_n": float(p.sigma2_ns_per_m * np.max(np.abs(np.diff(x))) / dt),
        "fs_n": p.fs_n,
    }
    return MemoryFigure(t, x, f_ls, f_lg, n, claims)


@dataclass
class RateFigure:
    """Figs. 8 and 9: friction-displacement at 10, 100 and 1000 Hz."""

    frequencies_hz: tuple
    x_m: dict  # (model, f) -> x of the last period
    f_n: dict
    claims: dict = field(default_factory=dict)


def rate_figure(p: ActuatorParams = PARAMS, amplitude_m: float = 0.3e-6) -> RateFigure:
    freqs = (10.0, 100.0, 1000.0)
    xs, fs = {}, {}
    dev = {}
    for model in ("ls", "lugre"):
        for f in freqs:
            t, x, dt = _sine_path(amplitude_m, f, 3)
            xs[(model, f)] = x[-4001:]
            fs[(model, f)] = friction_response(x, dt, model, p)[-4001:]
        ref = fs[(model, freqs[0])]
        dev[model] = float(max(np.max(np.abs(fs[(model, f)] - ref)) for f in freqs[1:]))
    v_max = 2 * np.pi * freqs[-1] * amplitude_m
    claims = {
        "ls_max_deviation_n": dev["ls"],
        "lugre_max_deviation_n": dev["lugre"],
        "viscous_bound_n": p.sigma2_ns_per_m * v_max,
        "amplitude_m": amplitude_m,
    }
    return RateFigure(freqs, xs, fs, claims)


@dataclass
class ActuatorFigure:
    """Fig. 13: the actuator under the 4.4 um, 500 Hz sawtooth."""

    t_s: np.ndarray
    x_p_m: np.ndarray
    x_rod_m: np.ndarray
    x_slider_m: np.ndarray
    steps_m: np.ndarray
    claims: dict = field(default_factory=dict)


def actuator_figure(p: ActuatorParams = PARAMS, cycles: int = 10) -> ActuatorFigure:
    w = Sawtooth(cycles=cycles)
    r = simulate(w, p)
    steps = r.per_cycle_steps()
    settled = steps[2:]
    # stick: over the second half of the last slow rise the slider follows the rod
    k0 = r.cycle_boundaries()[-2]
    a = k0 + int(0.5 * w.rise_fraction * w.period_s / r.dt_s)
    b = k0 + int(0.95 * w.rise_fraction * w.period_s / r.dt_s)
    follow = (r.x_slider_m[b] - r.x_slider_m[a]) / (r.x_rod_m[b] - r.x_rod_m[a])
    claims = {
        "mean_step_m": float(np.mean(settled)),
        "step_spread_rel": float((settled.max() - settled.min()) / np.mean(settled)),
        "slider_over_rod_motion_late_rise": float(follow),
        "stroke_m": float(w.amplitude_v * p.piezo_gain_m_per_v),
    }
    return ActuatorFigure(r.t_s, r.x_p_m, r.x_rod_m, r.x_slider_m, steps, claims)


@dataclass
class FallTimeFigure:
    """Step per cycle against the duration of the fast edge (500 Hz, 4.4 um)."""

    fall_s: np.ndarray
    step_ls_m: np.ndarray
    step_lugre_m: np.ndarray
    claims: dict = field(default_factory=dict)


def fall_time_figure(p: ActuatorParams = PARAMS) -> FallTimeFigure:
    falls = np.array([10, 20, 35, 50, 75, 100, 130, 160, 200, 250]) * 1e-6
    out = {}
    for model in ("ls", "lugre"):
        steps = []
        for ft in falls:
            r = simulate(Sawtooth(cycles=6).with_fall_time(float(ft)), p, model)
            steps.append(np.mean(r.per_cycle_steps()[2:]))
        out[model] = np.array(steps)
    claims = {f"step_ls_at_{int(round(ft * 1e6))}us_m": float(s) for ft, s in zip(falls, out["ls"])}
    return FallTimeFigure(falls, out["ls"], out["lugre"], claims)


# ---------------------------------------------------------------- plotting


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(f, path: Path) -> None:
    f.tight_layout()
    f.savefig(path, dpi=110)
    _plt().close(f)


def plot_stribeck(fig: StribeckFigure, path: Path) -> None:
    plt = _plt()
    f, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].semilogx(
        fig.v_m_per_s * 1e3, fig.force_steady_n, "o", label="LS, steady sliding (C core)"
    )
    ax[0].semilogx(fig.v_m_per_s * 1e3, fig.force_expected_n, "-", label="g(v) + sigma2 v")
    ax[0].set(xlabel="velocity (mm/s)", ylabel="friction (N)", title="Stribeck curve (Fig. 3)")
    ax[0].legend()
    ax[1].plot(fig.ramp_v * 1e3, fig.ramp_f)
    ax[1].set(
        xlabel="velocity (mm/s)", ylabel="friction (N)", title="constant acceleration from rest"
    )
    _save(f, path)


def plot_hysteresis(fig: HysteresisFigure, path: Path) -> None:
    plt = _plt()
    f, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(fig.x_m * 1e6, fig.f_n)
    ax[0].set(
        xlabel="displacement (um)", ylabel="friction (N)", title="LS presliding hysteresis (Fig. 4)"
    )
    ax[1].plot(fig.v_m_per_s * 1e3, fig.f_n)
    ax[1].set(xlabel="velocity (mm/s)", ylabel="friction (N)", title="friction against velocity")
    _save(f, path)


def plot_memory(fig: MemoryFigure, path: Path) -> None:
    plt = _plt()
    f, ax = plt.subplots(1, 3, figsize=(14, 4))
    ax[0].plot(fig.t_s * 1e3, fig.x_m * 1e6)
    ax[0].set(
        xlabel="time (ms)", ylabel="displacement (um)", title="random periodic excitation (Fig. 5)"
    )
    for a, fo, name in (
        (ax[1], fig.f_lugre, "LuGre: drifts (Fig. 6)"),
        (ax[2], fig.f_ls, "LS: closed loops (Fig. 7)"),
    ):
        n = fig.period_samples
        for k in range(len(fig.x_m) // n):
            s = slice(k * n, (k + 1) * n + 1)
            a.plot(fig.x_m[s] * 1e6, fo[s], lw=0.8, label=f"period {k + 1}")
        a.set(xlabel="displacement (um)", ylabel="friction (N)", title=name)
        a.legend(fontsize=7)
    _save(f, path)


def plot_rate(fig: RateFigure, path: Path) -> None:
    plt = _plt()
    f, ax = plt.subplots(1, 2, figsize=(10, 4))
    for a, model, title in ((ax[0], "lugre", "LuGre (Fig. 8)"), (ax[1], "ls", "LS (Fig. 9)")):
        for fr in fig.frequencies_hz:
            a.plot(fig.x_m[(model, fr)] * 1e6, fig.f_n[(model, fr)], label=f"{fr:g} Hz")
        a.set(xlabel="displacement (um)", ylabel="friction (N)", title=title)
        a.legend()
    _save(f, path)


def plot_actuator(fig: ActuatorFigure, path: Path) -> None:
    plt = _plt()
    f, ax = plt.subplots(figsize=(9, 4.5))
    ax.plot(fig.t_s * 1e3, fig.x_p_m * 1e6, lw=0.8, label="ideal piezo strain x_p")
    ax.plot(fig.t_s * 1e3, fig.x_rod_m * 1e6, lw=0.8, label="rod x_R")
    ax.plot(fig.t_s * 1e3, fig.x_slider_m * 1e6, lw=1.5, label="slider x_c")
    ax.set(
        xlabel="time (ms)",
        ylabel="displacement (um)",
        title=f"4.4 um, 500 Hz sawtooth (Fig. 13): "
        f"{fig.claims['mean_step_m'] * 1e6:.2f} um per cycle",
    )
    ax.legend()
    _save(f, path)


def plot_fall_time(fig: FallTimeFigure, path: Path) -> None:
    plt = _plt()
    f, ax = plt.subplots(figsize=(7, 4))
    ax.plot(fig.fall_s * 1e6, fig.step_ls_m * 1e6, "o-", label="LS")
    ax.plot(fig.fall_s * 1e6, fig.step_lugre_m * 1e6, "s--", label="LuGre")
    ax.axhline(0, color="k", lw=0.5)
    ax.set(
        xlabel="fall time (us)",
        ylabel="step per cycle (um)",
        title="step against fall time, 500 Hz, 4.4 um",
    )
    ax.legend()
    _save(f, path)


FIGURES: dict[str, tuple[Callable[[], Any], Callable[[Any, Path], None]]] = {
    "fig03_stribeck": (stribeck_figure, plot_stribeck),
    "fig04_hysteresis": (hysteresis_figure, plot_hysteresis),
    "fig05_07_memory": (memory_figure, plot_memory),
    "fig08_09_rate_independence": (rate_figure, plot_rate),
    "fig13_actuator": (actuator_figure, plot_actuator),
    "step_vs_fall_time": (fall_time_figure, plot_fall_time),
}


def make_all(out_dir: str | Path, progress=None) -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    claims = {}
    for i, (name, (compute, plot)) in enumerate(FIGURES.items()):
        if progress:
            progress(i, len(FIGURES), name)
        fig = compute()
        plot(fig, out / f"{name}.png")
        claims[name] = fig.claims
    (out / "figures.json").write_text(json.dumps(claims, indent=2) + "\n")
    return claims
