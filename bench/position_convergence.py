"""What the diagnosis fits, against the model's step: the slider's position on the 20 us fit
samples (the 13-run design's 50 kS/s), each run's mean offset removed as the diagnosis places the
slider's start, RMS against the same core at a reference step (BENCHMARKS.md, "The GMS law at the
diagnosis' step"). Six of the design's drives at 15 us falls, 20 cycles: 100 Hz forward, 300 Hz
reversed, 500 Hz forward, 1 000 Hz reversed, 2 000 Hz forward at 100 V, 500 Hz forward at 50 V.
Each step must divide the 20 us sample interval (to 0.1 %: 1.4286 us is taken as 20 / 14).

    PYTHONPATH=hil .venv/bin/python bench/position_convergence.py [--models ls,lugre,gms]
        [--ref-us 0.125] [--steps-us 0.25,0.5,1]
"""

from __future__ import annotations

import argparse

import numpy as np

from stickslip.model import Sawtooth, simulate

SAMPLE_S = 20e-6
DRIVES = [
    (100, 100, 1),
    (300, 100, -1),
    (500, 100, 1),
    (1000, 100, -1),
    (2000, 100, 1),
    (500, 50, 1),
]


def positions(model: str, f_hz: float, amp_v: float, direction: int, dt_s: float) -> np.ndarray:
    dec = round(SAMPLE_S / dt_s)
    if abs(dec * dt_s - SAMPLE_S) > 1e-3 * SAMPLE_S:  # 1.4286 is 20 / 14
        raise SystemExit(f"a step of {dt_s * 1e6:g} us does not divide the 20 us samples")
    w = Sawtooth(float(f_hz), float(amp_v), 0.0, 1.0 - 15e-6 * f_hz, direction, 20)
    return simulate(w, model=model, dt_s=SAMPLE_S / dec, decimation=dec).x_slider_m


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", default="ls,lugre,gms")
    ap.add_argument("--ref-us", type=float, default=0.125)
    ap.add_argument("--steps-us", default="0.25,0.5,1")
    a = ap.parse_args()
    for model in a.models.split(","):
        refs = [positions(model, f, v, d, a.ref_us * 1e-6) for f, v, d in DRIVES]
        for dt_us in (float(x) for x in a.steps_us.split(",")):
            rms = []
            for (f, v, d), ref in zip(DRIVES, refs):
                x = positions(model, f, v, d, dt_us * 1e-6)
                n = min(len(x), len(ref))
                e = x[:n] - ref[:n]
                rms.append(float(np.sqrt(np.mean((e - e.mean()) ** 2))))
            print(
                f"{model} at {dt_us:g} us against {a.ref_us:g} us: position RMS median "
                f"{np.median(rms) * 1e9:.2f} nm, worst {max(rms) * 1e9:.2f} nm",
                flush=True,
            )


if __name__ == "__main__":
    main()
