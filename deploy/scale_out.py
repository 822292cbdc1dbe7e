#!/usr/bin/env python3
"""geoslice replicas behind Debian's nginx on loopback.

    python3 deploy/scale_out.py --replicas 3 --port 8000 [--binary build/cli/geoslice] [-- SERVE ARGS]

starts N `geoslice serve` processes on 127.0.0.1:PORT+1..PORT+N, adds each one to the
nginx upstream list once its /readyz answers 200 (as Kubernetes adds ready endpoints),
and runs nginx on 127.0.0.1:PORT with deploy/nginx/geoslice.conf (consistent hashing by
URL, passive health checks, retries, a cache for images and tiles). A replica that dies is
taken out of the list, started again, and put back once ready (as a Deployment does).
Ctrl-C stops everything. State (nginx prefix, cache, logs, replica logs) goes to
build/scale-out/ (--dir). tests/deploy/scale_out_test.py and deploy/bench_scale_out.py
drive the same classes.
"""
import argparse
import http.client
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def http_get(port, path, timeout=10.0, headers=None, method="GET", body=None):
    """One request to 127.0.0.1:port; returns (status, headers dict lower-case, body bytes)."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        conn.request(method, path, body=body, headers=headers or {})
        r = conn.getresponse()
        data = r.read()
        return r.status, {k.lower(): v for k, v in r.getheaders()}, data
    finally:
        conn.close()


def free_port():
    """A TCP port on 127.0.0.1 that nothing listens on right now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_load(port, paths, threads=4, on_progress=None, stale_retries=None):
    """GET every path once through 127.0.0.1:port from `threads` keep-alive clients;
    returns [(path, status or exception text)] in completion order.
    stale_retries: a list; when given, a request on a reused keep-alive connection that the
    server closed before answering anything (RemoteDisconnected, a reset, a broken pipe) is
    sent again once on a new connection, as browsers and HTTP libraries do for idempotent
    requests (RFC 9110 9.2.2), and its path is appended to the list. nginx closes its idle
    keep-alive connections when it reloads its configuration (a replica added or removed),
    and a request may cross that close on the wire. Otherwise a failed request is reported,
    never retried."""
    results, lock, it = [], threading.Lock(), iter(paths)
    stale = (http.client.RemoteDisconnected, ConnectionResetError, BrokenPipeError)

    def client():
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        used = False  # the connection has carried a whole exchange
        while True:
            with lock:
                path = next(it, None)
            if path is None:
                break
            for attempt in (0, 1):
                try:
                    conn.request("GET", path)
                    r = conn.getresponse()
                    r.read()
                    out = r.status
                    used = True
                    if r.getheader("Connection", "").lower() == "close":
                        conn.close()
                        used = False
                    break
                except Exception as e:
                    out = f"{type(e).__name__}: {e}"
                    conn.close()
                    retry = stale_retries is not None and used and attempt == 0 and isinstance(e, stale)
                    used = False
                    if not retry:
                        break
                    with lock:
                        stale_retries.append(path)
            with lock:
                results.append((path, out))
                n = len(results)
            if on_progress:
                on_progress(n)
        conn.close()

    ts = [threading.Thread(target=client) for _ in range(threads)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    return results


class Replica:
    """One `geoslice serve` on 127.0.0.1:port; logs to DIR/replica-PORT.log."""

    def __init__(self, binary, port, run_dir, serve_args=()):
        self.binary, self.port, self.run_dir = binary, port, run_dir
        self.serve_args = list(serve_args)
        self.proc = None
        self.log_path = os.path.join(run_dir, f"replica-{port}.log")

    def start(self):
        log = open(self.log_path, "ab")
        cmd = [self.binary, "serve", "--host", "127.0.0.1", "--port", str(self.port)] + self.serve_args
        self.proc = subprocess.Popen(cmd, stdout=log, stderr=log, stdin=subprocess.DEVNULL)
        log.close()
        return self

    def ready(self):
        try:
            return http_get(self.port, "/readyz", timeout=2)[0] == 200
        except OSError:
            return False

    def wait_ready(self, timeout=120.0):
        t0 = time.monotonic()
        while time.monotonic() - t0 < timeout:
            if self.proc.poll() is not None:
                raise RuntimeError(f"replica {self.port} exited with {self.proc.returncode}: see {self.log_path}")
            if self.ready():
                return time.monotonic() - t0
            time.sleep(0.05)
        raise TimeoutError(f"replica {self.port} not ready after {timeout} s: see {self.log_path}")

    def kill(self, sig=signal.SIGKILL):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(sig)
        return self.proc.wait(timeout=60) if self.proc else None

    def metrics(self):
        return http_get(self.port, "/metrics")[2].decode()


class Balancer:
    """nginx on 127.0.0.1:port with deploy/nginx/geoslice.conf, prefix DIR/nginx.
    balance: "hash" (the file as shipped: consistent hashing on the routing key) or
    "round-robin" (its `hash` line dropped, for comparison); cache False drops nginx's own
    proxy_cache, so every request reaches a replica (to measure the replicas' caches)."""

    def __init__(self, port, run_dir, nginx="nginx", balance="hash", cache=True):
        if balance not in ("hash", "round-robin"):
            raise ValueError(f"balance '{balance}' is not hash or round-robin")
        self.port, self.nginx, self.balance, self.cache = port, nginx, balance, cache
        self.prefix = os.path.join(run_dir, "nginx")
        self.proc = None

    def _ctl(self, *args):
        return [self.nginx, "-p", self.prefix + "/", "-c", os.path.join(self.prefix, "nginx.conf"),
                "-e", os.path.join(self.prefix, "error.log")] + list(args)

    def configure(self, upstream_ports, fail_timeout_s=5):
        for d in ("tmp", "geoslice-cache"):
            os.makedirs(os.path.join(self.prefix, d), exist_ok=True)
        if os.geteuid() == 0:
            # nginx started as root runs its workers as `nobody`: they write the cache and
            # temp files, and must reach them.
            import pwd

            nobody = pwd.getpwnam("nobody")
            for d in (os.path.dirname(self.prefix), self.prefix):
                os.chmod(d, os.stat(d).st_mode | 0o755)
            for d in ("tmp", "geoslice-cache"):
                os.chown(os.path.join(self.prefix, d), nobody.pw_uid, nobody.pw_gid)
        shutil.copy(os.path.join(HERE, "nginx", "nginx-local.conf"), os.path.join(self.prefix, "nginx.conf"))
        with open(os.path.join(HERE, "nginx", "geoslice.conf")) as f:
            conf = f.read().replace("listen 127.0.0.1:8000;", f"listen 127.0.0.1:{self.port};")
        if self.balance == "round-robin":
            conf = "\n".join(ln for ln in conf.split("\n") if "# geoslice-balance:" not in ln)
        if not self.cache:
            conf = conf.replace("proxy_cache geoslice;", "proxy_cache off;")
        with open(os.path.join(self.prefix, "geoslice.conf"), "w") as f:
            f.write(conf)
        lines = [f"server 127.0.0.1:{p} max_fails=1 fail_timeout={fail_timeout_s}s;\n" for p in upstream_ports]
        if not lines:  # nginx needs one server; a closed port answers 502 until replicas are ready
            lines = ["server 127.0.0.1:1 down;\n"]
        with open(os.path.join(self.prefix, "geoslice-upstreams.conf"), "w") as f:
            f.writelines(lines)
        subprocess.run(self._ctl("-t", "-q"), check=True)

    def start(self):
        self.proc = subprocess.Popen(self._ctl(), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        t0 = time.monotonic()
        while time.monotonic() - t0 < 10:
            try:
                http_get(self.port, "/healthz", timeout=1)
                return self
            except OSError:
                time.sleep(0.05)
        raise TimeoutError(f"nginx did not listen on {self.port}")

    def reload(self, upstream_ports, fail_timeout_s=5):
        self.configure(upstream_ports, fail_timeout_s)
        subprocess.run(self._ctl("-s", "reload"), check=True)
        time.sleep(0.3)  # old workers finish, new ones take over

    def clear_cache(self):
        """Empties the cache (the running nginx keeps its key zone: use between runs only)."""
        d = os.path.join(self.prefix, "geoslice-cache")
        for e in os.listdir(d) if os.path.isdir(d) else []:
            shutil.rmtree(os.path.join(d, e), ignore_errors=True)

    def access_log(self):
        """Lines of the access log (format `geoslice` in deploy/nginx/geoslice.conf)."""
        path = os.path.join(self.prefix, "geoslice-access.log")
        if not os.path.exists(path):
            return []
        with open(path) as f:
            return f.read().splitlines()

    def stop(self):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGQUIT)  # graceful
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


def metric_sum(text, name, label=""):
    """Sum of a Prometheus sample family's values in `text` whose labels contain `label`."""
    total = 0.0
    for ln in text.splitlines():
        if ln.startswith(name) and (ln[len(name)] in " {") and label in ln:
            total += float(ln.rsplit(" ", 1)[1])
    return total


def upstream_tries(log_line):
    """[(replica address, its status)] for one access-log line, in the order nginx tried
    them (a retried request lists several); [] when the cache answered."""
    m = re.search(r" upstream=(.*) ustatus=(.*)$", log_line)
    if not m or m.group(1) == "-":
        return []
    return list(zip([a.strip() for a in m.group(1).split(",")], [s.strip() for s in m.group(2).split(",")]))


class Fleet:
    """Replicas behind a Balancer, kept as a Deployment keeps them: a replica that dies is
    taken out of the upstream list, started again on its port, and put back once ready.
    add() and remove() change the fleet's size (the list is reloaded gracefully)."""

    def __init__(self, binary, first_port, run_dir, serve_args, balancer):
        """first_port: replicas on first_port, first_port + 1, ...; None: each on a port free
        when it starts (tests and benchmarks, beside other servers)."""
        self.binary, self.run_dir, self.serve_args, self.lb = binary, run_dir, list(serve_args), balancer
        self.next_port = first_port
        self.replicas, self.in_list = [], []
        self.restarts = 0

    def _reload(self):
        self.lb.reload([r.port for r in self.in_list])

    def add(self, n=1, timeout=120.0, log=None):
        """Starts n more replicas at once and puts each in the list as it becomes ready;
        returns them."""
        if self.next_port is None:
            ports = [free_port() for _ in range(n)]
        else:
            ports = list(range(self.next_port, self.next_port + n))
            self.next_port += n
        new = [Replica(self.binary, p, self.run_dir, self.serve_args).start() for p in ports]
        self.replicas += new
        t0 = time.monotonic()
        for r in new:
            r.wait_ready(timeout)
            self.in_list.append(r)
            self._reload()
            if log:
                log(f"scale_out: replica 127.0.0.1:{r.port} ready after {time.monotonic() - t0:.1f} s, in the upstream")
        return new

    def remove(self, r, sig=signal.SIGTERM):
        """Takes r out of the list first (nginx sends it nothing new), then stops it."""
        if r in self.in_list:
            self.in_list.remove(r)
            self._reload()
        r.kill(sig)
        self.replicas.remove(r)

    def supervise_once(self, log=print):
        """Restarts replicas that died; returns how many."""
        dead = [r for r in self.replicas if r.proc.poll() is not None]
        for r in dead:
            code = r.proc.returncode
            if r in self.in_list:
                self.in_list.remove(r)
                self._reload()
            r.start()
            r.wait_ready()
            self.in_list.append(r)
            self._reload()
            self.restarts += 1
            log(f"scale_out: replica 127.0.0.1:{r.port} exited with {code}; started again, back in the upstream")
        return len(dead)

    def stop(self):
        for r in self.replicas:
            r.kill(signal.SIGTERM)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--replicas", type=int, default=3)
    ap.add_argument("--port", type=int, default=8000, help="nginx port; replicas use PORT+1..PORT+N")
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "geoslice"))
    ap.add_argument("--dir", default=os.path.join(REPO, "build", "scale-out"))
    ap.add_argument("--balance", choices=("hash", "round-robin"), default="hash",
                    help="hash: consistent hashing by URL, one render per tile across the fleet (default)")
    ap.add_argument("serve_args", nargs="*", help="after --: extra `geoslice serve` arguments")
    a = ap.parse_args()

    def stop(*_):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, stop)
    if shutil.which("nginx") is None and not os.path.exists("/usr/sbin/nginx"):
        sys.exit("scale_out: nginx is not installed (apt-get install nginx-light)")
    os.makedirs(a.dir, exist_ok=True)
    lb = Balancer(a.port, a.dir, shutil.which("nginx") or "/usr/sbin/nginx", balance=a.balance)
    lb.configure([])
    lb.start()
    fleet = Fleet(a.binary, a.port + 1, a.dir, a.serve_args, lb)
    print(f"scale_out: nginx on http://127.0.0.1:{a.port}/ ({a.balance}; logs in {a.dir}); Ctrl-C stops", flush=True)
    try:
        fleet.add(a.replicas, log=lambda m: print(m, flush=True))
        while True:
            time.sleep(1)
            fleet.supervise_once(lambda m: print(m, flush=True))
    except KeyboardInterrupt:
        pass
    finally:
        lb.stop()
        fleet.stop()


if __name__ == "__main__":
    main()
