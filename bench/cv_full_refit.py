"""Where the cross-validation refits a harmed family in full: for each check with a family the
cause harms to first order, every family's first-order figures and, for the refitted ones, the
full refits' (noise variances a sample; docs/diagnosis.md step 8, BENCHMARKS.md "A harmed family
refitted in full").

    PYTHONPATH=hil:bench .venv/bin/python bench/cv_full_refit.py base_compliance_on_gms 133 \
        --data DIR

CASE and SEED as in diagnosis_profile.py (the independent table's cases, generated into --data
when missing).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from diagnosis_profile import dataset

from stickslip.diagnosis import pipeline as PL
from stickslip.diagnosis import session as SE
from stickslip.diagnosis.guards import fold_rss


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("seed", type=int)
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    a = ap.parse_args()
    checked = SE.Session.cross_validate

    def logged(self, v, without, with_):
        checked(self, v, without, with_)
        if not any(f.refitted for f in v.folds):
            return
        la, lb = (self.assembled(c, self.linearization(c)) for c in (without, with_))
        print(
            f"{'+'.join(with_.causes) or with_.law} ({with_.law}) against "
            f"{'+'.join(without.causes) or without.law}: {'; '.join(v.reasons) or 'carries over'}"
        )
        for f, (_, idx) in zip(v.folds, self.families):
            ra, n = fold_rss(la, idx)
            rb, _ = fold_rss(lb, idx)
            row = f"  {f.family:8s} first order {ra / n:10.4g} without, {rb / n:10.4g} with"
            if f.refitted:
                row += f" | in full {f.rss_without / n:10.4g} without, {f.rss_with / n:10.4g} with"
            print(row, flush=True)

    SE.Session.cross_validate = logged
    d = PL.diagnose(dataset(a.case, a.seed, a.rate_hz, a.data))
    print(f"causes {d.causes}, unexplained {d.unexplained}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
