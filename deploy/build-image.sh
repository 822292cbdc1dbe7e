#!/usr/bin/env bash
# Builds the geoslice container image (deploy/Dockerfile) with podman, or docker where
# podman is missing, tags it with the project's version (CMakeLists.txt: the version of the
# binary, the OCI label and the Kubernetes manifests) and writes it as an OCI archive that a
# cluster can import or a registry take (docs/deploy.md "An image to pull"). Makes the
# debian:12 base with debootstrap first when there is none (deploy/make-base.sh: no registry
# needed). Podman's storage is build/podman (GEOSLICE_PODMAN_DIR), so the base image, the
# dependency layers and the compiler cache stay between runs.
#   image:   localhost/geoslice:VERSION, also tagged localhost/geoslice:latest
#   archive: build/geoslice-VERSION.oci.tar (GEOSLICE_IMAGE_ARCHIVE=0: none)
#   build stage: kept as localhost/geoslice-build:cache (the dependency layers a rebuild
#   reuses); the build stages of earlier builds, now untagged, are pruned.
# Usage: bash deploy/build-image.sh [--tag NAME] [extra build flags...]
set -euo pipefail
cd "$(dirname "$0")/.."
version=$(sed -n 's/^project(geoslice VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
tag=localhost/geoslice:$version
if [ "${1:-}" = --tag ]; then
    tag=$2
    shift 2
fi
source deploy/engine.sh
engine_init
bash deploy/make-base.sh
source deploy/revision.sh
revision=$(source_revision)
common=(-f deploy/Dockerfile --network host
    --build-arg VERSION="$version" --build-arg REVISION="$revision"
    --build-arg CREATED="$(git log -1 --format=%cI 2>/dev/null || date -u +%FT%TZ)")
# OCI image format drops HEALTHCHECK; docker format keeps it.
[ "$GEOSLICE_ENGINE" = podman ] && common+=(--format docker)
engine() { nice -n 10 "${ctr_prefix[@]}" "$GEOSLICE_ENGINE" "${ctr_args[@]}" "$@"; }
t0=$(date +%s)
# Builds share the machine: run them at lower priority.
engine build "${common[@]}" -t "$tag" "$@" .
# The build stage under a name (all its steps are cached by the build above: seconds), so
# that pruning untagged images removes earlier builds' stages and never this one's layers.
engine build "${common[@]}" --target build -t localhost/geoslice-build:cache "$@" . >/dev/null
t1=$(date +%s)
[ "$tag" = "localhost/geoslice:latest" ] || ctr tag "$tag" localhost/geoslice:latest
pruned=$(ctr image prune -f 2>/dev/null | grep -c . || true)
size=$(ctr image inspect --format '{{.Size}}' "$tag")
echo "build-image: $tag $(awk -v b="$size" 'BEGIN {printf "%.0f MB (%d bytes)", b / 1e6, b}'), built in $((t1 - t0)) s with $GEOSLICE_ENGINE; $pruned untagged images pruned"
if [ "${GEOSLICE_IMAGE_ARCHIVE:-1}" != 0 ]; then
    archive=build/geoslice-$version.oci.tar
    mkdir -p build
    rm -f "$archive.partial"
    if [ "$GEOSLICE_ENGINE" = docker ]; then
        ctr save -o "$archive.partial" "$tag"  # Docker >= 25 writes an OCI image layout
    else
        ctr save --format oci-archive -o "$archive.partial" "$tag"
    fi
    mv "$archive.partial" "$archive"
    echo "build-image: $archive $(($(stat -c %s "$archive") / 1000000)) MB (OCI archive of $tag; docs/deploy.md says how to import or push it)"
fi
