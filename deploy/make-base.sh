#!/usr/bin/env bash
# Makes docker.io/library/debian:12 in the local container storage when it is missing, for
# machines with no registry: debootstrap --variant=minbase bookworm from this host's Debian
# mirror, the host's apt sources copied in, apt caches cleaned as the official image does,
# then imported. Usage: bash deploy/make-base.sh   (needs root and debootstrap)
set -euo pipefail
source "$(dirname "$0")/engine.sh"
engine_init
base=docker.io/library/debian:12
if ctr image exists "$base" 2>/dev/null || ctr image inspect "$base" >/dev/null 2>&1; then
    echo "make-base: $base present"
    exit 0
fi
if [ "$GEOSLICE_ENGINE" = docker ]; then
    ctr pull "$base" && exit 0
fi
command -v debootstrap >/dev/null || { echo "make-base: no $base and no debootstrap (apt-get install debootstrap)" >&2; exit 1; }
sources=/etc/apt/sources.list.d/debian.sources
mirror=$(awk '/^URIs:/ {print $2; exit}' "$sources" 2>/dev/null || true)
mirror=${mirror:-http://deb.debian.org/debian}
rootfs=$GEOSLICE_PODMAN_DIR/base-rootfs
rm -rf "$rootfs"
echo "make-base: debootstrap bookworm from $mirror (a few minutes)"
t0=$(date +%s)
nice -n 10 debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >"$GEOSLICE_PODMAN_DIR/debootstrap.log" 2>&1 ||
    { tail -20 "$GEOSLICE_PODMAN_DIR/debootstrap.log" >&2; exit 1; }
[ -f "$sources" ] && { rm -f "$rootfs/etc/apt/sources.list"; cp "$sources" "$rootfs/etc/apt/sources.list.d/"; }
# What the official image does to keep apt's caches out of layers.
cat >"$rootfs/etc/apt/apt.conf.d/docker-clean" <<'CONF'
DPkg::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
APT::Update::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
Dir::Cache::pkgcache ""; Dir::Cache::srcpkgcache "";
CONF
echo 'APT::AutoRemove::SuggestsImportant "false";' >"$rootfs/etc/apt/apt.conf.d/docker-autoremove-suggests"
echo 'Acquire::GzipIndexes "true";' >"$rootfs/etc/apt/apt.conf.d/docker-gzip-indexes"
rm -rf "$rootfs"/var/lib/apt/lists/* "$rootfs"/var/cache/apt/*.bin "$rootfs"/var/cache/apt/archives/*.deb \
    "$rootfs"/var/log/*.log "$rootfs"/var/log/apt/* "$rootfs"/tmp/*
tar -C "$rootfs" --numeric-owner -c . | ctr import --change 'CMD ["bash"]' - "$base" >/dev/null
rm -rf "$rootfs"
echo "make-base: $base imported in $(($(date +%s) - t0)) s"
