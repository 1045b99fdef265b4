"""The drive-electronics side: a client for a stage-model node (docs/protocol.md), opened like a
python-can bus (a context manager configured by a URL), and the host node launcher."""

from __future__ import annotations

import io
import math
import os
import re
import select
import socket
import struct
import subprocess
import time
from collections import deque
from dataclasses import replace
from pathlib import Path

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
    checked,
    model_args,
    model_values,
    naming_sent_value,
)


def _rows(what: str, payload: bytes, offset: int, trailer: int = 0) -> tuple[int, list[tuple]]:
    """A block of state rows (u32 first step, u16 count, the rows), checked for its length; a
    trailer of that many bytes may follow the rows."""
    checked(what, payload, offset + 6)
    first, n = struct.unpack_from("<IH", payload, offset)
    if len(payload) - (offset + 6 + n * P.ROW.size) not in {0, trailer}:
        raise BadReplyError(what, f"{len(payload)} bytes for {n} rows")
    rows = [P.ROW.unpack_from(payload, offset + 6 + i * P.ROW.size) for i in range(n)]
    return first, rows


def _open_port(url: str) -> serial.SerialBase:
    """The serial port for url, the HilError for a bad one. pyserial empties a socket's input as
    it opens it; a node that refuses a second client says why at once, so for socket:// URLs the
    first bytes are kept."""
    check_socket_url(url)
    try:
        port = serial.serial_for_url(url, baudrate=1_000_000, timeout=0, do_not_open=True)
        if url.startswith("socket://"):
            port.reset_input_buffer = lambda: None  # type: ignore[method-assign]
            port.open()
            del port.reset_input_buffer
        else:
            port.open()
    except (serial.SerialException, ValueError) as e:
        raise LinkClosedError(f"cannot open the link {url!r}: {e}") from None
    return port


class NodeClient:
    """A session with a node over serial: a device path (a pty or a UART) or a pyserial URL
    (socket://127.0.0.1:PORT, loop://)."""

    def __init__(self, url: str, timeout_s: float = 2.0, handshake: bool = True):
        self.url, self.timeout_s = url, timeout_s
        # non-blocking: waiting is done with select on the port's descriptor (_read_available)
        self.port = _open_port(url)
        self.reader = P.FrameReader()
        self.seq = 0
        self.stats = LinkStats()
        self._node_seq: int | None = None
        self._inbox: deque[P.Packet] = deque()
        self.telemetry: list[tuple] = []
        self.run_misses: int | None = None  # the free run's deadline misses, from its telemetry
        self._run_progress: StepProgress = None  # told the last step of each telemetry frame
        if handshake:
            self.info = self.hello()

    # context manager, like can.Bus
    def __enter__(self) -> NodeClient:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self.port.close()

    # ------------------------------------------------------------ transport
    def send_raw(self, data: bytes) -> None:
        self.port.write(data)
        self.port.flush()

    def _read_available(self, wait_s: float) -> bytes:
        try:
            fd = self.port.fileno()
        except (
            AttributeError,
            NotImplementedError,
            io.UnsupportedOperation,
            serial.SerialException,
        ):
            fd = None  # loop:// and other in-memory ports
        if fd is None:
            time.sleep(max(0.0, min(wait_s, 0.001)))
        else:
            select.select([fd], [], [], max(0.0, min(wait_s, 0.05)))
        try:
            return self.port.read(65536)
        except serial.SerialException as e:
            said = [r for r in self.stats.bad_frames if r.startswith("unmatched error: ")]
            words = f"; the node said: {said[-1][len('unmatched error: ') :]}" if said else ""
            raise LinkClosedError(f"the link to the node closed ({e}){words}") from None

    def _pump(self, deadline: float) -> bool:
        data = self._read_available(deadline - time.monotonic())
        for item in self.reader.feed(data):
            if isinstance(item, P.FrameError):
                self.stats.bad_frames.append(item.reason)
                continue
            self.stats.frames_in += 1
            if self._node_seq is not None:
                gap = (item.seq - self._node_seq) & 0xFF
                if gap == 0:
                    self.stats.duplicate_frames += 1
                    continue
                self.stats.lost_frames += gap - 1
            self._node_seq = item.seq
            self._inbox.append(item)
        return time.monotonic() < deadline

    def _next(self, timeout_s: float) -> P.Packet:
        deadline = time.monotonic() + timeout_s
        while not self._inbox:
            if not self._pump(deadline):
                raise LinkTimeoutError(f"no frame from the node within {timeout_s} s")
        return self._inbox.popleft()

    def request(self, type_: int, payload: bytes = b"", timeout_s: float | None = None) -> bytes:
        """Send one request and return its reply's payload (after ref_seq); telemetry that
        arrives meanwhile is kept in self.telemetry."""
        seq = self.seq
        self.seq = (self.seq + 1) & 0xFF
        self.send_raw(P.frame(type_, seq, payload))
        return self.wait_reply(type_, seq, timeout_s)

    def wait_reply(self, type_: int, seq: int, timeout_s: float | None = None) -> bytes:
        """The payload of the reply to request (type_, seq), after its ref_seq. Telemetry that
        arrives meanwhile is kept, and each frame of it renews the wait: a node that streams a
        long run is busy, not lost."""
        waited = timeout_s or self.timeout_s
        deadline = time.monotonic() + waited
        last_step = None
        while True:
            try:
                pkt = self._next(deadline - time.monotonic())
            except LinkTimeoutError:
                where = (
                    "" if last_step is None else f" (its telemetry stopped after step {last_step})"
                )
                raise LinkTimeoutError(
                    f"no reply to request 0x{type_:02x} (seq {seq}) within {waited} s{where}: "
                    "the request or its reply was lost"
                ) from None
            if pkt.type == P.TELEMETRY:
                rows = _rows("TELEMETRY", pkt.payload, 1, trailer=4)[1]
                self.telemetry.extend(rows)
                end = 7 + len(rows) * P.ROW.size
                if len(pkt.payload) == end + 4:  # the run's deadline misses so far
                    self.run_misses = struct.unpack_from("<I", pkt.payload, end)[0]
                deadline = time.monotonic() + waited
                if rows:
                    last_step = int(rows[-1][0])
                    if self._run_progress is not None:
                        self._run_progress(last_step)
            elif pkt.type == P.ERROR:
                checked("ERROR", pkt.payload, 3)
                reason = pkt.payload[3:].decode(errors="replace")
                if pkt.payload[0] == seq:
                    raise NodeError(pkt.payload[1], pkt.payload[2], reason)
                self.stats.bad_frames.append(f"unmatched error: {reason}")
            elif pkt.type == (type_ | P.REPLY) and checked(P.name(type_), pkt.payload, 1)[0] == seq:
                return pkt.payload[1:]

    # ------------------------------------------------------------ requests
    def hello(self) -> NodeInfo:
        self._node_seq = None  # a new session
        b = checked("HELLO", self.request(P.HELLO), 8)
        ver, model, variant, n, dt = struct.unpack_from("<BBBBf", b)
        if ver != P.VERSION:
            raise BadReplyError("HELLO", f"protocol version {ver}, this client speaks {P.VERSION}")
        if model >= len(P.NODE_MODELS) or variant >= len(VARIANTS):
            raise BadReplyError("HELLO", f"model index {model}, variant index {variant} unknown")
        if not (math.isfinite(dt) and dt > 0):
            raise BadReplyError("HELLO", f"step {dt!r} s")
        return NodeInfo(
            ver, P.NODE_MODELS[model], VARIANTS[variant], n, dt, b[8:].decode(errors="replace")
        )

    def param_info(self, pid: int) -> ParamInfo:
        b = checked("PARAM_INFO", self.request(P.PARAM_INFO, bytes([pid])), 13)
        i, v, lo, hi = struct.unpack_from("<Bfff", b)
        return ParamInfo(i, b[13:].decode(errors="replace"), v, lo, hi)

    def params(self) -> dict[str, ParamInfo]:
        return {p.name: p for p in (self.param_info(i) for i in range(self.info.n_params))}

    @staticmethod
    def _key(param: int | str) -> bytes:
        return bytes([param]) if isinstance(param, int) else b"\xff" + param.encode()

    def get(self, param: int | str) -> float:
        return struct.unpack_from(
            "<Bf", checked("GET_PARAM", self.request(P.GET_PARAM, self._key(param)), 5)
        )[1]

    def set(self, param: int | str, value: float) -> float:
        if isinstance(param, int):
            payload = bytes([param]) + struct.pack("<f", value)
        else:
            payload = b"\xff" + struct.pack("<f", value) + param.encode()
        try:
            reply = self.request(P.SET_PARAM, payload)
        except NodeError as e:
            if "outside its range" not in e.reason:
                raise
            # the node's table has the range (PARAM_INFO); the firmware formats no floats
            p = self.param_info(param if isinstance(param, int) else P.PARAM_NAMES.index(param))
            words = f"{e.reason}: [{p.min:g}, {p.max:g}] (sent {value!r})"
            raise NodeError(e.code, e.request_type, words) from None
        pid, applied = struct.unpack_from("<Bf", checked("SET_PARAM", reply, 5))
        if pid == P.STEP_ID:  # the node's step changed: what info says, and pacing goes by
            self.info = replace(self.info, dt_s=applied)
        return applied

    def set_model(self, values: dict[str, float]) -> int:
        """SET_MODEL: every parameter given at once, applied together or not at all (the node
        names the field at fault); returns how many were set. The model goes to rest."""
        payload = b"".join(
            struct.pack("<Bf", P.PARAM_NAMES.index(k), float(v)) for k, v in values.items()
        )
        n = checked("SET_MODEL", self.request(P.SET_MODEL, payload), 1)[0]
        if "step_s" in values:
            self.info = replace(self.info, dt_s=self.get(P.STEP_ID))
        return n

    def load_model(self, model: ModelFile) -> None:
        """The node runs `model` from now on (model_values: every parameter, effects included)."""
        self.set_model(model_values(model))

    def reset(self, drive0_v: float = 0.0, x0_m: float = 0.0) -> None:
        """The model at rest at drive0_v, the slider at x0_m (|x0_m| <= 1 m)."""
        extra = struct.pack("<f", x0_m) if x0_m != 0.0 else b""  # the short form when at 0
        self.request(P.RESET, struct.pack("<f", drive0_v) + extra)

    def load_waveform(self, w: Sawtooth) -> None:
        payload = struct.pack(
            "<ffffbI",
            w.frequency_hz,
            w.amplitude_v,
            w.offset_v,
            w.rise_fraction,
            w.direction,
            w.cycles,
        )
        try:
            self.request(P.LOAD_WAVEFORM, payload)
        except NodeError as e:
            raise naming_sent_value(e, w.to_dict()) from None

    def drive_block(self, drive_v: np.ndarray, decimation: int = 1) -> list[tuple]:
        payload = struct.pack("<H", decimation) + np.asarray(drive_v, "<f4").tobytes()
        return _rows("DRIVE_BLOCK", self.request(P.DRIVE_BLOCK, payload), 0)[1]

    def lockstep(
        self,
        drive_v: np.ndarray,
        block: int = 40,
        decimation: int = 1,
        progress: StepProgress = None,
    ) -> Telemetry:
        """Co-simulate: send the drive (one sample per step) in blocks, collect the states;
        progress (if given) is told the steps done after each block."""
        if block % decimation:
            raise ValueError("block must be a multiple of decimation")
        rows: list[tuple] = []
        for i in range(0, len(drive_v), block):
            rows += self.drive_block(drive_v[i : i + block], decimation)
            if progress is not None:
                progress(min(i + block, len(drive_v)))
        return Telemetry.from_rows(rows)

    def run(
        self,
        steps: int,
        decimation: int = 1,
        paced: int = 0,
        timeout_s: float | None = None,
        progress: StepProgress = None,
    ) -> Telemetry:
        """Free run of the loaded waveform; telemetry until the node reports the run done;
        progress (if given) is told the node's step as telemetry arrives. paced: 0 as fast as the
        node goes, 1 real time by the node's clock, p > 1 slowed p times (docs/protocol.md); the
        result carries the node's count of steps that ended after their deadline."""
        if not 0 <= int(paced) <= 255:
            raise ValueError(f"paced must be 0 to 255 (a slot of paced x dt), got {paced}")
        self.telemetry = []
        self.run_misses = None
        budget = timeout_s or max(
            self.timeout_s, 5.0 + steps * self.info.dt_s * (1.5 * int(paced) if paced else 0.2)
        )
        self._run_progress = progress
        try:
            b = self.request(
                P.RUN, struct.pack("<IHB", steps, decimation, int(paced)), timeout_s=budget
            )
        finally:
            self._run_progress = None
        (done,) = struct.unpack_from("<I", checked("RUN", b, 4))
        if done != steps:
            raise HilError(f"run ended after {done} of {steps} steps (stopped)")
        misses = struct.unpack_from("<I", b, 4)[0] if len(b) >= 8 else self.run_misses
        return replace(Telemetry.from_rows(self.telemetry), deadline_misses=misses)

    def stop(self) -> int:
        return struct.unpack_from("<I", checked("STOP", self.request(P.STOP), 4))[0]


# ---------------------------------------------------------------- the host node


NODE_PROGRAMS = {"f32": "stickslip_node", "q": "stickslip_node_q"}


def node_binary(variant: str = "f32") -> Path:
    """The host node program: stickslip_node (float32 model) or stickslip_node_q (variant "q",
    the fixed-point model): $STICKSLIP_NODE (or $STICKSLIP_NODE_Q), the package's copy, or a
    development build."""
    if variant not in NODE_PROGRAMS:
        raise ValueError(f"variant must be one of {sorted(NODE_PROGRAMS)}, got {variant!r}")
    name = NODE_PROGRAMS[variant]
    here = Path(__file__).resolve().parent.parent
    for cand in (
        os.environ.get(name.upper()),
        here / "bin" / name,
        here.parents[1] / "build" / "host" / "host_sim" / name,
    ):
        if cand and Path(cand).is_file():
            return Path(cand)
    raise FileNotFoundError(
        f"{name} not found: set {name.upper()} or build with cmake --preset host"
    )


class HostNode:
    """Start stickslip_node (variant "q": stickslip_node_q) as a child process, serving `model`
    (Table I when None); `url` is where to connect: a pty path or socket://127.0.0.1:PORT,
    carrying the serial protocol (pty, tcp) or SLCAN (can-pty, can-tcp)."""

    ARGS = {
        "pty": ["--pty"],
        "tcp": ["--tcp", "0"],
        "can-pty": ["--can-pty"],
        "can-tcp": ["--can-tcp", "0"],
    }

    def __init__(self, link: str = "pty", variant: str = "f32", model: ModelFile | None = None):
        if link not in self.ARGS:
            raise ValueError(f"link must be one of {sorted(self.ARGS)}, got {link!r}")
        exe = node_binary(variant)
        cmd = [str(exe), *self.ARGS[link], *(model_args(model) if model else [])]
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline() if self.proc.stdout else ""
        m = re.search(r"(?:serial|slcan) (?:pty (\S+)|tcp (\S+))", line)
        if not m:
            self.close()
            said = self.proc.stderr.read().strip() if self.proc.stderr else ""
            raise HilError(f"{exe.name} did not start: {said or line!r}")
        self.url = m.group(1) or f"socket://{m.group(2)}"

    def __enter__(self) -> HostNode:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def alive(self) -> bool:
        return self.proc.poll() is None

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()


# target: (board, preset, image); the -q images are the fixed-point node (SS_NODE_MODEL_Q)
QEMU_TARGETS = {
    "qemu-m4f": ("mps2-an386", "cortex-m4f", "stickslip_fw.elf"),
    "qemu-m3": ("mps2-an385", "cortex-m3", "stickslip_fw.elf"),
    "qemu-m4f-q": ("mps2-an386", "cortex-m4f", "stickslip_fw_q.elf"),
    "qemu-m3-q": ("mps2-an385", "cortex-m3", "stickslip_fw_q.elf"),
    # ARMv6-M code on the an385's Cortex-M3 (a superset), as the q staircase runs
    "qemu-m0plus-q": ("mps2-an385", "cortex-m0plus", "stickslip_fw_q.elf"),
}


def firmware_elf(preset: str, image: str = "stickslip_fw.elf") -> Path:
    """A firmware image of a CMake preset (cortex-m4f, cortex-m3, cortex-m0plus): under
    $STICKSLIP_FIRMWARE_ROOT, the current directory (a checkout) or the checkout this module runs
    from. The node is stickslip_fw.elf, the fixed-point node stickslip_fw_q.elf; the fixed-point
    staircase stickslip_q_fw.elf."""
    roots = [
        os.environ.get("STICKSLIP_FIRMWARE_ROOT"),
        Path.cwd(),
        Path(__file__).resolve().parents[3],
    ]
    for root in roots:
        if root is None:
            continue
        elf = Path(root) / "build" / preset / "fw" / image
        if elf.is_file():
            return elf
    raise FileNotFoundError(
        f"build/{preset}/fw/{image} not found (run from the checkout, or set "
        f"STICKSLIP_FIRMWARE_ROOT): build it with cmake --preset {preset} && "
        f"cmake --build --preset {preset}"
    )


class QemuNode(HostNode):
    """The firmware node on an emulated MPS2 board (qemu-system-arm), its UART on TCP loopback.
    icount_shift: None runs the CPU as fast as the host can, and its clock in host time; n runs
    it at one instruction per 2^n ns of a virtual clock (QEMU's -icount shift=n: a 1 GHz part
    at 0, 125 MHz at 3), so a paced run's timing and deadline misses are deterministic."""

    def __init__(self, target: str = "qemu-m4f", icount_shift: int | None = None):
        if target not in QEMU_TARGETS:
            raise ValueError(f"target must be one of {sorted(QEMU_TARGETS)}, got {target!r}")
        board, preset, image = QEMU_TARGETS[target]
        elf = firmware_elf(preset, image)
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        cmd = [
            "qemu-system-arm",
            "-M",
            board,
            "-nographic",
            "-monitor",
            "none",
            "-kernel",
            str(elf),
            "-serial",
            f"tcp:127.0.0.1:{port},server=on,wait=on,nodelay=on",
            "-semihosting-config",
            "enable=on,target=native",
        ]
        if icount_shift is not None:
            if not 0 <= icount_shift <= 10:
                raise ValueError(f"icount_shift must be 0 to 10, got {icount_shift}")
            cmd += ["-icount", f"shift={icount_shift}"]
        self.proc = subprocess.Popen(
            cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
        )
        self.url = f"socket://127.0.0.1:{port}"
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:  # until QEMU listens (it waits for us before it runs)
            if self.proc.poll() is not None:
                raise RuntimeError(
                    f"qemu-system-arm exited: {self.proc.stderr.read() if self.proc.stderr else ''}"
                )
            try:
                socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
                break
            except OSError:
                time.sleep(0.05)
        # that probe connection was QEMU's first client; it takes the next one after it closed
