"""Where one diagnosis spends its time: wall time per phase and simulations (passes over the runs,
`fit.predict_all` calls) per progress stage, then the candidates of every round with their
validation error and the guards' verdict. Figures in BENCHMARKS.md.

    PYTHONPATH=hil .venv/bin/python bench/diagnosis_profile.py amplifier_slew_limit 100
    PYTHONPATH=hil .venv/bin/python bench/diagnosis_profile.py own:base_compliance 101

CASE is a case of diagnosis_bench.py's independent table (at --rate-hz, 250 kS/s by default), or
own:CASE for its own-generator table. The dataset is generated into --data and kept: a second run
skips the generation (for the own generator's data, only while the C library is the same).
"""

from __future__ import annotations

import argparse
import collections
import hashlib
import sys
import time
from pathlib import Path

import diagnosis_bench as B

from stickslip import _native as N
from stickslip import dataset as D
from stickslip.diagnosis import fit as F
from stickslip.diagnosis import pipeline as PL
from stickslip.diagnosis import session as SE
from stickslip.diagnosis.guards import share_removed


def library_stamp() -> str:
    """The first hex digits of the loaded C library's SHA-256."""
    return hashlib.sha256(Path(N.lib._name).read_bytes()).hexdigest()[:12]


def dataset(case: str, seed: int, rate_hz: float, data: Path) -> Path:
    data.mkdir(parents=True, exist_ok=True)
    if case.startswith("own:"):
        name = case[4:]
        causes, kw = {n: (c, k) for n, c, k in B.OWN_CASES}[name]
        # the own generator is the C model: data made before a change of the model's physics
        # is not that model's data any more (the stack-damper fix moved every base dataset)
        path = data / f"own_{name}_{seed}_{library_stamp()}"
        if not path.exists():
            B.make_own(data, f"own_{name}_{seed}_", causes, kw, seed).rename(path)
        return path
    causes, kw = {n: (c, k) for n, c, k in B.case_table("independent")[0]}[case]
    path = data / f"{case}_{seed}_{int(rate_hz)}"
    if not path.exists():
        B.make_independent(
            data, f"{case}_{seed}_{int(rate_hz)}_", causes, kw, seed, rate_hz
        ).rename(path)
    return path


def fit_inputs(case: str, seed: int, rate_hz: float, data: Path):
    """A case's dataset as the diagnosis fits it: (dataset, training runs, validation runs, noise
    in m), for the scripts that call the fits directly."""
    ds = D.load(dataset(case, seed, rate_hz, data))
    runs = F.prepare_all(ds.runs)
    train, val = PL.split_runs(runs)
    _, noise, _ = PL.noise_level(ds, runs)
    return ds, train, val, noise


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("seed", type=int)
    ap.add_argument("--rate-hz", type=float, default=250e3)
    ap.add_argument("--data", type=Path, default=Path("out/diagnosis-profile"))
    a = ap.parse_args()
    path = dataset(a.case, a.seed, a.rate_hz, a.data)

    calls: collections.Counter[str] = collections.Counter()
    stage = ["start"]
    original = F.predict_all

    def counted(*args, **kwargs):
        calls[stage[0]] += 1  # jobs still running from the stage before count here too
        return original(*args, **kwargs)

    F.predict_all = counted  # residuals() and evaluate() look it up at call time
    screens: list[tuple[str, list]] = []
    screen = SE.Session.screen

    def screen_logged(self, parent, causes):
        out = screen(self, parent, causes)
        screens.append(("+".join(parent.causes) or parent.law, parent.mse_over_noise, out))
        return out

    SE.Session.screen = screen_logged
    # how each least-squares solve ended: scipy's status 0 is its evaluation budget, 1-4 a
    # tolerance (per stage: the first's tolerance is 1e-3, the second's 1e-5)
    ends: collections.Counter[str] = collections.Counter()
    solve = F.least_squares

    def solve_counted(fun, x0, **kw):
        r = solve(fun, x0, **kw)
        stage_ = "first" if kw.get("xtol", 0.0) >= 1e-3 else "second"
        ends[f"{stage_} stage, {'budget' if r.status == 0 else 'converged'}"] += 1
        return r

    F.least_squares = solve_counted  # fit.fit looks it up at call time
    t0 = time.perf_counter()

    def say(msg: str) -> None:
        stage[0] = msg.split(":")[0][:40]
        print(f"{time.perf_counter() - t0:7.1f} s  {msg}", flush=True)

    d = PL.diagnose(path, progress=say)
    print(f"causes {d.causes}, unexplained {d.unexplained}, {time.perf_counter() - t0:.1f} s")
    print("phases (s):", {k: round(v, 1) for k, v in d.timing_s.items()})
    print(f"simulations: {sum(calls.values())}", dict(calls))
    print("least_squares ends:", dict(sorted(ends.items())))
    laws = ", ".join(f"{n} {c.val.rmse_m * 1e9:.2f} nm" for n, c in d.laws.items())
    print(f"laws calibrated: {laws}; causes added to {d.base.law}")
    for i, rnd in enumerate(d.rounds):
        for c in rnd:
            v = c.verdict
            verdict = "" if v is None else ("confirmed" if v.confirmed else "; ".join(v.reasons))
            share = (
                f" ({100 * share_removed(c.parent.mse_over_noise, c.mse_over_noise):.0f} % of the"
                " parent's excess)"
                if c.parent
                else ""
            )
            print(
                f"round {i}: {'+'.join(c.causes)} ({c.law}) {c.val.rmse_m * 1e9:.2f} nm{share}"
                f"  {verdict}"
            )
    # what each screen predicted: validation RMSE (noise units) and the share of the parent's
    # excess error (its first-order refit) that the cause would remove
    for parent, mse_parent, out in screens:
        row = []
        for x in out[:6]:
            predicted = share_removed(x.rss_parent / x.n_val, x.rss_val / x.n_val)
            row.append(f"{x.cause} {100 * predicted:.0f}%")
        print(f"screen on {parent} (mse {mse_parent:.3g}): " + ", ".join(row))
    print(
        f"baseline {d.baseline.val.rmse_m * 1e9:.2f} nm, chosen {d.chosen.val.rmse_m * 1e9:.2f} nm,"
        f" sensor noise {d.sensor_noise_m * 1e9:.2f} nm"
    )
    fitted = {k: v for k, v in d.chosen.fit.values.items() if "." in k}
    print("chosen causes' values:", {k: float(f"{v:.4g}") for k, v in fitted.items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
