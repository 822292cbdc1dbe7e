#!/usr/bin/env bash
# bench/gpu/run.sh PACK_DIR OUT_DIR [--backend egl-device] [--expect NVIDIA] [--sizes L1,L2,L3,L4]
#                  [--quick]
# One call measures everything on a machine with a GPU, from the folder bench/gpu/pack.sh
# made (nothing else of this project needs to be installed there; bash, tar and xz do):
#   gl.json      the GL context: renderer and version strings; with --expect TEXT the run
#                stops (exit 1) unless the renderer names TEXT (e.g. NVIDIA: the EGL device is
#                the GPU, not a software fallback)
#   render.json  bench_render: profile and perspective views at 1024x1024 and 1920x1080,
#                the plain draw the paper's pixel mask is measured against, clip distance
#                against fragment discard, level of detail (bench/render.cpp)
#   ids.json     bench_table1 with GL: the pixel-mask profile's record ids against the exact
#                point classifier at every pixel centre (accuracy "all" and "boundary"), and
#                the exact engine's times beside it (bench/table1/table1.cpp)
#   http.json    bench_http: the server with --gl BACKEND under load from keep-alive clients:
#                exact sections, perspective views on the GL workers, tiles, queries
#   summary.json per step: exit status, seconds; the machine: cores, load, date
# Every step has a time limit; the whole run stays within 5 minutes on the device. --quick:
# small models and short runs (the CI runs it so on llvmpipe with --backend egl-surfaceless,
# so that the script cannot rot). Exit 1 when a step failed.
set -uo pipefail
pack=${1:?usage: run.sh PACK_DIR OUT_DIR [--backend B] [--expect TEXT] [--sizes S] [--quick]}
out=${2:?usage: run.sh PACK_DIR OUT_DIR [--backend B] [--expect TEXT] [--sizes S] [--quick]}
shift 2
backend=egl-device expect="" sizes=L1,L2,L3,L4 quick=0
while (($#)); do
  case $1 in
    --backend) backend=$2; shift 2 ;;
    --expect) expect=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    *) echo "run.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar -C "$work" -xJf "$pack/geoslice-gpu.tar.xz" || { echo "run.sh: cannot unpack $pack/geoslice-gpu.tar.xz" >&2; exit 1; }
export LD_LIBRARY_PATH="$work/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PROJ_DATA="$work/share/proj" PROJ_LIB="$work/share/proj" PROJ_NETWORK=OFF
bin=$work/bin
if ((quick)); then
  rsizes=20000 isizes=20000 hsizes=20000 runs=1 planes=2 secs=1 res=256x256,320x200
else
  rsizes=$sizes isizes=L1,L2 hsizes=L1 runs=5 planes=5 secs=3 res=1024x1024,1920x1080
fi
failed=0
steps=""
step() {  # step NAME LIMIT_S COMMAND...: stdout to NAME.json, stderr to NAME.log
  local name=$1 limit=$2
  shift 2
  local t0=$SECONDS
  timeout "$limit" "$@" > "$out/$name.json" 2> "$out/$name.log"
  local rc=$?
  ((rc == 0)) || { failed=1; echo "run.sh: $name failed (exit $rc): $(tail -3 "$out/$name.log")" >&2; }
  steps+="${steps:+, }\"$name\": {\"exit\": $rc, \"seconds\": $((SECONDS - t0))}"
  return $rc
}
step gl 60 "$bin/bench_render" --backends "$backend" --sizes 2000 --resolutions 64x64 --runs 1
renderer=$(grep -o '"renderer": *"[^"]*"' "$out/gl.json" | head -1 | sed 's/.*: *"//; s/"$//')
echo "run.sh: $backend renderer: ${renderer:-none}" >&2
if [[ -n $expect && $renderer != *"$expect"* ]]; then
  echo "run.sh: the $backend renderer is '${renderer:-none}', not $expect: stopping" >&2
  failed=1
else
  step render 150 "$bin/bench_render" --backends "$backend" --sizes "$rsizes" --resolutions "$res" --runs "$runs"
  step ids 90 "$bin/bench_table1" --out "$work/table1" --sizes "$isizes" --planes "$planes" --gl "$backend" \
    --image 1024 --oracle 256 --octree-depths 6,6,6,6 --brute-queries 0
  step http 60 "$bin/bench_http" --sizes "$hsizes" --seconds "$secs" --connections 8 --gl "$backend"
fi
cat > "$out/summary.json" <<JSON
{"backend": "$backend", "renderer": "${renderer}", "quick": $quick, "cores": $(nproc),
 "load": "$(cut -d' ' -f1-3 /proc/loadavg)", "date": "$(date -u +%FT%TZ)", "steps": {$steps}, "ok": $((1 - failed))}
JSON
cat "$out/summary.json"
exit $failed
