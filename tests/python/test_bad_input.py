"""The bad-input table (issue 15): each row is an input a tool cannot honour, the exit status it
must give and the words its message must hold (the field, the value or the accepted range). An
input is honoured exactly or refused by name: no default stands in for a bad value, and nothing
is reported as written when it was not."""

from __future__ import annotations

import io
import math
import struct
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HOST_SIM = ROOT / "build" / "host" / "host_sim" / "stickslip_sim"

# (arguments, exit status, words the message must hold)
HOST_SIM_CASES = [
    # a bad value used to stand for "not given": the paper's default ran, exit 0
    (["--frequency-hz", "-250"], 2, ["--frequency-hz", "must be > 0 Hz", "-250"]),
    (["--rise-fraction", "-0.5"], 2, ["--rise-fraction", "(0, 1)", "-0.5"]),
    (["--rise-fraction", "1"], 2, ["--rise-fraction", "(0, 1)"]),
    (["--fall-time-s", "-1"], 2, ["--fall-time-s", "must be > 0 s", "-1"]),
    (["--direction", "0"], 2, ["--direction", "+1 (forward) or -1 (backward)", "'0'"]),
    # "waveform rejected" named the wrong field
    (["--dt-s", "0"], 2, ["--dt-s", "must be > 0 s"]),
    (["--dt-s", "-1e-6"], 2, ["--dt-s", "must be > 0 s"]),
    # a step longer than the edges: a number as if it meant something
    (["--dt-s", "1e-3"], 2, ["--dt-s", "does not resolve", "0.0001 s edge", "dt <= 1e-05 s"]),
    (["--frequency-hz", "1e6"], 2, ["does not resolve", "1e+06 Hz", "10 steps per edge"]),
    (["--fall-time-s", "5e-6"], 2, ["does not resolve", "5e-06 s edge"]),
    (["--fall-time-s", "0.01"], 2, ["--fall-time-s", "does not fit", "0.002 s period"]),
    (["--rise-fraction", "0.9", "--fall-time-s", "1e-5"], 2, ["give one of them, not both"]),
    # already refused by name before issue 15: kept from regressing
    (["--frequency-hz", "fast"], 2, ["--frequency-hz", "expected a finite number", "'fast'"]),
    (["--frequency-hz", "nan"], 2, ["--frequency-hz", "expected a finite number"]),
    (["--amplitude-v", "inf"], 2, ["--amplitude-v", "expected a finite number"]),
    (["--direction", "2"], 2, ["--direction", "integer out of range", "'2'"]),
    (["--cycles", "-1"], 2, ["--cycles", "integer out of range"]),
    (["--cycles", "1.5"], 2, ["--cycles", "expected an integer"]),
    (["--decimation", "0"], 2, ["--decimation", "integer out of range"]),
    (["--hold-s", "-1"], 2, ["--hold-s", "[0, 3600]"]),
    (["--model", "dahl"], 2, ["--model", "expected ls, lugre or gms", "'dahl'"]),
    (["--scenario", "nope"], 2, ["--scenario", "unknown scenario", "'nope'"]),
    (["--bogus"], 2, ["unknown or incomplete option", "--bogus"]),
    (["extra"], 2, ["unexpected argument", "'extra'"]),
    # the output could not be written: exit 0 before
    (["--cycles", "1", "--out", "/dev/full"], 1, ["--out", "writing '/dev/full' failed"]),
    (["--cycles", "1", "--out", "/nonexistent/x.csv"], 1, ["--out", "cannot open"]),
]


@pytest.mark.skipif(not HOST_SIM.exists(), reason="host build missing (cmake --preset host)")
@pytest.mark.parametrize(("args", "status", "words"), HOST_SIM_CASES, ids=lambda x: str(x))
def test_host_sim_refuses_by_name(args, status, words):
    r = subprocess.run([str(HOST_SIM), *args], capture_output=True, text=True, timeout=60)
    assert r.returncode == status, r.stderr
    for w in words:
        assert w in r.stderr, (w, r.stderr)
    if status != 0:
        assert "mean step" not in r.stderr  # nothing reported as done


@pytest.mark.skipif(not HOST_SIM.exists(), reason="host build missing (cmake --preset host)")
def test_host_sim_honours_the_edges_it_can_resolve(tmp_path):
    # the shortest edge the default 1 us step resolves (10 steps), given as a fall time
    out = tmp_path / "x.csv"
    r = subprocess.run(
        [str(HOST_SIM), "--fall-time-s", "10e-6", "--cycles", "1", "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    assert len(out.read_text().splitlines()) == 1 + 2000 + 1  # header, t = 0, one 2 ms period


SIMULATE_CASES = [
    # tracebacks before
    (["--cycles", "0", "--json"], ["--cycles", "must be >= 1", "got 0"]),
    (["--decimation", "40001", "--json"], ["--decimation 40001", "choose a divisor of 2000"]),
    # a summary of zeros, a moved final position
    (["--decimation", "20000", "--json"], ["--decimation 20000", "period boundary"]),
    (["--decimation", "7", "--json"], ["--decimation 7", "1, 2, 4, 5, 8, 10"]),
    (["--decimation", "8", "--hold-s", "3e-6"], ["40003 steps", "final position"]),
    (["--frequency-hz", "300", "--decimation", "2"], ["3333.33 steps", "--decimation 1"]),
    (["--decimation", "0"], ["--decimation", "must be >= 1"]),
    # a step as long as the edge or the period, reported as if it meant something
    (["--frequency-hz", "1e6", "--json"], ["--dt-s", "does not resolve", "1e+06 Hz"]),
    (["--dt-s", "1e-3", "--json"], ["--dt-s", "does not resolve", "dt <= 1e-05 s"]),
    (["--dt-s", "0"], ["--dt-s", "must be > 0 s"]),
    # refused by name before issue 15: kept from regressing
    (["--frequency-hz", "-5"], ["--frequency-hz", "must be > 0"]),
    (["--rise-fraction", "0.5", "--fall-time-s", "1e-5"], ["not both"]),
    (["--fall-time-s", "0.01"], ["rise fraction must be in (0, 1)"]),
]


@pytest.mark.parametrize(("args", "words"), SIMULATE_CASES, ids=lambda x: str(x))
def test_simulate_refuses_by_name(capsys, tmp_path, args, words):
    from stickslip.cli import main

    out = tmp_path / "never.csv"
    assert main(["simulate", *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    for w in words:
        assert w in err, (w, err)
    assert not out.exists()  # refused before anything ran or was written


def test_simulate_decimation_does_not_change_the_summary(capsys):
    import json

    from stickslip.cli import main

    summaries = []
    for dec in ("1", "8", "2000"):
        assert main(["simulate", "--cycles", "5", "--decimation", dec, "--json"]) == 0
        s = json.loads(capsys.readouterr().out)
        summaries.append({k: s[k] for k in ("per_cycle_steps_m", "final_slider_position_m")})
    assert summaries[0] == summaries[1] == summaries[2]


HIL_RUN_CASES = [
    # NaN in the JSON before (not valid JSON)
    (["--cycles", "0", "--json"], ["--cycles", "must be >= 1"]),
    # struct.error before
    (["--decimation", "100000", "--cycles", "1"], ["--decimation 100000", "divisor of 2000"]),
    # a 74.5 GiB allocation before
    (["--frequency-hz", "1e-3", "--cycles", "1"], ["1000000003 steps", "above the 10000000"]),
    (["--decimation", "7", "--cycles", "1"], ["--decimation 7", "1, 2, 4, 5, 8, 10"]),
]


@pytest.mark.skipif(
    not (ROOT / "build" / "host" / "host_sim" / "stickslip_node").exists(),
    reason="host build missing (cmake --preset host)",
)
@pytest.mark.parametrize(("args", "words"), HIL_RUN_CASES, ids=lambda x: str(x))
def test_hil_run_refuses_by_name_before_it_runs(capsys, tmp_path, args, words):
    from stickslip.cli import main

    out = tmp_path / "never"
    assert main(["hil", "run", *args, "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    for w in words:
        assert w in err, (w, err)
    assert not out.exists()


def test_run_budget_names_what_does_not_fit():
    from stickslip.hil.session import run_budget
    from stickslip.model import Sawtooth

    assert run_budget(Sawtooth(cycles=2), 1e-6, "lockstep", 10) == 4000
    with pytest.raises(ValueError, match=r"decimation: must be in \[1, 65535\], got 70000"):
        run_budget(Sawtooth(), 1e-6, "free", 70000)
    with pytest.raises(ValueError, match="raise --decimation to at least 2"):
        run_budget(Sawtooth(frequency_hz=1.0, cycles=15), 1e-6, "free", 1)
    with pytest.raises(ValueError, match="use --mode free"):
        run_budget(Sawtooth(frequency_hz=1.0, cycles=150), 1e-6, "lockstep", 100)


DIAGNOSE_OUTPUT_CASES = [
    # these failed only after the whole diagnosis (minutes) before
    (["--out", "/proc/stickslip-nope"], ["--out", "cannot write to '/proc/stickslip-nope'"]),
    (["--out", "/dev/null/x"], ["--out", "cannot write to", "Not a directory"]),
    (["--json", "/dev/null/x.json"], ["--json", "cannot write to '/dev/null'"]),
]


@pytest.mark.parametrize(("args", "words"), DIAGNOSE_OUTPUT_CASES, ids=lambda x: str(x))
def test_diagnose_refuses_an_unwritable_output_before_it_computes(capsys, monkeypatch, args, words):
    import stickslip.diagnosis.pipeline as pipeline
    from stickslip.cli import main

    def never(*_a, **_k):
        raise AssertionError("the diagnosis ran before its output was checked")

    monkeypatch.setattr(pipeline, "diagnose", never)
    assert main(["diagnose", str(ROOT / "examples" / "hidden-effect"), *args, "--quiet"]) == 2
    err = capsys.readouterr().err
    for w in words:
        assert w in err, (w, err)


def test_json_output_never_holds_a_nan(capsys):
    import argparse

    from stickslip.cli import _report

    with pytest.raises(ValueError, match="not JSON compliant"):
        _report(argparse.Namespace(json="-"), {"mean_step_per_cycle_m": float("nan")}, "")


def _example_copy(tmp_path: Path, edit_meta=None, edit_csv=None) -> Path:
    """A copy of the bundled example dataset, its first run's metadata or CSV edited."""
    import json
    import shutil

    dst = tmp_path / "ds"
    shutil.copytree(ROOT / "examples" / "hidden-effect", dst)
    meta = json.loads((dst / "dataset.json").read_text())
    run = meta["runs"][0]
    if edit_meta:
        edit_meta(run)
        (dst / "dataset.json").write_text(json.dumps(meta))
    if edit_csv:
        f = dst / run["file"]
        f.write_text(edit_csv(f.read_text()))
    return dst


def _scale_column(text: str, column: str, k: float) -> str:
    lines = text.splitlines()
    j = lines[0].split(",").index(column)
    out = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        cells[j] = repr(float(cells[j]) * k)
        out.append(",".join(cells))
    return "\n".join(out) + "\n"


def _set(key, value):
    def edit(run):
        run["waveform"][key] = value

    return edit


# (metadata edit, csv edit, words of the error): contradictions, named by file and field
DATASET_CONTRADICTIONS = [
    # the case: amplitude -100 against a 0 to 100 V ramp, confident wrong causes before
    (_set("amplitude_v", -100.0), None, ["drive_v contradicts runs[0].waveform", "amplitude_v"]),
    (_set("direction", -1), None, ["drive_v contradicts", "fits direction = 1, the block says -1"]),
    (_set("frequency_hz", 1000.0), None, ["drive_v contradicts", "frequency_hz = 500"]),
    (_set("offset_v", 20.0), None, ["drive_v contradicts", "offset_v = 0"]),
]


@pytest.mark.parametrize(("meta", "csv", "words"), DATASET_CONTRADICTIONS, ids=lambda x: str(x))
def test_dataset_metadata_contradicting_its_data_is_an_error(tmp_path, meta, csv, words):
    from stickslip import dataset as D

    path = _example_copy(tmp_path, meta, csv)
    with pytest.raises(D.DatasetError) as e:
        D.load(path)
    for w in words:
        assert w in str(e.value), (w, str(e.value))
    assert ".csv" in str(e.value) and "column 'drive_v'" in str(e.value)


def test_positions_in_millimetres_are_flagged_by_file(tmp_path, capsys):
    from stickslip import dataset as D

    path = _example_copy(tmp_path, None, lambda t: _scale_column(t, "x_m", 1e3))
    ds = D.load(path)
    assert len(ds.warnings) == 1 and "are the positions in metres?" in ds.warnings[0]
    assert ds.runs[0].file.name in ds.warnings[0]
    assert D.load(ROOT / "examples" / "hidden-effect").warnings == []


def test_an_unresolved_edge_without_a_waveform_block_is_an_error(tmp_path):
    from stickslip import dataset as D

    def drop_waveform(run):
        del run["waveform"]

    def every_5th_row(text: str) -> str:  # 50 kS/s to 10 kS/s: the 100 us fall in one sample
        lines = text.splitlines()
        return "\n".join([lines[0], *lines[1::5]]) + "\n"

    assert D.load(_example_copy(tmp_path / "a", drop_waveform)).runs[0].waveform is None
    with pytest.raises(D.DatasetError, match="the fast edge is not resolved at 1e\\+04 S/s"):
        D.load(_example_copy(tmp_path / "b", drop_waveform, every_5th_row))


def test_extra_columns_of_any_type_are_ignored(tmp_path):
    from stickslip import dataset as D

    def add_text_column(text: str) -> str:
        lines = text.splitlines()
        out = [lines[0] + ",operator_note"] + [line + ",ok" for line in lines[1:]]
        return "\n".join(out) + "\n"

    ds = D.load(_example_copy(tmp_path, None, add_text_column))
    assert "operator_note" not in ds.runs[0].extra  # not a number: ignored, as the format says
    # a required column stays strict
    bad = _example_copy(tmp_path / "b", None, lambda t: t.replace("\n0,", "\nzero,", 1))
    with pytest.raises(D.DatasetError, match="row 2, column 't_s': not a number: 'zero'"):
        D.load(bad)


def _client_replying(request_type: int, payload: bytes):
    """A serial client whose node answers a request of request_type with payload."""
    from stickslip.hil.client import NodeClient

    c = NodeClient.__new__(NodeClient)
    c.request = lambda type_, *_a, **_k: payload if type_ == request_type else b""  # type: ignore
    c._node_seq = None
    return c


HELLO_OK = bytes([1, 0, 0, 19]) + struct.pack("<f", 1e-6) + b"1.0"

BAD_REPLIES = [
    # a short or foreign HELLO was a struct.error or an IndexError in client.py
    ("HELLO", b"\x01\x00", "2 bytes, at least 8 expected"),
    ("HELLO", bytes([99]) + HELLO_OK[1:], "protocol version 99, this client speaks 1"),
    ("HELLO", HELLO_OK[:1] + bytes([7]) + HELLO_OK[2:], "model index 7"),
    ("HELLO", HELLO_OK[:2] + bytes([5]) + HELLO_OK[3:], "variant index 5"),
    ("HELLO", HELLO_OK[:4] + struct.pack("<f", float("nan")), "step nan s"),
    ("GET_PARAM", b"\x00", "1 bytes, at least 5 expected"),
]


@pytest.mark.parametrize(("request_name", "payload", "words"), BAD_REPLIES, ids=lambda x: str(x))
def test_client_checks_every_reply(request_name, payload, words):
    from stickslip.hil import protocol
    from stickslip.hil.node import BadReplyError, HilError

    c = _client_replying(getattr(protocol, request_name), payload)
    with pytest.raises(BadReplyError) as e:
        c.hello() if request_name == "HELLO" else c.get(0)
    assert isinstance(e.value, HilError)  # one documented type for every session error
    assert request_name in str(e.value) and words in str(e.value), str(e.value)


def test_a_good_hello_is_read():
    from stickslip.hil import protocol

    info = _client_replying(protocol.HELLO, HELLO_OK).hello()
    assert (info.protocol, info.model, info.variant) == (1, "ls", "f32")


@pytest.mark.parametrize(
    ("url", "words"),
    [
        ("socket://127.0.0.1", "expected socket://HOST:PORT with a port 1..65535"),
        ("socket://:5000", "expected socket://HOST:PORT"),
        ("socket://127.0.0.1:0", "expected socket://HOST:PORT"),
        ("socket://127.0.0.1:1", "cannot open the link 'socket://127.0.0.1:1'"),
        ("/dev/nonexistent-tty", "cannot open the link '/dev/nonexistent-tty'"),
    ],
)
def test_a_bad_serial_link_url_is_named(url, words):
    from stickslip.hil.client import NodeClient
    from stickslip.hil.node import HilError

    with pytest.raises(HilError) as e:
        NodeClient(url)
    assert words in str(e.value)


def _frames_after(request, *frames: bytes, closes: bool = False):
    """The serial client's answer to request when the node sends frames (then closes or not)."""
    from stickslip.hil import protocol as P
    from stickslip.hil.client import NodeClient
    from stickslip.hil.node import LinkStats

    class Port:
        data = b"".join(frames)

        def fileno(self):
            raise io.UnsupportedOperation  # in memory: the client sleeps, no select()

        def read(self, n):
            if not self.data and closes:
                import serial

                raise serial.SerialException("socket disconnected")
            d, self.data = self.data[:n], self.data[n:]
            return d

        def write(self, b):
            return len(b)

        def flush(self):
            pass

    c = NodeClient.__new__(NodeClient)
    c.port, c.reader, c.seq, c.stats, c._node_seq = Port(), P.FrameReader(), 0, LinkStats(), None
    c._inbox, c.telemetry, c.timeout_s, c._run_progress = (
        __import__("collections").deque(),
        [],
        0.05,
        None,
    )
    return request(c)


def _decoder_cases():
    from stickslip.hil import protocol as P

    return [
        # found by bench/fuzz_python.py decoder: IndexError, struct.error, ValueError before
        (
            "an ERROR frame without its header",
            P.frame(P.ERROR, 0, b""),
            "ERROR",
            "0 bytes, at least 3",
        ),
        (
            "a telemetry frame cut short",
            P.frame(P.TELEMETRY, 0, b"\x00\x01"),
            "TELEMETRY",
            "2 bytes",
        ),
        (
            "a telemetry frame claiming more rows than it holds",
            P.frame(P.TELEMETRY, 0, b"\x00" + struct.pack("<IH", 0, 3)),
            "TELEMETRY",
            "7 bytes for 3 rows",
        ),
        (
            "a reply without its ref_seq",
            P.frame(P.GET_PARAM | P.REPLY, 0, b""),
            "GET_PARAM",
            "0 bytes",
        ),
        (
            "a STOP reply without the step count",
            P.frame(P.STOP | P.REPLY, 0, b"\x00"),
            "STOP",
            "0 bytes",
        ),
    ]


@pytest.mark.parametrize("case", range(5))
def test_the_serial_decoder_names_a_malformed_frame(case):
    from stickslip.hil.node import BadReplyError

    what, frame, request, words = _decoder_cases()[case]
    call = {"ERROR": "get", "TELEMETRY": "get", "GET_PARAM": "get", "STOP": "stop"}[request]
    with pytest.raises(BadReplyError) as e:
        _frames_after(lambda c: c.get(0) if call == "get" else c.stop(), frame)
    assert request in str(e.value) and words in str(e.value), (what, str(e.value))


def test_a_node_that_closes_the_link_is_heard_verbatim():
    # what the node said before it closed reaches the user; the close is a HilError, not
    # pyserial's "read failed: socket disconnected"
    from stickslip.hil import protocol as P
    from stickslip.hil.node import LinkClosedError

    said = P.frame(P.ERROR, 0, bytes([9, 8, 0]) + b"another client is connected")
    with pytest.raises(LinkClosedError, match="the node said: another client is connected"):
        _frames_after(lambda c: c.get(0), said, closes=True)


# ------------------------------------------------------------------ refused by name before issue 15
# The rows below passed when the issue was filed; they are here so that none regresses.


def _node_frame_cases():
    from stickslip.hil import protocol as P

    def raw_packet(body: bytes) -> bytes:  # a COBS packet with whatever header and CRC it has
        return P.cobs_encode(body) + b"\x00"

    header = struct.pack("<BBH", P.GET_PARAM, 0, 5)
    f = struct.pack
    return [
        # (what, wire bytes, error name, words of the node's reason)
        ("bad CRC", P.frame(P.GET_PARAM, 0, b"\x00")[:-3] + b"\x01\x01\x00", "bad_crc", "bad_crc"),
        ("invalid COBS", b"\x05\x01\x00", "bad_framing", "bad_framing"),
        ("packet shorter than its header", raw_packet(b"\x03\x01"), "bad_length", "bad_length"),
        (
            "length field against the packet",
            raw_packet(header + b"\x00" + f("<H", P.crc16(header + b"\x00"))),
            "bad_length",
            "bad_length",
        ),
        ("unknown type", P.frame(0x42, 0, b""), "unknown_type", "unknown request type"),
        ("TELEMETRY sent to the node", P.frame(P.TELEMETRY, 0, b""), "unknown_type", "unknown"),
        ("frame past the size limit", b"\x01" * 1100 + b"\x00", "oversize", "oversize"),
        ("GET_PARAM without an id", P.frame(P.GET_PARAM, 0, b""), "bad_payload", "an id or 0xFF"),
        ("GET_PARAM id 99", P.frame(P.GET_PARAM, 0, b"\x63"), "unknown_param", "with that id"),
        ("GET_PARAM unknown name", P.frame(P.GET_PARAM, 0, b"\xffbogus"), "unknown_param", "name"),
        ("SET_PARAM cut short", P.frame(P.SET_PARAM, 0, b"\x00\x00"), "bad_payload", "id + f32"),
        (
            "SET_PARAM NaN",
            P.frame(P.SET_PARAM, 0, b"\x00" + f("<f", math.nan)),
            "non_finite",
            "piezo_stiffness_n_per_m: not a finite number",
        ),
        (
            "SET_PARAM negative mass",
            P.frame(P.SET_PARAM, 0, b"\x02" + f("<f", -1.0)),
            "out_of_range",
            "rod_mass_kg: outside its range",
        ),
        (
            "SET_PARAM mu_d above mu_s",
            P.frame(P.SET_PARAM, 0, b"\x06" + f("<f", 0.9)),
            "out_of_range",
            "mu_d: Fc = mu_d N: in [1e-6, 1e4] N, <= Fs",
        ),
        (
            "SET_PARAM friction_model 2.5",
            P.frame(P.SET_PARAM, 0, b"\x0c" + f("<f", 2.5)),
            "out_of_range",
            "friction_model",
        ),
        ("RESET cut short", P.frame(P.RESET, 0, b"\x00"), "bad_payload", "f32 drive0_v"),
        ("RESET inf", P.frame(P.RESET, 0, f("<f", math.inf)), "non_finite", "drive0_v"),
        ("RESET 1e6 V", P.frame(P.RESET, 0, f("<f", 1e6)), "out_of_range", "[-1e5, 1e5] V"),
        ("RESET x0 NaN", P.frame(P.RESET, 0, f("<ff", 0.0, math.nan)), "non_finite", "x0_m"),
        ("RESET x0 2 m", P.frame(P.RESET, 0, f("<ff", 0.0, 2.0)), "out_of_range", "[-1, 1] m"),
        ("RESET 6 bytes", P.frame(P.RESET, 0, b"\x00" * 6), "bad_payload", "f32 x0_m"),
        ("LOAD_WAVEFORM short", P.frame(P.LOAD_WAVEFORM, 0, bytes(10)), "bad_payload", "21 bytes"),
        ("DRIVE_BLOCK empty", P.frame(P.DRIVE_BLOCK, 0, b""), "bad_payload", "u16 + 1..255 f32"),
        (
            "DRIVE_BLOCK decimation 0",
            P.frame(P.DRIVE_BLOCK, 0, f("<Hf", 0, 1.0)),
            "out_of_range",
            "decimation: must be >= 1",
        ),
        (
            "DRIVE_BLOCK ragged samples",
            P.frame(P.DRIVE_BLOCK, 0, f("<H", 1) + b"\x00\x00\x00"),
            "bad_payload",
            "u16 + 1..255 f32",
        ),
        (
            "DRIVE_BLOCK NaN sample",
            P.frame(P.DRIVE_BLOCK, 0, f("<Hf", 1, math.nan)),
            "non_finite",
            "drive sample",
        ),
        (
            "DRIVE_BLOCK 1e38 V",
            P.frame(P.DRIVE_BLOCK, 0, f("<Hf", 1, 1e38)),
            "out_of_range",
            "drive sample: outside [-1e5, 1e5] V",
        ),
        ("RUN before LOAD_WAVEFORM", P.frame(P.RUN, 0, f("<IHB", 10, 1, 0)), "no_waveform", "RUN"),
        ("RUN cut short", P.frame(P.RUN, 0, b"\x00"), "bad_payload", "u32 + u16 + u8"),
    ]


NODE_FRAME_CASES = list(range(29))


@pytest.mark.skipif(
    not (ROOT / "build" / "host" / "host_sim" / "stickslip_node").exists(),
    reason="host build missing (cmake --preset host)",
)
def test_the_node_names_every_bad_frame_and_serves_on():
    import time

    from stickslip.hil import protocol as P
    from stickslip.hil.client import HostNode, NodeClient

    cases = _node_frame_cases()
    assert len(cases) == len(NODE_FRAME_CASES)
    with HostNode("tcp") as node, NodeClient(node.url) as c:
        for seq, (what, wire, name, words) in enumerate(cases, start=10):
            if wire.endswith(b"\x00") and what not in ("invalid COBS", "frame past the size limit"):
                # give each well-formed request its own seq (a repeated one is a duplicate)
                for pkt in P.FrameReader().feed(wire):
                    if isinstance(pkt, P.Packet):
                        wire = P.frame(pkt.type, seq, pkt.payload)
            c.send_raw(wire)
            deadline = time.monotonic() + 2.0
            while not c._inbox and c._pump(deadline):
                pass
            assert c._inbox, what
            pkt = c._inbox.popleft()
            assert pkt.type == P.ERROR, what
            assert P.ERROR_NAMES[pkt.payload[1]] == name, (what, pkt.payload)
            assert words in pkt.payload[3:].decode(), (what, pkt.payload[3:])
        c.seq = 200
        assert c.get("mu_s") == pytest.approx(0.36)  # nothing changed, the node serves on


def _dataset_cases():
    """(what, change to the run file's lines or to the metadata, words of the message)."""

    def cell(row: int, col: int, text: str):  # lines[row] with its col-th cell replaced
        def change(lines: list[str]) -> None:
            cells = lines[row].split(",")
            cells[col] = text
            lines[row] = ",".join(cells)

        return ("csv", change, None)

    def lines(change):
        return ("csv", change, None)

    def meta(change):
        return ("json", change, None)

    return [
        ("empty run file", lines(lambda ls: ls.clear()), "empty file, expected a header row"),
        ("header only", lines(lambda ls: ls.__delitem__(slice(1, None))), "at least 2 data rows"),
        ("required column missing", cell(0, 2, "pos"), "column 'x_m'"),
        ("duplicate column", lines(lambda ls: ls.__setitem__(0, ls[0] + ",x_m")), "duplicate"),
        ("a cell is text", cell(3, 1, "volts"), "not a number: 'volts'"),
        ("a cell is inf", cell(3, 2, "inf"), "not a finite number"),
        ("a short row", lines(lambda ls: ls.__setitem__(3, "1e-05,0")), "2 cells, header has 3"),
        ("a blank row", lines(lambda ls: ls.insert(3, "")), "empty row"),
        ("time going back", cell(3, 0, "-1"), "time not ascending"),
        ("uneven sampling", cell(3, 0, "2.1e-05"), "not uniformly sampled"),
        ("not UTF-8", ("bytes", b"\xff\xfe\x00t_s", None), "unreadable"),
        ("metadata not JSON", meta("{not json"), "invalid JSON"),
        ("metadata a list", meta([]), "top level must be an object"),
        ("unknown format", meta(lambda m: m.update(format="other/2")), "format must be"),
        ("actuator key missing", meta(lambda m: m["actuator"].pop("mu_s")), "missing keys"),
        ("actuator key unknown", meta(lambda m: m["actuator"].update(colour=1)), "unknown keys"),
        ("actuator value text", meta(lambda m: m["actuator"].update(mu_s="x")), "mu_s"),
        ("no runs", meta(lambda m: m.update(runs=[])), "runs must be a non-empty list"),
        ("run without file", meta(lambda m: m["runs"][0].pop("file")), "needs string 'id'"),
        ("duplicate run id", meta(lambda m: m["runs"].append(dict(m["runs"][0]))), "duplicate"),
        ("file outside", meta(lambda m: m["runs"][0].update(file="../x.csv")), "outside"),
        ("file missing", meta(lambda m: m["runs"][0].update(file="gone.csv")), "cannot open"),
        ("sensor not an object", meta(lambda m: m.update(sensor=3)), "sensor must be an object"),
        ("sensor noise < 0", meta(lambda m: m.update(sensor={"noise_rms_m": -1})), "noise_rms_m"),
        (
            "waveform shape",
            meta(lambda m: m["runs"][0]["waveform"].update(shape="sine")),
            "only 'sawtooth'",
        ),
        (
            "waveform key missing",
            meta(lambda m: m["runs"][0]["waveform"].pop("cycles")),
            "missing key 'cycles'",
        ),
        (
            "waveform direction 2",
            meta(lambda m: m["runs"][0]["waveform"].update(direction=2)),
            "direction: must be 1 or -1",
        ),
        (
            "waveform cycles 1.5",
            meta(lambda m: m["runs"][0]["waveform"].update(cycles=1.5)),
            "cycles: must be a whole number",
        ),
        (
            "waveform frequency NaN",
            meta(lambda m: m["runs"][0]["waveform"].update(frequency_hz="NaN")),
            "frequency_hz: expected a finite number",
        ),
    ]


DATASET_CASES = list(range(29))


@pytest.mark.parametrize("case", DATASET_CASES)
def test_diagnose_names_what_is_wrong_with_a_dataset(tmp_path, capsys, case):
    import json

    from stickslip import dataset as D
    from stickslip.cli import main
    from stickslip.model import ActuatorParams, Sawtooth, simulate

    cases = _dataset_cases()
    assert len(cases) == len(DATASET_CASES)
    what, (kind, a, b), words = cases[case]
    w = Sawtooth(cycles=1)
    r = simulate(w, decimation=10)
    run = D.Run("r", tmp_path / "r.csv", r.t_s, r.drive_v, r.x_slider_m, w, {})
    root = D.write(tmp_path / "ds", ActuatorParams.table1(), [run])
    if kind in ("csv", "bytes"):
        p = root / "r.csv"
        if kind == "bytes":
            p.write_bytes(a)
        else:
            rows = p.read_text().splitlines()
            a(rows)
            p.write_text("\n".join(rows) + ("\n" if rows else ""))
    else:
        p = root / "dataset.json"
        if callable(a):
            m = json.loads(p.read_text())
            a(m)
            p.write_text(json.dumps(m))
        else:
            p.write_text(a if isinstance(a, str) else json.dumps(a))
    assert main(["diagnose", str(root), "--quiet", "--out", str(tmp_path / "report.md")]) == 2
    err = capsys.readouterr().err
    assert words in err, (what, err)
    assert p.name in err or "gone.csv" in err or "x.csv" in err, (what, err)  # the file named
    assert not (tmp_path / "report.md").exists()


CLI_ARGUMENT_CASES = [
    (["simulate", "--frequency-hz", "abc"], "--frequency-hz"),
    (["simulate", "--cycles", "x"], "--cycles"),
    (["simulate", "--model", "dahl"], "--model"),
    (["simulate", "--direction", "0"], "--direction"),
    (["simulate", "--bogus"], "unrecognized arguments: --bogus"),
    (["diagnose"], "the following arguments are required: dataset"),
    (["diagnose", "x", "--workers", "many"], "--workers"),
    (["hil", "run", "--link", "wifi"], "--link"),
    (["hil", "run", "--mode", "teleport"], "--mode"),
    (["hil", "run", "--cycles", "-"], "--cycles"),
    (["hil", "position", "--target-m", "far"], "--target-m"),
    (["figures", "--only", "fig99"], "fig99"),
    (["nonsense"], "invalid choice: 'nonsense'"),
]


@pytest.mark.parametrize(("args", "words"), CLI_ARGUMENT_CASES, ids=lambda x: str(x))
def test_a_bad_argument_is_named_by_the_parser(capsys, args, words):
    from stickslip.cli import main

    with pytest.raises(SystemExit) as e:
        main(args)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert words in err, err


def test_the_can_decoder_names_a_step_count_that_is_not_one():
    # found by bench/fuzz_python.py can_decoder: ValueError from int(nan) before
    import can

    from stickslip.hil import protocol as P
    from stickslip.hil.can_client import CMD, CanNodeClient, load_dbc
    from stickslip.hil.node import BadReplyError, LinkStats, NodeInfo

    db = load_dbc()
    reply = db.get_message_by_name("SS_REPLY")

    class Bus:
        frames = [
            can.Message(
                arbitration_id=reply.frame_id,
                data=reply.encode(
                    {"cmd": CMD["RUN"], "seq": 0, "status": 0, "index": 1, "value": math.nan}
                ),
            )
        ]

        def send(self, msg):
            pass

        def recv(self, timeout=None):
            return self.frames.pop(0) if self.frames else None

    c = CanNodeClient.__new__(CanNodeClient)
    c.url, c.bus, c.db, c.timeout_s, c.seq, c.drive_seq = "test", Bus(), db, 0.05, 0, 0
    c.stats, c.info = LinkStats(), NodeInfo(P.VERSION, "ls", "f32", 13, 1e-6, "test")
    with pytest.raises(BadReplyError, match="RUN.*steps done nan, not a whole number"):
        c.run(5)


def test_a_million_row_run_is_filtered_and_decimated_before_any_fit():
    # a 1e6-row run at 1 MS/s took the diagnosis past 5 minutes: the fits now see it at 50 kS/s
    # (about 27 s for a 1.2 M-row dataset, BENCHMARKS.md), through an anti-alias filter
    import numpy as np

    from stickslip import dataset as D
    from stickslip.diagnosis.fit import MAX_FIT_RATE_HZ, prepare

    n, dt = 1_000_000, 1e-6
    t = np.arange(n) * dt
    slow = 1e-6 * np.sin(2 * np.pi * 1e3 * t)  # what a fit must see (a 1 kHz motion)
    alias = 1e-7 * np.sin(2 * np.pi * 170e3 * t)  # above the 25 kHz Nyquist of 50 kS/s
    run = D.Run("r", None, t, np.zeros(n), slow + alias, None, {})  # type: ignore[arg-type]
    fr = prepare(run)
    assert fr.dt_s == pytest.approx(1.0 / MAX_FIT_RATE_HZ) and len(fr.x_m) == n // 20
    ref = slow[::20][: len(fr.x_m)]
    inner = slice(100, -100)  # away from the filter's ends
    # the 170 kHz tone would fold to 20 kHz at full size (100 nm); filtered: below 1 nm
    assert np.max(np.abs(fr.x_m[inner] - ref[inner])) < 1e-9
