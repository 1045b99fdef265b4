"""What each diagnosis of the hit-rate tables costs, in model steps (deterministic, unlike wall
time on a shared machine), by stage, and where its kept causes came from (the round, and whether
from the first batch of fits of a screen or a later one), and its timeline (each progress message
with the wall time and model steps before it), and the report's candidates (each cause's fitted
validation error and parameters). One JSON line a diagnosis, so a run can be compared
with another line by line; the answers are diagnosis_bench.py's.

    PYTHONPATH=hil:bench .venv/bin/python bench/diagnosis_cost.py --generator own --out own.jsonl
    PYTHONPATH=hil:bench .venv/bin/python bench/diagnosis_cost.py --generator independent \\
        --cases piezo_hysteresis base_compliance --seeds 2 --out ind.jsonl
    ... --generator independent --only piezo_hysteresis:102 null_gms:100 --out slow.jsonl

Datasets are generated into --data and kept (a second run skips the generation; the own
generator's only while the C library is the same).
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import threading
import time
from pathlib import Path

import diagnosis_bench as B
import diagnosis_profile as P

from stickslip import _native as N
from stickslip.diagnosis import pipeline as PL
from stickslip.diagnosis import session as SE


class StepCounter:
    """Model steps simulated through the float core, per progress stage."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.by_stage: collections.Counter[str] = collections.Counter()
        self.stage = "start"

    def add(self, steps: int) -> None:
        with self.lock:
            self.by_stage[self.stage] += steps

    def install(self) -> None:
        one, many = N.run_f32, N.run_f32_many

        def run_f32(cfg, wave, n_steps, *args, **kw):
            self.add(n_steps)
            return one(cfg, wave, n_steps, *args, **kw)

        def run_f32_many(runs):
            self.add(sum(r[2] for r in runs))
            return many(runs)

        N.run_f32, N.run_f32_many = run_f32, run_f32_many  # model.py looks them up at call time


def tag_batches() -> None:
    """Mark each candidate with the batch of fits it came from (0: the first of its parent's
    screen, 1: the next, ...)."""
    fit_pending = SE.Session.fit_pending

    def tagged(self, parent, **kw):
        calls = self.__dict__.setdefault("_batches", collections.Counter())
        batch = calls[id(parent)]
        calls[id(parent)] += 1
        out = fit_pending(self, parent, **kw)
        for i, c in enumerate(out):
            c.batch = batch
            c.rank = batch * SE.TOP_FIT + i  # among the causes its screen found promising
        return out

    SE.Session.fit_pending = tagged


CANDIDATE_KEYS = ("name", "validation_rmse_m", "params", "confirmed", "screened_only")


def stage_of(msg: str) -> str:
    """The stage a progress message opens, without the names of causes and laws."""
    for key in (
        "calibrating",
        "the data prefer",
        "the calibrated",
        "screening",
        "checking each",
        "checking",
        "refining",
        "refitting",
        "choosing the friction law",
        "the base law explains",
        "adding to",
        "fitting",
        "nominal",
    ):
        if msg.startswith(key):
            return key
    return msg.split(" ")[0]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--generator", choices=("own", "independent"), default="own")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--first-seed", type=int, default=100)
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-cost"))
    ap.add_argument("--out", type=Path, required=True, help="JSON lines, one a diagnosis")
    a0, _ = ap.parse_known_args()
    table, default = B.case_table(a0.generator)
    names = [c[0] for c in table]
    ap.add_argument(
        "--cases", nargs="+", choices=names, default=default, help="default: the hit-rate table"
    )
    ap.add_argument(
        "--only", nargs="+", metavar="CASE:SEED", help="just these diagnoses (e.g. the slow ones)"
    )
    a = ap.parse_args()
    only = None
    if a.only:
        only = set()
        for x in a.only:
            name, _, seed = x.rpartition(":")
            if name not in names or not seed.isdigit():
                ap.error(f"--only {x}: expected CASE:SEED with CASE one of the table's cases")
            only.add((name, int(seed)))
        a.cases = sorted({nm for nm, _ in only})  # --only's cases, whatever --cases says
    counter = StepCounter()
    counter.install()
    tag_batches()
    with a.out.open("w") as out:
        for name, causes, kw in (c for c in table if c[0] in a.cases):
            seeds = range(a.first_seed, a.first_seed + a.seeds)
            if only is not None:  # --only's seeds, whatever --first-seed and --seeds say
                seeds = sorted({sd for nm, sd in only if nm == name})
            for seed in seeds:
                case = name if a.generator == "independent" else f"own:{name}"
                path = P.dataset(case, seed, a.rate_hz, a.data)
                counter.by_stage.clear()
                timeline: list[tuple[float, float, str]] = []
                t0 = time.perf_counter()

                def say(msg: str, timeline=timeline, t0=t0) -> None:
                    counter.stage = stage_of(msg)
                    steps = sum(counter.by_stage.values()) / 1e6
                    timeline.append((round(time.perf_counter() - t0, 1), round(steps, 1), msg))

                d = PL.diagnose(path, progress=say)
                wall = time.perf_counter() - t0
                j = d.to_json()
                hit = (
                    B.hit_own(name, causes, j)
                    if a.generator == "own"
                    else B.hit_independent(name, causes, kw, j)
                )
                kept = [
                    {
                        "round": i,
                        "batch": getattr(c, "batch", None),
                        "rank": getattr(c, "rank", None),
                        "causes": list(c.causes),
                        "law": c.law,
                    }
                    for i, rnd in enumerate(d.rounds)
                    for c in rnd
                    if c.verdict is not None and c.verdict.confirmed
                ]
                row = {
                    "case": name,
                    "seed": seed,
                    "hit": hit,
                    "causes": j["causes"],
                    "unexplained": j["unexplained"],
                    "rmse_over_noise": j["extended"]["validation_rmse_m"] / j["sensor_noise_m"],
                    # the named causes' values as reported (refined: a slew limit's bandwidth)
                    "params": {
                        k: v for k, v in j["extended"].get("params", {}).items() if "." in k
                    },
                    "wall_s": round(wall, 1),
                    "msteps": round(sum(counter.by_stage.values()) / 1e6, 2),
                    "msteps_by_stage": {
                        k: round(v / 1e6, 2) for k, v in counter.by_stage.most_common()
                    },
                    "rounds": [len(r) for r in d.rounds],
                    "kept": kept,
                    # the report's candidates, without their guards: how close each cause fitted
                    # in a named one's place came is read from these offline (twin checks)
                    "candidates": [
                        {k: c[k] for k in CANDIDATE_KEYS if k in c} for c in j["candidates"]
                    ],
                    # every progress message with the wall time and model steps (M) before it: a
                    # rule that would stop the search at some point is costed from this offline
                    "timeline": timeline,
                }
                out.write(json.dumps(row) + "\n")
                out.flush()
                print(
                    f"{name} {seed}: {'hit' if hit else 'miss'} {j['causes']} "
                    f"unexplained {j['unexplained']}, {wall:.0f} s, {row['msteps']} M steps",
                    flush=True,
                )
    return 0


if __name__ == "__main__":
    sys.exit(main())
