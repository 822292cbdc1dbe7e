// Attaching a block model to a model: the clipping bodies by name and the sidecar or option
// that names the source (<stem>.blocks.json, <stem>.blocks.csv, --blocks).
#include "model/blocks/block_model.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "model/io/loaders.hpp"
#include "model/model.hpp"
#include "model/text_scan.hpp"

namespace geoslice {

Status resolveBlockClip(const Model& model, BlockModel& blocks) {
    blocks.clipBodyIndex.clear();
    if (blocks.clipBodies.empty()) {
        for (std::uint32_t b = 0; b < model.bodies.size(); ++b)
            if (model.bodies[b].report.closed) blocks.clipBodyIndex.push_back(b);
        return {};
    }
    for (const std::string& name : blocks.clipBodies) {
        bool found = false;
        for (std::uint32_t b = 0; b < model.bodies.size(); ++b)
            if (model.bodies[b].name == name && model.bodies[b].report.closed) {
                blocks.clipBodyIndex.push_back(b);
                found = true;
            }
        if (!found) {
            std::string known;
            for (const Part& p : model.bodies)
                if (p.report.closed) known += (known.empty() ? "'" : ", '") + p.name + "'";
            return makeError(ErrorCode::InvalidArgument, "block model clip body '" + name +
                                                             "' is not a closed body of the model (bodies: " +
                                                             (known.empty() ? "none" : known) + ")");
        }
    }
    std::sort(blocks.clipBodyIndex.begin(), blocks.clipBodyIndex.end());
    blocks.clipBodyIndex.erase(std::unique(blocks.clipBodyIndex.begin(), blocks.clipBodyIndex.end()),
                               blocks.clipBodyIndex.end());
    return {};
}

namespace {

namespace fs = std::filesystem;

struct BlockSpec {
    std::string source;  // CSV path or grid:NAME
    std::vector<std::string> clip;
    std::vector<std::pair<std::string, std::string>> units;
    std::string sidecar;  // the JSON sidecar read, if any
};

Result<BlockSpec> blockSpec(const std::string& modelPath, const BlockOptions& options) {
    BlockSpec spec;
    const fs::path p(modelPath);
    const fs::path json = p.parent_path() / (p.stem().string() + ".blocks.json");
    const fs::path csv = p.parent_path() / (p.stem().string() + ".blocks.csv");
    std::error_code ec;
    if (options.source.empty() && fs::is_regular_file(json, ec)) {
        auto text = readFile(json.string(), std::size_t(1) << 20);
        if (!text) return text.error();
        const auto j = nlohmann::json::parse(text.value(), nullptr, false);
        if (j.is_discarded() || !j.is_object())
            return makeError(ErrorCode::ParseError, json.string() + ": not a JSON object");
        for (const auto& [key, value] : j.items())
            if (key != "source" && key != "clip" && key != "units")
                return makeError(ErrorCode::ParseError,
                                 json.string() + ": unknown field '" + key + "' (expected source, clip, units)");
        if (!j.contains("source") || !j["source"].is_string())
            return makeError(ErrorCode::ParseError,
                             json.string() + ": needs \"source\": a CSV file beside it or \"grid:NAME\"");
        spec.source = j["source"].get<std::string>();
        if (spec.source.rfind("grid:", 0) != 0) {
            if (fs::path(spec.source).is_absolute() || spec.source.find("..") != std::string::npos)
                return makeError(ErrorCode::InvalidArgument, json.string() + ": source '" + spec.source +
                                                                 "' must be a file name inside the sidecar's folder");
            spec.source = (p.parent_path() / spec.source).string();
        }
        if (j.contains("clip")) {
            if (!j["clip"].is_array())
                return makeError(ErrorCode::ParseError, json.string() + ": \"clip\" must be a list of body names");
            for (const auto& c : j["clip"]) {
                if (!c.is_string())
                    return makeError(ErrorCode::ParseError, json.string() + ": \"clip\" must be a list of body names");
                spec.clip.push_back(c.get<std::string>());
            }
        }
        if (j.contains("units")) {
            if (!j["units"].is_object())
                return makeError(ErrorCode::ParseError, json.string() + ": \"units\" must be an object");
            for (const auto& [k, v] : j["units"].items()) {
                if (!v.is_string())
                    return makeError(ErrorCode::ParseError, json.string() + ": units." + k + " must be a string");
                spec.units.emplace_back(k, v.get<std::string>());
            }
        }
        spec.sidecar = json.string();
    } else if (options.source.empty() && fs::is_regular_file(csv, ec)) {
        spec.source = csv.string();
    } else {
        spec.source = options.source;
    }
    if (!options.clip.empty()) spec.clip = options.clip;
    for (const auto& u : options.units) spec.units.push_back(u);
    return spec;
}

}  // namespace

std::vector<std::string> blockModelFiles(const std::string& modelPath, const BlockOptions& options) {
    std::vector<std::string> files;
    auto spec = blockSpec(modelPath, options);
    if (!spec) return files;
    if (!spec->sidecar.empty()) files.push_back(spec->sidecar);
    if (!spec->source.empty() && spec->source.rfind("grid:", 0) != 0) files.push_back(spec->source);
    return files;
}

Status attachBlockModel(Model& model, const std::string& modelPath, const BlockOptions& options) {
    auto spec = blockSpec(modelPath, options);
    if (!spec) return spec.error();
    if (spec->source.empty()) {
        if (!options.clip.empty())
            return makeError(ErrorCode::InvalidArgument, "--blocks-clip without a block model (--blocks)");
        return {};
    }
    Result<BlockModel> blocks = makeError(ErrorCode::Internal, "no block model");
    if (spec->source.rfind("grid:", 0) == 0) {
        const std::string name = spec->source.substr(5);
        const Grid* grid = nullptr;
        std::string known;
        for (const Grid& g : model.grids) {
            if (g.name == name) grid = &g;
            known += (known.empty() ? "'" : ", '") + g.name + "' (" + g.type + ")";
        }
        if (!grid)
            return makeError(ErrorCode::NotFound, "block model '" + spec->source + "': the model has no grid named '" +
                                                      name + "' (grids: " + (known.empty() ? "none" : known) + ")");
        blocks = blockModelFromGrid(*grid);
    } else {
        auto text = readFile(spec->source);
        if (!text) return text.error();
        blocks = blockModelFromCsv(text.value(), spec->source);
    }
    if (!blocks) return blocks.error();
    blocks->clipBodies = spec->clip;
    for (const auto& [prop, unit] : spec->units) {
        const int k = blocks->propertyIndex(prop);
        if (k < 0)
            return makeError(ErrorCode::InvalidArgument,
                             "block model " + blocks->source + ": a unit for '" + prop +
                                 "', which is not a property (properties: " + blocks->propertyList() + ")");
        blocks->properties[std::size_t(k)].unit = unit;
    }
    if (Status s = resolveBlockClip(model, blocks.value()); !s) return s;
    model.blocks = std::make_shared<const BlockModel>(std::move(blocks.value()));
    return {};
}

}  // namespace geoslice
