#!/usr/bin/env bash
# The include rule of docs/architecture.md: a module includes headers of the modules below it in
# its row and its own, never one above. A quoted include names a project header; its module is
# the top folder it lives in (proto/include/ss_port.h is proto's). System headers (<...>) are the
# compiler's business.
#   bash scripts/check_layers.sh     (scripts/lint.sh runs it)
set -euo pipefail
cd "$(dirname "$0")/.."
declare -A may=(
  [lib]="lib"
  [proto]="proto"
  [app]="lib proto app"
  [port]="proto port"
  [host_sim]="lib proto app port host_sim"
  [fw]="lib proto app port fw"
)
declare -A home
while read -r h; do
  home[$(basename "$h")]=${h%%/*}
done < <(git ls-files 'lib/*.h' 'proto/*.h' 'app/*.h' 'app/*.def' 'port/*.h' 'host_sim/*.h' 'fw/*.h')
bad=0
for mod in "${!may[@]}"; do
  while read -r f; do
    while read -r inc; do
      to=${home[$inc]:-}
      if [ -z "$to" ]; then
        echo "check_layers: $f includes \"$inc\", which no module holds"
        bad=1
      elif [[ " ${may[$mod]} " != *" $to "* ]]; then
        echo "check_layers: $f ($mod) includes \"$inc\" ($to): $mod may include only ${may[$mod]}"
        bad=1
      fi
    done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$f")
  done < <(git ls-files "$mod/*.c" "$mod/*.h" "$mod/*.def")
done
[ "$bad" -eq 0 ] && echo "check_layers: every include runs down the layers"
exit "$bad"
