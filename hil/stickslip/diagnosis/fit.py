"""Simulating measured runs with the C model, and fitting model parameters to them.

A model point is (friction law, ActuatorParams, Effects). A fit frees a chosen set of base
parameters (catalog.BASE_FACTOR) and the parameters of a list of causes, and minimises the
position residual over the given runs, scaled by the measurement noise, with scipy's
least_squares (finite-difference Jacobians at up to JAC_MAX_DT_S). Its Jacobian at the optimum
gives each parameter's standard error. Every function
here is a plain top-level function of picklable arguments, so an Executor (local processes, Dask)
can run it anywhere."""

from __future__ import annotations

import functools
import itertools
import math
import os
import threading
from collections import OrderedDict
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from functools import cache
from typing import Any, TypeVar, cast

import numpy as np
from scipy.optimize import least_squares
from scipy.signal import resample_poly
from threadpoolctl import threadpool_limits

from ..dataset import Run
from ..model import (
    GMS_DECAY,
    ActuatorParams,
    Effects,
    Sawtooth,
    SimResult,
    major_loop_gain,
    simulate,
    simulate_many,
)
from .catalog import (
    BASE_FACTOR,
    CAUSE_PARAMS,
    CAUSE_START,
    REFINE_PARAMS,
    Param,
    base_param,
    cause_params,
)

MAX_DT_S = 1e-6  # the model's step: converged to 0.08 % per cycle (docs/model.md)
# Fits and figures work on the measured positions anti-alias filtered and decimated to at most
# this rate: 2.5 samples on a 50 us stretch, far above the slider's 4.3 kHz contact mode.
MAX_FIT_RATE_HZ = 50e3
MAX_POINTS_PER_RUN = 1500  # residual samples per run in a fit (every k-th sample)
MIN_STEP_OVER_NOISE = 50.0  # a run steps when its mean step is above this x noise
# The fits' finite-difference Jacobians simulate at up to twice the model's step: they set only
# the direction of each least-squares step (the residual itself, hence the optimum, is at
# MAX_DT_S), and a derivative off by the 2 us step's 0.3 % per cycle leaves the optimum where it
# was; each column then costs half. Not where a base resonance rings: its phase error over a run
# at 2 us bent the Jacobian enough to stop a base-compliance fit at 59 nm instead of 25 nm
# (BENCHMARKS.md, "Faster, and a stricter word on unexplained data"). Nor in a polish (fit with
# polish=True, a refit from its own optimum): there the 2 us model's valley lies beside the 1 us
# one, and in a narrow valley its steps lead off the floor (own slew + thermal drift 101: the
# diagnosis ended at 7.0 x the noise, its thermal drift stopped in such a valley; with every
# polish's Jacobian at 1 us, 1.00 x).
JAC_MAX_DT_S = 2e-6
# A first stage with more start points than START_RANK_KEEP ranks them by their per-cycle cost over
# each run's first START_RANK_PERIODS periods (0.15 of the training runs' model steps in the 13-run
# design) and compares only the best START_RANK_KEEP over the whole runs. On 71 grids of 22
# independent diagnoses the whole runs' best start was among those 4 on 69 (ranked 1st on 63);
# on the other two, GMS's first stage of a base fitted under every law (a law that lost by 100 x),
# it ranked 12th and 13th; every answer and final error stayed main's to the last digit, for
# 13-20 % fewer model steps on a base's diagnosis, 7-8 % on clean GMS and LS-b (BENCHMARKS.md,
# "Start points ranked on their first periods"). Not with heat carried from run to run: a cut run
# would start with no run's heat before it.
START_RANK_PERIODS = 4
START_RANK_KEEP = 4
H_THETA = 1e-3  # finite-difference step in theta (0.1 % of a scale, 1e-3 ref of a signed value)
# A parameter whose standard error exceeds this share of its value (of its reference, for signed
# ones) is not pinned down by the runs: it is held at its nominal value and reported as such.
MAX_REL_STDERR = 0.3


def one_blas_thread() -> threadpool_limits:
    """A context in which BLAS runs on one thread. The fits' matrices are small (thousands of rows
    by a dozen columns); OpenBLAS's threads then gain nothing and spin, once woken, on the cores
    the simulations need: a diagnosis took 22 % less wall time with the same simulations and the
    same answer (BENCHMARKS.md)."""
    return threadpool_limits(limits=1, user_api="blas")


_Fn = TypeVar("_Fn", bound=Callable[..., Any])


def with_one_blas_thread(fn: _Fn) -> _Fn:
    """fn, run inside one_blas_thread()."""

    @functools.wraps(fn)
    def wrapped(*args: Any, **kwargs: Any) -> Any:
        with one_blas_thread():
            return fn(*args, **kwargs)

    return cast(_Fn, wrapped)


@dataclass
class FitRun:
    """A measured run as the fits see it: positions anti-alias filtered and decimated (t_s, x_m,
    dt_s), the drive as recorded (waveform, or drive_v at drive_dt_s) for the simulation."""

    id: str
    t_s: np.ndarray
    x_m: np.ndarray
    dt_s: float
    waveform: Sawtooth | None
    drive_v: np.ndarray
    drive_dt_s: float
    decimation: int  # measured samples per fit sample
    # the dataset's largest drive amplitude: a hysteresis keeps the nominal stroke over it
    # (model.major_loop_gain)
    stroke_v: float = 0.0
    # the run recorded just before this one (dataset.json's order, prepare_all): its contact's
    # heat is where this run's starts (thermal_drift)
    prev: FitRun | None = field(default=None, repr=False, compare=False)
    # its latest predictions by what decides them (_cached): a diagnosis simulates about 5 % of
    # its model steps again (a fitted point's residual for its linearization, a model whose causes
    # differ but not its effects)
    sims: OrderedDict = field(default_factory=OrderedDict, init=False, repr=False, compare=False)

    def __getstate__(self) -> dict:
        """Pickled (into a process pool's job) without the predictions kept."""
        return {**self.__dict__, "sims": OrderedDict()}


@cache
def filter_noise_gain(q: int) -> float:
    """RMS of white unit noise after the decimation filter of factor q (1 for q = 1)."""
    if q == 1:
        return 1.0
    w = np.random.default_rng(0).standard_normal(400_000)
    return float(np.std(resample_poly(w, 1, q)[100:-100]))


def prepare_all(runs: list[Run]) -> list[FitRun]:
    """Every run of a dataset prepared, each knowing the dataset's largest drive amplitude: the
    major loop its nominal gain strokes (model.major_loop_gain)."""
    stroke_v = max(
        (r.waveform.amplitude_v if r.waveform else float(np.ptp(r.drive_v)) for r in runs),
        default=0.0,
    )
    out = [prepare(r, stroke_v) for r in runs]
    for before, run in zip(out, out[1:]):
        run.prev = before
    return out


def prepare(run: Run, stroke_v: float = 0.0) -> FitRun:
    """Filter and decimate a run to at most MAX_FIT_RATE_HZ (polyphase FIR, zero phase, linear
    extension at the ends so a run's offset and drift are not pulled toward zero). stroke_v:
    the dataset's largest drive amplitude (prepare_all)."""
    q = max(1, math.ceil(1.0 / (run.dt_s * MAX_FIT_RATE_HZ) - 1e-9))
    x = run.x_m if q == 1 else resample_poly(run.x_m, 1, q, padtype="line")
    t = run.t_s[::q]
    n = min(len(t), len(x))
    return FitRun(
        run.id,
        t[:n],
        np.asarray(x[:n]),
        run.dt_s * q,
        run.waveform,
        run.drive_v,
        run.dt_s,
        q,
        stroke_v,
    )


@dataclass
class Model:
    params: ActuatorParams
    effects: Effects = field(default_factory=Effects)
    law: str = "ls"
    causes: tuple[str, ...] = ()  # catalog causes whose effects the model carries
    gms_decay: float = GMS_DECAY  # the GMS law's presliding shape (not an actuator parameter)

    def base_value(self, name: str) -> float:
        if name == "stribeck_excess":
            return self.params.mu_s - self.params.mu_d
        if name == "gms_decay":
            return self.gms_decay
        return float(getattr(self.params, name))

    def with_base(self, values: dict[str, float]) -> Model:
        kw = dict(values)
        if "stribeck_excess" in kw:
            kw["mu_s"] = self.params.mu_d + kw.pop("stribeck_excess")
        decay = kw.pop("gms_decay", self.gms_decay)
        return replace(self, params=replace(self.params, **kw), gms_decay=decay)

    def without(self, cause: str) -> Model:
        """The same model with one cause's effect switched off."""
        off = {q.name: 0.0 for q in cause_params(cause)}
        return replace(
            self,
            effects=replace(self.effects, **off),
            causes=tuple(c for c in self.causes if c != cause),
        )

    def values(self) -> dict[str, float]:
        """Every base value and the causes' fitted values, named as in the diagnosis JSON."""
        p = self.params
        out: dict = {
            "normal_force_n": p.normal_force_n,
            "mu_s": p.mu_s,
            "sigma0_n_per_m": p.sigma0_n_per_m,
            "stribeck_velocity_m_per_s": p.stribeck_velocity_m_per_s,
            "sigma1_ns_per_m": p.sigma1_ns_per_m,
            "sigma2_ns_per_m": p.sigma2_ns_per_m,
            "piezo_damping_kg_per_s": p.piezo_damping_kg_per_s,
        }
        if self.law == "gms":
            out["gms_decay"] = self.gms_decay
        for c in self.causes:
            for q in CAUSE_PARAMS[c]:
                out[f"{c}.{q.name}"] = float(getattr(self.effects, q.name))
        for c, name in self.refined_params():
            out[f"{c}.{name}"] = float(getattr(self.effects, name))
        return out

    def refined_params(self) -> tuple[tuple[str, str], ...]:
        """(cause, name) of each of its causes' REFINE_PARAMS that a refinement kept (set: not
        0, which is off)."""
        return tuple(
            (c, q.name)
            for c in self.causes
            for q in REFINE_PARAMS.get(c, ())
            if getattr(self.effects, q.name) != 0.0
        )


def slider_start_m(run: FitRun, effects: Effects) -> float:
    """Where a simulation of the run starts the slider: its first measured position through the
    sensor's scale error (what position-dependent friction sees; predict and the replay's RESET)."""
    return float(run.x_m[0]) / (1.0 + effects.sensor_scale_error)


def sim_step_s(run: FitRun, max_dt_s: float = MAX_DT_S) -> tuple[float, int]:
    """Model step dividing the fit's sample interval exactly, and the decimation."""
    dec = max(1, math.ceil(run.dt_s / max_dt_s - 1e-9))
    return run.dt_s / dec, dec


def predict(run: FitRun, model: Model, max_dt_s: float = MAX_DT_S) -> np.ndarray:
    """What the sensor would have reported at the run's fit sample times under this model. The
    slider's start is a nuisance offset per run, placed by least squares over the whole run.
    With thermal_drift, the runs recorded before it are simulated first (predict_all)."""
    if carries_heat(model) and run.prev is not None:
        return _predict_chain([run], model, False, max_dt_s)[0]
    return _predict_heat(run, model, max_dt_s, 0.0)[0]


def carries_heat(model: Model) -> bool:
    """Does a run's prediction depend on the runs before it (the heat of thermal_drift)?"""
    return model.effects.thermal_coeff_per_j != 0.0


def _predict_heat(
    run: FitRun, model: Model, max_dt_s: float, heat0_j: float
) -> tuple[np.ndarray, float]:
    """predict() from a contact holding heat0_j, and the heat the run leaves."""
    key = _sim_key(model, max_dt_s, heat0_j)
    hit = _cached(run, key)
    if hit is not None:
        return hit
    return _store(run, key, _predicted(run, simulate(**_request(run, model, max_dt_s, heat0_j))))


# Predictions kept per run (the oldest out first): 32 a run kept 3.7-4.0 % of the model steps of a
# slow diagnosis from being simulated again (all that repeats: 5.6-5.9 %), for 13 MB on the 13-run
# design (51 679 fit samples of 8 bytes, 32 times).
SIM_CACHE_PER_RUN = 32
_SIM_CACHE_LOCK = threading.Lock()


def _sim_key(model: Model, max_dt_s: float, heat0_j: float) -> tuple:
    """Everything besides the run that decides its simulation (_request): not the model's causes,
    which name its effects but do not set them."""
    return (model.law, model.gms_decay, model.params, model.effects, max_dt_s, heat0_j)


def _cached(run: FitRun, key: tuple) -> tuple[np.ndarray, float] | None:
    with _SIM_CACHE_LOCK:
        hit = run.sims.get(key)
        if hit is not None:
            run.sims.move_to_end(key)
        return hit


def _store(run: FitRun, key: tuple, out: tuple[np.ndarray, float]) -> tuple[np.ndarray, float]:
    """out kept for key (read-only: every caller shares the one array)."""
    out[0].setflags(write=False)
    with _SIM_CACHE_LOCK:
        run.sims[key] = out
        if len(run.sims) > SIM_CACHE_PER_RUN:
            run.sims.popitem(last=False)
    return out


def _request(run: FitRun, model: Model, max_dt_s: float, heat0_j: float) -> dict:
    """simulate()'s arguments for the run under the model."""
    dt, dec = sim_step_s(run, max_dt_s)
    kw = dict(
        params=major_loop_gain(model.params, model.effects, run.stroke_v),
        model=model.law,
        dt_s=dt,
        decimation=dec,
        effects=model.effects,
        x0_m=slider_start_m(run, model.effects),
        heat0_j=heat0_j,
        gms_decay=model.gms_decay,
    )
    if run.waveform is not None:
        n = len(run.t_s) - 1
        kw.update(waveform=run.waveform, hold_s=max(0.0, n * run.dt_s - run.waveform.duration_s))
    else:
        kw.update(drive_v=run.drive_v, drive_interval_s=run.drive_dt_s)
    return kw


def _predicted(run: FitRun, r: SimResult) -> tuple[np.ndarray, float]:
    """The run's fit samples from a simulation of it (placed), and the heat it leaves."""
    n = len(run.t_s) - 1
    x = r.x_meas_m
    if len(x) < n + 1:  # rounding of the duration: hold the last value
        x = np.concatenate([x, np.full(n + 1 - len(x), x[-1])])
    return placed(run, x[: n + 1]), r.heat_end_j


def placed(run: FitRun, x: np.ndarray) -> np.ndarray:
    """Simulated positions x shifted to where the run's slider started, by least squares over the
    whole run. That start is known only to the sensor's noise: placing it from the first samples
    alone left their mean noise (~0.7 nm from 10 samples) as an offset in every residual, and fits
    then bent the physical parameters to chase it."""
    return x + float(np.mean(run.x_m - x))


# One pool of simulation threads per process (the C core releases the GIL and keeps no state
# between calls): every evaluation spreads its runs over the cores, so that a fit running alone
# (a refinement, the law check) does not leave a core idle. Keyed by process id: a forked
# worker must not inherit its parent's pool, whose threads did not survive the fork.
_SIM_POOLS: dict[int, ThreadPoolExecutor] = {}
SIM_THREADS = max(1, min(os.cpu_count() or 1, 8))


def _sim_pool() -> ThreadPoolExecutor:
    pid = os.getpid()
    if pid not in _SIM_POOLS:
        _SIM_POOLS[pid] = ThreadPoolExecutor(max_workers=SIM_THREADS)
    return _SIM_POOLS[pid]


def _predict_chain(
    runs: list[FitRun], model: Model, far_on_error: bool, max_dt_s: float
) -> list[np.ndarray]:
    """predict() on runs whose contact carries heat from run to run: every run from the first
    recorded up to the last one asked for, one after another, each starting with the heat the
    one before left (the recorded hold at 0 V included; no rest between records is assumed).
    Sequential, so one core: only models with thermal_drift pay it."""
    wanted = {id(r) for r in runs}
    last = max(runs, key=_order)
    chain = [last]
    while chain[-1].prev is not None:
        chain.append(chain[-1].prev)
    out: dict[int, np.ndarray] = {}
    heat = 0.0
    for r in reversed(chain):
        try:
            x, heat = _predict_heat(r, model, max_dt_s, heat)
        except ValueError:
            if not far_on_error:
                raise
            x, heat = np.full(len(r.x_m), 1.0), 0.0
        if id(r) in wanted:
            out[id(r)] = x
    # a run not recorded before the last one asked for (another dataset's): from a cold contact
    return [out[id(r)] if id(r) in out else _predict_heat(r, model, max_dt_s, 0.0)[0] for r in runs]


def _order(run: FitRun) -> int:
    """How many runs were recorded before this one."""
    n, r = 0, run
    while r.prev is not None:
        n, r = n + 1, r.prev
    return n


def predict_all(
    runs: list[FitRun],
    model: Model,
    far_on_error: bool = False,
    max_dt_s: float = MAX_DT_S,
    pooled: bool = True,
) -> list[np.ndarray]:
    """predict() on every run, the runs spread over the simulation threads, each thread's share as
    one batch of the C core (simulate_many: runs stepped side by side, the same bits).
    far_on_error: a model the C library rejects gives a position of 1 m instead of an error.
    With thermal_drift, the runs in their recorded order, each from the heat the last left.
    pooled=False: all in the calling thread (a job already running on the simulation threads)."""
    if runs and carries_heat(model):
        return _predict_chain(runs, model, far_on_error, max_dt_s)
    groups = _balanced(runs, max_dt_s, SIM_THREADS if pooled else 1)
    if len(groups) < 2:
        return _predict_batch(runs, model, far_on_error, max_dt_s)
    futs = [
        _sim_pool().submit(_predict_batch, [runs[i] for i in g], model, far_on_error, max_dt_s)
        for g in groups
    ]
    out: list[np.ndarray] = [np.zeros(0)] * len(runs)
    for g, fu in zip(groups, futs):
        for i, x in zip(g, fu.result()):
            out[i] = x
    return out


def _balanced(runs: list[FitRun], max_dt_s: float, n: int) -> list[list[int]]:
    """The runs' indices in at most n groups of about equal simulation steps (longest first, each
    to the lightest group), each group longest first: a batch's two lanes then finish together."""
    steps = [len(r.x_m) * sim_step_s(r, max_dt_s)[1] for r in runs]
    groups: list[list[int]] = [[] for _ in range(max(1, min(n, len(runs))))]
    load = [0] * len(groups)
    for i in sorted(range(len(runs)), key=lambda i: -steps[i]):
        k = load.index(min(load))
        groups[k].append(i)
        load[k] += steps[i]
    return [g for g in groups if g]


def _predict_batch(
    runs: list[FitRun], model: Model, far_on_error: bool, max_dt_s: float
) -> list[np.ndarray]:
    """predict() on runs whose contact starts cold, as one batch of the C core (the runs whose
    prediction is not cached)."""
    key = _sim_key(model, max_dt_s, 0.0)
    hits = [_cached(r, key) for r in runs]
    todo = [r for r, h in zip(runs, hits) if h is None]
    sims = iter(simulate_many([_request(r, model, max_dt_s, 0.0) for r in todo]))
    out = []
    for run, hit in zip(runs, hits):
        if hit is not None:
            out.append(hit[0])
            continue
        sim = next(sims)
        if isinstance(sim, ValueError):
            if not far_on_error:  # a parameter the C library rejects
                raise sim
            out.append(np.full(len(run.x_m), 1.0))  # far off, not a crash
        else:
            out.append(_store(run, key, _predicted(run, sim))[0])
    return out


@dataclass(frozen=True)
class Free:
    """What a fit frees: base parameters by name, causes (each with all its parameters) and, by
    name, parameters of those causes fitted only in a refinement (catalog.REFINE_PARAMS)."""

    base: tuple[str, ...]
    causes: tuple[str, ...]
    refine: tuple[str, ...] = ()
    # the causes' parameters bounded by their physical range (Param.phys), not the fit's wider
    # bounds: a cause asked what it explains where a real stage can have it
    in_range: bool = False


def strides(runs: list[FitRun]) -> list[int]:
    """Every how many samples a run's residual is taken: at most MAX_POINTS_PER_RUN a run."""
    return [max(1, len(r.x_m) // MAX_POINTS_PER_RUN) for r in runs]


def run_of_row(runs: list[FitRun]) -> np.ndarray:
    """The index of the run each row of residuals(runs, ...) belongs to (at strides(runs))."""
    return np.concatenate(
        [np.full(len(r.x_m[::k]), i) for i, (r, k) in enumerate(zip(runs, strides(runs)))]
    )


def specs_for(nominal: ActuatorParams, free: Free) -> list[Param]:
    specs = []
    at_nominal = Model(nominal)
    for name in free.base:
        if name == "stribeck_excess":
            specs.append(base_param(name, max(nominal.mu_s - nominal.mu_d, 1e-3)))
        else:
            specs.append(base_param(name, at_nominal.base_value(name)))
    causes: list[Param] = []
    for c in free.causes:
        causes.extend(CAUSE_PARAMS[c])
    for c in free.causes:
        causes.extend(p for p in REFINE_PARAMS.get(c, ()) if p.name in free.refine)
    if free.in_range:
        causes = [p.within_range() for p in causes]
    return specs + causes


def _names(params: tuple[Param, ...]) -> set[str]:
    return {p.name for p in params}


def theta_of(model: Model, specs: list[Param]) -> np.ndarray:
    """The fit coordinates of a model's values (clipped into the bounds)."""
    out = []
    for s in specs:
        lo, hi = s.bounds()
        out.append(min(max(s.theta(_value_of(model, s)), lo), hi))
    return np.array(out)


def build(start: Model, free: Free, theta: np.ndarray, specs: list[Param]) -> Model:
    """The model at theta: start's values (its causes' effects included), with the free base
    parameters and the free causes' parameters from theta."""
    nb = len(free.base)
    m = start.with_base({s.name: s.value(float(t)) for s, t in zip(specs[:nb], theta[:nb])})
    kw = {s.name: s.value(float(t)) for s, t in zip(specs[nb:], theta[nb:])}
    causes = m.causes + tuple(c for c in free.causes if c not in m.causes)
    return replace(m, effects=replace(m.effects, **kw), causes=causes)


def _cycle_refs(run: FitRun) -> np.ndarray | None:
    """For each sample, the index of the sample at the start of its period (or of the hold)."""
    if run.waveform is None:
        return None
    w = run.waveform
    starts = np.rint(np.arange(w.cycles + 1) * w.period_s / run.dt_s).astype(int)
    idx = np.arange(len(run.x_m))
    return starts[np.clip(np.searchsorted(starts, idx, side="right") - 1, 0, len(starts) - 1)]


def _first_periods(run: FitRun, periods: int) -> FitRun:
    """The run up to the end of its first periods (no hold after them, no run before it)."""
    w = run.waveform
    if w is None or w.cycles <= periods:
        return run
    n = int(round(periods / w.frequency_hz / run.dt_s))
    return FitRun(
        run.id,
        run.t_s[: n + 1],
        run.x_m[: n + 1],
        run.dt_s,
        replace(w, cycles=periods),
        run.drive_v,
        run.drive_dt_s,
        run.decimation,
        run.stroke_v,
    )


def residuals(
    runs: list[FitRun],
    model: Model,
    noise_m: float,
    every: list[int],
    per_cycle: bool = False,
    max_dt_s: float = MAX_DT_S,
    pooled: bool = True,
) -> np.ndarray:
    """Simulated minus measured position over noise, every k-th sample. per_cycle measures each
    sample from the start of its period instead: the residual no longer accumulates over a run,
    which keeps the cost smooth far from the optimum (a fit's first stage). pooled: as in
    predict_all."""
    parts = []
    for run, k, x in zip(runs, every, predict_all(runs, model, True, max_dt_s, pooled)):
        r = x - run.x_m
        refs = _cycle_refs(run) if per_cycle else None
        if refs is not None:
            r = r - r[refs]
        parts.append(r[::k] / noise_m)
    return np.concatenate(parts)


@dataclass
class FitResult:
    free: Free
    model: Model
    values: dict[str, float]
    train_rms_m: float
    nfev: int
    # per free parameter: standard error of its value (first order, from the Jacobian at the
    # optimum, scaled by the reduced chi-square when the model does not reach the noise)
    stderr: dict[str, float] = field(default_factory=dict)
    correlation: dict[str, dict[str, float]] = field(default_factory=dict)
    at_bound: tuple[str, ...] = ()

    jac: np.ndarray | None = None  # residual / noise against theta at the optimum
    fun: np.ndarray | None = None  # residual / noise at the optimum
    specs: list[Param] = field(default_factory=list)
    # a fit whose law was chosen by first stages under each law: each law's per-cycle cost
    first_stage_costs: dict[str, float] = field(default_factory=dict)

    @property
    def causes(self) -> tuple[str, ...]:
        return self.model.causes

    @property
    def n_params(self) -> int:
        return len(self.stderr)


def covariance(jac: np.ndarray, chi2_red: float) -> np.ndarray:
    """Covariance of the fit coordinates from the Jacobian (residual over noise), scaled by the
    reduced chi-square when the model does not reach the noise. A direction the residual does not
    depend on (a dead parameter, or two that act alike) has an infinite variance, so that every
    parameter along it reads as not identifiable (a pseudo-inverse would report it as exact)."""
    jtj = jac.T @ jac
    s, v = np.linalg.eigh(jtj)
    dead = s <= max(float(s.max(initial=0.0)), 1e-300) * 1e-10
    inv = np.where(dead, 0.0, 1.0 / np.where(dead, 1.0, s))
    cov = (v * inv) @ v.T * max(1.0, chi2_red)
    along_dead = (
        np.any(np.abs(v[:, dead]) > 1e-6, axis=1) if np.any(dead) else np.zeros(len(s), bool)
    )
    cov[along_dead, :] = np.inf
    cov[:, along_dead] = np.inf
    return cov


def _uncertainty(
    jac: np.ndarray, fun: np.ndarray, specs: list[Param], model: Model
) -> tuple[dict[str, float], dict[str, dict[str, float]]]:
    n, k = jac.shape
    cov = covariance(jac, float(np.sum(fun**2)) / max(1, n - k))
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    vals = [_value_of(model, s) for s in specs]
    stderr = {s.name: s.stderr(v, float(e)) for s, v, e in zip(specs, vals, sd)}
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = np.nan_to_num(cov / np.outer(sd, sd), nan=0.0, posinf=0.0, neginf=0.0)
    correlation = {
        a.name: {b.name: float(corr[i, j]) for j, b in enumerate(specs) if j != i}
        for i, a in enumerate(specs)
    }
    return stderr, correlation


def _value_of(model: Model, s: Param) -> float:
    if s.name in BASE_FACTOR:
        return model.base_value(s.name)
    return float(getattr(model.effects, s.name))


def rel_stderr(p: Param, value: float, stderr: float) -> float:
    """Standard error relative to the value (to the reference, for a signed parameter that may
    be zero)."""
    scale = abs(value) if p.kind == "log" else max(abs(value), abs(p.ref))
    return stderr / scale if scale > 0 else math.inf


class _Problem:
    """One least-squares problem: the free parameters of start on runs, their fit coordinates,
    bounds and start point, and the residual at any point (simulations counted in nfev)."""

    def __init__(
        self, runs: list[FitRun], nominal: ActuatorParams, start: Model, free: Free, noise_m: float
    ):
        self.runs, self.start, self.free, self.noise_m = runs, start, free, noise_m
        self.specs = specs = specs_for(nominal, free)
        self.nb = len(free.base)
        self.every = strides(runs)
        theta0 = []
        for i, s in enumerate(specs):
            if i < self.nb:
                v = start.base_value(s.name)
            else:
                # by name: with free.in_range the spec is a narrowed copy of the catalog's
                cause = next(c for c in free.causes if s.name in _names(cause_params(c)))
                # a refinement parameter (a scale, never zero) starts at its ref
                off = 0.0 if s.name in _names(CAUSE_PARAMS[cause]) else s.ref
                v = CAUSE_START.get(cause, {}).get(s.name, off)
                if getattr(start.effects, s.name) != 0.0:
                    v = getattr(start.effects, s.name)
            t_lo, t_hi = s.bounds()
            theta0.append(min(max(s.theta(v), t_lo + 1e-9), t_hi - 1e-9))
        self.theta0 = np.array(theta0)
        self.lo = np.array([s.bounds()[0] for s in specs])
        self.hi = np.array([s.bounds()[1] for s in specs])
        self.nfev = 0
        rings = "base_compliance" in free.causes or start.effects.base_mass_kg != 0.0
        self.jac_dt = MAX_DT_S if rings else JAC_MAX_DT_S
        self._short: list[FitRun] | None = None

    def model(self, theta: np.ndarray) -> Model:
        return build(self.start, self.free, theta, self.specs)

    def res_at(self, theta: np.ndarray, per_cycle: bool, max_dt_s: float = MAX_DT_S) -> np.ndarray:
        self.nfev += 1
        return residuals(
            self.runs, self.model(theta), self.noise_m, self.every, per_cycle, max_dt_s
        )

    def short_runs(self) -> list[FitRun]:
        """The runs cut to their first START_RANK_PERIODS periods (runs without a sawtooth, and
        shorter ones, whole): their per-cycle residual is the whole runs' over those periods, the
        same samples (the same strides) of the same simulation, for a fraction of its steps."""
        if self._short is None:
            self._short = [_first_periods(r, START_RANK_PERIODS) for r in self.runs]
        return self._short

    def res_many(
        self, thetas: list[np.ndarray], per_cycle: bool, max_dt_s: float
    ) -> list[np.ndarray]:
        """res_at at each theta. A model with thermal_drift simulates its runs one after another
        (each starts with the heat the last left), on one core: its points then run side by side
        on the simulation threads instead, each in one thread (the same results)."""
        if not thetas or not carries_heat(self.model(thetas[0])):
            return [self.res_at(th, per_cycle, max_dt_s) for th in thetas]
        self.nfev += len(thetas)

        def one(th: np.ndarray) -> np.ndarray:
            m = self.model(th)
            return residuals(
                self.runs, m, self.noise_m, self.every, per_cycle, max_dt_s, pooled=False
            )

        return list(_sim_pool().map(one, thetas))

    def solve(self, theta0: np.ndarray, per_cycle: bool, nfev: int, tol: float):
        cache: dict[bytes, np.ndarray] = {}

        def fun(theta: np.ndarray) -> np.ndarray:
            key = theta.tobytes()
            if key not in cache:
                cache.clear()  # least_squares asks for jac at the point it just evaluated
                cache[key] = self.res_at(theta, per_cycle)
            return cache[key]

        def jac(theta: np.ndarray) -> np.ndarray:
            # forward differences with an absolute step of H_THETA: well above the float32
            # rounding of the model, well below its scales (scipy's relative steps vanish at 0)
            jac_dt = self.jac_dt
            f0 = fun(theta) if jac_dt == MAX_DT_S else self.res_at(theta, per_cycle, jac_dt)
            points, steps = [], []
            for i in range(len(theta)):
                th = theta.copy()
                h = H_THETA if th[i] + H_THETA <= self.hi[i] else -H_THETA
                th[i] += h
                points.append(th)
                steps.append(h)
            cols = self.res_many(points, per_cycle, jac_dt)
            return np.column_stack([(c - f0) / h for c, h in zip(cols, steps)])

        return least_squares(
            fun,
            theta0,
            jac=jac,
            bounds=(self.lo, self.hi),
            x_scale=1.0,
            max_nfev=nfev,
            xtol=tol,
            ftol=tol,
        )

    def start_points(self, grid: bool) -> list[np.ndarray]:
        """Every combination of the grid values (not grid: start's own point only), with the base
        parameters both as given and nominal (an effect the base model lacks distorts its
        calibration); one set when start is at nominal (theta is 0 there)."""
        nb, lo, hi, theta0 = self.nb, self.lo, self.hi, self.theta0
        starts = []
        axes = [(i, s.grid) for i, s in enumerate(self.specs) if s.grid and grid]
        combos = list(itertools.product(*(g for _, g in axes))) if axes else [()]
        bases = {theta0[:nb].tobytes(): theta0[:nb], np.zeros(nb).tobytes(): np.zeros(nb)}
        for b in bases.values():
            for combo in combos:
                th = theta0.copy()
                th[:nb] = np.clip(b, lo[:nb] + 1e-9, hi[:nb] - 1e-9)
                for (i, _), v in zip(axes, combo):
                    th[i] = self.specs[i].theta(v)
                starts.append(th)
        return starts

    def ranks_starts(self, starts: list[np.ndarray]) -> bool:
        """Are these starts ranked on the runs' first periods before the whole runs compare them?"""
        return len(starts) > START_RANK_KEEP and not carries_heat(self.model(starts[0]))

    def first_periods_costs(self, starts: list[np.ndarray]) -> list[float]:
        """Each start's per-cycle cost over the runs' first START_RANK_PERIODS periods."""
        short = self.short_runs()
        return [
            float(np.sum(residuals(short, self.model(th), self.noise_m, self.every, True) ** 2))
            for th in starts
        ]

    def first_stage(self, max_nfev: int, grid: bool) -> tuple[np.ndarray, float]:
        """Stage 1 on the per-cycle residual, from the cheapest start point (start_points; many
        ranked on the first periods, the best START_RANK_KEEP over the whole runs). Returns the
        point and its per-cycle cost (sum of squares over the noise)."""
        starts = self.start_points(grid)
        if self.ranks_starts(starts):
            ranked = self.first_periods_costs(starts)
            starts = [
                starts[i] for i in sorted(np.argsort(ranked, kind="stable")[:START_RANK_KEEP])
            ]
        theta0 = self.theta0
        if len(starts) > 1:
            costs = [float(np.sum(r**2)) for r in self.res_many(starts, True, MAX_DT_S)]
            theta0 = starts[int(np.argmin(costs))]
        # near is enough here: stage 2 sets the digits
        res = self.solve(theta0, True, max_nfev, 1e-3)
        return res.x, float(2.0 * res.cost)

    def second_stage(self, theta0: np.ndarray, nfev: int) -> FitResult:
        """Stage 2 on the absolute position (what the validation measures), from theta0."""
        res = self.solve(theta0, False, nfev, 1e-5)
        specs, lo, hi = self.specs, self.lo, self.hi
        model = self.model(res.x)
        stderr, corr = _uncertainty(res.jac, res.fun, specs, model)
        at_bound = tuple(
            s.name
            for s, t, a, b in zip(specs, res.x, lo, hi)
            if min(t - a, b - t) < 1e-3 * max(1.0, b - a)
        )
        r = res.fun * self.noise_m
        return FitResult(
            self.free,
            model,
            model.values(),
            float(np.sqrt(np.mean(r**2))),
            self.nfev,
            stderr,
            corr,
            at_bound,
            res.jac,
            res.fun,
            specs,
        )


def second_stage_nfev(max_nfev: int) -> int:
    """The second stage's budget after a first stage of max_nfev."""
    return max(10, max_nfev // 2)


@with_one_blas_thread  # a fit may run in an executor's process, outside diagnose()
def fit(
    runs: list[FitRun],
    nominal: ActuatorParams,
    start: Model,
    free: Free,
    noise_m: float,
    max_nfev: int = 30,
    polish: bool = False,
    grid: bool = True,
) -> FitResult:
    """Least-squares fit of the free parameters on runs, from start (which also holds every value
    that is not free). A cause's parameters start where start has them, else at the catalog's
    start; scale parameters with a grid are first tried at each grid value (their cost is not
    convex), unless polish (the fit continues from start alone) or not grid (start is already
    a good point, e.g. a screened one). Two stages: the per-cycle
    residual to get near, then the absolute position (what the validation measures)."""
    p = _Problem(runs, nominal, start, free, noise_m)
    if polish:
        p.jac_dt = MAX_DT_S  # near an optimum, the simulated model's own Jacobian (JAC_MAX_DT_S)
        return p.second_stage(p.theta0, max_nfev)
    theta, _ = p.first_stage(max_nfev, grid)
    return p.second_stage(theta, second_stage_nfev(max_nfev))


@with_one_blas_thread
def first_stage(
    runs: list[FitRun],
    nominal: ActuatorParams,
    start: Model,
    free: Free,
    noise_m: float,
    max_nfev: int = 30,
    grid: bool = True,
) -> tuple[np.ndarray, float]:
    """fit()'s first stage alone: the point it reaches and its per-cycle cost, to compare starts
    (e.g. the same cause under each friction law) before paying for a second stage."""
    return _Problem(runs, nominal, start, free, noise_m).first_stage(max_nfev, grid)


@with_one_blas_thread
def first_stage_model(
    runs: list[FitRun],
    nominal: ActuatorParams,
    start: Model,
    free: Free,
    noise_m: float,
    max_nfev: int = 30,
    grid: bool = True,
) -> tuple[Model, float]:
    """first_stage()'s point as a model, and its per-cycle cost: the fitted values near their
    optimum for the price of the first stage (where their size, not the last digit, is read)."""
    p = _Problem(runs, nominal, start, free, noise_m)
    theta, cost = p.first_stage(max_nfev, grid)
    return p.model(theta), cost


@with_one_blas_thread
def per_cycle_cost(
    runs: list[FitRun], nominal: ActuatorParams, model: Model, free: Free, noise_m: float
) -> float:
    """The first stage's cost (the per-cycle residual's sum of squares over the noise) at model's
    own point: a fitted model's side of a comparison with first stages fitted elsewhere."""
    p = _Problem(runs, nominal, model, free, noise_m)
    return float(np.sum(p.res_at(p.theta0, True) ** 2))


@with_one_blas_thread
def fit_from(
    runs: list[FitRun],
    nominal: ActuatorParams,
    start: Model,
    free: Free,
    noise_m: float,
    theta: np.ndarray,
    max_nfev: int = 30,
) -> FitResult:
    """fit()'s second stage from a first stage's point (first_stage with the same start, free
    and max_nfev): together they are fit(), bit for bit, but for the result's nfev, which counts
    the second stage's simulations only."""
    return _Problem(runs, nominal, start, free, noise_m).second_stage(
        theta, second_stage_nfev(max_nfev)
    )


@with_one_blas_thread
def refit_without(
    runs: list[FitRun],
    nominal: ActuatorParams,
    start: Model,
    free: Free,
    noise_m: float,
    held: list[int],
    max_nfev: int,
) -> np.ndarray:
    """start polished without the held runs (fit's second stage from its own point, as
    fit(polish=True)), and its residual on every run's rows at the point reached
    (residuals(runs, ...) at strides(runs); run_of_row(runs) says whose). A model that carries
    heat still simulates the held runs recorded before a kept one (_predict_chain follows the
    recorded order), so each kept run starts with the heat the data's did."""
    kept = [r for i, r in enumerate(runs) if i not in held]
    p = _Problem(kept, nominal, start, free, noise_m)
    p.jac_dt = MAX_DT_S
    model = p.model(p.solve(p.theta0, False, max_nfev, 1e-5).x)
    return residuals(runs, model, noise_m, strides(runs))


@dataclass
class Evaluation:
    """A model against runs it was not fitted on."""

    rmse_m: float
    step_error: float
    rss_over_noise: float  # sum of squared residuals / noise^2
    n_samples: int
    per_run: dict[str, dict] = field(default_factory=dict)

    @property
    def mse_over_noise(self) -> float:
        return self.rss_over_noise / self.n_samples


def cycle_steps(run: FitRun, x: np.ndarray) -> np.ndarray:
    """Per-period displacement of a position record (at the period boundaries)."""
    if run.waveform is None:
        return np.zeros(0)
    k = np.arange(run.waveform.cycles + 1) * run.waveform.period_s
    xb = np.interp(k, run.t_s - run.t_s[0], x)
    return np.diff(xb)


def evaluate(runs: list[FitRun], model: Model, noise_m: float) -> Evaluation:
    rss, n, step_rel = 0.0, 0, []
    per_run = {}
    for run, x in zip(runs, predict_all(runs, model)):
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
        per_run[run.id] = {"rmse_m": float(np.sqrt(np.mean(r**2))), "rss": float(np.sum(r**2))}
    step_err = float(np.sqrt(np.mean(np.square(step_rel)))) if step_rel else 0.0
    return Evaluation(float(np.sqrt(rss / n)), step_err, rss / noise_m**2, n, per_run)
