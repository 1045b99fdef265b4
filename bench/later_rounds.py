"""What the diagnosis' later rounds and law re-choices see (issue 13; BENCHMARKS.md, "Fits a later
round could not use"): for each dataset folder, one diagnosis, and one JSON line with

- `screens`: every screen on a model that has causes already (a round after the first): the
  parent's causes and validation error over the sensor noise, and per cause its predicted share
  of the parent's error above the noise (screen.predicted_share), whether it was fitted;
- `judged`: every candidate of those rounds put to the guards: its fitted share and verdict;
- `rechoose`: every law chosen again with a cause kept: the chosen model's per-cycle cost, and per
  other law it tried its first stage's cost over that (the ratio LAW_RECHOSEN_RATIO stops at),
  and whether the law changed.

    PYTHONPATH=hil:bench .venv/bin/python bench/later_rounds.py DATASET_DIR [DATASET_DIR ...]

With --first-round the first round's screen (on the calibrated law, no cause yet) is logged too.

The diagnoses' answers are the pipeline's own; the first-stage costs of a law the re-choice
stopped are still computed here, once more, to be reported (so the wall times are not the
diagnosis' own).
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import replace

import stickslip.diagnosis.pipeline as P
import stickslip.diagnosis.session as SE
from stickslip.diagnosis import fit as F
from stickslip.diagnosis.screen import predicted_share

_ORIG = (SE.Session.extend, SE.Session.judged, P._rechoose_law)


def install(log: dict, first_round: bool = False) -> None:
    extend, judged, rechoose = SE.Session.extend, SE.Session.judged, P._rechoose_law

    def logged_extend(self, parent, causes):
        out = extend(self, parent, causes)
        if parent.causes or first_round:
            fitted = {c.causes[-1] for c in out}
            log["screens"].append(
                {
                    "parent": list(parent.causes),
                    "parent_rmse_over_noise": parent.val.rmse_m / self.sensor_noise_m,
                    "causes": [
                        {
                            "cause": x.cause,
                            "predicted_share": predicted_share(x),
                            "fitted": x.cause in fitted,
                            "screened_on": x.on_calibrated
                            or (f"{x.law} at nominal" if x.from_nominal else ""),
                        }
                        for x in self.screened.get(id(parent), (parent, []))[1]
                    ],
                }
            )
        return out

    def logged_judged(self, cand, parent):
        v = judged(self, cand, parent)
        if parent.causes or first_round:
            log["judged"].append(
                {"causes": list(cand.causes), "share": v.share, "confirmed": v.confirmed}
            )
        return v

    def logged_rechoose(s, chosen, laws=None):
        own = F.per_cycle_cost(s.train, s.nominal, chosen.fit.model, chosen.fit.free, s.noise_m)
        ratios = {}
        tried = [law for law in (s.laws if laws is None else laws) if law != chosen.law]
        for law in tried:
            m = s.at_nominal(replace(chosen.fit.model, law=law))
            free = F.Free(s.free_base[law], chosen.causes)
            _, cost = F.first_stage(s.train, s.nominal, m, free, s.noise_m, SE.FIT_NFEV, False)
            ratios[law] = cost / own
        out = rechoose(s, chosen, laws)
        log["rechoose"].append(
            {
                "causes": list(chosen.causes),
                "law": chosen.law,
                "tried": tried,
                "new_law": out.law,
                "ratios": ratios,
            }
        )
        return out

    SE.Session.extend, SE.Session.judged = logged_extend, logged_judged
    P._rechoose_law = logged_rechoose


def main() -> int:
    first_round = "--first-round" in sys.argv
    for path in [a for a in sys.argv[1:] if a != "--first-round"]:
        log: dict = {"screens": [], "judged": [], "rechoose": []}
        install(log, first_round)
        t0 = time.perf_counter()
        d = P.diagnose(path)
        row = {"dataset": path, "causes": list(d.causes), "wall_s": time.perf_counter() - t0}
        print(json.dumps({**row, **log}, default=float), flush=True)
        SE.Session.extend, SE.Session.judged = _ORIG[:2]
        P._rechoose_law = _ORIG[2]
    return 0


if __name__ == "__main__":
    sys.exit(main())
