#!/usr/bin/env bash
# Builds the geoslice container image (deploy/Dockerfile) with podman, or docker where
# podman is missing, and prints its size and the build time. Makes the debian:12 base
# with debootstrap first when there is none (deploy/make-base.sh: no registry needed).
# Podman's storage is build/podman (GEOSLICE_PODMAN_DIR), so the base image, the
# dependency layers and the compiler cache stay between runs.
# Usage: bash deploy/build-image.sh [--tag NAME] [extra build flags...]   (default tag geoslice:latest)
set -euo pipefail
cd "$(dirname "$0")/.."
tag=geoslice:latest
if [ "${1:-}" = --tag ]; then
    tag=$2
    shift 2
fi
source deploy/engine.sh
engine_init
bash deploy/make-base.sh
version=$(sed -n 's/^project(geoslice VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
source deploy/revision.sh
revision=$(source_revision)
flags=(-f deploy/Dockerfile -t "$tag" --network host
    --build-arg VERSION="$version" --build-arg REVISION="$revision"
    --build-arg CREATED="$(git log -1 --format=%cI 2>/dev/null || date -u +%FT%TZ)")
# OCI image format drops HEALTHCHECK; docker format keeps it.
[ "$GEOSLICE_ENGINE" = podman ] && flags+=(--format docker)
t0=$(date +%s)
# Builds share the machine: run them at lower priority.
nice -n 10 "${ctr_prefix[@]}" "$GEOSLICE_ENGINE" "${ctr_args[@]}" build "${flags[@]}" "$@" .
t1=$(date +%s)
size=$(ctr image inspect --format '{{.Size}}' "$tag")
echo "build-image: $tag $(awk -v b="$size" 'BEGIN {printf "%.0f MB (%d bytes)", b / 1e6, b}'), built in $((t1 - t0)) s with $GEOSLICE_ENGINE"
