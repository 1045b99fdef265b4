"""Read and validate datasets of the `stick-slip-dataset/1` format (docs/data-format.md).

Validation is complete before anything is returned: a bad file raises DatasetError naming the
file, the row (1-based line number in the file) and the column, and no half-read data escapes."""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .dataset_checks import check_run
from .model import ActuatorParams, Sawtooth

FORMAT = "stick-slip-dataset/1"
REQUIRED_COLUMNS = ("t_s", "drive_v", "x_m")
# relative tolerance on the sampling interval: CSV writers round times to ~9 digits
UNIFORM_RTOL = 1e-4


class DatasetError(ValueError):
    """A dataset that breaks the format; says where."""

    def __init__(
        self, file: str | Path, message: str, row: int | None = None, column: str | None = None
    ):
        self.file, self.row, self.column = str(file), row, column
        where = self.file
        if row is not None:
            where += f", row {row}"
        if column is not None:
            where += f", column {column!r}"
        super().__init__(f"{where}: {message}")


@dataclass
class Run:
    id: str
    file: Path
    t_s: np.ndarray
    drive_v: np.ndarray
    x_m: np.ndarray
    waveform: Sawtooth | None = None
    extra: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def dt_s(self) -> float:
        return float(self.t_s[1] - self.t_s[0])


@dataclass
class Sensor:
    resolution_m: float | None = None
    noise_rms_m: float | None = None


@dataclass
class Dataset:
    path: Path
    description: str
    actuator: ActuatorParams
    runs: list[Run]
    sensor: Sensor
    # what the cross-checks suspect (dataset_checks.py): likely unit errors, named by file
    warnings: list[str] = field(default_factory=list)

    def run(self, run_id: str) -> Run:
        for r in self.runs:
            if r.id == run_id:
                return r
        raise KeyError(run_id)


def read_run_csv(path: Path) -> tuple[list[str], np.ndarray]:
    """Columns and values of one run file, validated cell by cell. Extra columns (the format
    ignores them) are kept only when every cell is a finite number; others are dropped."""
    try:
        f = open(path, newline="")  # noqa: SIM115 (closed by the with below; open errors named here)
    except OSError as e:
        raise DatasetError(path, f"cannot open: {e.strerror}") from None
    with f:
        reader = csv.reader(f)
        try:
            header = [h.strip() for h in next(reader)]
        except StopIteration:
            raise DatasetError(path, "empty file, expected a header row", row=1) from None
        except (csv.Error, UnicodeDecodeError) as e:
            raise DatasetError(path, f"unreadable header: {e}", row=1) from None
        for name in REQUIRED_COLUMNS:
            if name not in header:
                raise DatasetError(
                    path,
                    f"header lacks required column {name!r} (has {header})",
                    row=1,
                    column=name,
                )
        if len(set(header)) != len(header):
            raise DatasetError(path, f"duplicate column names in header {header}", row=1)
        rows: list[list[float]] = []
        numeric = [True] * len(header)  # extra columns: any cell not a finite number drops it
        line = 1
        try:
            for line, cells in enumerate(reader, start=2):
                if not cells or all(not c.strip() for c in cells):
                    raise DatasetError(path, "empty row", row=line)
                if len(cells) != len(header):
                    raise DatasetError(
                        path, f"{len(cells)} cells, header has {len(header)}", row=line
                    )
                vals = []
                for j, (name, cell) in enumerate(zip(header, cells)):
                    try:
                        v = float(cell)
                        problem = "" if math.isfinite(v) else "not a finite number"
                    except ValueError:
                        v, problem = math.nan, "not a number"
                    if problem and name not in REQUIRED_COLUMNS:
                        numeric[j] = False  # an extra column: ignored, as the format says
                    elif problem:
                        raise DatasetError(path, f"{problem}: {cell!r}", row=line, column=name)
                    vals.append(v)
                rows.append(vals)
        except (csv.Error, UnicodeDecodeError) as e:
            raise DatasetError(path, f"unreadable: {e}", row=line + 1) from None
    if len(rows) < 2:
        raise DatasetError(path, f"needs at least 2 data rows, has {len(rows)}")
    keep = [j for j in range(len(header)) if numeric[j]]
    header = [header[j] for j in keep]
    data = np.array(rows, dtype=np.float64)[:, keep]
    t = data[:, header.index("t_s")]
    dt = np.diff(t)
    bad = np.nonzero(dt <= 0)[0]
    if bad.size:
        i = int(bad[0])
        raise DatasetError(
            path,
            f"time not ascending: {float(t[i + 1])!r} after {float(t[i])!r}",
            row=i + 3,
            column="t_s",
        )
    step = (t[-1] - t[0]) / (len(t) - 1)
    off = np.nonzero(np.abs(dt - step) > UNIFORM_RTOL * step)[0]
    if off.size:
        i = int(off[0])
        raise DatasetError(
            path,
            f"not uniformly sampled: interval {float(dt[i])!r} s, mean {float(step)!r} s",
            row=i + 3,
            column="t_s",
        )
    return header, data


def load(path: str | Path) -> Dataset:
    """Load and validate a whole dataset folder."""
    root = Path(path)
    meta_path = root / "dataset.json"
    if not root.is_dir():
        raise DatasetError(root, "not a folder")
    try:
        meta = json.loads(meta_path.read_text())
    except FileNotFoundError:
        raise DatasetError(meta_path, "missing") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise DatasetError(meta_path, f"invalid JSON: {e}") from None
    if not isinstance(meta, dict):
        raise DatasetError(meta_path, "top level must be an object")
    if meta.get("format") != FORMAT:
        raise DatasetError(meta_path, f"format must be {FORMAT!r}, got {meta.get('format')!r}")
    try:
        actuator = ActuatorParams.from_dict(meta.get("actuator") or {}, "actuator")
    except ValueError as e:
        raise DatasetError(meta_path, str(e)) from None
    sensor = Sensor()
    if "sensor" in meta:
        s = meta["sensor"]
        if not isinstance(s, dict):
            raise DatasetError(meta_path, "sensor must be an object")
        for k in ("resolution_m", "noise_rms_m"):
            if k in s:
                v = s[k]
                if (
                    isinstance(v, bool)
                    or not isinstance(v, (int, float))
                    or not math.isfinite(v)
                    or v < 0
                ):
                    raise DatasetError(
                        meta_path, f"sensor.{k}: expected a finite number >= 0, got {v!r}"
                    )
                setattr(sensor, k, float(v))
    runs_meta = meta.get("runs")
    if not isinstance(runs_meta, list) or not runs_meta:
        raise DatasetError(meta_path, "runs must be a non-empty list")
    runs, seen = [], set()
    warnings: list[str] = []
    for i, rm in enumerate(runs_meta):
        where = f"runs[{i}]"
        if (
            not isinstance(rm, dict)
            or not isinstance(rm.get("id"), str)
            or not isinstance(rm.get("file"), str)
        ):
            raise DatasetError(meta_path, f"{where}: needs string 'id' and 'file'")
        if rm["id"] in seen:
            raise DatasetError(meta_path, f"{where}: duplicate run id {rm['id']!r}")
        seen.add(rm["id"])
        file = (root / rm["file"]).resolve()
        if root.resolve() not in file.parents:
            raise DatasetError(
                meta_path, f"{where}.file: {rm['file']!r} is outside the dataset folder"
            )
        waveform = None
        if rm.get("waveform") is not None:
            try:
                waveform = Sawtooth.from_dict(rm["waveform"], f"{where}.waveform")
            except ValueError as e:
                raise DatasetError(meta_path, str(e)) from None
        header, data = read_run_csv(file)
        cols = {name: data[:, j] for j, name in enumerate(header)}
        warnings += check_run(
            file, where, cols["t_s"], cols["drive_v"], cols["x_m"], waveform, actuator
        )
        runs.append(
            Run(
                id=rm["id"],
                file=file,
                t_s=cols.pop("t_s"),
                drive_v=cols.pop("drive_v"),
                x_m=cols.pop("x_m"),
                waveform=waveform,
                extra=cols,
            )
        )
    desc = meta.get("description", "")
    return Dataset(root, desc if isinstance(desc, str) else "", actuator, runs, sensor, warnings)


def write(
    path: str | Path,
    actuator: ActuatorParams,
    runs: list[Run],
    description: str = "",
    sensor: Sensor | None = None,
) -> Path:
    """Write a dataset folder (used by the generators and the HIL recorder)."""
    root = Path(path)
    root.mkdir(parents=True, exist_ok=True)
    meta: dict = {"format": FORMAT, "description": description, "actuator": actuator.to_dict()}
    if sensor is not None:
        meta["sensor"] = {k: v for k, v in vars(sensor).items() if v is not None}
    meta["runs"] = []
    for r in runs:
        name = f"{r.id}.csv"
        cols = [r.t_s, r.drive_v, r.x_m, *r.extra.values()]
        header = ",".join(["t_s", "drive_v", "x_m", *r.extra.keys()])
        np.savetxt(
            root / name,
            np.column_stack(cols),
            delimiter=",",
            header=header,
            comments="",
            fmt="%.10g",
        )
        entry: dict = {"id": r.id, "file": name}
        if r.waveform is not None:
            entry["waveform"] = r.waveform.to_dict()
        meta["runs"].append(entry)
    (root / "dataset.json").write_text(json.dumps(meta, indent=2) + "\n")
    return root
