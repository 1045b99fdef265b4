"""stick-slip-dataset/1: validation errors name the file, row and column; round trip."""

import json

import numpy as np
import pytest

from stickslip import dataset as D
from stickslip.model import ActuatorParams, Sawtooth, simulate


def make(tmp_path, cycles=3):
    w = Sawtooth(cycles=cycles)
    r = simulate(w, decimation=10)
    run = D.Run(
        "f500_fwd",
        tmp_path / "f500_fwd.csv",
        r.t_s,
        r.drive_v,
        r.x_slider_m,
        w,
        {"x_rod_m": r.x_rod_m},
    )
    return D.write(tmp_path / "ds", ActuatorParams.table1(), [run], "test", D.Sensor(1e-9, 2e-9))


def test_round_trip(tmp_path):
    root = make(tmp_path)
    ds = D.load(root)
    assert ds.runs[0].id == "f500_fwd"
    assert ds.runs[0].waveform == Sawtooth(cycles=3)
    assert "x_rod_m" in ds.runs[0].extra
    assert ds.sensor.noise_rms_m == 2e-9
    assert ds.actuator == ActuatorParams.table1()


def corrupt(root, line, text):
    p = root / "f500_fwd.csv"
    lines = p.read_text().splitlines()
    lines[line - 1] = text
    p.write_text("\n".join(lines) + "\n")
    return p


@pytest.mark.parametrize(
    "line,text,row,column,what",
    [
        (5, "4e-05,abc,1e-9,0", 5, "drive_v", "not a number"),
        (6, "5e-05,1.0,nan,0", 6, "x_m", "not a finite number"),
        (7, "1e-05,1.0,1e-9,0", 7, "t_s", "time not ascending"),
        (8, "7e-05,1.0,1e-9", 8, None, "3 cells"),
        (9, "7.5e-05,1.0,1e-9,0", 9, "t_s", "not uniformly sampled"),
        (1, "t_s,drive,x_m,x_rod_m", 1, "drive_v", "required column"),
    ],
)
def test_bad_csv_is_named(tmp_path, line, text, row, column, what):
    root = make(tmp_path)
    corrupt(root, line, text)
    with pytest.raises(D.DatasetError, match=what) as e:
        D.load(root)
    assert e.value.file.endswith("f500_fwd.csv")
    assert e.value.row == row
    assert e.value.column == column


@pytest.mark.parametrize(
    "change,what",
    [
        (lambda m: m.update(format="other/1"), "format must be"),
        (lambda m: m["actuator"].pop("mu_s"), "missing keys"),
        (lambda m: m["runs"][0]["waveform"].update(direction=2), "direction"),
        (lambda m: m["runs"][0].update(file="../escape.csv"), "outside the dataset"),
        (lambda m: m["runs"].append(dict(m["runs"][0])), "duplicate run id"),
        (lambda m: m.update(sensor={"noise_rms_m": -1}), "sensor.noise_rms_m"),
    ],
)
def test_bad_metadata_is_named(tmp_path, change, what):
    root = make(tmp_path)
    meta = json.loads((root / "dataset.json").read_text())
    change(meta)
    (root / "dataset.json").write_text(json.dumps(meta))
    with pytest.raises(D.DatasetError, match=what) as e:
        D.load(root)
    assert e.value.file.endswith("dataset.json")


def test_missing_files(tmp_path):
    with pytest.raises(D.DatasetError, match="not a folder"):
        D.load(tmp_path / "nope")
    (tmp_path / "empty").mkdir()
    with pytest.raises(D.DatasetError, match="missing"):
        D.load(tmp_path / "empty")


def test_simulated_dataset_matches_its_own_simulation(tmp_path):
    root = make(tmp_path)
    ds = D.load(root)
    r = simulate(ds.runs[0].waveform, ds.actuator)
    sim = np.interp(ds.runs[0].t_s, r.t_s, r.x_slider_m)
    assert np.max(np.abs(sim - ds.runs[0].x_m)) < 1e-12
