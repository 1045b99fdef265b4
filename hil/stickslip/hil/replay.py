"""Replay a dataset against a model running on a node (issue 16): each run's sawtooth played by
the node's own waveform player in a free run (a run without a waveform block: its recorded drive
in lock-step), the node's slider positions against the measured ones, the error computed as the
diagnosis computes its validation error (stickslip.diagnosis.fit.evaluate): at the fit's samples
(the measured positions anti-alias filtered to at most 50 kS/s), with each run's start placed by
least squares (fit.placed). A float32 host node steps the same C model with the same drive as the
batch simulation the fits ran, the corners inside a step included, from the same start of the
slider (RESET's x0_m): the figures agree to 1e-5 relative (tests/python/test_replay.py). In
lock-step, one drive sample a step, a 300 Hz sawtooth's peak inside a step was cut to its chord:
5.16 nm against the diagnosis' 2.0 nm on the example's 300 Hz run."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import dataset as D
from ..diagnosis.fit import FitRun, placed, prepare_all, sim_step_s, slider_start_m
from ..model import drive_samples
from ..model_file import ModelFile
from . import protocol as P
from .node import HilError, NodeSession, StepProgress


@dataclass
class ReplayedRun:
    id: str
    rmse_m: float
    rows: int
    rss_m2: float  # sum of squared residuals (the aggregate's share)
    t_s: np.ndarray  # the fit's sample times
    measured_m: np.ndarray  # the measured positions at them (anti-alias filtered)
    node_m: np.ndarray  # what the node's sensor reported, placed where the run started


def _drive(run: FitRun, dt_s: float, steps: int) -> np.ndarray:
    """The drive at t = 0 and after each step, as the batch simulation of the fits feeds it."""
    if run.waveform is not None:
        return drive_samples(run.waveform, dt_s, steps)
    # a run without a waveform block: its recorded drive, linearly interpolated (the C player's
    # rule for sampled drive), held after the end
    t = np.arange(steps + 1) * dt_s
    src_t = np.arange(len(run.drive_v)) * run.drive_dt_s
    return np.interp(t, src_t, run.drive_v).astype(np.float32)


def replay_run(
    client: NodeSession, run: FitRun, model: ModelFile, progress: StepProgress = None
) -> ReplayedRun:
    """One run through the node (its waveform in a free run, else in lock-step), and its error at
    the fit's samples."""
    dt, dec = sim_step_s(run)
    if not math.isclose(dt, client.info.dt_s, rel_tol=1e-6):
        raise HilError(
            f"run {run.id}: the fit samples every {run.dt_s:g} s, which needs a {dt:g} s step; "
            f"the node steps at {client.info.dt_s:g} s"
        )
    rows_per_block = min(P.MAX_ROWS, 255 // dec)
    if rows_per_block < 1:
        raise HilError(f"run {run.id}: {dec} steps per sample, more than a DRIVE_BLOCK carries")
    n = len(run.t_s) - 1
    # the slider starts where the fit's simulation started it: what position-dependent friction sees
    x0 = float(np.float32(slider_start_m(run, model.effects)))
    if run.waveform is not None:
        # the node's own player, as the batch simulation: it gives each step the corners of the
        # drive inside it (a 300 Hz peak falls inside a step), which one sample a step cannot
        client.load_waveform(run.waveform)
        client.reset(float(drive_samples(run.waveform, dt, 0)[0]), x0)
        tel = client.run(n * dec, decimation=dec, progress=progress)
    else:
        drive = _drive(run, dt, n * dec)
        client.reset(float(drive[0]), x0)
        tel = client.lockstep(
            drive[1:], block=dec * rows_per_block, decimation=dec, progress=progress
        )
    x = np.concatenate([[x0], tel.x_slider_m])[: n + 1]
    x = x * (1.0 + model.effects.sensor_scale_error)  # what the sensor reports (x_meas_m)
    xn = placed(run, x)
    r = xn - run.x_m
    rss = float(np.sum(r**2))
    return ReplayedRun(run.id, float(np.sqrt(rss / len(r))), len(r), rss, run.t_s, run.x_m, xn)


def replay(
    client: NodeSession,
    ds: D.Dataset,
    model: ModelFile,
    say=lambda msg: None,
    progress: StepProgress = None,
    only: list[str] | None = None,
    traces: list[ReplayedRun] | None = None,
) -> dict:
    """Load model into the node, replay the runs of ds (those named in `only`, when given; the
    word "validation" stands for the model's validation runs), and return the figures
    ({"model": ..., "runs": [{"id", "rmse_m", "rows"}], "validation_rmse_m", ...}). traces, when
    given, gets every replayed run with its positions (for replay_report)."""
    val_ids = model.source.get("validation_runs") or []
    runs = prepare_all(ds.runs)  # the stroke over every run, as the diagnosis saw it
    if only:
        wanted = {i for o in only for i in (val_ids if o == "validation" else [o])}
        unknown = sorted(wanted - {r.id for r in runs})
        if unknown or not wanted:
            raise HilError(
                f"runs {unknown or only} are not in {ds.path} (it has {[r.id for r in runs]})"
            )
        runs = [r for r in runs if r.id in wanted]
    client.load_model(model)
    done: list[ReplayedRun] = []
    for run in runs:
        say(f"replaying {run.id}")
        done.append(replay_run(client, run, model, progress))
    if traces is not None:
        traces.extend(done)
    val = [r for r in done if r.id in val_ids]

    def rms(rs: list[ReplayedRun]) -> float | None:
        return math.sqrt(sum(r.rss_m2 for r in rs) / sum(r.rows for r in rs)) if rs else None

    return {
        "model": {"law": model.law, "causes": list(model.causes), "source": model.source},
        "node": {"model": client.info.model, "variant": client.info.variant, "url": client.url},
        "runs": [{"id": r.id, "rmse_m": r.rmse_m, "rows": r.rows} for r in done],
        "rmse_m": rms(done),
        "validation_rmse_m": rms(val),
        "diagnosis_validation_rmse_m": model.source.get("validation_rmse_m"),
    }
