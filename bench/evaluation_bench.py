"""One evaluation of a dataset's runs by the diagnosis (fit.residuals: every run simulated,
spread over the simulation threads) against the same runs simulated one after another.

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
    threads, serial = [], []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        F.residuals(runs, model, 2e-9, every)
        threads.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        for r in runs:
            F.predict(r, model)
        serial.append(time.perf_counter() - t0)
    mt, ms = statistics.median(threads), statistics.median(serial)
    print(
        f"{len(runs)} runs, median of {a.repeat}: threads {1e3 * mt:.1f} ms, "
        f"serial {1e3 * ms:.1f} ms, ratio {ms / mt:.2f}"
    )


if __name__ == "__main__":
    main()
