#!/usr/bin/env bash
# Tests the container image against the binary built outside it (.ci/run runs this after
# scripts/test.sh). Builds the image first when it is missing, from another revision, from
# a tree with uncommitted edits, or GEOSLICE_IMAGE_REBUILD=1
# (deploy/build-image.sh: layers and ccache are kept in build/podman, so a rebuild after a
# source edit recompiles only what changed). Checks:
#   - the runtime image: non-root user, OCI labels, HEALTHCHECK kept, no compiler, every
#     shared library of the binary resolves;
#   - the container (read-only root, non-default port through GEOSLICE_PORT) reaches
#     /readyz, and a section (JPEG and PNG), a tile of a section id made by the binary, a
#     pixel query and a borehole equal the binary's answers byte for byte, ETags included;
#   - `healthcheck run` is healthy on that port;
#   - SIGTERM during a ~4 s render: the render is answered in full, the container exits 0.
#   - the OCI archive build-image.sh wrote (build/geoslice-VERSION.oci.tar) holds this image
#     (same config digest, tag and version label).
# Usage: bash deploy/test-image.sh [IMAGE]   (default localhost/geoslice:VERSION; binary:
# $GEOSLICE_BINARY or build/cli/geoslice, built first when missing). Prints timings; exit 0 =
# all passed.
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^project(geoslice VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
image=${1:-localhost/geoslice:$version}
binary=${GEOSLICE_BINARY:-${GEOSLICE_BUILD_DIR:-build}/cli/geoslice}
source deploy/engine.sh
engine_init
t_start=$(date +%s)
# No systemd here to run health checks on a timer: `healthcheck run` runs them on demand.
health_args=()
[ "$GEOSLICE_ENGINE" = podman ] && health_args=(--health-interval disable)

fail() {
    echo "test-image: FAIL: $*" >&2
    exit 1
}
if [ ! -x "$binary" ]; then
    # A clone with only the image (or nothing built yet): the binary to compare against.
    bdir=${GEOSLICE_BUILD_DIR:-build}
    echo "test-image: no binary at $binary: building it in $bdir"
    [ -f "$bdir/CMakeCache.txt" ] || cmake -S . -B "$bdir" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$bdir" --target geoslice >/dev/null
    binary=$bdir/cli/geoslice
    [ -x "$binary" ] || fail "no binary at $binary after building it"
fi
# An image from another revision (podman's storage is kept between CI runs) or from a tree
# with uncommitted edits is rebuilt: it must hold the code the binary was built from.
source deploy/revision.sh
want=$(source_revision)
have=$(ctr image inspect --format '{{index .Config.Labels "org.opencontainers.image.revision"}}' "$image" 2>/dev/null || true)
if [ "${GEOSLICE_IMAGE_REBUILD:-0}" = 1 ] || [ -z "$have" ] || [ "$have" != "$want" ] || [[ $want == *-dirty ]]; then
    echo "test-image: building $image (image revision '${have:-none}', source $want)"
    bash deploy/build-image.sh --tag "$image"
fi

work=$(mktemp -d)
name=geoslice-test-$$
host_pid=""
cleanup() {
    [ -n "$host_pid" ] && kill "$host_pid" 2>/dev/null && wait "$host_pid" 2>/dev/null
    ctr rm -f -t 0 "$name" >/dev/null 2>&1 || true
    rm -rf "$work"
}
trap cleanup EXIT

free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
wait_ready() { # PORT SECONDS -> prints the seconds it took
    local t0 now
    t0=$(date +%s.%N)
    while true; do
        curl -fs -o /dev/null "http://127.0.0.1:$1/readyz" && break
        now=$(date +%s.%N)
        awk -v a="$t0" -v b="$now" -v m="$2" 'BEGIN {exit !(b - a > m)}' && return 1
        sleep 0.05
    done
    awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}'
}

# ---- the image itself -----------------------------------------------------------------
user=$(ctr image inspect --format '{{.Config.User}}' "$image")
[ -n "$user" ] && [ "${user%%:*}" != 0 ] && [ "${user%%:*}" != root ] || fail "image runs as root (User='$user')"
health=$(ctr image inspect --format '{{json .Config.Healthcheck}}' "$image")
case "$health" in *GEOSLICE_PORT*) ;; *) fail "HEALTHCHECK missing or not on GEOSLICE_PORT: $health" ;; esac
for l in title version revision created; do
    ctr image inspect --format "{{index .Config.Labels \"org.opencontainers.image.$l\"}}" "$image" | grep -q . ||
        fail "label org.opencontainers.image.$l missing"
done
inside=$(ctr run --rm "${ctr_run_args[@]}" "${health_args[@]}" --entrypoint sh "$image" -c \
    'for c in cc gcc g++ c++ clang ld cmake; do command -v $c; done; ls /usr/include 2>/dev/null | head -3;
     ldd /usr/local/bin/geoslice | grep "not found"; true')
[ -z "$inside" ] || fail "runtime image has build tools, headers or unresolved libraries: $inside"
size=$(ctr image inspect --format '{{.Size}}' "$image")
echo "test-image: $image $((size / 1000000)) MB, user $user, labels and HEALTHCHECK present, no compiler"
label=$(ctr image inspect --format '{{index .Config.Labels "org.opencontainers.image.version"}}' "$image")
[ "$label" = "$version" ] || fail "image version label '$label' is not the project's $version"
archive=build/geoslice-$version.oci.tar
if [ "$image" = "localhost/geoslice:$version" ] && [ -f "$archive" ]; then
    layers=$(ctr image inspect --format '{{json .RootFS.Layers}}' "$image")
    revision=$(ctr image inspect --format '{{index .Config.Labels "org.opencontainers.image.revision"}}' "$image")
    python3 - "$archive" "$layers" "$image" "$version" "$revision" <<'PY' || fail "$archive does not hold $image"
import json, sys, tarfile
archive, layers, ref, version, revision = sys.argv[1], json.loads(sys.argv[2]), *sys.argv[3:6]
with tarfile.open(archive) as t:
    def blob(digest):
        return json.load(t.extractfile("blobs/" + digest.replace(":", "/")))
    index = json.load(t.extractfile("index.json"))
    (m,) = index["manifests"]
    name = m.get("annotations", {}).get("org.opencontainers.image.ref.name", "")
    config = blob(blob(m["digest"])["config"]["digest"])
    # The archive's config is the OCI form of the image's (another digest): its layers
    # (uncompressed digests) and labels are the image's.
    assert config["rootfs"]["diff_ids"] == layers, "its layers are not the image's"
    label = config["config"].get("Labels", {}).get("org.opencontainers.image.version")
    assert label == version, f"version label {label!r} is not {version}"
    built = config["config"].get("Labels", {}).get("org.opencontainers.image.revision")
    assert built == revision, f"built from {built!r}, the image from {revision!r}: a stale archive"
    assert name == ref, f"ref.name {name!r} is not {ref}"
    print(f"test-image: {archive}: OCI archive of {ref} ({len(layers)} layers, version {label}, revision {built})")
PY
fi

# ---- the binary and the container side by side --------------------------------------
p_host=$(free_port)
p_ctr=$(free_port)
"$binary" serve --host 127.0.0.1 --port "$p_host" --workers 1 >"$work/host.log" 2>&1 &
host_pid=$!
t_host=$(wait_ready "$p_host" 120) || fail "binary not ready: $(tail -5 "$work/host.log")"
ctr run -d --name "$name" --read-only "${ctr_run_args[@]}" "${health_args[@]}" -e GEOSLICE_PORT="$p_ctr" \
    "$image" serve --host 127.0.0.1 --workers 1 --deadline-ms 60000 --shutdown-grace-ms 60000 >/dev/null
t_ctr=$(wait_ready "$p_ctr" 120) || fail "container not ready: $(ctr logs "$name" 2>&1 | tail -5)"
echo "test-image: demo model ready in ${t_host} s (binary), ${t_ctr} s (container, read-only root, port $p_ctr)"

plane=0,1,0,-3388846
sid=$(curl -fsS -X POST "http://127.0.0.1:$p_host/v1/models/demo/sections" -H "Content-Type: application/json" -d "{\"plane\": \"$plane\"}" |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["sid"])')
paths=(
    "/v1/models/demo/section.jpg?plane=$plane&size=1024x512"
    "/v1/models/demo/section.png?plane=$plane&size=800x400&vx=2"
    "/v1/sections/$sid/tiles/2/1/1.png"
    "/v1/models/demo/query?plane=$plane&size=1024x512&px=500&py=300"
    "/v1/models/demo/borehole?x=35504000&y=3388000"
)
for path in "${paths[@]}"; do
    for side in host ctr; do
        port=$p_host
        [ $side = ctr ] && port=$p_ctr
        code=$(curl -sS -o "$work/$side.body" -D "$work/$side.headers" -w '%{http_code}' "http://127.0.0.1:$port$path")
        [ "$code" = 200 ] || fail "$side answered $code to $path: $(head -c 300 "$work/$side.body")"
    done
    cmp -s "$work/host.body" "$work/ctr.body" || fail "bytes differ for $path"
    etag_h=$(grep -i '^etag:' "$work/host.headers" | tr -d '\r' || true)
    etag_c=$(grep -i '^etag:' "$work/ctr.headers" | tr -d '\r' || true)
    [ "$etag_h" = "$etag_c" ] || fail "ETag differs for $path: '$etag_h' vs '$etag_c'"
    echo "test-image: same $(stat -c %s "$work/host.body") bytes${etag_h:+, same $etag_h} for ${path%%\?*}"
done

# ---- health check on the configured port ---------------------------------------------
ctr healthcheck run "$name" >/dev/null || fail "healthcheck run: unhealthy on port $p_ctr"
echo "test-image: healthcheck run: healthy (port $p_ctr via GEOSLICE_PORT)"

# ---- SIGTERM as PID 1 with a render in flight ------------------------------------------
slow="/v1/models/demo/section.png?plane=$plane&view=perspective&size=4096x4096"
curl -sS -o "$work/slow.body" -w '%{http_code} %{size_download}' "http://127.0.0.1:$p_ctr$slow" >"$work/slow.status" &
curl_pid=$!
sleep 0.5
ctr kill --signal TERM "$name" >/dev/null
wait "$curl_pid" || true
read -r slow_code slow_bytes <"$work/slow.status" || true  # no newline at the end
code=$(ctr wait "$name")
logs=$(ctr logs "$name" 2>&1)
grep -q 'event=shutdown_begin in_flight=[1-9]' <<<"$logs" ||
    fail "the render was not in flight at SIGTERM (make it slower?): $(grep shutdown <<<"$logs")"
[ "$slow_code" = 200 ] || fail "in-flight render answered '$slow_code' after SIGTERM"
python3 -c 'import sys; d = open(sys.argv[1], "rb").read(); sys.exit(d[:8] != b"\x89PNG\r\n\x1a\n" or d[-8:-4] != b"IEND")' \
    "$work/slow.body" || fail "in-flight render is not a whole PNG"
[ "$code" = 0 ] || fail "container exited with $code after SIGTERM"
echo "test-image: SIGTERM with a render in flight: answered 200 ($slow_bytes bytes), exit 0"
echo "test-image: all passed in $(($(date +%s) - t_start)) s"
