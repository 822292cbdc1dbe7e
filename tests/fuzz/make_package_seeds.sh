#!/usr/bin/env bash
# Writes the fuzz_package seed corpus (tests/fuzz/corpus/package/) from a real package of the
# current format: a unit cube (12 triangles, local CRS) baked by `geoslice bake` into an 8x8
# texture, then laid out as fuzz_package.cpp reads one input (flags byte, then manifest.json,
# mesh.glb and ids.r32ui.zst each prefixed by a little-endian uint32 length, then
# attributes.json). box_checked.bin has the checksum flag on, box_unchecked.bin off.
# Run it again whenever the package format version changes:
#   bash tests/fuzz/make_package_seeds.sh build/cli/geoslice
set -euo pipefail
bin=${1:-build/cli/geoslice}
out=$(cd "$(dirname "$0")" && pwd)/corpus/package
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat >"$tmp/seed.obj" <<'OBJ'
o seed
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
OBJ
"$bin" bake "$tmp/seed.obj" --crs local --size 8 --out "$tmp/pkg" >/dev/null 2>&1
mkdir -p "$out"
python3 - "$tmp/pkg" "$out" <<'PY'
import struct, sys
pkg, out = sys.argv[1], sys.argv[2]
read = lambda name: open(f"{pkg}/{name}", "rb").read()
body = b"".join(struct.pack("<I", len(b)) + b for b in (read("manifest.json"), read("mesh.glb"), read("ids.r32ui.zst")))
body += read("attributes.json")
for flag, name in ((1, "box_checked.bin"), (0, "box_unchecked.bin")):
    open(f"{out}/{name}", "wb").write(bytes([flag]) + body)
PY
echo "wrote $out/box_checked.bin, $out/box_unchecked.bin"
