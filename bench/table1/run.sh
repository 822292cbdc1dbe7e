#!/usr/bin/env bash
# The paper's Table 1, reproduced on this machine with the peers (one command):
#   bash bench/table1/run.sh [OUT_DIR]
# Environment: SIZES (default L1,L2,L3,L4), PLANES (20), BUILD (build), GL (egl-surfaceless;
# "none" skips the pixel mask), VTK_THREADS (2), VTK_CUTTER_BUDGET_S (120: vtkCutter is
# O(N) per plane, so it stops after this many seconds per model), KEEP_PLY=1 keeps the
# exported meshes.
# Needs the benchmark packages of scripts/install-deps.sh (python3-vtk9, libcgal-dev,
# python3-matplotlib); a peer whose package is missing is skipped and the report says so.
# Writes OUT_DIR (default BUILD/table1): geoslice.json, <size>.{vtk,cgal,geoslice}.json,
# table1.json, table1.md, table1.png.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD:-$root/build}
out=${1:-$build/table1}
sizes=${SIZES:-L1,L2,L3,L4}
planes=${PLANES:-20}
mkdir -p "$out"

peers=OFF
if [ -f /usr/include/CGAL/Polygon_mesh_slicer.h ]; then peers=ON; fi
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGEOSLICE_BENCH_PEERS=$peers >/dev/null
targets=(bench_table1)
[ "$peers" = ON ] && targets+=(bench_table1_cgal)
cmake --build "$build" --target "${targets[@]}"

uptime | tee "$out/uptime_start.txt"
"$build/bench/bench_table1" --out "$out" --sizes "$sizes" --planes "$planes" --gl "${GL:-egl-surfaceless}" \
  >"$out/geoslice.json"
have_vtk=0
/usr/bin/python3 -c 'import vtkmodules.vtkFiltersCore' 2>/dev/null && have_vtk=1
for s in ${sizes//,/ }; do
  if [ $have_vtk = 1 ]; then
    echo "table1: VTK $s" >&2
    /usr/bin/python3 "$root/bench/table1/vtk_peer.py" "$out/$s.ply" "$out/$s.planes.json" "$out/$s.vtk.json" \
      --threads "${VTK_THREADS:-2}" --cutter-budget-s "${VTK_CUTTER_BUDGET_S:-120}"
  fi
  if [ "$peers" = ON ]; then
    echo "table1: CGAL $s" >&2
    "$build/bench/bench_table1_cgal" "$out/$s.ply" "$out/$s.planes.json" "$out/$s.cgal.json"
  fi
  [ "${KEEP_PLY:-0}" = 1 ] || rm -f "$out/$s.ply"
done
{ echo "start: $(cat "$out/uptime_start.txt")"; echo "end: $(uptime)"; echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"; } >"$out/uptime.txt"
/usr/bin/python3 "$root/bench/table1/report.py" "$out"
