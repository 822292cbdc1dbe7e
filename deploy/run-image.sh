#!/usr/bin/env bash
# Runs the geoslice image as `podman run` (or `docker run`) would, with this project's
# storage and this host's work-arounds (deploy/engine.sh: hybrid cgroups, rlimits, host
# network), so the README's commands work as written on a fresh Debian 12 host.
#   bash deploy/run-image.sh                                   # the demo model on :8080
#   GEOSLICE_PORT=9000 bash deploy/run-image.sh -v /data/models:/models:ro -- serve --models /models
# Options before `--` go to `run` (volumes, -e, --name, -d...); what follows `--` is the
# server's command line (default: serve, the demo model). The container is read-only, runs
# as uid 10001 and is removed when it stops; Ctrl-C stops it (SIGTERM: in-flight requests
# finish). GEOSLICE_PORT (default 8080) sets the port of the server and of its health check.
# GEOSLICE_IMAGE picks another image (default localhost/geoslice:VERSION, deploy/build-image.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^project(geoslice VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
image=${GEOSLICE_IMAGE:-localhost/geoslice:$version}
source deploy/engine.sh
engine_init
opts=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do
    opts+=("$1")
    shift
done
[ "${1:-}" = -- ] && shift
if ! ctr image inspect "$image" >/dev/null 2>&1; then
    echo "run-image: no image $image in $([ "$GEOSLICE_ENGINE" = podman ] && echo "$GEOSLICE_PODMAN_DIR" || echo docker): bash deploy/build-image.sh builds it" >&2
    exit 1
fi
health=()
[ "$GEOSLICE_ENGINE" = podman ] && health=(--health-interval disable)  # no systemd timers here
exec "${ctr_prefix[@]}" "$GEOSLICE_ENGINE" "${ctr_args[@]}" run --rm --read-only "${ctr_run_args[@]}" "${health[@]}" \
    -e GEOSLICE_PORT="${GEOSLICE_PORT:-8080}" "${opts[@]}" "$image" "$@"
