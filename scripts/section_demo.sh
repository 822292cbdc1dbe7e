#!/usr/bin/env bash
# The command-line tour (no server): generate the demo mine to out/, describe it, convert
# a point, cut the east-west section exactly on the CPU and through headless GL.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target geoslice
mkdir -p out
./build/cli/geoslice generate --triangles 200000 --crs EPSG:4523 --at 105.05,30.62 --out out/demo.glb
./build/cli/geoslice info out/demo.glb
echo "35500000 3388620 700" | ./build/cli/geoslice coords --from EPSG:4523 --to EPSG:4490
./build/cli/geoslice section out/demo.glb --plane 0,1,0,-3388846 --size 1024x512 --out out/section.png --areas > out/section_areas.json
./build/cli/geoslice render out/demo.glb --plane 0,1,0,-3388846 --size 1024x512 --out out/render.png
./build/cli/geoslice borehole out/demo.glb --x 35504000 --y 3388000
echo "wrote out/section.png, out/section_areas.json, out/render.png"
