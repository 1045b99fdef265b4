"""The node over CAN: python-can's slcan interface against the node's SLCAN link (pty and TCP on
127.0.0.1), every frame through cantools and the DBC. SocketCAN is tried and skipped where the
kernel has no vcan."""

import importlib.util
import shutil
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from stickslip.hil.can_client import CanNodeClient
from stickslip.hil.client import HostNode, NodeError, node_binary
from stickslip.model import Sawtooth, simulate

VECTORS = Path(__file__).resolve().parents[1] / "vectors"


def f32(x):
    return np.asarray(x, dtype=np.float32)


@pytest.fixture(params=["can-tcp", "can-pty"])
def can_node(request):
    with HostNode(request.param) as n:
        yield n


def test_c_vectors_are_what_cantools_encodes_from_the_dbc():
    spec = importlib.util.spec_from_file_location("mk", VECTORS / "make_can_vectors.py")
    mk = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mk)
    assert (VECTORS / "can_frames.csv").read_text() == mk.render()


def test_lockstep_over_slcan_is_bit_exact(can_node):
    w = Sawtooth(cycles=1)
    r = simulate(w)
    with CanNodeClient(can_node.url) as c:
        c.reset(float(r.drive_v[0]))
        seen: list[int] = []
        tel = c.lockstep(r.drive_v[1:401], decimation=1, progress=seen.append)
        assert seen == list(range(40, 401, 40))
        assert np.array_equal(tel.step, np.arange(1, 401))
        assert np.array_equal(f32(tel.x_rod_m), f32(r.x_rod_m[1:401]))
        assert np.array_equal(f32(tel.friction_n), f32(r.force_n[1:401]))
        assert np.max(np.abs(tel.x_slider_m - r.x_slider_m[1:401])) < 1e-12


def test_free_run_over_slcan(can_node):
    w = Sawtooth(cycles=1)
    r = simulate(w)
    with CanNodeClient(can_node.url) as c:
        assert c.info.variant == "f32"
        c.load_waveform(w)
        seen: list[int] = []
        tel = c.run(2000, decimation=20, progress=seen.append)
        assert np.array_equal(tel.step, np.arange(20, 2001, 20))
        assert seen == list(range(20, 2001, 20))
        assert np.array_equal(f32(tel.x_rod_m), f32(r.x_rod_m[20::20]))


def test_parameters_and_refusals_over_can():
    with HostNode("can-tcp") as n, CanNodeClient(n.url) as c:
        assert c.get("mu_s") == pytest.approx(0.36)
        assert c.set("normal_force_n", 12.0) == 12.0
        for param, value, name in [
            ("rod_mass_kg", -1.0, "out_of_range"),
            ("sigma0_n_per_m", float("nan"), "non_finite"),
            ("mu_d", 0.9, "out_of_range"),
            (40, 1.0, "unknown_param"),
        ]:
            with pytest.raises(NodeError) as e:
                c.set(param, value)
            assert e.value.name == name
        assert c.get("rod_mass_kg") == pytest.approx(1.1e-3)
        with pytest.raises(NodeError, match="no_waveform"):
            c.run(10)
        # the node's SS_REASON frames reach the user (the client said "SET_WAVE index 4")
        with pytest.raises(NodeError, match="out_of_range: direction: \\+1 or -1"):
            c.request("SET_WAVE", index=4, value=0.5)
        # a refused LOAD_WAVE names its field, the range, and what was sent (was "index 0")
        with pytest.raises(NodeError) as e:
            c.load_waveform(Sawtooth(frequency_hz=2e6))
        assert "frequency_hz: outside [1e-6, 1e6] Hz (sent 2000000.0)" in str(e.value)


@pytest.mark.parametrize(
    ("channel", "words"),
    [
        ("socket://127.0.0.1", "expected socket://HOST:PORT with a port 1..65535"),
        ("socket://127.0.0.1:70000", "expected socket://HOST:PORT"),
        ("socket://127.0.0.1:1", "cannot open the CAN link 'slcan:socket://127.0.0.1:1'"),
    ],
)
def test_a_bad_can_link_url_is_named(channel, words):
    # python-can said "'debug|info|warning|error'"
    from stickslip.hil.node import HilError

    with pytest.raises(HilError) as e:
        CanNodeClient(channel)
    assert words in str(e.value)


def test_duplicate_drive_frame_is_not_executed():
    with HostNode("can-tcp") as n, CanNodeClient(n.url) as c:
        c.reset(0.0)
        c.send("SS_DRIVE", drive_v=1.0, seq=50, report=0)
        c.send("SS_DRIVE", drive_v=1.0, seq=50, report=0)  # delivered twice
        got = c.recv(2.0)
        while got is not None and got[0] != "SS_REPLY":
            got = c.recv(2.0)
        assert got is not None and got[1]["status"] == 7  # duplicate
        c.drive_seq = 50
        tel = c.lockstep(np.array([1.0]), decimation=1)
        assert tel.step[0] == 2  # one step for the first frame, one now


def test_malformed_slcan_lines_are_answered_with_bel():
    with HostNode("can-tcp") as n:
        host, port = n.url.removeprefix("socket://").split(":")
        s = socket.create_connection((host, int(port)), timeout=2)
        s.sendall(b"O\rt11G1aa\rt1109\rQ\r")
        data = b""
        while data.count(b"\a") < 3:
            data += s.recv(64)
        assert data == b"\r\a\a\a"
        s.close()
        with CanNodeClient(n.url) as c:  # and the node serves the next client
            assert c.get("mu_d") == pytest.approx(0.30)


def test_socketcan_where_the_kernel_has_vcan():
    if not sys.platform.startswith("linux") or shutil.which("ip") is None:
        pytest.skip("SocketCAN needs Linux and iproute2")
    made = subprocess.run(
        ["ip", "link", "add", "dev", "vcan0", "type", "vcan"], capture_output=True, text=True
    )
    if made.returncode != 0 and "File exists" not in made.stderr:
        pytest.skip(f"no vcan on this kernel, the SLCAN link stands in: {made.stderr.strip()}")
    subprocess.run(["ip", "link", "set", "up", "vcan0"], check=True)
    node = subprocess.Popen(
        [str(node_binary()), "--socketcan", "vcan0"],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert "socketcan vcan0" in node.stdout.readline()
        with CanNodeClient("vcan0", interface="socketcan") as c:
            assert c.get("mu_s") == pytest.approx(0.36)
    finally:
        node.terminate()
        subprocess.run(["ip", "link", "del", "vcan0"], capture_output=True)


def test_fixed_point_node_over_slcan_says_so_and_runs_the_q_model():
    w = Sawtooth(cycles=1)
    r = simulate(w, variant="q")
    with HostNode("can-tcp", variant="q") as n, CanNodeClient(n.url) as c:
        # HELLO's index carries the variant in its high nibble; a float node's stays 0 (LS)
        assert c.info.variant == "q" and c.info.model == "ls"
        assert c.info.dt_s == np.float32(1099512 * 2.0**-40)  # Table I's dt_q40
        c.reset(float(r.drive_v[0]))
        tel = c.lockstep(r.drive_v[1:401], decimation=1)  # Q16.16 drive values: exact in f32
        assert np.array_equal(f32(tel.x_rod_m), f32(r.x_rod_m[1:401]))
        assert np.array_equal(tel.x_slider_m, r.x_slider_m[1:401])  # hi + lo: the q position


def test_a_model_with_effects_goes_in_over_can_all_or_nothing():
    # issue 16: SET_PARAM with flags 1 stages, APPLY_MODEL applies the set (the serial SET_MODEL)
    from stickslip.model import ActuatorParams, Effects
    from stickslip.model_file import ModelFile

    m = ModelFile(ActuatorParams.table1(), "lugre", Effects(load_n=0.05, slew_v_per_s=3e6))
    w = Sawtooth(cycles=1)
    r = simulate(w, m.params, model=m.law, effects=m.effects)
    with HostNode("can-tcp") as n, CanNodeClient(n.url) as c:
        with pytest.raises(NodeError, match="model: effects.hysteresis_width_m"):
            c.set_model({"load_n": 0.3, "hysteresis_alpha": 0.2})  # a hysteresis needs its width
        assert c.get("load_n") == 0.0  # nothing of the refused set
        c.load_model(m)
        assert c.get("load_n") == pytest.approx(0.05) and c.get("friction_model") == 1.0
        c.reset(float(r.drive_v[0]))
        tel = c.lockstep(r.drive_v[1:401])
    assert np.array_equal(f32(tel.x_slider_m), f32(r.x_slider_m[1:401]))
