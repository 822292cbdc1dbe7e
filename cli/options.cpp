// The flags and readers the subcommands share (cli/options.hpp).
#include "cli/options.hpp"

#include "api/params.hpp"

namespace geoslice::cli {

Result<std::vector<double>> parseNumbersFlag(const std::string& flag, const std::string& text, std::size_t count) {
    return api::parseNumberList(flag, text, count);
}

Result<Plane> parsePlaneFlag(const std::string& text) {
    auto v = api::parseNumberList("--plane", text, 4);
    if (!v) return v.error();
    auto p = makePlane(v.value()[0], v.value()[1], v.value()[2], v.value()[3]);
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
