"""A one-parameter cause probed at nominal as the screen probes it (screen.probe_residual,
per-cycle residual on the validation runs), at given values, against the calibrated law's own
per-cycle cost (BENCHMARKS.md, "Held-out seeds": how narrow a slew limit's basin is).

    PYTHONPATH=hil:bench .venv/bin/python bench/nominal_probe_scan.py amplifier_slew_limit 106 \\
        lugre amplifier_slew_limit 1.2e6 1.3e6 1.345e6 1.4e6 1.458e6 1.5e6 1.6e6
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from diagnosis_profile import fit_inputs

from stickslip.diagnosis import calibrate as CA
from stickslip.diagnosis import fit as F
from stickslip.diagnosis.catalog import CAUSE_PARAMS
from stickslip.diagnosis.screen import probe_residual


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("seed", type=int)
    ap.add_argument("law")
    ap.add_argument("cause", choices=[c for c, ps in CAUSE_PARAMS.items() if len(ps) == 1])
    ap.add_argument("values", nargs="+", type=float)
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    a = ap.parse_args()
    ds, train, val, noise = fit_inputs(a.case, a.seed, a.rate_hz, a.data)
    f, _ = CA.calibrate(train, ds.actuator, a.law, noise)
    parent = float(np.sum(probe_residual(val, f.model, None, {}, noise, True) ** 2))
    print(f"{a.law} calibrated: per-cycle cost {parent:.4g}")
    nominal = F.Model(ds.actuator, law=a.law)
    (spec,) = CAUSE_PARAMS[a.cause]
    for v in a.values:
        c = float(np.sum(probe_residual(val, nominal, a.cause, {spec.name: v}, noise, True) ** 2))
        print(f"  at nominal, {spec.name} = {v:.4g}: {c:.4g} ({c / parent:.3g} x the calibrated)")


if __name__ == "__main__":
    main()
