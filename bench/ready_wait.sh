# Sourced by bench/serve_ready.sh and bench/container_ready.sh: the cold-start clock.
# ready_wait PORT [PID]: from $t0 (date +%s.%N, set by the caller just before the start),
# polls http://127.0.0.1:PORT/readyz every 20 ms until 200, then until every model's ray
# scene is built (/readyz "rays"; older servers have none: theirs were built before 200).
# Sets ready, rays (seconds since $t0) and load1 (load average at ready). Exits 1 with a JSON
# error when PID (if given) exits or nothing is ready in 600 s.
elapsed() { echo "$(date +%s.%N) - $t0" | bc; }
ready_wait() {
    local port=$1 pid=${2:-} code
    while :; do
        if [ -n "$pid" ] && ! kill -0 "$pid" 2>/dev/null; then echo '{"error": "the server exited"}'; exit 1; fi
        code=$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/readyz" || true)
        [ "$code" = 200 ] && break
        if [ "$(echo "$(elapsed) > 600" | bc)" = 1 ]; then echo '{"error": "not ready in 600 s"}'; exit 1; fi
        sleep 0.02
    done
    ready=$(elapsed)
    load1=$(cut -d' ' -f1-3 /proc/loadavg)
    while ! curl -s "http://127.0.0.1:$port/readyz" |
        python3 -c 'import json,sys; r=json.load(sys.stdin).get("rays"); sys.exit(0 if r is None or all(v["state"] in ("ready","failed") for v in r.values()) else 1)'; do
        sleep 0.05
    done
    rays=$(elapsed)
}
