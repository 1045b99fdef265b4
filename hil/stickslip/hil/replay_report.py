"""The replay's report (stickslip hil replay --report DIR): report.md with the error of every run
beside the diagnosis' figure, and for each run a figure of the measured positions, the node's,
and their difference (positions_<run>.png)."""

from __future__ import annotations

import re
from pathlib import Path

from .replay import ReplayedRun


def _nm(v: float | None) -> str:
    return "-" if v is None else f"{v * 1e9:.3f} nm"


def _figure_name(run_id: str) -> str:
    return "positions_" + re.sub(r"[^A-Za-z0-9_.-]", "_", run_id) + ".png"


def _plot(run: ReplayedRun, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5), sharex=True, height_ratios=(2, 1))
    t_ms = (run.t_s - run.t_s[0]) * 1e3
    top.plot(t_ms, run.measured_m * 1e6, lw=1.0, label="measured")
    top.plot(t_ms, run.node_m * 1e6, lw=0.8, ls="--", label="node")
    top.set_ylabel("slider position (um)")
    top.set_title(f"{run.id}: {_nm(run.rmse_m)} RMS over {run.rows} samples")
    top.legend(loc="best")
    bottom.plot(t_ms, (run.node_m - run.measured_m) * 1e9, lw=0.6, color="C3")
    bottom.set_ylabel("node - measured (nm)")
    bottom.set_xlabel("time (ms)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write_report(figures: dict, runs: list[ReplayedRun], out_dir: str | Path) -> Path:
    """Write report.md and one figure per run into out_dir; returns report.md's path."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    m, node = figures["model"], figures["node"]
    val_ids = set(m["source"].get("validation_runs") or [])
    causes = f", causes {', '.join(m['causes'])}" if m["causes"] else ""
    lines = [
        "# Replay of a measurement against its model",
        "",
        f"Model: {m['law']} friction{causes}; node: {node['model']} ({node['variant']}) at "
        f"{node['url']}.",
        "",
        "| run | RMS error | samples | validation run |",
        "|---|---|---|---|",
    ]
    for r in runs:
        used = "yes" if r.id in val_ids else ""
        lines.append(f"| {r.id} | {_nm(r.rmse_m)} | {r.rows} | {used} |")
    lines += [
        "",
        f"All runs: {_nm(figures['rmse_m'])} RMS.",
    ]
    if figures["validation_rmse_m"] is not None:
        lines.append(
            f"Validation runs: {_nm(figures['validation_rmse_m'])} RMS; the diagnosis said "
            f"{_nm(figures['diagnosis_validation_rmse_m'])}."
        )
    lines.append("")
    for r in runs:
        name = _figure_name(r.id)
        _plot(r, out / name)
        lines += [f"![{r.id}]({name})", ""]
    path = out / "report.md"
    path.write_text("\n".join(lines))
    return path
