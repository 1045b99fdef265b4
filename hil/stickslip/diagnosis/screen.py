"""Screening: what each cause would add to a model, to first order, before any cause is fitted.

For a fitted model (its residual r and Jacobian J on every run, guards.Linearization) and a cause
probed at a few points of its parameter space (each point one simulation), the probe's change of
the residual d is a new direction: the cause's predicted fit is r + J delta + a d with delta and a
fitted on the training rows (base parameters and the cause's amplitude refitted together, a
variable projection), and its validation error is that prediction on the held-out rows. Only the
best-ranked causes are then fitted in full: a fit costs a hundred simulations, a probe one."""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from .catalog import CAUSE_PARAMS, CAUSE_START
from .fit import FitRun, Model, residuals, strides
from .guards import LM_DAMPING, Linearization, share_removed


def probe_points(cause: str) -> list[dict[str, float]]:
    """Points of a cause's parameter space to probe: its amplitude (first parameter, when the cause
    has a shape too) at its starting value, every combination of its shape parameters' grids."""
    ps = CAUSE_PARAMS[cause]
    start = CAUSE_START.get(cause, {})
    amp, shape = (ps[0], ps[1:]) if len(ps) > 1 or not ps[0].grid else (None, ps)
    axes = [p.grid or (start.get(p.name, p.ref),) for p in shape]
    out = []
    for combo in itertools.product(*axes):
        v = {p.name: float(x) for p, x in zip(shape, combo)}
        if amp is not None:
            v[amp.name] = start.get(amp.name, amp.ref)
        out.append(v)
    return out


def probe_residual(
    runs: list[FitRun],
    model: Model,
    cause: str | None,
    values: dict[str, float],
    noise_m: float,
    per_cycle: bool = False,
) -> np.ndarray:
    """Residual on every run (every k-th sample, over noise; per_cycle: measured from the start
    of each period) of the model with the cause added at the given values (none: as it is)."""
    if cause is not None:
        fx = replace(model.effects, **values)
        model = replace(model, effects=fx, causes=(*model.causes, cause))
    return residuals(runs, model, noise_m, strides(runs), per_cycle)


@dataclass
class Screened:
    cause: str
    values: dict[str, float]  # the best probe point
    rss_val: float  # predicted summed squared validation residual, in noise variances
    n_val: int
    rss_parent: float  # ... of the model screened on, refitted to first order on its own
    amplitude: float  # the fitted multiple of the probe's change
    from_nominal: bool = False  # the best point was probed with the base parameters at nominal
    law: str = ""  # ... and with this friction law
    # per friction law, the best point probed with the base parameters at nominal under it
    nominal_points: dict[str, dict[str, float]] = field(default_factory=dict)
    # screened on this other law's calibration (the first round's, session.Session.screen)
    on_calibrated: str = ""


def screen(
    lin: Linearization,
    val_runs: list[int],
    cause: str,
    points,
    probes: list[np.ndarray],
    nominal_probes: dict[str, list[np.ndarray]] | None = None,
    parent_per_cycle: np.ndarray | None = None,
) -> Screened:
    """The best probe point of a cause and its predicted validation error. A probe on the
    calibrated model is refitted to first order (its base parameters and the cause's amplitude).
    A probe with the base parameters back at nominal, under each friction law, is compared as it
    is, on the error accumulated within each cycle (per_cycle residuals: the absolute position of
    a probe a little off a steep optimum, such as a slew limit's, is off by microseconds of slip
    in every cycle and hides the basin); its predicted validation error is the parent's scaled by
    the per-cycle ratio. Those probes see a cause whose absence bent the calibration too far for a
    linear step to undo: a slew limit the calibration absorbed into its friction, or its law.
    nominal_probes and parent_per_cycle hold the validation runs' rows only (all they are
    compared on); probes, lin's rows of every run."""
    val = np.isin(lin.run_of_row, val_runs)
    rss_parent, _ = _predict(lin.jac, lin.r, val)
    best = None
    for v, rp in zip(points, probes):
        d = rp - lin.r
        rss, a = _predict(np.column_stack([lin.jac, d]), lin.r, val)
        if best is None or rss < best.rss_val:
            best = Screened(cause, v, rss, int(np.sum(val)), rss_parent, a)
    per_law: dict[str, dict[str, float]] = {}
    if parent_per_cycle is not None:
        pc_parent = float(np.sum(parent_per_cycle**2))
        for law, rs in (nominal_probes or {}).items():
            costs = [float(np.sum(rn**2)) for rn in rs]
            i = int(np.argmin(costs))
            per_law[law] = points[i]
            rss = rss_parent * costs[i] / max(pc_parent, 1e-300)
            if best is None or rss < best.rss_val:
                best = Screened(cause, points[i], rss, int(np.sum(val)), rss_parent, 1.0, True, law)
    assert best is not None
    best.nominal_points = per_law
    return best


def _predict(jac: np.ndarray, r: np.ndarray, val: np.ndarray) -> tuple[float, float]:
    """Summed squared residual on the val rows after a damped Gauss-Newton step fitted on the
    others, and the step's last component."""
    j = jac[~val]
    jtj = j.T @ j
    delta = np.linalg.solve(jtj + LM_DAMPING * np.diag(np.diag(jtj) + 1e-12), -j.T @ r[~val])
    last = float(delta[-1]) if len(delta) else 0.0
    return float(np.sum((r[val] + jac[val] @ delta) ** 2)), last


def start_values(s: Screened) -> dict[str, float]:
    """Where a full fit of the screened cause starts: the best probe point, its amplitude scaled
    by the fitted multiple (kept inside the amplitude's bounds)."""
    ps = CAUSE_PARAMS[s.cause]
    out = dict(s.values)
    if len(ps) > 1 or not ps[0].grid:
        amp = ps[0]
        v = out[amp.name] * s.amplitude
        out[amp.name] = min(max(v, amp.lo), amp.hi) if v != 0 else out[amp.name]
    return out


def promising(s: Screened, k_added: int, min_bic_drop: float, min_mse_drop: float) -> bool:
    """Does the screen predict a gain worth a full fit: the same two thresholds a fitted cause
    must pass on the validation runs (BIC and mean-square drop, noise variances)?"""
    if s.rss_val <= 0:
        return True
    bic_drop = s.n_val * math.log(s.rss_parent / s.rss_val) - k_added * math.log(s.n_val)
    return bic_drop > min_bic_drop and (s.rss_parent - s.rss_val) / s.n_val > min_mse_drop


def predicted_share(s: Screened) -> float:
    """Share of its parent's error above the noise (the parent as the screen refits it) that the
    screened cause is predicted to remove, guards.share_removed's measure to first order."""
    return share_removed(s.rss_parent / s.n_val, s.rss_val / s.n_val)


def predicted_bic(s: Screened, k: int, n: int, noise_m: float) -> float:
    """BIC the screened cause would score on n validation samples with k parameters (the mean
    square predicted on the screen's rows), on the scale of the fitted candidates' BIC."""
    mse = max(s.rss_val / s.n_val, 1e-300) * noise_m**2
    return n * math.log(mse) + k * math.log(n)
