#!/usr/bin/env python3
"""Throughput and cache hit ratio of 1, 2 and 3 geoslice replicas behind nginx on
127.0.0.1, measured with wrk, and the fleet's hit ratio with 3 and 5 replicas by
balancing method (prints JSON; not part of the test suite).

    python3 deploy/bench_scale_out.py [--binary build/cli/geoslice] [--seconds 5] [--connections 8]
                                      [--only throughput|fleet]

Workloads, each through nginx for --seconds:
  new_sections  every request a section JPEG (256x128) at a plane no one asked for: all
                misses, so the replicas do the work;
  cached_tiles  64 tiles of one section id, fetched once before: all nginx cache hits;
  mixed         80 % tiles drawn from 400 tile URLs, 20 % new sections (cold cache at start):
                the hit ratio a tile viewer sees.
Then, with 3 replicas, one replica is killed (SIGKILL) a third into a new_sections run:
non-2xx answers and socket errors are reported.

Fleet (nginx's own cache off, so what is measured is the replicas' caches, as behind a
Kubernetes Service or several cache-tier pods): 256 tiles of a new section, each asked 32
times in a shuffled order by 4 keep-alive clients (scale_out.run_load: a request that crossed
nginx closing its idle connection on a reload is sent again, as browsers do, and counted) (8,192 requests; one render per tile
would be a hit ratio of 1 - 1/32 = 0.969). fleet hit ratio = 1 - renders / requests, the
renders summed over the replicas' geoslice_render_duration_seconds_count{kind="tile"}.
With 3 and 5 replicas, round robin against consistent hashing; then with hashing a
replica killed (SIGKILL) a third into the run, and one added a third into another run:
failed requests are counted. Views: 32 section images, each followed by 16 pixel queries of
that view; the replicas' ID-buffer cache hits say how many queries found the view's ID
buffer on the replica they reached. Replicas and wrk share this machine's
cores: on a 2-core machine the figures are ratios under shared load, not capacity.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from scale_out import REPO, Balancer, Replica, free_port, http_get, metric_sum, run_load, upstream_tries  # noqa: E402

LUA = r"""
local salt = %(salt)d
local counter = 0
local sid = "%(sid)s"
function setup(thread)
  counter = counter + 1
  thread:set("tid", counter)
end
function init(args)
  n = 0
  math.randomseed(tid * 7919 + salt)
end
function request()
  n = n + 1
  local mode = "%(mode)s"
  local new = mode == "new_sections" or (mode == "mixed" and math.random() < 0.2)
  if new then
    -- a fresh northing inside the demo model (3386846..3390846 m) for every request
    local i = n * 2 + tid  -- wrk -t 2: unique per request
    local y = 3387000 + (i %% 7000) * 0.5 + salt * 0.001 + math.floor(i / 7000) * 0.00001
    return wrk.format("GET", string.format("/v1/models/demo/section.jpg?plane=0,1,0,-%%.5f&size=256x128", y))
  end
  local k
  if mode == "cached_tiles" then k = n %% 64 else k = math.random(0, 399) end
  local z, x, y = 5, k %% 32, math.floor(k / 32)
  return wrk.format("GET", "/v1/sections/" .. sid .. "/tiles/" .. z .. "/" .. x .. "/" .. y .. ".png")
end
"""


def wrk(port, mode, sid, salt, seconds, connections, workdir):
    script = os.path.join(workdir, f"{mode}-{salt}.lua")
    with open(script, "w") as f:
        f.write(LUA % {"salt": salt, "sid": sid, "mode": mode})
    r = subprocess.run(["wrk", "-t", "2", "-c", str(connections), "-d", f"{seconds}s", "--timeout", "10s",
                        "-s", script, f"http://127.0.0.1:{port}"], capture_output=True, text=True, check=True)
    if r.stderr.strip():  # a Lua error makes wrk fall back to GET / silently
        raise RuntimeError(f"wrk: {r.stderr.strip()}")
    out = r.stdout
    rps = float(re.search(r"Requests/sec:\s+([\d.]+)", out).group(1))
    total = int(re.search(r"(\d+) requests in", out).group(1))
    non2xx = int(m.group(1)) if (m := re.search(r"Non-2xx or 3xx responses: (\d+)", out)) else 0
    sock = re.search(r"Socket errors: connect (\d+), read (\d+), write (\d+), timeout (\d+)", out)
    errors = sum(int(x) for x in sock.groups()) if sock else 0
    lat = re.search(r"Latency\s+([\d.]+\w+)", out).group(1)
    return {"requests": total, "rps": rps, "non2xx": non2xx, "socket_errors": errors, "mean_latency": lat}


def cache_stats(lines):
    st = [m.group(1) for ln in lines if (m := re.search(r" cache=(\S+) ", ln))]
    cached = [s for s in st if s != "-"]
    hits = sum(s == "HIT" for s in cached)
    return {"cacheable": len(cached), "hits": hits, "hit_ratio": round(hits / len(cached), 3) if cached else None}


def fleet_counts(replicas):
    """{port: (tile renders, ID-buffer hits, ID-buffer misses)} from each live replica."""
    out = {}
    for r in replicas:
        if r.proc.poll() is None:
            m = r.metrics()
            out[r.port] = (metric_sum(m, "geoslice_render_duration_seconds_count", 'kind="tile"'),
                           metric_sum(m, "geoslice_cache_total", 'cache="ids",result="hit"'),
                           metric_sum(m, "geoslice_cache_total", 'cache="ids",result="miss"'))
    return out


def fleet_runs(binary, nginx, work, workers):
    """The fleet workloads (see the module's doc); returns their results."""
    import random

    from scale_out import Fleet

    runs = []
    plane_n = 0
    for n, balance, event in ((3, "round-robin", None), (3, "hash", None), (5, "round-robin", None),
                              (5, "hash", None), (5, "hash", "kill"), (5, "hash", "add")):
        lb = Balancer(free_port(), work, nginx, balance=balance, cache=False)
        lb.configure([])
        lb.start()
        args = ["--workers", str(workers), "--http-threads", "32", "--log-level", "warn", "--cache-mib", "1024"]
        fleet = Fleet(binary, None, work, args, lb)
        try:
            fleet.add(n)
            plane_n += 1
            _, _, body = http_get(lb.port, "/v1/models/demo/sections", method="POST",
                                  body=json.dumps({"plane": f"0,1,0,-{3388846 + 3 * plane_n}"}),
                                  headers={"Content-Type": "application/json"})
            sid = json.loads(body)["sid"]
            tiles = [f"/v1/sections/{sid}/tiles/5/{k % 32}/{k // 32}.png" for k in range(256)]
            paths = tiles * 32
            random.Random(plane_n).shuffle(paths)
            before = fleet_counts(fleet.replicas)
            gone = {}

            def kill():
                victim = fleet.in_list[1]
                gone.update(fleet_counts([victim]))  # its renders so far (read just before it dies)
                victim.kill(signal.SIGKILL)

            def add():
                fleet.add(1)

            at_third = {"kill": kill, "add": add}.get(event)

            def progress(done):
                if at_third and done == len(paths) // 3:
                    threading.Thread(target=at_third).start()

            load0 = os.getloadavg()[0]
            t0 = time.monotonic()
            resent = []
            results = [status for _, status in run_load(lb.port, paths, on_progress=progress, stale_retries=resent)]
            seconds = time.monotonic() - t0
            after = fleet_counts(fleet.replicas)
            after.update(gone)
            renders = sum(after[p][0] - before.get(p, (0, 0, 0))[0] for p in after)
            failed = [x for x in results if x != 200]
            run = {"replicas": n, "balance": balance, "event": event, "requests": len(results),
                   "distinct_tiles": len(tiles), "tile_renders": int(renders),
                   "fleet_hit_ratio": round(1 - renders / len(results), 4), "ideal": round(1 - 1 / 32, 4),
                   "failed": len(failed), "failed_examples": failed[:3],
                   "resent_after_an_idle_close": len(resent), "seconds": round(seconds, 2),
                   "load": load0}
            if event is None:
                # Views: a section image, then 16 pixel queries of that view.
                before = fleet_counts(fleet.replicas)
                vpaths = []
                for v in range(32):
                    view = f"plane=0,1,0,-{3387100 + 97 * v + plane_n}&size=256x128"
                    vpaths.append(f"/v1/models/demo/section.png?{view}")
                    vpaths += [f"/v1/models/demo/query?{view}&px={(7 * q) % 256}&py={(11 * q) % 128}"
                               for q in range(16)]
                qfailed = [x for _, x in run_load(lb.port, vpaths, threads=1) if x != 200]
                after = fleet_counts(fleet.replicas)
                hits = sum(after[p][1] - before[p][1] for p in after)
                misses = sum(after[p][2] - before[p][2] for p in after)
                run.update({"queries": 32 * 16, "queries_on_a_cached_id_buffer": int(hits),
                            "queries_without": int(misses), "query_failed": len(qfailed)})
            runs.append(run)
            print(json.dumps(run), file=sys.stderr, flush=True)
        finally:
            lb.stop()
            fleet.stop()
    return runs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "geoslice"))
    ap.add_argument("--seconds", type=int, default=5)
    ap.add_argument("--connections", type=int, default=8)
    ap.add_argument("--workers", type=int, default=1, help="render workers per replica")
    ap.add_argument("--only", choices=("throughput", "fleet"), help="one part only")
    a = ap.parse_args()
    nginx = shutil.which("nginx") or "/usr/sbin/nginx"
    work = tempfile.mkdtemp(prefix="geoslice-bench-")
    if a.only == "fleet":
        result = {"machine": {"cores": os.cpu_count(), "load_before": os.getloadavg()},
                  "fleet": fleet_runs(os.path.abspath(a.binary), nginx, work, a.workers)}
        result["machine"]["load_after"] = os.getloadavg()
        shutil.rmtree(work, ignore_errors=True)
        print(json.dumps(result, indent=1))
        return
    args = ["--workers", str(a.workers), "--http-threads", "32", "--log-level", "warn"]
    replicas = [Replica(os.path.abspath(a.binary), free_port(), work, args).start() for _ in range(3)]
    lb = Balancer(free_port(), work, nginx)
    result = {"machine": {"cores": os.cpu_count(), "load_before": os.getloadavg()}, "seconds": a.seconds,
              "connections": a.connections, "workers_per_replica": a.workers, "runs": []}
    try:
        for r in replicas:
            r.wait_ready()
        lb.configure([replicas[0].port])
        lb.start()
        status, _, body = http_get(lb.port, "/v1/models/demo/sections", method="POST",
                                   body=json.dumps({"plane": "0,1,0,-3388846"}),
                                   headers={"Content-Type": "application/json"})
        sid = json.loads(body)["sid"]
        salt = 0
        for k in (1, 2, 3):
            lb.reload([r.port for r in replicas[:k]])
            for mode in ("new_sections", "cached_tiles", "mixed"):
                salt += 1
                if mode == "cached_tiles":  # warm the 64 tiles
                    for i in range(64):
                        http_get(lb.port, f"/v1/sections/{sid}/tiles/5/{i % 32}/{i // 32}.png")
                before = len(lb.access_log())
                run = {"replicas": k, "mode": mode, "load": os.getloadavg()[0]}
                run.update(wrk(lb.port, mode, sid, salt, a.seconds, a.connections, work))
                run.update(cache_stats(lb.access_log()[before:]))
                result["runs"].append(run)
                print(json.dumps(run), file=sys.stderr, flush=True)
            # the mixed run cached up to 400 tiles: a new section id for the next k
            status, _, body = http_get(lb.port, "/v1/models/demo/sections", method="POST",
                                       body=json.dumps({"plane": f"0,1,0,-{3388846 + k}"}),
                                       headers={"Content-Type": "application/json"})
            sid = json.loads(body)["sid"]
        # A replica killed a third into a new_sections run with 3 replicas.
        victim = replicas[2]
        timer = threading.Timer(a.seconds / 3, lambda: victim.kill(signal.SIGKILL))
        before = len(lb.access_log())
        timer.start()
        run = {"replicas": 3, "mode": "new_sections, one replica SIGKILLed", "load": os.getloadavg()[0]}
        run.update(wrk(lb.port, "new_sections", sid, 99, a.seconds, a.connections, work))
        timer.join()
        lines = lb.access_log()[before:]
        run["retried_on_another_replica"] = sum(len(upstream_tries(ln)) > 1 for ln in lines)
        run["answered_5xx"] = sum(bool(re.search(r'HTTP/1\.1" 5\d\d ', ln)) for ln in lines)
        result["runs"].append(run)
        print(json.dumps(run), file=sys.stderr, flush=True)
        if a.only != "throughput":
            result["fleet"] = fleet_runs(os.path.abspath(a.binary), nginx, work, a.workers)
        result["machine"]["load_after"] = os.getloadavg()
    finally:
        lb.stop()
        for r in replicas:
            r.kill(signal.SIGTERM)
        shutil.rmtree(work, ignore_errors=True)
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
