"""The evidence one candidate model must bring to be preferred to another, and the limits of
"explained" and "unexplained": BIC and mean-square thresholds on the validation runs."""

from __future__ import annotations

import math

from .fit import Evaluation
from .guards import FWD_SHARE, share_removed
from .result import Candidate

# Evidence a model must bring on the validation runs to beat another: a BIC drop of 10 ("very
# strong" on the Kass-Raftery scale) and a fall of the mean-square error by at least 10 % of the
# noise variance (a smaller fall is within what a few fitted parameters chase in correlated
# residuals). Necessary, never sufficient: with 50 000 samples any flexible term passes the BIC,
# so a cause must also pass the guards.
MIN_BIC_DROP = 10.0
MIN_MSE_DROP_OVER_NOISE = 0.1
# Explained / unexplained are judged against the sensor's noise per recorded sample, not on the
# filtered fit samples: the verdict must not depend on the sample rate, and the C model's own
# numerical error at its 1 us step (about 3 nm RMS against a float64 reference at 15 us edges,
# docs/diagnosis.md) sits at that level.
EXPLAINED_RMSE_OVER_NOISE = 1.5  # validation RMSE up to this x sensor noise: explained
UNEXPLAINED_RMSE_OVER_NOISE = 3.0  # above this x sensor noise after extension: unexplained


def bic(ev: Evaluation, noise_m: float, k: int) -> float:
    n = ev.n_samples
    mse = ev.rss_over_noise * noise_m**2 / n
    return n * math.log(mse) + k * math.log(n)


def beats(new: Candidate, old: Candidate, noise_m: float, floor_m: float) -> bool:
    """Is new's validation fit better than old's by more than the noise explains? The BIC on the
    fit samples (noise_m), and a fall of the mean-square error by a share of the sensor's own
    noise variance (floor_m): a smaller fall is below what the data can vouch for, and below the
    C model's own numerical error."""
    n = new.val.n_samples
    mse_new = new.val.rss_over_noise * noise_m**2 / n
    mse_old = old.val.rss_over_noise * noise_m**2 / n
    bic_drop = n * math.log(mse_old / mse_new) - (new.n_params - old.n_params) * math.log(n)
    return bic_drop > MIN_BIC_DROP and (mse_old - mse_new) > MIN_MSE_DROP_OVER_NOISE * floor_m**2


def clearly_worse(a: Candidate, b: Candidate) -> bool:
    """Is a's validation error clearly above b's: would b remove at least FWD_SHARE of a's error
    above the noise, the share a cause must remove to be named?"""
    return share_removed(a.mse_over_noise, b.mse_over_noise) >= FWD_SHARE


def explained_enough(c: Candidate, noise_m: float) -> bool:
    """Not unexplained: the validation error within UNEXPLAINED_RMSE_OVER_NOISE x the noise."""
    return within_unexplained_limit(c.val.rmse_m, noise_m)


def within_unexplained_limit(rmse_m: float, noise_m: float) -> bool:
    return rmse_m <= UNEXPLAINED_RMSE_OVER_NOISE * noise_m


def explained(c: Candidate, noise_m: float) -> bool:
    return c.val.rmse_m <= EXPLAINED_RMSE_OVER_NOISE * noise_m
