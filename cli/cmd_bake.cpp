// geoslice bake MODEL [--attributes table.csv|json] [--field blocks.csv | --vertex-field NAME]
// [--breaks a,b,..] [--field-unit U] [--size 4096] [--min-density D]
// [--max-pages N] [--threads N] [--gltf FILE.glb] --out DIR: bakes the attribute-indexed texture and writes the
// package (bake/package.hpp). Progress: a bar on a terminal (stderr), plain lines otherwise.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "cli/commands.hpp"
#include "model/io/loaders.hpp"
#include "section/index/leaf_order.hpp"

namespace geoslice::cli {
namespace {

struct BakeArgs {
    std::string model, attributes, out, gltf, field, vertexField, fieldUnit;
    std::vector<double> breaks;
    std::uint32_t size = 4096;
    double minDensity = bake::PackOptions{}.minDensity;
    std::uint32_t maxPages = bake::PackOptions{}.maxPages;
    std::uint32_t maxChart = bake::ChartOptions{}.maxTriangles;
    double angle = bake::ChartOptions{}.maxDihedralDegrees;
    unsigned threads = 0;
    LoadOptions load;
};

// Progress on stderr: a redrawn bar on a terminal; otherwise one line per stage and per 25 %.
class Progress {
public:
    Progress() : tty_(isatty(STDERR_FILENO) != 0) {}
    void operator()(std::string_view stage, double f) {
        if (tty_) {
            const int width = 30, filled = static_cast<int>(f * width + 0.5);
            std::fprintf(stderr, "\r%-7.*s [%.*s%*s] %3d%%", int(stage.size()), stage.data(), filled,
                         "##############################", width - filled, "", int(f * 100.0 + 0.5));
            if (f >= 1.0) std::fputc('\n', stderr);
            std::fflush(stderr);
            return;
        }
        const int quarter = static_cast<int>(f * 4.0);
        if (stage != stage_ || quarter > quarter_) {
            stage_ = std::string(stage);
            quarter_ = quarter;
            std::fprintf(stderr, "bake: %s %d%%\n", stage_.c_str(), quarter * 25);
        }
    }

private:
    bool tty_;
    std::string stage_;
    int quarter_ = -1;
};

int runBake(const BakeArgs& a) {
    auto model = loadModel(a.model, a.load);
    if (!model) {
        std::fprintf(stderr, "geoslice bake: %s\n", model.error().message.c_str());
        return 1;
    }
    if (!a.attributes.empty()) {
        auto table = AttributeTable::load(a.attributes);
        if (!table) {
            std::fprintf(stderr, "geoslice bake: %s\n", table.error().message.c_str());
            return 1;
        }
        for (const auto& [id, rec] : table->records()) model->attributes.put(rec);
    }
    if (!a.field.empty() && !a.vertexField.empty()) {
        std::fprintf(stderr,
                     "geoslice bake: --field (block model) and --vertex-field (per-vertex property) exclude "
                     "each other: give one\n");
        return 1;
    }
    bake::BlockModel blocks;
    if (!a.field.empty()) {
        std::ifstream in(a.field, std::ios::binary);
        if (!in) {
            std::fprintf(stderr, "geoslice bake: %s: cannot open\n", a.field.c_str());
            return 1;
        }
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        auto parsed = bake::parseBlockCsv(text, a.field);
        if (!parsed) {
            std::fprintf(stderr, "geoslice bake: %s\n", parsed.error().message.c_str());
            return 1;
        }
        blocks = std::move(parsed).value();
    }
    // The package stores the mesh in the section BVH's leaf order (section/index/leaf_order.hpp).
    if (auto s = reorderForSection(model.value()); !s) {
        std::fprintf(stderr, "geoslice bake: %s\n", s.error().message.c_str());
        return 1;
    }
    bake::BakeOptions o;
    if (!a.field.empty() || !a.vertexField.empty()) {
        if (!a.field.empty()) o.field.blocks = &blocks;
        o.field.vertexProperty = a.vertexField;
        o.field.breaks = a.breaks;
        o.field.unit = a.fieldUnit;
    }
    o.pack.width = o.pack.height = a.size;
    o.pack.minDensity = a.minDensity;
    o.pack.maxPages = a.maxPages;
    o.charts.maxTriangles = a.maxChart;
    o.charts.maxDihedralDegrees = a.angle;
    o.threads = a.threads;
    Progress progress;
    auto baked = bake::bakeModel(model.value(), o, [&](std::string_view s, double f) { progress(s, f); });
    if (!baked) {
        std::fprintf(stderr, "geoslice bake: %s: %s\n", a.model.c_str(), baked.error().message.c_str());
        return 1;
    }
    progress("write", 0.0);
    if (auto s = bake::writePackage(model.value(), baked.value(), a.out); !s) {
        std::fprintf(stderr, "geoslice bake: %s\n", s.error().message.c_str());
        return 1;
    }
    if (!a.gltf.empty()) {
        if (auto s = bake::writeFeatureGlb(model.value(), baked.value(), a.gltf); !s) {
            std::fprintf(stderr, "geoslice bake: %s: %s\n", a.gltf.c_str(), s.error().message.c_str());
            return 1;
        }
    }
    progress("write", 1.0);
    // The package must load as the server loads it: float32 positions can merge vertices a
    // fraction of a millimetre apart, and a body that is not closed would be refused.
    progress("check", 0.0);
    if (auto s = bake::verifyPackage(a.out); !s) {
        std::fprintf(stderr, "geoslice bake: %s: %s\n", a.out.c_str(), s.error().message.c_str());
        return 1;
    }
    progress("check", 1.0);
    const auto& st = baked->stats;
    std::printf(
        "baked %zu triangles into %zu charts (%zu split after LSCM), %u page(s) of %ux%u at %.4g texels/m, "
        "texel utilisation %.1f %%, angle distortion mean %.4f max %.3g, area distortion mean %.4f max %.3g -> %s\n",
        st.triangles, st.charts, st.splitCharts, baked->pages, baked->width, baked->height, baked->density,
        100.0 * st.texelUtilisation, st.distortion.meanAngle, st.distortion.maxAngle, st.distortion.meanArea,
        st.distortion.maxArea, a.out.c_str());
    return 0;
}

}  // namespace

void addBake(CLI::App& app, int& exitCode) {
    auto a = std::make_shared<BakeArgs>();
    CLI::App* cmd = app.add_subcommand(
        "bake", "Bake the attribute-indexed texture (charts, LSCM, packing, R32UI record ids) and write the package");
    cmd->add_option("MODEL", a->model, "Model file (glTF/GLB, OBJ, TSurf, Geo3DML, .vtu)")->required();
    addLoadOptions(cmd, a->load);
    cmd->add_option("--attributes", a->attributes, "Attribute table (.csv or .json) merged over the model's records");
    cmd->add_option("--field", a->field,
                    "Field from a block model CSV (x,y,z,dx,dy,dz,value: centres and sizes in world metres): texels "
                    "inside a block get a record per (part record, class of the block's value)");
    cmd->add_option("--vertex-field", a->vertexField,
                    "Field from a per-vertex property of the model (e.g. a TSurf PVRTX column such as \"grade\"): "
                    "texels get a record per (part record, class of the value interpolated from the triangle's "
                    "vertices); parts without it keep their record. Not with --field");
    cmd->add_option("--breaks", a->breaks,
                    "Class breaks of the field's value (--field or --vertex-field), increasing (e.g. 95,98)")
        ->delimiter(',');
    cmd->add_option("--field-unit", a->fieldUnit, "Unit of the field's value (e.g. \"% SiO2\")");
    cmd->add_option("--size", a->size, "Texture width and height, texels (default 4096)")->check(CLI::Range(8, 16384));
    cmd->add_option("--min-density", a->minDensity,
                    "Texels per metre below which more texture pages are used instead of one")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-pages", a->maxPages, "Texture budget in pages; a model needing more is an error")
        ->check(CLI::Range(1, 4096));
    cmd->add_option("--max-chart", a->maxChart, "Triangles per chart at most")->check(CLI::Range(1, 1 << 20));
    cmd->add_option("--angle", a->angle, "Dihedral angle threshold for charts, degrees (default 85)")
        ->check(CLI::Range(1.0, 180.0));
    cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)");
    cmd->add_option("--out", a->out, "Package directory (created)")->required();
    cmd->add_option("--gltf", a->gltf,
                    "Also write a GLB with EXT_mesh_features (feature-ID texture) and EXT_structural_metadata "
                    "(one-page bakes)");
    cmd->callback([a, &exitCode] { exitCode = runBake(*a); });
}

}  // namespace geoslice::cli
