"""One diagnosis' shared state (runs, noise, executor, caches) and the jobs it submits: fits,
calibrations, screens, linearizations, and the guards' questions that need new fits."""

from __future__ import annotations

import math
import os
from concurrent.futures import Executor, Future, ThreadPoolExecutor
from dataclasses import replace

import numpy as np

from .calibrate import calibrate
from .catalog import (
    CAUSE_PARAMS,
    FIT_FROM_NOMINAL,
    LAW_PARAMS,
    POSITION_ONLY,
)
from .evidence import (
    MIN_BIC_DROP,
    MIN_MSE_DROP_OVER_NOISE,
    beats,
    bic,
    clearly_worse,
    within_unexplained_limit,
)
from .fit import (
    Evaluation,
    FitResult,
    Free,
    Model,
    evaluate,
    first_stage,
    fit,
    fit_from,
    predict_all,
    refit_without,
)
from .guards import (
    FINAL_SHARE,
    FWD_SHARE,
    UNEXPLAINED_FINAL_SHARE,
    FoldResult,
    Linearization,
    Verdict,
    assemble,
    families,
    fold_rss,
    harm_decided,
    judge_cv,
    linearize_column,
    position_floor_problem,
    range_problems,
    share_removed,
)
from .result import Candidate
from .screen import (
    NOMINAL_REFINED,
    Screened,
    predicted_share,
    probe_points,
    probe_residual,
    promising,
    refine_at_nominal,
    screen,
    start_values,
)

FIT_NFEV = 12  # least-squares iterations of a candidate fit (from its screened point)
REFINE_NFEV = 10  # ... and of the kept model (a polish from its own optimum)
TOP_FIT = 3  # causes fitted in full per round, the best screened first
# A batch whose best fit leaves more than this many times the mean-square validation error that a
# cause still pending was screened to leave is followed at once by the next batch: the screen's
# rank is to first order, and a cause it placed fourth may be the one. Independent position-
# dependent friction, seed 100 (N falls by 64 % over the long run): the first batch held a
# thermal drift (93.5 nm once fitted) and a slew limit and a creep fitted from nominal (no gain);
# the position, screened at 42 nm, was never fitted, and the thermal drift was named.
BATCH_SHORTFALL = 2.0
# A further cause (the parent has causes: its error is above the unexplained limit, or no round
# would seek one) is fitted only if the screen predicts it removes at least this share of what the
# final check demands of it. The screen's first order underestimates a cause that is there: on the
# project's own generator's pairs the second cause was predicted to remove 69-95 % of the error
# and removed 99.9-100 % once fitted; on the independent generator no second cause survived to an
# answer, and those fits were half of the slowest diagnoses (hysteresis 101-103: 30-35 s of 64-80).
SCREEN_SHARE_OF_NEED = 0.5
# A first cause fitted on its parent's calibration is also started from every other law's
# calibration, however much worse that calibration is: a cause the base law lacks can be what
# makes a law's calibration worse (independent GMS creep, seed 133: LuGre calibrated to 72.6 nm
# and GMS to 110 nm, so the creep was fitted on LuGre's alone, to 62 nm, and refused; from GMS's
# calibration it is named at 15.7 nm, against the clean contact's floor of about 14 nm). Each
# other calibration is ranked by RANK_NFEV iterations of its first stage (about a sixth of a
# full one) and goes on to a full first stage only when that already beats the parent's, so that
# the fit is fit()'s from the parent, bit for bit, when no other law wins (both hit-rate
# tables: every hit kept; GMS singles 11 / 18, 10 / 18 before; clean GMS +20 % model steps).
# Two iterations rank as four did (4 until 2026-11-30: both tables and the 20 GMS singles gave
# every answer again) for fewer model steps: clean LS-b seed 103 2 187 -> 1 739 M, its
# hysteresis refused before its cross-validation (BENCHMARKS.md, "Other laws' calibrations
# ranked by two iterations").
RANK_NFEV = 2


def fitted(fu: Future) -> tuple[FitResult, Evaluation]:
    """A fit job's result: the fit and its validation."""
    f, v = fu.result()
    return f, v


# The jobs a Session submits: top-level functions of picklable arguments (runs as numpy arrays,
# parameters as dataclasses), so that any concurrent.futures Executor runs them, Dask's too.
def calibrate_and_validate(train, val, nominal, law, noise_m):
    f, held = calibrate(train, nominal, law, noise_m)
    return f, held, evaluate(val, f.model, noise_m)


def fit_and_validate(
    train, val, nominal, start, free, noise_m, max_nfev=FIT_NFEV, polish=False, grid=True
):
    f = fit(train, nominal, start, free, noise_m, max_nfev=max_nfev, polish=polish, grid=grid)
    return f, evaluate(val, f.model, noise_m)


def fit_from_and_validate(train, val, nominal, start, free, noise_m, theta, max_nfev=FIT_NFEV):
    """fit()'s second stage from a first stage's point, and its validation."""
    f = fit_from(train, nominal, start, free, noise_m, theta, max_nfev)
    return f, evaluate(val, f.model, noise_m)


def fit_under_best_law(train, val, nominal, starts, noise_m, max_nfev=FIT_NFEV):
    """fit() from each (start, free, grid), one per friction law, as far as its first stage (the
    per-cycle residual); the second stage only from the one whose first stage fits best. With a
    base compliance the first stages' costs are orders of magnitude apart: the generator's law
    (LS on our own generator, LuGre on the independent one) 2.7e4-3.5e4 and 7.2e4-3.0e5 against
    at least 4.8e6 under the others, on every seed of both (BENCHMARKS.md)."""
    firsts = [
        first_stage(train, nominal, m, free, noise_m, max_nfev, grid) for m, free, grid in starts
    ]
    i = int(np.argmin([cost for _, cost in firsts]))
    m, free, _ = starts[i]
    f, v = fit_from_and_validate(train, val, nominal, m, free, noise_m, firsts[i][0], max_nfev)
    f.first_stage_costs = {s[0].law: cost for s, (_, cost) in zip(starts, firsts)}
    return f, v


def fit_under_best_calibration(
    train, val, nominal, start, others, noise_m, max_nfev=FIT_NFEV, rank_nfev=RANK_NFEV
):
    """fit() from start, (model, free), unless one of others, each (model, free) from another
    law's calibration, fits better: each other is ranked by rank_nfev iterations of its first
    stage, and one whose ranked cost already beats start's full first stage gets a full one; the
    second stage goes on from the best full first stage. When start's is the
    best, the result is fit(start, free, max_nfev, grid=False)'s, bit for bit. Its
    first_stage_costs hold the full first stages' costs only (a ranked cost is not one: the law
    choice reads them, pipeline._law_chosen_with_it)."""
    m, free = start
    theta, cost = first_stage(train, nominal, m, free, noise_m, max_nfev, False)
    costs = {m.law: cost}
    for mo, fo in others:
        _, ranked = first_stage(train, nominal, mo, fo, noise_m, rank_nfev, False)
        if ranked < cost:
            theta_o, cost_o = first_stage(train, nominal, mo, fo, noise_m, max_nfev, False)
            costs[mo.law] = cost_o
            if cost_o < cost:
                m, free, theta, cost = mo, fo, theta_o, cost_o
    f, v = fit_from_and_validate(train, val, nominal, m, free, noise_m, theta, max_nfev)
    f.first_stage_costs = costs
    return f, v


def default_executor() -> Executor:
    """Threads: the C core releases the GIL, and a thread needs no copy of the runs (a process
    pool pickles every run into every job)."""
    return ThreadPoolExecutor(max_workers=max(1, min(os.cpu_count() or 1, 8)))


class Session:
    """One diagnosis' shared state: runs, noise, executor; submits fits and collects them."""

    def __init__(self, nominal, runs, train, val, noise_m, ex, say, sensor_noise_m=None):
        self.nominal, self.runs, self.train, self.val = nominal, runs, train, val
        self.noise_m, self.ex, self.say = noise_m, ex, say
        self.sensor_noise_m = noise_m if sensor_noise_m is None else sensor_noise_m
        self.families = families(runs)
        xs = [r.x_m for r in runs if len(r.x_m)]
        self.travel_m = float(max(map(np.max, xs)) - min(map(np.min, xs))) if xs else 0.0
        self._lin_cache: dict[int, tuple[Candidate, list[Future]]] = {}
        # per model and family left out: its full refit (Session.fold_refit), the model held too
        self._refit_cache: dict[tuple[int, tuple[int, ...]], tuple[Candidate, Future]] = {}
        # per parent: its causes, screened (the parent held, as in _lin_cache, so that its id
        # is not another's while the entry lives)
        self.screened: dict[int, tuple[Candidate, list[Screened]]] = {}
        self.held: dict[str, tuple[str, ...]] = {}  # per law: what its calibration could not fit
        self.free_base: dict[str, tuple[str, ...]] = {}  # ... and what it could
        self.laws: tuple[str, ...] = ()  # the laws calibrated
        # the chosen law's calibration predicts the held-out runs worse than the nominal model:
        # its parameters took up an effect the base model lacks (own load + hysteresis 102: the
        # calibrations at 2.05-2.71 um against nominal's 1.83 um; the load fitted on them reached
        # 1.2 um, from nominal 167 nm), so first causes are fitted from nominal, as a base's are
        self.calibration_bent = False
        # per parent: the promising causes screened on it and not fitted yet, best first
        self.pending: dict[int, tuple[Candidate, list[Screened]]] = {}
        # the smallest fall of the mean-square error worth a fit, in fit-noise variances
        self.min_mse_drop = MIN_MSE_DROP_OVER_NOISE * (self.sensor_noise_m / noise_m) ** 2
        self.verdicts: dict[str, Verdict] = {}  # per cause: the guards' last word
        self.calibrated: dict[str, Candidate] = {}  # per law: its calibration
        self.refitted_alone: set[tuple[str, frozenset[str]]] = set()  # by without_absent
        # per (candidate, cause): the candidate (held, so that its id is not reused) and its
        # refit without the cause from its own point
        self._without_cache: dict[tuple[int, str], tuple[Candidate, Future]] = {}
        # per (model, cause): the model (held, as above), the spread of the cause's size from law
        # to law and the sizes, said (pipeline._law_dependence)
        self.law_spread: dict[tuple[int, str], tuple[Candidate, float, str]] = {}

    def cand(self, f: FitResult, v: Evaluation, parent=None, held=None) -> Candidate:
        if held is not None:  # a law's calibration: what it fitted is what causes free again
            self.held[f.model.law] = held
            self.free_base[f.model.law] = f.free.base
        law = f.model.law
        k = len(LAW_PARAMS[law]) - len(self.held.get(law, ()))
        k += sum(len(CAUSE_PARAMS[c]) for c in f.causes) + len(f.model.refined_params())
        return Candidate(f, v, bic(v, self.noise_m, k), parent, held=self.held[law], k=k)

    def submit_fit(
        self, start: Model, free: Free, nfev=FIT_NFEV, polish=False, grid=True
    ) -> Future:
        return self.ex.submit(
            fit_and_validate,
            self.train,
            self.val,
            self.nominal,
            start,
            free,
            self.noise_m,
            nfev,
            polish,
            grid,
        )

    def screen(self, parent: Candidate, causes: list[str]) -> list[Screened]:
        """Every cause's predicted validation error on top of parent, best first (screen.py)."""
        lin_futs = self.linearization(parent)
        m, noise = parent.fit.model, self.noise_m
        # with the base parameters back at nominal: under every law on the first round (the law
        # the calibration preferred may be the one that absorbed the cause best), the parent's
        # law afterwards
        laws = self.laws if not parent.causes else (m.law,)
        m_nom = {law: self.at_nominal(replace(m, law=law)) for law in laws}

        def probes(model: Model, c: str, pts, pc: bool = False) -> list[Future]:
            # a per-cycle probe is compared on the validation runs alone: only those are simulated
            # (with the runs before them when heat carries over: fit.predict_all)
            runs = self.val if pc else self.runs
            return [self.ex.submit(probe_residual, runs, model, c, v, noise, pc) for v in pts]

        parent_pc = self.ex.submit(probe_residual, self.val, m, None, {}, noise, True)
        jobs = [
            (
                c,
                pts,
                probes(m, c, pts),
                {law: probes(mn, c, pts, True) for law, mn in m_nom.items()},
            )
            for c in causes
            for pts in [probe_points(c)]
        ]
        # the grid's best point under each law, refined along the cause's refined parameter (each
        # search a job: one law's probes one after the other); the new points are probed as the
        # grid's are (on the parent, and at nominal per law)
        searches = {
            k: [
                self.ex.submit(
                    refine_at_nominal,
                    self.val,
                    m_nom[law],
                    c,
                    pts,
                    [float(np.sum(f.result() ** 2)) for f in fl],
                    noise,
                )
                for law, fl in fn.items()
            ]
            for k, (c, pts, fs, fn) in enumerate(jobs)
            if c in NOMINAL_REFINED
        }
        for k, found in searches.items():
            c, pts, fs, fn = jobs[k]
            extra = []
            for fu in found:
                v = fu.result()
                if v is not None and v not in pts and v not in extra:
                    extra.append(v)
            if extra:
                pts = pts + extra
                fs = fs + probes(m, c, extra)
                fn = {law: fl + probes(m_nom[law], c, extra, True) for law, fl in fn.items()}
                jobs[k] = (c, pts, fs, fn)
        # On the first round, also on each other law's calibration that is not clearly worse
        # than the parent's (clearly_worse: a near tie is decided by the fits' stopping points,
        # and an ulp moves those; independent load seed 102: LuGre's calibration 0.5 % better
        # than LS's, the load screened on it and found; with the rod's flow an ulp off, 0.5 %
        # worse, the screen on LS alone led to a false asymmetric friction): on a law that
        # misfits the data every cause's probe competes with the law's own error (independent
        # asymmetry seed 104: on the LS calibration, 323 nm, six causes screened at 60-87 % and
        # the asymmetry that was there did not rank; fitted under LuGre it reaches 3.8 nm). A
        # cause then keeps its better prediction of the two, and is fitted from that law's
        # calibration. Not the causes fitted from nominal (their own path).
        others = self.other_calibrations(parent) if not parent.causes else []
        other_jobs = [
            (
                o,
                self.linearization(o),
                [(c, probe_points(c)) for c in causes if c not in FIT_FROM_NOMINAL],
            )
            for o in others
        ]
        other_probes = [[probes(o.fit.model, c, pts) for c, pts in cs] for o, _, cs in other_jobs]
        lin = self.assembled(parent, lin_futs)
        val_ids = {id(r) for r in self.val}
        val_idx = [i for i, r in enumerate(self.runs) if id(r) in val_ids]
        out = {
            c: screen(
                lin,
                val_idx,
                c,
                pts,
                [f.result() for f in fs],
                {law: [f.result() for f in fl] for law, fl in fn.items()},
                parent_pc.result(),
            )
            for c, pts, fs, fn in jobs
        }
        for (o, lf, cs), fss in zip(other_jobs, other_probes):
            lin_o = self.assembled(o, lf)
            for (c, pts), fs in zip(cs, fss):
                x = screen(lin_o, val_idx, c, pts, [f.result() for f in fs])
                if share_left(x) < share_left(out[c]):
                    x.on_calibrated, x.nominal_points = o.law, out[c].nominal_points
                    out[c] = x
        # with screens on two calibrations, by the share of its own parent's error each cause is
        # predicted to leave (absolute errors favour the better calibration's causes whatever
        # they add); else by the predicted error, as always
        return sorted(out.values(), key=share_left if others else (lambda x: x.rss_val))

    def extend(self, parent: Candidate, causes: list[str]) -> list[Candidate]:
        """The causes that screen best on top of parent, fitted in full: with the parent's causes
        and every base parameter its law's calibration identified freed again (an effect the base
        model lacks biases its calibration, and a load fitted alone is biased by a hysteresis it
        lacked)."""
        self.say(f"screening {len(causes)} causes on {'+'.join(parent.causes) or parent.law}")
        ranked = self.screen(parent, causes)
        self.screened.setdefault(id(parent), (parent, ranked))
        worth = [
            x
            for x in ranked
            if promising(x, len(CAUSE_PARAMS[x.cause]), MIN_BIC_DROP, self.min_mse_drop)
            and (not parent.causes or self.could_carry(x))
        ]
        self.pending[id(parent)] = (parent, worth)
        fits = self.fit_pending(parent)
        left = self.pending[id(parent)][1]
        if fits and left:
            got = min(c.mse_over_noise for c in fits)
            x = min(left, key=lambda x: x.rss_val / x.n_val)
            if got > BATCH_SHORTFALL * x.rss_val / x.n_val:
                self.say(
                    f"fitting {TOP_FIT} more: the best fit leaves {got:.3g} noise variances, "
                    f"{x.cause} was screened to leave {x.rss_val / x.n_val:.3g}"
                )
                fits += self.fit_pending(parent)
        return fits

    def could_carry(self, x: Screened) -> bool:
        """Is a further cause screened to remove at least SCREEN_SHARE_OF_NEED of the share the
        final check will demand of it (FINAL_SHARE in a model its prediction explains, else
        UNEXPLAINED_FINAL_SHARE)? Below, its fit is not worth its hundreds of simulations."""
        rmse_m = math.sqrt(x.rss_val / x.n_val) * self.noise_m
        explained = within_unexplained_limit(rmse_m, self.sensor_noise_m)
        need = FINAL_SHARE if explained else UNEXPLAINED_FINAL_SHARE
        return predicted_share(x) >= SCREEN_SHARE_OF_NEED * need

    def fit_pending(self, parent: Candidate, carrying: bool = False) -> list[Candidate]:
        """Fit the next TOP_FIT promising causes screened on parent (none left: []); with
        carrying, only those that could carry their share (could_carry)."""
        parent, worth = self.pending.get(id(parent), (parent, []))
        batch = [x for x in worth if not carrying or self.could_carry(x)][:TOP_FIT]
        rest = [x for x in worth if not any(x is b for b in batch)]
        if carrying and len(batch) < min(TOP_FIT, len(worth)):
            few = ", ".join(f"{x.cause} ({100 * predicted_share(x):.0f} %)" for x in rest)
            self.say(f"not fitted, screened to remove too little of the error: {few}")
        self.pending[id(parent)] = (parent, rest)
        futs = []
        for x in batch:
            m = parent.fit.model
            if not parent.causes and (x.cause in FIT_FROM_NOMINAL or self.calibration_bent):
                futs.append(self.submit_under_best_law(x, m))
                continue
            if not parent.causes and not x.from_nominal:
                if x.on_calibrated:
                    futs.append(self.submit_under_best_calibration(x, parent))
                else:
                    futs.append(self.submit_from_every_calibration(x, parent))
                continue
            if x.from_nominal:
                m = self.at_nominal(replace(m, law=x.law))
            fx = replace(m.effects, **start_values(x))
            free = Free(self.free_base[m.law], (*parent.causes, x.cause))
            futs.append(self.submit_fit(replace(m, effects=fx), free, grid=False))
        return [self.cand(*fitted(fu), parent=parent) for fu in futs]

    def other_calibrations(self, parent: Candidate) -> list[Candidate]:
        """The other laws' calibrations a first round screens on beside its parent's: those not
        clearly worse than it (screen)."""
        return [
            o
            for law, o in self.calibrated.items()
            if law != parent.law and not clearly_worse(o, parent)
        ]

    def calibrated_start(self, c: Candidate, x: Screened) -> tuple[Model, Free]:
        """A first-round cause's start on calibration c: its screened values on c's model, with
        the base parameters c's law identified freed again."""
        m = c.fit.model
        fx = replace(m.effects, **start_values(x))
        return replace(m, effects=fx), Free(self.free_base[c.law], (x.cause,))

    def submit_under_best_calibration(self, x: Screened, parent: Candidate) -> Future:
        """A first-round cause that screened best on another law's calibration, fitted from every
        calibration it was screened on, on to the end from the one whose first stage fits best.
        The screen's first-order prediction picks among near ties of the laws (independent load
        seed 100, a LuGre contact: the load probed best on GMS's calibration, 725 nm, and fitted
        there reached 61 nm, where from LuGre's it reaches 3 nm; the asymmetry, its twin, fitted
        from LuGre's to 54 nm and was named)."""
        starts = [
            (*self.calibrated_start(c, x), False)
            for c in [parent, *self.other_calibrations(parent)]
        ]
        return self.ex.submit(
            fit_under_best_law, self.train, self.val, self.nominal, starts, self.noise_m, FIT_NFEV
        )

    def submit_from_every_calibration(self, x: Screened, parent: Candidate) -> Future:
        """A first-round cause screened on parent, fitted from parent's calibration unless
        another law's calibration ranks better (fit_under_best_calibration)."""
        others = [
            self.calibrated_start(o, x) for law, o in self.calibrated.items() if law != parent.law
        ]
        return self.ex.submit(
            fit_under_best_calibration,
            self.train,
            self.val,
            self.nominal,
            self.calibrated_start(parent, x),
            others,
            self.noise_m,
            FIT_NFEV,
        )

    def submit_under_best_law(self, x: Screened, m: Model) -> Future:
        """A first-round cause fitted from the nominal parameters (catalog.FIT_FROM_NOMINAL),
        under the law whose first stage fits best: a missing base resonance bends the
        calibration's choice of law, and the screen's (own generator seed 103, an LS contact: the
        base probed best under LuGre and was fitted there to 669 nm; under LS it reaches the 2 nm
        noise). Every first cause goes this way when the chosen calibration predicts the left-out
        runs worse than nominal (calibration_bent). Under each law from the screen's best probe of
        it at nominal when a probe at nominal screened best, else from the best of the cause's
        grid: the screen's probes on the calibrated model point at the wrong frequency (base at
        3.3 kHz, seed 101: 1.3 kHz)."""
        starts = []
        for law in self.laws:
            mn = self.at_nominal(replace(m, law=law))
            probe = x.nominal_points.get(law) if x.from_nominal else None
            if probe is not None:
                mn = replace(mn, effects=replace(mn.effects, **probe))
            starts.append((mn, Free(self.free_base[law], (x.cause,)), probe is None))
        return self.ex.submit(
            fit_under_best_law, self.train, self.val, self.nominal, starts, self.noise_m, FIT_NFEV
        )

    def refit_without(self, c: Candidate, cause: str) -> Future:
        """c refitted without cause from c's own point (a polish, cached): what the final check
        measures a cause against."""
        key = (id(c), cause)
        if key not in self._without_cache:
            rest = tuple(x for x in c.causes if x != cause)
            fut = self.submit_fit(
                c.fit.model.without(cause), Free(self.free_base[c.law], rest), REFINE_NFEV, True
            )
            self._without_cache[key] = (c, fut)
        return self._without_cache[key][1]

    def at_nominal(self, m: Model) -> Model:
        """The model with its law's base parameters back at their nominal values."""
        nom = Model(self.nominal)
        return m.with_base({n: nom.base_value(n) for n in LAW_PARAMS[m.law]})

    def better(self, new: Candidate, old: Candidate) -> bool:
        return beats(new, old, self.noise_m, self.sensor_noise_m)

    def linearization(self, c: Candidate) -> list[Future]:
        """The model's residual and Jacobian on every run, one column per job (cached; the cache
        holds c too, so that its id is not given to another candidate while the entry lives)."""
        if id(c) not in self._lin_cache:
            m, free = c.fit.model, c.fit.free
            self._lin_cache[id(c)] = (
                c,
                [
                    self.ex.submit(
                        linearize_column, self.runs, self.nominal, m, free, self.noise_m, i
                    )
                    for i in range(-1, len(c.fit.specs))
                ],
            )
        return self._lin_cache[id(c)][1]

    def assembled(self, c: Candidate, futs: list[Future]) -> Linearization:
        return assemble(
            self.runs, self.nominal, c.fit.model, c.fit.free, [f.result() for f in futs]
        )

    def cross_validate(self, v: Verdict, without: Candidate, with_: Candidate) -> None:
        """Leave each run family out in turn: both models refitted without it, then asked to
        predict it. The refits are to first order; a family that with_ predicts clearly worse
        (FoldResult.harmed) is refitted in full, both models, unless with_ would lose the other
        families' vote even if it won every harmed one. with_ is a cause added to without, or
        another friction law."""
        la, lb = self.linearization(without), self.linearization(with_)
        a = assemble(
            self.runs, self.nominal, without.fit.model, without.fit.free, [f.result() for f in la]
        )
        b = assemble(
            self.runs, self.nominal, with_.fit.model, with_.fit.free, [f.result() for f in lb]
        )
        folds = []
        for name, idx in self.families:
            ra, n = fold_rss(a, idx)
            rb, _ = fold_rss(b, idx)
            folds.append(FoldResult(name, ra, rb, n))
        # The first order can be far off where leaving a family out moves a parameter far: a true
        # base compliance on a GMS contact (independent seed 133, 4.07 kHz, its fourth harmonic
        # on the 1000 Hz drive) came out 52 x worse at 1000 Hz to first order; refitted in full,
        # the model without it missed that family 46 x worse than its first order said, and the
        # two came out 1.00 x apart (bench/cv_full_refit.py).
        harmed = [i for i, f in enumerate(folds) if f.harmed]
        wins = sum(f.rss_with < f.rss_without for f in folds if not f.harmed)
        pending: list[int] = []
        if harmed and 2 * (wins + len(harmed)) > len(folds):
            # the most harmed first, one at a time, until the rest could not change the verdict
            # (harm_decided): on clean data of another law a spurious cause's first refitted
            # family often stays harmed beside a family it does not help, and its other refits
            # decide nothing. One family's two refits (one, when the parent's is cached from an
            # earlier check) keep both cores busy: each evaluation spreads its runs over them.
            pending = sorted(harmed, key=lambda i: folds[i].rss_without / folds[i].rss_with)
            while pending:
                if harm_decided([f for i, f in enumerate(folds) if i not in pending]):
                    break
                i = pending.pop(0)
                self.say(
                    f"refitting in full without the {folds[i].family} family: harmed to first order"
                )
                held = self.families[i][1]
                rows = np.isin(a.run_of_row, held)
                ra, rb = (
                    float(np.sum(fu.result()[rows] ** 2))
                    for fu in [self.fold_refit(c, held) for c in (without, with_)]
                )
                folds[i] = FoldResult(folds[i].family, ra, rb, folds[i].n, refitted=True)
        v.folds.extend(f for i, f in enumerate(folds) if i not in pending)
        v.unrefitted.extend(folds[i] for i in sorted(pending))
        judge_cv(v)

    def fold_refit(self, c: Candidate, held: list[int]) -> Future:
        """c refitted in full without the held runs (fit.refit_without): its residual on every
        run's rows (cached per model and family: a parent is the model without the cause of many
        checks; the cache holds c, as _lin_cache does)."""
        key = (id(c), tuple(held))
        if key not in self._refit_cache:
            fu = self.ex.submit(
                refit_without,
                self.runs,
                self.nominal,
                c.fit.model,
                c.fit.free,
                self.noise_m,
                held,
                REFINE_NFEV,
            )
            self._refit_cache[key] = (c, fu)
        return self._refit_cache[key][1]

    def judge(self, cand: Candidate, parent: Candidate, new: tuple[str, ...]) -> Verdict:
        """Range, share and cross-validation of what cand adds to parent."""
        v = Verdict()
        # every cause of the candidate: one kept on the way in must still lie in its range
        absent: list[str] = []
        for c in cand.causes:
            problems = range_problems(cand.fit, (c,)) + self.position_floor(cand, c)
            v.reasons.extend(problems)
            if problems:
                absent.append(c)
        v.absent, v.in_range = tuple(absent), not v.reasons
        # a first cause is measured as the final check (_backward) measures it: against the best
        # model without it, its own law's calibration when that beats the parent (a cause fitted
        # under another law than the base's is not credited with the law's gain)
        v.share = share_removed(self.without_first(cand, parent), cand.mse_over_noise)
        if v.share < FWD_SHARE:
            v.reasons.append(
                f"removes only {100 * v.share:.0f} % of the error above the noise "
                f"(a cause must remove at least {100 * FWD_SHARE:.0f} %)"
            )
        if v.reasons:  # the cross-validation is the costly test: only when the rest holds
            return v
        self.cross_validate(v, parent, cand)
        return v

    def without_first(self, cand: Candidate, parent: Candidate) -> float:
        """The error (mean square over the noise's) that cand's new causes are measured against:
        parent's; for a first cause, the lower of parent's and its own law's calibration's."""
        cal = self.calibrated.get(cand.law)
        if parent.causes or cal is None:
            return parent.mse_over_noise
        return min(parent.mse_over_noise, cal.mse_over_noise)

    def position_floor(self, cand: Candidate, cause: str) -> list[str]:
        """The problem of a position-only cause of cand that moves the positions no more than a
        sensor's own linearity error over the travel measured (two simulations), if any."""
        if cause not in POSITION_ONLY:
            return []
        m = cand.fit.model
        moved = max(
            (
                float(np.max(np.abs(a - b)))
                for a, b in zip(predict_all(self.runs, m), predict_all(self.runs, m.without(cause)))
            ),
            default=0.0,
        )
        problem = position_floor_problem(cause, moved, self.travel_m)
        return [problem] if problem else []

    def under_other_law(self, cand: Candidate, parent: Candidate) -> Candidate | None:
        """A first cause that carries the share a kept cause needs (UNEXPLAINED_FINAL_SHARE) and
        failed only on the run families left out, fitted again from each other law's calibration
        (from its own fitted values): the best of those, if it beats its law's calibration, to be
        judged there. Under a law that misfits the data the base's error differs from family to
        family, and a cause that is there absorbs some of it and stops carrying over (independent
        load seed 101: 88 % of the LS calibration's error, 4.4 x worse on the 1 000 Hz runs left
        out; the load is found under LuGre, the data's law). None when that does not apply."""
        v = cand.verdict
        if (
            parent.causes
            or v is None
            or not v.folds  # the cross-validation ran: range and share held
            or v.share < UNEXPLAINED_FINAL_SHARE
            or len(cand.causes) != 1
        ):
            return None
        (cause,) = cand.causes
        values = {p.name: getattr(cand.fit.model.effects, p.name) for p in CAUSE_PARAMS[cause]}
        others = [c for law, c in self.calibrated.items() if law != cand.law]
        if not others:
            return None
        self.say(
            f"{cause} under {', '.join(c.law for c in others)}: fitted from their calibrations"
        )
        futs = [
            self.submit_fit(
                replace(c.fit.model, effects=replace(c.fit.model.effects, **values)),
                Free(self.free_base[c.law], (cause,)),
                grid=False,
            )
            for c in others
        ]
        alts = [(self.cand(*fitted(fu), parent=c), c) for c, fu in zip(others, futs)]
        best, cal = min(alts, key=lambda a: a[0].score)
        return best if self.better(best, cal) else None

    def without_absent(self, cand: Candidate, parent: Candidate) -> Candidate | None:
        """cand failed its guards only on causes it took from parent whose fitted values say
        they are not there (outside their range, at a bound, under the position floor): its new
        cause refitted without them, from cand's point, on parent's own parent. An effect that
        screens below causes that are not there is reached only on top of them (an asymmetry,
        independent seed 104, came as three pairs at 5-9 nm: on a hysteresis below its range, a
        creep at its bound, a gradient under the floor), and each pair fails for the other cause.
        Also when what is not there is cand's new cause: the pair's fit may have carried parent's
        own causes to a better point than parent's fit reached, and they are refitted alone from
        there (our own generator's slew limit, seed 7, on the core with the rod's compliance: the
        slew alone stopped at 136 nm, 1.36 V/us; beside a hysteresis that came out at its bound,
        1.271 V/us, the truth, and 2.0 nm, the noise).
        None when that does not apply, or when the same causes were refitted so already."""
        v, gp = cand.verdict, parent.parent
        if v is None or gp is None or not v.absent or v.share < FWD_SHARE:
            return None
        # each absent cause came from parent, not from further up (so none is cand's new one) ...
        from_parent = all(c in parent.causes and c not in gp.causes for c in v.absent)
        # ... or each is new, and parent's causes remain
        only_new = bool(parent.causes) and all(c not in parent.causes for c in v.absent)
        if not (from_parent or only_new):
            return None
        keep = tuple(c for c in cand.causes if c not in v.absent)
        if (cand.law, frozenset(keep)) in self.refitted_alone:
            return None
        self.refitted_alone.add((cand.law, frozenset(keep)))
        m = cand.fit.model
        for c in v.absent:
            m = m.without(c)
        self.say(f"refitting {'+'.join(keep)} without {'+'.join(v.absent)}")
        f, val = self.submit_fit(m, Free(self.free_base[m.law], keep), grid=False).result()
        return self.cand(f, val, parent=gp)

    def judged(self, cand: Candidate, parent: Candidate) -> Verdict:
        new = tuple(c for c in cand.causes if c not in parent.causes)
        s_ = "+".join(cand.causes)
        self.say(f"checking {s_}: physical range, share of the error, left-out run families")
        v = self.judge(cand, parent, new)
        for c in new:
            self.verdicts[c] = v
        return v


def share_left(x: Screened) -> float:
    """The share of its parent's predicted validation error a screened cause would leave."""
    return x.rss_val / max(x.rss_parent, 1e-300)
