"""The `stickslip` command: simulate, figures, hil, diagnose."""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .model import DT_S, MODELS, VARIANTS, Effects, Sawtooth, simulate
from .progress import Progress

if TYPE_CHECKING:
    from .hil.node import NodeSession

# nodes `hil run` can start: the host node (-q: fixed point) and the firmware images in QEMU
# (hil.client.QEMU_TARGETS; listed here so that --help does not import pyserial)
NODE_LINKS = (
    "pty",
    "tcp",
    "pty-q",
    "tcp-q",
    "qemu-m4f",
    "qemu-m3",
    "qemu-m4f-q",
    "qemu-m3-q",
    "qemu-m0plus-q",
)


class CliError(Exception):
    """A user error: printed as one line, exit status 2."""


def _add_json_option(p: argparse.ArgumentParser, what: str) -> None:
    """--json [FILE], the same on every subcommand: the result as JSON to FILE (the summary still
    printed), or to stdout in place of the summary when FILE is '-' or omitted."""
    p.add_argument(
        "--json",
        nargs="?",
        const="-",
        metavar="FILE",
        help=f"write {what} as JSON to FILE; to stdout instead of the summary when FILE is '-' "
        "or omitted",
    )


def _add_quiet_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--quiet",
        action="store_true",
        help="no progress display (it is shown only when stderr is a terminal)",
    )


def _report(a: argparse.Namespace, result: dict, summary: str) -> None:
    """Print the summary, or the JSON result in its place (--json, --json -); with --json FILE
    write the JSON there as well."""
    # allow_nan=False: a NaN is an error here, never an invalid JSON document
    if a.json == "-":
        print(json.dumps(result, indent=2, allow_nan=False))
        return
    if a.json:
        path = Path(a.json)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=2, allow_nan=False) + "\n")
    print(summary)


def _check_writable(path: str | Path, option: str, folder: bool) -> None:
    """Refuse an output that cannot be written before the work that fills it (a diagnosis takes
    minutes): a file is written in its folder and removed, and the folders this made are removed
    again (a refused run writes nothing)."""
    p = Path(path)
    where = p if folder else p.parent
    if not folder and p.is_dir():
        raise CliError(f"{option}: '{p}' is a folder, not a file")
    made = [d for d in (where, *where.parents) if not d.exists()]
    try:
        where.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=where, prefix=".stickslip-probe-"):
            pass
    except OSError as e:
        raise CliError(f"{option}: cannot write to '{where}': {e.strerror or e}") from None
    finally:
        for d in made:  # innermost first
            with contextlib.suppress(OSError):
                d.rmdir()


def _finite(name: str):
    def parse(s: str) -> float:
        try:
            v = float(s)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}: expected a number, got {s!r}") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{name}: expected a finite number, got {s!r}")
        return v

    return parse


def _add_waveform_options(p: argparse.ArgumentParser) -> None:
    d = Sawtooth()
    g = p.add_argument_group(
        "waveform (stick-slip-dataset/1 sawtooth; defaults: the paper's 4.4 um, 500 Hz run)"
    )
    g.add_argument("--frequency-hz", type=_finite("--frequency-hz"), default=d.frequency_hz)
    g.add_argument("--amplitude-v", type=_finite("--amplitude-v"), default=d.amplitude_v)
    g.add_argument("--offset-v", type=_finite("--offset-v"), default=d.offset_v)
    g.add_argument(
        "--rise-fraction",
        type=_finite("--rise-fraction"),
        default=None,
        help=f"slow-edge share of the period, in (0, 1) (default {d.rise_fraction})",
    )
    g.add_argument(
        "--fall-time-s",
        type=_finite("--fall-time-s"),
        default=None,
        help="duration of the fast edge, instead of --rise-fraction",
    )
    g.add_argument("--direction", type=int, choices=(1, -1), default=d.direction)
    g.add_argument("--cycles", type=int, default=d.cycles)


def _waveform(a: argparse.Namespace) -> Sawtooth:
    if a.rise_fraction is not None and a.fall_time_s is not None:
        raise CliError("give --rise-fraction or --fall-time-s, not both")
    if a.cycles < 0:
        raise CliError(f"--cycles: must be >= 0, got {a.cycles}")
    if a.frequency_hz <= 0:
        raise CliError(f"--frequency-hz: must be > 0, got {a.frequency_hz}")
    w = Sawtooth(
        a.frequency_hz, a.amplitude_v, a.offset_v, Sawtooth().rise_fraction, a.direction, a.cycles
    )
    if a.fall_time_s is not None:
        w = w.with_fall_time(a.fall_time_s)
    elif a.rise_fraction is not None:
        w = Sawtooth(
            a.frequency_hz, a.amplitude_v, a.offset_v, a.rise_fraction, a.direction, a.cycles
        )
    if not 0.0 < w.rise_fraction < 1.0:
        raise CliError(
            f"rise fraction must be in (0, 1), got {w.rise_fraction:g} "
            f"(fall time {w.fall_time_s:g} s at {w.frequency_hz:g} Hz)"
        )
    return w


# Each edge of the sawtooth must span at least this many steps (host_sim/main.c gives the
# measurement behind it: 0.1-0.8 % per cycle from 1 us to 2 us on a 15 us edge, 0.5-3 % at 4 us).
MIN_STEPS_PER_EDGE = 10


def _check_resolution(w: Sawtooth, dt_s: float, hold_s: float, decimation: int) -> None:
    """Refuse a step that cannot resolve the waveform, and a decimation that would move the
    summary: its period boundaries and its last position must be recorded samples."""
    if not dt_s > 0:
        raise CliError(f"--dt-s: the integration step must be > 0 s, got {dt_s:g}")
    edge = min(w.rise_fraction, 1.0 - w.rise_fraction) * w.period_s
    if edge < MIN_STEPS_PER_EDGE * dt_s:
        raise CliError(
            f"--dt-s: a {dt_s:g} s step does not resolve the {edge:g} s edge of the sawtooth "
            f"({w.frequency_hz:g} Hz, fall {w.fall_time_s:g} s): at least {MIN_STEPS_PER_EDGE} "
            f"steps per edge are needed, so dt <= {edge / MIN_STEPS_PER_EDGE:g} s"
        )
    if decimation < 1:
        raise CliError(f"--decimation: must be >= 1, got {decimation}")
    if decimation == 1:
        return
    per_period = w.period_s / dt_s
    k = round(per_period)
    if abs(per_period - k) > 1e-6 * per_period:
        raise CliError(
            f"--decimation {decimation}: a period of {per_period:g} steps is not a whole number "
            "of steps, so its boundaries are recorded only at --decimation 1"
        )
    if k % decimation:
        small = [d for d in range(1, math.isqrt(k) + 1) if k % d == 0]
        divisors = sorted({*small, *(k // d for d in small)})[:12]
        raise CliError(
            f"--decimation {decimation}: the summary measures the slider at each period boundary "
            f"({per_period:g} steps apart), which must be a recorded sample: choose a divisor of "
            f"{k} ({', '.join(map(str, divisors))}, ...)"
        )
    n_total = round((w.duration_s + hold_s) / dt_s)
    if n_total % decimation:
        raise CliError(
            f"--decimation {decimation}: the run's {n_total} steps are not a multiple of it, so "
            "its final position would not be recorded (change --hold-s)"
        )


def cmd_simulate(a: argparse.Namespace) -> int:
    if a.dataset:
        return _simulate_dataset(a)
    w = _waveform(a)
    if w.cycles < 1:
        raise CliError(f"--cycles: must be >= 1 (the summary is per period), got {w.cycles}")
    _check_resolution(w, a.dt_s, a.hold_s, a.decimation)
    r = simulate(
        w, model=a.model, dt_s=a.dt_s, hold_s=a.hold_s, decimation=a.decimation, variant=a.variant
    )
    if a.out:
        r.to_csv(a.out)
    s = r.summary()
    if a.out:
        s["csv"] = str(a.out)
    _report(
        a,
        s,
        f"{a.model} ({a.variant}): {w.cycles} cycles at {w.frequency_hz:g} Hz, "
        f"fall {w.fall_time_s * 1e6:.1f} us: "
        f"mean step {s['mean_step_per_cycle_m'] * 1e6:.4f} um per cycle"
        + (f"; wrote {a.out}" if a.out else ""),
    )
    return 0


def _simulate_dataset(a: argparse.Namespace) -> int:
    from . import dataset as D

    if a.variant != "f32":
        raise CliError("--dataset runs the f32 core (measured runs may need a sampled drive)")

    ds = D.load(a.dataset)
    out_dir = Path(a.out) if a.out else None
    if out_dir:
        out_dir.mkdir(parents=True, exist_ok=True)
    rows = []
    with Progress("simulating", total=len(ds.runs), unit="run", quiet=a.quiet) as bar:
        for i, run in enumerate(ds.runs):
            bar.to(i, run.id)
            hold = max(0.0, float(run.t_s[-1]) - (run.waveform.duration_s if run.waveform else 0.0))
            if run.waveform is not None:
                r = simulate(run.waveform, ds.actuator, a.model, a.dt_s, hold_s=hold)
            else:
                r = simulate(
                    None,
                    ds.actuator,
                    a.model,
                    a.dt_s,
                    drive_v=run.drive_v,
                    drive_interval_s=run.dt_s,
                )
            sim = np.interp(run.t_s - run.t_s[0], r.t_s, r.x_slider_m)
            meas = run.x_m - run.x_m[0]
            row: dict[str, Any] = {
                "run": run.id,
                "rmse_m": float(np.sqrt(np.mean((meas - sim) ** 2))),
            }
            if run.waveform is not None:
                k = np.arange(run.waveform.cycles + 1) * run.waveform.period_s
                row["measured_mean_step_m"] = float(
                    np.mean(np.diff(np.interp(k, run.t_s - run.t_s[0], meas)))
                )
                row["simulated_mean_step_m"] = r.mean_step_m
            rows.append(row)
            if out_dir:
                r.to_csv(out_dir / f"{run.id}.csv")
    lines = []
    for row in rows:
        extra = ""
        if "measured_mean_step_m" in row:
            extra = (
                f", step measured {row['measured_mean_step_m'] * 1e6:.4f} um, "
                f"simulated {row['simulated_mean_step_m'] * 1e6:.4f} um"
            )
        lines.append(f"{row['run']}: rmse {row['rmse_m'] * 1e9:.1f} nm{extra}")
    _report(a, {"dataset": str(ds.path), "model": a.model, "runs": rows}, "\n".join(lines))
    return 0


def cmd_figures(a: argparse.Namespace) -> int:
    from .figures import FIGURES, make_all

    with Progress("figures", total=len(FIGURES), unit="fig", quiet=a.quiet) as bar:
        claims = make_all(a.out, progress=lambda i, n, name: bar.to(i, name))
    _report(a, claims, f"wrote {len(claims)} figures and figures.json to {a.out}")
    return 0


def cmd_hil_node(a: argparse.Namespace) -> int:
    import os

    from .hil.client import node_binary

    exe = str(node_binary())
    args = [exe, "--pty"] if a.link == "pty" else [exe, "--tcp", str(a.port)]
    if a.model:
        from .hil.node import HilError, model_args
        from .model_file import load as load_model

        try:
            args += model_args(load_model(a.model))
        except HilError as e:
            raise CliError(f"--model {a.model}: {e}") from None
    sys.stdout.flush()
    os.execv(exe, args)  # the node prints where it listens; Ctrl-C stops it
    return 0  # not reached


def _start_node(stack: contextlib.ExitStack, node_link: str, can: bool = False) -> str:
    """Start the node --node-link names (the host node, or the firmware in QEMU) in stack, which
    stops it whatever happens; its URL."""
    from .hil.client import HostNode, QemuNode

    if node_link.startswith("qemu-"):
        if can:
            raise CliError("the firmware serves the serial link only; use --link serial")
        return stack.enter_context(QemuNode(node_link)).url
    host_link, _, variant = node_link.partition("-")
    return stack.enter_context(HostNode(("can-" if can else "") + host_link, variant or "f32")).url


def cmd_hil_run(a: argparse.Namespace) -> int:
    from .hil.client import NodeClient
    from .hil.session import node_params, play, record, run_budget, summary

    w = _waveform(a)
    if w.cycles < 1:
        raise CliError(f"--cycles: must be >= 1 (the summary is per period), got {w.cycles}")
    if a.decimation < 1:
        raise CliError(f"--decimation: must be >= 1, got {a.decimation}")
    with contextlib.ExitStack() as stack:
        url = a.url if a.url is not None else _start_node(stack, a.node_link, a.link == "can")
        if a.link == "can":
            from .hil.can_client import CanNodeClient

            client: NodeSession = CanNodeClient(url, interface=a.can_interface)
        else:
            client = NodeClient(url)
        with client as c:
            if a.dt_s is not None:
                c.set("step_s", a.dt_s)  # refused by name when out of the node's range
            _check_resolution(w, c.info.dt_s, 0.0, a.decimation)
            steps = run_budget(w, c.info.dt_s, a.mode, a.decimation)
            with Progress(f"{a.mode} run", total=steps, unit="step", quiet=a.quiet) as bar:
                run = play(c, w, a.mode, a.decimation, a.paced, progress=bar.to)
            s = summary(run, c)
            if a.out:
                s["dataset"] = str(record(run, node_params(c), a.out))
    _report(
        a,
        s,
        f"{a.mode} over {url}: {run.steps} steps in {run.wall_s:.3f} s "
        f"({run.steps_per_s:.0f} steps/s), mean step {s['mean_step_per_cycle_m'] * 1e6:.4f} um "
        f"per cycle"
        + (
            f", {run.telemetry.deadline_misses} deadline misses"
            if a.paced and run.telemetry.deadline_misses is not None
            else ""
        )
        + (f"; dataset in {a.out}" if a.out else ""),
    )
    return 0


def cmd_hil_replay(a: argparse.Namespace) -> int:
    from . import dataset as D
    from .hil.client import NodeClient
    from .hil.replay import replay
    from .model_file import load as load_model

    m = load_model(a.model)
    ds = D.load(a.dataset)
    if a.report:
        _check_writable(a.report, "--report", folder=True)
    traces: list = []
    with contextlib.ExitStack() as stack:
        url = a.url if a.url is not None else _start_node(stack, a.node_link)
        with NodeClient(url) as c, Progress("replay", total=None, quiet=a.quiet) as bar:
            r = replay(c, ds, m, say=bar.status, only=a.runs, traces=traces)
    report = ""
    if a.report:
        from .hil.replay_report import write_report

        report = f"\nreport: {write_report(r, traces, a.report)}"
    runs = "\n".join(
        f"  {x['id']:24s} {x['rmse_m'] * 1e9:8.3f} nm ({x['rows']} samples)" for x in r["runs"]
    )
    val, diag = r["validation_rmse_m"], r["diagnosis_validation_rmse_m"]
    against = (
        f"; validation runs {val * 1e9:.3f} nm, the diagnosis said {diag * 1e9:.3f} nm"
        if val is not None and diag is not None
        else ""
    )
    _report(
        a,
        r,
        f"replay of {a.dataset} on {r['node']['variant']} node {url}:\n{runs}\n"
        f"all runs {r['rmse_m'] * 1e9:.3f} nm RMS{against}{report}",
    )
    return 0


def cmd_hil_position(a: argparse.Namespace) -> int:
    from .hil.client import HostNode, NodeClient
    from .hil.positioning import position

    if not math.isfinite(a.target_m) or abs(a.target_m) > 0.025:
        raise CliError(f"--target-m: must be within +-25 mm, got {a.target_m}")
    if not a.tolerance_m > 0:
        raise CliError(f"--tolerance-m: must be > 0, got {a.tolerance_m}")
    with contextlib.ExitStack() as stack:
        url = a.url or stack.enter_context(HostNode("tcp")).url
        with NodeClient(url) as c:
            r = position(c, a.target_m, a.tolerance_m, max_time_s=a.max_time_s)
    settle = (
        "not settled" if r.settle_time_s is None else f"settled in {r.settle_time_s * 1e3:.1f} ms"
    )
    _report(
        a,
        r.summary(),
        f"target {a.target_m * 1e6:.3f} um: {r.coarse_periods} coarse periods, {settle} "
        f"(model time), final error {r.final_error_m * 1e9:.2f} nm",
    )
    return 0 if r.settle_time_s is not None else 1


def cmd_hil_firmware_q(a: argparse.Namespace) -> int:
    from . import _native as N
    from .hil import firmware_q as FQ

    try:
        elf = FQ.q_firmware_elf(a.preset)
    except FileNotFoundError as e:
        raise CliError(str(e)) from None
    with Progress(f"{elf.name} in QEMU", total=None, quiet=a.quiet):
        run = FQ.run_q_firmware(elf)
    header, rows = FQ.host_reference()
    exact = all(run.header.get(k) == v for k, v in header.items()) and np.array_equal(
        run.rows, rows
    )
    lines = [f"{elf}: {len(run.rows)} rows over the UART, {run.header['steps']} steps of 1 us"]
    per_cycle = FQ.STEPS_PER_CYCLE // FQ.EVERY
    x_m = run.rows[per_cycle::per_cycle, 1] * N.q_scale("x_slider_q40")
    for k, (x, step) in enumerate(zip(x_m, run.steps_m), start=1):
        lines.append(f"  cycle {k}: slider at {x * 1e6:8.4f} um, step {step * 1e6:.4f} um")
    lines.append("bit-exact with the host's fixed-point core: " + ("yes" if exact else "NO"))
    result = {
        "elf": str(elf),
        "header": run.header,
        "rows": len(run.rows),
        "slider_at_cycle_end_m": [float(x) for x in x_m],
        "steps_m": [float(v) for v in run.steps_m],
        "bit_exact": bool(exact),
    }
    _report(a, result, "\n".join(lines))
    return 0 if exact else 1


def cmd_diagnose(a: argparse.Namespace) -> int:
    from concurrent.futures import ThreadPoolExecutor

    from .diagnosis.pipeline import diagnose
    from .diagnosis.report import write_report

    if a.workers < 1:
        raise CliError(f"--workers must be >= 1, got {a.workers}")
    _check_writable(a.out, "--out", folder=True)
    if a.json and a.json != "-":
        _check_writable(a.json, "--json", folder=False)
    if a.export:
        _check_writable(a.export, "--export", folder=True)
    # a live status line: what the pipeline is doing now, and for how long
    with Progress("diagnosing", total=None, quiet=a.quiet) as bar:
        with ThreadPoolExecutor(max_workers=a.workers) as ex:
            d = diagnose(a.dataset, executor=ex, progress=bar.status)
        bar.status("writing the report")
        report = write_report(d, a.out)
    if a.export:
        from .model_file import export

        exported = export(d.model_file(), a.export)
    for w in d.warnings:  # also in the report; here even under --quiet
        print(f"stickslip diagnose: warning: {w}", file=sys.stderr)
    j = d.to_json()
    verdict = ", ".join(j["causes"]) + (
        " (unexplained residuals remain)" if j["unexplained"] else ""
    )
    rmse = {k: j[k]["validation_rmse_m"] * 1e9 for k in ("nominal", "baseline", "extended")}
    _report(
        a,
        j,
        f"causes: {verdict}; validation RMSE nominal {rmse['nominal']:.1f} nm,"
        f" calibrated {rmse['baseline']:.1f} nm, extended {rmse['extended']:.1f} nm"
        f" (noise {d.noise_m * 1e9:.1f} nm); gain {j['gain']:.3f}\nreport: {report}"
        + (f"\nmodel: {exported[0]} and {exported[1]}" if a.export else ""),
    )
    return 0


def cmd_model_export(a: argparse.Namespace) -> int:
    from .model import ActuatorParams
    from .model_file import ModelFile, ModelFileError, export
    from .model_file import load as load_model

    if a.model:
        m = load_model(a.model)
    elif a.dataset:
        from . import dataset as D

        ds = D.load(a.dataset)
        m = ModelFile(ds.actuator, source={"dataset": str(a.dataset), "nominal": True})
    else:
        m = ModelFile(ActuatorParams.table1(), source={"nominal": "Table I"})
    changes = {"law": a.law} if a.law else {}
    for item in a.set or []:
        name, sep, text = item.partition("=")
        if not sep:
            raise CliError(f"--set: expected NAME=VALUE, got {item!r}")
        try:
            value = float(text)
        except ValueError:
            raise CliError(f"--set {name}: expected a number, got {text!r}") from None
        group = "effects" if name in Effects.__dataclass_fields__ else "actuator"
        changes.setdefault(group, {})[name] = value
    d = m.to_dict()
    d["law"] = changes.get("law", d["law"])
    d["actuator"].update(changes.get("actuator", {}))
    d["effects"].update(changes.get("effects", {}))
    try:
        m = ModelFile.from_dict(d, "--set")
    except ModelFileError as e:
        raise CliError(e.problem) from None
    _check_writable(a.out, "--out", folder=True)
    j, h = export(m, a.out)
    _report(a, m.to_dict(), f"model ({m.law}, {len(m.effects.active())} effects): {j} and {h}")
    return 0


def cmd_model_check(a: argparse.Namespace) -> int:
    from .model_file import load as load_model

    m = load_model(a.file)
    _report(
        a, m.to_dict(), f"{a.file}: a valid {m.law} model, effects {m.effects.active() or 'none'}"
    )
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="stickslip", description="Simulate, test and identify stick-slip piezo actuators."
    )
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser(
        "simulate",
        help="simulate the actuator (Table I parameters) with the C core",
        description="Simulate the stick-slip actuator and write CSV and/or a JSON summary.",
    )
    _add_waveform_options(s)
    s.add_argument("--model", choices=MODELS, default="ls", help="friction model (default ls)")
    s.add_argument(
        "--variant",
        choices=VARIANTS,
        default="f32",
        help="f32: the float core; q: the fixed-point core (docs/fixed-point.md)",
    )
    s.add_argument(
        "--dt-s",
        type=_finite("--dt-s"),
        default=DT_S,
        help=f"integration step (default {DT_S:g}, Table I's)",
    )
    s.add_argument(
        "--hold-s",
        type=_finite("--hold-s"),
        default=0.0,
        help="time simulated after the last period",
    )
    s.add_argument("--decimation", type=int, default=1, help="keep every N-th step in the CSV")
    s.add_argument("--out", help="CSV file to write (with --dataset: a folder for one CSV per run)")
    _add_json_option(s, "the summary (includes mean_step_per_cycle_m)")
    s.add_argument(
        "--dataset", help="simulate every run of this dataset with its nominal parameters"
    )
    _add_quiet_option(s)
    s.set_defaults(func=cmd_simulate)
    f = sub.add_parser(
        "figures",
        help="reproduce the LS paper's figures as PNGs",
        description="Reproduce Figs. 3-9 and 13 of the LS paper from the C core.",
    )
    f.add_argument("--out", default="out/figures", help="folder for the PNGs and figures.json")
    _add_json_option(f, "the figures' claims (as figures.json)")
    _add_quiet_option(f)
    f.set_defaults(func=cmd_figures)
    dg = sub.add_parser(
        "diagnose",
        help="what the simulation gets wrong on a measured dataset, its cause, and the gain",
        description="Validate a stick-slip-dataset/1 folder, calibrate the model, fit every cause "
        "of the catalog, rank them on held-out runs, and write a report and "
        "stick-slip-diagnosis/1 JSON.",
    )
    dg.add_argument("dataset", help="dataset folder (with dataset.json)")
    dg.add_argument("--out", default="out/diagnosis", help="folder for report.md and its plots")
    _add_json_option(dg, "the diagnosis (stick-slip-diagnosis/1)")
    dg.add_argument(
        "--workers",
        type=int,
        default=max(1, min(os.cpu_count() or 1, 8)),
        help="fits run at once, in threads (the C model releases the GIL; each fit also spreads"
        " its runs over the cores) (default: the CPU count, at most 8)",
    )
    dg.add_argument(
        "--export",
        metavar="DIR",
        help="also write the identified model there: model.json (stick-slip-model/1) and "
        "stickslip_model.h (C initialisers for firmware)",
    )
    _add_quiet_option(dg)
    dg.set_defaults(func=cmd_diagnose)

    mo = sub.add_parser(
        "model",
        help="model files (stick-slip-model/1): export any parameter set, check a file",
        description="Write or check stick-slip-model/1 files (docs/model-file.md).",
    )
    ms = mo.add_subparsers(dest="model_command", required=True)
    me = ms.add_parser("export", help="write model.json and stickslip_model.h")
    me.add_argument("--out", required=True, metavar="DIR", help="folder for the two files")
    src = me.add_mutually_exclusive_group()
    src.add_argument("--model", metavar="FILE", help="start from this model file")
    src.add_argument("--dataset", metavar="DIR", help="start from a dataset's nominal parameters")
    me.add_argument("--law", choices=("ls", "lugre", "gms"), help="friction law")
    me.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="a parameter or effect (stick-slip-dataset/1 and docs/effects.md names); repeatable",
    )
    _add_json_option(me, "the model (stick-slip-model/1)")
    _add_quiet_option(me)
    me.set_defaults(func=cmd_model_export)
    mc = ms.add_parser("check", help="validate a model file, naming the field at fault")
    mc.add_argument("file")
    _add_json_option(mc, "the model (stick-slip-model/1)")
    _add_quiet_option(mc)
    mc.set_defaults(func=cmd_model_check)

    h = sub.add_parser(
        "hil",
        help="hardware in the loop: the stage-model node and the drive emulator",
        description="Serve the stage model as a node, or drive one as the electronics would.",
    )
    hs = h.add_subparsers(dest="hil_command", required=True)
    hn = hs.add_parser("node", help="start a host node (stickslip_node) and print where it listens")
    hn.add_argument("--link", choices=("pty", "tcp"), default="pty")
    hn.add_argument("--port", type=int, default=0, help="TCP port on 127.0.0.1 (0: any free port)")
    hn.add_argument(
        "--model", metavar="FILE", help="serve this model (stick-slip-model/1) instead of Table I"
    )
    hn.set_defaults(func=cmd_hil_node)
    hr = hs.add_parser(
        "run",
        help="play a sawtooth through a node and record a dataset",
        description="Emulate the drive electronics: play a sawtooth through a node "
        "(started here unless --url names one) and record the run.",
    )
    _add_waveform_options(hr)
    hr.add_argument("--link", choices=("serial", "can"), default="serial")
    hr.add_argument(
        "--url",
        help="node to use: a device path (pty, UART) or socket://127.0.0.1:PORT; with --link can "
        "the python-can channel (an SLCAN device or URL, or vcan0 with --can-interface socketcan)",
    )
    hr.add_argument(
        "--can-interface",
        default="slcan",
        help="python-can interface for --link can (default slcan)",
    )
    hr.add_argument(
        "--node-link",
        choices=NODE_LINKS,
        default="pty",
        help="the node started here: the host node on a pty or TCP (default pty; -q: the "
        "fixed-point node), or the firmware in QEMU (Cortex-M4F on mps2-an386, Cortex-M3 and the "
        "ARMv6-M image on mps2-an385; -q: the fixed-point firmware; serial only)",
    )
    hr.add_argument(
        "--mode",
        choices=("lockstep", "free"),
        default="lockstep",
        help="lockstep: drive samples from here, step by step; free: the node plays it",
    )
    hr.add_argument("--decimation", type=int, default=1, help="keep every N-th step")
    hr.add_argument("--paced", action="store_true", help="free mode: keep to real time")
    hr.add_argument(
        "--dt-s",
        type=_finite("--dt-s"),
        help="the node's model step for this run (its step_s parameter; default: the node's own, "
        "1e-06 unless set); a paced run's slots follow it",
    )
    hr.add_argument("--out", help="write the run as a stick-slip-dataset/1 folder")
    _add_json_option(hr, "the run's summary")
    _add_quiet_option(hr)
    hr.set_defaults(func=cmd_hil_run)
    hy = hs.add_parser(
        "replay",
        help="replay a dataset against a model on a node, run by run",
        description="Load a model file (stick-slip-model/1) into a node, drive it with each run's "
        "recorded drive in lock-step, and report the RMS error against the measured positions, "
        "computed as the diagnosis computes its validation error.",
    )
    hy.add_argument("dataset", help="dataset folder (stick-slip-dataset/1)")
    hy.add_argument("--model", required=True, metavar="FILE", help="model file (diagnose --export)")
    hy.add_argument("--url", help="serial node to use (default: start one, --node-link)")
    hy.add_argument(
        "--node-link",
        choices=NODE_LINKS,
        default="tcp",
        help="the node started here (default tcp: the host node; qemu-*: the firmware)",
    )
    hy.add_argument(
        "--runs",
        nargs="+",
        metavar="ID",
        help="replay these runs only ('validation': the model's validation runs)",
    )
    hy.add_argument("--report", metavar="DIR", help="write report.md and a figure per run into DIR")
    _add_json_option(hy, "the replay's figures")
    _add_quiet_option(hy)
    hy.set_defaults(func=cmd_hil_replay)
    hp = hs.add_parser(
        "position",
        help="closed-loop positioning to a target through a node",
        description="Coarse stick-slip steps toward the target, then fine positioning "
        "within one piezo stroke, on the slider-position feedback (lock-step).",
    )
    hp.add_argument(
        "--target-m",
        type=_finite("--target-m"),
        required=True,
        help="target, relative to the start (m)",
    )
    hp.add_argument("--tolerance-m", type=_finite("--tolerance-m"), default=5e-9)
    hp.add_argument(
        "--max-time-s", type=_finite("--max-time-s"), default=0.2, help="model time limit"
    )
    hp.add_argument("--url", help="serial node to use (default: start one)")
    _add_json_option(hp, "the result")
    hp.set_defaults(func=cmd_hil_position)
    hq = hs.add_parser(
        "firmware-q",
        help="run the fixed-point firmware in QEMU and check its staircase against the host",
        description="Boot the fixed-point firmware image in qemu-system-arm: it plays the paper's "
        "drive and sends the staircase over its UART, compared integer for integer with the "
        "host's fixed-point core.",
    )
    hq.add_argument(
        "--preset", choices=("cortex-m0plus", "cortex-m3", "cortex-m4f"), default="cortex-m0plus"
    )
    _add_json_option(hq, "the staircase and the comparison")
    _add_quiet_option(hq)
    hq.set_defaults(func=cmd_hil_firmware_q)
    return p


def main(argv: list[str] | None = None) -> int:
    p = build_parser()
    a = p.parse_args(argv)
    try:
        return a.func(a)
    except CliError as e:
        print(f"stickslip {a.command}: {e}", file=sys.stderr)
        return 2
    except (ValueError, OSError, RuntimeError) as e:  # the message says what and where
        print(f"stickslip {a.command}: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
