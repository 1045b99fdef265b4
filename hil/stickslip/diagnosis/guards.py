"""What a cause must show before the diagnosis names it (docs/diagnosis.md, "Guards"):

1. range: its fitted parameters lie in the physical range the catalog documents, off the fit's
   bounds (a 15 % sensor scale error is the fit absorbing something else, not a sensor);
2. share: it removes a large share of the error the model it extends leaves above the noise,
   a pattern of its own, rather than a little of everything (a flexible term always removes a
   little);
3. cross-validation over run families: fitted without a whole frequency, or a whole amplitude,
   it still predicts the runs left out better than the model without it, in most families and in
   total by more than the noise explains. A term that only absorbs a model-form error on the runs
   it was fitted to does not carry over to a frequency it has not seen.

The same tests confirm a friction law other than the base law."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..model import ActuatorParams
from .catalog import CAUSE_PARAMS, SENSOR_LINEARITY
from .fit import (
    H_THETA,
    FitResult,
    FitRun,
    Free,
    Model,
    build,
    residuals,
    run_of_row,
    specs_for,
    strides,
    theta_of,
)

LM_DAMPING = 1e-2  # Levenberg-Marquardt damping of a fold's first-order refit
# Evidence on the families left out: the summed squared error must fall by this much (in noise
# variances; the BIC's "very strong" 10 for a few parameters), and in more than half the folds.
CV_MIN_DROP = 10.0
# ... and no family may come out clearly worse: by more than this factor and by more than one
# noise variance per sample. A physical effect acts on every run by the same law, so a model
# that has it predicts a left-out family at least about as well as one without; a term that
# absorbs a model-form error on some runs spoils the others (on clean data of another reading of
# the LS law, a "hysteresis" won 4 of 7 folds but made the 100 Hz and both reduced-amplitude
# families 2.2-3.1 x worse, exactly where a real piezo hysteresis shows most).
CV_MAX_HARM = 1.5
# A family harmed to first order is refitted in full before it counts (Session.cross_validate).
# One family still harmed then is excused when the term predicts every other family clearly
# better (by the same factor): a refit without a family that holds much of the data (the long
# run's frequency) can miss for both models, and one such fold outvoting six clear gains is the
# refit failing, not the effect (measured with first-order refits, before the full ones: under
# LS on LuGre data, a true load was 2.4-550 x better on six
# families and 1.7 x worse at 1000 Hz; a true hysteresis 1.9-28 x better and 1.8 x worse there).
# A spurious slew limit on miscalibrated clean LuGre data was 2.9 x worse at 50 V and no better
# at 75 V: not excused. An excused family is left out of the summed error change as well (a true
# load, seed 101: 3x the others' total gain lost at 1000 Hz alone).
FWD_SHARE = 0.25  # share of the excess error a cause must remove when it is added
FINAL_SHARE = 0.5  # ... and that it must account for in the final model (backward check)
# ... and in a final model that stays unexplained (error above 3 x the noise). The base model is
# then wrong in a way no cause describes, and a flexible term takes a part of any such misfit: on
# clean data of a presliding law none of ours has (the independent generator's ls_b), a base
# compliance removed 54 % and a hysteresis 65 % of the calibrated law's error and passed every
# other guard. A cause the data force carries most of what is left without it: that generator's
# Prandtl-Ishlinskii hysteresis, a form our Bouc-Wen loop only approaches, 89 %; its slew limit,
# base compliance and load 99.7 to 99.99 %. The threshold sits between the two groups, on few
# cases: the hit-rate tables (BENCHMARKS.md) are its test. A hysteresis or a base compliance,
# whose signature a law's misfit can make, is asked directly whether its size depends on the law,
# and needs FINAL_SHARE when it does not (pipeline._first_share_bar).
UNEXPLAINED_FINAL_SHARE = 0.8


def families(runs: list[FitRun]) -> list[tuple[str, list[int]]]:
    """Run families to leave out: each frequency, each amplitude. A family holding more than half
    the runs is not left out: the rest could not identify the model (leaving out 100 V leaves the
    one or two runs at other amplitudes)."""
    fam: dict[str, list[int]] = {}
    for i, r in enumerate(runs):
        if r.waveform is None:
            continue
        fam.setdefault(f"{r.waveform.frequency_hz:g} Hz", []).append(i)
        fam.setdefault(f"{r.waveform.amplitude_v:g} V", []).append(i)
    out: dict[tuple[int, ...], str] = {}
    for k, v in fam.items():
        if 0 < len(v) <= len(runs) // 2:  # the same runs under two names: one fold, both names
            out[tuple(v)] = f"{out[tuple(v)]} = {k}" if tuple(v) in out else k
    return [(k, list(v)) for v, k in out.items()]


@dataclass
class FoldResult:
    family: str
    rss_without: float  # summed squared error on the family left out, in noise variances
    rss_with: float
    n: int
    refitted: bool = False  # both models refitted in full without it (harmed to first order)

    @property
    def harmed(self) -> bool:
        """Does the model with the cause predict the family clearly worse (CV_MAX_HARM)?"""
        return (
            self.rss_with > CV_MAX_HARM * self.rss_without
            and self.rss_with - self.rss_without > self.n
        )


@dataclass
class Linearization:
    """A fitted model's residual on every run (every k-th sample, over noise) and its Jacobian
    against the fit's free parameters: enough to refit it without any run family to first order."""

    r: np.ndarray
    jac: np.ndarray
    run_of_row: np.ndarray  # index of the run each row belongs to


def _column_step(theta: np.ndarray, specs, i: int) -> float:
    return H_THETA if theta[i] + H_THETA <= specs[i].bounds()[1] else -H_THETA


def linearize_column(
    runs: list[FitRun], nominal: ActuatorParams, model: Model, free: Free, noise_m: float, i: int
) -> np.ndarray:
    """Residual of the model on runs with free parameter i moved by one finite-difference step
    (i = -1: unmoved). One job per column, so that an executor spreads them."""
    specs = specs_for(nominal, free)
    theta = theta_of(model, specs)
    if i >= 0:
        theta[i] += _column_step(theta, specs, i)
    every = strides(runs)
    return residuals(runs, build(model, free, theta, specs), noise_m, every)


def assemble(
    runs: list[FitRun], nominal: ActuatorParams, model: Model, free: Free, cols: list[np.ndarray]
) -> Linearization:
    """The linearization from linearize_column's results (-1 first, then each parameter)."""
    specs = specs_for(nominal, free)
    theta = theta_of(model, specs)
    r0 = cols[0]
    jac = np.zeros((len(r0), len(specs)))
    for i, c in enumerate(cols[1:]):
        jac[:, i] = (c - r0) / _column_step(theta, specs, i)
    return Linearization(r0, jac, run_of_row(runs))


def fold_rss(a: Linearization, held: list[int]) -> tuple[float, int]:
    """Refit to first order without the held runs (one Gauss-Newton step from the fitted point,
    damped as Levenberg-Marquardt so that a parameter the rest cannot pin down stays put), and
    the summed squared residual predicted on the held runs, in noise variances."""
    out = np.isin(a.run_of_row, held)
    j, r = a.jac[~out], a.r[~out]
    if j.shape[1]:
        jtj = j.T @ j
        delta = np.linalg.solve(jtj + LM_DAMPING * np.diag(np.diag(jtj) + 1e-12), -j.T @ r)
        pred = a.r[out] + a.jac[out] @ delta
    else:
        pred = a.r[out]
    return float(np.sum(pred**2)), int(np.sum(out))


@dataclass
class Verdict:
    """The guards' findings on one cause (or friction law) added to a model."""

    in_range: bool = True
    # causes whose fitted values say they are not there: outside their range, at a bound, or
    # under the position floor
    absent: tuple[str, ...] = ()
    share: float = 0.0  # of the excess validation error removed
    folds: list[FoldResult] = field(default_factory=list)
    # families harmed to first order whose full refits were not run: the refitted ones had already
    # refused the cause (harm_decided); not judged, and listed as such
    unrefitted: list[FoldResult] = field(default_factory=list)
    reasons: list[str] = field(default_factory=list)

    @property
    def confirmed(self) -> bool:
        return not self.reasons

    def to_json(self) -> dict:
        return {
            "confirmed": self.confirmed,
            "reasons": self.reasons,
            "share_removed": self.share,
            "cross_validation": [
                {
                    "left_out": f.family,
                    "mse_without": f.rss_without / f.n,
                    "mse_with": f.rss_with / f.n,
                    "refit": refit,
                }
                for f, refit in [
                    *((f, "full" if f.refitted else "first_order") for f in self.folds),
                    # harmed to first order, not judged (Verdict.unrefitted)
                    *((f, "skipped") for f in self.unrefitted),
                ]
            ],
        }


def range_problems(f: FitResult, causes: tuple[str, ...]) -> list[str]:
    out = []
    for c in causes:
        for p in CAUSE_PARAMS[c]:
            v = f.model.effects.__getattribute__(p.name)
            if p.name in f.at_bound:
                out.append(f"{c}.{p.name} = {v:.4g} is at the fit's bound")
            elif p.phys is not None and not p.phys[0] <= v <= p.phys[1]:
                out.append(
                    f"{c}.{p.name} = {v:.4g} is outside its physical range "
                    f"[{p.phys[0]:.4g}, {p.phys[1]:.4g}]"
                )
    return out


def position_floor_problem(cause: str, moved_m: float, travel_m: float) -> str | None:
    """A position-only cause that moves the positions by no more than a sensor's own linearity
    error over the travel (catalog.SENSOR_LINEARITY) cannot be told from that error."""
    floor = SENSOR_LINEARITY * travel_m
    if moved_m > floor:
        return None
    return (
        f"{cause} moves the positions by at most {moved_m * 1e9:.0f} nm, "
        f"{100 * moved_m / max(travel_m, 1e-300):.3f} % of the {travel_m * 1e6:.0f} um travelled: "
        f"a sensor's own reading error along its range is as large "
        f"({100 * SENSOR_LINEARITY:.2f} % of it, {floor * 1e9:.0f} nm)"
    )


def share_removed(mse_without: float, mse_with: float) -> float:
    """Share of the error above the noise (both in noise variances) that the addition removes."""
    excess = mse_without - 1.0
    return (mse_without - mse_with) / excess if excess > 0 else 0.0


def clearly_better(f: FoldResult) -> bool:
    """Does the model with the cause predict the family better by CV_MAX_HARM or more?"""
    return CV_MAX_HARM * f.rss_with <= f.rss_without


def harm_decided(final: list[FoldResult]) -> bool:
    """Is the cause refused by the harm it does to families, whatever the folds still to be
    refitted come out as? final: the folds whose values are final (not harmed to first order, or
    refitted in full). A family still harmed is excused only when it is the only one and every
    other family is clearly better (judge_cv): two harmed, or one and a final fold not clearly
    better, refuse the cause however the rest come out."""
    still = [f for f in final if f.harmed]
    return len(still) >= 2 or (
        len(still) == 1 and any(not clearly_better(f) for f in final if f is not still[0])
    )


def judge_cv(v: Verdict) -> None:
    if not v.folds:
        return
    harmed = [f for f in v.folds if f.harmed]
    excused = len(harmed) == 1 and all(clearly_better(f) for f in v.folds if f is not harmed[0])
    # an excused fold's refit is not to be trusted: it counts neither way, in the total either
    folds = [f for f in v.folds if not (excused and f is harmed[0])]
    drop = sum(f.rss_without - f.rss_with for f in folds)
    wins = sum(f.rss_with < f.rss_without for f in folds)
    if drop <= CV_MIN_DROP or 2 * wins <= len(folds):
        v.reasons.append(
            f"does not carry over to run families it was not fitted on: better on "
            f"{wins} of {len(folds)} left-out families, summed error change "
            f"{-drop:+.3g} noise variances"
            + (f" ({harmed[0].family} left aside: its refit misses)" if excused else "")
        )
    if harmed and not excused:
        v.reasons.append(
            "predicts left-out run families worse than the model without it: "
            + ", ".join(f"{f.family} ({f.rss_with / f.rss_without:.1f} x)" for f in harmed)
            + " (a physical effect would act on them by the same law)"
            + (
                "; " + ", ".join(f.family for f in v.unrefitted) + " harmed to first order, "
                "not refitted: the verdict was decided"
                if v.unrefitted
                else ""
            )
        )
