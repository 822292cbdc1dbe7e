#!/usr/bin/env bash
# bench/container_ready.sh IMAGE PORT PACKAGE_DIR [--binary PATH] [serve arguments...]: the
# container's cold start, like bench/serve_ready.sh for the binary. Runs IMAGE (podman or
# docker through deploy/engine.sh; GEOSLICE_PODMAN_DIR picks podman's storage) with a
# read-only root and the baked package mounted read-only as /models/<its name>, as a replica
# does (`serve --models /models --no-bake --gl none`), and prints one JSON line: seconds from
# `run` to the first /readyz 200 (polled every 20 ms), then to every model's ray scene built
# (/readyz "rays"; images without it built them before /readyz), and the load average before and after. --binary mounts another geoslice
# binary over the image's (the image's libraries must hold what it links). Removes the
# container. Example:
#   GEOSLICE_PODMAN_DIR=/var/cache/geoslice/podman bash bench/container_ready.sh \
#       localhost/geoslice:latest 18090 /data/baked/l4
set -euo pipefail
cd "$(dirname "$0")/.."
image=$1 port=$2 pkg=$(cd "$3" && pwd)
shift 3
mounts=(-v "$pkg:/models/$(basename "$pkg"):ro")
if [ "${1:-}" = --binary ]; then
    mounts+=(-v "$(realpath "$2"):/usr/local/bin/geoslice:ro")
    shift 2
fi
source deploy/engine.sh
source bench/ready_wait.sh
engine_init
health_args=()
[ "$GEOSLICE_ENGINE" = podman ] && health_args=(--health-interval disable)
name=geoslice-ready-$$
trap 'ctr rm -f -t 0 "$name" >/dev/null 2>&1 || true' EXIT
load0=$(cut -d' ' -f1-3 /proc/loadavg)
t0=$(date +%s.%N)
ctr run -d --name "$name" --read-only "${ctr_run_args[@]}" "${health_args[@]}" "${mounts[@]}" \
    -e GEOSLICE_PORT="$port" "$image" serve --host 127.0.0.1 --models /models --no-bake --gl none \
    --log-level warn "$@" >/dev/null
ready_wait "$port"
printf '{"readySeconds": %.3f, "raysReadySeconds": %.3f, "loadBefore": "%s", "loadAtReady": "%s", "image": "%s", "args": "%s"}\n' \
    "$ready" "$rays" "$load0" "$load1" "$image" "${mounts[*]} $*"
