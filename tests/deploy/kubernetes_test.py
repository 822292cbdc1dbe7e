#!/usr/bin/env python3
"""Checks deploy/kubernetes/*.yaml (CTest label deploy).

1. Schema: every object against the Kubernetes 1.27 OpenAPI schemas bundled offline by the
   npm package kubernetes-models (validate_k8s.cjs), when `npm ci` has installed it into
   tests/deploy/node_modules (scripts/test.sh does); otherwise says it was skipped. Those schemas
   do not reject unknown fields, hence 2.
2. Fields this deployment depends on, with python3-yaml: probes on the right paths and
   port, resources, IfNotPresent, workers = CPU request, the port env = containerPort, the
   claim defined and ReadOnlyMany, mounted read-only by replicas and written by the bake
   Job, selectors of the Service, PodDisruptionBudget, HPA and ServiceMonitor matching the
   pods, topology spread, non-root read-only pods, a grace period longer than preStop +
   the render deadline, and the GPU variant's EGL settings; replicas keep looking for
   packages written after they start; the image is the project's version.
3. The cache tier: its ConfigMap is deploy/nginx/geoslice.conf (sync-cache-config.py
   --check), routes by consistent hashing to the replicas' headless Service, and passes
   Debian's `nginx -t` (with the Kubernetes resolver and `resolve`, which need nginx >=
   1.27.3, swapped for loopback ones).
"""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import unittest

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
K8S = os.path.join(REPO, "deploy", "kubernetes")
DEADLINE_S = 10  # server/config.hpp deadlineMs default


def project_version():
    with open(os.path.join(REPO, "CMakeLists.txt")) as f:
        return re.search(r"project\(geoslice VERSION ([0-9.]+)", f.read()).group(1)


def load():
    docs = []
    for f in sorted(glob.glob(os.path.join(K8S, "*.yaml"))):
        with open(f) as fh:
            docs += [d for d in yaml.safe_load_all(fh) if d]
    return docs


def find(docs, kind, name=None):
    out = [d for d in docs if d["kind"] == kind and (name is None or d["metadata"]["name"] == name)]
    if not out:
        raise AssertionError(f"no {kind} {name or ''} in deploy/kubernetes")
    return out[0] if name else out


def matches(selector, labels):
    return all(labels.get(k) == v for k, v in selector.items())


def env_of(container):
    return {e["name"]: e.get("value") for e in container.get("env", [])}


def cpu_cores(q):
    q = str(q)
    return float(q[:-1]) / 1000 if q.endswith("m") else float(q)


class Manifests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.docs = load()

    def test_schema(self):
        node = shutil.which("node")
        if not node or not os.path.isdir(os.path.join(HERE, "node_modules", "kubernetes-models")):
            print("kubernetes_test: schema validation skipped (no node or tests/deploy/node_modules: "
                  "npm ci --prefix tests/deploy); field checks still run")
            return
        r = subprocess.run([node, os.path.join(HERE, "validate_k8s.cjs")], input=json.dumps(self.docs),
                           capture_output=True, text=True, timeout=120)
        print(r.stdout, end="")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertEqual(r.stdout.count("\nvalid ") + r.stdout.startswith("valid "), len(self.docs))

    def test_schema_rejects_a_bad_object(self):
        # The validator must be able to fail: a string where an integer belongs.
        node = shutil.which("node")
        if not node or not os.path.isdir(os.path.join(HERE, "node_modules", "kubernetes-models")):
            return
        bad = json.loads(json.dumps(find(self.docs, "Deployment", "geoslice")))
        bad["spec"]["replicas"] = "three"
        r = subprocess.run([node, os.path.join(HERE, "validate_k8s.cjs")], input=json.dumps([bad]),
                           capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 1, r.stdout)
        self.assertIn("replicas", r.stdout)

    def pod_templates(self):
        for d in self.docs:
            if d["kind"] in ("Deployment", "Job"):
                yield d, d["spec"]["template"]

    def test_every_container_is_local_first_non_root_read_only(self):
        for d, t in self.pod_templates():
            spec = t["spec"]
            self.assertTrue(spec["securityContext"]["runAsNonRoot"], d["metadata"]["name"])
            self.assertNotEqual(spec["securityContext"]["runAsUser"], 0)
            for c in spec["containers"]:
                self.assertEqual(c.get("imagePullPolicy"), "IfNotPresent", d["metadata"]["name"])
                self.assertTrue(c["securityContext"]["readOnlyRootFilesystem"])
                self.assertFalse(c["securityContext"]["allowPrivilegeEscalation"])
                self.assertIn("memory", c["resources"]["requests"])
                self.assertIn("cpu", c["resources"]["requests"])
                self.assertIn("memory", c["resources"]["limits"])
                mounts = {m["mountPath"] for m in c.get("volumeMounts", [])}
                self.assertIn("/tmp", mounts, "a writable /tmp on a read-only root")

    def check_server(self, dep):
        spec = dep["spec"]["template"]["spec"]
        labels = dep["spec"]["template"]["metadata"]["labels"]
        self.assertTrue(matches(dep["spec"]["selector"]["matchLabels"], labels))
        (c,) = spec["containers"]
        env = env_of(c)
        port = c["ports"][0]
        self.assertEqual(env.get("GEOSLICE_PORT"), str(port["containerPort"]), "the server listens on containerPort")
        self.assertEqual(int(env["GEOSLICE_WORKERS"]), int(cpu_cores(c["resources"]["requests"]["cpu"])),
                         "render workers = the CPU request")
        for probe, path in (("startupProbe", "/healthz"), ("readinessProbe", "/readyz"), ("livenessProbe", "/healthz")):
            p = c[probe]["httpGet"]
            self.assertEqual(p["path"], path, probe)
            self.assertIn(p["port"], (port["containerPort"], port.get("name")), probe)
        sleep = c["lifecycle"]["preStop"]["exec"]["command"]
        self.assertEqual(sleep[0], "sleep")
        self.assertGreater(spec["terminationGracePeriodSeconds"], int(sleep[1]) + DEADLINE_S + 1)
        claims = {v["name"]: v["persistentVolumeClaim"] for v in spec["volumes"] if "persistentVolumeClaim" in v}
        models = [m for m in c["volumeMounts"] if m["name"] in claims]
        self.assertTrue(models and all(m.get("readOnly") for m in models), "models mounted read-only")
        for m in models:
            self.assertTrue(claims[m["name"]].get("readOnly"))
            find(self.docs, "PersistentVolumeClaim", claims[m["name"]]["claimName"])
            self.assertIn(m["mountPath"].rstrip("/") + "/baked", " ".join(c["args"]), "serves the baked packages")
        self.assertIn("--no-bake", c["args"], "replicas on a read-only volume never bake")
        self.assertGreater(int(env.get("GEOSLICE_MODELS_POLL_MS", "2000")), 0,
                           "a replica started before the bake Job keeps looking for its packages")
        self.assertEqual(c["image"], f"localhost/geoslice:{project_version()}",
                         "the image deploy/build-image.sh tags and archives")
        self.check_keys(spec, c)
        return c, labels

    def check_keys(self, spec, c):
        """API keys: GEOSLICE_KEYS_FILE names a file inside a read-only mount of the Secret
        geoslice-keys, which is not optional (a pod without it must not start open)."""
        keys_file = env_of(c).get("GEOSLICE_KEYS_FILE")
        self.assertTrue(keys_file, "replicas serve models to API keys only")
        secrets = {v["name"]: v["secret"] for v in spec["volumes"] if "secret" in v}
        mounts = [m for m in c["volumeMounts"] if m["name"] in secrets
                  and keys_file.startswith(m["mountPath"].rstrip("/") + "/")]
        self.assertEqual(len(mounts), 1, "the keys file lies in a Secret mount")
        m = mounts[0]
        self.assertTrue(m.get("readOnly"))
        secret = secrets[m["name"]]
        self.assertEqual(secret["secretName"], "geoslice-keys")
        self.assertFalse(secret.get("optional", False), "no Secret, no pod")
        self.assertEqual(secret.get("defaultMode", 0o644) & 0o222, 0, "the keys file is not writable")
        self.assertEqual(keys_file[len(m["mountPath"].rstrip("/")) + 1:], "keys", "the Secret's data key")
        self.assertFalse([d for d in self.docs if d["kind"] == "Secret"],
                         "no Secret in the manifests: kubectl apply would reset the real one")

    def test_cpu_deployment(self):
        dep = find(self.docs, "Deployment", "geoslice")
        c, labels = self.check_server(dep)
        spread = dep["spec"]["template"]["spec"]["topologySpreadConstraints"]
        self.assertIn("kubernetes.io/hostname", [s["topologyKey"] for s in spread])
        for s in spread:
            self.assertTrue(matches(s["labelSelector"]["matchLabels"], labels))
        svc = find(self.docs, "Service", "geoslice-pods")
        self.assertTrue(matches(svc["spec"]["selector"], labels))
        self.assertEqual(svc["spec"]["clusterIP"], "None", "headless: DNS lists each ready replica")
        self.assertFalse(svc["spec"].get("publishNotReadyAddresses", False), "only ready replicas get traffic")
        self.assertIn(svc["spec"]["ports"][0]["targetPort"], (c["ports"][0]["containerPort"], c["ports"][0]["name"]))
        pdb = find(self.docs, "PodDisruptionBudget", "geoslice")
        self.assertTrue(matches(pdb["spec"]["selector"]["matchLabels"], labels))
        self.assertLess(pdb["spec"]["minAvailable"], dep["spec"]["replicas"], "a node can still be drained")
        hpa = find(self.docs, "HorizontalPodAutoscaler", "geoslice")
        self.assertEqual(hpa["spec"]["scaleTargetRef"]["name"], "geoslice")
        self.assertEqual(hpa["spec"]["scaleTargetRef"]["kind"], "Deployment")
        self.assertIn("cpu", [m["resource"]["name"] for m in hpa["spec"]["metrics"] if m["type"] == "Resource"])
        self.assertGreaterEqual(hpa["spec"]["minReplicas"], pdb["spec"]["minAvailable"] + 1)
        mon = find(self.docs, "ServiceMonitor", "geoslice")
        self.assertTrue(matches(mon["spec"]["selector"]["matchLabels"], svc["metadata"]["labels"]))
        self.assertIn(mon["spec"]["endpoints"][0]["port"], [p["name"] for p in svc["spec"]["ports"]])

    def test_cache_tier(self):
        cm = find(self.docs, "ConfigMap", "geoslice-cache")
        r = subprocess.run([sys.executable, os.path.join(K8S, "sync-cache-config.py"), "--check"],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        conf, upstreams = cm["data"]["geoslice.conf"], cm["data"]["geoslice-upstreams.conf"]
        self.assertRegex(conf, r"(?m)^\s*hash \$geoslice_route_key consistent;", "one owner per URL")
        self.assertRegex(conf, r"(?m)^\s*zone \S+ \S+;", "`resolve` needs a shared zone")
        self.assertRegex(conf, r"(?m)^\s*listen 8080;")
        replicas = find(self.docs, "Deployment", "geoslice")
        port = replicas["spec"]["template"]["spec"]["containers"][0]["ports"][0]["containerPort"]
        self.assertRegex(upstreams, rf"server geoslice-pods\.default\.svc\.cluster\.local:{port} resolve ")
        self.assertIn("resolver ", cm["data"]["nginx.conf"])
        dep = find(self.docs, "Deployment", "geoslice-cache")
        spec = dep["spec"]["template"]["spec"]
        (c,) = spec["containers"]
        self.assertRegex(c["image"], r"nginx:1\.(2[89]|[3-9]\d)", "upstream `resolve` is in nginx >= 1.27.3")
        self.assertEqual(c["ports"][0]["containerPort"], 8080)
        vols = {v["name"]: v for v in spec["volumes"]}
        conf_dir = [m["mountPath"] for m in c["volumeMounts"] if "configMap" in vols[m["name"]]]
        self.assertEqual(conf_dir, ["/etc/geoslice-cache"])
        self.assertIn("/etc/geoslice-cache/nginx.conf", c["command"])
        prefix = c["command"][c["command"].index("-p") + 1].rstrip("/")
        self.assertIn(prefix, [m["mountPath"] for m in c["volumeMounts"]], "the cache lives in a volume")
        svc = find(self.docs, "Service", "geoslice")
        self.assertTrue(matches(svc["spec"]["selector"], dep["spec"]["template"]["metadata"]["labels"]),
                        "the entry Service is the cache tier")
        self.assertEqual(svc["spec"]["ports"][0]["targetPort"], "http")
        # Debian's nginx parses it: the same file set in a prefix, with the Kubernetes-only
        # parts (resolver name, `resolve`) swapped for loopback ones.
        nginx = shutil.which("nginx") or ("/usr/sbin/nginx" if os.path.exists("/usr/sbin/nginx") else None)
        if not nginx:
            print("kubernetes_test: nginx -t of the cache tier skipped (no nginx)")
            return
        import tempfile

        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "tmp"))
            main = cm["data"]["nginx.conf"].replace("/tmp/", d + "/tmp/")
            main = re.sub(r"resolver [^;]*;", "resolver 127.0.0.1;", main)
            files = {"nginx.conf": main, "geoslice.conf": conf.replace("/dev/stdout", d + "/access.log"),
                     "geoslice-upstreams.conf": re.sub(r"server \S+ resolve ", "server 127.0.0.1:8080 ", upstreams)}
            for name, text in files.items():
                with open(os.path.join(d, name), "w") as f:
                    f.write(text)
            r = subprocess.run([nginx, "-t", "-p", d + "/", "-c", os.path.join(d, "nginx.conf"), "-e",
                                os.path.join(d, "error.log")], capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)

    def test_models_claim_and_bake_job(self):
        pvc = find(self.docs, "PersistentVolumeClaim", "geoslice-models")
        self.assertIn("ReadOnlyMany", pvc["spec"]["accessModes"])
        job = find(self.docs, "Job", "geoslice-bake")
        spec = job["spec"]["template"]["spec"]
        vols = {v["name"]: v for v in spec["volumes"]}
        (c,) = spec["containers"]
        written = [m for m in c["volumeMounts"]
                   if vols[m["name"]].get("persistentVolumeClaim", {}).get("claimName") == "geoslice-models"]
        self.assertTrue(written and not written[0].get("readOnly"), "the Job writes the claim")
        args = c.get("command", []) + c.get("args", [])
        self.assertTrue(args[0].endswith("geoslice"))
        self.assertIn("--bake-only", args, "bakes with the server's bake-dir rules, then exits")
        self.assertEqual(args[args.index("--bake-dir") + 1], written[0]["mountPath"] + "/baked")

    def test_gpu_variant(self):
        dep = find(self.docs, "Deployment", "geoslice-gpu")
        c, _ = self.check_server(dep)
        self.assertEqual(str(c["resources"]["limits"]["nvidia.com/gpu"]), "1")
        caps = env_of(c)["NVIDIA_DRIVER_CAPABILITIES"].split(",")
        self.assertIn("graphics", caps, "without graphics the toolkit does not mount libEGL_nvidia")
        self.assertIn("egl-device", c["args"])
        vendor = env_of(c).get("__EGL_VENDOR_LIBRARY_FILENAMES")
        self.assertTrue(vendor)
        self.assertTrue(os.path.exists(os.path.join(REPO, "deploy", "egl", os.path.basename(vendor))),
                        "the vendor file the pod names is the one the image carries")
        with open(os.path.join(REPO, "deploy", "Dockerfile")) as f:
            self.assertIn(vendor, f.read())


if __name__ == "__main__":
    unittest.main(verbosity=2)
