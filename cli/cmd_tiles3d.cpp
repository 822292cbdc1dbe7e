// geoslice tiles3d MODEL --out DIR: the model as a static OGC 3D Tiles 1.1 tileset
// (renderer/tiles3d/tileset3d.hpp), the same one GET /v1/models/{id}/3dtiles/ serves:
// DIR/tileset.json and DIR/tiles/<n>.glb, for any static file server or CesiumJS app.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "api/catalog.hpp"
#include "cli/commands.hpp"
#include "model/io/loaders.hpp"
#include "model/json_text.hpp"
#include "model/version.hpp"
#include "renderer/tiles3d/tileset3d.hpp"

namespace geoslice::cli {

void addTiles3d(CLI::App& app, int& exitCode) {
    struct Opts {
        std::string model, out;
        std::size_t perTile = Tiles3dOptions{}.trianglesPerTile;
        LoadOptions load;
    };
    auto o = std::make_shared<Opts>();
    CLI::App* cmd =
        app.add_subcommand("tiles3d", "Write the model as a 3D Tiles 1.1 tileset (tileset.json + glTF tiles)");
    cmd->add_option("MODEL", o->model, "Model file")->required();
    addLoadOptions(cmd, o->load);
    cmd->add_option("--out", o->out, "Directory to write (created; tileset.json and tiles/ inside)")->required();
    cmd->add_option("--triangles-per-tile", o->perTile, "About this many triangles per leaf tile")
        ->check(CLI::Range(std::size_t(256), std::size_t(1) << 24));
    cmd->callback([o, &exitCode] {
        auto fail = [&](const std::string& msg, int code) {
            std::fprintf(stderr, "geoslice tiles3d: %s\n", msg.c_str());
            exitCode = code;
        };
        auto model = loadModel(o->model, o->load);
        if (!model) return fail(model.error().message, 1);
        if (model->crs.isLocal())
            return fail(o->model + " has no CRS: 3D Tiles place the model on the globe (give --crs or a .crs file)", 1);
        const api::Wgs84Choice w = api::chooseWgs84Transform(model->crs, model->bounds());
        if (!w.lonLat) return fail("no WGS 84 transformation for " + model->crs.id() + ": " + w.lonLatNote, 1);
        if (!w.lonLatNote.empty()) std::fprintf(stderr, "geoslice tiles3d: note: %s\n", w.lonLatNote.c_str());
        Tiles3dOptions options;
        options.trianglesPerTile = o->perTile;
        auto ts = Tileset3d::build(
            model.value(), [&w](const glm::dvec3& p) { return w.lonLat->apply(p); }, options);
        if (!ts) return fail(ts.error().message, 1);
        std::error_code ec;
        const std::filesystem::path dir(o->out);
        std::filesystem::create_directories(dir / "tiles", ec);
        if (ec) return fail("cannot create " + (dir / "tiles").string() + ": " + ec.message(), 1);
        auto write = [&](const std::filesystem::path& p, const void* data, std::size_t n) {
            std::ofstream f(p, std::ios::binary);
            f.write(static_cast<const char*>(data), std::streamsize(n));
            f.close();
            return bool(f);
        };
        std::size_t bytes = 0;
        for (std::size_t n = 0; n < ts.value()->tileCount(); ++n) {
            auto glb = ts.value()->tileGlb(n);
            if (!glb) return fail(glb.error().message, 1);
            const auto p = dir / "tiles" / (std::to_string(n) + ".glb");
            if (!write(p, glb->data(), glb->size())) return fail("cannot write " + p.string(), 1);
            bytes += glb->size();
        }
        const std::string text = jsonText(ts.value()->tilesetJson("tiles/", kGeneratorName), 1);
        if (!write(dir / "tileset.json", text.data(), text.size()))
            return fail("cannot write " + (dir / "tileset.json").string(), 1);
        std::printf("%s: %zu triangles, %zu tiles, %.1f MB, built in %.0f ms\n", (dir / "tileset.json").c_str(),
                    ts.value()->triangleCount(), ts.value()->tileCount(), double(bytes) / 1e6, ts.value()->buildMs());
    });
}

}  // namespace geoslice::cli
