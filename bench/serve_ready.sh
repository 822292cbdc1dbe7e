#!/usr/bin/env bash
# bench/serve_ready.sh BINARY PORT [serve arguments...]: starts `BINARY serve --port PORT
# --gl none ARGS` and prints one JSON line: seconds from the start to the first /readyz 200
# (polled every 20 ms with curl), and the load average before and after (the machine is
# shared: quote it with the figure). Stops the server with SIGTERM. Example:
#   bash bench/serve_ready.sh build/cli/geoslice 18080 --models /data/baked --no-bake
set -euo pipefail
bin=$1 port=$2
shift 2
load0=$(cut -d' ' -f1-3 /proc/loadavg)
t0=$(date +%s.%N)
"$bin" serve --port "$port" --gl none --log-level warn "$@" >/dev/null 2>&1 &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true; wait $pid 2>/dev/null || true' EXIT
while :; do
    if ! kill -0 $pid 2>/dev/null; then echo '{"error": "the server exited"}'; exit 1; fi
    code=$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/readyz" || true)
    [ "$code" = 200 ] && break
    if [ "$(echo "$(date +%s.%N) - $t0 > 600" | bc)" = 1 ]; then echo '{"error": "not ready in 600 s"}'; exit 1; fi
    sleep 0.02
done
t1=$(date +%s.%N)
load1=$(cut -d' ' -f1-3 /proc/loadavg)
printf '{"readySeconds": %.3f, "loadBefore": "%s", "loadAfter": "%s", "args": "%s"}\n' \
    "$(echo "$t1 - $t0" | bc)" "$load0" "$load1" "$*"
