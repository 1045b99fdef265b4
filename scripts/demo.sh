#!/usr/bin/env bash
# The demo: set up, reproduce the paper's figures, simulate the 4.4 um, 500 Hz staircase (float and
# fixed point), and diagnose the bundled example dataset, which hides a physical effect.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out
.venv/bin/stickslip figures --out out/figures
.venv/bin/stickslip simulate --out out/staircase.csv --json > out/staircase.json
build/host/host_sim/stickslip_sim --scenario paper --model lugre --out out/staircase_lugre.csv
.venv/bin/stickslip simulate --variant q --out out/staircase_q.csv --json > out/staircase_q.json
echo "demo: diagnosing examples/hidden-effect (12 runs; what it hides is in examples/README.md)"
.venv/bin/stickslip diagnose examples/hidden-effect --out out/diagnosis --json out/diagnosis.json \
  --export out/model
# the identified model as the stage's twin: into a node, the validation runs replayed through it
# (the M4F firmware in QEMU when the dev set-up built it, the host node otherwise)
link=tcp
if command -v qemu-system-arm >/dev/null && [ -f build/cortex-m4f/fw/stickslip_fw.elf ]; then
  link=qemu-m4f
fi
echo "demo: replaying the validation runs against the identified model on the $link node"
.venv/bin/stickslip hil replay examples/hidden-effect --model out/model/model.json --runs validation \
  --node-link "$link" --json out/replay.json --report out/replay
echo
echo "demo: figures in out/figures/ (PNG, with the numbers behind them in figures.json)"
echo "demo: the LS staircase in out/staircase.csv, its summary in out/staircase.json:"
.venv/bin/python -c "import json; s = json.load(open('out/staircase.json')); print(f\"  mean step {s['mean_step_per_cycle_m'] * 1e6:.3f} um per cycle over {s['waveform']['cycles']} cycles\")"
.venv/bin/python -c "import json; s = json.load(open('out/staircase_q.json')); print(f\"  fixed point (out/staircase_q.csv): {s['mean_step_per_cycle_m'] * 1e6:.3f} um per cycle\")"
echo "demo: the diagnosis report is out/diagnosis/report.md (plots beside it), its JSON out/diagnosis.json"
echo "demo: the identified model in out/model/ (model.json, stickslip_model.h for firmware); replay figures in out/replay.json, its report in out/replay/report.md"
