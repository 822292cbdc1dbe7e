// bench_load [--tets N] [--dir DIR] [--keep]: load time and peak memory of real-format
// volume models, generated here:
//  - a tetrahedral layered model (tests/common/tet_model.hpp, Kuhn tetrahedra with a
//    pinched-out lens) of about N tetrahedra (default 1,000,000) written as .vtu with
//    appended zlib-compressed data and as ascii (tests/common/vtu_writer.hpp);
//  - a GOCAD Model3d (TSURF/TFACE patches + REGION definitions) of a synthetic model
//    (model/synthetic/synthetic.hpp) of about 10M triangles (writeModel3d below).
// Each case is loaded with loadModel() in a forked child; `load_peak_rss_mib` is that
// child's peak resident memory when the load (and a second validate) is done. Phases:
// `load_s` is loadModel end to end (read + parse + boundary shells + validate);
// `validate_s` and `boundaries_s` are those steps timed again on their own in the child
// (validate() on the loaded model; regionBoundaries on the same cells, generated again after
// the model is freed), and `parse_cpu_s` = load - validate - boundaries (process CPU
// seconds) is what remains (reading, decoding, cell conversion, model assembly). Wall and
// CPU seconds are both given: on a shared machine the CPU figures are the cost. Prints one
// JSON document.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "model/mesh/volume_mesh.hpp"
#include "model/synthetic/synthetic.hpp"
#include "tests/common/tet_model.hpp"
#include "tests/common/vtu_writer.hpp"

using namespace geoslice;

namespace {

// Runs f() in a forked child that prints one JSON object; adds the child's peak RSS.
template <class F>
nlohmann::ordered_json inChild(const std::string& label, F&& f) {
    std::fflush(stdout);
    int fds[2];
    if (pipe(fds) != 0) return {{"case", label}, {"error", "pipe failed"}};
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        const std::string line = f().dump();
        if (write(fds[1], line.data(), line.size()) < 0) _exit(1);
        _exit(0);
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
    if (j.is_discarded()) j = {{"case", label}, {"error", "child failed"}};
    j["peak_rss_mib"] = double(ru.ru_maxrss) / 1024.0;
    return j;
}

// A GOCAD Model3d of a synthetic model (model/synthetic/synthetic.hpp): every part is a TSURF with one
// TFACE (its key triangle = its first triangle); every closed body is a REGION bounded by its
// own shell, listed as -id (outward triangles: the region lies against the key triangle's
// normal); the Universe lists every shell as +id. Surfaces (faults) are TSURFs in no region.
// Returns the triangles written.
std::size_t writeModel3d(const Model& m, const std::string& path) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::vector<char> buffer(1 << 20);
    std::setvbuf(f, buffer.data(), _IOFBF, buffer.size());
    char num[64];
    auto put = [&](double v) {
        auto r = std::to_chars(num, num + sizeof num, v);
        std::fwrite(num, 1, static_cast<std::size_t>(r.ptr - num), f);
    };
    auto putInt = [&](std::uint64_t v) {
        auto r = std::to_chars(num, num + sizeof num, v);
        std::fwrite(num, 1, static_cast<std::size_t>(r.ptr - num), f);
    };
    std::vector<const Part*> parts;
    for (const auto& b : m.bodies) parts.push_back(&b);
    for (const auto& s : m.surfaces) parts.push_back(&s);
    auto name = [&](std::size_t i) { return "part_" + std::to_string(i); };
    std::fputs("GOCAD Model3d 1\nHEADER {\nname:bench_model3d\n}\n", f);
    for (std::size_t i = 0; i < parts.size(); ++i) std::fprintf(f, "TSURF %s\n", name(i).c_str());
    for (std::size_t i = 0; i < parts.size(); ++i) {
        std::fprintf(f, "TFACE %zu %s %s\n", i + 1, i < m.bodies.size() ? "boundary" : "fault", name(i).c_str());
        const Mesh& mesh = parts[i]->mesh;
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3& p = mesh.positions[mesh.indices[static_cast<std::size_t>(k)]];
            std::fputs("  ", f);
            put(p.x), std::fputc(' ', f), put(p.y), std::fputc(' ', f), put(p.z), std::fputc('\n', f);
        }
    }
    const std::size_t universe = parts.size() + 1;
    std::fprintf(f, "REGION %zu Universe\n", universe);
    for (std::size_t i = 0; i < m.bodies.size(); ++i) std::fprintf(f, " +%zu", i + 1);
    std::fputs(" 0\n", f);
    for (std::size_t i = 0; i < m.bodies.size(); ++i) {
        std::string region = m.bodies[i].name.empty() ? name(i) : m.bodies[i].name;  // one token
        for (char& ch : region)
            if (ch == ' ' || ch == '\t') ch = '_';
        std::fprintf(f, "REGION %zu %s\n -%zu 0\n", universe + 1 + i, region.c_str(), i + 1);
    }
    std::fputs("END\n", f);
    std::size_t triangles = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const Mesh& mesh = parts[i]->mesh;
        std::fprintf(f, "GOCAD TSurf 1\nHEADER {\nname:%s\n}\nTFACE\n", name(i).c_str());
        for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
            std::fputs("VRTX ", f);
            putInt(v + 1);
            const glm::dvec3& p = mesh.positions[v];
            std::fputc(' ', f), put(p.x), std::fputc(' ', f), put(p.y), std::fputc(' ', f), put(p.z),
                std::fputc('\n', f);
        }
        for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
            std::fputs("TRGL ", f);
            putInt(mesh.indices[t] + 1), std::fputc(' ', f), putInt(mesh.indices[t + 1] + 1), std::fputc(' ', f);
            putInt(mesh.indices[t + 2] + 1), std::fputc('\n', f);
        }
        triangles += mesh.triangleCount();
        std::fputs("END\n", f);
    }
    const bool ok = std::fclose(f) == 0;
    return ok ? triangles : 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t tets = 1000000, model3dTriangles = 10000000;
    std::filesystem::path dir = std::filesystem::temp_directory_path() / ("bench_load_" + std::to_string(getpid()));
    bool keep = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--tets" && i + 1 < argc)
            tets = std::stoul(argv[++i]);
        else if (a == "--model3d-triangles" && i + 1 < argc)
            model3dTriangles = std::stoul(argv[++i]);
        else if (a == "--dir" && i + 1 < argc)
            dir = argv[++i];
        else if (a == "--keep")
            keep = true;
        else {
            std::fprintf(stderr,
                         "usage: bench_load [--tets N] [--model3d-triangles N (0: skip)] [--dir DIR] [--keep]\n");
            return 2;
        }
    }
    std::filesystem::create_directories(dir);
    nlohmann::ordered_json results = nlohmann::ordered_json::array();

    // (a) .vtu: nx = ny = 1.04 nz cubes of six tetrahedra each. The files are written by a
    // child of their own, so that the loading children start from a small parent.
    test::TetModelOptions to;
    to.nz = std::max(3, static_cast<int>(std::lround(std::cbrt(double(tets) / 6.0 / (1.04 * 1.04)))));
    to.nx = to.ny = std::max(6, static_cast<int>(std::lround(std::sqrt(double(tets) / 6.0 / to.nz))));
    to.origin = glm::dvec3(35500000.0, 3388000.0, -1000.0);
    struct VtuCase {
        std::string name, file;
        testing::VtuEncoding encoding;
    };
    std::vector<VtuCase> cases(2);
    cases[0].name = "vtu appended zlib";
    cases[0].file = (dir / "appended_zlib.vtu").string();
    cases[0].encoding.format = testing::VtuEncoding::Format::Appended;
    cases[0].encoding.zlib = true;
    cases[0].encoding.header64 = true;
    cases[1].name = "vtu ascii";
    cases[1].file = (dir / "ascii.vtu").string();
    auto written = inChild("write .vtu files", [&] {
        const test::TetModel tm = test::tetLayeredModel(to);
        testing::VtuGrid grid;
        grid.points = tm.mesh.positions;
        testing::VtuGrid::Array formation{"formation", "Int32", 1, {}};
        grid.types.assign(tm.mesh.cellCount(), 10);
        grid.connectivity.assign(tm.mesh.cellVertices.begin(), tm.mesh.cellVertices.end());
        for (std::size_t c = 0; c < tm.mesh.cellCount(); ++c) {
            grid.offsets.push_back(tm.mesh.cellOffsets[c + 1]);
            formation.values.push_back(tm.mesh.cellRegions[c] + 1);
        }
        grid.cellData.push_back(std::move(formation));
        nlohmann::ordered_json j{{"case", "write .vtu files"}};
        for (const VtuCase& c : cases) {
            const double t0 = bench::nowSeconds();
            std::ofstream(c.file, std::ios::binary) << testing::writeVtu(grid, c.encoding);
            j[c.name + " write_s"] = bench::nowSeconds() - t0;
        }
        return j;
    });
    results.push_back(written);
    for (const VtuCase& c : cases) {
        results.push_back(inChild(c.name, [&] {
            // Wall and process CPU seconds: on a shared machine the CPU figures show the
            // cost without the waiting.
            const double t0 = bench::nowSeconds(), c0 = bench::processCpuSeconds();
            auto m = loadModel(c.file);
            const double t1 = bench::nowSeconds(), c1 = bench::processCpuSeconds();
            if (!m) return nlohmann::ordered_json{{"case", c.name}, {"error", m.error().message}};
            validate(m.value());
            const double t2 = bench::nowSeconds(), c2 = bench::processCpuSeconds();
            const double loadPeak = bench::peakRssMiB();
            nlohmann::ordered_json j{{"case", c.name},
                                     {"file_mib", double(std::filesystem::file_size(c.file)) / 1048576.0},
                                     {"bodies", m->bodies.size()},
                                     {"boundary_triangles", m->triangleCount()},
                                     {"validation_errors", m->validation.hasErrors()},
                                     {"load_s", t1 - t0},
                                     {"load_cpu_s", c1 - c0},
                                     {"validate_s", t2 - t1},
                                     {"validate_cpu_s", c2 - c1}};
            m = makeError(ErrorCode::Internal, "freed");
            // Boundary shells alone, on the same cells.
            const test::TetModel tm = test::tetLayeredModel(to);
            const double t3 = bench::nowSeconds(), c3 = bench::processCpuSeconds();
            auto shells = regionBoundaries(tm.mesh, tm.regionCount());
            const double t4 = bench::nowSeconds(), c4 = bench::processCpuSeconds();
            j["tetrahedra"] = tm.mesh.cellCount();
            j["points"] = tm.mesh.positions.size();
            j["boundaries_s"] = shells ? t4 - t3 : -1.0;
            j["boundaries_cpu_s"] = shells ? c4 - c3 : -1.0;
            j["parse_cpu_s"] = (c1 - c0) - (c2 - c1) - (c4 - c3);
            j["load_peak_rss_mib"] = loadPeak;
            return j;
        }));
    }

    // (b) GOCAD Model3d of a synthetic model of about N triangles (text: ~50 bytes a triangle).
    if (model3dTriangles > 0) {
        const std::string file = (dir / "synthetic.ml").string();
        results.push_back(inChild("write .ml file", [&] {
            SyntheticOptions so;
            so.triangles = model3dTriangles;
            so.crs = Crs::fromEpsg(4523).value();
            auto m = generateSynthetic(so);
            if (!m) return nlohmann::ordered_json{{"case", "write .ml file"}, {"error", m.error().message}};
            const double t0 = bench::nowSeconds();
            const std::size_t count = writeModel3d(m.value(), file);
            return nlohmann::ordered_json{{"case", "write .ml file"},
                                          {"triangles", count},
                                          {"bodies", m->bodies.size()},
                                          {"surfaces", m->surfaces.size()},
                                          {"write_s", bench::nowSeconds() - t0}};
        }));
        results.push_back(inChild("model3d", [&] {
            const double t0 = bench::nowSeconds(), c0 = bench::processCpuSeconds();
            auto m = loadModel(file);
            const double t1 = bench::nowSeconds(), c1 = bench::processCpuSeconds();
            if (!m) return nlohmann::ordered_json{{"case", "model3d"}, {"error", m.error().message}};
            validate(m.value());
            const double t2 = bench::nowSeconds(), c2 = bench::processCpuSeconds();
            return nlohmann::ordered_json{{"case", "model3d"},
                                          {"file_mib", double(std::filesystem::file_size(file)) / 1048576.0},
                                          {"bodies", m->bodies.size()},
                                          {"surfaces", m->surfaces.size()},
                                          {"triangles", m->triangleCount()},
                                          {"validation_errors", m->validation.hasErrors()},
                                          {"load_s", t1 - t0},
                                          {"load_cpu_s", c1 - c0},
                                          {"validate_s", t2 - t1},
                                          {"validate_cpu_s", c2 - c1},
                                          {"parse_cpu_s", (c1 - c0) - (c2 - c1)},
                                          {"load_peak_rss_mib", bench::peakRssMiB()}};
        }));
    }

    if (!keep) std::filesystem::remove_all(dir);
    std::printf("%s\n", nlohmann::ordered_json({{"benchmark", "load"}, {"results", results}}).dump(2).c_str());
    return 0;
}
