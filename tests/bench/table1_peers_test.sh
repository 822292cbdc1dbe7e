#!/usr/bin/env bash
# bench/table1 end to end on a small generated model (20k triangles, 3 planes, no GL): the
# export, the VTK peer (python3-vtk9), the CGAL peer when it was built
# (-DGEOSLICE_BENCH_PEERS=ON) and report.py, which exits 1 when a peer's segment counts,
# lengths or loop areas disagree with geoslice's (tolerances in report.py).
# usage: table1_peers_test.sh BENCH_TABLE1 [BENCH_TABLE1_CGAL]
set -euo pipefail
here=$(cd "$(dirname "$0")/../../bench/table1" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$1" --out "$out" --sizes 20000 --planes 3 --gl none --octree-depths 6 >"$out/geoslice.json"
/usr/bin/python3 "$here/vtk_peer.py" "$out/20000.ply" "$out/20000.planes.json" "$out/20000.vtk.json" --threads 1
if [ -n "${2:-}" ] && [ -x "$2" ]; then
  "$2" "$out/20000.ply" "$out/20000.planes.json" "$out/20000.cgal.json"
fi
/usr/bin/python3 "$here/report.py" "$out" >/dev/null
grep -q '| vtk_cutter/20000 | 3 | 3 |' "$out/table1.md"
grep -q '| vtk_plane_cutter/20000 | 3 | 3 |' "$out/table1.md"
test -s "$out/table1.png"
echo "table1 peers agree"
