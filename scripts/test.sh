#!/usr/bin/env bash
# All the tests: set up, then the C unit tests (ctest) and the Python tests (pytest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --preset host
.venv/bin/python -m pytest -q tests/python
