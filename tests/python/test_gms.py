"""GMS, the third friction law, through the Python API (docs/model.md, "GMS (third law)")."""

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


def test_gms_has_no_fixed_point_variant():
    with pytest.raises(N.NativeError, match="friction_model"):
        simulate(Sawtooth(cycles=1), model="gms", variant="q")


def test_unknown_model_is_refused():
    with pytest.raises(ValueError, match="gms"):
        simulate(Sawtooth(cycles=1), model="maxwell")
