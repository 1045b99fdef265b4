"""Hidden-effect tests on data our code did not make: datasets from the independent generator
(stickslip.independent: float64, its own friction laws and effects, no code shared with lib/),
the issue's 13-run design at 250 kS/s, diagnosed blind.

- clean data from a law we do not have (Al-Bender's GMS, another reading of the LS paper) names
  no catalog effect: none, parameter_miscalibration or friction_law only;
- a hidden effect (slew limit, load, hysteresis) is the first catalog cause named (friction_law
  may come first: the contact is LuGre's, not LS's), with its strength recovered;
- two effects neither of which passes alone (a slew limit and an asymmetric friction) are named
  together;
- an effect outside the catalog is unexplained and names no catalog effect.

CI (scripts/test.sh, pytest -m "not full") runs clean LS-b, the slew limit, the load and the
periodic sensor error, one seed each: 4.6 of the 11.4 minutes all of them took under coverage on 2
cores. The sensor scale, hysteresis, thermal drift, base compliance and the cubic sensor errors
(the weak one the law absorbs, one above the position floor) are marked full (`pytest -m full`);
bench/diagnosis_cost.py --generator independent runs every case, clean GMS and LuGre contacts
included, over 5 seeds (BENCHMARKS.md)."""

from __future__ import annotations

import multiprocessing
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from stickslip import independent
from stickslip.dataset import load
from stickslip.diagnosis.catalog import CAUSES, LAW_PARAMS
from stickslip.diagnosis.fit import Free, Model, first_stage_model, prepare_all
from stickslip.diagnosis.pipeline import diagnose, noise_level, split_runs
from stickslip.diagnosis.screen import probe_points, probe_residual, refine_at_nominal

NOT_EFFECTS = {"none", "parameter_miscalibration", "friction_law"}
RATE_HZ = 250e3
SEED = 100
_DONE: dict = {}


@pytest.fixture(scope="module")
def executor():
    # spawned, not forked: a forked worker would inherit coverage's tracer (test_diagnosis.py)
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=2, mp_context=ctx) as ex:
        yield ex


def _run(tmp_path, law: str, effects: tuple[str, ...], executor, seed: int = SEED):
    key = (law, effects, seed)
    if key not in _DONE:
        rng = np.random.default_rng(seed)
        drawn = {e: independent.draw_effect(e, rng) for e in effects}
        path = tmp_path / "ds"
        truth = independent.generate(
            path, law=law, effects=drawn, seed=seed, sample_rate_hz=RATE_HZ
        )
        _DONE[key] = (truth, diagnose(path, executor=executor).to_json())
    return _DONE[key]


# CI: the ls_b reading (the outside test's own situation); GMS and LuGre run in the bench
@pytest.mark.parametrize("law", ["ls_b"])
def test_clean_data_of_another_law_names_no_effect(tmp_path, executor, law):
    _, j = _run(tmp_path, law, (), executor)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named == [], (j["causes"], [(c["name"], c.get("guards")) for c in j["candidates"][:3]])
    # every candidate that would have reduced the error says why it was not named
    for c in j["candidates"]:
        if c["name"] in CAUSES and c.get("guards"):
            assert not c["confirmed"] and c["guards"]["reasons"]


@pytest.mark.full
def test_a_pair_that_takes_up_the_laws_misfit_is_not_named(tmp_path, executor):
    # held-out clean LS-b seed 118: with no cause passing alone, a base compliance (4.0 kHz) with a
    # slew limit beside it took the LS calibration's 298 nm to 66 nm and passed the pair's guards;
    # the base read from the other laws' calibrations is 10.8 and 4.6 kHz: the law's misfit
    _, j = _run(tmp_path, "ls_b", (), executor, seed=118)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named == [], j["causes"]
    assert j["unexplained"]


def test_slew_limit_is_found_where_the_outside_test_missed_it(tmp_path, executor):
    # the outside test's miss: a slew limit fitted to 3 % but ranked fifth behind a base model
    # calibrated to N = 22 N
    # (seed 102: 0.388 V/us, the slowest of seeds 100-104, whose bandwidth the final model keeps)
    truth, j = _run(tmp_path, "lugre", ("amplifier_slew_limit",), executor, seed=102)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named[:1] == ["amplifier_slew_limit"], j["causes"]
    p, want = j["extended"]["params"], truth["effects"]["amplifier_slew_limit"]
    assert p["amplifier_slew_limit.slew_v_per_s"] == pytest.approx(want["slew_v_per_s"], rel=0.05)
    assert j["gain"] > 0.9
    # the amplifier's bandwidth behind the slew, fitted in the final model: within a factor of 2
    # of the generator's 160 kHz. Its rounding of the slewed edge's corners lasts about tau =
    # 1 us, the model's step, which biases it (161 kHz here, 208 kHz on seed 101; on seed 100 the
    # same refit without it gains as much, and it is not kept: BENCHMARKS.md, "The amplifier's
    # bandwidth in the final model")
    bw = p.get("amplifier_slew_limit.amp_bandwidth_hz")
    assert bw is not None and 0.5 < bw / want["bandwidth_hz"] < 2.0, p
    assert not j["unexplained"]  # 2.66 x the noise with it, 4.8 x without


@pytest.mark.full
@pytest.mark.parametrize(
    "effect", ["thermal_drift", "position_dependent_friction", "piezo_hysteresis"]
)
def test_a_single_effect_on_a_gms_contact_is_named(tmp_path, executor, effect):
    # a GMS contact (the generator's default law). The thermal drift: our GMS without
    # micro-damping and with a fixed presliding curve calibrated to 70-200 x the noise there, and
    # it was `none` (BENCHMARKS.md, "GMS with micro-damping and a calibrated presliding shape").
    # The position (+1 044 /m, the normal force up 68 % over the long run): probed at 300 /m
    # alone, the screen put it at 205 nm against the calibration's 319 nm, it was never fitted,
    # and a thermal drift at 98 nm was named; probed over its grid of gradients it is fitted.
    # The hysteresis: alpha 0.216 / 0.152 / 0.0435 under GMS / LS / LuGre, refused as the laws'
    # misfit (4.97 x) until the law test left out LuGre, whose first stage with it costs 3.5 x
    # GMS's (pipeline.LAW_FIT_RATIO)
    _, j = _run(tmp_path, "gms", (effect,), executor, seed=132)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named[:1] == [effect], j["causes"]


def test_external_load_is_named_first(tmp_path, executor):
    truth, j = _run(tmp_path, "lugre", ("external_load",), executor)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named[:1] == ["external_load"], j["causes"]
    got = j["extended"]["params"]["external_load.load_n"]
    assert got == pytest.approx(truth["effects"]["external_load"]["load_n"], rel=0.1)


@pytest.mark.full
def test_slew_limit_and_asymmetry_are_named_together(tmp_path, executor):
    # seed 103: the asymmetry's twin, the load, fitted in its place from the chosen law's
    # calibration the same way, predicts the left-out runs 3.1 x worse (pipeline._twins_separated)
    truth, j = _run(
        tmp_path, "lugre", ("amplifier_slew_limit", "asymmetric_friction"), executor, seed=103
    )
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert sorted(named) == ["amplifier_slew_limit", "asymmetric_friction"], j["causes"]
    p, e = j["extended"]["params"], truth["effects"]
    want = e["amplifier_slew_limit"]["slew_v_per_s"]
    assert p["amplifier_slew_limit.slew_v_per_s"] == pytest.approx(want, rel=0.02)
    want = e["asymmetric_friction"]["asymmetry"]
    assert p["asymmetric_friction.friction_asymmetry"] == pytest.approx(want, rel=0.25)


@pytest.mark.full
def test_a_load_and_an_asymmetry_the_runs_do_not_separate_are_neither_named(tmp_path, executor):
    # seed 100: the slew (1.1497 V/us against 1.1501) and an asymmetry of -6.3 %; fitted in each
    # other's place from the chosen law's calibration, the load and the asymmetry predict the
    # left-out runs within 1.17 x of each other: the slew is named, and both twins' verdicts say
    # that these runs do not tell them apart (before, the pair was named, the asymmetry at -5.4 %)
    truth, j = _run(tmp_path, "lugre", ("amplifier_slew_limit", "asymmetric_friction"), executor)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named == ["amplifier_slew_limit"], j["causes"]
    want = truth["effects"]["amplifier_slew_limit"]["slew_v_per_s"]
    assert j["extended"]["params"]["amplifier_slew_limit.slew_v_per_s"] == pytest.approx(
        want, rel=0.02
    )
    reasons = {c["name"]: c.get("guards", {}).get("reasons", []) for c in j["candidates"]}
    for twin in ("external_load", "asymmetric_friction"):
        assert any(r.startswith("not separated from") for r in reasons[twin]), reasons[twin]


@pytest.mark.full
def test_sensor_scale_error_is_named_first(tmp_path, executor):
    # the calibrated LuGre law takes a -4.4 % scale as a stronger contact (66 nm left); the
    # screen on that bent model credited the scale with 4 % of the error and it was never
    # fitted, until the scale was probed at both signs with the base at nominal. Fitted, it
    # comes within 0.2 % of the generator's value and explains the data (1.6 nm, 2 nm noise)
    truth, j = _run(tmp_path, "lugre", ("sensor_scale_error",), executor)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named[:1] == ["sensor_scale_error"], j["causes"]
    assert not j["unexplained"]
    got = j["extended"]["params"]["sensor_scale_error.sensor_scale_error"]
    want = truth["effects"]["sensor_scale_error"]["scale_error"]
    assert got == pytest.approx(want, rel=0.05)


def test_sensor_error_outside_the_catalog_is_unexplained(tmp_path, executor):
    _, j = _run(tmp_path, "lugre", ("sensor_periodic_error",), executor)
    assert j["unexplained"]
    assert [c for c in j["causes"] if c not in NOT_EFFECTS] == [], j["causes"]


@pytest.mark.full
def test_piezo_hysteresis_is_named_first(tmp_path, executor):
    # a Prandtl-Ishlinskii stack, not our Bouc-Wen: found only since both keep the nominal
    # stroke over the 100 V loop (model.major_loop_gain; it was missed at 600 nm RMS before)
    _, j = _run(tmp_path, "lugre", ("piezo_hysteresis",), executor)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named[:1] == ["piezo_hysteresis"], j["causes"]
    assert j["gain"] > 0.5


@pytest.mark.full
def test_thermal_drift_is_named_first(tmp_path, executor):
    # the generator's runs follow one another and the contact stays warm from one to the next
    # (50 V starts at its hottest); with every run started cold the fit predicted the 50 V and
    # 75 V runs 2.4 and 3.7 x worse than the law alone, and it was missed on 5 seeds of 5
    truth, j = _run(tmp_path, "lugre", ("thermal_drift",), executor)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named[:1] == ["thermal_drift"], j["causes"]
    assert not j["unexplained"]
    # its strength per joule of heat: the generator's beta / C (friction times 1 - beta T,
    # T = heat / C), and its time constant. Both heat the contact by the friction's power on
    # the relative motion, F v (docs/effects.md): seed 100 gives 201 /J against 204 /J and
    # 38.3 ms against 36.7 ms. When ours took F^2 / 2 sigma0 off each step and counted a
    # negative step as 0, it stored 12-15 % more heat and the fit gave 170 /J
    th = truth["effects"]["thermal_drift"]
    p = j["extended"]["params"]
    want = th["beta_per_k"] / th["heat_capacity_j_per_k"]
    assert p["thermal_drift.thermal_coeff_per_j"] == pytest.approx(want, rel=0.05)
    assert p["thermal_drift.thermal_tau_s"] == pytest.approx(th["tau_s"], rel=0.1)


@pytest.mark.full
def test_base_compliance_is_named_first_with_its_resonance(tmp_path, executor):
    # the calibration mimics a missing base by the piezo damping (42 kg/s against 6.2) and a
    # halved contact stiffness; fitted on top of that the base stopped at 261 nm and was missed
    # on 4 seeds of 5. From the nominal parameters and the best of its frequency grid it lands
    # on the generator's resonance. Since the stack's damper acts alike on rod and base (as the
    # generator's does, docs/effects.md) the model explains the data (2.5 nm, 1.2 x the noise;
    # 6.6 nm before, with the piezo damping pulled from 6.2 to 0.9 kg/s to make up for the
    # one-sided damper): seed 100 gives 4562 Hz (truth 4573), 37.9 g (38.3), damping ratio 0.041
    # (0.043) and a piezo damping of 5.4 kg/s. The bounds leave room for the 1 us step's error on
    # the base's ringing (20 nm RMS at the truth's parameters, 1 nm at 0.125 us)
    truth, j = _run(tmp_path, "lugre", ("base_compliance",), executor)
    named = [c for c in j["causes"] if c not in NOT_EFFECTS]
    assert named[:1] == ["base_compliance"], j["causes"]
    assert not j["unexplained"]
    b, p = truth["effects"]["base_compliance"], j["extended"]["params"]
    assert p["base_compliance.base_freq_hz"] == pytest.approx(b["base_freq_hz"], rel=0.01)
    assert p["base_compliance.base_mass_kg"] == pytest.approx(b["base_mass_kg"], rel=0.03)
    assert p["base_compliance.base_damping_ratio"] == pytest.approx(b["damping_ratio"], rel=0.1)
    assert p["piezo_damping_kg_per_s"] == pytest.approx(6.2, rel=0.2)


@pytest.mark.full
def test_weak_sensor_error_the_law_absorbs_names_no_effect(tmp_path, executor):
    # a cubic sensor nonlinearity (outside the catalog): the calibrated LuGre law leaves 2.6 x
    # the noise, where a thermal drift and a position-dependent friction each explained most of
    # the rest and the drift was named; within 3 x the noise no cause is sought
    _, j = _run(tmp_path, "lugre", ("sensor_cubic",), executor)
    assert [c for c in j["causes"] if c not in NOT_EFFECTS] == [], j["causes"]
    assert all(c.get("screened_only") for c in j["candidates"] if c["name"] in CAUSES)


@pytest.mark.full
def test_sensor_error_above_the_floor_is_unexplained(tmp_path, executor):
    # the same cubic sensor error at 0.5-2 um over the travel (0.07-0.28 %: a capacitive gauge's
    # or an LVDT's linearity; the position floor is 0.05 %) as bench/diagnosis_bench.py draws it
    # (outside_sensor_cubic_above_floor): seed 100 is 1.39 um over 0.72 mm; the diagnosis leaves
    # 71 x the noise and names no catalog cause (BENCHMARKS.md: seeds 100-107, 69-77 x)
    rng = np.random.default_rng(SEED)
    drawn = {"sensor_cubic": independent.draw_effect("sensor_cubic", rng)}
    drawn["sensor_cubic"]["amplitude_m"] = rng.uniform(0.5e-6, 2e-6)
    path = tmp_path / "ds"
    independent.generate(path, law="lugre", effects=drawn, seed=SEED, sample_rate_hz=RATE_HZ)
    j = diagnose(path, executor=executor).to_json()
    assert [c for c in j["causes"] if c not in NOT_EFFECTS] == [], j["causes"]
    assert j["unexplained"]


def _fit_inputs(tmp_path, law: str, effects: tuple[str, ...], seed: int):
    """An independent dataset as the diagnosis fits it: (truth, dataset, training runs,
    validation runs, noise in m), for the tests that call the fits and probes directly."""
    rng = np.random.default_rng(seed)
    drawn = {e: independent.draw_effect(e, rng) for e in effects}
    path = tmp_path / f"ds_{law}_{'+'.join(effects)}_{seed}"
    truth = independent.generate(path, law=law, effects=drawn, seed=seed, sample_rate_hz=RATE_HZ)
    ds = load(path)
    runs = prepare_all(ds.runs)
    train, val = split_runs(runs)
    _, noise, _ = noise_level(ds, runs)
    return truth, ds, train, val, noise


@pytest.mark.parametrize("seed", [105, 118])
def test_a_sharp_base_resonance_is_fitted_in_its_own_basin(tmp_path, seed):
    # held-out seed 105: a base at 7.9 kHz and 28 g, damped 0.028. The cost has a basin per pair
    # of mass and frequency; with the mass's grid in factors of 2 the best start was 20 g at
    # 11 kHz, and the fit stopped in the next basin (32.6 g, 11.5 kHz), which the cross-validation
    # then refused (catalog.py). Held-out seed 118: 7.3 kHz and 44.7 g, damped 0.042, above the
    # grid's 40 g of the time; the diagnosis fitted it at 134 g and 9.7 kHz and refused it. The
    # first stage alone, from nominal LuGre (the generator's law) with its base parameters free
    # and the grid, as the diagnosis fits a first base: the frequency within 1 %.
    truth, ds, train, _, noise = _fit_inputs(tmp_path, "lugre", ("base_compliance",), seed)
    b = truth["effects"]["base_compliance"]
    assert b["base_freq_hz"] > 7000.0 and b["damping_ratio"] < 0.05  # the sharp case in question
    start = Model(ds.actuator, law="lugre")
    free = Free(LAW_PARAMS["lugre"], ("base_compliance",))
    m, _ = first_stage_model(train, ds.actuator, start, free, noise)
    assert m.effects.base_freq_hz == pytest.approx(b["base_freq_hz"], rel=0.01)
    assert m.effects.base_mass_kg == pytest.approx(b["base_mass_kg"], rel=0.1)


def _nominal_probes(tmp_path, cause: str, law: str, effects: tuple[str, ...], seed: int):
    """Per-cycle cost (validation runs) of a cause's grid probes on nominal LuGre, the point and
    cost the search along its refined parameter finds (None: nothing better than the grid), and
    the dataset's truth."""
    truth, ds, _, val, noise = _fit_inputs(tmp_path, law, effects, seed)
    m = Model(ds.actuator, law="lugre")
    pts = probe_points(cause)

    def cost(v):
        return float(np.sum(probe_residual(val, m, cause, v, noise, True) ** 2))

    costs = [cost(v) for v in pts]
    found = refine_at_nominal(val, m, cause, pts, costs, noise)
    return min(costs), found, (cost(found) if found is not None else None), truth


def test_a_base_between_the_grid_frequencies_is_probed_at_its_resonance(tmp_path):
    # held-out seed 161: a mount of 21 g at 5.45 kHz damped at 3.9 %, between the frequency grid's
    # 5.0 and 6.5 kHz (30 % apart; the resonance is 8 % wide). Screened on the grid it took 0 % of
    # LS's calibrated error and the diagnosis answered `none`. Searched between the grid's
    # neighbours of the best nominal probe (nominal LuGre, the generator's law), the resonance
    # comes within 2 % and the probe costs less than a tenth of the grid's best.
    best, found, at_found, truth = _nominal_probes(
        tmp_path, "base_compliance", "lugre", ("base_compliance",), 161
    )
    f_true = truth["effects"]["base_compliance"]["base_freq_hz"]
    assert 5000.0 * 1.05 < f_true < 6500.0 / 1.05  # between the grid's points, off both
    assert found is not None
    assert found["base_freq_hz"] == pytest.approx(f_true, rel=0.02)
    assert at_found < 0.1 * best


def test_a_wide_hysteresis_loop_is_probed_at_its_size(tmp_path):
    # held-out seed 106: a loop 14.8 % of the stroke wide. The screen's probes at nominal take
    # the amplitude's start (alpha 0.05, a loop a few times narrower): the best of them was 11 %
    # below no hysteresis at all, and the calibrations' absorbed loop was all the screen saw
    # (named friction_law). Searched along the amplitude, the probe at nominal LuGre (the
    # generator's law) costs 7 x less than the grid's best, at alpha 0.32: where the full fit
    # from nominal LuGre ends (0.324). A quarter of the grid's best and alpha above 0.15 (a loop
    # three times the start's) leave room for the search's 5 % bracket.
    best, found, at_found, _ = _nominal_probes(
        tmp_path, "piezo_hysteresis", "lugre", ("piezo_hysteresis",), 106
    )
    assert found is not None and found["hysteresis_alpha"] > 0.15, found
    assert at_found < 0.25 * best
    # clean data from the same law: no amplitude beats the grid's small start
    assert _nominal_probes(tmp_path, "piezo_hysteresis", "lugre", (), 106)[1] is None
    # clean data from another law (Al-Bender's GMS): a narrow loop takes up a little of the
    # presliding's different shape (15 % on this seed), never the loop's sevenfold
    best, found, at_found, _ = _nominal_probes(tmp_path, "piezo_hysteresis", "gms", (), 106)
    assert found is None or at_found > 0.5 * best
