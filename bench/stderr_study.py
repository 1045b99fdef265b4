"""How far the uncertainty block's standard errors depend on the Jacobian they come from: one law
calibrated on a dataset, then the relative standard errors at that optimum from forward
differences simulated at 1 and 2 us, with steps of 1e-3 and 3e-3 in the fit coordinates (the
diagnosis uses 2 us and 1e-3). Figures in docs/diagnosis.md, section 5.

    PYTHONPATH=hil:bench .venv/bin/python bench/stderr_study.py amplifier_slew_limit 100 lugre
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from diagnosis_profile import fit_inputs

from stickslip.diagnosis import fit as F
from stickslip.diagnosis.calibrate import calibrate


def relative_stderr(f: F.FitResult, jac: np.ndarray, fun: np.ndarray) -> dict[str, float]:
    se, _ = F._uncertainty(jac, fun, f.specs, f.model)
    return {s.name: F.rel_stderr(s, F._value_of(f.model, s), se[s.name]) for s in f.specs}


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("seed", type=int)
    ap.add_argument("law")
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    a = ap.parse_args()
    ds, train, _, noise = fit_inputs(a.case, a.seed, a.rate_hz, a.data)
    f, held = calibrate(train, ds.actuator, a.law, noise)
    print(f"{a.law} calibrated: {f.train_rms_m * 1e9:.1f} nm on the training runs, held {held}")
    every = F.strides(train)
    theta = F.theta_of(f.model, f.specs)
    hi = np.array([s.bounds()[1] for s in f.specs])
    fun = F.residuals(train, f.model, noise, every, False, F.MAX_DT_S)  # chi-square at 1 us
    print("relative standard errors:", ", ".join(s.name for s in f.specs))
    for dt in (2e-6, 1e-6):
        for h in (1e-3, 3e-3):
            f0 = F.residuals(train, f.model, noise, every, False, dt)
            cols = []
            for i in range(len(theta)):
                th = theta.copy()
                step = h if th[i] + h <= hi[i] else -h
                th[i] += step
                m = F.build(f.model, f.free, th, f.specs)
                cols.append((F.residuals(train, m, noise, every, False, dt) - f0) / step)
            rel = relative_stderr(f, np.column_stack(cols), fun)
            print(f"  {dt * 1e6:g} us, step {h:g}: " + ", ".join(f"{v:.3g}" for v in rel.values()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
