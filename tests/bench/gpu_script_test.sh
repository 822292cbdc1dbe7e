#!/usr/bin/env bash
# The GPU measurement script (bench/gpu/) run here on llvmpipe, so that it cannot rot before a
# device runs it: pack.sh makes the folder (under 60 MiB) from this build, run.sh --quick
# unpacks it into a temporary directory and runs every step with EGL surfaceless (Mesa), and
# each output must be the JSON the step documents. Usage: gpu_script_test.sh BUILD_DIR
set -euo pipefail
build=${1:?usage: gpu_script_test.sh BUILD_DIR}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash "$root/bench/gpu/pack.sh" "$build" "$tmp/pack"
# What the device gets: only the pack folder (no build tree, no Debian packages beside it).
(cd "$tmp" && bash "$tmp/pack/run.sh" "$tmp/pack" "$tmp/out" --backend egl-surfaceless --quick)
python3 - "$tmp/out" <<'PY'
import json, sys, pathlib
out = pathlib.Path(sys.argv[1])
s = json.loads((out / "summary.json").read_text())
assert s["ok"] == 1, s
for step in ("gl", "render", "ids", "http"):
    assert s["steps"][step]["exit"] == 0, (step, s)
assert "llvmpipe" in s["renderer"].lower() or s["renderer"], s
render = json.loads((out / "render.json").read_text())
assert render["sizes"], render
ids = json.loads((out / "ids.json").read_text())
text = json.dumps(ids)
assert "pixel_mask" in text and "accuracy" in text, text[:500]
http = json.loads((out / "http.json").read_text())
r = http["results"][0]
assert r["perspective_jpeg_1024"] and r["section_jpeg_1024"] and r["tile_cached"], r
print("gpu_script: ok,", s["renderer"], {k: v["seconds"] for k, v in s["steps"].items()})
PY
