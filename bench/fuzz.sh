#!/usr/bin/env bash
# Fuzz the link parsers (serial frames, the node behind them, SLCAN, the CAN node) with libFuzzer
# under ASan + UBSan for a bounded time, seeded with the shared protocol vectors.
#   bash bench/fuzz.sh [SECONDS]        (default 60; needs clang-14 and libclang-rt-14-dev)
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
out=build/fuzz
mkdir -p "$out/corpus" "$out/crashes"
CC=${CC:-clang-14}
$CC -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -D_DEFAULT_SOURCE \
  -Ilib/include -Iproto/include -Iapp bench/fuzz/fuzz_parsers.c app/ss_node_core.c app/ss_node_serial.c \
  app/ss_node_can.c app/ss_node_model_f32.c proto/src/*.c lib/src/*.c -lm \
  -o "$out/fuzz_parsers"
# seeds: every frame of the shared vectors, and SLCAN lines
i=0
while IFS=, read -r t s p w; do
  [[ "$t" == \#* ]] && continue
  echo -n "$w" | xxd -r -p > "$out/corpus/frame_$i"; i=$((i + 1))
done < tests/vectors/proto_frames.csv
printf 'C\rS8\rO\rt1108000048410301\rt100803070500000000\r' > "$out/corpus/slcan_0"
"$out/fuzz_parsers" -max_total_time="$secs" -print_final_stats=1 -artifact_prefix="$out/crashes/" \
  "$out/corpus" 2>&1 | tee "$out/fuzz.log" | grep -E "^#[0-9]+ +(DONE|pulse)|stat::|ERROR|SUMMARY" || true
crashes=$(find "$out/crashes" -type f | wc -l)
execs=$(grep -oE "stat::number_of_executed_units: [0-9]+" "$out/fuzz.log" | grep -oE "[0-9]+$" || echo 0)
echo "fuzz: $execs executions in $secs s, $crashes findings (artifacts in $out/crashes)"
[ "$crashes" -eq 0 ]
