"""Write tests/vectors/can_frames.csv from the DBC with cantools: the frames the C side must
produce byte for byte (tests/c/test_can.c). tests/python/test_hil_can.py regenerates the file in
memory and fails if it differs, so the vectors cannot drift from the DBC.

    .venv/bin/python tests/vectors/make_can_vectors.py
"""

from __future__ import annotations

import io
import json
import struct
from pathlib import Path

from stickslip.hil.can_client import load_dbc

OUT = Path(__file__).with_name("can_frames.csv")

CASES = [
    ("SS_CMD", {"cmd": 3, "seq": 7, "index": 5, "flags": 0, "value": 0.5}),
    ("SS_CMD", {"cmd": 7, "seq": 255, "index": 10, "flags": 1, "value": 123456.0}),
    ("SS_REPLY", {"cmd": 1, "seq": 0, "status": 0, "index": 1, "value": 1e-6}),
    ("SS_REPLY", {"cmd": 3, "seq": 9, "status": 5, "index": 6, "value": -2.5}),
    ("SS_REASON", {"cmd": 3, "seq": 9, "text": int.from_bytes(b"mu_d: ", "little")}),
    ("SS_DRIVE", {"drive_v": 12.5, "seq": 3, "report": 1}),
    ("SS_DRIVE", {"drive_v": -99.75, "seq": 200, "report": 0}),
    ("SS_STATE_A", {"step": 4000000000, "drive_v": 100.0}),
    ("SS_STATE_B", {"x_rod_m": 4.4e-6, "friction_n": -3.0}),
    ("SS_STATE_C", {"x_slider_hi_m": 0.0125, "x_slider_lo_m": -1.5e-12}),
]


def f32(v: float) -> float:
    return struct.unpack("<f", struct.pack("<f", v))[0]


def render() -> str:
    db = load_dbc()
    out = io.StringIO()
    out.write("# stickslip.dbc frames encoded by cantools: name;id;dlc;signals (JSON);data_hex\n")
    for name, sig in CASES:
        m = db.get_message_by_name(name)
        data = m.encode(sig)
        exact = {k: (f32(v) if isinstance(v, float) else v) for k, v in sig.items()}
        out.write(f"{name};{m.frame_id};{m.length};{json.dumps(exact)};{data.hex()}\n")
    return out.getvalue()


if __name__ == "__main__":
    OUT.write_text(render())
    print(f"wrote {OUT}")
