#!/usr/bin/env bash
# Set up a fresh Debian machine for stickslip: system packages, the Python virtual environment
# at .venv (with the `stickslip` command and the C library built into it), and the host build.
# Idempotent: re-running only does what is missing.
#   --dev   also what the tests need beyond the demo: the analysers (clang-format, clang-tidy,
#           cppcheck), and the Cortex-M cross toolchain and QEMU for the firmware tests
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES=(cmake ninja-build gcc libc6-dev libcmocka-dev pkg-config)
if [ "${1:-}" = "--dev" ]; then
  APT_PACKAGES+=(clang-format clang-tidy cppcheck gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm)
fi
if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
  APT_PACKAGES+=(python3 python3-venv)
fi
missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing system packages: ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    SUDO="sudo"
  fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv"
  python3 -m venv .venv
fi
# The package build compiles lib/ with CMake (scikit-build-core) into the installed package.
echo "setup: installing the stickslip package into .venv"
.venv/bin/pip install -q --disable-pip-version-check ".[test]"

echo "setup: building the C library, host simulator and C tests (build/host)"
cmake --preset host >/dev/null
cmake --build --preset host
if [ "${1:-}" = "--dev" ]; then
  # every preset builds the node images (stickslip_fw.elf on the M4F and M3, stickslip_fw_q.elf,
  # the fixed-point node, on all three); cortex-m0plus checks its q-only images for float helpers
  echo "setup: building the firmware (build/cortex-m4f, build/cortex-m3, build/cortex-m0plus)"
  for preset in cortex-m4f cortex-m3 cortex-m0plus; do
    cmake --preset "$preset" >/dev/null
    cmake --build --preset "$preset"
  done
fi
