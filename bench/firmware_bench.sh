#!/usr/bin/env bash
# Firmware figures (BENCHMARKS.md): flash and RAM per target (arm-none-eabi-size), and
# instructions per actuator step on the emulated Cortex-M (QEMU -icount shift=0: one instruction
# per ns of virtual time; SysTick on the 25 MHz MPS2 clock resolves 40 instructions), for the
# float32 node image (M4F, M3) and the fixed-point images (every target; the M0+ runs on the an385).
#   bash bench/firmware_bench.sh     (after bash scripts/setup.sh --dev)
set -euo pipefail
cd "$(dirname "$0")/.."
lib_size() { # text, data, bss summed over a static library's modules
  arm-none-eabi-size "$1" | awk -v name="$(basename "$1")" 'NR > 1 {t += $1; d += $2; b += $3}
    END {printf "   %s, all modules (before --gc-sections): text %d, data %d, bss %d bytes\n", name, t, d, b}'
}
bench() { # board, image: the image's lines
  timeout 300 qemu-system-arm -M "$1" -nographic -monitor none -icount shift=0 \
    -semihosting-config enable=on,target=native -serial stdio -kernel "$2" </dev/null | sed 's/^/   /'
}
for t in "cortex-m4f mps2-an386" "cortex-m3 mps2-an385" "cortex-m0plus mps2-an385"; do
  set -- $t
  fw=build/"$1"/fw
  cmake --preset "$1" >/dev/null
  cmake --build --preset "$1" >/dev/null
  echo "== $1 ($2)"
  if [ "$1" != cortex-m0plus ]; then # the q-only preset builds no float image
    arm-none-eabi-size "$fw"/stickslip_fw.elf | sed 's/^/   /'
    lib_size build/"$1"/lib/libstickslip.a
    bench "$2" "$fw"/stickslip_bench_fw.elf
  fi
  arm-none-eabi-size "$fw"/stickslip_q_fw.elf | sed 1d | sed 's/^/   /'
  lib_size build/"$1"/lib/libstickslip_q.a
  bench "$2" "$fw"/stickslip_q_bench_fw.elf
done
