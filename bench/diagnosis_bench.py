"""Diagnosis benchmarks (figures in BENCHMARKS.md):

1. wall time of `stickslip diagnose` on the bundled example and on the independent generator's
   13-run design at 250 kS/s (median of --repeat runs);
2. hit rate of the hidden-effect cases over many seeds, on data from the project's own generator
   (stickslip.synth, the C model) or from the independent one (stickslip.independent, which
   shares no code with lib/).

    .venv/bin/python bench/diagnosis_bench.py --generator own --seeds 5 --repeat 0
    .venv/bin/python bench/diagnosis_bench.py --generator independent --seeds 5 --repeat 3

A hit, own generator: the named causes equal the hidden ones (as a set), "none" on clean data,
"parameter_miscalibration" on miscalibrated clean data, unexplained=true for the sensor
distortion outside the catalog.
A hit, independent generator: clean data from any of its laws names no catalog effect (only
none, parameter_miscalibration or friction_law); a hidden effect is the first catalog cause
named (friction_law may come before it: the laws differ); both effects of a pair are named; an
effect outside the catalog gives unexplained=true and names no catalog effect.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from stickslip import independent, synth
from stickslip.diagnosis.catalog import CAUSES
from stickslip.diagnosis.pipeline import diagnose

ROOT = Path(__file__).resolve().parents[1]
NOT_EFFECTS = {"none", "parameter_miscalibration", "friction_law"}

OWN_CASES: list[tuple[str, tuple[str, ...], dict]] = [(c, (c,), {}) for c in sorted(CAUSES)] + [
    ("none", (), {}),
    ("parameter_miscalibration", (), {"miscalibrate": True}),
    ("lugre_law", (), {"law": "lugre"}),
    ("external_load+piezo_hysteresis", ("external_load", "piezo_hysteresis"), {}),
    ("amplifier_slew_limit+thermal_drift", ("amplifier_slew_limit", "thermal_drift"), {}),
    ("asymmetric_friction+piezo_creep", ("asymmetric_friction", "piezo_creep"), {}),
    ("unexplained", (), {"distortion": 40e-9}),
]

# Independent generator: the law of each effect case is LuGre (its form is one of ours: what is
# measured is the effect, not the law); the null cases run every law it has.
IND_CASES: list[tuple[str, tuple[str, ...], dict]] = (
    [(f"null_{law}", (), {"law": law}) for law in independent.LAWS]
    + [("miscalibrated_lugre", (), {"law": "lugre", "miscalibrate": True})]
    + [(c, (c,), {"law": "lugre"}) for c in sorted(CAUSES)]
    + [
        ("external_load+piezo_hysteresis", ("external_load", "piezo_hysteresis"), {"law": "lugre"}),
        (
            "amplifier_slew_limit+asymmetric_friction",
            ("amplifier_slew_limit", "asymmetric_friction"),
            {"law": "lugre"},
        ),
    ]
    + [
        (f"outside_{e}", (e,), {"law": "lugre", "outside": True})
        for e in independent.OUTSIDE_EFFECTS
    ]
    # the generator's cubic sensor error (40-100 nm over 0.72 mm, 0.006-0.014 % of the travel)
    # lies below the position floor (0.05 %, a good sensor's own linearity: docs/diagnosis.md) and
    # the calibrated law takes it up; at 0.5-2 um (0.07-0.28 %, a capacitive gauge's or an LVDT's
    # linearity) it is a sensor error the runs must show
    + [
        (
            "outside_sensor_cubic_above_floor",
            ("sensor_cubic",),
            {"law": "lugre", "outside": True, "cubic_m": (0.5e-6, 2e-6)},
        )
    ]
)
# The same single effects in contacts none of our laws fits (GMS, and the LS paper's other reading):
# the calibration then leaves about 70 x the noise, and an effect must stand out of that misfit.
# Not in the default table; run with --cases (BENCHMARKS.md, "Single effects on a GMS contact").
IND_OTHER_CONTACTS: list[tuple[str, tuple[str, ...], dict]] = [
    (f"{c}_on_{law}", (c,), {"law": law}) for law in ("gms", "ls_b") for c in sorted(CAUSES)
]


def case_table(generator: str) -> tuple[list, list[str]]:
    """The generator's cases that --cases may name, and the names run by default."""
    if generator == "own":
        return OWN_CASES, [c[0] for c in OWN_CASES]
    return IND_CASES + IND_OTHER_CONTACTS, [c[0] for c in IND_CASES]


def hit_own(name: str, causes: tuple[str, ...], j: dict) -> bool:
    if name == "unexplained":
        return bool(j["unexplained"])
    if name == "lugre_law":
        return j["causes"] == ["friction_law"] and not j["unexplained"]
    if name in ("none", "parameter_miscalibration"):
        return j["causes"] == [name] and not j["unexplained"]
    return sorted(j["causes"]) == sorted(causes) and not j["unexplained"]


def hit_independent(name: str, causes: tuple[str, ...], kw: dict, j: dict) -> bool:
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    if not causes:
        return not named
    if kw.get("outside"):
        return bool(j["unexplained"]) and not named
    if len(causes) == 1:
        return bool(named) and named[0] == causes[0]
    return sorted(named) == sorted(causes)


def make_own(tmp: Path, name: str, causes, kw: dict, seed: int) -> Path:
    rng = np.random.default_rng(seed)
    truth = synth.draw_truth(causes, rng, miscalibrate=kw.get("miscalibrate", False))
    if "law" in kw:
        truth.law = kw["law"]
    return synth.generate(
        tmp / f"{name}_{seed}", truth, seed=seed, sensor_distortion_m=kw.get("distortion", 0.0)
    )


def make_independent(tmp: Path, name: str, causes, kw: dict, seed: int, rate_hz: float) -> Path:
    rng = np.random.default_rng(seed)
    true_params = None
    if kw.get("miscalibrate"):
        true_params = {
            "normal_force_n": 10.0 * rng.uniform(0.7, 1.3),
            "sigma0_n_per_m": 1e7 * rng.uniform(0.5, 2.0),
            "sigma2_ns_per_m": 8.0 * rng.uniform(0.5, 2.0),
        }
    path = tmp / f"{name}_{seed}"
    effects = {c: independent.draw_effect(c, rng) for c in causes}
    if "cubic_m" in kw:  # drawn last: the other draws are the plain case's
        effects["sensor_cubic"]["amplitude_m"] = rng.uniform(*kw["cubic_m"])
    independent.generate(
        path,
        law=kw["law"],
        effects=effects,
        seed=seed,
        sample_rate_hz=rate_hz,
        true_params=true_params,
    )
    return path


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--generator", choices=("own", "independent"), default="own")
    ap.add_argument("--repeat", type=int, default=3, help="timed diagnoses (0: none)")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--first-seed", type=int, default=100)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rate-hz", type=float, default=250e3, help="independent generator's rate")
    a0, _ = ap.parse_known_args()
    table, default = case_table(a0.generator)
    names = [c[0] for c in table]
    ap.add_argument(
        "--cases", nargs="+", choices=names, default=default, help="default: the hit-rate table"
    )
    a = ap.parse_args()
    cases = [c for c in table if c[0] in a.cases]
    with ThreadPoolExecutor(max_workers=a.workers) as ex, tempfile.TemporaryDirectory() as tmp:
        times: list[float] = []
        if a.repeat:
            if a.generator == "own":
                target, what = ROOT / "examples" / "hidden-effect", "example"
            else:
                target = Path(tmp) / "timed"
                independent.generate(target, law="lugre", seed=1, sample_rate_hz=a.rate_hz)
                what = f"independent outside13 at {a.rate_hz / 1e3:g} kS/s, clean LuGre"
            for _ in range(a.repeat):
                t0 = time.perf_counter()
                d = diagnose(target, executor=ex)
                times.append(time.perf_counter() - t0)
            print(
                f"{what} ({len(d.train_ids) + len(d.val_ids)} runs, {a.workers} workers): "
                f"median {statistics.median(times):.1f} s over {a.repeat} (min {min(times):.1f},"
                f" max {max(times):.1f}); causes {d.causes}",
                flush=True,
            )
        rows = []
        for name, causes, kw in cases:
            hits, misses, secs = 0, [], []
            for seed in range(a.first_seed, a.first_seed + a.seeds):
                if a.generator == "own":
                    path = make_own(Path(tmp), name, causes, kw, seed)
                else:
                    path = make_independent(Path(tmp), name, causes, kw, seed, a.rate_hz)
                t0 = time.perf_counter()
                j = diagnose(path, executor=ex).to_json()
                secs.append(time.perf_counter() - t0)
                ok = (
                    hit_own(name, causes, j)
                    if a.generator == "own"
                    else hit_independent(name, causes, kw, j)
                )
                # one line a diagnosis: the time and answer of each (the "under 60 s" count)
                print(
                    f"  {name} seed {seed}: {secs[-1]:.1f} s, {j['causes']}, unexplained "
                    f"{j['unexplained']}, {'hit' if ok else 'miss'}",
                    flush=True,
                )
                if ok:
                    hits += 1
                else:
                    # with how far the best calibrated law stayed from the noise: an effect it
                    # leaves within 3 x is not sought (docs/diagnosis.md, step 9)
                    law_x = min(v["validation_rmse_m"] for v in j["friction_laws"].values())
                    misses.append(
                        (seed, j["causes"], j["unexplained"], round(law_x / j["sensor_noise_m"], 1))
                    )
            rows.append((name, hits, a.seeds, misses))
            print(
                f"{name}: {hits}/{a.seeds} (median {statistics.median(secs):.0f} s)"
                + (f"  misses {misses}" if misses else ""),
                flush=True,
            )
    total = sum(r[1] for r in rows)
    print(f"total: {total}/{sum(r[2] for r in rows)}")
    print(json.dumps({"times_s": times, "cases": [r[:3] for r in rows]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
