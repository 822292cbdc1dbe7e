#include "server/container_memory.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace geoslice::server {
namespace {

std::optional<std::string> firstLine(const std::string& path) {
    std::ifstream f(path);
    std::string line;
    if (!f || !std::getline(f, line)) return std::nullopt;
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r' || line.back() == ' ')) line.pop_back();
    return line;
}

std::optional<std::size_t> parseBytes(const std::string& text) {
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 19)
        return std::nullopt;
    const unsigned long long v = std::stoull(text);
    if (v >= (1ULL << 62) || v == 0) return std::nullopt;  // the kernel's "no limit"
    return std::size_t(v);
}

}  // namespace

std::optional<ContainerMemory> containerMemoryLimit(const std::string& procSelfCgroup, const std::string& cgroupRoot) {
    std::ifstream f(procSelfCgroup);
    std::string line, v2Path, v1Path;
    bool haveV2 = false, haveV1 = false;
    while (std::getline(f, line)) {
        // hierarchy-ID:controller-list:cgroup-path
        const auto a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
        if (line.compare(0, a, "0") == 0 && controllers.empty()) haveV2 = true, v2Path = path;
        std::stringstream list(controllers);
        for (std::string c; std::getline(list, c, ',');)
            if (c == "memory") haveV1 = true, v1Path = path;
    }
    if (haveV1) {
        const std::string file = cgroupRoot + "/memory" + (v1Path == "/" ? "" : v1Path) + "/memory.limit_in_bytes";
        if (auto text = firstLine(file)) {
            if (auto bytes = parseBytes(*text)) return ContainerMemory{*bytes, file};
            return std::nullopt;
        }
    }
    if (haveV2) {
        const std::string file = cgroupRoot + (v2Path == "/" ? "" : v2Path) + "/memory.max";
        if (auto text = firstLine(file); text && *text != "max")
            if (auto bytes = parseBytes(*text)) return ContainerMemory{*bytes, file};
    }
    return std::nullopt;
}

void fitToContainer(ServerConfig& config, const ContainerMemory& limit) {
    const ServerConfig defaults;
    const std::size_t limitMiB = limit.limitBytes >> 20;
    config.containerMemoryMiB = limitMiB;
    config.containerMemorySource = limit.source;
    if (config.memoryBudgetMiB == defaults.memoryBudgetMiB)
        config.memoryBudgetMiB = std::min(config.memoryBudgetMiB,
                                          std::max<std::size_t>(1, std::size_t(double(limitMiB) * kRenderBudgetShare)));
    if (config.cacheMiB == defaults.cacheMiB)
        config.cacheMiB = std::min(config.cacheMiB, std::size_t(double(limitMiB) * kCacheShare));
}

}  // namespace geoslice::server
