// The memory limit of the container (or systemd unit) the server runs in, from its cgroup, so
// that the render budget and the caches fit inside it by default: a pod with a 6 GiB limit
// must answer 503 when renders would need more, never be OOM-killed.
//
// cgroup v2 (unified): <root><path>/memory.max ("max": no limit); cgroup v1:
// <root>/memory<path>/memory.limit_in_bytes (a value of 2^62 or more, the kernel's "no limit",
// counts as none). <path> is this process's cgroup from /proc/self/cgroup ("0::/path" for v2,
// "N:memory:/path" for v1; "/" inside a container's own cgroup namespace).
// Any thread; reads a few small files.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "server/config.hpp"

namespace geoslice::server {

struct ContainerMemory {
    std::size_t limitBytes = 0;
    std::string source;  // the file the limit came from
};

// The limit, or nullopt when there is none (or no cgroup file can be read).
std::optional<ContainerMemory> containerMemoryLimit(const std::string& procSelfCgroup = "/proc/self/cgroup",
                                                    const std::string& cgroupRoot = "/sys/fs/cgroup");

// Fractions of a container's limit the defaults take: renders under way (admission by
// estimated memory, 503 beyond it) and the encoded-answer cache. The rest is for the models
// themselves (a baked L4 model is about 1.5 GB) and the process.
constexpr double kRenderBudgetShare = 0.5, kCacheShare = 0.125;

// Lowers memoryBudgetMiB and cacheMiB to their shares of `limit` where they are still at
// their defaults (never raises them; an operator's explicit value is kept), and records the
// limit in config.containerMemoryMiB / containerMemorySource for /readyz.
void fitToContainer(ServerConfig& config, const ContainerMemory& limit);

}  // namespace geoslice::server
