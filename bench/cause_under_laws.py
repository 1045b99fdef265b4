"""One catalog cause fitted from the nominal parameters under each friction law, beside each law's
calibration: how far the law a cause is fitted under decides whether it is found (issue 13;
BENCHMARKS.md, "Hit rates today": base_compliance seed 103 reaches 742 nm under GMS, the law the
calibration preferred, and 28.8 nm under LuGre, the generator's). Validation RMS on the runs the
diagnosis validates on, and the cause's fitted values.

    PYTHONPATH=hil:bench .venv/bin/python bench/cause_under_laws.py \
        base_compliance 103 base_compliance
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from diagnosis_profile import fit_inputs

from stickslip.diagnosis import fit as F
from stickslip.diagnosis.calibrate import calibrate
from stickslip.diagnosis.catalog import CAUSES
from stickslip.diagnosis.pipeline import FIT_NFEV


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("case", help="a case of diagnosis_bench.py's independent table (own:CASE: own)")
    ap.add_argument("seed", type=int)
    ap.add_argument("cause", choices=sorted(CAUSES))
    ap.add_argument("--laws", nargs="+", default=["ls", "lugre", "gms"])
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    a = ap.parse_args()
    ds, train, val, noise = fit_inputs(a.case, a.seed, a.rate_hz, a.data)
    for law in a.laws:
        cal, _ = calibrate(train, ds.actuator, law, noise)
        start = F.Model(ds.actuator, law=law)
        free = F.Free(cal.free.base, (a.cause,))
        f = F.fit(train, ds.actuator, start, free, noise, max_nfev=FIT_NFEV, grid=True)
        values = {
            k.split(".", 1)[1]: round(v, 4) for k, v in f.values.items() if k.startswith(a.cause)
        }
        rms_cal = F.evaluate(val, cal.model, noise).rmse_m * 1e9
        rms = F.evaluate(val, f.model, noise).rmse_m * 1e9
        print(
            f"{law:6s} calibrated {rms_cal:8.1f} nm; + {a.cause} from nominal {rms:8.1f} nm",
            values,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
