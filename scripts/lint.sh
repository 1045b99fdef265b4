#!/usr/bin/env bash
# Static checks: clang-format, cppcheck and clang-tidy on the C code; ruff and mypy on Python.
# Needs the dev tools (bash scripts/setup.sh --dev) and build/host/compile_commands.json.
set -euo pipefail
cd "$(dirname "$0")/.."
C_FILES=$(git ls-files 'lib/*.c' 'lib/*.h' 'proto/*.c' 'proto/*.h' 'app/*.c' 'app/*.h' 'host_sim/*.c' 'port/*.c' \
  'port/*.h' 'fw/*.c' 'fw/*.h' 'tests/c/*.c' 'tests/c/*.h' 'bench/*.c')
C_SOURCES=$(git ls-files 'lib/src/*.c' 'proto/src/*.c' 'app/*.c' 'host_sim/*.c' 'port/*.c' | grep -v '^port/cortex_m/')
FW_SOURCES=$(git ls-files 'port/cortex_m/*.c' 'fw/*.c')

echo "lint: include layers"
bash scripts/check_layers.sh

echo "lint: clang-format"
clang-format --dry-run --Werror $C_FILES
echo "lint: cppcheck"
# -U: the node core's compiled-in model header is a build option, not a configuration to check
cppcheck --enable=warning,style,performance,portability --std=c99 --inline-suppr --error-exitcode=1 -q \
  -USS_MODEL_HEADER -I lib/include -I proto/include -I app -I port/posix -I port/cortex_m -I fw $C_SOURCES $FW_SOURCES
echo "lint: clang-tidy"
# (the shared library's GCC link-time-optimisation flags mean nothing to clang: not a finding)
clang-tidy -p build/host --quiet --extra-arg=-Wno-ignored-optimization-argument $C_SOURCES 2>/dev/null
if [ -f build/cortex-m4f/compile_commands.json ]; then
  echo "lint: clang-tidy (Cortex-M4F firmware)"
  clang-tidy -p build/cortex-m4f --quiet --extra-arg=--target=arm-none-eabi \
    --extra-arg=-isystem/usr/lib/arm-none-eabi/include $FW_SOURCES 2>/dev/null
fi
echo "lint: ruff"
.venv/bin/ruff check hil tests bench
.venv/bin/ruff format --check hil tests bench
echo "lint: mypy"
.venv/bin/mypy hil/stickslip
echo "lint: clean"
