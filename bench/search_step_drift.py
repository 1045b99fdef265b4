"""How far the model at a coarser step drifts from the diagnosis' 1 us model on a dataset's runs
(BENCHMARKS.md, "Per-cycle probes on the validation runs alone; the search at 2 us"): the RMS
difference of the predicted positions, run by run, at 2 us and at 0.5 us against 1 us, for each
friction law at the nominal parameters; and, with a thermal drift, the heat each run leaves at
each step (runs in their recorded order, each from the heat the last left).

    PYTHONPATH=hil:bench .venv/bin/python bench/search_step_drift.py null_gms 100
    PYTHONPATH=hil:bench .venv/bin/python bench/search_step_drift.py own:thermal_drift 100 \\
        --heat 55.8 0.0963
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from diagnosis_profile import fit_inputs

from stickslip.diagnosis import fit as F

STEPS_S = (0.5e-6, 1e-6, 2e-6)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("case", help="a case of diagnosis_bench.py's independent table (own:CASE: own)")
    ap.add_argument("seed", type=int)
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    ap.add_argument(
        "--heat",
        nargs=2,
        type=float,
        metavar=("COEFF_PER_J", "TAU_S"),
        help="also the heat each run leaves with this thermal drift, under LS",
    )
    a = ap.parse_args()
    ds, train, val, _ = fit_inputs(a.case, a.seed, a.rate_hz, a.data)
    runs = sorted(train + val, key=F._order)  # recorded order
    for law in ("ls", "lugre", "gms"):
        m = F.Model(ds.actuator, law=law)
        x = {dt: F.predict_all(runs, m, max_dt_s=dt) for dt in STEPS_S}
        for dt in (2e-6, 0.5e-6):
            rms = [float(np.sqrt(np.mean((p - q) ** 2))) * 1e9 for p, q in zip(x[1e-6], x[dt])]
            print(
                f"{law:6s} {dt * 1e6:g} us against 1 us, nm RMS a run: "
                + " ".join(f"{v:.1f}" for v in rms)
            )
    if a.heat:
        m = F.Model(ds.actuator, law="ls")
        fx = replace(m.effects, thermal_coeff_per_j=a.heat[0], thermal_tau_s=a.heat[1])
        m = replace(m, effects=fx, causes=("thermal_drift",))
        for dt in STEPS_S:
            heat, left = 0.0, []
            for r in runs:
                _, heat = F._predict_heat(r, m, dt, heat)
                left.append(heat)
            print(
                f"heat left at {dt * 1e6:g} us, mJ a run: "
                + " ".join(f"{1e3 * h:.3f}" for h in left)
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
