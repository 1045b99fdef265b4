#!/usr/bin/env bash
# Do what a new user does: clone the repository into an empty folder, run the README's two
# commands exactly as written there, and check that they succeed and leave what they promise.
#   bash scripts/fresh_clone_check.sh [REPO]     (default: this checkout's committed HEAD)
set -euo pipefail
repo="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
git clone -q "$repo" "$work/stickslip"
cd "$work/stickslip"
# the first fenced block of the README holds the two commands
mapfile -t cmds < <(awk '/^```/{n++; next} n==1' README.md | sed 's/[[:space:]]*#.*$//' | grep -v '^[[:space:]]*$')
[ "${#cmds[@]}" -eq 2 ] || { echo "fresh-clone: expected 2 commands in the README, found ${#cmds[@]}" >&2; exit 1; }
for c in "${cmds[@]}"; do
  echo "fresh-clone: \$ $c"
  start=$(date +%s)
  bash -c "$c" > "$work/log.txt" 2>&1 || { tail -40 "$work/log.txt"; echo "fresh-clone: FAILED: $c" >&2; exit 1; }
  echo "fresh-clone: ok in $(( $(date +%s) - start )) s"
done
for f in out/figures/fig03_stribeck.png out/figures/fig13_actuator.png out/figures/figures.json out/staircase.csv; do
  [ -s "$f" ] || { echo "fresh-clone: the demo did not write $f" >&2; exit 1; }
done
echo "fresh-clone: both README commands work on a fresh clone"
