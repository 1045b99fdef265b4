"""Closed-loop positioning as a stick-slip drive does it, against a node in lock-step: coarse
stick-slip periods toward the target, then fine positioning within one piezo stroke (the slider
sticks to the rod while the voltage changes slowly), both on the slider-position feedback."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..model import Sawtooth, drive_samples
from .node import NodeSession


@dataclass
class PositioningResult:
    target_m: float
    final_error_m: float
    settle_time_s: float | None  # model time until the error stayed within tolerance
    coarse_periods: int
    steps: int
    t_s: np.ndarray
    x_m: np.ndarray
    drive_v: np.ndarray

    def summary(self) -> dict:
        return {
            "target_m": self.target_m,
            "final_error_m": self.final_error_m,
            "settle_time_s": self.settle_time_s,
            "coarse_periods": self.coarse_periods,
            "model_time_s": float(self.t_s[-1]),
        }


def position(
    client: NodeSession,
    target_m: float,
    tolerance_m: float = 5e-9,
    stroke_v: float = 100.0,
    frequency_hz: float = 500.0,
    max_time_s: float = 0.2,
    block: int = 233,
    max_slew_v_per_s: float = 2e4,
    gain_per_s: float = 500.0,
    hold_s: float = 2e-3,
) -> PositioningResult:
    """Drive the slider of the node behind `client` (a NodeSession: serial or CAN) to target_m
    (relative to where it is at the start). Coarse: whole sawtooth periods (forward or backward)
    until the target lies inside the piezo stroke ahead of the slider, with a margin. Fine: the
    voltage follows dV/dt = gain * error / piezo_gain, slew-limited so the slider sticks, updated
    once per `block` steps (one period of the slider's contact ringing, 233 us with Table I)."""
    dt = client.info.dt_s
    piezo_gain = client.get("piezo_gain_m_per_v")
    stroke_m = stroke_v * piezo_gain
    client.reset(0.0)
    ts, xs, vs = [0.0], [0.0], [0.0]
    x, v, step = 0.0, 0.0, 0

    def play(drive: np.ndarray) -> None:
        nonlocal x, v, step
        tel = client.lockstep(drive, block=min(block, 40))
        ts.extend(tel.step * dt)
        xs.extend(tel.x_slider_m)
        vs.extend(tel.drive_v)
        # the slider rings on its contact (4.3 kHz with Table I): read its position as the mean
        # over the block, one ringing period long, so the loop does not chase the ringing
        x, v, step = float(np.mean(tel.x_slider_m)), float(tel.drive_v[-1]), int(tel.step[-1])

    coarse = 0
    margin = 0.25 * stroke_m
    while step * dt < max_time_s:
        err = target_m - x
        if margin <= err <= stroke_m - margin:
            break
        # one period of the paper's drive shape (its rise fraction) at this stroke and rate
        w = replace(
            Sawtooth(),
            frequency_hz=frequency_hz,
            amplitude_v=stroke_v,
            offset_v=0.0,
            direction=1 if err > 0 else -1,
            cycles=1,
        )
        play(drive_samples(w, dt, int(round(w.period_s / dt)))[1:])
        coarse += 1
    # let the contact ring down before the fine loop reads the position
    play(np.zeros(int(round(hold_s / dt)), np.float32))
    settled_at = None
    dv_max = max_slew_v_per_s * dt * block
    while step * dt < max_time_s:
        err = target_m - x
        if abs(err) <= tolerance_m:
            settled_at = settled_at if settled_at is not None else step * dt
        else:
            settled_at = None
        if settled_at is not None and step * dt - settled_at >= hold_s:
            break
        dv = float(np.clip(gain_per_s * err / piezo_gain * dt * block, -dv_max, dv_max))
        target_v = float(np.clip(v + dv, 0.0, stroke_v))
        play(np.linspace(v, target_v, block + 1, dtype=np.float32)[1:])
    return PositioningResult(
        target_m, target_m - x, settled_at, coarse, step, np.array(ts), np.array(xs), np.array(vs)
    )
