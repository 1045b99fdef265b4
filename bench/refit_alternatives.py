"""What else a base compliance's gain could be (docs/diagnosis.md, known limits): a law's
calibration on a dataset's training runs, then from its point (a) the same fit continued, nothing
freed, (b) each named actuator parameter freed beside the law's (fit range /3 to x3), (c) a catalog
cause; each validated on the held-out runs.

    PYTHONPATH=hil:bench .venv/bin/python bench/refit_alternatives.py null_gms 101 lugre \\
        piezo_stiffness_n_per_m rod_mass_kg base_compliance
"""

from __future__ import annotations

import argparse
from pathlib import Path

from diagnosis_profile import fit_inputs

from stickslip.diagnosis import calibrate as CA
from stickslip.diagnosis import catalog as CAT
from stickslip.diagnosis import fit as F


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("seed", type=int)
    ap.add_argument("law")
    ap.add_argument("extra", nargs="*", help="ActuatorParams fields or catalog causes")
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    a = ap.parse_args()
    ds, train, val, noise = fit_inputs(a.case, a.seed, a.rate_hz, a.data)
    nom = ds.actuator
    f, held = CA.calibrate(train, nom, a.law, noise)
    names = tuple(n for n in CA.LAW_PARAMS[a.law] if n not in held)

    def say(what: str, m: F.Model) -> None:
        vals = " ".join(f"{k}={v:.4g}" for k, v in m.values().items())
        k = m.params.piezo_stiffness_n_per_m
        rmse = F.evaluate(val, m, noise).rmse_m * 1e9
        print(f"{what:28s} {rmse:7.1f} nm  {vals} k={k:.4g}", flush=True)

    say(f"{a.law} calibrated", f.model)
    say("continued", F.fit(train, nom, f.model, F.Free(names, ()), noise, 20, grid=False).model)
    for x in a.extra:
        if x in CAT.CAUSE_PARAMS:
            g = F.fit(train, nom, f.model, F.Free(names, (x,)), noise, 20)
        else:
            CAT.BASE_FACTOR.setdefault(x, 3.0)
            g = F.fit(train, nom, f.model, F.Free((*names, x), ()), noise, 20, grid=False)
        say(f"+ {x}", g.model)


if __name__ == "__main__":
    main()
