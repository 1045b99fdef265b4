"""The diagnosis: nominal simulation, calibration, candidate causes fitted and ranked on held-out
runs, forward selection of causes, and the stick-slip-diagnosis/1 result (docs/diagnosis.md)."""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import dataset as D
from .catalog import CAUSES
from .fit import Evaluation, FitResult, Model, evaluate, fit, predict

FORMAT = "stick-slip-diagnosis/1"
# Evidence a cause must bring on the validation runs: a BIC drop of 10 ("very strong" on the
# Kass-Raftery scale) and a fall of the mean-square error by at least 10 % of the noise variance
# (a smaller fall is within what a few fitted parameters chase in correlated residuals).
MIN_BIC_DROP = 10.0
MIN_MSE_DROP_OVER_NOISE = 0.1
EXPLAINED_RMSE_OVER_NOISE = 1.5  # validation RMSE up to this x noise: explained
UNEXPLAINED_RMSE_OVER_NOISE = 3.0  # above this x noise after extension: unexplained
MAX_CAUSES = 3
FIT_NFEV = 30  # least-squares iterations of a candidate fit
REFINE_NFEV = 60  # ... and of the kept model before the next round
# Models extended in the next round: the kept one and the runner-up of its round if that one
# removes at least BEAM_SHARE of the mean-square error the kept one removes (the two compete for
# the same residual). Every remaining cause is tried on each: how well a cause does alone says
# little about what it adds to another (a hysteresis under a load ranks low alone), and the best
# single cause need not be one of the pair (while a hysteresis is present, an asymmetric friction
# mimics a load better than the load does: both remove ~96 % of the error, the load 1-2 % less).
BEAM_WIDTH = 2
BEAM_SHARE = 0.5


def split_runs(runs: list[D.Run]) -> tuple[list[D.Run], list[D.Run]]:
    """Every third run, from the third on, is held out for validation; the rest is for fitting.
    With the standard design (stickslip.synth) that holds out one run of each direction at
    three frequencies and both amplitudes."""
    if len(runs) < 3:
        raise ValueError(
            f"a diagnosis needs at least 3 runs (2 to fit, 1 to validate), got {len(runs)}"
        )
    train = [r for i, r in enumerate(runs) if i % 3 != 2]
    val = [r for i, r in enumerate(runs) if i % 3 == 2]
    return train, val


def noise_level(ds: D.Dataset, nominal_residuals: list[np.ndarray]) -> tuple[float, str]:
    """Sensor noise in m (RMS, quantisation included) from dataset.json, else estimated from the
    sample-to-sample scatter of the nominal residual (model errors are smooth; noise is not)."""
    s = ds.sensor
    if s.noise_rms_m is not None:
        res = s.resolution_m or 0.0
        sigma = math.sqrt(s.noise_rms_m**2 + res**2 / 12.0)
        if sigma > 0:
            return sigma, "dataset.json sensor"
    d = np.concatenate([np.diff(r) for r in nominal_residuals])
    mad = float(np.median(np.abs(d - np.median(d))))
    return max(1.4826 * mad / math.sqrt(2.0), 1e-12), "estimated from the data"


@dataclass
class Candidate:
    causes: tuple[str, ...]
    fit: FitResult
    val: Evaluation
    score: float  # BIC on the validation runs, lower is better


@dataclass
class Diagnosis:
    dataset: str
    noise_m: float
    noise_source: str
    train_ids: list[str]
    val_ids: list[str]
    nominal: Evaluation
    nominal_model: Model
    baseline: Candidate
    singles: list[Candidate]
    rounds: list[list[Candidate]]
    chosen: Candidate
    causes: list[str]
    unexplained: bool
    timing_s: dict[str, float] = field(default_factory=dict)

    @property
    def gain(self) -> float:
        b = self.baseline.val.rmse_m
        return 0.0 if b == 0 else 1.0 - self.chosen.val.rmse_m / b

    def to_json(self) -> dict:
        def block(c: Candidate | None, ev: Evaluation, with_params: bool = True) -> dict:
            d: dict = {"validation_rmse_m": ev.rmse_m, "validation_step_error": ev.step_error}
            if with_params and c is not None:
                d["params"] = c.fit.values
            return d

        return {
            "format": FORMAT,
            "dataset": self.dataset,
            "causes": self.causes,
            "nominal": block(None, self.nominal, with_params=False),
            "baseline": block(self.baseline, self.baseline.val),
            "extended": block(self.chosen, self.chosen.val),
            "gain": self.gain,
            "unexplained": self.unexplained,
            "candidates": [
                {
                    "name": c.causes[-1],
                    "validation_rmse_m": c.val.rmse_m,
                    "score": c.score,
                    "params": {
                        k: v for k, v in c.fit.values.items() if k.startswith(c.causes[-1] + ".")
                    },
                }
                for c in self.singles
            ],
            "validation_runs": self.val_ids,
            "noise_m": self.noise_m,
        }


def _bic(ev: Evaluation, noise_m: float, k: int) -> float:
    n = ev.n_samples
    mse = ev.rss_over_noise * noise_m**2 / n
    return n * math.log(mse) + k * math.log(n)


def _fit_and_validate(
    train, val, base, causes, noise_m, start, max_nfev: int = FIT_NFEV
) -> tuple[FitResult, Evaluation]:
    f = fit(
        train, base, causes, noise_m, start=start, max_nfev=max_nfev, polish=max_nfev > FIT_NFEV
    )
    return f, evaluate(val, f.model, noise_m)


def default_executor() -> Executor:
    return ProcessPoolExecutor(max_workers=max(1, min(os.cpu_count() or 1, 8)))


def diagnose(
    path: str | Path,
    executor: Executor | None = None,
    progress: Callable[[str], None] | None = None,
) -> Diagnosis:
    """Diagnose a dataset folder. Simulations run in `executor` (local processes by default;
    any concurrent.futures Executor works, e.g. dask.distributed's Client.get_executor())."""
    say = progress or (lambda msg: None)
    t_start = time.perf_counter()
    ds = D.load(path)  # validated whole before anything runs
    train, val = split_runs(ds.runs)
    base = ds.actuator
    timing: dict[str, float] = {}

    say(f"nominal model on {len(ds.runs)} runs")
    nominal_model = Model(base)
    nominal_res = [predict(r, nominal_model) - r.x_m for r in ds.runs]
    noise_m, noise_src = noise_level(ds, nominal_res)
    noise_eff = noise_m  # the fitted start offset removes one sample's worth per run: negligible
    nominal = evaluate(val, nominal_model, noise_eff)
    timing["nominal_s"] = time.perf_counter() - t_start

    own = executor is None
    ex = executor or default_executor()
    try:
        say("calibrating the base model (normal_force_n, mu_s)")
        t0 = time.perf_counter()
        bf, bv = ex.submit(_fit_and_validate, train, val, base, (), noise_eff, None).result()
        baseline = Candidate((), bf, bv, _bic(bv, noise_eff, bf.n_params))
        timing["baseline_s"] = time.perf_counter() - t0

        t0 = time.perf_counter()
        names = list(CAUSES)
        futures = {
            n: ex.submit(_fit_and_validate, train, val, base, (n,), noise_eff, bf.model)
            for n in names
        }
        singles = []
        for i, n in enumerate(names):
            say(f"[{i + 1}/{len(names)}] fitting candidate {n}")
            f, v = futures[n].result()
            singles.append(Candidate((n,), f, v, _bic(v, noise_eff, f.n_params)))
        singles.sort(key=lambda c: c.score)
        timing["candidates_s"] = time.perf_counter() - t0

        # forward selection: add the best cause while the validation error falls by more than
        # the noise can explain
        t0 = time.perf_counter()
        chosen = baseline
        rounds: list[list[Candidate]] = [singles]
        pool = list(singles)
        while True:
            best = pool[0] if pool else None
            if best is None or not _better(best, chosen, noise_eff):
                break
            before = chosen
            # polish the kept model before anything is compared with it, so that a second cause
            # cannot win by merely continuing the first one's optimisation
            say(f"refining {'+'.join(best.causes)}")
            f, v = ex.submit(
                _fit_and_validate,
                train,
                val,
                base,
                best.causes,
                noise_eff,
                best.fit.model,
                REFINE_NFEV,
            ).result()
            chosen = Candidate(best.causes, f, v, _bic(v, noise_eff, f.n_params))
            if len(chosen.causes) >= MAX_CAUSES or _explained(chosen, noise_eff):
                break
            fall = before.val.rmse_m**2 - best.val.rmse_m**2
            beam = [chosen] + [
                c
                for c in pool[1:BEAM_WIDTH]
                if before.val.rmse_m**2 - c.val.rmse_m**2 >= BEAM_SHARE * fall
            ]
            tried: dict[frozenset[str], tuple[tuple[str, ...], Model]] = {}
            for b in beam:
                for n in CAUSES:
                    key = frozenset((*b.causes, n))
                    if n not in b.causes and key not in tried:
                        tried[key] = ((*b.causes, n), b.fit.model)
            say(
                f"adding to {' or '.join('+'.join(b.causes) for b in beam)}: "
                f"{len(tried)} combinations"
            )
            futs = [
                (combo, ex.submit(_fit_and_validate, train, val, base, combo, noise_eff, start))
                for combo, start in tried.values()
            ]
            pool = []
            for combo, fu in futs:
                f, v = fu.result()
                pool.append(Candidate(combo, f, v, _bic(v, noise_eff, f.n_params)))
            pool.sort(key=lambda c: c.score)
            rounds.append(pool)
        # Backward check: a cause stays only if the model without it, re-polished from the same
        # point, is clearly worse. Guards against a second cause that merely let the optimiser
        # go on where the first one's fit had stopped short.
        while len(chosen.causes) > 1:
            back = {
                c: ex.submit(
                    _fit_and_validate,
                    train,
                    val,
                    base,
                    tuple(x for x in chosen.causes if x != c),
                    noise_eff,
                    chosen.fit.model,
                    REFINE_NFEV,
                )
                for c in chosen.causes
            }
            say(f"checking each of {'+'.join(chosen.causes)} is needed")
            reduced = []
            for fu in back.values():
                f, v = fu.result()
                reduced.append(Candidate(f.causes, f, v, _bic(v, noise_eff, f.n_params)))
            reduced.sort(key=lambda c: c.score)
            if _better(chosen, reduced[0], noise_eff):
                break
            chosen = reduced[0]
        timing["selection_s"] = time.perf_counter() - t0
    finally:
        if own:
            ex.shutdown()

    if chosen.causes:
        causes = list(chosen.causes)
    elif _explained(baseline, noise_eff) and _better(baseline, _as_candidate(nominal), noise_eff):
        causes = ["parameter_miscalibration"]
    else:
        causes = ["none"]
    unexplained = chosen.val.rmse_m > UNEXPLAINED_RMSE_OVER_NOISE * noise_eff
    timing["total_s"] = time.perf_counter() - t_start
    return Diagnosis(
        str(path),
        noise_eff,
        noise_src,
        [r.id for r in train],
        [r.id for r in val],
        nominal,
        nominal_model,
        baseline,
        singles,
        rounds,
        chosen,
        causes,
        unexplained,
        timing,
    )


def _as_candidate(ev: Evaluation) -> Candidate:
    return Candidate((), None, ev, math.nan)  # type: ignore[arg-type]


def _better(new: Candidate, old: Candidate, noise_m: float) -> bool:
    """Is new's validation fit better than old's by more than the noise explains?"""
    n = new.val.n_samples
    mse_new = new.val.rss_over_noise * noise_m**2 / n
    mse_old = old.val.rss_over_noise * noise_m**2 / n
    k_new = new.fit.n_params if new.fit else 0
    k_old = old.fit.n_params if old.fit else 0
    bic_drop = n * math.log(mse_old / mse_new) - (k_new - k_old) * math.log(n)
    return bic_drop > MIN_BIC_DROP and (mse_old - mse_new) > MIN_MSE_DROP_OVER_NOISE * noise_m**2


def _explained(c: Candidate, noise_m: float) -> bool:
    return c.val.rmse_m <= EXPLAINED_RMSE_OVER_NOISE * noise_m
