"""Property-based tests of the friction models and the actuator through the bindings: random
parameters inside the documented ranges (ss_friction.h, ss_actuator.h), random paths."""

import math

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from stickslip import _native as N
from stickslip.model import ActuatorParams, Sawtooth, friction_response, simulate

SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def friction_params(draw):
    mu_s = draw(st.floats(0.05, 1.0))
    return ActuatorParams(
        mu_s=mu_s,
        mu_d=mu_s * draw(st.floats(0.3, 1.0)),
        normal_force_n=draw(st.floats(0.1, 100.0)),
        stribeck_velocity_m_per_s=draw(st.floats(1e-5, 1e-2)),
        sigma0_n_per_m=draw(st.floats(1e5, 1e9)),
        sigma1_ns_per_m=draw(st.floats(0.0, 300.0)),
        sigma2_ns_per_m=draw(st.floats(0.0, 50.0)),
    )


@st.composite
def paths(draw, p):
    """A random piecewise-linear relative displacement, within +-8 presliding lengths."""
    ell = p.fs_n / p.sigma0_n_per_m
    n_knots = draw(st.integers(3, 12))
    knots = np.array(draw(st.lists(st.floats(-8, 8), min_size=n_knots, max_size=n_knots))) * ell
    knots[0] = 0.0
    per_seg = draw(st.integers(20, 200))
    segments = zip(knots[:-1], knots[1:])
    x = np.concatenate([np.linspace(a, b, per_seg, endpoint=False) for a, b in segments])
    dt = draw(st.sampled_from([1e-7, 1e-6, 1e-5, 1e-4]))
    return x, dt


@SETTINGS
@given(data=st.data())
def test_friction_finite_and_bounded(data):
    p = data.draw(friction_params())
    x, dt = data.draw(paths(p))
    v = np.abs(np.diff(x, prepend=x[0])) / dt
    for model in ("ls", "lugre"):
        f = friction_response(x, dt, model, p)
        assert np.all(np.isfinite(f))
        # |sigma0 z| and the presliding force never exceed Fs; dz/dt is at most
        # |v| (1 + Fs/Fc): the bound is Fs + (sigma1 (1 + Fs/Fc) + sigma2) |v|, plus rounding
        bound = p.fs_n + (p.sigma1_ns_per_m * (1 + p.fs_n / p.fc_n) + p.sigma2_ns_per_m) * v
        assert np.all(np.abs(f) <= bound * (1 + 1e-5) + 1e-6 * p.fs_n)


@SETTINGS
@given(data=st.data())
def test_ls_creates_no_energy_on_closed_paths(data):
    """A quasi-static closed path (1 um/s, so the rate terms vanish) returns to its start: the
    work of the LS friction over it is >= 0 (it can only dissipate)."""
    p = data.draw(friction_params())
    x, _ = data.draw(paths(p))
    x = np.concatenate([x, np.linspace(x[-1], 0.0, 50)])
    step = np.max(np.abs(np.diff(x)))
    dt = max(step / 1e-6, 1e-9)
    f = friction_response(x, dt, "ls", p)
    work = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))
    scale = p.fs_n * float(np.sum(np.abs(np.diff(x))))
    assert work >= -1e-4 * scale


PARAM_RANGES = {
    "piezo_stiffness_n_per_m": (1.0, 1e12),
    "piezo_damping_kg_per_s": (0.0, 1e6),
    "rod_mass_kg": (1e-9, 1e3),
    "slider_mass_kg": (1e-9, 1e3),
    "sigma0_n_per_m": (1.0, 1e12),
    "sigma1_ns_per_m": (0.0, 1e6),
    "sigma2_ns_per_m": (0.0, 1e6),
    "stribeck_velocity_m_per_s": (1e-9, 10.0),
}


@SETTINGS
@given(
    name=st.sampled_from(sorted(PARAM_RANGES)),
    outside=st.one_of(
        st.floats(allow_nan=False, allow_infinity=False, min_value=-1e30, max_value=1e30),
        st.sampled_from([math.nan, math.inf, -math.inf]),
    ),
)
def test_init_rejects_every_out_of_range_parameter(name, outside):
    lo, hi = PARAM_RANGES[name]
    p = ActuatorParams(**{name: outside})
    with np.errstate(over="ignore"):
        seen = float(np.float32(outside))  # what the float32 library is given
    try:
        simulate(Sawtooth(cycles=1), p)
    except N.NativeError as e:
        assert not (lo <= seen <= hi)
        expect = N.lib.ss_status_str(-3 if not math.isfinite(seen) else -2).decode()
        assert expect in str(e)
        assert name in str(e)  # the error names the parameter
    else:
        assert lo <= seen <= hi


@settings(max_examples=15, deadline=None)
@example(f_hz=2160.0, amp=112.0, rise=0.96875, direction=-1, model="lugre")  # found by hypothesis
@given(
    f_hz=st.floats(50, 3000),
    amp=st.floats(-150, 150),
    rise=st.floats(0.5, 0.995),
    direction=st.sampled_from([1, -1]),
    model=st.sampled_from(["ls", "lugre"]),
)
def test_actuator_runs_stay_finite(f_hz, amp, rise, direction, model):
    r = simulate(Sawtooth(f_hz, amp, 0.0, rise, direction, 3), model=model)
    for col in (r.x_rod_m, r.x_slider_m, r.force_n, r.state_a):
        assert np.all(np.isfinite(col))
    # friction never exceeds its static level by more than the damping terms can add at the
    # relative velocity of the moment (LuGre's sigma1 dz/dt reaches several Fs on fast edges)
    p = ActuatorParams.table1()
    v_rel = np.abs(r.v_rod_m_per_s - r.v_slider_m_per_s)
    bound = p.fs_n + (p.sigma1_ns_per_m * (1 + p.fs_n / p.fc_n) + p.sigma2_ns_per_m) * v_rel
    assert np.all(np.abs(r.force_n) <= bound * (1 + 1e-4) + 1e-4)
