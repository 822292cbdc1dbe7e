// geoslice query MODEL [view parameters] --pixel px,py [--pixel ...]: the pixel query of
// GET /v1/models/{id}/query without a server. The view takes HTTP's parameter names as flags
// (--plane, --planes, --cut, --line, --coords, --elevation, --view, --frame, --size, --vx,
// --eye, --target, --up, --fov) and is parsed and checked by the same code (api::parseViewPlan),
// the model file is loaded as the server loads a file of its models directory
// (api::loadCatalogModel: sidecars, validation, section index, ray scene; the model id is the
// file stem), and each pixel is answered by api::answerPixel as an uncached HTTP query is
// (the exact oracle at the pixel centre; perspective views: the first visible point on the
// pixel's ray). Prints {"results": [answer, ...]}, each answer as GET /query prints it.
// Exit 0; 1 when the model or a pixel fails; 2 for a bad view or pixel (the message names it).
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "api/catalog.hpp"
#include "api/params.hpp"
#include "api/pixel_query.hpp"
#include "api/plan.hpp"
#include "api/request.hpp"
#include "api/view.hpp"
#include "cli/commands.hpp"

namespace geoslice::cli {
namespace {

struct QueryArgs {
    std::string model;
    std::vector<std::string> planes;  // --plane, repeated: a cut-out's planes in order
    std::map<std::string, std::string> view;
    std::vector<std::string> pixels;
};

int runQuery(const QueryArgs& a) {
    auto fail = [](const std::string& m, int code) {
        std::fprintf(stderr, "geoslice query: %s\n", m.c_str());
        return code;
    };
    std::multimap<std::string, std::string> query;
    for (const std::string& p : a.planes) query.emplace("plane", p);
    for (const auto& [name, value] : a.view)
        if (!value.empty()) query.emplace(name, value);
    auto params = api::paramsFromQuery(query);
    if (!params) return fail(params.error().message, 2);
    std::vector<api::PixelXY> pixels;
    for (const std::string& text : a.pixels) {
        // "px,py" read by GET /query's own reader, so the limits and messages are HTTP's.
        const std::size_t comma = text.find(',');
        if (comma == std::string::npos) return fail("--pixel " + text + ": expected px,py, e.g. 100,200", 2);
        auto xy = api::parseQueryPixel(api::Params{{"px", text.substr(0, comma)}, {"py", text.substr(comma + 1)}});
        if (!xy) return fail("--pixel " + text + ": " + xy.error().message, 2);
        pixels.push_back(xy.value());
    }
    if (pixels.empty()) return fail("--pixel: give at least one pixel, e.g. --pixel 100,200", 2);

    const std::string stem = std::filesystem::path(a.model).stem().string();
    const std::string id = api::isValidModelId(stem) ? stem : std::string("model");
    auto model = api::loadCatalogModel(id, a.model);
    if (!model) return fail(model.error().message, 1);
    const api::CatalogModel& m = *model.value();
    auto plan = api::parseViewPlan(params.value(), m.id, m.model.crs);
    if (!plan) return fail(plan.error().message, 2);
    auto answer = api::answerBatch(m, plan.value(), pixels, nullptr, {}, nullptr, "--pixel",
                                   [&a](std::size_t i) { return "--pixel " + a.pixels[i]; });
    if (!answer) return fail(answer.error().message, 1);
    const std::string out = answer.value() + "\n";
    std::fwrite(out.data(), 1, out.size(), stdout);
    return 0;
}

}  // namespace

void addQuery(CLI::App& app, int& exitCode) {
    auto a = std::make_shared<QueryArgs>();
    CLI::App* cmd = app.add_subcommand(
        "query",
        "Answer pixel queries of a view of MODEL as GET /v1/models/{id}/query does (record, attributes, block "
        "cell, world, projected and geodetic coordinates), without a server; prints {\"results\": [...]}");
    cmd->add_option("MODEL", a->model, "Model file (its sidecars are read as the server reads them)")->required();
    cmd->add_option("--pixel", a->pixels, "Pixel px,py of the view (column, row; row 0 at the top); repeatable")
        ->required();
    cmd->add_option("--plane", a->planes,
                    "Plane a,b,c,d (keeps a*x+b*y+c*z+d >= 0); repeated: a cut-out of a perspective view");
    // The other view parameters, with HTTP's names and meanings (GET /openapi.json).
    const std::pair<const char*, const char*> viewFlags[] = {
        {"planes", "Cut-out planes a,b,c,d;a,b,c,d;... (as HTTP planes=)"},
        {"cut", "union|intersection: how a cut-out's planes combine"},
        {"line", "Vertical section along a map polyline x1,y1,x2,y2[,...]"},
        {"coords", "world|lonlat: units of --line"},
        {"elevation", "Horizontal slice at elevation z (metres)"},
        {"view", "profile|perspective (default profile)"},
        {"frame", "u0,u1,v0,v1: the plane metres shown (default: the model's bounds, 2 % margin)"},
        {"size", "WxH pixels (default 1024x1024)"},
        {"vx", "Vertical exaggeration 0.1..100 (default 1)"},
        {"eye", "Perspective camera eye x,y,z (world)"},
        {"target", "Perspective camera target x,y,z (world)"},
        {"up", "Perspective camera up x,y,z"},
        {"fov", "Perspective vertical field of view, degrees"},
    };
    for (const auto& [name, help] : viewFlags) cmd->add_option(std::string("--") + name, a->view[name], help);
    cmd->callback([a, &exitCode] { exitCode = runQuery(*a); });
}

}  // namespace geoslice::cli
