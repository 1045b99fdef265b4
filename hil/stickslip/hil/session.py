"""A HIL session as the drive electronics run it: play a sawtooth through a node (lock-step or
free-running) and record the run as a stick-slip-dataset/1 folder."""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .. import dataset as D
from ..model import ActuatorParams, Sawtooth, drive_samples, simulate
from .node import NodeSession, StepProgress, Telemetry


@dataclass
class HilRun:
    waveform: Sawtooth
    mode: str
    telemetry: Telemetry
    dt_s: float
    wall_s: float
    steps: int
    drive0_v: float
    x_rod0_m: float

    @property
    def steps_per_s(self) -> float:
        return self.steps / self.wall_s

    def table(self) -> dict[str, np.ndarray]:
        """Columns with the rest state at t = 0 first."""
        tel = self.telemetry
        return {
            "t_s": np.concatenate([[0.0], tel.step * self.dt_s]),
            "drive_v": np.concatenate([[self.drive0_v], tel.drive_v]),
            "x_m": np.concatenate([[0.0], tel.x_slider_m]),
            "x_rod_m": np.concatenate([[self.x_rod0_m], tel.x_rod_m]),
            "friction_n": np.concatenate([[0.0], tel.friction_n]),
        }

    def mean_step_m(self) -> float:
        t = self.table()
        k = np.arange(self.waveform.cycles + 1) * self.waveform.period_s
        return float(np.mean(np.diff(np.interp(k, t["t_s"], t["x_m"]))))


def node_params(client: NodeSession) -> ActuatorParams:
    """The node's actuator and friction parameters (a recorded dataset's nominal ones; its
    effects, like a real stage's, are for the diagnosis to find)."""
    names = set(ActuatorParams.__dataclass_fields__)
    values = {name: p.value for name, p in client.params().items() if name in names}
    return ActuatorParams.from_dict(values, "node parameters")


MAX_DECIMATION = 65535  # the protocol carries it as a u16 (docs/protocol.md)
# What a run may hold here: the recorded rows (7 float64 columns each, ~0.6 GB at the limit) and,
# in lock-step, the drive generated here (float32, one per step: 0.4 GB at the limit).
MAX_RUN_ROWS = 10_000_000
MAX_LOCKSTEP_STEPS = 100_000_000


def run_budget(w: Sawtooth, dt_s: float, mode: str, decimation: int) -> int:
    """The steps of a run of w at the node's step dt_s, after checking the request fits the
    protocol and this machine's memory (ValueError naming the field otherwise): a run's cost is
    known from the request, before anything is allocated or sent."""
    if not 1 <= decimation <= MAX_DECIMATION:
        raise ValueError(f"decimation: must be in [1, {MAX_DECIMATION}], got {decimation}")
    steps = int(round(w.duration_s / dt_s))
    rows = steps // decimation + 1
    if rows > MAX_RUN_ROWS:
        raise ValueError(
            f"the run is {steps} steps ({w.cycles} periods of {w.period_s:g} s at {dt_s:g} s): "
            f"{rows} rows at decimation {decimation}, above the {MAX_RUN_ROWS} a run may record; "
            f"raise --decimation to at least {-(-steps // (MAX_RUN_ROWS - 1))} or shorten it"
        )
    if mode == "lockstep" and steps > MAX_LOCKSTEP_STEPS:
        raise ValueError(
            f"the run is {steps} steps: a lock-step run sends at most {MAX_LOCKSTEP_STEPS} drive "
            "samples; use --mode free, or fewer or faster periods"
        )
    return steps


def lockstep_drive(w: Sawtooth, dt_s: float, steps: int, variant: str = "f32") -> np.ndarray:
    """The drive at t = 0 and after each of `steps` steps, float32. For a fixed-point node
    (variant "q") the q player's Q16.16 samples, exact in float32 below 256 V, so the node's
    conversion back to Q16.16 gives the q model's own drive."""
    if variant != "q":
        return drive_samples(w, dt_s, steps)
    # dt_s as the node reports it (dt_q40 x 2^-40, 1.0000003 us for Table I's 1 us): the q
    # converter gives the same dt_q40 back
    hold_s = max(0, steps - int(round(w.duration_s / dt_s))) * dt_s
    drive = simulate(w, variant="q", dt_s=dt_s, hold_s=hold_s).drive_v[: steps + 1]
    if len(drive) != steps + 1:
        raise ValueError(f"q drive: {len(drive) - 1} steps, not {steps}")
    return drive.astype(np.float32)


def play(
    client: NodeSession,
    w: Sawtooth,
    mode: str = "lockstep",
    decimation: int = 1,
    paced: int = 0,
    progress: StepProgress = None,
) -> HilRun:
    """Play w through the node. lockstep: the drive is generated here (the sawtooth of the C
    library, one sample per step: the float32 player, or the q player for a fixed-point node) and
    sent in blocks; free: the node plays it itself. progress (if given) is told the steps done
    as the run goes."""
    dt = client.info.dt_s
    steps = run_budget(w, dt, mode, decimation)
    if mode == "lockstep":
        drive = lockstep_drive(w, dt, steps, client.info.variant)
        block = max(decimation, (40 // decimation) * decimation)
        client.reset(float(drive[0]))
        t0 = time.perf_counter()
        tel = client.lockstep(
            drive[1 : steps + 1], block=block, decimation=decimation, progress=progress
        )
    elif mode == "free":
        client.load_waveform(w)
        t0 = time.perf_counter()
        tel = client.run(steps, decimation, paced, progress=progress)
    else:
        raise ValueError(f"mode must be lockstep or free, got {mode!r}")
    wall = time.perf_counter() - t0
    gain = client.get("piezo_gain_m_per_v")
    drive0 = float(np.float32(w.offset_v))
    return HilRun(w, mode, tel, dt, wall, steps, drive0, gain * drive0)


def record(run: HilRun, params: ActuatorParams, out: str | Path, run_id: str = "hil") -> Path:
    t = run.table()
    r = D.Run(
        run_id,
        Path(out) / f"{run_id}.csv",
        t["t_s"],
        t["drive_v"],
        t["x_m"],
        run.waveform,
        {"x_rod_m": t["x_rod_m"], "friction_n": t["friction_n"]},
    )
    desc = f"HIL {run.mode} run through a stickslip node, {run.steps} steps of {run.dt_s:g} s"
    return D.write(out, params, [r], desc)


def summary(run: HilRun, client: NodeSession) -> dict:
    return {
        "mode": run.mode,
        "url": client.url,
        "node": asdict(client.info),
        "waveform": run.waveform.to_dict(),
        "steps": run.steps,
        "rows": len(run.telemetry.step),
        "wall_s": run.wall_s,
        "steps_per_s": run.steps_per_s,
        "mean_step_per_cycle_m": run.mean_step_m(),
        # a paced free run's steps that ended after their deadline (None: not reported)
        "deadline_misses": run.telemetry.deadline_misses,
        "link": asdict(client.stats),
    }
