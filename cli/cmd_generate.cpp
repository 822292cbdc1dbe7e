// geoslice generate: write a deterministic synthetic mine model as GLB + attribute table.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli/commands.hpp"
#include "model/gltf_io.hpp"
#include "model/json_text.hpp"
#include "model/synthetic.hpp"
#include "model/validate.hpp"

namespace geoslice::cli {

void addGenerate(CLI::App& app, int& exitCode) {
    struct Opts {
        std::string size, crs, at, ore = "nested", out;
        std::size_t triangles = 0;
        std::uint64_t seed = 1;
        bool draco = false, check = false;
    };
    auto o = std::make_shared<Opts>();
    CLI::App* cmd =
        app.add_subcommand("generate", "Write a deterministic synthetic mine model (GLB + <stem>.attributes.json)");
    cmd->add_option("--triangles", o->triangles, "Target triangle count (met within 5%; at least 2000)");
    cmd->add_option("--size", o->size, "Named size instead of --triangles: L1 (500K), L2 (2M), L3 (5M), L4 (10M)");
    cmd->add_option("--seed", o->seed, "Seed for fold phases, thickness and terrain (default 1)");
    cmd->add_option("--crs", o->crs, "Projected CRS to place the model in, e.g. EPSG:4523 (CGCS2000 GK zone 35)");
    cmd->add_option("--at", o->at, "Model centre as LON,LAT in degrees (default: central meridian, 30.6 N)");
    cmd->add_option("--ore", o->ore, "Orebody variant: nested (host without hole) or partition (host with cavity)");
    cmd->add_flag("--draco", o->draco, "Compress meshes with KHR_draco_mesh_compression");
    cmd->add_flag("--check", o->check, "Validate the generated model before writing (slower)");
    cmd->add_option("--out", o->out, "Output .glb path")->required();
    cmd->callback([o, &exitCode] {
        auto fail = [&](const std::string& msg, int code) {
            std::fprintf(stderr, "geoslice generate: %s\n", msg.c_str());
            exitCode = code;
        };
        SyntheticOptions so;
        so.seed = o->seed;
        if (!o->size.empty()) {
            auto n = namedModelSize(o->size);
            if (!n) return fail("--size \"" + o->size + "\" is not one of L1, L2, L3, L4", 2);
            so.triangles = *n;
        } else if (o->triangles) {
            so.triangles = o->triangles;
        }
        if (o->ore == "nested")
            so.ore = OreVariant::Nested;
        else if (o->ore == "partition")
            so.ore = OreVariant::Partition;
        else
            return fail("--ore \"" + o->ore + "\" must be nested or partition", 2);
        if (!o->crs.empty()) {
            auto crs = Crs::parse(o->crs);
            if (!crs) return fail(crs.error().message, 2);
            so.crs = crs.value();
        }
        if (!o->at.empty()) {
            double lon = 0, lat = 0;
            char extra = 0;
            if (std::sscanf(o->at.c_str(), "%lf,%lf%c", &lon, &lat, &extra) != 2 || !std::isfinite(lon) ||
                !std::isfinite(lat))
                return fail("--at \"" + o->at + "\" is not LON,LAT in degrees", 2);
            so.atLonLat = glm::dvec2(lon, lat);
        }
        const auto t0 = std::chrono::steady_clock::now();
        auto model = generateSynthetic(so);
        if (!model) return fail(model.error().message, 1);
        const auto t1 = std::chrono::steady_clock::now();
        if (o->check) {
            ValidationReport r = validate(model.value());
            for (const auto& i : r.issues)
                if (i.severity == ValidationIssue::Severity::Error)
                    std::fprintf(stderr, "  error: %s: %s\n", i.part.c_str(), i.message.c_str());
            if (r.hasErrors()) return fail("the generated model failed validation", 1);
        }
        GlbWriteOptions wo;
        wo.draco = o->draco;
        if (auto s = writeGlb(model.value(), o->out, wo); !s) return fail(s.error().message, 1);
        std::filesystem::path p(o->out);
        std::string side = (p.parent_path() / (p.stem().string() + ".attributes.json")).string();
        std::ofstream f(side);
        f << jsonText(model->attributes.toJson(), 2) << "\n";
        if (!f) return fail(side + ": cannot write the attribute table", 1);
        const auto t2 = std::chrono::steady_clock::now();
        std::printf("wrote %s (%zu triangles, %zu bodies, %zu surfaces, %s) and %s in %.2f s (generate %.2f s)\n",
                    o->out.c_str(), model->triangleCount(), model->bodies.size(), model->surfaces.size(),
                    model->crs.id().c_str(), side.c_str(), std::chrono::duration<double>(t2 - t0).count(),
                    std::chrono::duration<double>(t1 - t0).count());
    });
}

}  // namespace geoslice::cli
