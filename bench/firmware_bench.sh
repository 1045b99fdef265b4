#!/usr/bin/env bash
# Firmware figures (BENCHMARKS.md): flash and RAM per target (arm-none-eabi-size), and
# instructions per actuator step on the emulated Cortex-M (QEMU -icount shift=0: one instruction
# per ns of virtual time; SysTick on the 25 MHz MPS2 clock resolves 40 instructions).
#   bash bench/firmware_bench.sh     (after bash scripts/setup.sh --dev)
set -euo pipefail
cd "$(dirname "$0")/.."
for t in "cortex-m4f mps2-an386" "cortex-m3 mps2-an385"; do
  set -- $t
  cmake --preset "$1" >/dev/null
  cmake --build --preset "$1" >/dev/null
  echo "== $1 ($2)"
  arm-none-eabi-size build/"$1"/port/cortex_m/stickslip_fw.elf | sed 's/^/   /'
  arm-none-eabi-size build/"$1"/lib/libstickslip.a | awk 'NR > 1 {t += $1; d += $2; b += $3}
    END {printf "   libstickslip.a, all modules (before --gc-sections): text %d, data %d, bss %d bytes\n", t, d, b}'
  timeout 300 qemu-system-arm -M "$2" -nographic -monitor none -icount shift=0 \
    -semihosting-config enable=on,target=native -serial stdio \
    -kernel build/"$1"/port/cortex_m/stickslip_bench_fw.elf | sed 's/^/   /'
done
