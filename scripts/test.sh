#!/usr/bin/env bash
# All the tests: set up (with the analysers), static checks, the C unit tests on the host build
# and under AddressSanitizer + UndefinedBehaviorSanitizer, then the Python tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --dev
bash scripts/lint.sh
ctest --preset host
cmake --preset asan >/dev/null
cmake --build --preset asan
ctest --preset asan
.venv/bin/python -m pytest -q tests/python
