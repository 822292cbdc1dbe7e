#!/usr/bin/env bash
# bench/gpu/pack.sh [BUILD_DIR] [OUT_DIR]: everything the GPU measurement needs, in one folder
# for a machine that has an NVIDIA GPU but none of this project's packages:
#   OUT_DIR/geoslice-gpu.tar.xz   bin/ (the stripped release geoslice, bench_render,
#                                 bench_table1, bench_http), lib/ (every shared library they
#                                 load except glibc's own and the GL dispatch: libEGL, libGL*,
#                                 libOpenGL, libGLX, libGLdispatch, libgbm, libdrm come from the
#                                 device, so that its glvnd picks NVIDIA's vendor library),
#                                 share/proj/proj.db, run.sh
#   OUT_DIR/run.sh                the run script (bench/gpu/run.sh)
# Fails when the folder exceeds 60 MiB. Prints one JSON line: bytes, files, libraries.
# Defaults: BUILD_DIR build, OUT_DIR BUILD_DIR/gpu-pack.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$build/gpu-pack}
bins=(cli/geoslice bench/bench_render bench/bench_table1 bench/bench_http)
for b in "${bins[@]}"; do
  [[ -x $build/$b ]] || { echo "pack.sh: $build/$b is missing: build with -DGEOSLICE_BENCH=ON first" >&2; exit 1; }
done
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib" "$stage/share/proj"
for b in "${bins[@]}"; do strip -o "$stage/bin/$(basename "$b")" "$build/$b"; done
skip='^(libc|libm|libpthread|libdl|librt|libresolv|libutil|ld-linux-x86-64|libEGL|libGL|libGLX|libGLdispatch|libOpenGL|libgbm|libdrm)\.so'
libs=0
while read -r lib; do
  name=$(basename "$lib")
  [[ $name =~ $skip ]] && continue
  cp -L "$lib" "$stage/lib/$name"
  libs=$((libs + 1))
done < <(for b in "${bins[@]}"; do ldd "$build/$b"; done | awk '/=> \//{print $3}' | sort -u)
proj_db=$(pkg-config --variable=datadir proj 2>/dev/null || true)/proj.db
[[ -f $proj_db ]] || proj_db=/usr/share/proj/proj.db
cp "$proj_db" "$stage/share/proj/"
cp "$here/run.sh" "$stage/run.sh"
mkdir -p "$out"
tar -C "$stage" -cf - . | xz -6 -T0 > "$out/geoslice-gpu.tar.xz"
cp "$here/run.sh" "$out/run.sh"
bytes=$(du -sb "$out" | cut -f1)
files=$(find "$stage" -type f | wc -l)
echo "{\"pack\": \"$out\", \"bytes\": $bytes, \"files\": $files, \"libraries\": $libs}"
if (( bytes > 60 * 1024 * 1024 )); then
  echo "pack.sh: $out is $bytes bytes, over 60 MiB" >&2
  exit 1
fi
