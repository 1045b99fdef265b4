"""One evaluation of a dataset's runs by the diagnosis (fit.residuals: every run simulated, each
simulation thread's share as one batch of the C core, its runs stepped side by side) against
the runs as one job each on the same threads (the layout before the batches) and against the runs
simulated one after another.

    PYTHONPATH=hil .venv/bin/python bench/evaluation_bench.py [--repeat 10]

Uses the independent generator's 13-run design at 250 kS/s, clean LuGre, seed 1."""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from stickslip import dataset as D
from stickslip import independent
from stickslip.diagnosis import fit as F
from stickslip.model import ActuatorParams


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=10)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "ds"
        independent.generate(path, law="lugre", seed=1, sample_rate_hz=250e3)
        runs = F.prepare_all(D.load(path).runs)
    model = F.Model(ActuatorParams.table1(), law="lugre")
    every = F.strides(runs)
    F.residuals(runs, model, 2e-9, every)  # warm-up: the pool's threads, the library
    pool = F._sim_pool()
    threads, jobs, serial = [], [], []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        F.residuals(runs, model, 2e-9, every)
        threads.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        longest_first = sorted(runs, key=lambda r: -len(r.x_m))
        [fu.result() for fu in [pool.submit(F.predict, r, model) for r in longest_first]]
        jobs.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        for r in runs:
            F.predict(r, model)
        serial.append(time.perf_counter() - t0)
    mt, mj, ms = (statistics.median(x) for x in (threads, jobs, serial))
    print(
        f"{len(runs)} runs, median of {a.repeat}: batches on the threads {1e3 * mt:.1f} ms, "
        f"a job a run on the threads {1e3 * mj:.1f} ms, serial {1e3 * ms:.1f} ms; "
        f"ratios {mj / mt:.2f} and {ms / mt:.2f}"
    )


if __name__ == "__main__":
    main()
