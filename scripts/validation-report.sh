#!/usr/bin/env bash
# Builds, runs every validation study (ctest label `validation`) and writes
# validation/REPORT.md with its figures in validation/figures/. The report is
# written even when a study misses its tolerance (it says which); the exit
# status is then ctest's.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset ci
cmake --build --preset ci
status=0
ctest --test-dir build-ci -L validation --output-on-failure || status=$?
/usr/bin/python3 validation/report.py build-ci/validation validation
exit "$status"
