#!/usr/bin/env bash
# Builds geoslice and runs it on the built-in demo model: a synthetic silica-sandstone
# mine placed at CGCS2000 Gauss-Kruger zone 35 (EPSG:4523) in Sichuan.
# (Until the HTTP server lands, this describes and probes the demo model instead of serving it.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target geoslice
mkdir -p out
./build/cli/geoslice generate --triangles 200000 --crs EPSG:4523 --at 105.05,30.62 --out out/demo.glb
./build/cli/geoslice info out/demo.glb
echo "35500000 3388620 700" | ./build/cli/geoslice coords --from EPSG:4523 --to EPSG:4490
