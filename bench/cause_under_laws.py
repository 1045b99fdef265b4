"""One catalog cause fitted under each friction law, beside each law's calibration: how far the law
a cause is fitted under decides whether it is found (issue 13; BENCHMARKS.md, "Hit rates today":
base_compliance seed 103 reaches 742 nm under GMS, the law the calibration preferred, and 28.8 nm
under LuGre, the generator's), and whether the cause's values agree from law to law (a property
of the actuator does not depend on the law the contact is read with; BENCHMARKS.md, "A short
first stage"). Validation RMS on the runs the diagnosis validates on, the share of the law's
calibrated error the cause removes, and the cause's fitted values.

    PYTHONPATH=hil:bench .venv/bin/python bench/cause_under_laws.py \
        base_compliance 103 base_compliance
    PYTHONPATH=hil:bench .venv/bin/python bench/cause_under_laws.py \
        null_ls_b 101 piezo_hysteresis --from calibration
    PYTHONPATH=hil:bench .venv/bin/python bench/cause_under_laws.py \
        thermal_drift 100 thermal_drift --from both
    PYTHONPATH=hil:bench .venv/bin/python bench/cause_under_laws.py \
        null_ls_b 102 piezo_hysteresis --from calibration --first-stage-only

The last line gives each of the cause's values' spread over the laws (largest over smallest
magnitude; "signs differ" when they do): a physical effect's should not depend on the law.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from diagnosis_profile import fit_inputs

from stickslip.diagnosis import fit as F
from stickslip.diagnosis.calibrate import calibrate
from stickslip.diagnosis.catalog import CAUSES
from stickslip.diagnosis.guards import share_removed
from stickslip.diagnosis.screen import probe_points, probe_residual
from stickslip.diagnosis.session import FIT_NFEV


def fit_under(a, ds, train, val, noise, cal, law: str, origin: str):
    """The cause fitted under law from origin's base parameters: (its model, first-stage cost)."""
    start = F.Model(ds.actuator, law=law) if origin == "nominal" else cal.model
    free = F.Free(cal.free.base, (a.cause,))
    grid = a.start == "grid"
    if not grid:
        pts = probe_points(a.cause)
        val_rows = [
            float(np.sum(probe_residual(val, start, a.cause, v, noise, True) ** 2)) for v in pts
        ]
        best = pts[int(np.argmin(val_rows))]
        start = replace(start, effects=replace(start.effects, **best))
    # the fit in its two stages (together fit(), bit for bit): the first stage's per-cycle
    # cost is what a choice of law before the second stage would see
    if a.first_stage_only:
        m, cost1 = F.first_stage_model(train, ds.actuator, start, free, noise, FIT_NFEV, grid)
        return m, cost1
    theta, cost1 = F.first_stage(train, ds.actuator, start, free, noise, FIT_NFEV, grid=grid)
    f = F.fit_from(train, ds.actuator, start, free, noise, theta, FIT_NFEV)
    return f.model, cost1


def spread(values: list[float]) -> str:
    """Largest over smallest magnitude, or why there is none."""
    if all(v > 0 for v in values) or all(v < 0 for v in values):
        mags = [abs(v) for v in values]
        return f"{max(mags) / min(mags):.2f} x"
    return "signs differ"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("case", help="a case of diagnosis_bench.py's independent table (own:CASE: own)")
    ap.add_argument("seed", type=int)
    ap.add_argument("cause", choices=sorted(CAUSES))
    ap.add_argument("--laws", nargs="+", default=["ls", "lugre", "gms"])
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    ap.add_argument(
        "--start",
        choices=("grid", "probe"),
        default="grid",
        help="grid: the best of the cause's grid (fit's own); probe: the screen's best probe of "
        "the cause at nominal under the law (per-cycle error on the validation runs)",
    )
    ap.add_argument(
        "--from",
        dest="origin",
        choices=("nominal", "calibration", "both"),
        default="nominal",
        help="the base parameters the fit starts from: nominal (as the diagnosis fits a base "
        "compliance on its first round), the law's calibration (as it fits the other causes), "
        "or both, keeping the fit with the smaller validation error",
    )
    ap.add_argument(
        "--first-stage-only",
        action="store_true",
        help="stop after the first stage, as the diagnosis' law-dependence guard does "
        "(pipeline.LAW_SENSITIVE)",
    )
    a = ap.parse_args()
    ds, train, val, noise = fit_inputs(a.case, a.seed, a.rate_hz, a.data)
    origins = ["nominal", "calibration"] if a.origin == "both" else [a.origin]
    per_law: dict[str, dict[str, float]] = {}
    for law in a.laws:
        cal, _ = calibrate(train, ds.actuator, law, noise)
        ev_cal = F.evaluate(val, cal.model, noise)
        fits = []
        for origin in origins:
            m, cost1 = fit_under(a, ds, train, val, noise, cal, law, origin)
            fits.append((F.evaluate(val, m, noise), origin, m, cost1))
        ev, origin, m, cost1 = min(fits, key=lambda x: x[0].mse_over_noise)
        values = {
            k.split(".", 1)[1]: float(f"{v:.4g}")
            for k, v in m.values().items()
            if k.startswith(a.cause)
        }
        per_law[law] = values
        share = share_removed(ev_cal.mse_over_noise, ev.mse_over_noise)
        print(
            f"{law:6s} calibrated {ev_cal.rmse_m * 1e9:8.1f} nm; + {a.cause} from {origin}: "
            f"first stage's per-cycle cost {cost1:.4g}, validation {ev.rmse_m * 1e9:8.1f} nm "
            f"({100 * share:.0f} % of the calibration's error above the noise)",
            values,
        )
    names = next(iter(per_law.values()), {}).keys()
    print("spread over the laws:", {n: spread([v[n] for v in per_law.values()]) for n in names})
    return 0


if __name__ == "__main__":
    sys.exit(main())
