#!/usr/bin/env bash
# Builds geoslice with warnings as errors and runs the whole test suite (unit, fuzz
# replay; later gl). Usage: bash scripts/test.sh [extra cmake args, e.g. -DGEOSLICE_SANITIZE=ON]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# tests/web: playwright-core and axe-core at the versions in tests/web/package-lock.json.
(cd tests/web && npm ci --no-audit --no-fund --loglevel=error)
# tests/deploy: the offline Kubernetes schemas (kubernetes-models) in tests/deploy/package-lock.json.
(cd tests/deploy && npm ci --no-audit --no-fund --loglevel=error)
build=${GEOSLICE_BUILD_DIR:-build}
jobs=$(nproc)
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGEOSLICE_WERROR=ON "$@"
cmake --build "$build" -j"$jobs"
ctest --test-dir "$build" --output-on-failure -j"$jobs"
