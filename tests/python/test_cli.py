"""The `stickslip` command and the host simulator, as a user runs them."""

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from stickslip.cli import main
from stickslip.dataset import Run, write
from stickslip.model import ActuatorParams, Sawtooth, simulate

ROOT = Path(__file__).resolve().parents[2]
HOST_SIM = ROOT / "build" / "host" / "host_sim" / "stickslip_sim"


def test_simulate_json_reports_mean_step(capsys, tmp_path):
    out = tmp_path / "run.csv"
    assert main(["simulate", "--cycles", "4", "--json", "--out", str(out)]) == 0
    s = json.loads(capsys.readouterr().out)
    assert 1e-6 < s["mean_step_per_cycle_m"] < 4.4e-6
    assert len(s["per_cycle_steps_m"]) == 4
    header = out.read_text().splitlines()[0]
    assert header == "t_s,drive_v,x_p_m,x_rod_m,x_slider_m,friction_n,level_n,presliding_n"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape == (4 * 2000 + 1, 8)


def test_simulate_options_reach_the_model(capsys):
    main(
        [
            "simulate",
            "--cycles",
            "4",
            "--json",
            "--direction",
            "-1",
            "--model",
            "lugre",
            "--fall-time-s",
            "20e-6",
        ]
    )
    s = json.loads(capsys.readouterr().out)
    assert s["model"] == "lugre"
    assert s["waveform"]["rise_fraction"] == pytest.approx(0.99)
    assert s["mean_step_per_cycle_m"] < -3e-6


@pytest.mark.parametrize(
    "args,msg",
    [
        (["--rise-fraction", "1.5"], "rise fraction must be in (0, 1)"),
        (["--rise-fraction", "0.9", "--fall-time-s", "1e-5"], "not both"),
        (["--cycles", "-3"], "--cycles"),
        (["--frequency-hz", "0"], "--frequency-hz"),
    ],
)
def test_bad_options_say_what_is_wrong(capsys, args, msg):
    assert main(["simulate", *args]) == 2
    assert msg in capsys.readouterr().err


def test_nan_option_is_refused():
    r = subprocess.run(
        [sys.executable, "-m", "stickslip", "simulate", "--amplitude-v", "nan"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2
    assert "--amplitude-v: expected a finite number" in r.stderr


def test_simulate_dataset(capsys, tmp_path):
    w = Sawtooth(cycles=3)
    r = simulate(w, decimation=10)
    run = Run("a", tmp_path / "a.csv", r.t_s, r.drive_v, r.x_slider_m, w)
    root = write(tmp_path / "ds", ActuatorParams.table1(), [run])
    assert main(["simulate", "--dataset", str(root), "--json", "--out", str(tmp_path / "sim")]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["runs"][0]["rmse_m"] < 1e-12  # nominal parameters reproduce data made with them
    assert (tmp_path / "sim" / "a.csv").is_file()
    (root / "a.csv").write_text("t_s,drive_v,x_m\n0,0,0\n1e-5,x,0\n")
    assert main(["simulate", "--dataset", str(root)]) == 2
    assert "a.csv, row 3, column 'drive_v': not a number" in capsys.readouterr().err


@pytest.mark.skipif(not HOST_SIM.exists(), reason="host build missing (cmake --preset host)")
def test_host_simulator_matches_binding(tmp_path):
    out = tmp_path / "h.csv"
    r = subprocess.run(
        [str(HOST_SIM), "--cycles", "3", "--out", str(out)], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stderr
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    py = simulate(Sawtooth(cycles=3))
    # the same C code from the same parameters: equal to the CSV's 9 significant digits, which
    # hold a float32 exactly
    np.testing.assert_array_equal(data[:, 4].astype(np.float32), py.x_slider_m.astype(np.float32))
    bad = subprocess.run([str(HOST_SIM), "--frequency-hz", "fast"], capture_output=True, text=True)
    assert (
        bad.returncode == 2 and "--frequency-hz: expected a finite number, got 'fast'" in bad.stderr
    )
    assert (
        "usage" in subprocess.run([str(HOST_SIM), "--help"], capture_output=True, text=True).stdout
    )


def test_json_means_the_same_on_every_subcommand():
    # --json [FILE] everywhere: FILE, or stdout when FILE is '-' or omitted
    from stickslip.cli import build_parser

    def subparsers(p):
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sp in action.choices.items():
                    yield name, sp
                    yield from subparsers(sp)

    seen = []
    for name, sp in subparsers(build_parser()):
        for action in sp._actions:
            if "--json" in action.option_strings:
                seen.append(name)
                assert (action.nargs, action.const, action.default) == ("?", "-", None), name
    assert set(seen) == {
        "simulate",
        "figures",
        "diagnose",
        "run",
        "position",
        "firmware-q",
        "replay",
        "export",
        "check",
    }


def test_json_to_a_file_keeps_the_summary_and_dash_is_stdout(capsys, tmp_path):
    js = tmp_path / "deep" / "s.json"
    assert main(["simulate", "--cycles", "2", "--json", str(js)]) == 0
    out = capsys.readouterr()
    assert "mean step" in out.out and out.err == ""  # no progress display off a terminal
    assert json.loads(js.read_text())["per_cycle_steps_m"]
    assert main(["simulate", "--cycles", "2", "--json", "-"]) == 0
    assert len(json.loads(capsys.readouterr().out)["per_cycle_steps_m"]) == 2


def test_dataset_progress_is_quiet_off_a_terminal(capsys, tmp_path):
    runs = []
    for i in range(4):
        w = Sawtooth(cycles=1, amplitude_v=50.0 + 10 * i)
        r = simulate(w, decimation=10)
        runs.append(Run(f"r{i}", tmp_path / f"r{i}.csv", r.t_s, r.drive_v, r.x_slider_m, w))
    root = write(tmp_path / "ds", ActuatorParams.table1(), runs)
    assert main(["simulate", "--dataset", str(root)]) == 0
    out = capsys.readouterr()
    assert out.err == "" and out.out.count("rmse") == 4
