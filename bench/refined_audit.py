"""Audit a change to pipeline._refined against an earlier revision's, diagnosis by diagnosis: the
diagnosis runs with the current code, and wherever the current code's early law-dependence test
(pipeline._law_weakness_first) refuses a candidate, REV's _refined is run as well on the same
candidate in the same session. Where REV refuses it too, the rest of the diagnosis is REV's path,
so its answer is REV's (BENCHMARKS.md, "Held-out seeds 124-127"). One JSON line a dataset:
the answer, the model steps (all, and without the audit's own), and the early refusals, with
"different" counting those REV would have kept.

    PYTHONPATH=hil .venv/bin/python bench/refined_audit.py --rev 9b23a4b DATASET [DATASET ...]

Datasets as `bench/diagnosis_profile.py` makes them (its --data folder).
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

from stickslip import _native as N
from stickslip.diagnosis import pipeline as PL

ROOT = Path(__file__).resolve().parents[1]


def rev_refined(rev: str):
    """REV's _refined, defined in the current pipeline module's namespace (its helpers are the
    current ones: a change to them is not audited)."""
    src = subprocess.run(
        ["git", "-C", str(ROOT), "show", f"{rev}:hil/stickslip/diagnosis/pipeline.py"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    m = re.search(r"^def _refined\(.*?(?=^def )", src, re.S | re.M)
    if m is None:
        raise SystemExit(f"no _refined in {rev}'s pipeline.py")
    ns = PL.__dict__
    exec(m.group(0).replace("def _refined(", "def _refined_audited_rev(", 1), ns)
    return ns["_refined_audited_rev"]


class Audit:
    def __init__(self, rev: str) -> None:
        self.old = rev_refined(rev)
        self.steps = 0
        self.audit_steps = 0
        self.counts = {"refused_early": 0, "same": 0, "different": 0}
        self.weak = False
        one, many = N.run_f32, N.run_f32_many

        def run_f32(cfg, wave, n, *a, **k):
            self.steps += n
            return one(cfg, wave, n, *a, **k)

        def run_f32_many(runs):
            self.steps += sum(r[2] for r in runs)
            return many(runs)

        N.run_f32, N.run_f32_many = run_f32, run_f32_many  # model.py looks them up at call time
        first, refined = PL._law_weakness_first, PL._refined

        def law_weakness_first(*a, **k):
            w = first(*a, **k)
            self.weak = bool(w)
            return w

        def audited(s, accepted, chosen, on_provisional=False):
            self.weak = False
            reasons = list(accepted.verdict.reasons)
            new = refined(s, accepted, chosen, on_provisional)
            if self.weak:
                self.counts["refused_early"] += 1
                after = list(accepted.verdict.reasons)
                accepted.verdict.reasons[:] = reasons
                s0 = self.steps
                old = self.old(s, accepted, chosen, on_provisional)
                self.audit_steps += self.steps - s0
                self.counts["same" if old is None else "different"] += 1
                why = accepted.verdict.reasons[len(reasons) :]
                print(
                    f"audit: {'+'.join(accepted.causes)} ({accepted.law}) refused early; "
                    f"{'refused' if old is None else 'KEPT'} by the revision: {why}",
                    file=sys.stderr,
                    flush=True,
                )
                accepted.verdict.reasons[:] = after
            return new

        PL._law_weakness_first, PL._refined = law_weakness_first, audited

    def run(self, path: Path) -> dict:
        self.steps = self.audit_steps = 0
        self.counts = dict.fromkeys(self.counts, 0)
        t0 = time.perf_counter()
        j = PL.diagnose(path, progress=lambda _: None).to_json()
        return {
            "data": path.name,
            "causes": j["causes"],
            "unexplained": j["unexplained"],
            "rmse_over_noise": j["extended"]["validation_rmse_m"] / j["sensor_noise_m"],
            "msteps": round((self.steps - self.audit_steps) / 1e6, 1),
            "audit_msteps": round(self.audit_steps / 1e6, 1),
            "wall_s": round(time.perf_counter() - t0, 1),
            **self.counts,
        }


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rev", required=True, help="the revision whose _refined is audited beside")
    ap.add_argument("datasets", nargs="+", type=Path)
    a = ap.parse_args()
    audit = Audit(a.rev)
    for path in a.datasets:
        print(json.dumps(audit.run(path)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
