# Sourced by deploy/build-image.sh, deploy/test-image.sh and tests/deploy/*: picks the
# container engine (podman, else docker; GEOSLICE_ENGINE=podman|docker forces one) and
# defines `ctr`, which runs it. For podman, storage lives in the project's build tree
# (GEOSLICE_PODMAN_DIR, default build/podman: root/, runroot/, tmp/) so the base image and
# the dependency layers stay cached between runs and `rm -rf build/podman` cleans all.
# Two host quirks are handled when present (issue 13):
# - hybrid cgroups (cgroup v1 with /sys/fs/cgroup/unified mounted), which crun refuses:
#   podman runs in a private mount namespace (kept in $GEOSLICE_PODMAN_DIR/mntns) where
#   that mount is gone;
# - a root that cannot raise rlimits: containers.conf sets default_ulimits to the
#   current limits instead of podman's 1048576 open files.
# Containers run with --network host (no bridge, so the host's iptables stay untouched).

geoslice_repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
ctr_prefix=()
ctr_args=()
ctr_run_args=()

engine_init() {
    local engine=${GEOSLICE_ENGINE:-}
    if [ -z "$engine" ]; then
        if command -v podman >/dev/null; then
            engine=podman
        elif command -v docker >/dev/null; then
            engine=docker
        else
            echo "engine: neither podman nor docker is installed (apt-get install podman)" >&2
            return 1
        fi
    fi
    GEOSLICE_ENGINE=$engine
    if [ "$engine" = docker ]; then
        ctr_run_args=(--network host)
        return 0
    fi
    local dir=${GEOSLICE_PODMAN_DIR:-$geoslice_repo/build/podman}
    mkdir -p "$dir/root" "$dir/runroot" "$dir/tmp"
    GEOSLICE_PODMAN_DIR=$(cd "$dir" && pwd)
    local nofile nproc
    nofile=$(ulimit -Hn)
    nproc=$(ulimit -Hu)
    [ "$nofile" = unlimited ] && nofile=1048576
    [ "$nproc" = unlimited ] && nproc=32768
    [ "$nofile" -gt 1048576 ] && nofile=1048576
    [ "$nproc" -gt 32768 ] && nproc=32768
    cat >"$GEOSLICE_PODMAN_DIR/containers.conf" <<CONF
[containers]
default_ulimits = ["nofile=$nofile:$nofile", "nproc=$nproc:$nproc"]
[engine]
cgroup_manager = "cgroupfs"
events_logger = "file"
CONF
    export CONTAINERS_CONF=$GEOSLICE_PODMAN_DIR/containers.conf
    export TMPDIR=$GEOSLICE_PODMAN_DIR/tmp
    ctr_args=(--root "$GEOSLICE_PODMAN_DIR/root" --runroot "$GEOSLICE_PODMAN_DIR/runroot" --storage-driver overlay)
    ctr_run_args=(--network host --cgroups=disabled)
    if [ "$(id -u)" -eq 0 ] && mountpoint -q /sys/fs/cgroup/unified 2>/dev/null &&
        [ "$(stat -f -c %T /sys/fs/cgroup)" != cgroup2fs ]; then
        local ns=$GEOSLICE_PODMAN_DIR/mntns
        if ! nsenter --mount="$ns" true 2>/dev/null; then
            touch "$ns"
            unshare --mount="$ns" --propagation private umount /sys/fs/cgroup/unified
        fi
        ctr_prefix=(nsenter --mount="$ns" --wd="$PWD" --)
    fi
}

# ctr ARGS...: the engine with this project's storage and work-arounds.
ctr() {
    if [ "$GEOSLICE_ENGINE" = docker ]; then
        docker "$@"
    else
        "${ctr_prefix[@]}" podman "${ctr_args[@]}" "$@"
    fi
}
