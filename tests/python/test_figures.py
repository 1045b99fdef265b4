"""Each figure's claim from the LS paper, asserted with numbers (docs/model.md gives the
tolerances' reasons)."""

import numpy as np
import pytest

from stickslip import figures as F
from stickslip.model import ActuatorParams

P = ActuatorParams.table1()


def test_fig03_steady_sliding_follows_stribeck_curve():
    c = F.stribeck_figure().claims
    # the level relaxes exponentially over 30 presliding lengths: e^-30 is far below float32
    assert c["max_rel_error_vs_g_plus_sigma2_v"] < 1e-4
    assert c["static_force_n"] == pytest.approx(P.fs_n, rel=1e-4)
    # the dip: friction falls from Fs towards Fc, then viscous friction lifts it again
    assert (
        c["minimum_force_n"]
        < P.fc_n + 0.05 * (P.fs_n - P.fc_n) + P.sigma2_ns_per_m * c["velocity_at_minimum_m_per_s"]
    )
    assert c["force_at_highest_velocity_n"] > c["minimum_force_n"]
    # from rest under slow acceleration the force rises towards Fs before it breaks away
    assert 0.95 * P.fs_n < c["ramp_peak_n"] <= P.fs_n * 1.001


def test_fig04_presliding_hysteresis():
    c = F.hysteresis_figure().claims
    assert c["loop_area_j"] > 0  # energy is dissipated on every loop
    # at the same displacement the rising and falling branches are far apart (> 10 % of Fs)
    assert c["force_gap_at_x0_n"] > 0.1 * P.fs_n


def test_fig05_07_lugre_drifts_ls_closes_its_loops():
    c = F.memory_figure().claims
    assert c["minor_loops"] >= 1
    # LS: a minor loop closes on the force where it began (wiping-out); what remains is the
    # viscous term sigma2 v at the closing instant (rate dependent by definition)
    assert c["ls_minor_loop_closure_error_n"] <= c["viscous_bound_n"] + 1e-4 * P.fs_n
    assert c["lugre_minor_loop_closure_error_n"] > 20 * c["ls_minor_loop_closure_error_n"]
    # period after period the LS curve repeats to float32 precision; LuGre's still moves
    assert c["ls_period_to_period_change_n"] < 1e-5 * P.fs_n
    assert c["lugre_period_to_period_change_n"] > 20 * c["ls_period_to_period_change_n"]


def test_fig08_09_rate_independence():
    c = F.rate_figure().claims
    # LS curves at 10, 100 and 1000 Hz differ by no more than the viscous term sigma2 v
    assert c["ls_max_deviation_n"] <= 1.01 * c["viscous_bound_n"] + 1e-4 * P.fs_n
    # LuGre's change by more than 5 % of Fs, and 10 x more than LS's
    assert c["lugre_max_deviation_n"] > 0.05 * P.fs_n
    assert c["lugre_max_deviation_n"] > 10 * c["ls_max_deviation_n"]


def test_fig13_staircase():
    c = F.actuator_figure().claims
    # each 4.4 um period moves the slider forward by a steady step smaller than the stroke
    assert 0.2 * c["stroke_m"] < c["mean_step_m"] < c["stroke_m"]
    assert c["step_spread_rel"] < 0.01
    # stick: late in the slow rise the slider moves with the rod (within 10 %)
    assert c["slider_over_rod_motion_late_rise"] == pytest.approx(1.0, abs=0.1)


def test_step_falls_with_slower_fall_edge():
    f = F.fall_time_figure()
    for steps in (f.step_ls_m, f.step_lugre_m):
        # faster fall, larger step, up to the slow falls where the slider is dragged back
        i_min = int(np.argmin(steps))
        assert np.all(np.diff(steps[: i_min + 1]) < 0)
        assert steps[0] > 0.85 * 4.4e-6
        assert steps[i_min] < 0
    c = f.claims
    # the rough check with Table I at 500 Hz: 20 us ~ 4 um, 100 us ~ 1.6 um, 200 us < 0
    assert c["step_ls_at_20us_m"] == pytest.approx(4e-6, rel=0.1)
    assert 1.0e-6 < c["step_ls_at_100us_m"] < 2.5e-6
    assert c["step_ls_at_200us_m"] < 0


def test_make_all_writes_pngs(tmp_path):
    claims = F.make_all(tmp_path)
    for name in F.FIGURES:
        png = tmp_path / f"{name}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert claims[name]
    assert (tmp_path / "figures.json").is_file()
