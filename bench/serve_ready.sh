#!/usr/bin/env bash
# bench/serve_ready.sh BINARY PORT [serve arguments...]: starts `BINARY serve --port PORT
# --gl none ARGS` and prints one JSON line: seconds from the start to the first /readyz 200
# (polled every 20 ms with curl), then (servers whose /readyz reports "rays") to every model's
# ray scene built, and the load average before and at ready (the machine is shared: quote it
# with the figure). Stops the server with SIGTERM. Example:
#   bash bench/serve_ready.sh build/cli/geoslice 18080 --models /data/baked --no-bake
# The container's figure: bench/container_ready.sh.
set -euo pipefail
source "$(dirname "$0")/ready_wait.sh"
bin=$1 port=$2
shift 2
load0=$(cut -d' ' -f1-3 /proc/loadavg)
t0=$(date +%s.%N)
"$bin" serve --port "$port" --gl none --log-level warn "$@" >/dev/null 2>&1 &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true; wait $pid 2>/dev/null || true' EXIT
ready_wait "$port" "$pid"
printf '{"readySeconds": %.3f, "raysReadySeconds": %.3f, "loadBefore": "%s", "loadAtReady": "%s", "args": "%s"}\n' \
    "$ready" "$rays" "$load0" "$load1" "$*"
