#!/usr/bin/env bash
# Builds geoslice and starts the HTTP section server on the built-in demo model: a
# synthetic silica-sandstone mine at CGCS2000 Gauss-Kruger zone 35 (EPSG:4523) in Sichuan,
# generated in memory at start (about 0.1 s). Port: $PORT or 8080. Ctrl-C stops it.
# Then, from another shell:
#   curl localhost:8080/v1/models
#   curl -o section.jpg 'localhost:8080/v1/models/demo/section.jpg?plane=0,1,0,-3388846&size=1024x512'
#   curl 'localhost:8080/v1/models/demo/query?plane=0,1,0,-3388846&size=1024x512&px=500&py=300'
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target geoslice
# Sections saved from the web client are kept in build/saved-sections (a flag or the
# environment may name another directory).
export GEOSLICE_SECTIONS_DIR="${GEOSLICE_SECTIONS_DIR:-build/saved-sections}"
exec ./build/cli/geoslice serve --port "${PORT:-8080}" "$@"
