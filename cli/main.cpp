// geoslice: one executable, one subcommand per task (generate, info, coords, classify...).
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"
#include "model/version.hpp"

namespace geoslice::cli {

Result<Plane> parsePlaneFlag(const std::string& text) {
    double v[4];
    char extra = 0;
    if (std::sscanf(text.c_str(), "%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &extra) != 4)
        return makeError(ErrorCode::InvalidArgument, "--plane \"" + text + "\" is not a,b,c,d (four numbers)");
    auto p = makePlane(v[0], v[1], v[2], v[3]);
    if (!p) return makeError(p.error().code, "--plane: " + p.error().message);
    return p;
}

void addLoadOptions(CLI::App* cmd, LoadOptions& options) {
    cmd->add_option("--region-array", options.vtu.regionArray,
                    ".vtu: the cell-data array naming each cell's formation (default: the first integer array)");
    cmd->add_option("--crs", options.crs,
                    "the model's CRS (EPSG:<code>, a CRS name, WKT, or local), for formats that carry none (OBJ); "
                    "overrides the CRS the file or a <stem>.crs declares (with a warning when they differ); must "
                    "measure in metres");
    cmd->add_option("--blocks", options.blocks.source,
                    "block model: a CSV (x,y,z,dx,dy,dz + property columns, e.g. grade [g/t Au]) or grid:NAME for a "
                    "Voxet of the model (default: the <stem>.blocks.json or <stem>.blocks.csv sidecar)");
    cmd->add_option("--blocks-clip", options.blocks.clip,
                    "bodies the block model counts inside (comma-separated names; default: the sidecar's, else all)")
        ->delimiter(',');
}

void addColourOptions(CLI::App* cmd, ColourOptions& options, const std::string& colourHelp) {
    cmd->add_option("--colour", options.colour, colourHelp);
    cmd->add_option("--breaks", options.breaks, "Class breaks of --colour, comma-separated (default: 5 equal classes)")
        ->delimiter(',');
    cmd->add_option("--ramp", options.ramp, "Colour ramp of --colour: viridis (default), magma, greys, spectral");
}

Result<std::optional<PropertyClasses>> colourClasses(const Model& model, const ColourOptions& options) {
    if (options.colour.empty()) return std::optional<PropertyClasses>();
    if (!model.blocks)
        return makeError(ErrorCode::InvalidArgument, "--colour: the model has no block model (--blocks or a sidecar)");
    auto c = propertyClasses(*model.blocks, options.colour, options.ramp,
                             options.breaks.empty() ? std::nullopt : std::optional(options.breaks));
    if (!c) return makeError(c.error().code, "--colour: " + c.error().message);
    return std::optional<PropertyClasses>(std::move(c.value()));
}

}  // namespace geoslice::cli

int main(int argc, char** argv) {
    CLI::App app{"geoslice: cut 3D geological models with planes and serve the sections"};
    app.require_subcommand(1);
    app.set_version_flag("--version", geoslice::kGeneratorName);
    int exitCode = 0;
    geoslice::cli::addGenerate(app, exitCode);
    geoslice::cli::addInfo(app, exitCode);
    geoslice::cli::addCoords(app, exitCode);
    geoslice::cli::addClassify(app, exitCode);
    geoslice::cli::addSection(app, exitCode);
    geoslice::cli::addRender(app, exitCode);
    geoslice::cli::addBorehole(app, exitCode);
    geoslice::cli::addReserves(app, exitCode);
    geoslice::cli::addBake(app, exitCode);
    geoslice::cli::addServe(app, exitCode);
    geoslice::cli::addQuery(app, exitCode);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "geoslice: error: %s\n", e.what());
        return 1;
    }
    return exitCode;
}
