"""A first stage's start points, ranked on the runs' first periods: what those periods simulate,
and which starts the whole runs then compare (fit._Problem.first_stage)."""

from __future__ import annotations

import numpy as np

from stickslip import synth
from stickslip.dataset import load
from stickslip.diagnosis import fit as F
from stickslip.diagnosis.fit import Free, Model
from stickslip.model import ActuatorParams, Effects

NOMINAL = ActuatorParams.table1()


def test_the_first_periods_are_the_whole_runs_residual_over_them(tmp_path):
    """The ranking is worth only what the same samples of the whole runs say: cut runs must give
    the whole runs' per-cycle residual over their periods (no hold, no shift of a sample), with a
    base that rings across the cut."""
    design = [synth.RunDesign(f"f{f:g}_{d}", f, 100.0, d, 9) for f, d in ((500.0, 1), (2e3, -1))]
    truth = synth.Truth(NOMINAL, Effects(), ())
    runs = F.prepare_all(load(synth.generate(tmp_path / "ds", truth, seed=3, design=design)).runs)
    model = Model(NOMINAL, Effects(base_mass_kg=0.02, base_freq_hz=4e3, base_damping_ratio=0.05))
    every = F.strides(runs)
    periods = F.START_RANK_PERIODS
    short = [F._first_periods(r, periods) for r in runs]
    whole = F.residuals(runs, model, 2e-9, every, True)
    cut = F.residuals(short, model, 2e-9, every, True)
    at = 0
    for r, s, k in zip(runs, short, every):
        n_whole, n_cut = len(r.x_m[::k]), len(s.x_m[::k])
        assert s.waveform.cycles == periods and s.t_s[-1] <= periods / s.waveform.frequency_hz
        assert n_cut < n_whole
        # to the rounding of the offset each places its slider by (1e-6 m over 2e-9 m of noise:
        # 1e-13); a sample off by one would be off by whole noise units
        np.testing.assert_allclose(cut[:n_cut], whole[at : at + n_cut], rtol=0, atol=1e-9)
        cut, at = cut[n_cut:], at + n_whole
    assert len(cut) == 0
    # a run of no more periods than that is kept whole
    assert F._first_periods(runs[0], 9) is runs[0]


def test_the_whole_runs_choose_among_the_best_starts_of_the_first_periods(monkeypatch):
    """A base's 66-point grid: every start costed on the first periods, only the best
    START_RANK_KEEP simulated over the whole runs, and the best of those is where the solve
    starts, even when the first periods ranked it last of them."""
    free = Free((), ("base_compliance",))
    p = F._Problem([], NOMINAL, Model(NOMINAL), free, 2e-9)
    k = F.START_RANK_KEEP
    short_rank: dict[bytes, float] = {}  # a start's cost on the first periods, by its theta
    whole: list[bytes] = []  # the starts simulated over the whole runs
    solved_from: list[np.ndarray] = []

    def residuals(runs, model, noise_m, every, per_cycle=False, max_dt_s=F.MAX_DT_S):
        assert runs == ["cut"] and per_cycle
        key = F.theta_of(model, p.specs).tobytes()
        return np.array([short_rank.setdefault(key, float(len(short_rank)))])

    def res_many(self, thetas, per_cycle, max_dt_s):
        whole.extend(th.tobytes() for th in thetas)
        # the whole runs reverse the first periods' order among the starts they see
        return [np.array([100.0 - short_rank[th.tobytes()]]) for th in thetas]

    def solve(self, theta0, per_cycle, nfev, tol):
        solved_from.append(theta0)
        return type("R", (), {"x": theta0, "cost": 0.0})()

    monkeypatch.setattr(F, "residuals", residuals)
    monkeypatch.setattr(F._Problem, "short_runs", lambda self: ["cut"])
    monkeypatch.setattr(F._Problem, "res_many", res_many)
    monkeypatch.setattr(F._Problem, "solve", solve)
    p.first_stage(10, True)
    assert len(short_rank) == 66  # every grid point costed on the first periods
    best_k = sorted(short_rank, key=short_rank.__getitem__)[:k]
    assert sorted(whole) == sorted(best_k)  # only those over the whole runs
    # the whole runs' best: the first periods' k-th
    assert solved_from[0].tobytes() == best_k[-1]


def test_starts_with_heat_carried_over_are_all_simulated_whole(monkeypatch):
    """A thermal drift's runs depend on the runs before them: a cut run would start cold, so
    every start is costed over the whole runs, as before."""
    free = Free((), ("thermal_drift",))
    start = Model(NOMINAL, Effects(thermal_coeff_per_j=50.0, thermal_tau_s=0.1))
    p = F._Problem([], NOMINAL, start, free, 2e-9)
    seen: list[int] = []

    def res_many(self, thetas, per_cycle, max_dt_s):
        seen.append(len(thetas))
        return [np.array([float(i)]) for i in range(len(thetas))]

    monkeypatch.setattr(F._Problem, "short_runs", lambda self: 1 / 0)  # never asked for
    monkeypatch.setattr(F._Problem, "res_many", res_many)
    monkeypatch.setattr(
        F._Problem, "solve", lambda self, th, pc, n, tol: type("R", (), {"x": th, "cost": 0.0})()
    )
    p.first_stage(10, True)
    assert seen and seen[0] > F.START_RANK_KEEP
