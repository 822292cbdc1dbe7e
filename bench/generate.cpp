// bench_generate [L1 L2 ...]: synthetic model generation time, GLB encode time and peak
// RSS per size. Each size runs in a forked child so that peak RSS is that size's own.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/io/gltf/gltf_io.hpp"
#include "model/synthetic/synthetic.hpp"

using namespace geoslice;

int main(int argc, char** argv) {
    std::vector<std::string> sizes;
    for (int i = 1; i < argc; ++i) sizes.emplace_back(argv[i]);
    if (sizes.empty()) sizes = {"L1", "L2", "L3", "L4"};
    nlohmann::ordered_json results = nlohmann::ordered_json::array();
    for (const auto& size : sizes) {
        int fds[2];
        if (pipe(fds) != 0) return 1;
        pid_t pid = fork();
        if (pid == 0) {
            close(fds[0]);
            SyntheticOptions so;
            so.triangles = bench::triangleCountFor(size);
            so.crs = Crs::fromEpsg(4523).value();
            double t0 = bench::nowSeconds();
            auto m = generateSynthetic(so);
            double t1 = bench::nowSeconds();
            auto glb = m ? encodeGlb(m.value()) : Result<std::vector<std::uint8_t>>(m.error());
            double t2 = bench::nowSeconds();
            std::string line = nlohmann::json({{"size", size},
                                               {"triangles", m ? m->triangleCount() : 0},
                                               {"target", so.triangles},
                                               {"generate_s", t1 - t0},
                                               {"encode_glb_s", t2 - t1},
                                               {"glb_mib", glb ? double(glb->size()) / 1048576.0 : 0.0}})
                                   .dump();
            if (write(fds[1], line.data(), line.size()) < 0) _exit(1);
            _exit(m && glb ? 0 : 1);
        }
        close(fds[1]);
        std::string buf;
        char tmp[4096];
        ssize_t n;
        while ((n = read(fds[0], tmp, sizeof tmp)) > 0) buf.append(tmp, static_cast<std::size_t>(n));
        close(fds[0]);
        int status = 0;
        rusage ru{};
        wait4(pid, &status, 0, &ru);
        auto j = nlohmann::ordered_json::parse(buf, nullptr, false);
        if (j.is_discarded()) j = {{"size", size}, {"error", "child failed"}};
        j["peak_rss_mib"] = double(ru.ru_maxrss) / 1024.0;
        j["within_5_percent"] =
            j.contains("target") &&
            std::abs(j["triangles"].get<double>() - j["target"].get<double>()) <= 0.05 * j["target"].get<double>();
        results.push_back(j);
    }
    std::printf("%s\n", nlohmann::ordered_json({{"benchmark", "generate"}, {"results", results}}).dump(2).c_str());
    return 0;
}
