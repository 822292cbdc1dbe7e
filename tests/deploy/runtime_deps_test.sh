#!/usr/bin/env bash
# The runtime package list (scripts/install-deps.sh --runtime, the image's runtime stage)
# must provide every shared library the built binary loads: those ldd lists, and those it
# opens at run time (OSMesa, Mesa's EGL vendor library, the llvmpipe DRI driver). Each
# library is mapped to its Debian package with dpkg -S on this machine.
# Usage: runtime_deps_test.sh BINARY   (CTest label deploy)
set -euo pipefail
binary=$1
repo=$(cd "$(dirname "$0")/../.." && pwd)
runtime=$(bash "$repo/scripts/install-deps.sh" --runtime --list)
owner() { # PATH -> package, trying the merged-/usr aliases dpkg may know it by
    local p=$1 real
    real=$(readlink -f "$p")
    for q in "$p" "$real" "${p#/usr}" "/usr$p" "${real#/usr}" "/usr$real" "$(dirname "$p")/$(basename "$real")"; do
        dpkg -S "$q" 2>/dev/null | head -1 | cut -d: -f1 && return 0
    done
    return 1
}
libs=$(ldd "$binary" | awk '/=> \// {print $3} /^\t\/[^ ]+ \(/ {print $1}')
[ -n "$libs" ] || { echo "runtime_deps_test: ldd found no libraries in $binary" >&2; exit 1; }
for name in libOSMesa.so.8 libEGL_mesa.so.0; do
    libs+=$'\n'$(ldconfig -p | awk -v n="$name" '$1 == n {print $NF; exit}')
done
libs+=$'\n'$(ls /usr/lib/*/dri/swrast_dri.so 2>/dev/null | head -1)
missing=0 checked=0
declare -A seen=()
while read -r lib; do
    [ -n "$lib" ] || continue
    pkg=$(owner "$lib") || { echo "runtime_deps_test: no Debian package owns $lib" >&2; missing=1; continue; }
    [ -n "${seen[$pkg]:-}" ] && continue
    seen[$pkg]=1
    checked=$((checked + 1))
    grep -qx "$pkg" <<<"$runtime" ||
        { echo "runtime_deps_test: $lib comes from $pkg, which is not on the runtime list (scripts/install-deps.sh)" >&2; missing=1; }
done <<<"$libs"
[ "$missing" -eq 0 ] || exit 1
echo "runtime_deps_test: the $checked packages the binary loads from are all on the runtime list"
