#!/usr/bin/env python3
"""geoslice replicas behind Debian's nginx on loopback.

    python3 deploy/scale_out.py --replicas 3 --port 8000 [--binary build/cli/geoslice] [-- SERVE ARGS]

starts N `geoslice serve` processes on 127.0.0.1:PORT+1..PORT+N, adds each one to the
nginx upstream list once its /readyz answers 200 (as Kubernetes adds ready endpoints),
and runs nginx on 127.0.0.1:PORT with deploy/nginx/geoslice.conf (round robin, passive
health checks, retries, a cache for images and tiles). Ctrl-C stops everything. State
(nginx prefix, cache, logs, replica logs) goes to build/scale-out/ (--dir).
tests/deploy/scale_out_test.py drives the same classes.
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
    """nginx on 127.0.0.1:port with deploy/nginx/geoslice.conf, prefix DIR/nginx."""

    def __init__(self, port, run_dir, nginx="nginx"):
        self.port, self.nginx = port, nginx
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


def upstream_tries(log_line):
    """[(replica address, its status)] for one access-log line, in the order nginx tried
    them (a retried request lists several); [] when the cache answered."""
    m = re.search(r" upstream=(.*) ustatus=(.*)$", log_line)
    if not m or m.group(1) == "-":
        return []
    return list(zip([a.strip() for a in m.group(1).split(",")], [s.strip() for s in m.group(2).split(",")]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--replicas", type=int, default=3)
    ap.add_argument("--port", type=int, default=8000, help="nginx port; replicas use PORT+1..PORT+N")
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "cli", "geoslice"))
    ap.add_argument("--dir", default=os.path.join(REPO, "build", "scale-out"))
    ap.add_argument("serve_args", nargs="*", help="after --: extra `geoslice serve` arguments")
    a = ap.parse_args()

    def stop(*_):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, stop)
    if shutil.which("nginx") is None and not os.path.exists("/usr/sbin/nginx"):
        sys.exit("scale_out: nginx is not installed (apt-get install nginx-light)")
    os.makedirs(a.dir, exist_ok=True)
    replicas = [Replica(a.binary, a.port + 1 + i, a.dir, a.serve_args).start() for i in range(a.replicas)]
    lb = Balancer(a.port, a.dir, shutil.which("nginx") or "/usr/sbin/nginx")
    lb.configure([])
    lb.start()
    print(f"scale_out: nginx on http://127.0.0.1:{a.port}/ (logs in {a.dir}); Ctrl-C stops", flush=True)
    try:
        ready = []
        for r in replicas:
            s = r.wait_ready()
            ready.append(r.port)
            lb.reload(ready)
            print(f"scale_out: replica 127.0.0.1:{r.port} ready after {s:.1f} s, in the upstream", flush=True)
        while True:
            signal.pause()
    except KeyboardInterrupt:
        pass
    finally:
        lb.stop()
        for r in replicas:
            r.kill(signal.SIGTERM)


if __name__ == "__main__":
    main()
