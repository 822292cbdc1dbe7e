#!/usr/bin/env python3
"""Three geoslice replicas behind Debian's nginx on 127.0.0.1 (CTest label deploy).

Uses deploy/scale_out.py (the launcher) and deploy/nginx/geoslice.conf (the config under
test). Loads are bounded (a few hundred small requests, 4 client threads) and go to
127.0.0.1 only. Exit 77 (CTest skip) when nginx is not installed.
    python3 tests/deploy/scale_out_test.py --binary build/cli/geoslice
"""
import argparse
import json
import os
import shutil
import signal
import socket
import sys
import tempfile
import threading
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "deploy"))
from scale_out import Balancer, Replica, free_port, http_get, metric_sum, run_load, upstream_tries  # noqa: E402

BINARY = None
NGINX = shutil.which("nginx") or ("/usr/sbin/nginx" if os.path.exists("/usr/sbin/nginx") else None)
PLANE = "0,1,0,-3388846"


def new_section(i, salt=0):
    """A section image no one asked for before: a plane at a new northing (the demo model
    spans 3386846..3390846 m; i < 6000, salt < 50)."""
    return f"/v1/models/demo/section.jpg?plane=0,1,0,-{3387000 + 0.5 * i + 0.01 * salt:.2f}&size=256x128"


class CrashingUpstream:
    """A stand-in replica on 127.0.0.1 that dies on every request: it reads the whole request
    (head and Content-Length body), counts it, then resets the connection without answering,
    as a replica killed by that request would. `answer` instead makes it answer 201."""

    def __init__(self, answer=False):
        self.sock = socket.socket()
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(16)
        self.port = self.sock.getsockname()[1]
        self.answer, self.seen, self.lock = answer, [], threading.Lock()
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self):
        import struct

        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            with conn:
                conn.settimeout(5)
                data = b""
                try:
                    while b"\r\n\r\n" not in data:
                        chunk = conn.recv(65536)
                        if not chunk:
                            break
                        data += chunk
                    head, _, body = data.partition(b"\r\n\r\n")
                    length = 0
                    for line in head.split(b"\r\n")[1:]:
                        k, _, v = line.partition(b":")
                        if k.strip().lower() == b"content-length":
                            length = int(v.strip())
                    while len(body) < length:
                        chunk = conn.recv(65536)
                        if not chunk:
                            break
                        body += chunk
                except OSError:
                    continue
                if not head:
                    continue
                with self.lock:
                    self.seen.append(head.split(b"\r\n")[0].decode())
                if self.answer:
                    conn.sendall(b"HTTP/1.1 201 Created\r\nContent-Length: 2\r\nConnection: close\r\n\r\n{}")
                else:  # RST, no answer: the process died
                    conn.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))

    def close(self):
        # shutdown wakes the thread blocked in accept(); a bare close() would leave it to
        # accept on whatever socket reuses the descriptor (another test's stand-in).
        try:
            self.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self.thread.join(timeout=10)
        self.sock.close()


class Retries(unittest.TestCase):
    """deploy/nginx/geoslice.conf's proxy_next_upstream: a request that kills the replica it
    reached is not replayed into every other replica (it was, 3 times, with non_idempotent)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="geoslice-retries-")
        self.upstreams = []
        self.lb = None

    def tearDown(self):
        if self.lb:
            self.lb.stop()
        for u in self.upstreams:
            u.close()
        shutil.rmtree(self.dir, ignore_errors=True)

    def seen(self, prefix):
        """How many times the stand-in replicas received a request line starting with `prefix`
        (Balancer.start's own /healthz probes are not counted)."""
        return sum(line.startswith(prefix) for u in self.upstreams for line in u.seen)

    def balance(self, ports):
        self.lb = Balancer(free_port(), self.dir, NGINX)
        self.lb.configure(ports)
        self.lb.start()
        # start() probes /healthz, which the stand-ins fail: new workers forget those marks.
        self.lb.reload(ports)
        return self.lb.port

    def test_a_request_that_kills_replicas_reaches_at_most_two_and_a_post_one(self):
        self.upstreams = [CrashingUpstream() for _ in range(3)]
        port = self.balance([u.port for u in self.upstreams])
        status, _, _ = http_get(port, "/v1/models/demo/sections", method="POST", body='{"plane": "0,1,0,-5"}',
                                headers={"Content-Type": "application/json"})
        self.assertEqual(status, 502)
        posts = self.seen("POST /v1/models/demo/sections")
        self.assertEqual(posts, 1, "a POST that was sent is never replayed")
        self.lb.reload([u.port for u in self.upstreams])  # forget the failure marks
        status, _, _ = http_get(port, "/v1/models/demo/section.png?plane=0,1,0,-7")
        self.assertEqual(status, 502)
        gets = self.seen("GET /v1/models/demo/section.png")
        self.assertEqual(gets, 2, "a GET that killed a replica is tried on one more, not on all")
        print(f"a request that kills its replica: POST reached {posts} replica, GET {gets} of 3")

    def test_a_post_that_was_never_sent_goes_to_another_replica(self):
        good = CrashingUpstream(answer=True)
        self.upstreams = [good]
        dead = free_port()  # nothing listens: the connection is refused before anything is sent
        port = self.balance([dead, good.port])
        for i in range(4):  # round robin starts on either; every POST ends on the live one
            status, _, body = http_get(port, "/v1/models/demo/sections", method="POST",
                                       body=json.dumps({"plane": f"0,1,0,-{i}"}),
                                       headers={"Content-Type": "application/json"})
            self.assertEqual(status, 201, body)
        self.assertEqual(self.seen("POST /v1/models/demo/sections"), 4)


class KeysThroughNginx(unittest.TestCase):
    """A replica with API keys behind deploy/nginx/geoslice.conf: nginx passes Authorization
    and X-Api-Key through, never stores or serves a keyed answer from its cache, never
    answers a request without a key from the cache, and logs no key."""

    KEY = "k3yThr0ughNg1nx-0123456789abcdef"

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="geoslice-keys-")
        keys = os.path.join(cls.dir, "keys")
        with open(keys, "w") as f:
            f.write(f"viewer {cls.KEY} demo\n")
        cls.replica = Replica(BINARY, free_port(), cls.dir, ["--workers", "1", "--demo-triangles", "20000",
                                                              "--keys", keys]).start()
        cls.lb = Balancer(free_port(), cls.dir, NGINX)
        try:
            cls.replica.wait_ready()
            cls.lb.configure([cls.replica.port])
            cls.lb.start()
        except Exception:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        try:
            cls.lb.stop()
        finally:
            cls.replica.kill(signal.SIGTERM)
            shutil.rmtree(cls.dir, ignore_errors=True)

    def test_keyed_answers_pass_through_and_are_never_cached(self):
        path = f"/v1/models/demo/section.png?plane={PLANE}&size=128x64"
        answers = [http_get(self.lb.port, path, headers=h) for h in
                   ({"Authorization": f"Bearer {self.KEY}"}, {"Authorization": f"Bearer {self.KEY}"},
                    {"X-Api-Key": self.KEY})]
        for status, headers, body in answers:
            self.assertEqual(status, 200, body[:200])
            self.assertNotEqual(headers.get("x-cache-status"), "HIT")
            self.assertTrue(headers.get("cache-control", "").startswith("private"), headers)
        for headers in ({}, {"Authorization": "Bearer not-a-key-of-this-server"}):
            status, h, _ = http_get(self.lb.port, path, headers=headers)
            self.assertEqual(status, 401, "no cached image for a request without a valid key")
            self.assertNotEqual(h.get("x-cache-status"), "HIT")
            self.assertTrue(h.get("www-authenticate", "").startswith("Bearer"))
        log = "\n".join(self.lb.access_log())
        self.assertIn("section.png", log)
        self.assertNotIn(self.KEY, log, "nginx logs no key")
        with open(self.replica.log_path) as f:
            self.assertNotIn(self.KEY, f.read(), "the replica logs no key")


class RebakeBehindNginx(unittest.TestCase):
    """A model changes under a replica behind nginx's cache (deploy/nginx/geoslice.conf): the
    replica re-bakes it on restart, GET /v1/models/{id} names the new version, and a URL
    pinned to it (version=) gets the new picture at once, through the cache; a URL pinned to
    the old version still names the old picture (cached for a year, immutable), never a new
    one; the replica answers a stale pin with 404; an unpinned URL is cached a minute only."""

    def generate(self, seed):
        import subprocess
        subprocess.run([BINARY, "generate", "--triangles", "20000", "--seed", str(seed), "--crs", "EPSG:4523",
                        "--out", os.path.join(self.models, "mine.glb")], check=True, capture_output=True)

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="geoslice-rebake-")
        self.models = os.path.join(self.dir, "models")
        os.makedirs(self.models)
        self.generate(1)
        self.args = ["--workers", "1", "--models", self.models, "--bake-dir", os.path.join(self.dir, "bake")]
        self.replica = Replica(BINARY, free_port(), self.dir, self.args).start()
        self.lb = Balancer(free_port(), self.dir, NGINX)
        self.replica.wait_ready()
        self.lb.configure([self.replica.port])
        self.lb.start()

    def tearDown(self):
        try:
            self.lb.stop()
        finally:
            self.replica.kill(signal.SIGTERM)
            shutil.rmtree(self.dir, ignore_errors=True)

    def version(self):
        status, _, body = http_get(self.lb.port, "/v1/models/mine")
        self.assertEqual(status, 200, body[:200])
        return json.loads(body)["version"]

    def test_a_rebaked_model_gets_new_urls_and_never_a_stale_picture(self):
        m = json.loads(http_get(self.lb.port, "/v1/models/mine")[2])
        y = 0.5 * (m["bounds"]["min"][1] + m["bounds"]["max"][1])
        image = f"/v1/models/mine/section.png?plane=0,1,0,{-y:.3f}&size=256x128"
        v1 = self.version()
        status, h, old = http_get(self.lb.port, f"{image}&version={v1}")
        self.assertEqual(status, 200, old[:200])
        self.assertEqual(h["cache-control"], "public, max-age=31536000, immutable")
        self.assertEqual(http_get(self.lb.port, f"{image}&version={v1}")[1].get("x-cache-status"), "HIT")
        status, h, plain = http_get(self.lb.port, image)
        self.assertEqual((status, h["cache-control"]), (200, "public, max-age=60"))
        # The model changes; the replica restarts and re-bakes it.
        self.replica.kill(signal.SIGTERM)
        self.generate(2)
        self.replica = Replica(BINARY, self.replica.port, self.dir, self.args).start()
        self.replica.wait_ready()
        v2 = self.version()
        self.assertNotEqual(v1, v2, "a changed model has a new version")
        status, h, new = http_get(self.lb.port, f"{image}&version={v2}")
        self.assertEqual(status, 200, new[:200])
        self.assertNotEqual(h.get("x-cache-status"), "HIT", "a new version is a new URL: never in the cache")
        self.assertNotEqual(new, old, "the re-baked model draws another picture")
        # The old pin names the old picture: from the cache, or 404 from the replica; never new.
        status, h, again = http_get(self.lb.port, f"{image}&version={v1}")
        self.assertTrue((status == 200 and again == old) or status == 404, (status, h))
        status, _, body = http_get(self.replica.port, f"{image}&version={v1}")
        self.assertEqual(status, 404)
        self.assertIn(b"model_version", body)


class FleetRouting(unittest.TestCase):
    """deploy/nginx/geoslice.conf's consistent hashing, with nginx's own cache off (as behind
    several cache-tier pods, each with its own cache): each tile is rendered by one replica of
    the fleet, a pixel query reaches the replica that rendered its view, and a replica killed
    or added under load loses no request."""

    @classmethod
    def setUpClass(cls):
        from scale_out import Fleet

        cls.dir = tempfile.mkdtemp(prefix="geoslice-fleet-")
        cls.lb = Balancer(free_port(), cls.dir, NGINX, balance="hash", cache=False)
        cls.fleet = Fleet(BINARY, None, cls.dir, ["--workers", "1", "--http-threads", "16"], cls.lb)
        try:
            cls.lb.configure([])
            cls.lb.start()
            cls.fleet.add(3)
        except Exception:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        try:
            cls.lb.stop()
        finally:
            cls.fleet.stop()
            shutil.rmtree(cls.dir, ignore_errors=True)

    def counts(self, family, label):
        return sum(metric_sum(r.metrics(), family, label) for r in self.fleet.in_list)

    def new_tiles(self, plane_offset, n):
        status, _, body = http_get(self.lb.port, "/v1/models/demo/sections", method="POST",
                                   body=json.dumps({"plane": f"0,1,0,-{3388846 + plane_offset}"}),
                                   headers={"Content-Type": "application/json"})
        self.assertIn(status, (200, 201), body)
        sid = json.loads(body)["sid"]
        return [f"/v1/sections/{sid}/tiles/4/{k % 16}/{k // 16}.png" for k in range(n)]

    def test_each_tile_is_rendered_once_in_the_fleet(self):
        import random

        tiles = self.new_tiles(11, 48)
        paths = tiles * 6
        random.Random(1).shuffle(paths)
        renders0 = self.counts("geoslice_render_duration_seconds_count", 'kind="tile"')
        before = len(self.lb.access_log())
        results = run_load(self.lb.port, paths, threads=4)
        self.assertEqual([(p, s) for p, s in results if s != 200], [])
        renders = self.counts("geoslice_render_duration_seconds_count", 'kind="tile"') - renders0
        # A request nginx passed on to another replica (its owner's connection failed: an idle
        # upstream keep-alive connection closed as it was reused) is rendered there too: the
        # only allowed exception, counted from the access log.
        owners, moved = {}, set()
        for ln in self.lb.access_log()[before:]:
            path = ln.split('"')[1].split(" ")[1]
            tries = upstream_tries(ln)
            if len(tries) > 1:
                moved.add(path)
                continue
            owners.setdefault(path, set()).add(tries[-1][0])
        self.assertEqual({p: o for p, o in owners.items() if len(o) > 1}, {}, "one replica per tile")
        self.assertGreater(len({a for o in owners.values() for a in o}), 1, "the tiles spread over the replicas")
        self.assertGreaterEqual(renders, len(tiles))
        self.assertLessEqual(renders, len(tiles) + len(moved), f"each tile rendered once in the fleet ({moved})")
        print(f"fleet: {len(paths)} requests of {len(tiles)} tiles through {len(self.fleet.in_list)} replicas: "
              f"{int(renders)} renders ({len(moved)} requests passed on by nginx), "
              f"fleet hit ratio {1 - renders / len(paths):.3f} (ideal {1 - len(tiles) / len(paths):.3f})")

    def test_a_query_reaches_the_replica_that_rendered_its_view(self):
        hits0 = self.counts("geoslice_cache_total", 'cache="ids",result="hit"')
        misses0 = self.counts("geoslice_cache_total", 'cache="ids",result="miss"')
        before = len(self.lb.access_log())
        for v in range(8):
            view = f"plane=0,1,0,-{3387300 + 311 * v}&size=256x128"
            status, _, body = http_get(self.lb.port, f"/v1/models/demo/section.png?{view}")
            self.assertEqual(status, 200, body[:200])
            for q in range(4):
                status, _, body = http_get(self.lb.port, f"/v1/models/demo/query?{view}&px={30 * q + 7}&py={20 * q + 5}")
                self.assertEqual(status, 200, body[:200])
        hits = self.counts("geoslice_cache_total", 'cache="ids",result="hit"') - hits0
        misses = self.counts("geoslice_cache_total", 'cache="ids",result="miss"') - misses0
        # Only a request nginx passed on to another replica may miss (see the tile test).
        moved = sum(len(upstream_tries(ln)) > 1 for ln in self.lb.access_log()[before:])
        self.assertEqual(hits + misses, 32)
        self.assertLessEqual(misses, moved, "every query found its view's ID buffer")

    def test_a_replica_killed_or_added_under_load_loses_no_request(self):
        victim = self.fleet.in_list[1]
        tiles = self.new_tiles(23, 96)
        results = run_load(self.lb.port, tiles, threads=4,
                           on_progress=lambda n: n == 24 and victim.kill(signal.SIGKILL))
        self.assertIsNotNone(victim.proc.poll(), "the replica was killed during the load")
        self.assertEqual([(p, s) for p, s in results if s != 200], [], "killed: no request lost")
        self.assertEqual(self.fleet.supervise_once(lambda m: None), 1, "the dead replica is started again")
        self.assertTrue(victim.ready())
        # A replica added while the load runs: rounds of new tiles until it is in the list.
        import threading

        errors = []

        def add():
            try:
                self.fleet.add()
            except Exception as e:  # reported below
                errors.append(e)

        grow = threading.Thread(target=add)
        grow.start()
        total, lost, rounds, resent = 0, [], 0, []
        while grow.is_alive() or rounds < 2:
            results = run_load(self.lb.port, self.new_tiles(29 + rounds, 48), threads=4, stale_retries=resent)
            total += len(results)
            lost += [(p, s) for p, s in results if s != 200]
            rounds += 1
        grow.join()
        self.assertEqual(errors, [], "the replica added")
        self.assertEqual(lost, [], "added: no request lost")
        self.assertEqual(len(self.fleet.in_list), 4)
        print(f"fleet: a replica SIGKILLed under load (0 of 96 requests lost), one added under load "
              f"(0 of {total} lost; {len(resent)} sent again by the client on a new connection after nginx's "
              f"reload closed the idle one they were sent on)")


class ScaleOut(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="geoslice-scale-")
        cls.serve_args = ["--workers", "1", "--http-threads", "16"]
        cls.replicas = [Replica(BINARY, free_port(), cls.dir, cls.serve_args).start() for _ in range(3)]
        cls.lb = Balancer(free_port(), cls.dir, NGINX)
        try:
            for r in cls.replicas:
                r.wait_ready()
            cls.lb.configure([r.port for r in cls.replicas])
            cls.lb.start()
        except Exception:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        try:
            cls.lb.stop()
        finally:
            for r in cls.replicas:
                r.kill(signal.SIGTERM)
            shutil.rmtree(cls.dir, ignore_errors=True)

    def sid(self, port, plane=PLANE):
        status, _, body = http_get(port, "/v1/models/demo/sections", method="POST",
                                   body=json.dumps({"plane": plane}),
                                   headers={"Content-Type": "application/json"})
        self.assertIn(status, (200, 201), body)
        return json.loads(body)["sid"]

    def test_a_section_id_from_one_replica_serves_tiles_on_the_others(self):
        a, b, c = self.replicas
        sid = self.sid(a.port)
        self.assertEqual([self.sid(r.port) for r in (b, c)], [sid, sid], "the id is canonical on every replica")
        for tile in ("0/0/0.png", "2/1/1.png", "3/4/2.webp"):
            answers = [http_get(r.port, f"/v1/sections/{sid}/tiles/{tile}") for r in (b, c, a)]
            for status, headers, body in answers:
                self.assertEqual(status, 200, body[:200])
            self.assertEqual(len({body for _, _, body in answers}), 1, tile)
            self.assertEqual(len({h["etag"] for _, h, _ in answers}), 1, tile)

    def test_identical_requests_give_identical_bytes_and_etags(self):
        sid = self.sid(self.replicas[0].port)
        paths = [
            f"/v1/models/demo/section.jpg?plane={PLANE}&size=512x256",
            f"/v1/models/demo/section.png?plane={PLANE}&size=400x200&vx=2",
            f"/v1/models/demo/section.geojson?plane={PLANE}",
            f"/v1/sections/{sid}/tiles/1/0/0.png",
            f"/v1/models/demo/query?plane={PLANE}&size=512x256&px=250&py=150",
            "/v1/models/demo/borehole?x=35504000&y=3388000",
        ]
        for path in paths:
            answers = [http_get(r.port, path) for r in self.replicas]
            answers += [http_get(self.lb.port, path), http_get(self.lb.port, path)]  # a miss, then a hit
            for status, _, body in answers:
                self.assertEqual(status, 200, (path, body[:200]))
            self.assertEqual(len({body for _, _, body in answers}), 1, path)
            self.assertEqual(len({h.get("etag") for _, h, _ in answers}), 1, path)
            if "/section." in path and not path.split("?")[0].endswith("geojson") or "/tiles/" in path:
                self.assertEqual(answers[-1][1].get("x-cache-status"), "HIT", path)

    def test_killing_a_replica_under_load_loses_no_request(self):
        victim = self.replicas[2]
        n = 240
        killed_at = {}

        def progress(done):
            if done == n // 4 and not killed_at:
                killed_at["t"] = time.time()
                victim.kill(signal.SIGKILL)

        before = len(self.lb.access_log())
        results = run_load(self.lb.port, [new_section(i, 1) for i in range(n)], threads=4,
                           on_progress=progress)
        try:
            self.assertTrue(killed_at, "the replica was killed during the load")
            lost = [(p, s) for p, s in results if s != 200]
            self.assertEqual(len(results), n)
            self.assertEqual(lost, [], f"{len(lost)} of {n} requests failed")
            after = self.lb.access_log()[before:]
            served = [upstream_tries(ln)[-1][0] for ln in after if "section.jpg" in ln]
            tail = served[len(served) // 2:]  # well after the kill
            for r in self.replicas[:2]:
                self.assertIn(f"127.0.0.1:{r.port}", tail, "the surviving replicas keep serving")
            self.assertNotIn(f"127.0.0.1:{victim.port}", tail)
            retried = sum(len(upstream_tries(ln)) > 1 for ln in after)
            print(f"replica killed under load: {n} of {n} answered 200, {retried} retried on another replica")
        finally:
            victim.start().wait_ready()

    def test_a_replica_that_is_not_ready_gets_no_traffic(self):
        # A 4th replica that loads a big model is in the upstream list before it is ready
        # (as after a restart): it answers 503, nginx retries elsewhere and sets it aside
        # for fail_timeout, so no client sees it.
        slow = Replica(BINARY, free_port(), self.dir, self.serve_args + ["--demo-triangles", "6000000"]).start()
        ports = [r.port for r in self.replicas] + [slow.port]
        try:
            t0 = time.monotonic()
            while not self._listening(slow):
                self.assertLess(time.monotonic() - t0, 30, "the slow replica never listened")
                time.sleep(0.05)
            self.lb.reload(ports, fail_timeout_s=5)
            before = len(self.lb.access_log())
            t0 = time.monotonic()
            results = run_load(self.lb.port, [new_section(i, 2) for i in range(60)], threads=4)
            elapsed = time.monotonic() - t0
            still_unready = not slow.ready()
            self.assertTrue(still_unready, "inconclusive: the slow replica became ready during the load")
            self.assertEqual([(p, s) for p, s in results if s != 200], [])
            after = self.lb.access_log()[before:]
            tries = [(a, st) for ln in after for a, st in upstream_tries(ln) if a == f"127.0.0.1:{slow.port}"]
            for a, st in tries:
                self.assertEqual(st, "503", "it answered nothing but 503 (retried)")
            self.assertLessEqual(len(tries), 1 + int(elapsed / 5) + 1,
                                 f"probed {len(tries)} times in {elapsed:.1f} s with fail_timeout 5 s")
            print(f"not-ready replica: {len(tries)} probe(s) answered 503 and retried elsewhere in "
                  f"{elapsed:.1f} s; 60 of 60 requests answered 200")
        finally:
            slow.kill(signal.SIGKILL)
            self.lb.reload([r.port for r in self.replicas])

    @staticmethod
    def _listening(r):
        try:
            with socket.create_connection(("127.0.0.1", r.port), timeout=1):
                return True
        except OSError:
            return False


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", required=True)
    a, rest = ap.parse_known_args()
    BINARY = os.path.abspath(a.binary)
    if NGINX is None:
        print("scale_out_test: SKIP: nginx is not installed (bash scripts/install-deps.sh)")
        sys.exit(77)
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
