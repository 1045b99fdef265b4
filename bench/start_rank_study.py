"""Would the whole runs have chosen the same start? (fit.START_RANK_PERIODS, START_RANK_KEEP)

A first stage with a grid of start points costs each over the runs' first START_RANK_PERIODS
periods and simulates only the best START_RANK_KEEP over the whole runs. This diagnoses datasets on
that path and, at every such grid, also simulates every start over the whole runs (the path is
not changed): the rank, among the first periods' costs, of the start the whole runs would have
chosen, and what the chosen start costs over the whole runs against that best. One JSON line a
grid; a summary at the end. Costs about 1.5 x a diagnosis.

    PYTHONPATH=hil:bench .venv/bin/python bench/start_rank_study.py --data DIR --out X.jsonl \\
        --only base_compliance:118 null_gms:100 own:base_compliance:100   (own: our generator's)
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import threading
from pathlib import Path

import diagnosis_bench as B
import diagnosis_profile as P
import numpy as np

from stickslip.diagnosis import fit as F
from stickslip.diagnosis import pipeline as PL


def install(log: list[dict], where: list[str]) -> None:
    """Wrap _Problem.first_stage: log each ranked grid's costs, then run it unchanged."""
    first_stage = F._Problem.first_stage
    lock = threading.Lock()

    def logged(self, max_nfev, grid):
        starts = self.start_points(grid)
        if self.ranks_starts(starts):
            short = self.first_periods_costs(starts)
            whole = [float(np.sum(r**2)) for r in self.res_many(starts, True, F.MAX_DT_S)]
            order = np.argsort(short, kind="stable")
            kept = sorted(order[: F.START_RANK_KEEP])
            best = int(np.argmin(whole))
            chosen = kept[int(np.argmin([whole[i] for i in kept]))]
            with lock:
                log.append(
                    {
                        "data": where[0],
                        "law": self.start.law,
                        "causes": list(self.free.causes),
                        "starts": len(starts),
                        "rank_of_best": int(np.where(order == best)[0][0]),
                        "chosen_over_best": whole[chosen] / whole[best],
                    }
                )
        return first_stage(self, max_nfev, grid)

    F._Problem.first_stage = logged


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-cost"))
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--out", type=Path, required=True, help="JSON lines, one a grid")
    ap.add_argument("--only", nargs="+", metavar="CASE:SEED", required=True)
    a = ap.parse_args()
    names = {c[0] for c in B.IND_CASES} | {f"own:{c[0]}" for c in B.OWN_CASES}
    log: list[dict] = []
    where = [""]
    install(log, where)
    with a.out.open("w") as out:
        for x in a.only:
            name, _, seed = x.rpartition(":")
            if name not in names or not seed.isdigit():
                ap.error(f"--only {x}: expected CASE:SEED, CASE an independent case or own:CASE")
            where[0] = x
            n0 = len(log)
            d = PL.diagnose(P.dataset(name, int(seed), a.rate_hz, a.data)).to_json()
            for row in log[n0:]:
                out.write(json.dumps(row) + "\n")
            print(f"{x}: {d['causes']}, {len(log) - n0} ranked grids", flush=True)
    ranks = collections.Counter(r["rank_of_best"] for r in log)
    missed = [r for r in log if r["rank_of_best"] >= F.START_RANK_KEEP]
    print(
        f"{len(log)} ranked grids; the whole runs' best ranked (0 = first): {sorted(ranks.items())}"
    )
    print(f"outside the best {F.START_RANK_KEEP}: {len(missed)}")
    for r in missed:
        print(
            f"  {r['data']} {r['law']} {'+'.join(r['causes'])} ({r['starts']} starts): ranked "
            f"{r['rank_of_best']}, the chosen start {r['chosen_over_best']:.3f} x its cost"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
