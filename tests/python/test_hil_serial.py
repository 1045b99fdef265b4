"""Loopback tests of the stage-model node over its serial link (pty and TCP on 127.0.0.1):
the same trajectory as the batch simulator, parameters, and every kind of bad input."""

import re
import socket
import struct
import time
from pathlib import Path

import numpy as np
import pytest

from stickslip import dataset as D
from stickslip.cli import main
from stickslip.hil import protocol as P
from stickslip.hil.client import HostNode, LinkTimeoutError, NodeClient, NodeError
from stickslip.model import Sawtooth, simulate

VECTORS = Path(__file__).resolve().parents[1] / "vectors" / "proto_frames.csv"


@pytest.fixture(params=["pty", "tcp"])
def node(request):
    with HostNode(request.param) as n:
        yield n


@pytest.fixture
def tcp_node():
    with HostNode("tcp") as n:
        yield n


def f32(x):
    return np.asarray(x, dtype=np.float32)


def test_protocol_vectors_shared_with_c():
    assert P.crc16(b"123456789") == 0x29B1  # CRC-16/CCITT-FALSE check value
    for line in VECTORS.read_text().splitlines():
        if line.startswith("#"):
            continue
        t, s, payload, wire = line.split(",")
        payload, wire = bytes.fromhex(payload), bytes.fromhex(wire)
        assert P.frame(int(t), int(s), payload) == wire
        (pkt,) = list(P.FrameReader().feed(wire))
        assert (pkt.type, pkt.seq, pkt.payload) == (int(t), int(s), payload)


def test_lockstep_is_bit_exact_with_batch(node):
    w = Sawtooth(cycles=2)
    r = simulate(w)
    with NodeClient(node.url) as c:
        c.reset(float(r.drive_v[0]))
        rows = []
        for i in range(1, len(r.drive_v), 40):
            rows += c.drive_block(r.drive_v[i : i + 40])
        a = np.array(rows)
        slider = f32(a[:, 3]) + f32(a[:, 4])  # the library's float32 sum
        assert np.array_equal(slider, f32(r.x_slider_m[1:]))
        assert np.array_equal(f32(a[:, 2]), f32(r.x_rod_m[1:]))
        assert np.array_equal(f32(a[:, 5]), f32(r.force_n[1:]))
        assert c.stats.lost_frames == 0 and c.stats.duplicate_frames == 0


def test_lockstep_tells_progress_per_block(tcp_node):
    w = Sawtooth(cycles=1)
    drive = simulate(w).drive_v.astype(np.float32)
    seen: list[int] = []
    with NodeClient(tcp_node.url) as c:
        c.reset(float(drive[0]))
        c.lockstep(drive[1:101], block=40, progress=seen.append)
    assert seen == [40, 80, 100]


def test_free_run_matches_batch(tcp_node):
    w = Sawtooth(cycles=2)
    r = simulate(w)
    with NodeClient(tcp_node.url) as c:
        assert c.info.variant == "f32" and c.info.model == "ls"
        c.load_waveform(w)
        seen: list[int] = []
        tel = c.run(4000, decimation=10, progress=seen.append)
        assert np.array_equal(tel.step, np.arange(10, 4001, 10))
        # progress is told the node's step as telemetry arrives, up to the last row
        assert seen and seen == sorted(seen) and seen[-1] == 4000
        assert np.array_equal(f32(tel.x_rod_m), f32(r.x_rod_m[10::10]))
        assert np.max(np.abs(tel.x_slider_m - r.x_slider_m[10::10])) < 1e-12


def test_paced_run_keeps_real_time(tcp_node):
    with NodeClient(tcp_node.url) as c:
        c.load_waveform(Sawtooth(cycles=100))
        t0 = time.perf_counter()
        tel = c.run(100_000, decimation=100, paced=True)  # 0.1 s of model time
        wall = time.perf_counter() - t0
        assert len(tel.step) == 1000
        # paced by the port's clock: never faster than real time, not much slower on a quiet host
        assert 0.095 < wall < 1.0


PARAMS_DEF = Path(__file__).resolve().parents[2] / "app" / "ss_node_params.def"


def c_param_table() -> list[tuple[str, float, float]]:
    """The node's parameter table as app/ss_node_params.def writes it: (name, min, max) by id."""
    entry = re.compile(
        r'^SS_NODE_PARAM\(\s*\w+\s*,\s*"(\w+)"\s*,.*,\s*([-+.\de]+)f\s*,\s*([-+.\de]+)f\s*\)\s*$'
    )
    rows = []
    for line in PARAMS_DEF.read_text().splitlines():
        if line.startswith("SS_NODE_PARAM("):
            m = entry.match(line)
            assert m, f"unparsed entry: {line}"
            rows.append((m[1], float(m[2]), float(m[3])))
    return rows


def test_python_parameter_ids_match_the_c_table_entry_by_entry():
    table = c_param_table()
    assert len(table) == 29  # 13 actuator and friction parameters, 14 effects, the step, 1 effect
    assert [name for name, _, _ in table] == P.PARAM_NAMES
    for i, (name, lo, hi) in enumerate(table):
        assert P.PARAM_NAMES.index(name) == i and lo < hi


def test_parameters_round_trip_by_name_and_id(tcp_node):
    with NodeClient(tcp_node.url) as c:
        params = c.params()
        assert list(params) == P.PARAM_NAMES  # all 13, in id order
        assert c.get("mu_s") == pytest.approx(0.36)
        assert c.set("normal_force_n", 12.5) == 12.5
        assert c.get(7) == 12.5
        assert c.set(5, 0.4) == pytest.approx(0.4)
        assert c.get("mu_s") == pytest.approx(0.4)
        for name, value, err in [
            ("rod_mass_kg", -1.0, "out_of_range"),
            ("rod_mass_kg", float("nan"), "non_finite"),
            ("mu_d", 0.9, "out_of_range"),  # Fc above Fs
            ("piezo_gain_m_per_v", 0.0, "out_of_range"),
            ("no_such_param", 1.0, "unknown_param"),
        ]:
            with pytest.raises(NodeError) as e:
                c.set(name, value)
            assert e.value.name == err
            if err != "unknown_param":
                assert name in e.value.reason
        assert c.get("rod_mass_kg") == pytest.approx(1.1e-3)  # nothing changed
        # a parameter really reaches the model: more normal force, more friction, other step
        w = Sawtooth(cycles=3)
        base = simulate(w).mean_step_m
        c.set("normal_force_n", 10.0)
        c.set("mu_s", 0.36)
        c.set("sigma0_n_per_m", 2e7)
        c.load_waveform(w)
        tel = c.run(6000)
        assert abs(tel.x_slider_m[-1] / 3 - base) > 0.01 * base


def next_error(c: NodeClient, timeout=2.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        pkt = c._next(deadline - time.monotonic())
        if pkt.type == P.ERROR:
            return P.ERROR_NAMES[pkt.payload[1]], pkt.payload[3:].decode()
    raise AssertionError("no error frame")


def test_bad_frames_get_named_errors_and_change_nothing(node):
    w = Sawtooth(cycles=1)
    r = simulate(w)
    with NodeClient(node.url) as c:
        c.reset(float(r.drive_v[0]))
        c.drive_block(r.drive_v[1:41])
        good = P.frame(P.GET_PARAM, 100, bytes([5]))
        corrupt = bytearray(P.packet(P.GET_PARAM, 104, bytes([5])))
        corrupt[4] ^= 0x20  # a payload bit flipped on the way, framing intact
        cases = [
            (good[:-1][:7] + b"\x00", {"bad_framing", "bad_length"}),  # truncated
            (b"\x55" * 3000 + b"\x00", {"oversize"}),
            (P.cobs_encode(bytes(corrupt)) + b"\x00", {"bad_crc"}),
            (P.frame(0x33, 101), {"unknown_type"}),
            (P.frame(P.RESET, 102, b"\x00"), {"bad_payload"}),
            (P.frame(P.RESET, 103, struct.pack("<f", float("inf"))), {"non_finite"}),
        ]
        for raw, names in cases:
            c.send_raw(raw)
            name, reason = next_error(c)
            assert name in names, (raw[:16], name, reason)
        # random bytes: the node answers with errors but acts on nothing
        rng = np.random.default_rng(7)
        c.send_raw(bytes(rng.integers(0, 256, 5000, dtype=np.uint8)) + b"\x00")
        time.sleep(0.2)
        c.port.reset_input_buffer()
        c.reader = P.FrameReader()
        c._inbox.clear()
        # a NaN in a drive block is refused whole
        bad = r.drive_v[41:81].copy()
        bad[17] = np.nan
        with pytest.raises(NodeError, match="non_finite"):
            c.drive_block(bad)
        # and the trajectory goes on exactly as the batch run's
        rows = []
        for i in range(41, 2001, 40):
            rows += c.drive_block(r.drive_v[i : i + 40])
        a = np.array(rows)
        assert np.array_equal(f32(a[:, 3]) + f32(a[:, 4]), f32(r.x_slider_m[41:2001]))


def test_duplicate_request_is_refused_not_executed(tcp_node):
    with NodeClient(tcp_node.url) as c:
        c.reset(0.0)
        frame = P.frame(P.DRIVE_BLOCK, c.seq, struct.pack("<H", 1) + f32([1.0] * 10).tobytes())
        c.send_raw(frame)
        first = c.wait_reply(P.DRIVE_BLOCK, c.seq)
        c.send_raw(frame)  # the same frame again, as a link that duplicates would deliver it
        with pytest.raises(NodeError, match="duplicate"):
            c.wait_reply(P.DRIVE_BLOCK, c.seq)
        c.seq += 1
        rows = c.drive_block(f32([1.0] * 10))
        assert struct.unpack_from("<I", first)[0] == 1
        assert rows[0][0] == 11  # the duplicate did not advance the model


def test_lost_and_duplicated_node_frames_are_counted():
    c = NodeClient("loop://", handshake=False)
    for seq in (1, 2, 4, 4, 5):  # 3 lost, 4 twice
        c.send_raw(P.frame(P.TELEMETRY, seq, bytes([0]) + struct.pack("<IH", 0, 0)))
    with pytest.raises(LinkTimeoutError):
        c.wait_reply(P.HELLO, 0, timeout_s=0.3)
    assert c.stats.lost_frames == 1
    assert c.stats.duplicate_frames == 1
    c.close()


def test_lost_request_times_out_with_a_name(tcp_node):
    with (
        NodeClient(tcp_node.url, timeout_s=0.3) as c,
        pytest.raises(LinkTimeoutError, match="0x03"),
    ):
        c.wait_reply(P.GET_PARAM, 77)  # a request that never arrived


def test_second_client_is_refused(tcp_node):
    host, port = tcp_node.url.removeprefix("socket://").split(":")
    with NodeClient(tcp_node.url) as c:
        s = socket.create_connection((host, int(port)), timeout=2)
        data = b""
        while True:
            chunk = s.recv(4096)
            if not chunk:
                break
            data += chunk
        s.close()
        (pkt,) = list(P.FrameReader().feed(data))
        assert pkt.type == P.ERROR and P.ERROR_NAMES[pkt.payload[1]] == "busy"
        assert c.get("mu_s") == pytest.approx(0.36)  # the first client is served on


def test_second_client_hears_the_nodes_own_reason(tcp_node):
    # it was told "socket disconnected": pyserial emptied the socket as it opened it
    with NodeClient(tcp_node.url) as c:
        with pytest.raises(NodeError, match="busy: another client is connected"):
            NodeClient(tcp_node.url)
        assert c.get("mu_s") == pytest.approx(0.36)


def test_a_long_run_that_streams_is_busy_not_lost(tcp_node):
    # telemetry renews the wait: a run longer than the reply timeout completes (it was reported
    # as "no reply, lost"); 8 M unpaced steps take ~0.7-2 s here, 4 x the 0.2 s timeout or more.
    # A frame of 40 rows comes every 320 000 steps, some 30 ms; with both cores busy (diagnoses
    # beside the tests) frames of 160 000 steps came up to 50 ms apart, so a timeout of 0.05 s
    # failed where nothing was lost
    with NodeClient(tcp_node.url) as c:
        c.load_waveform(Sawtooth(cycles=4000))
        tel = c.run(8_000_000, decimation=8000, timeout_s=0.2)
        assert len(tel.step) == 1000 and tel.step[-1] == 8_000_000


@pytest.mark.parametrize(
    ("field", "value", "words"),
    [
        ("frequency_hz", 2e6, "frequency_hz: outside [1e-6, 1e6] Hz (sent 2000000.0)"),
        ("amplitude_v", -1e6, "amplitude_v: outside [-1e5, 1e5] V (sent -1000000.0)"),
        ("offset_v", float("inf"), "non_finite: offset_v: not a finite number (sent inf)"),
        ("rise_fraction", 1.0, "rise_fraction: outside (0, 1) (sent 1.0)"),
        ("direction", 0, "direction: +1 or -1 (sent 0)"),
    ],
)
def test_a_refused_waveform_names_its_field(tcp_node, field, value, words):
    # it said "waveform: parameter out of range (status -2)"
    import dataclasses

    with NodeClient(tcp_node.url) as c:
        bad = dataclasses.replace(Sawtooth(), **{field: value})
        with pytest.raises(NodeError) as e:
            c.load_waveform(bad)
        assert words in str(e.value)


def test_disconnect_mid_run_recovers(tcp_node):
    c = NodeClient(tcp_node.url)
    c.load_waveform(Sawtooth(cycles=1000))
    c.send_raw(P.frame(P.RUN, c.seq, struct.pack("<IHB", 2_000_000, 1, 1)))  # 2 s, paced
    time.sleep(0.1)
    c.close()  # gone in the middle of the run
    time.sleep(0.1)
    assert tcp_node.alive()
    w = Sawtooth(cycles=1)
    r = simulate(w)
    with NodeClient(tcp_node.url) as c2:
        c2.reset(float(r.drive_v[0]))
        tel = c2.lockstep(r.drive_v[1:2001])
        assert np.array_equal(f32(tel.x_rod_m), f32(r.x_rod_m[1:2001]))


def test_busy_during_run_then_stop(tcp_node):
    with NodeClient(tcp_node.url) as c:
        c.load_waveform(Sawtooth(cycles=1000))
        c.send_raw(P.frame(P.RUN, c.seq, struct.pack("<IHB", 2_000_000, 100, 1)))
        c.seq += 1
        time.sleep(0.05)
        with pytest.raises(NodeError, match="busy"):
            c.reset(0.0)
        done = c.stop()
        assert 10_000 < done < 2_000_000


def test_hil_run_command_records_a_dataset(tmp_path, capsys):
    out = tmp_path / "ds"
    assert main(["hil", "run", "--cycles", "3", "--out", str(out), "--json"]) == 0
    import json

    s = json.loads(capsys.readouterr().out)
    assert s["steps"] == 6000 and s["link"]["lost_frames"] == 0
    ds = D.load(out)
    r = simulate(ds.runs[0].waveform, ds.actuator)
    assert np.max(np.abs(np.interp(ds.runs[0].t_s, r.t_s, r.x_slider_m) - ds.runs[0].x_m)) < 1e-12
    assert main(["hil", "run", "--link", "serial", "--cycles", "-1"]) == 2
    assert "--cycles" in capsys.readouterr().err


def test_hil_run_at_another_step(capsys):
    # --dt-s sets the node's step_s for the run: the free run is the library's at that step
    import json

    args = ["hil", "run", "--node-link", "tcp", "--mode", "free", "--cycles", "2"]
    assert main([*args, "--dt-s", "1e-5", "--decimation", "10", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["node"]["dt_s"] == np.float32(1e-5) and s["steps"] == 400
    r = simulate(Sawtooth(cycles=2), dt_s=s["node"]["dt_s"])
    assert s["mean_step_per_cycle_m"] == pytest.approx(r.mean_step_m, rel=1e-6)
    # out of the node's range: refused by the node, by name, with the range
    assert main([*args, "--dt-s", "0.01"]) == 2
    assert "step_s: outside its range (PARAM_INFO): [1e-09, 0.001] (sent 0.01)" in (
        capsys.readouterr().err
    )


def test_reconnect_at_once_is_served(tcp_node):
    # a client that closes and a new one that connects before the node has polled: the node must
    # see the old session is over rather than refuse the new client as a second one
    for _ in range(5):
        with NodeClient(tcp_node.url) as c:
            assert c.get("mu_s") == pytest.approx(0.36)


@pytest.mark.parametrize("target", [30e-6, -12.3e-6, 2e-6])
def test_closed_loop_positioning_reaches_target(tcp_node, target):
    from stickslip.hil.positioning import position

    with NodeClient(tcp_node.url) as c:
        r = position(c, target, tolerance_m=5e-9, max_time_s=0.1)
    # coarse periods of ~2.3 um, then the fine loop: within 5 nm, held for 2 ms, in < 100 ms
    assert r.settle_time_s is not None and r.settle_time_s < 0.1
    assert abs(r.final_error_m) <= 5e-9
    assert r.coarse_periods == (
        0 if abs(target) < 4.4e-6 else pytest.approx(abs(target) / 2.3e-6, abs=3)
    )


def test_position_command(capsys):
    assert main(["hil", "position", "--target-m", "5e-6", "--json"]) == 0
    import json

    s = json.loads(capsys.readouterr().out)
    assert abs(s["final_error_m"]) <= 5e-9
    assert main(["hil", "position", "--target-m", "1"]) == 2


def _model_with_effects():
    from stickslip.model import ActuatorParams, Effects
    from stickslip.model_file import ModelFile

    effects = Effects(
        load_n=0.05, hysteresis_alpha=0.1, hysteresis_width_m=2e-7, slew_v_per_s=2e6,
        friction_asymmetry=0.1, creep_ratio=0.02, creep_tau_s=0.05,
    )  # fmt: skip
    return ModelFile(ActuatorParams.table1(), "lugre", effects)


@pytest.mark.parametrize("how", ["started_with", "sent"])
def test_a_model_with_effects_runs_on_the_node_bit_for_bit(how):
    # issue 16: a model file into the node, at start (--set) or over the link (SET_MODEL)
    m = _model_with_effects()
    w = Sawtooth(cycles=2)
    r = simulate(w, m.params, model=m.law, effects=m.effects)
    with HostNode("tcp", model=m if how == "started_with" else None) as n, NodeClient(n.url) as c:
        if how == "sent":
            c.load_model(m)
        assert c.get("load_n") == pytest.approx(0.05) and c.get("friction_model") == 1.0
        c.reset(float(r.drive_v[0]))
        tel = c.lockstep(r.drive_v[1:4001])
    assert np.array_equal(f32(tel.x_slider_m), f32(r.x_slider_m[1:4001]))
    assert np.array_equal(f32(tel.friction_n), f32(r.force_n[1:4001]))


def test_a_model_at_its_own_step_runs_at_that_step(tcp_node):
    # the model file's step goes to the node (step_s) with the rest; the client's info follows,
    # and the node's run is the library's at that step, bit for bit
    import dataclasses

    m = dataclasses.replace(_model_with_effects(), dt_s=2.5e-6)
    w = Sawtooth(cycles=2)
    r = simulate(w, m.params, model=m.law, effects=m.effects, dt_s=m.dt_s)
    with NodeClient(tcp_node.url) as c:
        c.load_model(m)
        assert c.info.dt_s == np.float32(2.5e-6) and c.get("step_s") == c.info.dt_s
        c.reset(float(r.drive_v[0]))
        tel = c.lockstep(r.drive_v[1:1601])
        assert np.array_equal(f32(tel.x_slider_m), f32(r.x_slider_m[1:1601]))
        # and back to 1 us one parameter at a time: a step out of the library's range is refused
        assert c.set("step_s", 1e-6) == np.float32(1e-6) and c.info.dt_s == np.float32(1e-6)
        with pytest.raises(NodeError, match=r"step_s: outside its range.*\[1e-09, 0.001\]"):
            c.set("step_s", 0.01)
        assert c.info.dt_s == np.float32(1e-6)


def test_a_model_the_node_cannot_run_is_refused_by_name(tcp_node):
    import dataclasses

    from stickslip.hil.node import HilError

    m = _model_with_effects()
    with NodeClient(tcp_node.url) as c:
        with pytest.raises(HilError, match="the node runs ls or lugre friction, the model gms"):
            c.load_model(dataclasses.replace(m, law="gms"))
        # all or nothing: a rule between fields refuses the whole set
        with pytest.raises(NodeError, match="model: effects.hysteresis_width_m"):
            c.set_model({"load_n": 0.3, "hysteresis_alpha": 0.2, "hysteresis_width_m": 0.0})
        assert c.get("load_n") == 0.0
    with pytest.raises(HilError, match="creep_ratio: the fixed-point node does not model"):
        HostNode("tcp", variant="q", model=m)
