"""GMS, the third friction law, through the Python API (docs/model.md, "GMS (third law)")."""

import dataclasses

import numpy as np
import pytest

from stickslip import _native as N
from stickslip.model import MODELS, ActuatorParams, Sawtooth, friction_response, simulate


def test_gms_is_a_model():
    assert MODELS == ("ls", "lugre", "gms")


def test_simulate_gms_steps_forward_and_back():
    fwd = simulate(Sawtooth(cycles=5), model="gms")
    rev = simulate(Sawtooth(cycles=5, direction=-1), model="gms")
    assert fwd.model == "gms"
    assert fwd.state_names == ("level_n", "elastic_n")
    # settled steps of the paper's drive: a few um forward, as much back
    assert 1e-6 < np.mean(fwd.per_cycle_steps()[2:]) < 4.4e-6
    assert -4.4e-6 < np.mean(rev.per_cycle_steps()[2:]) < -1e-6
    # the recorded states: the slip level never exceeds Fs, the elastic force never exceeds it
    fs = ActuatorParams().fs_n
    assert np.all(fwd.state_a <= fs * (1 + 1e-6)) and np.all(
        fwd.state_a >= ActuatorParams().fc_n * 0.99
    )
    assert np.max(np.abs(fwd.state_b)) <= fs * (1 + 1e-6)
    # it is a law of its own: neither LS nor LuGre
    for other in ("ls", "lugre"):
        assert not np.array_equal(
            simulate(Sawtooth(cycles=5), model=other).x_slider_m, fwd.x_slider_m
        )


def test_friction_response_gms_virgin_curve_and_saturation():
    p = ActuatorParams()
    fs, s0 = p.fs_n, p.sigma0_n_per_m
    x = np.linspace(0.0, 3 * fs / s0, 3001)  # 0.36 nm steps at 1 ms each: slow, g(v) = Fs
    f = friction_response(x, 1e-3, "gms")
    alpha = (2 * np.arange(1, 5) - 1) / 16  # the element shares of the slip level
    elastic = np.minimum.outer(s0 / 4 * x, alpha * fs).sum(axis=1)
    expect = elastic + p.sigma2_ns_per_m * np.diff(x, prepend=x[0]) / 1e-3
    assert np.max(np.abs(f - expect)) < 1e-5 * fs
    assert f[-1] == pytest.approx(fs, rel=1e-5)


def test_gms_presliding_shape_and_damping():
    """gms_decay reshapes the virgin curve (docs/model.md): at one Fs / sigma0 of travel the
    parabola's 0.75 Fs, more for a slower decay, less for a faster one; sigma1 damps the sticking
    contact, sigma1 v on top of the elastic force while every element sticks."""
    p = ActuatorParams()
    fs, s0 = p.fs_n, p.sigma0_n_per_m
    x = np.linspace(0.0, fs / s0, 1001)
    at = {d: friction_response(x, 1e-3, "gms", gms_decay=d)[-1] / fs for d in (0.25, 1.0, 4.0)}
    # (the damping and viscous forces at 0.36 um/s: (sigma1 + sigma2) v, below 1e-5 Fs)
    assert at[1.0] == pytest.approx(0.75, abs=1e-5)
    assert at[0.25] > at[1.0] > at[4.0]  # a slow decay stays stiff longer
    slow = friction_response(x[:11], 1e-3, "gms")  # 0.36 nm in 10 ms
    fast = friction_response(x[:11], 1e-6, "gms")  # ... in 10 us: 36 um/s
    dv = (x[1] - x[0]) * (1 / 1e-6 - 1 / 1e-3)
    damping = p.sigma1_ns_per_m + p.sigma2_ns_per_m  # micro-damping and viscous friction
    np.testing.assert_allclose(fast[1:] - slow[1:], damping * dv, rtol=1e-3)
    with pytest.raises(ValueError, match="gms_decay"):
        simulate(Sawtooth(cycles=1), model="gms", gms_decay=0.0)


def test_gms_stiffness_ratio():
    """gms_stiffness_ratio rho (docs/model.md, "Unequal stiffnesses"): stiffnesses in the ratio
    1 : rho : rho^2 : rho^3 summing to sigma0, break-away displacements in the same ratios as for
    equal stiffnesses; the virgin curve is sum_i min(k_i u, alpha_i Fs), computed here afresh
    (without micro-damping: the elastic part)."""
    p = dataclasses.replace(ActuatorParams(), sigma1_ns_per_m=0.0)
    fs, s0 = p.fs_n, p.sigma0_n_per_m
    x = np.linspace(0.0, 4 * fs / s0, 2001)
    rho = 0.4
    k = rho ** np.arange(4)
    k = s0 * k / k.sum()
    gap = (2 * np.arange(1, 5) - 1) / 16 * 4  # equal stiffnesses' break-aways at d = 1, in Fs/s0
    alpha = k * gap / np.sum(k * gap)
    f = friction_response(x, 1e-3, "gms", p, gms_stiffness_ratio=rho)
    elastic = np.minimum.outer(np.outer(x, k), alpha * fs).diagonal(axis1=1, axis2=2).sum(axis=1)
    expect = elastic + p.sigma2_ns_per_m * np.diff(x, prepend=x[0]) / 1e-3
    assert np.max(np.abs(f - expect)) < 1e-5 * fs
    # the same initial stiffness, a softer tail than equal stiffnesses
    equal = friction_response(x, 1e-3, "gms", p)
    assert f[1] == pytest.approx(equal[1], rel=1e-4)
    at = int(np.searchsorted(x, 1.5 * fs / s0))
    assert f[at] < equal[at] - 0.05 * fs
    assert f[-1] == pytest.approx(fs, rel=1e-5)
    with pytest.raises(ValueError, match="gms_stiffness_ratio"):
        simulate(Sawtooth(cycles=1), model="gms", gms_stiffness_ratio=30.0)


def test_gms_has_no_fixed_point_variant():
    with pytest.raises(N.NativeError, match="friction_model"):
        simulate(Sawtooth(cycles=1), model="gms", variant="q")


def test_unknown_model_is_refused():
    with pytest.raises(ValueError, match="gms"):
        simulate(Sawtooth(cycles=1), model="maxwell")
