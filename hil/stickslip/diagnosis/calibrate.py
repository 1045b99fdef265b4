"""Calibration of a friction law: every parameter the runs can identify is fitted, the rest is
held at its nominal value and reported as not identifiable."""

from __future__ import annotations

import numpy as np

from ..model import ActuatorParams
from .catalog import LAW_PARAMS
from .fit import MAX_REL_STDERR, FitResult, FitRun, Free, Model, covariance, fit, rel_stderr

FIT_NFEV = 20  # least-squares iterations of a full calibration
POLISH_NFEV = 15  # ... of the refit once the unidentifiable parameters are held


def unidentifiable(f: FitResult) -> list[str]:
    """Base parameters the fit's Jacobian cannot pin down: the one with the largest relative
    standard error goes first, and the others are judged again without it (two strongly
    correlated parameters both look loose until one of them is held)."""
    if f.jac is None or f.fun is None:
        return []
    nb = len(f.free.base)
    keep = list(range(nb))
    n = f.jac.shape[0]
    chi2_red = float(np.sum(f.fun**2)) / max(1, n - len(f.specs))
    dropped = []
    while keep:
        cols = keep + list(range(nb, len(f.specs)))
        cov = covariance(f.jac[:, cols], chi2_red)
        rel = []
        for i, c in enumerate(keep):
            s = f.specs[c]
            v = f.model.base_value(s.name)
            rel.append(rel_stderr(s, v, s.stderr(v, float(np.sqrt(max(cov[i, i], 0.0))))))
        worst = int(np.argmax(rel))
        if rel[worst] <= MAX_REL_STDERR:
            break
        dropped.append(f.specs[keep[worst]].name)
        keep.pop(worst)
    return dropped


def calibrate(
    runs: list[FitRun], nominal: ActuatorParams, law: str, noise_m: float
) -> tuple[FitResult, tuple[str, ...]]:
    """Fit every parameter of the law (and the piezo damping) on runs; hold what the runs cannot
    identify at its nominal value and fit the rest again. Returns the fit and the held names."""
    names = tuple(n for n in LAW_PARAMS[law] if Model(nominal).base_value(n) > 0)
    start = Model(nominal, law=law)
    f = fit(runs, nominal, start, Free(names, ()), noise_m, max_nfev=FIT_NFEV)
    held = unidentifiable(f)
    if not held:
        return f, ()
    kept = tuple(n for n in names if n not in held)
    at_nominal = {n: Model(nominal).base_value(n) for n in held}
    g = fit(
        runs,
        nominal,
        f.model.with_base(at_nominal),
        Free(kept, ()),
        noise_m,
        max_nfev=POLISH_NFEV,
        polish=True,
    )
    return g, tuple(held)
