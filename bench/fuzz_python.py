"""Fuzz the Python side's readers of outside input with atheris (coverage-guided, libFuzzer's
engine), a fixed number of executions each:

  decoder      the serial client's reply path: a request, then whatever bytes the "node" sends
               (framed packets of any type, seq and payload, raw bytes, a closed link);
  can_decoder  the CAN client's: a request, then CAN frames of any id and data;
  dataset      the dataset reader: a run CSV of any bytes beside a valid dataset.json, or a
               dataset.json of any bytes beside a valid run.

Each input must end in a return or in the documented exception (HilError for the clients,
DatasetError for the reader); anything else (IndexError, struct.error, a hang) is a finding.

    .venv/bin/pip install atheris      # or: pip install '.[fuzz]'
    PYTHONPATH=hil .venv/bin/python bench/fuzz_python.py TARGET [RUNS] [libFuzzer flags...]

Findings go to build/fuzz/py_<target>/ as crash-* files; corpora persist there.
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

try:
    import atheris
except ImportError:
    sys.exit("fuzz_python: needs atheris (.venv/bin/pip install atheris)")

import contextlib
import json

import can
import numpy as np
import serial

with atheris.instrument_imports(include=["stickslip"]):  # coverage of our code, not numpy's
    from stickslip import dataset as D
    from stickslip.hil import protocol as P
    from stickslip.hil.can_client import CanNodeClient, load_dbc
    from stickslip.hil.client import NodeClient
    from stickslip.hil.node import HilError, LinkStats, NodeInfo
    from stickslip.model import ActuatorParams, Sawtooth

ROOT = Path(__file__).resolve().parent.parent
INFO = NodeInfo(P.VERSION, "ls", "f32", len(P.PARAM_NAMES), 1e-6, "fuzz")

# ------------------------------------------------------------------ serial client


class FakePort:
    """The node's side of a link: hands out the fuzzer's bytes, then b"" or a disconnect."""

    def __init__(self) -> None:
        self.fd = os.open(os.devnull, os.O_RDONLY)  # select() on it returns at once
        self.data, self.closes = b"", False

    def fileno(self) -> int:
        return self.fd

    def read(self, n: int) -> bytes:
        if not self.data and self.closes:
            raise serial.SerialException("socket disconnected")
        d, self.data = self.data[:n], self.data[n:]
        return d

    def write(self, b: bytes) -> int:
        return len(b)

    def flush(self) -> None:
        pass

    def close(self) -> None:
        pass


def _serial_client() -> NodeClient:
    c = NodeClient("loop://", timeout_s=1e-4, handshake=False)
    c.port.close()
    c.port = FakePort()
    c.info = INFO
    return c


SERIAL = None
TYPES = [*range(1, 10), P.TELEMETRY, P.ERROR, *(t | P.REPLY for t in range(1, 10))]
REQUESTS = [
    lambda c: c.hello(),
    lambda c: c.param_info(3),
    lambda c: c.get("mu_s"),
    lambda c: c.set(2, 1e-3),
    lambda c: c.reset(0.0),
    lambda c: c.load_waveform(Sawtooth()),
    lambda c: c.drive_block(np.zeros(4), 2),
    lambda c: c.run(8, 2, timeout_s=1e-4),
    lambda c: c.stop(),
]


def fuzz_decoder(data: bytes) -> None:
    global SERIAL
    if SERIAL is None:
        SERIAL = _serial_client()
    c = SERIAL
    c.reader, c.seq, c.stats, c._node_seq = P.FrameReader(), 0, LinkStats(), None
    c._inbox.clear()
    c.telemetry = []
    f = atheris.FuzzedDataProvider(data)
    request = REQUESTS[f.ConsumeIntInRange(0, len(REQUESTS) - 1)]
    wire = bytearray()
    for _ in range(f.ConsumeIntInRange(0, 6)):
        kind = f.ConsumeIntInRange(0, 3)
        if kind == 3:
            wire += f.ConsumeBytes(f.ConsumeIntInRange(0, 40))  # raw bytes
            continue
        type_ = TYPES[f.ConsumeIntInRange(0, len(TYPES) - 1)] if kind else f.ConsumeInt(1) & 0xFF
        ref = b"\x00" if f.ConsumeBool() else b""  # the reply's ref_seq (the request's seq: 0)
        payload = ref + f.ConsumeBytes(f.ConsumeIntInRange(0, 300))
        wire += P.frame(type_, f.ConsumeInt(1) & 0xFF, payload[: P.MAX_PAYLOAD])
    c.port.data, c.port.closes = bytes(wire), f.ConsumeBool()
    with contextlib.suppress(HilError):  # the documented refusal; anything else is a finding
        request(c)


# ------------------------------------------------------------------ CAN client


class FakeBus:
    def __init__(self) -> None:
        self.frames: list[can.Message] = []

    def send(self, msg: can.Message) -> None:
        pass

    def recv(self, timeout: float | None = None) -> can.Message | None:
        return self.frames.pop(0) if self.frames else None

    def shutdown(self) -> None:
        pass


def _can_client() -> CanNodeClient:
    c = CanNodeClient.__new__(CanNodeClient)  # no bus to open: the fuzzer is the bus
    c.url, c.bus, c.db, c.timeout_s = "fuzz", FakeBus(), load_dbc(), 1e-4
    c.seq = c.drive_seq = 0
    c.stats, c.info = LinkStats(), INFO
    return c


CAN = None
CAN_IDS = [0x101, 0x102, 0x120, 0x121, 0x122, 0x100, 0x110]
CAN_REQUESTS = [
    lambda c: c.hello(),
    lambda c: c.get(1),
    lambda c: c.set(1, 2.0),
    lambda c: c.reset(0.0),
    lambda c: c.load_waveform(Sawtooth()),
    lambda c: c.lockstep(np.zeros(3)),
    lambda c: c.run(5, 1, timeout_s=1e-4),
    lambda c: c.stop(),
]


def fuzz_can_decoder(data: bytes) -> None:
    global CAN
    if CAN is None:
        CAN = _can_client()
    c = CAN
    c.seq = c.drive_seq = 0
    f = atheris.FuzzedDataProvider(data)
    request = CAN_REQUESTS[f.ConsumeIntInRange(0, len(CAN_REQUESTS) - 1)]
    frames = []
    for _ in range(f.ConsumeIntInRange(0, 12)):
        i = f.ConsumeIntInRange(0, len(CAN_IDS))
        arb = CAN_IDS[i] if i < len(CAN_IDS) else f.ConsumeIntInRange(0, 0x7FF)
        frames.append(
            can.Message(arbitration_id=arb, data=f.ConsumeBytes(f.ConsumeIntInRange(0, 8)))
        )
    c.bus.frames = frames
    with contextlib.suppress(HilError):  # the documented refusal; anything else is a finding
        request(c)


# ------------------------------------------------------------------ dataset reader

DATA_DIR = Path(
    tempfile.mkdtemp(prefix="ss_fuzz_", dir="/dev/shm" if os.path.isdir("/dev/shm") else None)
)
GOOD_CSV = b"t_s,drive_v,x_m\n0,0,0\n1e-5,1,4.4e-8\n2e-5,2,8.8e-8\n"
GOOD_JSON = json.dumps(
    {
        "format": D.FORMAT,
        "actuator": ActuatorParams().to_dict(),
        "sensor": {"resolution_m": 1e-9},
        "runs": [{"id": "r", "file": "r.csv", "waveform": Sawtooth(cycles=1).to_dict()}],
    }
).encode()


def fuzz_dataset(data: bytes) -> None:
    which, body = (data[0] & 1, data[1:]) if data else (0, b"")
    (DATA_DIR / "r.csv").write_bytes(body if which == 0 else GOOD_CSV)
    (DATA_DIR / "dataset.json").write_bytes(GOOD_JSON if which == 0 else body)
    with contextlib.suppress(D.DatasetError):
        D.load(DATA_DIR)


TARGETS = {"decoder": fuzz_decoder, "can_decoder": fuzz_can_decoder, "dataset": fuzz_dataset}


def main() -> None:
    if len(sys.argv) < 2 or sys.argv[1] not in TARGETS:
        sys.exit(f"usage: fuzz_python.py {{{','.join(TARGETS)}}} [RUNS] [libFuzzer flags]")
    target = sys.argv[1]
    runs = sys.argv[2] if len(sys.argv) > 2 and sys.argv[2].isdigit() else "1000000"
    extra = sys.argv[3:] if len(sys.argv) > 2 and sys.argv[2].isdigit() else sys.argv[2:]
    out = ROOT / "build" / "fuzz" / f"py_{target}"
    (out / "corpus").mkdir(parents=True, exist_ok=True)
    if target == "dataset":  # seeds: the valid files, each in its slot
        (out / "corpus" / "csv").write_bytes(b"\x00" + GOOD_CSV)
        (out / "corpus" / "json").write_bytes(b"\x01" + GOOD_JSON)
    argv = [sys.argv[0], f"-runs={runs}", f"-artifact_prefix={out}/", "-print_final_stats=1"]
    atheris.Setup([*argv, *extra, str(out / "corpus")], TARGETS[target])
    atheris.Fuzz()


if __name__ == "__main__":
    main()
