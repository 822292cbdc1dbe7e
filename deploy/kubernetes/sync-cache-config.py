#!/usr/bin/env python3
"""Writes deploy/nginx/geoslice.conf into the cache tier's ConfigMap (geoslice.conf key of
ConfigMap geoslice-cache in deploy/kubernetes/geoslice.yaml), with the two lines that differ
in a pod: `listen 8080;` and `access_log /dev/stdout geoslice;`. Run it after editing
geoslice.conf; `--check` exits 1 when the manifest is out of date (tests/deploy/kubernetes_test.py).

    python3 deploy/kubernetes/sync-cache-config.py [--check]
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CONF = os.path.join(os.path.dirname(HERE), "nginx", "geoslice.conf")
MANIFEST = os.path.join(HERE, "geoslice.yaml")
POD_LINES = {"listen 127.0.0.1:8000;": "listen 8080;",
             "access_log geoslice-access.log geoslice;": "access_log /dev/stdout geoslice;"}


def pod_conf():
    """geoslice.conf as the cache tier runs it."""
    with open(CONF) as f:
        text = f.read()
    for old, new in POD_LINES.items():
        if old not in text:
            sys.exit(f"sync-cache-config: '{old}' is not in {CONF}")
        text = text.replace(old, new)
    return text


def render(manifest):
    """The manifest with the ConfigMap's geoslice.conf block replaced by pod_conf()."""
    body = "".join("    " + ln if ln.strip() else "\n" for ln in pod_conf().splitlines(True))
    m = re.search(r"(?m)^  geoslice\.conf: \|\n((?:    .*\n|\n)*?)(?=---\n|\Z)", manifest)
    if not m:
        sys.exit(f"sync-cache-config: no `  geoslice.conf: |` block in {MANIFEST}")
    return manifest[:m.start(1)] + body + manifest[m.end(1):]


def main():
    with open(MANIFEST) as f:
        manifest = f.read()
    if "__GEOSLICE_CONF__\n" in manifest:
        manifest = manifest.replace("__GEOSLICE_CONF__\n", "")
    new = render(manifest)
    if "--check" in sys.argv[1:]:
        if new != manifest:
            print("sync-cache-config: deploy/kubernetes/geoslice.yaml's ConfigMap differs from "
                  "deploy/nginx/geoslice.conf: run python3 deploy/kubernetes/sync-cache-config.py")
            sys.exit(1)
        print("sync-cache-config: the ConfigMap matches deploy/nginx/geoslice.conf")
        return
    with open(MANIFEST, "w") as f:
        f.write(new)


if __name__ == "__main__":
    main()
