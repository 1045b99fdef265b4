"""Two runs of bench/diagnosis_cost.py side by side, diagnosis by diagnosis: did each take the same
path (the same answer and the same model steps: a change that keeps the float core's bits and the
search's decisions must), what it cost in model steps (deterministic) and in wall time (the
machine's noise included), and the totals a BENCHMARKS.md entry quotes (hits, diagnoses under
60 s, median and longest wall time).

    .venv/bin/python bench/diagnosis_compare.py BEFORE.jsonl AFTER.jsonl [--limit-s 60]

Diagnoses in only one file are listed and left out of the comparison; either file may be partial
(a run stopped part way).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path


def load(path: Path) -> dict[tuple[str, int], dict]:
    rows = {}
    for n, line in enumerate(path.read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            d = json.loads(line)
            rows[(d["case"], int(d["seed"]))] = d
        except (ValueError, KeyError, TypeError) as e:
            raise SystemExit(f"{path}:{n}: not a diagnosis_cost.py line ({e})") from None
    return rows


def summary(rows: list[dict], limit_s: float) -> str:
    walls = [d["wall_s"] for d in rows]
    return (
        f"{sum(d['hit'] for d in rows)} / {len(rows)} hits, {sum(w < limit_s for w in walls)} / "
        f"{len(rows)} under {limit_s:g} s, median {statistics.median(walls):.1f} s, longest "
        f"{max(walls):.1f} s, {sum(d['msteps'] for d in rows):.0f} M model steps"
    )


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--limit-s", type=float, default=60.0)
    a = ap.parse_args()
    before, after = load(a.before), load(a.after)
    both = [k for k in after if k in before]
    for name, rows, other in (("first", before, after), ("second", after, before)):
        alone = sorted(k for k in rows if k not in other)
        if alone:
            listed = ", ".join(f"{c} {s}" for c, s in alone[:3])
            listed += ", ..." if len(alone) > 3 else ""
            print(f"{len(alone)} diagnoses only in the {name} file ({listed})")
    if not both:
        print("no diagnosis in both files")
        return 1
    moved = 0
    for k in both:
        b, d = before[k], after[k]
        same = b["causes"] == d["causes"] and b["msteps"] == d["msteps"]
        moved += not same
        path = "same path" if same else "MOVED"
        if b["causes"] != d["causes"]:
            path += f" ({'+'.join(b['causes'])} -> {'+'.join(d['causes'])})"
        print(
            f"{k[0][:40]:40s} {k[1]}  {path:12s} steps {b['msteps']:7.0f} -> {d['msteps']:7.0f} M "
            f"({100 * (d['msteps'] / b['msteps'] - 1):+5.1f} %)  wall {b['wall_s']:6.1f} -> "
            f"{d['wall_s']:6.1f} s"
        )
    print(f"\nbefore: {summary([before[k] for k in both], a.limit_s)}")
    print(f"after:  {summary([after[k] for k in both], a.limit_s)}")
    print(f"{moved} of {len(both)} diagnoses took another path")
    return 0


if __name__ == "__main__":
    sys.exit(main())
