"""The Python API over the C core: validation, errors that say what is wrong, determinism."""

import math

import numpy as np
import pytest

from stickslip import _native as N
from stickslip.model import ActuatorParams, Sawtooth, friction_response, simulate


def test_binding_runs_the_same_code_as_the_host_simulator_default():
    # two runs, bit for bit the same
    a = simulate(Sawtooth(cycles=3))
    b = simulate(Sawtooth(cycles=3))
    assert np.array_equal(a.x_slider_m, b.x_slider_m)


@pytest.mark.parametrize(
    "field,value,message",
    [
        ("rod_mass_kg", -1.0, "out of range"),
        ("piezo_damping_kg_per_s", math.nan, "non-finite"),
        ("sigma0_n_per_m", math.inf, "non-finite"),
        ("mu_d", 0.5, "out of range"),  # Fc above Fs
    ],
)
def test_bad_parameters_are_rejected_by_name(field, value, message):
    p = ActuatorParams(**{field: value})
    with pytest.raises(N.NativeError, match=message) as e:
        simulate(Sawtooth(cycles=1), p)
    assert (field if field != "mu_d" else "Fc") in str(e.value)


@pytest.mark.parametrize(
    "kw",
    [{"rise_fraction": 1.0}, {"direction": 0}, {"frequency_hz": -1.0}, {"amplitude_v": math.nan}],
)
def test_bad_waveforms_are_rejected(kw):
    with pytest.raises(N.NativeError, match="waveform"):
        simulate(Sawtooth(cycles=1, **kw))


def test_sampled_drive_equals_sawtooth_sampled_on_the_step_grid():
    w = Sawtooth(cycles=2)
    r = simulate(w)
    s = simulate(drive_v=r.drive_v, drive_interval_s=1e-6)
    # the same drive at every step: the same trajectory, to float32 interpolation rounding
    assert np.max(np.abs(s.x_slider_m - r.x_slider_m)) < 1e-9


def test_from_dict_names_the_bad_key():
    d = ActuatorParams().to_dict()
    d["rod_mass_kg"] = "heavy"
    with pytest.raises(ValueError, match=r"actuator\.rod_mass_kg"):
        ActuatorParams.from_dict(d)
    d = ActuatorParams().to_dict()
    del d["mu_s"]
    with pytest.raises(ValueError, match="missing keys \\['mu_s'\\]"):
        ActuatorParams.from_dict(d)


def test_friction_response_rejects_nan_path():
    x = np.linspace(0, 1e-6, 10)
    x[5] = np.nan
    with pytest.raises(N.NativeError, match="non-finite"):
        friction_response(x, 1e-6)
