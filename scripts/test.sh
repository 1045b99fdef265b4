#!/usr/bin/env bash
# All the tests: set up (with the analysers), static checks, the C unit tests on the host build,
# under AddressSanitizer + UndefinedBehaviorSanitizer and with coverage, then the Python tests
# under coverage. Prints both coverage summaries.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --dev
bash scripts/lint.sh
ctest --preset host
cmake --preset asan >/dev/null
cmake --build --preset asan
ctest --preset asan
cmake --preset coverage >/dev/null
cmake --build --preset coverage
find build/coverage -name '*.gcda' -delete
ctest --preset coverage
echo "C coverage of lib/, proto/, app/ and port/ (the cmocka tests):"
.venv/bin/gcovr -r . --filter 'lib/' --filter 'proto/' --filter 'app/' --filter 'port/' build/coverage --merge-mode-functions=separate --txt-metric line --print-summary | tail -16
rm -f .coverage .coverage.*
# a representative subset of the hidden-effect diagnoses: the others are marked full (pytest -m full)
.venv/bin/python -m coverage run -m pytest -q --durations=25 -m "not full" tests/python
.venv/bin/python -m coverage combine -q
echo "Python coverage of the stickslip package (pytest, worker processes included):"
.venv/bin/python -m coverage report --skip-empty
