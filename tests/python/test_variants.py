"""The float (f32) and fixed-point (q) cores through the bindings: the same runs agree within the
issue's tolerance on the shared drive vectors, and the same behavioural properties hold for both."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from stickslip.model import Effects, Sawtooth, simulate

VECTORS = Path(__file__).resolve().parents[1] / "vectors"


def _drives() -> list[dict]:
    with open(VECTORS / "fixed_model_drives.csv") as f:
        rows = [line for line in f if not line.startswith("#")]
    return list(csv.DictReader(rows))


@pytest.mark.parametrize(
    "d", _drives(), ids=lambda d: "{frequency_hz}Hz-{amplitude_v}V-{model}".format(**d)
)
def test_q_steps_follow_f32(d):
    w = Sawtooth(
        float(d["frequency_hz"]),
        float(d["amplitude_v"]),
        0.0,
        float(d["rise_fraction"]),
        1,
        int(d["cycles"]),
    )
    f = simulate(w, model=d["model"], variant="f32").per_cycle_steps()
    q = simulate(w, model=d["model"], variant="q").per_cycle_steps()
    # 1 % of each step; where steps are tiny (100 Hz: the slow fall lets the slider follow the
    # rod back) 1 % of 0.2 % of the stroke (0.044 nm at 50 V), a third of the float core's own
    # discretisation error there (its 1 us step against 0.125 us: 0.12-0.33 nm a cycle at 50 V).
    # On such cycles q and f32 scatter by 0.004-0.16 nm (50-200 Hz, 50 and 100 V, measured with
    # and without LS's turn inside a step alike): rounding that decides the odd sign of a
    # velocity near 0 in a stick phase. 0.1 % of the stroke (0.022 nm) sat on that scatter
    stroke = 4.4e-8 * float(d["amplitude_v"])
    tol = float(d["step_tol_rel"]) * np.maximum(np.abs(f[1:]), 2e-3 * stroke)
    assert np.all(np.abs(q[1:] - f[1:]) <= tol), q - f


@pytest.mark.parametrize(("f_hz", "cycles"), [(2000.0, 12), (500.0, 8), (100.0, 4)])
@pytest.mark.parametrize("direction", [1, -1])
def test_q_takes_the_turns_inside_a_step_as_f32_does(f_hz, cycles, direction):
    # a 15 us fall rings the rod (69 kHz): the relative motion turns inside a step some 70 times
    # a cycle, and LS takes each turn where it happened (docs/model.md). q follows f32 within
    # 0.001-0.005 % of a cycle's step; with q's turn switched off it lagged by 0.006-0.054 %
    w = Sawtooth(f_hz, 100.0, 0.0, 0.95, direction, cycles).with_fall_time(15e-6)
    f = simulate(w, model="ls", variant="f32").per_cycle_steps()[1:]
    q = simulate(w, model="ls", variant="q").per_cycle_steps()[1:]
    assert np.max(np.abs(q / f - 1)) < 1e-4


@pytest.mark.parametrize(
    ("dt_s", "f_hz", "cycles"), [(1e-6, 300.0, 6), (1.5e-6, 100.0, 4), (1.5e-6, 2000.0, 12)]
)
@pytest.mark.parametrize("law", ["ls", "lugre"])
def test_q_takes_the_drive_corners_inside_a_step_as_f32_does(dt_s, f_hz, cycles, law):
    # the 15 us fall's corners fall inside steps there (300 Hz at 1 us, every drive at 1.5 us); q
    # takes them by the rod's response to the anchor's triangle off the chord (docs/fixed-point.md),
    # f32 by the flow over each piece: within 0.0005-0.005 % a cycle of each other, measured; on
    # the chord q was 0.04-0.23 % off f32 there
    w = Sawtooth(f_hz, 100.0, 0.0, 0.95, 1, cycles).with_fall_time(15e-6)
    f = simulate(w, model=law, dt_s=dt_s, variant="f32").per_cycle_steps()[1:]
    q = simulate(w, model=law, dt_s=dt_s, variant="q").per_cycle_steps()[1:]
    n = min(len(f), len(q))
    assert n >= cycles - 2
    assert np.max(np.abs(q[:n] / f[:n] - 1)) < 1e-4


@pytest.mark.parametrize("variant", ["f32", "q"])
def test_properties_hold_for_both_variants(variant):
    # at rest under a zero-amplitude drive nothing moves
    r = simulate(Sawtooth(500.0, 0.0, 0.0, 0.95, 1, 3), variant=variant)
    assert np.max(np.abs(r.x_slider_m)) == 0.0
    # the reverse drive steps the other way, by a similar amount (the model is symmetric)
    fwd = simulate(Sawtooth(500.0, 100.0, 0.0, 0.95, 1, 6), variant=variant).per_cycle_steps()
    rev = simulate(Sawtooth(500.0, 100.0, 0.0, 0.95, -1, 6), variant=variant).per_cycle_steps()
    assert np.all(fwd[1:] > 0) and np.all(rev[1:] < 0)
    assert np.median(-rev[1:]) == pytest.approx(np.median(fwd[1:]), rel=0.05)
    # the faster the fall, the bigger the step (the paper's trend)
    steps = [
        simulate(Sawtooth(500.0, 100.0, 0.0, 0.95, 1, 4).with_fall_time(t), variant=variant)
        .per_cycle_steps()[1:]
        .mean()
        for t in (20e-6, 100e-6, 200e-6)
    ]
    assert steps[0] > steps[1] > steps[2]


def test_q_refuses_what_it_does_not_model():
    with pytest.raises(ValueError, match="effects.creep_ratio"):
        simulate(
            Sawtooth(cycles=1), variant="q", effects=Effects(creep_ratio=0.1, creep_tau_s=1e-2)
        )
    with pytest.raises(ValueError, match="sampled drive"):
        simulate(None, variant="q", drive_v=np.zeros(10), drive_interval_s=1e-5)
    with pytest.raises(ValueError, match="variant must be"):
        simulate(Sawtooth(cycles=1), variant="q16")


def test_cli_variant_q():
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "stickslip",
            "simulate",
            "--variant",
            "q",
            "--cycles",
            "4",
            "--json",
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert p.returncode == 0, p.stderr
    assert '"variant": "q"' in p.stdout


def test_q_takes_a_sampled_drive_one_sample_a_step():
    # the q core fed the player's samples (a q node's lock-step) is the player's run where no
    # corner falls inside a step: one period of the paper's drive, its corners within 2^-10 of a
    # step of q's grid
    w = Sawtooth(cycles=1)
    r = simulate(w, variant="q")
    dt_q = 1099512 * 2.0**-40  # Table I's dt_q40
    s = simulate(drive_v=r.drive_v, drive_interval_s=dt_q, variant="q")
    assert np.array_equal(s.x_slider_m, r.x_slider_m) and np.array_equal(s.force_n, r.force_n)
    # at another interval the samples would not be one a step: refused, naming the step
    with pytest.raises(ValueError, match="one sample a step: drive_interval_s must be its step"):
        simulate(drive_v=r.drive_v, drive_interval_s=1e-6 * 1.01, variant="q")
    with pytest.raises(ValueError, match="hold_s must be 0"):
        simulate(drive_v=r.drive_v, drive_interval_s=dt_q, variant="q", hold_s=1e-3)
