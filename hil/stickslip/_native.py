"""The one thin binding to the C library (libstickslip): ctypes mirrors of the public structs,
checked against the library's own sizes at load time. Nothing else in the package touches
pointers."""

from __future__ import annotations

import ctypes as C
import os
from pathlib import Path

import numpy as np

_HERE = Path(__file__).resolve().parent


SS_OK = 0  # ss_status.h
SS_FRICTION_LS = 0
SS_FRICTION_LUGRE = 1
SS_FRICTION_GMS = 2  # float family only: the q converter refuses it
SS_WAVE_SAWTOOTH = 0
SS_WAVE_SAMPLED = 1


class FrictionConfig(C.Structure):
    _fields_ = [
        ("fs_n", C.c_float),
        ("fc_n", C.c_float),
        ("vs_m_per_s", C.c_float),
        ("sigma0_n_per_m", C.c_float),
        ("sigma1_ns_per_m", C.c_float),
        ("sigma2_ns_per_m", C.c_float),
        ("asymmetry", C.c_float),
    ]


class EffectsConfig(C.Structure):
    """ss_effects_config_f32_t: the optional effects of the diagnosis catalog, zero = off."""

    _fields_ = [
        (name, C.c_float)
        for name in (
            "hysteresis_alpha",
            "hysteresis_width_m",
            "creep_ratio",
            "creep_tau_s",
            "load_n",
            "friction_gradient_per_m",
            "slew_v_per_s",
            "thermal_coeff_per_j",
            "thermal_tau_s",
            "base_mass_kg",
            "base_freq_hz",
            "base_damping_ratio",
            "sensor_scale_error",
        )
    ]


class ActuatorConfig(C.Structure):
    _fields_ = [
        ("piezo_stiffness_n_per_m", C.c_float),
        ("piezo_damping_kg_per_s", C.c_float),
        ("rod_mass_kg", C.c_float),
        ("slider_mass_kg", C.c_float),
        ("piezo_gain_m_per_v", C.c_float),
        ("dt_s", C.c_float),
        ("friction_model", C.c_int32),
        ("friction", FrictionConfig),
        ("effects", EffectsConfig),
    ]


class WaveformConfig(C.Structure):
    _fields_ = [
        ("kind", C.c_int32),
        ("frequency_hz", C.c_float),
        ("amplitude_v", C.c_float),
        ("offset_v", C.c_float),
        ("rise_fraction", C.c_float),
        ("direction", C.c_int32),
        ("cycles", C.c_uint32),
        ("samples_v", C.POINTER(C.c_float)),
        ("n_samples", C.c_uint32),
        ("sample_interval_s", C.c_float),
    ]


_FP = C.POINTER(C.c_float)


class ActuatorTrace(C.Structure):
    _fields_ = [
        ("step", C.POINTER(C.c_uint32)),
        ("drive_v", _FP),
        ("x_p_m", _FP),
        ("x_rod_m", _FP),
        ("x_slider_m", _FP),
        ("v_rod_m_per_s", _FP),
        ("v_slider_m_per_s", _FP),
        ("force_n", _FP),
        ("state_a", _FP),
        ("state_b", _FP),
        ("x_meas_m", _FP),
        ("capacity", C.c_uint32),
    ]


TRACE_COLUMNS = [f[0] for f in ActuatorTrace._fields_ if f[0] != "capacity"]


# --- the fixed-point (_q) family: integer configs, made from the float ones by the library's
# host-side converter (ss_convert_q.h); formats in docs/fixed-point.md


class FrictionConfigQ(C.Structure):
    _fields_ = [
        (n, C.c_int32)
        for n in ("fs_q24", "fc_q24", "vs_q28", "sigma0_n_per_m", "sigma1_q16", "sigma2_q16")
    ]


class ActuatorConfigQ(C.Structure):
    _fields_ = [
        ("dt_q40", C.c_int32),
        ("piezo_gain_q48", C.c_int32),
        ("friction_model", C.c_int32),
        ("lag_q24", C.c_int32),
        ("kick_rod_q40", C.c_int32),
        ("kick_slider_q40", C.c_int32),
        ("phi_q28", C.c_int32 * 4),
        ("friction", FrictionConfigQ),
    ]


class WaveformConfigQ(C.Structure):
    _fields_ = [
        ("frequency_mhz", C.c_uint32),
        ("amplitude_q16", C.c_int32),
        ("offset_q16", C.c_int32),
        ("rise_q32", C.c_uint32),
        ("direction", C.c_int32),
        ("cycles", C.c_uint32),
    ]


_I32P = C.POINTER(C.c_int32)


class ActuatorTraceQ(C.Structure):
    _fields_ = [
        ("step", C.POINTER(C.c_uint32)),
        ("drive_q16", _I32P),
        ("x_p_q40", _I32P),
        ("x_rod_q40", _I32P),
        ("x_slider_q40", C.POINTER(C.c_int64)),
        ("v_rod_q28", _I32P),
        ("v_slider_q28", _I32P),
        ("force_q24", _I32P),
        ("state_a", _I32P),
        ("state_b", _I32P),
        ("capacity", C.c_uint32),
    ]


# column -> (numpy dtype, SI scale); state_a/state_b scales depend on the friction model
TRACE_Q_COLUMNS = {
    "step": (np.uint32, 1.0),
    "drive_q16": (np.int32, 2.0**-16),
    "x_p_q40": (np.int32, 2.0**-40),
    "x_rod_q40": (np.int32, 2.0**-40),
    "x_slider_q40": (np.int64, 2.0**-40),
    "v_rod_q28": (np.int32, 2.0**-28),
    "v_slider_q28": (np.int32, 2.0**-28),
    "force_q24": (np.int32, 2.0**-24),
    "state_a": (np.int32, None),
    "state_b": (np.int32, None),
}

# ids of ss_abi.h
_ABI = {
    FrictionConfig: 0,
    ActuatorConfig: 1,
    WaveformConfig: 3,
    ActuatorTrace: 7,
    EffectsConfig: 20,
    FrictionConfigQ: 8,
    ActuatorConfigQ: 9,
    WaveformConfigQ: 11,
    ActuatorTraceQ: 15,
}
_ABI_ACTUATOR_STATE_Q, _ABI_WAVEFORM_STATE_Q = 10, 12
_ABI_ACTUATOR_STATE, _ABI_WAVEFORM_STATE, _ABI_LS_STATE, _ABI_LUGRE_STATE = 2, 4, 5, 6
_ABI_GMS_STATE = 21


def _candidates() -> list[Path]:
    env = os.environ.get("STICKSLIP_LIB")
    paths = [Path(env)] if env else []
    paths.append(_HERE / "libstickslip.so")
    # a development checkout built with `cmake --preset host`
    paths.append(_HERE.parents[1] / "build" / "host" / "lib" / "libstickslip.so")
    return paths


def _load() -> C.CDLL:
    tried = []
    for path in _candidates():
        if path.is_file():
            return C.CDLL(str(path))
        tried.append(str(path))
    raise ImportError(
        "libstickslip.so not found; install the package (pip install .) or build it with "
        "`cmake --preset host && cmake --build --preset host`. Looked in: " + ", ".join(tried)
    )


lib = _load()


def _proto(name: str, restype, *argtypes) -> None:
    fn = getattr(lib, name)
    fn.restype = restype
    fn.argtypes = list(argtypes)


_P = C.c_void_p
_proto("ss_status_str", C.c_char_p, C.c_int)
_proto("ss_abi_sizeof", C.c_uint32, C.c_int32)
_proto("ss_actuator_config_table1_f32", ActuatorConfig)
_proto("ss_friction_config_table1_f32", FrictionConfig)
_proto("ss_friction_config_from_mu_f32", FrictionConfig, *([C.c_float] * 7))
_proto("ss_stribeck_f32", C.c_float, C.POINTER(FrictionConfig), C.c_float)
_proto("ss_friction_config_check_f32", C.c_int, C.POINTER(FrictionConfig), C.POINTER(C.c_char_p))
_proto("ss_actuator_config_check_f32", C.c_int, C.POINTER(ActuatorConfig), C.POINTER(C.c_char_p))
_proto("ss_actuator_init_f32", C.c_int, C.POINTER(ActuatorConfig), _P, C.c_float)
_proto("ss_actuator_step_f32", C.c_int, C.POINTER(ActuatorConfig), _P, C.c_float)
_proto("ss_actuator_place_slider_f32", None, _P, C.c_float)
_proto(
    "ss_actuator_record_f32",
    None,
    C.POINTER(ActuatorConfig),
    _P,
    C.POINTER(ActuatorTrace),
    C.c_uint32,
)
_proto(
    "ss_actuator_run_f32",
    C.c_int,
    C.POINTER(ActuatorConfig),
    _P,
    C.POINTER(WaveformConfig),
    _P,
    C.c_uint32,
    C.c_uint32,
    C.POINTER(ActuatorTrace),
    C.POINTER(C.c_uint32),
)
_proto("ss_waveform_init_f32", C.c_int, C.POINTER(WaveformConfig), C.c_float, _P)
_proto("ss_waveform_value_f32", C.c_float, C.POINTER(WaveformConfig), _P)
_proto("ss_waveform_fill_f32", C.c_int, C.POINTER(WaveformConfig), _P, _FP, C.c_uint32)
for _m in ("ls", "lugre", "gms"):
    _proto(f"ss_{_m}_init_f32", C.c_int, C.POINTER(FrictionConfig), _P)
    _proto(
        f"ss_{_m}_run_f32", C.c_int, C.POINTER(FrictionConfig), _P, _FP, C.c_uint32, C.c_float, _FP
    )

_proto(
    "ss_actuator_config_to_q",
    C.c_int,
    C.POINTER(ActuatorConfig),
    C.POINTER(ActuatorConfigQ),
    C.POINTER(C.c_char_p),
)
_proto(
    "ss_waveform_config_to_q",
    C.c_int,
    C.POINTER(WaveformConfig),
    C.POINTER(WaveformConfigQ),
    C.POINTER(C.c_char_p),
)
_proto("ss_waveform_init_q", C.c_int, C.POINTER(WaveformConfigQ), C.c_int32, _P)
_proto("ss_waveform_value_q", C.c_int32, C.POINTER(WaveformConfigQ), _P)
_proto("ss_actuator_init_q", C.c_int, C.POINTER(ActuatorConfigQ), _P, C.c_int32)
_proto(
    "ss_actuator_record_q",
    None,
    C.POINTER(ActuatorConfigQ),
    _P,
    C.POINTER(ActuatorTraceQ),
    C.c_uint32,
)
_proto(
    "ss_actuator_run_q",
    C.c_int,
    C.POINTER(ActuatorConfigQ),
    _P,
    C.POINTER(WaveformConfigQ),
    _P,
    C.c_uint32,
    C.c_uint32,
    C.POINTER(ActuatorTraceQ),
    C.POINTER(C.c_uint32),
)

for _struct, _id in _ABI.items():
    if lib.ss_abi_sizeof(_id) != C.sizeof(_struct):
        raise ImportError(
            f"libstickslip ABI mismatch: {_struct.__name__} is {C.sizeof(_struct)} bytes here, "
            f"{lib.ss_abi_sizeof(_id)} in the library; rebuild and reinstall the package"
        )


class NativeError(ValueError):
    """A call into libstickslip returned an error status."""

    def __init__(self, status: int, where: str):
        self.status = status
        msg = lib.ss_status_str(status).decode()
        super().__init__(f"{where}: {msg} (status {status})")


def check(status: int, where: str) -> None:
    if status != SS_OK:
        raise NativeError(status, where)


# C field names -> the parameter names users give (stick-slip-dataset/1)
_USER_NAMES = {
    "fs_n": "mu_s * normal_force_n (Fs)",
    "fc_n": "mu_d * normal_force_n (Fc, must not exceed Fs)",
    "vs_m_per_s": "stribeck_velocity_m_per_s",
}


def check_config(cfg, what: str = "actuator") -> None:
    """Raise NativeError naming the first bad field of an ActuatorConfig or FrictionConfig."""
    bad = C.c_char_p()
    if isinstance(cfg, ActuatorConfig):
        status = lib.ss_actuator_config_check_f32(C.byref(cfg), C.byref(bad))
    else:
        status = lib.ss_friction_config_check_f32(C.byref(cfg), C.byref(bad))
    if status != SS_OK:
        field = (bad.value or b"?").decode().removeprefix("friction.")
        raise NativeError(status, f"{what} parameter {_USER_NAMES.get(field, field)}")


def opaque(abi_id: int) -> C.Array:
    """A zeroed buffer the size of a C state struct, 8-byte aligned."""
    n = lib.ss_abi_sizeof(abi_id)
    return (C.c_uint64 * ((n + 7) // 8))()


def new_actuator_state() -> C.Array:
    return opaque(_ABI_ACTUATOR_STATE)


def new_waveform_state() -> C.Array:
    return opaque(_ABI_WAVEFORM_STATE)


_FRICTION_STATE_ABI = {
    SS_FRICTION_LS: _ABI_LS_STATE,
    SS_FRICTION_LUGRE: _ABI_LUGRE_STATE,
    SS_FRICTION_GMS: _ABI_GMS_STATE,
}


def new_friction_state(kind: int) -> C.Array:
    return opaque(_FRICTION_STATE_ABI[kind])


def float_ptr(a: np.ndarray):
    assert a.dtype == np.float32 and a.flags.c_contiguous
    return a.ctypes.data_as(_FP)


def trace_for(columns: dict[str, np.ndarray], capacity: int) -> ActuatorTrace:
    tr = ActuatorTrace()
    tr.capacity = capacity
    for name, arr in columns.items():
        if name == "step":
            tr.step = arr.ctypes.data_as(C.POINTER(C.c_uint32))
        else:
            setattr(tr, name, float_ptr(arr))
    return tr


def to_q(cfg: ActuatorConfig, wave: WaveformConfig) -> tuple[ActuatorConfigQ, WaveformConfigQ]:
    """The fixed-point configs for float ones, by the library's converter; NativeError names the
    field that does not fit its Q format (or an effect the q family does not model)."""
    cq, wq, bad = ActuatorConfigQ(), WaveformConfigQ(), C.c_char_p()
    status = lib.ss_actuator_config_to_q(C.byref(cfg), C.byref(cq), C.byref(bad))
    if status != SS_OK:
        raise NativeError(status, f"q variant: parameter {(bad.value or b'?').decode()}")
    status = lib.ss_waveform_config_to_q(C.byref(wave), C.byref(wq), C.byref(bad))
    if status != SS_OK:
        raise NativeError(status, f"q variant: waveform {(bad.value or b'?').decode()}")
    return cq, wq


def new_actuator_state_q() -> C.Array:
    return opaque(_ABI_ACTUATOR_STATE_Q)


def new_waveform_state_q() -> C.Array:
    return opaque(_ABI_WAVEFORM_STATE_Q)


def trace_q_for(columns: dict[str, np.ndarray], capacity: int) -> ActuatorTraceQ:
    tr = ActuatorTraceQ()
    tr.capacity = capacity
    pointer_types = {f[0]: f[1] for f in ActuatorTraceQ._fields_}
    for name, arr in columns.items():
        setattr(tr, name, arr.ctypes.data_as(pointer_types[name]))  # type: ignore[type-var]
    return tr
