"""The node protocol of docs/protocol.md: COBS framing, CRC-16/CCITT-FALSE, packets."""

from __future__ import annotations

import binascii
import struct
from collections.abc import Iterator
from dataclasses import dataclass

VERSION = 1
MAX_PAYLOAD = 1024
OVERHEAD = 6
MAX_PACKET = MAX_PAYLOAD + OVERHEAD
MAX_WIRE = MAX_PACKET + MAX_PACKET // 254 + 2

HELLO, PARAM_INFO, GET_PARAM, SET_PARAM, RESET, LOAD_WAVEFORM, DRIVE_BLOCK, RUN, STOP = range(1, 10)
SET_MODEL = 0x0A
TELEMETRY, ERROR, REPLY = 0x10, 0x7F, 0x80
TYPE_NAMES = {
    HELLO: "HELLO",
    PARAM_INFO: "PARAM_INFO",
    GET_PARAM: "GET_PARAM",
    SET_PARAM: "SET_PARAM",
    RESET: "RESET",
    LOAD_WAVEFORM: "LOAD_WAVEFORM",
    DRIVE_BLOCK: "DRIVE_BLOCK",
    RUN: "RUN",
    STOP: "STOP",
    SET_MODEL: "SET_MODEL",
    TELEMETRY: "TELEMETRY",
    ERROR: "ERROR",
}


def name(type_: int) -> str:
    """A message type's name ("RUN"), or its number for one the protocol does not define."""
    return TYPE_NAMES.get(type_, f"0x{type_:02x}")


MAX_ROWS = 40
ROW = struct.Struct("<Ifffff")  # step, drive_v, x_rod_m, x_slider_hi_m, x_slider_lo_m, friction_n

ERROR_NAMES = {
    1: "bad_crc",
    2: "bad_length",
    3: "unknown_type",
    4: "bad_payload",
    5: "out_of_range",
    6: "non_finite",
    7: "duplicate",
    8: "busy",
    9: "bad_framing",
    10: "oversize",
    11: "no_waveform",
    12: "unknown_param",
}
ERROR_CODES = {v: k for k, v in ERROR_NAMES.items()}

NODE_MODELS = ("ls", "lugre")  # HELLO's model index (the node's friction_model parameter)

# parameter ids of docs/protocol.md (the CAN messages carry ids only)
PARAM_NAMES = [
    "piezo_stiffness_n_per_m",
    "piezo_damping_kg_per_s",
    "rod_mass_kg",
    "slider_mass_kg",
    "piezo_gain_m_per_v",
    "mu_s",
    "mu_d",
    "normal_force_n",
    "stribeck_velocity_m_per_s",
    "sigma0_n_per_m",
    "sigma1_ns_per_m",
    "sigma2_ns_per_m",
    "friction_model",
    # the catalog's effects (ids 13 on; docs/effects.md), all off by default
    "friction_asymmetry",
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
    # the model's step (id 27), the node's clock for paced runs
    "step_s",
    # the amplifier's bandwidth behind its slew limit (id 28), an effect added after the step
    "amp_bandwidth_hz",
]
STEP_ID = PARAM_NAMES.index("step_s")
EFFECT_PARAMS = [
    *PARAM_NAMES[PARAM_NAMES.index("friction_asymmetry") : STEP_ID],
    *PARAM_NAMES[STEP_ID + 1 :],
]
NODE_LAWS = {"ls": 0.0, "lugre": 1.0}  # the friction_model parameter's values


def crc16(data: bytes) -> int:
    """CRC-16/CCITT-FALSE: binascii's CRC-CCITT (poly 0x1021, MSB first) from init 0xFFFF."""
    return binascii.crc_hqx(data, 0xFFFF)


def cobs_encode(data: bytes) -> bytes:
    out = bytearray([0])
    code_at, code = 0, 1
    for b in data:
        if b == 0:
            out[code_at] = code
            code_at, code = len(out), 1
            out.append(0)
        else:
            out.append(b)
            code += 1
            if code == 0xFF:
                out[code_at] = code
                code_at, code = len(out), 1
                out.append(0)
    out[code_at] = code
    return bytes(out)


def cobs_decode(data: bytes) -> bytes:
    out = bytearray()
    i = 0
    while i < len(data):
        code = data[i]
        i += 1
        if code == 0 or i + code - 1 > len(data):
            raise ValueError("invalid COBS")
        chunk = data[i : i + code - 1]
        if 0 in chunk:
            raise ValueError("invalid COBS")
        out += chunk
        i += code - 1
        if code != 0xFF and i < len(data):
            out.append(0)
    return bytes(out)


def packet(type_: int, seq: int, payload: bytes = b"") -> bytes:
    """The packet before COBS: header, payload, CRC."""
    if len(payload) > MAX_PAYLOAD:
        raise ValueError(f"payload of {len(payload)} bytes exceeds {MAX_PAYLOAD}")
    head = struct.pack("<BBH", type_, seq & 0xFF, len(payload)) + payload
    return head + struct.pack("<H", crc16(head))


def frame(type_: int, seq: int, payload: bytes = b"") -> bytes:
    """A complete wire frame: COBS(packet) + 0x00."""
    return cobs_encode(packet(type_, seq, payload)) + b"\x00"


@dataclass(frozen=True)
class Packet:
    type: int
    seq: int
    payload: bytes


@dataclass(frozen=True)
class FrameError:
    """A frame that ended bad on this side (our receiver's view)."""

    reason: str


class FrameReader:
    """Byte stream in, packets (or FrameError) out; resynchronises on 0x00."""

    def __init__(self) -> None:
        self.buf = bytearray()
        self.overflow = False

    def feed(self, data: bytes) -> Iterator[Packet | FrameError]:
        *complete, rest = bytes(data).split(b"\x00")
        for part in complete:
            raw = bytes(self.buf) + part
            overflow = self.overflow or len(raw) > MAX_WIRE
            self.buf.clear()
            self.overflow = False
            if overflow:
                yield FrameError("oversize")
            elif raw:
                yield self._judge(raw)
        if len(self.buf) + len(rest) > MAX_WIRE:
            self.overflow = True  # discard up to the next delimiter
            self.buf.clear()
        elif not self.overflow:
            self.buf += rest

    @staticmethod
    def _judge(raw: bytes) -> Packet | FrameError:
        try:
            pkt = cobs_decode(raw)
        except ValueError:
            return FrameError("bad_framing")
        if len(pkt) < OVERHEAD:
            return FrameError("bad_length")
        type_, seq, n = struct.unpack_from("<BBH", pkt)
        if n + OVERHEAD != len(pkt):
            return FrameError("bad_length")
        if struct.unpack_from("<H", pkt, 4 + n)[0] != crc16(pkt[: 4 + n]):
            return FrameError("bad_crc")
        return Packet(type_, seq, pkt[4 : 4 + n])
