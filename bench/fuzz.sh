#!/usr/bin/env bash
# Fuzz what takes input from outside with libFuzzer under ASan + UBSan, for a bounded time each:
#   parsers        arbitrary bytes into the serial frame receiver, the node behind its serial link,
#                  the SLCAN decoder and adapter, and the node behind its CAN link
#                  (bench/fuzz/fuzz_parsers.c, seeded with the shared protocol vectors);
#   node_core_f32  the node's requests with any float32 bit pattern as drive, parameter or waveform
#   node_core_q    field, then runs: the model must stay finite (bench/fuzz/fuzz_node_core.c),
#                  for the float32 node and the fixed-point one.
#   bash bench/fuzz.sh [SECONDS] [TARGET...]   (default 60 s, every target; needs clang-14 and
#                                               libclang-rt-14-dev)
#   FUZZ_RUNS=5000000 FUZZ_JOBS=2 bash bench/fuzz.sh 7200 parsers   (2 processes, 5 M executions each)
# Corpora persist in build/fuzz/<target>/corpus; a run fails when any target leaves an artifact.
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(parsers node_core_f32 node_core_q)
CC=${CC:-clang-14}
rt=$($CC -print-resource-dir 2>/dev/null)/lib/linux/libclang_rt.fuzzer-x86_64.a
if ! command -v "$CC" >/dev/null || [ ! -f "$rt" ]; then
  echo "fuzz: needs $CC and libFuzzer: apt-get install clang-14 libclang-rt-14-dev" >&2
  exit 2
fi
flags=(-std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -D_DEFAULT_SOURCE
       -Ilib/include -Iproto/include -Iapp)
status=0
for t in "${targets[@]}"; do
  out=build/fuzz/$t
  mkdir -p "$out/corpus" "$out/crashes"
  case "$t" in
    parsers)
      $CC "${flags[@]}" bench/fuzz/fuzz_parsers.c app/ss_node_core.c app/ss_node_serial.c app/ss_node_can.c \
        app/ss_node_model_f32.c proto/src/*.c lib/src/*.c -lm -o "$out/fuzz"
      # seeds: every frame of the shared vectors, and SLCAN lines
      i=0
      while IFS=, read -r kind _ _ wire; do
        [[ "$kind" == \#* ]] && continue
        echo -n "$wire" | xxd -r -p > "$out/corpus/frame_$i"; i=$((i + 1))
      done < tests/vectors/proto_frames.csv
      printf 'C\rS8\rO\rt1108000048410301\rt100803070500000000\r' > "$out/corpus/slcan_0"
      ;;
    node_core_f32)
      $CC "${flags[@]}" bench/fuzz/fuzz_node_core.c app/ss_node_core.c app/ss_node_model_f32.c \
        proto/src/*.c lib/src/*.c -lm -o "$out/fuzz"
      ;;
    node_core_q)
      $CC "${flags[@]}" -DSS_NODE_MODEL_Q bench/fuzz/fuzz_node_core.c app/ss_node_core.c \
        app/ss_node_model_q.c proto/src/*.c lib/src/*.c -lm -o "$out/fuzz"
      ;;
    *) echo "fuzz: unknown target '$t' (parsers, node_core_f32, node_core_q)" >&2; exit 2 ;;
  esac
  # FUZZ_JOBS processes share the corpus (each its own log, FUZZ_RUNS executions each)
  jobs=${FUZZ_JOBS:-1}
  t0=$(date +%s)
  for ((k = 0; k < jobs; k++)); do
    "$out/fuzz" -max_total_time="$secs" ${FUZZ_RUNS:+-runs=$FUZZ_RUNS} -print_final_stats=1 \
      -artifact_prefix="$out/crashes/" "$out/corpus" > "$out/fuzz.$k.log" 2>&1 &
  done
  wait || true
  cat "$out"/fuzz.*.log > "$out/fuzz.log"
  grep -E "ERROR|SUMMARY|runtime error" "$out/fuzz.log" | head -5 || true
  crashes=$(find "$out/crashes" -type f | wc -l)
  execs=$(grep -oE "stat::number_of_executed_units: [0-9]+" "$out/fuzz.log" | grep -oE "[0-9]+$" | awk '{s += $1} END {print s + 0}')
  line=$(grep -E "^#[0-9]+[[:space:]]+DONE" "$out/fuzz.log" | tail -1 || true)
  echo "fuzz $t: ${execs:-0} executions in $(($(date +%s) - t0)) s ($jobs process(es)), $crashes findings (artifacts in $out/crashes); ${line#*DONE }"
  [ "$crashes" -eq 0 ] || status=1
done
exit $status
