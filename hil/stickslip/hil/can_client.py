"""The drive-electronics side over CAN: python-can for the bus (SLCAN on a pty or on
socket://127.0.0.1:PORT, SocketCAN where the kernel has it), cantools and the project's DBC
(stickslip.dbc, the single source of truth for ids, signals and scaling) for every frame."""

from __future__ import annotations

import math
import time
from dataclasses import replace
from pathlib import Path

import can
import cantools
import numpy as np
import serial

from ..model import VARIANTS, Sawtooth
from ..model_file import ModelFile
from . import protocol as P
from .node import (
    BadReplyError,
    HilError,
    LinkClosedError,
    LinkStats,
    LinkTimeoutError,
    NodeError,
    NodeInfo,
    ParamInfo,
    StepProgress,
    Telemetry,
    check_socket_url,
    model_values,
    naming_sent_value,
)

DBC_PATH = Path(__file__).with_name("stickslip.dbc")
CMD = {
    "HELLO": 1,
    "GET_PARAM": 2,
    "SET_PARAM": 3,
    "RESET": 4,
    "SET_WAVE": 5,
    "LOAD_WAVE": 6,
    "RUN": 7,
    "STOP": 8,
    "APPLY_MODEL": 9,
}
DRIVE_CMD = 0x10  # replies about lock-step drive frames
WAVE_FIELDS = ["frequency_hz", "amplitude_v", "offset_v", "rise_fraction", "direction", "cycles"]


def load_dbc() -> cantools.database.can.Database:
    db = cantools.database.load_file(str(DBC_PATH))
    if not isinstance(db, cantools.database.can.Database):
        raise TypeError(f"{DBC_PATH} is not a CAN database")
    return db


class CanNodeClient:
    """A session with a node over CAN: a node.NodeSession, as NodeClient (serial) is."""

    def __init__(
        self, channel: str, interface: str = "slcan", timeout_s: float = 2.0, **bus_kwargs
    ):
        kw = dict(bus_kwargs)
        if interface == "slcan":
            kw.setdefault("sleep_after_open", 0)
            kw.setdefault("bitrate", 1_000_000)
        self.url = f"{interface}:{channel}"
        check_socket_url(channel)
        try:
            self.bus = can.Bus(interface=interface, channel=channel, **kw)
        except (can.CanError, serial.SerialException, OSError, ValueError) as e:
            # the host node refuses a second client and closes at once; over SLCAN python-can
            # then only sees its own writes fail
            hint = " (a node serves one client at a time: is another one connected?)"
            raise LinkClosedError(
                f"cannot open the CAN link {self.url!r}: {e}"
                + (hint if channel.startswith("socket://") else "")
            ) from None
        self.db = load_dbc()
        self.timeout_s = timeout_s
        self.seq = 0
        self.drive_seq = 0
        self.stats = LinkStats()
        self.info = self.hello()

    def __enter__(self) -> CanNodeClient:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self.bus.shutdown()

    # ------------------------------------------------------------ frames
    def send(self, name: str, **signals) -> None:
        m = self.db.get_message_by_name(name)
        self.bus.send(
            can.Message(arbitration_id=m.frame_id, data=m.encode(signals), is_extended_id=False)
        )

    def recv(self, timeout_s: float) -> tuple[str, dict] | None:
        msg = self.bus.recv(timeout_s)
        if msg is None:
            return None
        try:
            m = self.db.get_message_by_frame_id(msg.arbitration_id)
        except KeyError:
            return ("", {})  # other traffic
        try:
            signals = m.decode(bytes(msg.data), decode_choices=False)
        except (cantools.database.DecodeError, ValueError, KeyError) as e:
            raise BadReplyError(
                m.name, f"{len(msg.data)} data bytes {bytes(msg.data).hex()}: {e}"
            ) from None
        assert isinstance(signals, dict)  # a plain (not multiplexed container) message
        return m.name, signals

    def request(
        self,
        cmd: str,
        index: int = 0,
        flags: int = 0,
        value: float = 0.0,
        timeout_s: float | None = None,
        states: list | None = None,
        progress: StepProgress = None,
    ) -> dict:
        seq = self.seq
        self.seq = (self.seq + 1) & 0xFF
        self.send("SS_CMD", cmd=CMD[cmd], seq=seq, index=index, flags=flags, value=value)
        waited = timeout_s or self.timeout_s
        deadline = time.monotonic() + waited
        pending: dict = {}
        reason: list[bytes] = []  # SS_REASON frames before a refusal: the node's own words
        while True:
            left = deadline - time.monotonic()
            got = self.recv(max(left, 0.0)) if left > 0 else None
            if got is None:
                raise LinkTimeoutError(
                    f"no SS_REPLY to {cmd} (seq {seq}) within {waited} s: lost on the bus"
                )
            name, sig = got
            if name.startswith("SS_STATE") and states is not None:
                pending.update(sig)
                if name == "SS_STATE_C":
                    states.append(_row(pending))
                    pending = {}
                    if progress is not None:
                        progress(int(states[-1][0]))
            elif name == "SS_REASON" and sig["seq"] == seq and sig["cmd"] == CMD[cmd]:
                reason.append(int(sig["text"]).to_bytes(6, "little").rstrip(b"\0"))
            elif name == "SS_REPLY" and sig["seq"] == seq and sig["cmd"] == CMD[cmd]:
                if sig["status"]:
                    text = b"".join(reason).decode("ascii", errors="replace")
                    raise NodeError(sig["status"], CMD[cmd], text or f"{cmd} index {sig['index']}")
                return sig

    # ------------------------------------------------------------ requests
    def hello(self) -> NodeInfo:
        r = self.request("HELLO")
        model, variant = r["index"] & 0x0F, r["index"] >> 4  # docs/protocol.md, the CAN link
        if model >= len(P.NODE_MODELS) or variant >= len(VARIANTS):
            raise BadReplyError("HELLO", f"model index {model}, variant index {variant} unknown")
        if not (math.isfinite(r["value"]) and r["value"] > 0):
            raise BadReplyError("HELLO", f"step {r['value']!r} s")
        return NodeInfo(
            1,
            P.NODE_MODELS[model],
            VARIANTS[variant],
            len(P.PARAM_NAMES),
            r["value"],
            "can",
        )

    def _id(self, param: int | str) -> int:
        if isinstance(param, int):
            return param
        if param not in P.PARAM_NAMES:
            raise NodeError(
                P.ERROR_CODES["unknown_param"], CMD["GET_PARAM"], f"no parameter {param!r}"
            )
        return P.PARAM_NAMES.index(param)

    def get(self, param: int | str) -> float:
        return self.request("GET_PARAM", index=self._id(param))["value"]

    def set(self, param: int | str, value: float) -> float:
        applied = self.request("SET_PARAM", index=self._id(param), value=value)["value"]
        if self._id(param) == P.STEP_ID:  # the node's step changed: info and pacing follow
            self.info = replace(self.info, dt_s=applied)
        return applied

    def params(self) -> dict[str, ParamInfo]:
        return {
            n: ParamInfo(i, n, self.get(i), math.nan, math.nan) for i, n in enumerate(P.PARAM_NAMES)
        }

    def set_model(self, values: dict[str, float]) -> int:
        """Every parameter given at once (docs/protocol.md, the CAN link: SET_PARAM with flags 1
        stages a value, APPLY_MODEL applies the staged set, all or none); returns how many."""
        for k, v in values.items():
            self.request("SET_PARAM", index=self._id(k), flags=1, value=float(v))
        n = _steps_done("APPLY_MODEL", self.request("APPLY_MODEL")["value"])
        if "step_s" in values:
            self.info = replace(self.info, dt_s=self.get(P.STEP_ID))
        return n

    def load_model(self, model: ModelFile) -> None:
        """The node runs `model` from now on (model_values: every parameter, effects included)."""
        self.set_model(model_values(model))

    def reset(self, drive0_v: float = 0.0, x0_m: float = 0.0) -> None:
        """The model at rest at drive0_v; the CAN RESET places the slider at 0 only."""
        if x0_m != 0.0:
            raise HilError(f"x0_m: the CAN RESET places the slider at 0 (asked {x0_m!r} m)")
        self.request("RESET", value=drive0_v)

    def load_waveform(self, w: Sawtooth) -> None:
        try:
            for i, f in enumerate(WAVE_FIELDS):
                self.request("SET_WAVE", index=i, value=float(getattr(w, f)))
            self.request("LOAD_WAVE")
        except NodeError as e:
            raise naming_sent_value(e, {f: getattr(w, f) for f in WAVE_FIELDS}) from None

    def lockstep(
        self,
        drive_v: np.ndarray,
        block: int = 40,
        decimation: int = 1,
        progress: StepProgress = None,
    ) -> Telemetry:
        """One SS_DRIVE frame per step, `block` frames in flight; a state every decimation steps;
        progress (if given) is told the steps done after each block."""
        rows: list[tuple] = []
        pending: dict = {}
        n = len(drive_v)
        for start in range(0, n, block):
            end = min(n, start + block)
            want = len(rows) + sum(1 for i in range(start, end) if (i + 1) % decimation == 0)
            for i in range(start, end):
                self.drive_seq = (self.drive_seq + 1) & 0xFF
                self.send(
                    "SS_DRIVE",
                    drive_v=float(drive_v[i]),
                    seq=self.drive_seq,
                    report=int((i + 1) % decimation == 0),
                )
            deadline = time.monotonic() + self.timeout_s
            while len(rows) < want:
                got = self.recv(max(0.0, deadline - time.monotonic()))
                if got is None:
                    raise LinkTimeoutError(
                        f"lock-step: {want - len(rows)} states missing after step {i + 1}"
                    )
                name, sig = got
                if name == "SS_REPLY" and sig["status"]:
                    raise NodeError(sig["status"], sig["cmd"], f"drive frame seq {sig['seq']}")
                if name.startswith("SS_STATE"):
                    pending.update(sig)
                    if name == "SS_STATE_C":
                        rows.append(_row(pending))
                        pending = {}
            if progress is not None:
                progress(end)
        return Telemetry.from_rows(rows)

    def run(
        self,
        steps: int,
        decimation: int = 1,
        paced: int = 0,
        timeout_s: float | None = None,
        progress: StepProgress = None,
    ) -> Telemetry:
        if not 1 <= decimation <= 255:
            raise ValueError(f"decimation over CAN is 1..255, got {decimation}")
        rows: list[tuple] = []
        # model time when paced, plus the reading: python-can's slcan parses ~1 frame per 0.5 ms
        frames = 3 * (steps // decimation)
        paced_s = steps * self.info.dt_s * 1.5 * int(paced)
        budget = timeout_s or max(self.timeout_s, 5.0 + paced_s + frames * 1e-3)
        r = self.request(
            "RUN",
            index=decimation,
            flags=int(paced),
            value=float(steps),
            timeout_s=budget,
            states=rows,
            progress=progress,
        )
        done = _steps_done("RUN", r["value"])
        if done != steps:
            raise HilError(f"run ended after {done} of {steps} steps (stopped)")
        return Telemetry.from_rows(rows)

    def stop(self) -> int:
        return _steps_done("STOP", self.request("STOP")["value"])


def _steps_done(what: str, value: float) -> int:
    """A reply's step count (a float32 on CAN): a whole number >= 0, or BadReplyError."""
    if not (math.isfinite(value) and value >= 0 and value == int(value)):
        raise BadReplyError(what, f"steps done {value!r}, not a whole number")
    return int(value)


def _row(s: dict) -> tuple:
    """One state from its A, B and C frames (SS_STATE_C closes it)."""
    missing = [k for k in _ROW_SIGNALS if k not in s]
    if missing:
        raise BadReplyError("SS_STATE_C", f"a state without {missing}: its A or B frame was lost")
    return (
        s["step"],
        s["drive_v"],
        s["x_rod_m"],
        s["x_slider_hi_m"],
        s["x_slider_lo_m"],
        s["friction_n"],
    )


_ROW_SIGNALS = ("step", "drive_v", "x_rod_m", "x_slider_hi_m", "x_slider_lo_m", "friction_n")
