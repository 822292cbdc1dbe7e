#!/usr/bin/env python3
"""Mixed saturation (soak) run of one geoslice server: wrk at full load for --minutes, one
minute at a time, with the server's RSS sampled at every minute boundary (prints JSON).

    python3 bench/soak.py [--binary build/cli/geoslice] [--minutes 30] [--connections 32]

Every request picks one of (per cent): 35 tiles of five section ids (cache hits after
their first render), 15 section JPEGs at a plane no one asked for (misses: real renders),
20 pixel queries at random pixels of a profile, 5 POST batch queries (64 pixels), 5
boreholes at random collars, 5 perspective PNGs at a fresh eye, 5 GeoJSON sections, 5
bad requests (a 400 is the expected answer; counted apart), 5 /healthz + /metrics.
Reported per minute: requests/s, p50/p90/p99 latency (wrk's, over all routes), non-2xx
answers split into 400s (the bad requests: ~5 %), 5xx and others, socket errors, the server's RSS (VmRSS and VmHWM),
and load average. The server and wrk share this machine's cores: a 2-core machine
gives figures under shared load, not capacity. Not part of the test suite.
"""
import argparse
import json
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

LUA = r"""
local salt = %(salt)d
local sids = {%(sids)s}
local counter = 0
local threads = {}
function setup(thread)
  counter = counter + 1
  thread:set("tid", counter)
  table.insert(threads, thread)
end
function init(args)
  n = 0
  st400, st5xx, st_other = 0, 0, 0
  math.randomseed(tid * 7919 + salt)
end
local function fresh_y()
  n = n + 1
  return 3387000 + math.random() * 3600 + salt * 1e-4 + n * 1e-7 + tid * 1e-8
end
function request()
  local r = math.random(100)
  if r <= 35 then
    local sid = sids[math.random(#sids)]
    local z = math.random(0, 4)
    local m = 2 ^ z
    return wrk.format("GET", string.format("/v1/sections/%%s/tiles/%%d/%%d/%%d.png", sid, z,
      math.random(0, m - 1), math.random(0, m - 1)))
  elseif r <= 50 then
    return wrk.format("GET", string.format(
      "/v1/models/demo/section.jpg?plane=0,1,0,-%%.7f&size=512x256", fresh_y()))
  elseif r <= 70 then
    return wrk.format("GET", string.format(
      "/v1/models/demo/query?plane=0,1,0,-3388846&size=1024x512&px=%%d&py=%%d",
      math.random(0, 1023), math.random(0, 511)))
  elseif r <= 75 then
    local px = {}
    for i = 1, 64 do px[i] = string.format("[%%d,%%d]", math.random(0, 1023), math.random(0, 511)) end
    return wrk.format("POST", "/v1/models/demo/query", {["Content-Type"] = "application/json"},
      '{"view":{"plane":"0,1,0,-3388846","size":"1024x512"},"pixels":[' .. table.concat(px, ",") .. ']}')
  elseif r <= 80 then
    return wrk.format("GET", string.format("/v1/models/demo/borehole?x=%%.3f&y=%%.3f",
      35502500 + math.random() * 3000, 3387000 + math.random() * 3000))
  elseif r <= 85 then
    return wrk.format("GET", string.format(
      "/v1/models/demo/section.png?plane=0,1,0,-3388846&view=perspective&size=320x240&eye=%%.3f,3384000,2000&target=35504000,3388846,0",
      35500000 + math.random() * 8000))
  elseif r <= 90 then
    return wrk.format("GET", string.format(
      "/v1/models/demo/section.geojson?plane=0,1,0,-%%.7f", fresh_y()))
  elseif r <= 95 then
    local bad = {"/v1/models/demo/section.png?plane=0,0,0,1", "/v1/models/demo/section.png?plane=0,1,0,-3388846&size=99999x2",
                 "/v1/models/demo/query?plane=0,1,0,-3388846&size=64x64&px=-1&py=3",
                 "/v1/models/demo/section.png?plane=0,1,0,-3388846&frame=0,1e-300,0,1e-300",
                 "/v1/models/demo/section.png?plane=nan,1,0,0", "/v1/models/demo/section.png?plane=0,1,0,-3388846&bogus=1"}
    return wrk.format("GET", bad[math.random(#bad)])
  else
    if math.random(2) == 1 then return wrk.format("GET", "/healthz") end
    return wrk.format("GET", "/metrics")
  end
end
function response(status, headers, body)
  if status == 400 then st400 = st400 + 1
  elseif status >= 500 then st5xx = st5xx + 1
  elseif status >= 300 then st_other = st_other + 1 end
end
function done(summary, latency, requests)
  local a, b, c = 0, 0, 0
  for _, t in ipairs(threads) do
    a = a + t:get("st400"); b = b + t:get("st5xx"); c = c + t:get("st_other")
  end
  io.write(string.format("SOAK {\"p50_ms\": %%.3f, \"p90_ms\": %%.3f, \"p99_ms\": %%.3f, \"max_ms\": %%.3f, " ..
    "\"status_400\": %%d, \"status_5xx\": %%d, \"status_other_non2xx\": %%d}\n",
    latency:percentile(50) / 1000, latency:percentile(90) / 1000, latency:percentile(99) / 1000, latency.max / 1000, a, b, c))
end
"""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def get(port, path, method="GET", body=None):
    req = urllib.request.Request(f"http://127.0.0.1:{port}{path}", method=method, data=body,
                                 headers={"Content-Type": "application/json"} if body else {})
    with urllib.request.urlopen(req, timeout=30) as r:
        return r.status, r.read()


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        st = dict(ln.split(":", 1) for ln in f if ":" in ln)
    return int(st["VmRSS"].split()[0]), int(st["VmHWM"].split()[0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "geoslice"))
    ap.add_argument("--minutes", type=int, default=30)
    ap.add_argument("--connections", type=int, default=32)
    ap.add_argument("--threads", type=int, default=2, help="wrk threads")
    ap.add_argument("--seconds-per-sample", type=int, default=60, help="(for a quick check of this script)")
    ap.add_argument("--serve-args", default="", help="extra arguments for serve")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="geoslice-soak-")
    port = free_port()
    log = open(os.path.join(work, "serve.log"), "w")
    server = subprocess.Popen([os.path.abspath(a.binary), "serve", "--host", "127.0.0.1", "--port", str(port),
                               "--log-level", "warn"] + a.serve_args.split(), stdout=log, stderr=subprocess.STDOUT)
    result = {"machine": {"cores": os.cpu_count()}, "minutes": a.minutes, "connections": a.connections,
              "serve_args": a.serve_args, "per_minute": []}
    try:
        t0 = time.time()
        while True:
            try:
                if get(port, "/readyz")[0] == 200:
                    break
            except OSError:
                pass
            if server.poll() is not None or time.time() - t0 > 300:
                raise RuntimeError("server did not become ready")
            time.sleep(0.1)
        sids = []
        for k in range(5):
            _, body = get(port, "/v1/models/demo/sections", "POST",
                          json.dumps({"plane": f"0,1,0,-{3387500 + 600 * k}"}).encode())
            sids.append(json.loads(body)["sid"])
        result["rss_kib_ready"] = rss_kib(server.pid)[0]
        for minute in range(a.minutes):
            script = os.path.join(work, f"m{minute}.lua")
            with open(script, "w") as f:
                f.write(LUA % {"salt": minute + 1, "sids": ",".join(f'"{s}"' for s in sids)})
            r = subprocess.run(["wrk", "-t", str(a.threads), "-c", str(a.connections), "-d", f"{a.seconds_per_sample}s", "--timeout", "15s",
                                "-s", script, f"http://127.0.0.1:{port}"], capture_output=True, text=True)
            out = r.stdout
            if r.returncode != 0 or "SOAK" not in out:
                raise RuntimeError(f"wrk failed: {r.stderr.strip()} {out[-500:]}")
            row = {"minute": minute + 1, "load1": round(os.getloadavg()[0], 2)}
            row["requests"] = int(re.search(r"(\d+) requests in", out).group(1))
            row["rps"] = float(re.search(r"Requests/sec:\s+([\d.]+)", out).group(1))
            row.update(json.loads(re.search(r"SOAK (\{.*\})", out).group(1)))
            non2xx = int(m.group(1)) if (m := re.search(r"Non-2xx or 3xx responses: (\d+)", out)) else 0
            sock = re.search(r"Socket errors: connect (\d+), read (\d+), write (\d+), timeout (\d+)", out)
            row["socket_errors"] = sum(int(x) for x in sock.groups()) if sock else 0
            row["non2xx"] = non2xx
            rss, hwm = rss_kib(server.pid)
            row["rss_mib"] = round(rss / 1024, 1)
            row["hwm_mib"] = round(hwm / 1024, 1)
            st, body = get(port, "/metrics")
            for name in ("geoslice_queue_depth", "geoslice_cache_bytes", "geoslice_render_overruns_total", "geoslice_renders_dropped_total"):
                m = re.search(rf"^{name}(?:\{{[^}}]*\}})? (\S+)$", body.decode(), re.M)
                if m:
                    row[name] = float(m.group(1))
            result["per_minute"].append(row)
            print(json.dumps(row), file=sys.stderr, flush=True)
            if server.poll() is not None:
                raise RuntimeError(f"server exited with {server.returncode}")
        rows = result["per_minute"]
        result["summary"] = {
            "requests": sum(r["requests"] for r in rows),
            "median_rps": sorted(r["rps"] for r in rows)[len(rows) // 2],
            "median_p50_ms": sorted(r["p50_ms"] for r in rows)[len(rows) // 2],
            "median_p99_ms": sorted(r["p99_ms"] for r in rows)[len(rows) // 2],
            "socket_errors": sum(r["socket_errors"] for r in rows),
            "status_5xx": sum(r["status_5xx"] for r in rows),
            "status_other_non2xx": sum(r["status_other_non2xx"] for r in rows),
            "rss_mib_first_last_max": [rows[0]["rss_mib"], rows[-1]["rss_mib"], max(r["rss_mib"] for r in rows)],
        }
    finally:
        server.terminate()
        try:
            result["exit_code_after_sigterm"] = server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
            result["exit_code_after_sigterm"] = "did not exit within 30 s"
        log.close()
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
