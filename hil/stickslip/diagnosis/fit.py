"""Simulating measured runs with the C model, and fitting model parameters to them.

A model point is (ActuatorParams, Effects). A fit takes a list of causes, frees the base
parameters (catalog.BASE_PARAMS) and each cause's parameters, and minimises the position residual
over the training runs, scaled by the measurement noise, with scipy's least_squares. Every
function here is a plain top-level function of picklable arguments, so an Executor (local
processes, Dask) can run it anywhere."""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import least_squares

from ..dataset import Run
from ..model import ActuatorParams, Effects, simulate
from .catalog import BASE_PARAMS, CAUSE_FIXED, CAUSE_PARAMS, CAUSE_START, Param

MAX_DT_S = 1e-6  # the model's step: converged to 0.08 % per cycle (docs/model.md)
MAX_POINTS_PER_RUN = 1500  # residual samples per run in a fit (every k-th sample)
MIN_STEP_OVER_NOISE = 50.0  # a run steps when its mean step is above this x noise
H_THETA = 1e-3  # finite-difference step in theta (0.1 % of a scale, 1e-3 ref of a signed value)


@dataclass
class Model:
    params: ActuatorParams
    effects: Effects = field(default_factory=Effects)

    def values(self, causes: tuple[str, ...]) -> dict[str, float]:
        """The fitted values, named as in the diagnosis JSON."""
        out = {"normal_force_n": self.params.normal_force_n, "mu_s": self.params.mu_s}
        for c in causes:
            for p in CAUSE_PARAMS[c]:
                out[f"{c}.{p.name}"] = float(getattr(self.effects, p.name))
        return out


def sim_step_s(run: Run) -> tuple[float, int]:
    """Model step dividing the run's sample interval exactly, and the decimation."""
    dec = max(1, math.ceil(run.dt_s / MAX_DT_S - 1e-9))
    return run.dt_s / dec, dec


def predict(run: Run, model: Model) -> np.ndarray:
    """What the sensor would have reported at the run's sample times under this model, the slider
    starting where the run's first samples put it."""
    dt, dec = sim_step_s(run)
    scale = 1.0 + model.effects.sensor_scale_error
    x0 = float(run.x_m[0]) / scale
    n = len(run.t_s) - 1
    if run.waveform is not None:
        hold = max(0.0, n * run.dt_s - run.waveform.duration_s)
        r = simulate(
            run.waveform,
            model.params,
            dt_s=dt,
            hold_s=hold,
            decimation=dec,
            effects=model.effects,
            x0_m=x0,
        )
    else:
        r = simulate(
            None,
            model.params,
            dt_s=dt,
            decimation=dec,
            drive_v=run.drive_v,
            drive_interval_s=run.dt_s,
            effects=model.effects,
            x0_m=x0,
        )
    x = r.x_meas_m
    if len(x) < n + 1:  # rounding of the duration: hold the last value
        x = np.concatenate([x, np.full(n + 1 - len(x), x[-1])])
    x = x[: n + 1]
    # Where the slider started is known only to the sensor's noise: it is placed by least squares
    # over the whole run (the model is translation invariant), one nuisance offset per run, the
    # same for every model compared. Placing it from the first samples alone left their mean
    # noise (~0.7 nm from 10 samples) as an offset in every residual, and fits then bent the
    # physical parameters to chase it.
    return x + float(np.mean(run.x_m - x))


def build(base: ActuatorParams, causes: tuple[str, ...], theta: np.ndarray, specs) -> Model:
    """Model for a parameter vector theta (BASE_PARAMS then each cause's params)."""
    vals = {s.name: s.value(float(t)) for s, t in zip(specs, theta)}
    p = replace(
        base,
        normal_force_n=vals["normal_force_n"],
        mu_s=base.mu_d + vals["stribeck_excess"],
    )
    kw: dict[str, float] = {}
    for c in causes:
        kw.update(CAUSE_FIXED.get(c, {}))
    kw.update({k: v for k, v in vals.items() if k not in ("normal_force_n", "stribeck_excess")})
    return Model(p, Effects(**kw))


def specs_for(base: ActuatorParams, causes: tuple[str, ...]) -> list[Param]:
    n, ex = BASE_PARAMS
    specs = [
        replace(n, ref=base.normal_force_n),
        replace(ex, ref=max(base.mu_s - base.mu_d, 1e-3)),
    ]
    for c in causes:
        specs.extend(CAUSE_PARAMS[c])
    return specs


def _cycle_refs(run: Run) -> np.ndarray | None:
    """For each sample, the index of the sample at the start of its period (or of the hold)."""
    if run.waveform is None:
        return None
    w = run.waveform
    starts = np.rint(np.arange(w.cycles + 1) * w.period_s / run.dt_s).astype(int)
    idx = np.arange(len(run.x_m))
    return starts[np.clip(np.searchsorted(starts, idx, side="right") - 1, 0, len(starts) - 1)]


def residuals(
    runs: list[Run], model: Model, noise_m: float, every: list[int], per_cycle: bool = False
) -> np.ndarray:
    """Simulated minus measured position over noise, every k-th sample. per_cycle measures each
    sample from the start of its period instead: the residual no longer accumulates over a run,
    which keeps the cost smooth far from the optimum (a fit's first stage)."""
    parts = []
    for run, k in zip(runs, every):
        try:
            x = predict(run, model)
        except ValueError:  # a parameter the C library rejects: far off, not a crash
            x = np.full(len(run.x_m), 1.0)
        r = x - run.x_m
        refs = _cycle_refs(run) if per_cycle else None
        if refs is not None:
            r = r - r[refs]
        parts.append(r[::k] / noise_m)
    return np.concatenate(parts)


@dataclass
class FitResult:
    causes: tuple[str, ...]
    model: Model
    values: dict[str, float]
    train_rms_m: float
    n_params: int
    nfev: int


def fit(
    runs: list[Run],
    base: ActuatorParams,
    causes: tuple[str, ...],
    noise_m: float,
    start: Model | None = None,
    max_nfev: int = 30,
    polish: bool = False,
) -> FitResult:
    """Least-squares fit of the base parameters and the causes' parameters on runs. Starts from
    `start` where it holds a value (the baseline fit), else from the catalog's start; scale
    parameters with a grid are first tried at each grid value (their cost is not convex), unless
    polish: then the fit continues from `start` alone."""
    specs = specs_for(base, causes)
    every = [max(1, len(r.x_m) // MAX_POINTS_PER_RUN) for r in runs]
    theta0 = []
    for s in specs:
        if s.name == "normal_force_n":
            v = start.params.normal_force_n if start else base.normal_force_n
        elif s.name == "stribeck_excess":
            v = (start.params.mu_s - start.params.mu_d) if start else base.mu_s - base.mu_d
        else:
            cause = next(c for c in causes if s in CAUSE_PARAMS[c])
            v = CAUSE_START.get(cause, {}).get(s.name, 0.0)
            if start is not None and getattr(start.effects, s.name) != 0.0:
                v = getattr(start.effects, s.name)
        t_lo, t_hi = s.bounds()
        theta0.append(min(max(s.theta(v), t_lo + 1e-9), t_hi - 1e-9))
    theta0_arr = np.array(theta0)
    lo = np.array([s.bounds()[0] for s in specs])
    hi = np.array([s.bounds()[1] for s in specs])

    counter = [0]

    def solve(theta0: np.ndarray, per_cycle: bool, nfev: int, tol: float):
        cache: dict[bytes, np.ndarray] = {}

        def fun(theta: np.ndarray) -> np.ndarray:
            key = theta.tobytes()
            if key not in cache:
                cache.clear()  # least_squares asks for jac at the point it just evaluated
                cache[key] = residuals(
                    runs, build(base, causes, theta, specs), noise_m, every, per_cycle
                )
                counter[0] += 1
            return cache[key]

        def jac(theta: np.ndarray) -> np.ndarray:
            # forward differences with an absolute step of H_THETA: well above the float32
            # rounding of the model, well below its scales (scipy's relative steps vanish at 0)
            f0 = fun(theta)
            cols = []
            for i in range(len(theta)):
                th = theta.copy()
                h = H_THETA if th[i] + H_THETA <= hi[i] else -H_THETA
                th[i] += h
                m = build(base, causes, th, specs)
                cols.append((residuals(runs, m, noise_m, every, per_cycle) - f0) / h)
                counter[0] += 1
            return np.column_stack(cols)

        return least_squares(
            fun, theta0, jac=jac, bounds=(lo, hi), x_scale=1.0, max_nfev=nfev, xtol=tol, ftol=tol
        )

    if not polish:
        # Stage 1 on the per-cycle residual. Start points: every combination of the grid values,
        # with the base parameters both as given and nominal (an effect the base model lacks
        # distorts its calibration); the cheapest is fitted.
        starts = []
        axes = [(i, s.grid) for i, s in enumerate(specs) if s.grid]
        combos = list(itertools.product(*(g for _, g in axes))) if axes else [()]
        for b in {theta0_arr[:2].tobytes(): theta0_arr[:2], b"nominal": np.zeros(2)}.values():
            for combo in combos:
                th = theta0_arr.copy()
                th[:2] = b
                for (i, _), v in zip(axes, combo):
                    th[i] = specs[i].theta(v)
                starts.append(th)
        if len(starts) > 1:
            costs = []
            for th in starts:
                r = residuals(runs, build(base, causes, th, specs), noise_m, every, True)
                counter[0] += 1
                costs.append(float(np.sum(r**2)))
            theta0_arr = starts[int(np.argmin(costs))]
        # near is enough here: stage 2 sets the digits
        theta0_arr = solve(theta0_arr, True, max_nfev, 1e-3).x
    # Stage 2 (or a polish) on the absolute position: what the validation measures
    res = solve(theta0_arr, False, max_nfev if polish else max(10, max_nfev // 2), 1e-5)
    model = build(base, causes, res.x, specs)
    r = res.fun * noise_m
    return FitResult(
        causes,
        model,
        model.values(causes),
        float(np.sqrt(np.mean(r**2))),
        len(specs),
        counter[0],
    )


@dataclass
class Evaluation:
    """A model against runs it was not fitted on."""

    rmse_m: float
    step_error: float
    rss_over_noise: float  # sum of squared residuals / noise^2
    n_samples: int
    per_run: dict[str, dict] = field(default_factory=dict)


def cycle_steps(run: Run, x: np.ndarray) -> np.ndarray:
    """Per-period displacement of a position record (at the period boundaries)."""
    if run.waveform is None:
        return np.zeros(0)
    k = np.arange(run.waveform.cycles + 1) * run.waveform.period_s
    xb = np.interp(k, run.t_s - run.t_s[0], x)
    return np.diff(xb)


def evaluate(runs: list[Run], model: Model, noise_m: float) -> Evaluation:
    rss, n, step_rel = 0.0, 0, []
    per_run = {}
    for run in runs:
        x = predict(run, model)
        r = x - run.x_m
        rss += float(np.sum(r**2))
        n += len(r)
        s_meas, s_sim = cycle_steps(run, run.x_m), cycle_steps(run, x)
        # relative to the run's mean step size, so that one cycle stepping ~0 cannot blow it up;
        # runs that do not step (mean step under MIN_STEP_OVER_NOISE x noise: the slider follows
        # the rod back on a slow edge) have no step size to be relative to
        typical = float(np.mean(np.abs(s_meas))) if len(s_meas) else 0.0
        if typical > MIN_STEP_OVER_NOISE * noise_m:
            step_rel.extend(((s_sim - s_meas) / typical).tolist())
        per_run[run.id] = {"rmse_m": float(np.sqrt(np.mean(r**2)))}
    step_err = float(np.sqrt(np.mean(np.square(step_rel)))) if step_rel else 0.0
    return Evaluation(float(np.sqrt(rss / n)), step_err, rss / noise_m**2, n, per_run)
