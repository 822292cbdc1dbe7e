#!/usr/bin/env bash
# Runs one libFuzzer target (clang, ASan+UBSan) on a copy of its seed corpus.
# Usage: bash scripts/fuzz.sh tsurf|gocad|obj|geo3dml|gltf|vtu|stl|ply|dxf|surpac|drillholes|package|request|request_whole|http|server [seconds=60]
# Crashes are written to build-fuzz/crash-*; replay one with: build-fuzz/tests/fuzz/fuzz_<name> FILE
set -euo pipefail
cd "$(dirname "$0")/.."
name=${1:?usage: scripts/fuzz.sh tsurf|gocad|obj|geo3dml|gltf|vtu|stl|ply|dxf|surpac|drillholes|package|request|request_whole|http|server [seconds]}
seconds=${2:-60}
[ -d "tests/fuzz/corpus/$name" ] || { echo "no corpus tests/fuzz/corpus/$name" >&2; exit 2; }
bash scripts/install-deps.sh
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DGEOSLICE_FUZZ=ON -DGEOSLICE_TESTS=OFF -DGEOSLICE_BENCH=OFF >/dev/null
cmake --build build-fuzz --target "fuzz_$name"
work=build-fuzz/corpus-$name
mkdir -p "$work"
cp -n tests/fuzz/corpus/"$name"/* "$work"/ 2>/dev/null || true
cd build-fuzz
# fontconfig's process-lifetime caches are not leaks of ours (tests/fuzz/lsan.supp).
export LSAN_OPTIONS="suppressions=$(cd .. && pwd)/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
"./tests/fuzz/fuzz_$name" -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=262144 "corpus-$name"
