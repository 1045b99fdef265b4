"""A cause fitted from the nominal parameters (base compliance) under the friction law whose first
stage fits it best: which starts are submitted, which law is kept, and when the law need not be
chosen again (session.fit_under_best_law, _law_chosen_with_it; screen's per-law probe points)."""

from __future__ import annotations

from concurrent.futures import Future
from dataclasses import replace

import numpy as np

from stickslip.diagnosis import pipeline as PL
from stickslip.diagnosis import session as SE
from stickslip.diagnosis.fit import Evaluation, FitResult, Free, Model
from stickslip.diagnosis.guards import FoldResult, Linearization, Verdict
from stickslip.diagnosis.result import Candidate
from stickslip.diagnosis.screen import Screened, screen
from stickslip.diagnosis.session import Session
from stickslip.model import ActuatorParams, Effects

NOMINAL = ActuatorParams.table1()
BENT = ActuatorParams(normal_force_n=6.0, piezo_damping_kg_per_s=40.0)  # a calibration a base bent
LAWS = ("ls", "lugre", "gms")


class _Recorder:
    """An executor that runs nothing: it records each job and returns an empty fit."""

    def __init__(self):
        self.jobs: list[tuple] = []

    def submit(self, fn, *args):
        self.jobs.append((fn, args))
        fu: Future = Future()
        m = Model(NOMINAL)
        fu.set_result((FitResult(Free((), ()), m, m.values(), 0.0, 0), Evaluation(0, 0, 1, 1)))
        return fu


def _session() -> tuple[Session, _Recorder, Candidate]:
    ex = _Recorder()
    s = Session(NOMINAL, [], [], [], 2e-9, ex, lambda _: None)
    s.laws = LAWS
    for law in LAWS:
        s.held[law], s.free_base[law] = (), ("normal_force_n", f"{law}_only")
    m = Model(BENT, law="lugre")
    base = Candidate(FitResult(Free((), ()), m, m.values(), 0.0, 0), Evaluation(0, 0, 1, 1), 0.0)
    return s, ex, base


def _screened(from_nominal: bool) -> Screened:
    points = {
        law: {"base_mass_kg": 0.02, "base_freq_hz": f} for law, f in zip(LAWS, (1e3, 2e3, 3e3))
    }
    return Screened(
        "base_compliance", points["lugre"], 1.0, 10, 2.0, 1.0, from_nominal, "lugre", points
    )


def test_a_base_is_fitted_from_nominal_under_every_law():
    for from_nominal in (True, False):
        s, ex, base = _session()
        s.pending[id(base)] = (base, [_screened(from_nominal)])
        s.fit_pending(base)
        [(fn, args)] = ex.jobs
        assert fn is SE.fit_under_best_law
        starts = args[3]
        assert [m.law for m, _, _ in starts] == list(LAWS)
        for (m, free, grid), f_hz in zip(starts, (1e3, 2e3, 3e3)):
            # at nominal, whatever the calibration bent; the law's identifiable parameters free
            assert m.params == NOMINAL
            assert free == Free(("normal_force_n", f"{m.law}_only"), ("base_compliance",))
            # from the screen's probe of this law at nominal when one screened best, else the grid
            assert grid is not from_nominal
            assert m.effects.base_freq_hz == (f_hz if from_nominal else 0.0)


def test_the_law_whose_first_stage_fits_best_is_kept(monkeypatch):
    costs = {"ls": 5e7, "lugre": 3e5, "gms": 2e7}
    seen = []

    def first_stage(train, nominal, m, free, noise_m, max_nfev, grid):
        return np.array([costs[m.law]]), costs[m.law]

    def fit_from(train, nominal, m, free, noise_m, theta, max_nfev):
        seen.append((m.law, float(theta[0])))
        return FitResult(free, m, m.values(), 0.0, 0)

    monkeypatch.setattr(SE, "first_stage", first_stage)
    monkeypatch.setattr(SE, "fit_from", fit_from)
    monkeypatch.setattr(SE, "evaluate", lambda val, model, noise: Evaluation(0, 0, 1, 1))
    starts = [(Model(NOMINAL, law=law), Free((), ("base_compliance",)), True) for law in LAWS]
    f, _ = SE.fit_under_best_law([], [], NOMINAL, starts, 2e-9)
    assert seen == [("lugre", 3e5)]  # the second stage from LuGre's first-stage point only
    assert f.model.law == "lugre" and f.first_stage_costs == costs


def _with_costs(law: str, costs: dict[str, float]) -> Candidate:
    m = Model(NOMINAL, Effects(base_mass_kg=0.02, base_freq_hz=3e3), law=law)
    f = FitResult(Free((), ("base_compliance",)), m, m.values(), 0.0, 0, first_stage_costs=costs)
    return Candidate(f, Evaluation(0, 0, 1, 1), 0.0)


def test_the_law_is_not_chosen_again_only_when_the_first_stages_were_clear():
    assert PL._law_chosen_with_it(_with_costs("lugre", {"ls": 5e6, "lugre": 3e5, "gms": 2e7}))
    # within 10 x of another law: the validation and the left-out families decide again
    assert not PL._law_chosen_with_it(_with_costs("lugre", {"ls": 2e6, "lugre": 3e5, "gms": 2e7}))
    # not fitted under each law (any other cause)
    assert not PL._law_chosen_with_it(_with_costs("lugre", {}))


def test_the_screen_keeps_each_law_s_best_probe_at_nominal():
    # three rows, the last held out; two probe points; per law the point with the smaller
    # per-cycle error on the held-out row is kept, whichever law screened best overall (the
    # probes at nominal and the parent's per-cycle error hold the held-out row alone)
    lin = Linearization(np.array([1.0, 1.0, 1.0]), np.zeros((3, 0)), np.array([0, 0, 1]))
    points = [{"base_freq_hz": 2e3}, {"base_freq_hz": 5e3}]
    probes = [np.array([1.0, 1.0, 1.0]), np.array([1.0, 1.0, 1.0])]
    nominal = {
        "ls": [np.array([0.5]), np.array([0.1])],
        "lugre": [np.array([0.2]), np.array([0.9])],
    }
    x = screen(lin, [1], "base_compliance", points, probes, nominal, np.array([1.0]))
    assert x.nominal_points == {"ls": points[1], "lugre": points[0]}
    assert x.from_nominal and x.law == "ls" and x.values == points[1]


def _done(*result) -> Future:
    fu: Future = Future()
    fu.set_result(result)
    return fu


class _Now:
    """An executor that runs each job at once."""

    def submit(self, fn, *args):
        fu: Future = Future()
        fu.set_result(fn(*args))
        return fu


def test_the_law_chosen_again_goes_on_only_under_laws_whose_first_stage_ends_below_it(monkeypatch):
    # the chosen model (LuGre, a load kept) scores 1e6 per cycle; LS's first stage ends at half of
    # it and goes on to its second stage, GMS's 1.4 x above it (the closest a law that was not
    # taken came, slew limit on a GMS contact, seed 132) and stops there
    firsts = {"ls": 5e5, "gms": 1.4e6}
    seconds = []
    monkeypatch.setattr(PL, "per_cycle_cost", lambda train, nominal, m, free, noise: 1e6)
    monkeypatch.setattr(
        PL,
        "first_stage",
        lambda train, nominal, m, free, noise, nfev, grid: (
            np.array([firsts[m.law]]),
            firsts[m.law],
        ),
    )

    def second(train, val, nominal, m, free, noise, theta):
        seconds.append((m.law, float(theta[0])))
        return FitResult(free, m, m.values(), 0.0, 0), Evaluation(0, 0, 1e3, 1000)

    monkeypatch.setattr(PL, "fit_from_and_validate", second)
    s, _, _ = _session()
    s.ex = _Now()
    m = Model(BENT, Effects(load_n=0.1), law="lugre")
    f = FitResult(Free(("normal_force_n",), ("external_load",)), m, m.values(), 0.0, 0)
    chosen = Candidate(f, Evaluation(0, 0, 1e3, 1000), 0.0)
    assert PL._rechoose_law(s, chosen) is chosen  # LS no better on the validation runs
    assert seconds == [("ls", 5e5)]
    # every other law's first stage above the chosen model's cost: no second stage at all
    firsts["ls"] = 1.2e6
    seconds.clear()
    assert PL._rechoose_law(s, chosen) is chosen
    assert seconds == []


def _calibrated(s: Session, rmse_m: float = 200e-9) -> dict[str, Candidate]:
    """Each law's calibration: BENT under it, rmse_m on the validation runs."""
    cal = {}
    for law in LAWS:
        m = Model(BENT, law=law)
        f = FitResult(Free(("normal_force_n",), ()), m, m.values(), 0.0, 0)
        cal[law] = Candidate(f, Evaluation(rmse_m, 0, (rmse_m / 2e-9) ** 2 * 1000, 1000), 0.0)
    s.calibrated = cal
    return cal


def test_a_first_cause_short_of_its_share_is_chosen_again_only_under_laws_calibrated_near(
    monkeypatch,
):
    # clean GMS data 128-133: a thermal drift, a load, an asymmetry removed 38-49 % of the GMS
    # calibration's error; LuGre's and LS's calibrations were 2-16 x and 53-69 x worse than GMS's
    # (mean square), and refitted from nominal with the cause they ended 3.5-114 x worse than GMS
    # with it (seed 133). The law
    # is chosen again only among the laws calibrated near the parent (those the first round
    # screened on); one that carries the final check's share is chosen again among all.
    tried = []
    monkeypatch.setattr(PL, "_rechoose_law", lambda s, c, laws=None: tried.append(laws) or c)
    monkeypatch.setattr(PL, "_law_weakness_first", lambda *args: "")
    monkeypatch.setattr(PL, "_final_weakness", lambda s, c, cause, explained: ("", c))
    monkeypatch.setattr(PL, "_law_dependence", lambda *args: "")
    s, _, _ = _session()
    s.ex = _Now()
    cal = _calibrated(s)  # 200 nm under each law: 10 000 noise variances
    worse = Evaluation(400e-9, 0, 40000.0 * 1000, 1000)
    cal["ls"] = Candidate(cal["ls"].fit, worse, 0.0)  # 4 x GMS's error
    m = Model(
        BENT,
        Effects(thermal_coeff_per_j=1e-3, thermal_tau_s=0.3),
        law="gms",
        causes=("thermal_drift",),
    )
    f = FitResult(Free(("normal_force_n",), ("thermal_drift",)), m, m.values(), 0.0, 0)

    def refined_to(ev: Evaluation) -> Candidate:
        monkeypatch.setattr(SE, "fit_and_validate", lambda *args: (f, ev))  # the refinement
        return Candidate(f, ev, 0.0, cal["gms"], Verdict())

    weak = Evaluation(150e-9, 0, 5625.0 * 1000, 1000)  # 44 % of GMS's excess
    accepted = refined_to(weak)
    assert PL._refined(s, accepted, cal["gms"]) is None
    assert tried == [("lugre",)]  # LuGre's calibration as good as GMS's, LS's 4 x worse
    assert "accounts for only 44 %" in accepted.verdict.reasons[-1]
    strong = Evaluation(60e-9, 0, 900.0 * 1000, 1000)  # 91 % of GMS's excess
    tried.clear()
    assert PL._refined(s, refined_to(strong), cal["gms"]) is not None
    assert tried == [("ls", "lugre")]


def test_a_hysteresis_whose_size_depends_on_the_law_is_the_law_s_misfit(monkeypatch):
    # clean LS-b data of the independent generator (seed 102, the corrected core): a hysteresis of
    # alpha 0.39 under LS came out 0.04 under LuGre and 0.24 under GMS; a true one 0.15-0.20
    alphas = {"lugre": 0.04, "gms": 0.24, "ls": 0.35}
    costs = {"lugre": 1.0, "gms": 1.0, "ls": 1.0}
    fitted = []

    def first(train, nominal, m, free, noise, nfev):
        fitted.append((m.law, m.params.normal_force_n, free.causes))
        e = Effects(hysteresis_alpha=alphas[m.law], hysteresis_width_m=1e-6)
        return Model(m.params, e, law=m.law, causes=free.causes), costs[m.law]

    monkeypatch.setattr(PL, "first_stage_model", first)
    s, _, _ = _session()
    s.ex = _Now()
    _calibrated(s)
    e = Effects(hysteresis_alpha=0.39, hysteresis_width_m=3e-7)
    m = Model(BENT, e, law="ls", causes=("piezo_hysteresis",))
    f = FitResult(Free(("normal_force_n",), ("piezo_hysteresis",)), m, m.values(), 0.0, 0)
    chosen = Candidate(f, Evaluation(120e-9, 0, 3.6e6, 1000), 0.0)
    why = PL._law_dependence(s, chosen, "piezo_hysteresis")
    assert "0.39 under ls" in why and "0.04 under lugre" in why
    # fitted from each other law's calibration (its base values), the cause alone freed; past
    # LAW_SPREAD_TIGHT from the chosen law's calibration too, to compare the first stages' costs
    assert sorted(fitted) == [
        ("gms", BENT.normal_force_n, ("piezo_hysteresis",)),
        ("ls", BENT.normal_force_n, ("piezo_hysteresis",)),
        ("lugre", BENT.normal_force_n, ("piezo_hysteresis",)),
    ]
    fitted.clear()  # asked again of the same model: the answer kept, nothing fitted
    assert PL._law_dependence(s, chosen, "piezo_hysteresis") == why and fitted == []
    # independent GMS hysteresis 132: the law that reads the odd size cannot carry the cause
    # (LuGre's first stage 2.2 x LS's): left out, the others agree within 2 x (0.39 and 0.24)
    costs.update(lugre=2.2, gms=1.2)
    s.law_spread.clear()
    assert PL._law_dependence(s, chosen, "piezo_hysteresis") == ""
    costs.update(lugre=1.9)  # within LAW_FIT_RATIO of the best: it reads the size
    s.law_spread.clear()
    assert "0.04 under lugre" in PL._law_dependence(s, chosen, "piezo_hysteresis")
    costs.update(lugre=1.0, gms=1.0)
    alphas.update(lugre=0.2, gms=0.3)  # within 2 x of 0.39
    s.law_spread.clear()
    assert PL._law_dependence(s, chosen, "piezo_hysteresis") == ""
    alphas.update(lugre=0.3, gms=0.35)  # within LAW_SPREAD_TIGHT: no first stage of the chosen
    s.law_spread.clear()
    fitted.clear()
    assert PL._law_dependence(s, chosen, "piezo_hysteresis") == ""
    assert sorted(law for law, _, _ in fitted) == ["gms", "lugre"]
    fitted.clear()  # a cause the law's presliding cannot make: not checked, nothing fitted
    assert PL._law_dependence(s, chosen, "external_load") == ""
    assert fitted == []


def test_a_base_s_law_test_keeps_the_cheaper_of_its_fits_from_calibration_and_from_nominal(
    monkeypatch,
):
    # independent GMS seed 133, a true base at 4.07 kHz: from LuGre's calibration, which had taken
    # up the missing base with the contact's and the stack's parameters, the base stopped at 11.9
    # kHz and was refused; from LuGre's nominal parameters it reached 4.05 kHz at a first-stage
    # cost 7.2 x lower, as the screen fits a first base (catalog.FIT_FROM_NOMINAL)
    freq = {("lugre", "cal"): 11.9e3, ("lugre", "nom"): 4.05e3, ("gms", "cal"): 4.1e3}
    freq[("gms", "nom")] = 13.9e3  # seed 104's GMS from nominal: the costlier start here
    cost = {("lugre", "cal"): 7.2, ("lugre", "nom"): 1.0, ("gms", "cal"): 1.0, ("gms", "nom"): 3.0}
    fitted = []

    def first(train, nominal, m, free, noise, nfev):
        start = "nom" if m.params.normal_force_n == NOMINAL.normal_force_n else "cal"
        fitted.append((m.law, start, m.params.piezo_damping_kg_per_s))
        e = Effects(base_mass_kg=0.048, base_freq_hz=freq[(m.law, start)], base_damping_ratio=0.05)
        return Model(m.params, e, law=m.law, causes=free.causes), cost[(m.law, start)]

    monkeypatch.setattr(PL, "first_stage_model", first)
    s, _, _ = _session()
    s.ex = _Now()
    _calibrated(s)
    e = Effects(base_mass_kg=0.049, base_freq_hz=4.09e3, base_damping_ratio=0.04)
    m = Model(BENT, e, law="ls", causes=("base_compliance",))
    f = FitResult(Free(("normal_force_n",), ("base_compliance",)), m, m.values(), 0.0, 0)
    chosen = Candidate(f, Evaluation(120e-9, 0, 3.6e6, 1000), 0.0)
    assert PL._law_dependence(s, chosen, "base_compliance") == ""  # 4.05 and 4.1 kHz kept
    # each other law from its calibration (BENT's damping) and from its nominal values
    damping = {"cal": BENT.piezo_damping_kg_per_s, "nom": NOMINAL.piezo_damping_kg_per_s}
    assert sorted(fitted) == sorted(
        (law, start, damping[start]) for law in ("lugre", "gms") for start in ("cal", "nom")
    )
    cost[("lugre", "cal")] = 0.5  # the calibration's basin cheaper: 11.9 kHz kept, refused
    # (past LAW_SPREAD_TIGHT the chosen law's first stages too: none costs above 2 x LuGre's)
    freq.update({("ls", "cal"): 4.09e3, ("ls", "nom"): 4.09e3})
    cost.update({("ls", "cal"): 1.0, ("ls", "nom"): 1.0})
    s.law_spread.clear()
    assert "1.19e+04 under lugre" in PL._law_dependence(s, chosen, "base_compliance")


def test_a_strong_first_cause_that_fails_only_the_left_out_families_is_judged_under_each_other_law(
    monkeypatch,
):
    # independent load seed 101: 88 % of the LS calibration's error, worse on the 1 000 Hz runs
    # left out; from LuGre's calibration the load reaches 3.9 nm
    rmse = {"lugre": 4e-9, "gms": 150e-9}
    starts = []

    def fitted(train, val, nominal, m, free, noise, nfev, polish, grid):
        starts.append((m.law, m.params.normal_force_n, m.effects.load_n, free.causes, grid))
        r, m = rmse[m.law], Model(m.params, m.effects, law=m.law, causes=free.causes)
        return FitResult(free, m, m.values(), r, 0), Evaluation(r, 0, (r / 2e-9) ** 2 * 1000, 1000)

    monkeypatch.setattr(SE, "fit_and_validate", fitted)
    s, _, _ = _session()
    s.ex = _Now()
    cal = _calibrated(s)
    m = Model(BENT, Effects(load_n=0.12), law="ls", causes=("external_load",))
    f = FitResult(Free(("normal_force_n",), ("external_load",)), m, m.values(), 0.0, 0)
    cand = Candidate(f, Evaluation(190e-9, 0, 9e6, 1000), 0.0, parent=cal["ls"])
    cand.verdict = Verdict(share=0.88, folds=[FoldResult("1000 Hz", 1.0, 6.1, 10)])
    cand.verdict.reasons.append("predicts left-out run families worse")
    alt = s.under_other_law(cand, cal["ls"])
    assert alt is not None and alt.law == "lugre" and alt.parent is cal["lugre"]
    assert alt.causes == ("external_load",)
    assert sorted(starts) == [
        ("gms", BENT.normal_force_n, 0.12, ("external_load",), False),
        ("lugre", BENT.normal_force_n, 0.12, ("external_load",), False),
    ]
    # not when it carries less than a kept cause needs, failed before the cross-validation, or
    # is not a first cause
    for v in (
        Verdict(share=0.7, folds=cand.verdict.folds),
        Verdict(share=0.88, in_range=False),
    ):
        cand.verdict = v
        assert s.under_other_law(cand, cal["ls"]) is None
    cand.verdict = Verdict(share=0.88, folds=[FoldResult("1000 Hz", 1.0, 6.1, 10)])
    assert s.under_other_law(cand, cand) is None  # cand as a parent: it has a cause
    # no other law fits it better than that law's own calibration
    rmse.update(lugre=250e-9, gms=300e-9)
    assert s.under_other_law(cand, cal["ls"]) is None


def test_the_batch_after_a_failed_first_round_fits_only_causes_that_could_carry_their_share():
    """pipeline._select: when every first candidate fails, the next pending causes are fitted
    only if the screen predicts they could carry what the final check demands (could_carry);
    clean LS-b 101 fitted a position and a base screened at 15 % and 12 %, 17 s of 60."""
    n = 1000
    points = {
        "position_dependent_friction": {"friction_gradient_per_m": 300.0},
        "external_load": {"load_n": 0.2},
        "asymmetric_friction": {"friction_asymmetry": 0.05},
    }

    def cause(name: str, mse: float) -> Screened:  # the base at 100 noise variances
        return Screened(name, points[name], mse * n, n, 100.0 * n, 1.0)

    weak, strong, weaker = (
        cause("position_dependent_friction", 85.0),  # 15 %
        cause("external_load", 50.0),  # 49 %: predicted unexplained, 80 % due, 40 % screened
        cause("asymmetric_friction", 88.0),  # 12 %
    )
    s, ex, base = _session()
    s.pending[id(base)] = (base, [weak, strong, weaker])
    s.fit_pending(base, carrying=True)
    assert len(ex.jobs) == 1  # the load alone
    assert s.pending[id(base)][1] == [weak, weaker]  # kept pending, in their order
    s.fit_pending(base, carrying=True)
    assert len(ex.jobs) == 1  # nothing left that could carry: no fit
    s.fit_pending(base)  # without the gate (a first batch) both are fitted
    assert len(ex.jobs) == 3 and s.pending[id(base)][1] == []


def test_first_causes_are_fitted_from_nominal_when_the_calibration_predicts_worse_than_it():
    # own load + hysteresis 102: the calibrations predicted the left-out runs at 2.05-2.71 um,
    # nominal at 1.83 um; the load fitted on them stopped at 1.2 um, from nominal at 167 nm
    load = Screened("external_load", {"load_n": 0.2}, 1.0, 10, 2.0, 1.0)
    for bent in (False, True):
        s, ex, base = _session()
        s.calibration_bent = bent
        s.pending[id(base)] = (base, [load])
        s.fit_pending(base)
        [(fn, args)] = ex.jobs
        if not bent:  # from the calibrated model, under its law (and the others' calibrations)
            assert fn is SE.fit_under_best_calibration
            assert args[3][0].params == BENT and args[3][0].law == "lugre"
            continue
        assert fn is SE.fit_under_best_law
        starts = args[3]
        assert [m.law for m, _, _ in starts] == list(LAWS)
        for m, free, grid in starts:
            assert m.params == NOMINAL and grid  # no probe at nominal: the cause's grid
            assert free == Free(("normal_force_n", f"{m.law}_only"), ("external_load",))
    # a further cause is fitted on its parent as before: the rule is for the first round only
    s, ex, base = _session()
    s.calibration_bent = True
    m = replace(base.fit.model, causes=("piezo_hysteresis",))
    fit = FitResult(Free((), m.causes), m, m.values(), 0.0, 0)
    child = Candidate(fit, base.val, 0.0, parent=base)
    s.pending[id(child)] = (child, [load])
    s.fit_pending(child)
    [(fn, _)] = ex.jobs
    assert fn is SE.fit_and_validate


def test_a_first_cause_whose_size_depends_on_the_law_is_refused_before_the_law_is_chosen_again(
    monkeypatch,
):
    # held-out clean GMS data, seed 127: a base at 4.56 kHz under LS read 15.1 and 17.3 kHz from
    # LuGre's and GMS's calibrations, and was refused for it after the law's re-choice (337 M model
    # steps) had kept LS. The test comes first now; where it passes, the re-choice goes on, and
    # with the law kept the test after it is this one, not fitted again.
    alphas = {"lugre": 0.04, "gms": 1e-9, "ls": 0.39}
    fitted, rechosen = [], []

    def first(train, nominal, m, free, noise, nfev):
        fitted.append(m.law)
        e = Effects(hysteresis_alpha=alphas[m.law], hysteresis_width_m=1e-6)
        return Model(m.params, e, law=m.law, causes=free.causes), 1.0

    e = Effects(hysteresis_alpha=0.39, hysteresis_width_m=3e-7)
    m = Model(BENT, e, law="ls", causes=("piezo_hysteresis",))
    f = FitResult(Free(("normal_force_n",), ("piezo_hysteresis",)), m, m.values(), 0.0, 0)
    unexplained = Evaluation(50e-9, 0, 625.0 * 1000, 1000)  # 25 x the noise, 94 % of LS's excess
    monkeypatch.setattr(PL, "first_stage_model", first)
    monkeypatch.setattr(SE, "fit_and_validate", lambda *args: (f, unexplained))  # the refinement
    monkeypatch.setattr(PL, "_rechoose_law", lambda s, c, laws=None: rechosen.append(c) or c)
    monkeypatch.setattr(PL, "_final_weakness", lambda s, c, cause, explained: ("", c))
    s, _, _ = _session()
    s.ex = _Now()
    cal = _calibrated(s)  # 200 nm under each law
    accepted = Candidate(f, unexplained, 0.0, cal["ls"], Verdict())
    assert PL._refined(s, accepted, cal["ls"]) is None
    # (past LAW_SPREAD_TIGHT, the chosen law's first stage beside the others' for their costs)
    assert rechosen == [] and sorted(fitted) == ["gms", "ls", "lugre"]
    assert "depends on the friction law" in accepted.verdict.reasons[-1]
    # within 2 x under every law: the law chosen again, and the test after it not fitted again
    alphas.update(lugre=0.3, gms=0.35)
    fitted.clear()
    accepted = Candidate(f, unexplained, 0.0, cal["ls"], Verdict())
    refined = PL._refined(s, accepted, cal["ls"])
    assert refined is not None and len(rechosen) == 1 and sorted(fitted) == ["gms", "lugre"]
    # a first cause that carries less than the final check's share is not tested before
    fitted.clear()
    weak = Evaluation(150e-9, 0, 5625.0 * 1000, 1000)  # 44 % of LS's excess
    monkeypatch.setattr(SE, "fit_and_validate", lambda *args: (f, weak))
    accepted = Candidate(f, weak, 0.0, cal["ls"], Verdict())
    assert PL._refined(s, accepted, cal["ls"]) is None
    assert len(rechosen) == 2 and fitted == []
    assert "accounts for only 44 %" in accepted.verdict.reasons[-1]


def test_a_first_cause_of_the_law_s_own_kind_that_keeps_its_size_under_every_law_needs_half(
    monkeypatch,
):
    # held-out independent hysteresis, seed 126 (a Prandtl-Ishlinskii loop of ratio 0.05): 76 % of
    # the LuGre calibration's error, alpha 0.12-0.14 under every law, every left-out family 4-100 x
    # better; dropped for the 80 % an unexplained model demands. A hysteresis or a base is put to
    # the law-dependence test instead and, passing it, needs the share any kept cause needs.
    alphas = {"lugre": 0.13, "gms": 0.12, "ls": 0.124}
    fitted = []

    def first(train, nominal, m, free, noise, nfev):
        fitted.append(m.law)
        e = Effects(hysteresis_alpha=alphas[m.law], hysteresis_width_m=1e-6)
        return Model(m.params, e, law=m.law, causes=free.causes), 1.0

    def refined_as(cause: str, ev: Evaluation) -> Candidate:
        e = Effects(hysteresis_alpha=0.124, hysteresis_width_m=1.5e-6, load_n=0.1)
        m = Model(BENT, e, law="ls", causes=(cause,))
        f = FitResult(Free(("normal_force_n",), (cause,)), m, m.values(), 0.0, 0)
        monkeypatch.setattr(SE, "fit_and_validate", lambda *args: (f, ev))  # the refinement
        return Candidate(f, ev, 0.0, cal["ls"], Verdict())

    monkeypatch.setattr(PL, "first_stage_model", first)
    monkeypatch.setattr(PL, "_rechoose_law", lambda s, c, laws=None: c)
    s, _, _ = _session()
    s.ex = _Now()
    cal = _calibrated(s)  # 200 nm under each law: 10 000 noise variances
    # the model without it, refitted from its point, no better than the calibration
    s.refit_without = lambda c, cause: _done(cal["ls"].fit, cal["ls"].val)
    share_76 = Evaluation(98e-9, 0, 2401.0 * 1000, 1000)  # 49 x the noise
    accepted = refined_as("piezo_hysteresis", share_76)
    refined = PL._refined(s, accepted, cal["ls"])
    assert refined is not None and sorted(fitted) == ["gms", "lugre"]
    # the final check holds it to the same test, asked once for the model
    fitted.clear()
    assert PL._final_weakness(s, refined, "piezo_hysteresis", explained=False)[0] == ""
    assert fitted == []
    # its size depends on the law: refused for that; and within the 2 x a cause that carries
    # 80 % may differ by, but not the 1.5 x asked of one that rests on this test
    for gms in (1e-9, 0.22):
        alphas.update(gms=gms)
        accepted = refined_as("piezo_hysteresis", share_76)
        assert PL._refined(s, accepted, cal["ls"]) is None
        assert "depends on the friction law" in accepted.verdict.reasons[-1]
    assert "at most 1.5 x where the cause carries less than 80 %" in accepted.verdict.reasons[-1]
    # a cause the law's presliding cannot make has no such test: the higher bar holds
    fitted.clear()
    accepted = refined_as("external_load", share_76)
    assert PL._refined(s, accepted, cal["ls"]) is None
    assert "accounts for only 76 %" in accepted.verdict.reasons[-1]
    assert "must account for 80 %" in accepted.verdict.reasons[-1] and fitted == []
    # under half, nothing is fitted: the share any kept cause needs is not there
    accepted = refined_as("piezo_hysteresis", Evaluation(150e-9, 0, 5625.0 * 1000, 1000))
    assert PL._refined(s, accepted, cal["ls"]) is None
    assert "accounts for only 44 %" in accepted.verdict.reasons[-1] and fitted == []


def test_a_first_cause_is_started_from_each_law_s_calibration_however_much_worse():
    # independent GMS creep 133: LuGre calibrated to 72.6 nm, GMS to 110 nm (clearly worse), so
    # the creep was screened and fitted on LuGre's alone (62 nm); from GMS's calibration it is
    # named at 15.7 nm. The parent's start and every other law's go to fit_under_best_calibration.
    load = Screened("external_load", {"load_n": 0.2}, 1.0, 10, 2.0, 1.0)
    s, ex, base = _session()
    cal = _calibrated(s)
    cal["gms"] = Candidate(cal["gms"].fit, Evaluation(400e-9, 0, 4e7, 1000), 0.0)
    parent = cal["lugre"]
    s.pending[id(parent)] = (parent, [load])
    s.fit_pending(parent)
    [(fn, args)] = ex.jobs
    assert fn is SE.fit_under_best_calibration
    (m, free), others = args[3], args[4]
    assert m.law == "lugre" and m.effects.load_n == 0.2
    assert free == Free(("normal_force_n", "lugre_only"), ("external_load",))
    assert sorted(mo.law for mo, _ in others) == ["gms", "ls"]
    for mo, fo in others:
        assert mo.params == BENT and mo.effects.load_n == 0.2  # its calibration, the start
        assert fo == Free(("normal_force_n", f"{mo.law}_only"), ("external_load",))
    # a further cause is fitted on its parent alone: the rule is for the first round only
    s, ex, base = _session()
    _calibrated(s)
    m = replace(base.fit.model, causes=("piezo_hysteresis",))
    child = Candidate(FitResult(Free((), m.causes), m, m.values(), 0.0, 0), base.val, 0.0, base)
    s.pending[id(child)] = (child, [load])
    s.fit_pending(child)
    [(fn, _)] = ex.jobs
    assert fn is SE.fit_and_validate


def _fit(law: str, effects: Effects, causes: tuple[str, ...], at_bound=()) -> FitResult:
    m = Model(BENT, effects, law=law, causes=causes)
    return FitResult(Free(("normal_force_n",), causes), m, m.values(), 0.0, 0, at_bound=at_bound)


def test_a_named_load_or_asymmetry_stands_only_when_its_twin_is_far_enough_worse(monkeypatch):
    # a load named under GMS (the README's first example: GMS contact, load of seed 3), its twin
    # the asymmetry; each fitted in the other's place from GMS's calibration, the same way
    s, _, _ = _session()
    s.ex = _Now()
    final = s.cand(
        _fit("gms", Effects(load_n=0.4), ("external_load",)), Evaluation(29.6e-9, 0, 1e5, 1000)
    )
    cal = _calibrated(s, 800e-9)
    points = {"asymmetric_friction": {"friction_asymmetry": 0.2}, "external_load": {"load_n": 0.3}}
    monkeypatch.setattr(
        s,
        "screen",
        lambda parent, causes: [Screened(c, points[c], 1e3, 1000, 1e8, 1.0) for c in causes],
    )
    fits = []
    rmse = {"external_load": 30.0e-9, "asymmetric_friction": 33.0e-9}
    asym = [0.25]
    at_bound: list[tuple[str, ...]] = [()]
    held = [90.1e-9]  # the asymmetry's left-out error held within its range (0.3 at most)

    def submit_fit(start, free, nfev, polish=False, grid=True):
        fits.append(
            (start.law, start.effects.friction_asymmetry, start.effects.load_n, free.causes)
        )
        if free.in_range:
            f = _fit("gms", Effects(friction_asymmetry=0.3), free.causes)
            return _done(f, Evaluation(held[0], 0, 1e5, 1000))
        e = (
            Effects(friction_asymmetry=asym[0])
            if free.causes[0] != "external_load"
            else Effects(load_n=0.4)
        )
        f = _fit("gms", e, free.causes, at_bound=at_bound[0])
        return _done(f, Evaluation(rmse[free.causes[0]], 0, 1e5, 1000))

    monkeypatch.setattr(s, "submit_fit", submit_fit)
    # within 3 x (33 against 30 nm, 15 x the noise): neither is named; the model is the best one
    # without the load: its refit without it from the final point (here), or the law's
    # calibration where that scores better
    without = s.cand(_fit("gms", Effects(), ()), Evaluation(900e-9, 0, 2e5, 1000))
    monkeypatch.setattr(s, "refit_without", lambda c, cause: _done(without.fit, without.val))
    got = PL._twins_separated(s, final)
    assert got.causes == () and got.val.rmse_m == 900e-9 and got is not cal["gms"]
    # both from GMS's calibration, each at its screened point
    assert fits == [
        ("gms", 0.0, 0.3, ("external_load",)),
        ("gms", 0.2, 0.0, ("asymmetric_friction",)),
    ]
    for c in ("external_load", "asymmetric_friction"):
        assert s.verdicts[c].reasons[0].startswith(PL.NOT_SEPARATED)
        assert not s.verdicts[c].confirmed
    # the twin 3 x better: it takes the cause's place, with the cause's verdict
    s.verdicts.clear()
    rmse["external_load"], rmse["asymmetric_friction"] = 90.1e-9, 30.0e-9
    got = PL._twins_separated(s, final)
    assert got.causes == ("asymmetric_friction",) and got.law == "gms"
    assert "replaced" in s.verdicts["external_load"].reasons[0]
    # the twin 3 x worse: the load stays, and its verdict says nothing
    s.verdicts.clear()
    rmse["external_load"], rmse["asymmetric_friction"] = 30.0e-9, 90.1e-9
    assert PL._twins_separated(s, final) is final
    assert not s.verdicts
    # where the law misfits (30 nm, 15 x the noise), a twin outside its physical range (0.32) or
    # at its fit's bound is refitted from where it ended held within its range, and compared so:
    # 3 x worse held, the load stays; within 3 x, neither is named; better held, still neither
    # (only the range guard holds it: never named)
    rmse["asymmetric_friction"] = 30.0e-9
    for a, b in ((0.32, ()), (0.25, ("friction_asymmetry",))):
        asym[0], at_bound[0], held[0] = a, b, 90.1e-9
        fits.clear()
        assert PL._twins_separated(s, final) is final and len(fits) == 3
        assert fits[2][1] == a  # from where it ended
        assert not s.verdicts
    held[0] = 60e-9
    assert PL._twins_separated(s, final).causes == ()
    assert "within 3 x" in s.verdicts["external_load"].reasons[0]
    assert "held within its range" in s.verdicts["external_load"].reasons[0]
    s.verdicts.clear()
    held[0] = 9e-9
    assert PL._twins_separated(s, final).causes == ()
    why = s.verdicts["external_load"].reasons[0]
    assert "held within it, predicts the left-out runs 3.33 x better" in why
    s.verdicts.clear()
    # where the law fits (10 nm, 5 x the noise) a twin out of its range is not refitted: the load
    # stays
    asym[0], at_bound[0] = 0.32, ()
    rmse["external_load"], rmse["asymmetric_friction"] = 10.0e-9, 10.0e-9
    fits.clear()
    assert PL._twins_separated(s, final) is final and len(fits) == 2
    asym[0] = 0.25
    # where the better twin is within 6 x the noise (2 nm here) the law fits and 1.15 x separates
    # them (1.18 x keeps the load, 1.12 x names neither); past it, 3 x (2.9 x names neither)
    rmse["external_load"], rmse["asymmetric_friction"] = 10.0e-9, 11.8e-9
    assert PL._twins_separated(s, final) is final
    rmse["asymmetric_friction"] = 11.2e-9
    assert PL._twins_separated(s, final).causes == ()
    assert "within 1.15 x" in s.verdicts["external_load"].reasons[0]
    s.verdicts.clear()
    rmse["external_load"], rmse["asymmetric_friction"] = 12.5e-9, 36.3e-9
    assert PL._twins_separated(s, final).causes == ()
    assert "within 3 x" in s.verdicts["external_load"].reasons[0]
    s.verdicts.clear()
    rmse["asymmetric_friction"] = 37.6e-9
    assert PL._twins_separated(s, final) is final
    # a cause without a twin, or a model that names both, is not refitted
    fits.clear()
    hyst = s.cand(
        _fit("gms", Effects(hysteresis_alpha=0.2), ("piezo_hysteresis",)),
        Evaluation(30e-9, 0, 1e5, 1000),
    )
    assert PL._twins_separated(s, hyst) is hyst and fits == []
    both = s.cand(
        _fit(
            "gms",
            Effects(load_n=0.4, friction_asymmetry=0.1),
            ("external_load", "asymmetric_friction"),
        ),
        Evaluation(30e-9, 0, 1e5, 1000),
    )
    assert PL._twins_separated(s, both) is both and fits == []


def test_a_cause_beside_twins_not_separated_stays_only_if_it_stands_beside_the_other(monkeypatch):
    # LS-b load 157: a load and a sensor scale error named; the load against the asymmetry in its
    # place is not separated (within 3 x). The sensor scale error was confirmed beside the load;
    # beside the asymmetry it must pass the final check again, or it goes too
    s, _, _ = _session()
    s.ex = _Now()
    _calibrated(s, 800e-9)
    both = ("external_load", "sensor_scale_error")
    final = s.cand(
        _fit("ls", Effects(load_n=0.3, sensor_scale_error=0.01), both),
        Evaluation(30e-9, 0, 1e5, 1000),
    )
    monkeypatch.setattr(
        s,
        "screen",
        lambda parent, causes: [Screened(c, points[c], 1e3, 1000, 1e8, 1.0) for c in causes],
    )
    points = {"asymmetric_friction": {"friction_asymmetry": 0.1}, "external_load": {"load_n": 0.3}}
    rmse = {"external_load": 30e-9, "asymmetric_friction": 40e-9}

    def submit_fit(start, free, nfev, polish=False, grid=True):
        e = Effects(friction_asymmetry=0.1, load_n=0.3, sensor_scale_error=0.01)
        return _done(_fit("ls", e, free.causes), Evaluation(rmse[free.causes[0]], 0, 1e5, 1000))

    monkeypatch.setattr(s, "submit_fit", submit_fit)
    removed = []

    def refit_without(c, cause):
        removed.append((c.causes, cause))
        rest = tuple(x for x in c.causes if x != cause)
        return _done(_fit("ls", Effects(), rest), Evaluation(50e-9 * (3 - len(rest)), 0, 2e5, 1000))

    monkeypatch.setattr(s, "refit_without", refit_without)
    checked = []
    why = ["accounts for only 49 % of the error left without it"]

    def final_weakness(s_, chosen, c, explained):
        checked.append((chosen.causes, c))
        return why[0], chosen

    monkeypatch.setattr(PL, "_final_weakness", final_weakness)
    got = PL._twins_separated(s, final)
    # checked beside the asymmetry, dropped: the model is the best one without both
    assert checked == [(("asymmetric_friction", "sensor_scale_error"), "sensor_scale_error")]
    assert got.causes == ()
    assert removed == [(both, "external_load"), (("sensor_scale_error",), "sensor_scale_error")]
    assert s.verdicts["sensor_scale_error"].reasons == [
        "dropped beside asymmetric_friction: accounts for only 49 % of the error left without it"
    ]
    # where it stands beside the asymmetry too, it stays (the load alone goes)
    s.verdicts.clear()
    removed.clear()
    why[0] = ""
    got = PL._twins_separated(s, final)
    assert got.causes == ("sensor_scale_error",) and removed == [(both, "external_load")]
    assert "sensor_scale_error" not in s.verdicts
