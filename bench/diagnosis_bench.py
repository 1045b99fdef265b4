"""Diagnosis benchmarks (figures in BENCHMARKS.md):

1. wall time of `stickslip diagnose` on the bundled 12-run example (median of --repeat runs);
2. hit rate of the hidden-effect cases over many seeds (the tests run one seed each).

    .venv/bin/python bench/diagnosis_bench.py --repeat 3 --seeds 5 --workers 2

A hit: the named causes equal the hidden ones (as a set), "none" on clean data,
"parameter_miscalibration" on miscalibrated clean data, unexplained=true for the sensor
distortion outside the catalog.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from stickslip import synth
from stickslip.diagnosis.catalog import CAUSES
from stickslip.diagnosis.pipeline import diagnose

ROOT = Path(__file__).resolve().parents[1]

CASES: list[tuple[str, tuple[str, ...], dict]] = [(c, (c,), {}) for c in sorted(CAUSES)] + [
    ("none", (), {}),
    ("parameter_miscalibration", (), {"miscalibrate": True}),
    ("external_load+piezo_hysteresis", ("external_load", "piezo_hysteresis"), {}),
    ("amplifier_slew_limit+thermal_drift", ("amplifier_slew_limit", "thermal_drift"), {}),
    ("asymmetric_friction+piezo_creep", ("asymmetric_friction", "piezo_creep"), {}),
    ("unexplained", (), {"distortion": 40e-9}),
]


def hit(name: str, causes: tuple[str, ...], j: dict) -> bool:
    if name == "unexplained":
        return bool(j["unexplained"])
    if name in ("none", "parameter_miscalibration"):
        return j["causes"] == [name] and not j["unexplained"]
    return sorted(j["causes"]) == sorted(causes) and not j["unexplained"]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3, help="timed example runs (0: none)")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--first-seed", type=int, default=100)
    ap.add_argument("--workers", type=int, default=2)
    names = [c[0] for c in CASES]
    ap.add_argument("--cases", nargs="+", choices=names, default=names, help="default: all")
    a = ap.parse_args()
    cases = [c for c in CASES if c[0] in a.cases]
    with ProcessPoolExecutor(max_workers=a.workers) as ex:
        times = []
        for _ in range(a.repeat):
            t0 = time.perf_counter()
            d = diagnose(ROOT / "examples" / "hidden-effect", executor=ex)
            times.append(time.perf_counter() - t0)
        if times:
            print(
                f"example diagnosis ({len(d.train_ids) + len(d.val_ids)} runs, "
                f"{a.workers} workers): median {statistics.median(times):.1f} s over "
                f"{a.repeat} (min {min(times):.1f}, max {max(times):.1f}); causes {d.causes}",
                flush=True,
            )
        rows = []
        with tempfile.TemporaryDirectory() as tmp:
            for name, causes, kw in cases:
                hits, misses = 0, []
                for seed in range(a.first_seed, a.first_seed + a.seeds):
                    rng = np.random.default_rng(seed)
                    truth = synth.draw_truth(
                        causes, rng, miscalibrate=kw.get("miscalibrate", False)
                    )
                    path = synth.generate(
                        Path(tmp) / f"{name}_{seed}",
                        truth,
                        seed=seed,
                        sensor_distortion_m=kw.get("distortion", 0.0),
                    )
                    j = diagnose(path, executor=ex).to_json()
                    if hit(name, causes, j):
                        hits += 1
                    else:
                        misses.append((seed, j["causes"], j["unexplained"]))
                rows.append((name, hits, a.seeds, misses))
                print(
                    f"{name}: {hits}/{a.seeds}" + (f"  misses {misses}" if misses else ""),
                    flush=True,
                )
    total = sum(r[1] for r in rows)
    print(f"total: {total}/{sum(r[2] for r in rows)}")
    print(json.dumps({"times_s": times, "cases": [r[:3] for r in rows]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
