#!/usr/bin/env bash
# A server inside a cgroup with a 2 GiB memory limit, as a pod with `limits.memory: 2Gi` runs
# it (cgroup v1's memory controller or v2, as root): /readyz shows the limit and the defaults
# fitted to it (render budget 1024 MiB, cache 256 MiB: server/container_memory.hpp); a burst
# of large renders that would need more than the budget is answered 503 with Retry-After for
# the excess, the server is never OOM-killed and keeps answering, and the cgroup's peak stays
# under the limit. Exit 77 (CTest skip) where no cgroup can be made (not root, read-only).
#   bash tests/deploy/cgroup_memory_test.sh build/cli/geoslice
set -uo pipefail
bin=$(readlink -f "${1:?usage: cgroup_memory_test.sh GEOSLICE_BINARY}")
limit=$((2 << 30))
if [[ -w /sys/fs/cgroup/memory ]]; then
  cg=/sys/fs/cgroup/memory/geoslice-test-$$
  mkdir "$cg" 2>/dev/null || { echo "SKIP: cannot make $cg"; exit 77; }
  echo "$limit" > "$cg/memory.limit_in_bytes" || { rmdir "$cg"; echo "SKIP: cannot set a limit"; exit 77; }
  peak_file=$cg/memory.max_usage_in_bytes
  ooms() { grep -o 'oom_kill [0-9]*' "$cg/memory.oom_control" | awk '{print $2}'; }
elif grep -qw memory /sys/fs/cgroup/cgroup.controllers 2>/dev/null && [[ -w /sys/fs/cgroup ]]; then
  cg=/sys/fs/cgroup/geoslice-test-$$
  mkdir "$cg" 2>/dev/null || { echo "SKIP: cannot make $cg"; exit 77; }
  echo "$limit" > "$cg/memory.max" || { rmdir "$cg"; echo "SKIP: cannot set a limit"; exit 77; }
  peak_file=$cg/memory.peak
  ooms() { grep -o 'oom_kill [0-9]*' "$cg/memory.events" | awk '{print $2}'; }
else
  echo "SKIP: no writable cgroup memory controller"
  exit 77
fi
# A process must be able to join it (a nested container may refuse).
if ! (echo "$BASHPID" > "$cg/cgroup.procs") 2>/dev/null; then
  rmdir "$cg" 2>/dev/null
  echo "SKIP: cannot move a process into $cg"
  exit 77
fi
tmp=$(mktemp -d)
pid=""
cleanup() {
  [[ -n $pid ]] && kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
  sleep 0.2
  rmdir "$cg" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
# The server joins the cgroup before it starts (as a container's process does).
sh -c 'echo $$ > "$1/cgroup.procs" && exec "$2" serve --host 127.0.0.1 --port "$3" --workers 2 --demo-triangles 200000 --log-level warn' \
  sh "$cg" "$bin" "$port" > "$tmp/log" 2>&1 &
pid=$!
for _ in $(seq 300); do
  curl -sf "http://127.0.0.1:$port/readyz" > "$tmp/readyz" && break
  kill -0 "$pid" 2>/dev/null || { echo "FAIL: the server exited: $(cat "$tmp/log")"; exit 1; }
  sleep 0.1
done
fail=0
python3 - "$tmp/readyz" <<'PY' || fail=1
import json, sys
m = json.load(open(sys.argv[1]))["memory"]
assert m["containerLimitMiB"] == 2048, m
assert m["renderBudgetMiB"] == 1024 and m["cacheMiB"] == 256, m
print("readyz memory:", m)
PY
# Six 4096x4096 exact renders at once: about 512 MiB each by the server's estimate, two fit.
url="http://127.0.0.1:$port/v1/models/demo/section.png?plane=0,1,0,-3388846&size=4096x4096"
for i in 1 2 3 4 5 6; do
  curl -s -o /dev/null -w '%{http_code}\n' "$url&vx=1.$i" > "$tmp/status.$i" &
done
wait $(jobs -p | grep -v "^$pid$") 2>/dev/null
codes=$(cat "$tmp"/status.* | sort | uniq -c | tr '\n' ' ')
echo "burst: $codes"
grep -q 503 "$tmp"/status.* || { echo "FAIL: no 503 for renders past the budget ($codes)"; fail=1; }
grep -q 200 "$tmp"/status.* || { echo "FAIL: no render fitted in the budget ($codes)"; fail=1; }
grep -qv -e 200 -e 503 "$tmp"/status.* && { echo "FAIL: answers other than 200/503 ($codes)"; fail=1; }
kill -0 "$pid" 2>/dev/null || { echo "FAIL: the server died"; fail=1; }
curl -sf "http://127.0.0.1:$port/healthz" > /dev/null || { echo "FAIL: /healthz after the burst"; fail=1; }
peak=$(cat "$peak_file" 2>/dev/null || echo 0)
echo "cgroup peak: $((peak >> 20)) MiB of $((limit >> 20)) MiB; OOM kills: $(ooms)"
[[ "$(ooms)" == 0 ]] || { echo "FAIL: OOM kills in the cgroup"; fail=1; }
((fail == 0)) && echo "cgroup_memory: ok"
exit $fail
