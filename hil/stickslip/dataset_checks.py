"""Cross-checks of a run's metadata against the data it describes (issue 15): contradictions are
errors (DatasetError, naming the file and the field), suspicions are warnings (returned as text,
printed on stderr and in the diagnosis report).

- the `waveform` block against the `drive_v` column: amplitude, frequency, direction, offset;
- the positions against the piezo's stroke: a slider that moves 10 x more than its periods could
  move it, or 1000 x less than the stroke it follows while it sticks, is a likely unit error;
- without a waveform block, the sample rate against the fast edge: the drive between samples
  is interpolated, so an edge shorter than a sample interval cannot be simulated."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from .model import ActuatorParams, Sawtooth

# The drive_v column is the drive as commanded, so away from the edges it equals the waveform to
# the recording's resolution. Its median absolute difference from the waveform may be at most
# this share of the amplitude (plus DRIVE_ATOL_V): a sample on a fast edge may fall a fraction of
# an interval off and differ by up to the whole amplitude, so the median, not the RMS, decides.
DRIVE_RTOL = 0.05
DRIVE_ATOL_V = 0.1
# A slider moves at most about one stroke per period; over this many times (periods + 1) strokes
# the positions are likely not in metres (mm give 1000 x)...
TRAVEL_OVER_STROKE_MAX = 10.0
# ...and while it sticks it follows the piezo over its stroke: under this share of one stroke of
# travel in a whole run, likely not metres either.
TRAVEL_OVER_STROKE_MIN = 1e-3
# Without a waveform block, a drive that jumps by more than this share of its range between two
# samples has an edge the sampling does not resolve.
MAX_JUMP_SHARE = 0.5


def sawtooth_at(w: Sawtooth, t_s: np.ndarray) -> np.ndarray:
    """The waveform's voltage at times t_s (numpy, not the C player: an independent reading of
    the data format's definition), the offset after the last period."""
    phase = np.mod(t_s, w.period_s) / w.period_s
    if w.direction < 0:
        phase = 1.0 - phase
    r = w.rise_fraction
    up = np.where(phase < r, phase / r, (1.0 - phase) / (1.0 - r))
    v = w.offset_v + w.amplitude_v * up
    return np.where(t_s < w.duration_s, v, w.offset_v)


def _drive_mismatch(w: Sawtooth, t: np.ndarray, drive: np.ndarray) -> float:
    inside = t < w.duration_s
    return float(np.median(np.abs(drive[inside] - sawtooth_at(w, t[inside]))))


def _explain(w: Sawtooth, t: np.ndarray, drive: np.ndarray, tol: float) -> str:
    """Which field of the block the column contradicts: the first single change that fits."""
    tries = [
        ("amplitude_v", replace(w, amplitude_v=-w.amplitude_v), -w.amplitude_v),
        ("direction", replace(w, direction=-w.direction), -w.direction),
        ("offset_v", replace(w, offset_v=float(np.min(drive))), float(np.min(drive))),
    ]
    for k in (0.5, 2.0, 0.25, 4.0, 0.1, 10.0):
        f = w.frequency_hz * k
        tries.append(("frequency_hz", replace(w, frequency_hz=f), f))
    for name, cand, value in tries:
        if _drive_mismatch(cand, t, drive) <= tol:
            return f"; the column fits {name} = {value:g}, the block says {getattr(w, name):g}"
    span = float(np.ptp(drive))
    return f"; the column spans {span:g} V, the block's amplitude is {w.amplitude_v:g} V"


def check_run(
    file: Path,
    where: str,
    t_s: np.ndarray,
    drive_v: np.ndarray,
    x_m: np.ndarray,
    w: Sawtooth | None,
    actuator: ActuatorParams,
) -> list[str]:
    """Check one run; raise DatasetError on a contradiction, return the warnings."""
    from .dataset import DatasetError

    t = t_s - t_s[0]
    warnings: list[str] = []
    if w is not None:
        tol = DRIVE_RTOL * abs(w.amplitude_v) + DRIVE_ATOL_V
        miss = _drive_mismatch(w, t, drive_v)
        if miss > tol:
            raise DatasetError(
                file,
                f"drive_v contradicts {where}.waveform: median difference {miss:.3g} V, more "
                f"than {tol:.3g} V" + _explain(w, t, drive_v, tol),
                column="drive_v",
            )
        stroke = actuator.piezo_gain_m_per_v * abs(w.amplitude_v)
        periods = w.cycles
    else:
        span = float(np.ptp(drive_v))
        jump = float(np.max(np.abs(np.diff(drive_v)))) if len(drive_v) > 1 else 0.0
        if span > 0 and jump > MAX_JUMP_SHARE * span:
            raise DatasetError(
                file,
                f"drive_v jumps by {jump:.3g} V between two samples ({100 * jump / span:.0f} % "
                f"of its range): the fast edge is not resolved at {1 / (t[1] - t[0]):.4g} S/s, "
                "so the drive between samples is unknown; record faster, or give the run a "
                "waveform block",
                column="drive_v",
            )
        stroke = actuator.piezo_gain_m_per_v * span
        periods = 1
    travel = float(np.ptp(x_m))
    if stroke > 0:
        if travel > TRAVEL_OVER_STROKE_MAX * (periods + 1) * stroke:
            warnings.append(
                f"{file}: x_m spans {travel:.3g}, {travel / stroke:.3g} x the {stroke:.3g} m "
                f"stroke over {periods} periods, more than a slider can move: are the "
                "positions in metres?"
            )
        elif travel < TRAVEL_OVER_STROKE_MIN * stroke:
            warnings.append(
                f"{file}: x_m spans {travel:.3g}, {travel / stroke:.2g} x the {stroke:.3g} m "
                "stroke the slider follows while it sticks: are the positions in metres?"
            )
    return warnings
