#include "server/routes/common.hpp"

#include <chrono>

#include "api/pixel_query.hpp"
#include "api/request.hpp"
#include "server/respond.hpp"

namespace geoslice::server {

bool mayRead(const ServerState& state, const HttpRequest& req, std::string_view id) {
    // A keyed route always has req.key while keys are on (the router answered 401 otherwise);
    // a request without one reads nothing.
    return !state.keys.enabled() || (req.key && req.key->mayRead(id));
}

void forbidModel(HttpResponse& res, std::string_view id, const std::string& instance) {
    problem(res, 403, "this API key may not read model '" + std::string(id) + "'", instance, "forbidden");
}

std::shared_ptr<const api::CatalogModel> findModel(ServerState& state, const HttpRequest& req, const std::string& id,
                                                   HttpResponse& res) {
    const std::string& instance = req.path;
    if (!api::isValidModelId(id)) {
        problem(res, 404, "model id '" + id.substr(0, 80) + "' is not a valid id ([A-Za-z0-9][A-Za-z0-9._-]{0,63})",
                instance, "not_found");
        return nullptr;
    }
    if (!mayRead(state, req, id)) {
        forbidModel(res, id, instance);
        return nullptr;
    }
    auto m = state.catalog.find(id);
    if (!m) {
        if (!state.loaded) {
            res.set_header("Retry-After", "2");
            problem(res, 503, "models are still loading; model '" + id + "' is not available yet", instance);
        } else {
            problem(res, 404, "no model '" + id + "'", instance, "not_found");
        }
        return nullptr;
    }
    if (!versionPinHolds(req, *m, res)) return nullptr;
    return m;
}

bool versionPinHolds(const HttpRequest& req, const api::CatalogModel& m, HttpResponse& res) {
    const auto range = req.params.equal_range(std::string(api::kVersionParam));
    for (auto it = range.first; it != range.second; ++it)
        if (it->second != m.version) {
            problem(res, 404,
                    "model '" + m.id + "' is at version " + m.version + " here; this URL names version '" +
                        it->second.substr(0, 40) + "' (re-read GET /v1/models/" + m.id + " for the current URLs)",
                    req.path, "model_version");
            return false;
        }
    return true;
}

std::string versionQuery(const api::CatalogModel& m) { return "?" + std::string(api::kVersionParam) + "=" + m.version; }

Result<api::Params> queryParams(const HttpRequest& req) { return api::paramsFromQuery(req.params); }

api::RayWait rayWait(const ServerState& state, const HttpRequest& req) {
    return {std::chrono::steady_clock::now() + std::chrono::milliseconds(state.config.deadlineMs), req.cancelled.get()};
}

Status validateView(const ServerState& state, const api::CatalogModel& m, const api::ViewPlan& plan) {
    if (auto classes = api::blockClasses(m, plan.section); !classes) return classes.error();
    if (plan.view == api::ViewKind::Perspective) {
        if (auto s = api::checkPerspectiveCut(m, plan); !s) return s;
        if (auto s = api::checkShownUnits(m, plan); !s) return s;
        if (!state.glEnabled)
            return makeError(ErrorCode::Unsupported,
                             "parameter 'view': perspective views need GL, which is disabled on this server (--gl "
                             "none)");
        return {};
    }
    auto mapping = api::profileMapping(m, plan);
    if (!mapping) return mapping.error();
    return {};
}

Rendered encodeEntry(const api::ViewImage& v, ImageFormat format, int quality, const std::string& etag,
                     const std::atomic<bool>* cancel) {
    EncodeOptions eo;
    eo.cancel = cancel;
    if (quality > 0) {
        eo.jpegQuality = quality;
        eo.webpQuality = quality;
    }
    auto bytes = encodeImage(v.rgba.data(), v.width, v.height, format, eo);
    if (!bytes) return bytes.error();
    auto e = std::make_shared<Encoded>();
    e->body.assign(reinterpret_cast<const char*>(bytes.value().data()), bytes.value().size());
    e->contentType = mimeType(format);
    e->etag = etag;
    return std::shared_ptr<const Encoded>(std::move(e));
}

Rendered documentEntry(std::string body, std::string contentType, std::string etag) {
    auto e = std::make_shared<Encoded>();
    e->body = std::move(body);
    e->contentType = std::move(contentType);
    e->etag = std::move(etag);
    return std::shared_ptr<const Encoded>(std::move(e));
}

std::vector<std::string_view> withNames(std::vector<std::string_view> names,
                                        std::initializer_list<std::string_view> more) {
    names.insert(names.end(), more.begin(), more.end());
    return names;
}

}  // namespace geoslice::server
