"""The one thin binding to the C library (libstickslip): ctypes mirrors of the public structs,
checked against the library's own sizes at load time, and the calls into it. The only module of
the package that imports ctypes: the rest calls the functions below and never touches pointers."""

from __future__ import annotations

import ctypes as C
import math
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
# the friction laws by the names users give (docs/model.md)
FRICTION_KINDS = {"ls": SS_FRICTION_LS, "lugre": SS_FRICTION_LUGRE, "gms": SS_FRICTION_GMS}


class FrictionConfig(C.Structure):
    _fields_ = [
        ("fs_n", C.c_float),
        ("fc_n", C.c_float),
        ("vs_m_per_s", C.c_float),
        ("sigma0_n_per_m", C.c_float),
        ("sigma1_ns_per_m", C.c_float),
        ("sigma2_ns_per_m", C.c_float),
        ("asymmetry", C.c_float),
        ("gms_decay", C.c_float),
        ("gms_stiffness_ratio", C.c_float),
    ]


class FrictionMu(C.Structure):
    """ss_friction_mu_f32_t: the friction as the dataset names it (coefficients, clamping force)."""

    _fields_ = [
        (name, C.c_float)
        for name in (
            "mu_s",
            "mu_d",
            "normal_force_n",
            "vs_m_per_s",
            "sigma0_n_per_m",
            "sigma1_ns_per_m",
            "sigma2_ns_per_m",
        )
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
            "amp_bandwidth_hz",
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


class RunJob(C.Structure):
    """ss_actuator_run_job_f32_t: one simulation of ss_actuator_run_many_f32."""

    _fields_ = [
        ("cfg", C.POINTER(ActuatorConfig)),
        ("st", C.c_void_p),
        ("wave", C.POINTER(WaveformConfig)),
        ("wst", C.c_void_p),
        ("n_steps", C.c_uint32),
        ("decimation", C.c_uint32),
        ("trace", C.POINTER(ActuatorTrace)),
        ("rows", C.c_uint32),
        ("status", C.c_int),
    ]


class ActuatorCoarse(C.Structure):
    """ss_actuator_coarse_f32_t: coarse steps while the contact sticks (LuGre)."""

    _fields_ = [
        ("phi", C.c_float * 4),
        ("phi_mid", C.c_float * 4),
        ("dt_s", C.c_float),
        ("n", C.c_uint32),
        ("v_rel_max_m_per_s", C.c_float),
        ("v_ring_max_m_per_s", C.c_float),
        ("v_rel_mid_max_m_per_s", C.c_float),
        ("v_ring_mid_max_m_per_s", C.c_float),
        ("stick_n", C.c_uint32),
        ("stick_dt_s", C.c_float),
        ("stick_omega_per_s", C.c_float),
        ("edge_parts", C.c_uint32),
        ("stick_phi", C.c_float * 16),
        ("split_min_n", C.c_uint32),
    ]


# --- the fixed-point (_q) family: integer configs, made from the float ones by the library's
# host-side converter (ss_convert_q.h); formats in docs/fixed-point.md


class FrictionConfigQ(C.Structure):
    _fields_ = [
        (n, C.c_int32)
        for n in (
            "fs_q24",
            "fc_q24",
            "vs_q28",
            "sigma0_n_per_m",
            "sigma1_q16",
            "sigma2_q16",
            "asymmetry_q30",
            "inv_vs_q45",
            "inv_sigma0_q47",
            "inv_fs_q48",
            "sat_length_q40",
            "fc_recip_mantissa",
            "fc_recip_shift",
        )
    ]


class EffectsConfigQ(C.Structure):
    _fields_ = [
        *[(n, C.c_int32) for n in ("load_q24", "slew_q24", "sensor_scale_q30")],
        ("hysteresis_alpha_q30", C.c_int32),
        ("hysteresis_width_q40", C.c_int32),
        ("pad", C.c_int32),
        ("hysteresis_inv_width_q48", C.c_int64),
        *[
            (n, C.c_int32)
            for n in (
                "base_kick_q40",
                "base_stiffness_n_per_m",
                "base_damping_q16",
                "piezo_stiffness_n_per_m",
                "piezo_damping_q16",
                "pad2",
            )
        ],
    ]


class ActuatorConfigQ(C.Structure):
    _fields_ = [
        ("dt_q40", C.c_int32),
        ("piezo_gain_q48", C.c_int32),
        ("friction_model", C.c_int32),
        ("lag_q24", C.c_int32),
        ("kick_rod_q40", C.c_uint32),
        ("kick_slider_q40", C.c_int32),
        ("phi_q28", C.c_int32 * 4),
        ("friction", FrictionConfigQ),
        ("inv_dt_q47", C.c_int32),
        ("effects", EffectsConfigQ),
        ("contact_lag_q30", C.c_int32),
        ("rod_w2dt2_q28", C.c_int32),
    ]


class ActuatorCoarseQ(C.Structure):
    """ss_actuator_coarse_q_t: the q family's coarse steps (ss_actuator_coarse_to_q)."""

    _fields_ = [
        ("cfg", ActuatorConfigQ),
        ("cfg_mid", ActuatorConfigQ),
        ("n", C.c_uint32),
        ("v_rel_max_q28", C.c_int32),
        ("ring_max_q40", C.c_int32),
        ("ring_max_2_q40", C.c_int32),
        ("v_rel_mid_max_q28", C.c_int32),
        ("ring_mid_max_q40", C.c_int32),
        ("compliance_q56", C.c_int32),
        ("split", C.c_int32),
        ("stick_n", C.c_uint32),
        ("stick_h_q40", C.c_int32),
        ("stick_inv_h_q47", C.c_int32),
        ("stick_omega_q47", C.c_int32),
        ("stick_inv_omega_q40", C.c_int32),
        ("stick_lag_q30", C.c_int32),
        ("stick_v_rel_max_q28", C.c_int32),
        ("stick_ring_max_q40", C.c_int32),
        ("stick_force_max_q24", C.c_int32),
        ("stick_phi_shift", C.c_int32),
        ("stick_phi_q", C.c_int32 * 16),
        ("edge_parts", C.c_uint32),
        ("edge_limit_q16", C.c_int32),
        ("edge_part_q30", C.c_int32),
        ("edge_pad", C.c_int32),
        ("cfg_edge", ActuatorConfigQ),
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
        ("x_meas_q40", C.POINTER(C.c_int64)),
        ("capacity", C.c_uint32),
    ]


# column -> numpy dtype; the SI scale of each is q_scale(column), of state_a/state_b
# q_scale(TRACE_Q_STATES[model][0 or 1])
TRACE_Q_COLUMNS = {
    "step": np.uint32,
    "drive_q16": np.int32,
    "x_p_q40": np.int32,
    "x_rod_q40": np.int32,
    "x_slider_q40": np.int64,
    "v_rod_q28": np.int32,
    "v_slider_q28": np.int32,
    "force_q24": np.int32,
    "state_a": np.int32,
    "state_b": np.int32,
    "x_meas_q40": np.int64,
}
TRACE_Q_STATES = {"ls": ("ls.level_q24", "ls.fm_q24"), "lugre": ("lugre.z_q40", "lugre.zdot_q28")}

# ids of ss_abi.h
_ABI = {
    FrictionConfig: 0,
    ActuatorConfig: 1,
    WaveformConfig: 3,
    ActuatorTrace: 7,
    RunJob: 23,
    ActuatorCoarse: 24,
    ActuatorCoarseQ: 25,
    EffectsConfig: 20,
    FrictionMu: 22,
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
_proto("ss_abi_qformat", C.c_int32, C.c_uint32, C.POINTER(C.c_char_p))
_proto("ss_actuator_config_table1_f32", ActuatorConfig)
_proto("ss_friction_config_table1_f32", FrictionConfig)
_proto("ss_friction_mu_table1_f32", FrictionMu)
_proto("ss_waveform_paper_f32", WaveformConfig)
_proto("ss_friction_config_from_mu_f32", FrictionConfig, *([C.c_float] * 7))
_proto("ss_stribeck_f32", C.c_float, C.POINTER(FrictionConfig), C.c_float)
_proto("ss_friction_config_check_f32", C.c_int, C.POINTER(FrictionConfig), C.POINTER(C.c_char_p))
_proto("ss_actuator_config_check_f32", C.c_int, C.POINTER(ActuatorConfig), C.POINTER(C.c_char_p))
_proto("ss_actuator_init_f32", C.c_int, C.POINTER(ActuatorConfig), _P, C.c_float)
_proto("ss_actuator_step_f32", C.c_int, C.POINTER(ActuatorConfig), _P, C.c_float)
_proto("ss_actuator_place_slider_f32", None, _P, C.c_float)
_proto("ss_actuator_heat_f32", C.c_float, _P)
_proto("ss_actuator_set_heat_f32", None, _P, C.c_float)
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
_proto("ss_actuator_run_many_f32", C.c_int, C.POINTER(RunJob), C.c_uint32)
_proto(
    "ss_actuator_coarse_init_f32",
    C.c_int,
    C.POINTER(ActuatorConfig),
    C.c_uint32,
    C.POINTER(ActuatorCoarse),
    C.POINTER(C.c_char_p),
)
_proto(
    "ss_actuator_coarse_stick_f32",
    C.c_int,
    C.POINTER(ActuatorConfig),
    C.c_uint32,
    C.POINTER(ActuatorCoarse),
    C.POINTER(C.c_char_p),
)
_proto(
    "ss_actuator_run_coarse_f32",
    C.c_int,
    C.POINTER(ActuatorConfig),
    C.POINTER(ActuatorCoarse),
    _P,
    C.POINTER(WaveformConfig),
    _P,
    C.c_uint32,
    C.c_uint32,
    C.POINTER(ActuatorTrace),
    C.POINTER(C.c_uint32),
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
_proto("ss_actuator_step_q", C.c_int, C.POINTER(ActuatorConfigQ), _P, C.c_int32)
_proto("ss_volts_to_q16", C.c_int32, C.c_double)
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
_proto(
    "ss_actuator_coarse_stick_to_q",
    C.c_int,
    C.POINTER(ActuatorConfig),
    C.c_uint32,
    C.POINTER(ActuatorCoarseQ),
    C.POINTER(C.c_char_p),
)
_proto(
    "ss_actuator_coarse_to_q",
    C.c_int,
    C.POINTER(ActuatorConfig),
    C.c_uint32,
    C.POINTER(ActuatorCoarseQ),
    C.POINTER(C.c_char_p),
)
_proto(
    "ss_actuator_run_coarse_q",
    C.c_int,
    C.POINTER(ActuatorConfigQ),
    C.POINTER(ActuatorCoarseQ),
    _P,
    C.POINTER(WaveformConfigQ),
    _P,
    C.c_uint32,
    C.c_uint32,
    C.POINTER(ActuatorTraceQ),
    C.POINTER(C.c_uint32),
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


def config_to_q(cfg: ActuatorConfig) -> ActuatorConfigQ:
    """The fixed-point actuator config for a float one, by the library's converter; NativeError
    names the field that does not fit its Q format (or an effect the q family does not model)."""
    cq, bad = ActuatorConfigQ(), C.c_char_p()
    status = lib.ss_actuator_config_to_q(C.byref(cfg), C.byref(cq), C.byref(bad))
    if status != SS_OK:
        raise NativeError(status, f"q variant: parameter {(bad.value or b'?').decode()}")
    return cq


def to_q(cfg: ActuatorConfig, wave: WaveformConfig) -> tuple[ActuatorConfigQ, WaveformConfigQ]:
    """The fixed-point configs for float ones (config_to_q, and the waveform's)."""
    cq, wq, bad = config_to_q(cfg), WaveformConfigQ(), C.c_char_p()
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


# --- the Q formats of the q family's signals (ss_qformat.h, read through ss_abi_qformat)


def _qformats() -> dict[str, int]:
    out: dict[str, int] = {}
    name = C.c_char_p()
    i = 0
    while (shift := lib.ss_abi_qformat(i, C.byref(name))) >= 0:
        out[(name.value or b"").decode()] = shift
        i += 1
    return out


Q_SHIFTS = _qformats()


def q_scale(signal: str) -> float:
    """SI units per LSB of a q-family signal named as its C field (e.g. "x_slider_q40": 2^-40 m)."""
    return math.ldexp(1.0, -Q_SHIFTS[signal])


# --- the single sources of Table I and the paper's drive


def table1_actuator() -> ActuatorConfig:
    """ss_actuator_config_table1_f32(): Table I of the LS paper, dt 1 us, LS friction."""
    return lib.ss_actuator_config_table1_f32()


def table1_friction_mu() -> FrictionMu:
    """ss_friction_mu_table1_f32(): Table I's friction as coefficients and clamping force."""
    return lib.ss_friction_mu_table1_f32()


def table1_friction() -> FrictionConfig:
    return lib.ss_friction_config_table1_f32()


def paper_sawtooth() -> WaveformConfig:
    """ss_waveform_paper_f32(): the LS paper's drive (Fig. 13)."""
    return lib.ss_waveform_paper_f32()


# --- the calls the model makes


def friction_config_from_mu(
    mu_s: float,
    mu_d: float,
    normal_force_n: float,
    vs_m_per_s: float,
    sigma0_n_per_m: float,
    sigma1_ns_per_m: float,
    sigma2_ns_per_m: float,
) -> FrictionConfig:
    """Fs = mu_s N and Fc = mu_d N, formed in float by the C library as firmware forms them."""
    return lib.ss_friction_config_from_mu_f32(
        mu_s, mu_d, normal_force_n, vs_m_per_s, sigma0_n_per_m, sigma1_ns_per_m, sigma2_ns_per_m
    )


def sampled_waveform(samples: np.ndarray, interval_s: float) -> WaveformConfig:
    """A sampled drive over samples (float32, C-contiguous), which the caller keeps alive for as
    long as the config is used."""
    w = WaveformConfig()
    w.kind = SS_WAVE_SAMPLED
    w.samples_v = float_ptr(samples)
    w.n_samples = len(samples)
    w.sample_interval_s = interval_s
    return w


def check_waveform(wave: WaveformConfig, dt_s: float) -> None:
    """NativeError unless the library accepts the waveform at step dt_s."""
    check(lib.ss_waveform_init_f32(C.byref(wave), dt_s, new_waveform_state()), "waveform")


def drive_samples(wave: WaveformConfig, dt_s: float, n_steps: int) -> np.ndarray:
    """The drive at t = 0 and after each of n_steps steps, float32, from the waveform player."""
    wst = new_waveform_state()
    check(lib.ss_waveform_init_f32(C.byref(wave), dt_s, wst), "waveform")
    out = np.zeros(n_steps + 1, np.float32)
    out[0] = lib.ss_waveform_value_f32(C.byref(wave), wst)
    check(lib.ss_waveform_fill_f32(C.byref(wave), wst, float_ptr(out[1:]), n_steps), "waveform")
    return out


class _RunF32:
    """A float run set up for the C core: its state at rest (slider at x0_m, stored heat heat0_j)
    with the initial state recorded, and the trace its steps write from row 1 on."""

    def __init__(
        self,
        cfg: ActuatorConfig,
        wave: WaveformConfig,
        n_steps: int,
        decimation: int,
        x0_m: float,
        heat0_j: float,
    ):
        self.cfg, self.wave, self.n_steps, self.decimation = cfg, wave, n_steps, decimation
        rows = n_steps // decimation
        cols = {name: np.zeros(rows + 1, np.float32) for name in TRACE_COLUMNS if name != "step"}
        cols["step"] = np.zeros(rows + 1, np.uint32)
        self.cols = cols
        self.st = new_actuator_state()
        self.wst = new_waveform_state()
        check(lib.ss_waveform_init_f32(C.byref(wave), cfg.dt_s, self.wst), "waveform")
        v0 = lib.ss_waveform_value_f32(C.byref(wave), self.wst)
        check(lib.ss_actuator_init_f32(C.byref(cfg), self.st, v0), "actuator parameters")
        if x0_m != 0.0:
            lib.ss_actuator_place_slider_f32(self.st, x0_m)
        if heat0_j != 0.0:
            lib.ss_actuator_set_heat_f32(self.st, heat0_j)
        first = trace_for(cols, rows + 1)
        lib.ss_actuator_record_f32(C.byref(cfg), self.st, C.byref(first), 0)
        # the run writes from row 1 on: point a second trace one row in
        self.trace = trace_for({k: v[1:] for k, v in cols.items()}, rows)

    def result(self, status: int, rows: int) -> tuple[dict[str, np.ndarray], float]:
        check(status, f"run stopped after {rows * self.decimation} steps")
        return self.cols, float(lib.ss_actuator_heat_f32(self.st))


def run_f32(
    cfg: ActuatorConfig,
    wave: WaveformConfig,
    n_steps: int,
    decimation: int,
    x0_m: float = 0.0,
    heat0_j: float = 0.0,
) -> tuple[dict[str, np.ndarray], float]:
    """The float core from rest (slider at x0_m, stored heat heat0_j) over n_steps; every
    decimation-th step recorded, the initial state first. Returns columns as TRACE_COLUMNS
    (float32, step uint32) and the stored heat at the end."""
    r = _RunF32(cfg, wave, n_steps, decimation, x0_m, heat0_j)
    written = C.c_uint32(0)
    status = lib.ss_actuator_run_f32(
        C.byref(cfg),
        r.st,
        C.byref(wave),
        r.wst,
        n_steps,
        decimation,
        C.byref(r.trace),
        C.byref(written),
    )
    return r.result(status, written.value)


def _coarse(make, struct, cfg: ActuatorConfig, n: int):
    """The library's coarse steps of n steps of cfg's dt (make: ss_actuator_coarse_init_f32, or
    ss_actuator_coarse_to_q for the q family), or a NativeError naming the bad field."""
    co, bad = struct(), C.c_char_p()
    status = make(C.byref(cfg), n, C.byref(co), C.byref(bad))
    if status != SS_OK:
        raise NativeError(status, f"coarse steps ({(bad.value or b'').decode()})")
    return co


def _stick(make, cfg: ActuatorConfig, co, stick_steps: int) -> None:
    """Turn co's stick steps on (make: ss_actuator_coarse_stick_f32, or
    ss_actuator_coarse_stick_to_q for the q family), or a NativeError naming the bad field."""
    bad = C.c_char_p()
    status = make(C.byref(cfg), stick_steps, C.byref(co), C.byref(bad))
    if status != SS_OK:
        raise NativeError(status, f"stick steps ({(bad.value or b'').decode()})")


def run_f32_coarse(
    cfg: ActuatorConfig,
    wave: WaveformConfig,
    n_steps: int,
    decimation: int,
    coarse_steps: int,
    x0_m: float = 0.0,
    heat0_j: float = 0.0,
    stick_steps: int = 0,
) -> tuple[dict[str, np.ndarray], float, int]:
    """run_f32 with coarse steps of coarse_steps steps where the contact sticks
    (ss_actuator_run_coarse_f32; LuGre and LS), and stick steps of stick_steps where it has
    stopped ringing (ss_actuator_coarse_stick_f32; LuGre; 0: none). Returns run_f32's columns and
    heat, and the steps the model took."""
    co = _coarse(lib.ss_actuator_coarse_init_f32, ActuatorCoarse, cfg, coarse_steps)
    if stick_steps:
        _stick(lib.ss_actuator_coarse_stick_f32, cfg, co, stick_steps)
    r = _RunF32(cfg, wave, n_steps, decimation, x0_m, heat0_j)
    written, taken = C.c_uint32(0), C.c_uint32(0)
    status = lib.ss_actuator_run_coarse_f32(
        C.byref(cfg),
        C.byref(co),
        r.st,
        C.byref(wave),
        r.wst,
        n_steps,
        decimation,
        C.byref(r.trace),
        C.byref(written),
        C.byref(taken),
    )
    cols, heat = r.result(status, written.value)
    return cols, heat, int(taken.value)


def run_f32_many(
    runs: list[tuple[ActuatorConfig, WaveformConfig, int, int, float, float]],
) -> list[tuple[dict[str, np.ndarray], float] | NativeError]:
    """run_f32 on each (cfg, wave, n_steps, decimation, x0_m, heat0_j), with the same bits, as
    one batch (ss_actuator_run_many_f32: four simulations stepped side by side, phase by phase:
    on one core the 13 runs of a dataset take 0.53 (LuGre) to 0.94 (GMS) x the time they take
    one after the other, BENCHMARKS.md). A run that fails gives its NativeError in its place; the
    others still run. The configs (and a sampled wave's samples) must live until this returns."""
    out: list = [None] * len(runs)
    ready: list[tuple[int, _RunF32]] = []
    for i, args in enumerate(runs):
        try:
            ready.append((i, _RunF32(*args)))
        except NativeError as e:
            out[i] = e
    jobs = (RunJob * max(1, len(ready)))()
    for j, (_, r) in zip(jobs, ready):
        j.cfg, j.st, j.wave, j.wst = (
            C.pointer(r.cfg),
            C.cast(r.st, C.c_void_p),
            C.pointer(r.wave),
            C.cast(r.wst, C.c_void_p),
        )
        j.n_steps, j.decimation, j.trace = r.n_steps, r.decimation, C.pointer(r.trace)
    lib.ss_actuator_run_many_f32(jobs, len(ready))
    for j, (i, r) in zip(jobs, ready):
        try:
            out[i] = r.result(j.status, j.rows)
        except NativeError as e:
            out[i] = e
    return out


def run_q(
    cfg: ActuatorConfig, wave: WaveformConfig, n_steps: int, decimation: int
) -> dict[str, np.ndarray]:
    """The fixed-point core on the configs the library's converter makes of cfg and wave, as
    run_f32; columns as TRACE_Q_COLUMNS, the integers of the q family (scales: q_scale)."""
    return _run_q(cfg, wave, n_steps, decimation, 1)[0]


def run_q_coarse(
    cfg: ActuatorConfig,
    wave: WaveformConfig,
    n_steps: int,
    decimation: int,
    coarse_steps: int,
    stick_steps: int = 0,
) -> tuple[dict[str, np.ndarray], int]:
    """run_q with coarse steps of coarse_steps steps where the contact sticks
    (ss_actuator_run_coarse_q, from ss_actuator_coarse_to_q; LuGre and LS), and stick steps of
    stick_steps (ss_actuator_coarse_stick_to_q; LuGre; 0: none): the columns, and the steps the
    model took."""
    return _run_q(cfg, wave, n_steps, decimation, coarse_steps, stick_steps)


def _run_q(
    cfg: ActuatorConfig,
    wave: WaveformConfig,
    n_steps: int,
    decimation: int,
    coarse_steps: int,
    stick_steps: int = 0,
) -> tuple[dict[str, np.ndarray], int]:
    cq, wq = to_q(cfg, wave)
    co = None
    if coarse_steps > 1:
        co = _coarse(lib.ss_actuator_coarse_to_q, ActuatorCoarseQ, cfg, coarse_steps)
    if stick_steps:
        _stick(lib.ss_actuator_coarse_stick_to_q, cfg, co, stick_steps)
    rows = n_steps // decimation
    cols = {k: np.zeros(rows + 1, dt) for k, dt in TRACE_Q_COLUMNS.items()}
    st, wst = new_actuator_state_q(), new_waveform_state_q()
    check(lib.ss_waveform_init_q(C.byref(wq), cq.dt_q40, wst), "q waveform")
    v0 = lib.ss_waveform_value_q(C.byref(wq), wst)
    check(lib.ss_actuator_init_q(C.byref(cq), st, v0), "q actuator parameters")
    lib.ss_actuator_record_q(C.byref(cq), st, C.byref(trace_q_for(cols, rows + 1)), 0)
    tr = trace_q_for({k: v[1:] for k, v in cols.items()}, rows)
    written, taken = C.c_uint32(0), C.c_uint32(n_steps)
    args = (st, C.byref(wq), wst, n_steps, decimation, C.byref(tr), C.byref(written))
    if co is None:
        status = lib.ss_actuator_run_q(C.byref(cq), *args)
    else:
        status = lib.ss_actuator_run_coarse_q(C.byref(cq), C.byref(co), *args, C.byref(taken))
    check(status, f"q run stopped after {written.value * decimation} steps")
    return cols, int(taken.value)


def run_q_samples(
    cfg: ActuatorConfig, samples_v: np.ndarray, decimation: int
) -> dict[str, np.ndarray]:
    """The fixed-point core fed a sampled drive one sample a step (float32 volts to Q16.16 by
    ss_volts_to_q16, as the q node takes a DRIVE_BLOCK): the drive linear between samples, no
    corner inside a step. Columns as run_q. One ctypes call a step: some 0.3 s per 1e5 steps."""
    cq = config_to_q(cfg)
    n_steps = len(samples_v) - 1
    rows = n_steps // decimation
    cols = {k: np.zeros(rows + 1, dt) for k, dt in TRACE_Q_COLUMNS.items()}
    st = new_actuator_state_q()
    drive = [lib.ss_volts_to_q16(float(v)) for v in samples_v]
    check(lib.ss_actuator_init_q(C.byref(cq), st, drive[0]), "q actuator parameters")
    tr = trace_q_for(cols, rows + 1)
    lib.ss_actuator_record_q(C.byref(cq), st, C.byref(tr), 0)
    for i in range(1, n_steps + 1):
        check(lib.ss_actuator_step_q(C.byref(cq), st, drive[i]), f"q step {i}")
        if i % decimation == 0:
            lib.ss_actuator_record_q(C.byref(cq), st, C.byref(tr), i // decimation)
    return cols


def friction_run(model: str, fcfg: FrictionConfig, dx: np.ndarray, dt_s: float) -> np.ndarray:
    """Friction force (N, float32) of law `model` from the virgin state under increments dx
    (float32, C-contiguous), each taken in dt_s."""
    st = new_friction_state(FRICTION_KINDS[model])
    init, run = getattr(lib, f"ss_{model}_init_f32"), getattr(lib, f"ss_{model}_run_f32")
    check(init(C.byref(fcfg), st), "friction parameters")
    out = np.zeros_like(dx)
    check(run(C.byref(fcfg), st, float_ptr(dx), len(dx), dt_s, float_ptr(out)), "friction run")
    return out


def stribeck(fcfg: FrictionConfig, v_m_per_s: np.ndarray) -> np.ndarray:
    """The Stribeck curve g(v) of the library (N) at each velocity."""
    return np.array([lib.ss_stribeck_f32(C.byref(fcfg), float(v)) for v in np.ravel(v_m_per_s)])


# ---------------------------------------------------------------- C source for a struct


def c_value(v: object) -> str:
    if isinstance(v, float):  # the float32 the struct holds, in the shortest digits that read back
        text = str(np.float32(v))
        return text + ("f" if any(c in text for c in ".e") else ".0f")
    return str(int(v))  # type: ignore[call-overload]


def c_define(name: str, s: C.Structure) -> list[str]:
    """The lines of a C macro NAME holding c_initializer(s): what a header hands a firmware
    build to compile in (model_file.c_header, bench/q_bench_config.py)."""
    body = ("{\n" + c_initializer(s, "") + "\n}").splitlines()
    return [f"#define {name} \\", *[line + " \\" for line in body[:-1]], body[-1]]


def c_initializer(s: C.Structure, indent: str) -> str:
    """A C99 designated initialiser of a ctypes mirror of a library struct, field by field
    (model_file.c_header)."""
    lines = []
    for name, *_ in s._fields_:
        v = getattr(s, name)
        if isinstance(v, C.Structure):
            body = c_initializer(v, indent + "    ")
            lines.append(f"{indent}    .{name} = {{\n{body}\n{indent}    }},")
        elif isinstance(v, C.Array):
            items = ", ".join(c_value(x) for x in v)
            lines.append(f"{indent}    .{name} = {{{items}}},")
        else:
            lines.append(f"{indent}    .{name} = {c_value(v)},")
    return "\n".join(lines)
