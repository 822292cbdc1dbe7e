#!/usr/bin/env bash
# bench/serve_ready.sh BINARY PORT [serve arguments...]: starts `BINARY serve --port PORT
# --gl none ARGS` and prints one JSON line: seconds from the start to the first /readyz 200
# (polled every 20 ms with curl), then (servers whose /readyz reports "rays") to every model's
# ray scene built, and the load average before and at ready (the machine is shared: quote it
# with the figure). Stops the server with SIGTERM. Example:
#   bash bench/serve_ready.sh build/cli/geoslice 18080 --models /data/baked --no-bake
# The container's figure: bench/container_ready.sh.
set -euo pipefail
bin=$1 port=$2
shift 2
load0=$(cut -d' ' -f1-3 /proc/loadavg)
t0=$(date +%s.%N)
"$bin" serve --port "$port" --gl none --log-level warn "$@" >/dev/null 2>&1 &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true; wait $pid 2>/dev/null || true' EXIT
elapsed() { echo "$(date +%s.%N) - $t0" | bc; }
while :; do
    if ! kill -0 $pid 2>/dev/null; then echo '{"error": "the server exited"}'; exit 1; fi
    code=$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/readyz" || true)
    [ "$code" = 200 ] && break
    if [ "$(echo "$(elapsed) > 600" | bc)" = 1 ]; then echo '{"error": "not ready in 600 s"}'; exit 1; fi
    sleep 0.02
done
ready=$(elapsed)
load1=$(cut -d' ' -f1-3 /proc/loadavg)
# Older binaries have no "rays" in /readyz: their ray scenes were built before it turned 200.
while ! curl -s "http://127.0.0.1:$port/readyz" |
    python3 -c 'import json,sys; r=json.load(sys.stdin).get("rays"); sys.exit(0 if r is None or all(v["state"] in ("ready","failed") for v in r.values()) else 1)'; do
    sleep 0.05
done
rays=$(elapsed)
printf '{"readySeconds": %.3f, "raysReadySeconds": %.3f, "loadBefore": "%s", "loadAtReady": "%s", "args": "%s"}\n' \
    "$ready" "$rays" "$load0" "$load1" "$*"
