#!/usr/bin/env python3
"""The first `kubectl apply`, in the manifests' order, with the plain binary (CTest label
deploy): deploy/kubernetes/geoslice.yaml applies the replicas and the bake Job at once, so a
replica may start before any package exists. Read from the manifests (args and env of the
Deployment geoslice and of the Job geoslice-bake, the claim mounted at /models, which here is
a temporary directory), this test:

1. starts a replica on an empty volume: /healthz 200 (nothing restarts it), /readyz 503
   naming the missing packages directory, for several poll periods;
2. runs the Job's command: the replica becomes ready by itself, and the first pixel query
   after ready answers without waiting for a ray scene (printed; asserted < 250 ms on a busy
   CI core, the ray scene being built before ready);
3. changes the raw model and runs the Job again: the replica serves the new version within
   seconds and /readyz never leaves 200 meanwhile.

    python3 tests/deploy/first_install_test.py --binary build/cli/geoslice
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "deploy"))
from scale_out import free_port, http_get  # noqa: E402

BINARY = None


def manifests():
    with open(os.path.join(REPO, "deploy", "kubernetes", "geoslice.yaml")) as f:
        docs = [d for d in yaml.safe_load_all(f) if d]
    by = {(d["kind"], d["metadata"]["name"]): d for d in docs}
    replica = by[("Deployment", "geoslice")]["spec"]["template"]["spec"]["containers"][0]
    job = by[("Job", "geoslice-bake")]["spec"]["template"]["spec"]["containers"][0]
    return replica, job


def remap(args, volume):
    """Container paths under /models/ -> the test's volume."""
    return [volume + a[len("/models"):] if a == "/models" or a.startswith("/models/") else a for a in args]


def generate(path, seed):
    subprocess.run([BINARY, "generate", "--triangles", "20000", "--seed", str(seed), "--crs", "EPSG:4523",
                    "--out", path], check=True, capture_output=True)


class FirstInstall(unittest.TestCase):
    def test_replica_first_bake_later(self):
        replica, job = manifests()
        volume = tempfile.mkdtemp(prefix="geoslice-first-install-")
        proc = None
        try:
            os.makedirs(os.path.join(volume, "raw"))
            generate(os.path.join(volume, "raw", "mine.glb"), 1)
            env = dict(os.environ)
            env.update({e["name"]: e["value"] for e in replica.get("env", []) if "value" in e})
            env.pop("GEOSLICE_KEYS_FILE", None)  # the Secret: keys are tested elsewhere
            port = free_port()
            env.update({"GEOSLICE_PORT": str(port), "GEOSLICE_HOST": "127.0.0.1", "GEOSLICE_WORKERS": "1",
                        "GEOSLICE_LOG_LEVEL": "warn"})
            poll_s = int(env.get("GEOSLICE_MODELS_POLL_MS", "2000")) / 1000
            args = remap(replica["args"], volume)
            self.assertIn("--no-bake", args)
            log = open(os.path.join(volume, "replica.log"), "wb")
            proc = subprocess.Popen([BINARY] + args, env=env, stdout=log, stderr=log, stdin=subprocess.DEVNULL)
            log.close()

            def status(path):
                try:
                    return http_get(port, path, timeout=5)
                except OSError:
                    return None, {}, b""

            t0 = time.monotonic()
            while status("/healthz")[0] != 200:
                self.assertLess(time.monotonic() - t0, 30, "not listening after 30 s")
                time.sleep(0.05)
            # 1. No packages yet: alive, not ready, for several poll periods.
            until = time.monotonic() + 2.5 * poll_s
            while time.monotonic() < until:
                code, _, body = status("/readyz")
                self.assertEqual(code, 503, body)
                self.assertEqual(status("/healthz")[0], 200)
                self.assertIsNone(proc.poll(), "the replica exited")
                time.sleep(0.2)
            failed = json.loads(status("/readyz")[2])["models"]["failed"]
            self.assertTrue(any("does not exist" in f["error"] for f in failed), failed)

            # 2. The bake Job.
            cmd = remap(job.get("command", []) + job["args"], volume)
            cmd[0] = BINARY
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            t_job = time.monotonic()
            while status("/readyz")[0] != 200:
                self.assertLess(time.monotonic() - t_job, poll_s + 30, "not ready 30 s after the bake")
                time.sleep(0.02)
            ready_s = time.monotonic() - t_job
            ready = json.loads(status("/readyz")[2])
            self.assertEqual(ready["rays"]["mine"]["state"], "ready")
            b = json.loads(status("/v1/models/mine")[2])["bounds"]
            plane = f"0,1,0,{-0.5 * (b['min'][1] + b['max'][1]):.3f}"
            q0 = time.monotonic()
            code, _, body = status(f"/v1/models/mine/query?plane={plane}&size=256x128&px=128&py=64")
            first_query_ms = (time.monotonic() - q0) * 1000
            self.assertEqual(code, 200, body)
            print(f"first_install: ready {ready_s:.2f} s after the bake Job ended (poll {poll_s:g} s); "
                  f"first pixel query {first_query_ms:.1f} ms", flush=True)
            self.assertLess(first_query_ms, 250)
            v1 = json.loads(status("/v1/models/mine")[2])["version"]

            # 3. The raw model changes; the Job runs again; the replica follows, staying ready.
            generate(os.path.join(volume, "raw", "mine.glb.new"), 2)
            os.replace(os.path.join(volume, "raw", "mine.glb.new"), os.path.join(volume, "raw", "mine.glb"))
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            t_job, v2 = time.monotonic(), v1
            while v2 == v1:
                self.assertLess(time.monotonic() - t_job, poll_s + 30, "the new package was not served")
                self.assertEqual(status("/readyz")[0], 200)
                v2 = json.loads(status("/v1/models/mine")[2])["version"]
                time.sleep(0.05)
            print(f"first_install: re-baked version served {time.monotonic() - t_job:.2f} s after the Job, "
                  f"never unready", flush=True)
            code, _, _ = status(f"/v1/models/mine/section.png?plane={plane}&size=64x32&version={v1}")
            self.assertEqual(code, 404, "the old version's URLs are gone")
        finally:
            if proc and proc.poll() is None:
                proc.terminate()
                proc.wait(timeout=30)
            if proc and proc.returncode not in (0, None):
                with open(os.path.join(volume, "replica.log")) as f:
                    print(f.read()[-3000:])
            shutil.rmtree(volume, ignore_errors=True)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", required=True)
    a, rest = ap.parse_known_args()
    BINARY = os.path.abspath(a.binary)
    unittest.main(argv=[sys.argv[0], "-v"] + rest)
