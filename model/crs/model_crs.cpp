#include "model/crs/model_crs.hpp"

namespace geoslice {
namespace {

void addWarning(Model& model, const std::string& text) {
    std::string& w = model.notes["crs_warning"];
    if (!w.empty()) w += "; ";
    w += text;
}

std::string shown(const Crs& c) { return c.isLocal() || c.epsg() != 0 ? c.id() : c.name(); }

}  // namespace

Status declareModelCrs(Model& model, std::string_view text, CrsDeclaration level, const std::string& origin) {
    auto crs = Crs::parse(text);
    if (!crs) return makeError(crs.error().code, origin + ": " + crs.error().message);
    if (auto ok = crs->checkModelCrs(); !ok) return makeError(ok.error().code, origin + ": " + ok.error().message);
    if (!model.crs.isLocal() && model.notes.find("crs_source") == model.notes.end())
        model.notes["crs_source"] = "the model file";
    if (model.crs == crs.value()) return {};
    if (!model.crs.isLocal()) {
        const std::string previous = model.notes["crs_source"];
        if (level == CrsDeclaration::Sidecar) {
            addWarning(model, origin + " declares " + shown(crs.value()) + " but " + previous + " declares " +
                                  shown(model.crs) + ": keeping " + shown(model.crs) +
                                  " (a <stem>.crs file or --crs overrides it)");
            return {};
        }
        addWarning(model,
                   origin + " overrides " + shown(model.crs) + " (from " + previous + ") with " + shown(crs.value()));
    }
    model.crs = crs.value();
    model.notes["crs_source"] = origin;
    return {};
}

}  // namespace geoslice
