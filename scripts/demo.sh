#!/usr/bin/env bash
# Builds geoslice and runs it on the built-in demo model: a synthetic silica-sandstone
# mine placed at CGCS2000 Gauss-Kruger zone 35 (EPSG:4523) in Sichuan.
# (Until the HTTP server lands, this describes the demo model, converts a point and cuts a
# section, instead of serving it.)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target geoslice
mkdir -p out
./build/cli/geoslice generate --triangles 200000 --crs EPSG:4523 --at 105.05,30.62 --out out/demo.glb
./build/cli/geoslice info out/demo.glb
echo "35500000 3388620 700" | ./build/cli/geoslice coords --from EPSG:4523 --to EPSG:4490
# The east-west section through the model centre (northing 3388846 m), kept side y >= it:
# once exactly on the CPU, once through headless GL (llvmpipe or a GPU through EGL).
./build/cli/geoslice section out/demo.glb --plane 0,1,0,-3388846 --size 1024x512 --out out/section.ppm --out out/section_ids.pgm --areas > out/section_areas.json
./build/cli/geoslice render out/demo.glb --plane 0,1,0,-3388846 --size 1024x512 --out out/render.png --ids out/render_ids.pgm
echo "wrote out/section.ppm, out/section_ids.pgm, out/section_areas.json, out/render.png, out/render_ids.pgm"
