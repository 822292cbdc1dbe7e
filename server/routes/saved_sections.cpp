// Saved sections (api/saved_sections.hpp): a model's exploration lines and the sections
// users saved, listed and opened by name.
//   GET    /v1/models/{id}/saved-sections          the model's lines, then the saved ones
//   POST   /v1/models/{id}/saved-sections          save one: 201 new, 200 saved before (same id)
//   GET    /v1/models/{id}/saved-sections/{sid}    one
//   DELETE /v1/models/{id}/saved-sections/{sid}    delete a saved one (204); the model's own are 409
// Saving needs a store (serve --sections-dir, a directory shared by the replicas): without one
// POST is a 501 naming the flag and the list says "saving": false. Answers are never cached
// (Cache-Control: no-store): another replica may have saved a section a moment ago.
#include <optional>

#include "api/request.hpp"
#include "api/saved_sections.hpp"
#include "model/json_text.hpp"
#include "model/text_scan.hpp"
#include "server/respond.hpp"
#include "server/routes/common.hpp"
#include "server/routes/routes.hpp"

namespace geoslice::server {
namespace {

void noStore(HttpResponse& res) { res.set_header("Cache-Control", "no-store"); }

std::string sectionPath(const std::string& model, const std::string& id) {
    return "/v1/models/" + model + "/saved-sections/" + id;
}

void list(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), {}); !s) return problem(res, s.error(), req.path);
    nlohmann::ordered_json j;
    j["model"] = m->id;
    j["version"] = m->version;
    j["saving"] = st.savedSections != nullptr;
    nlohmann::ordered_json warnings = nlohmann::ordered_json::array();
    if (!m->sectionsWarning.empty()) warnings.push_back(m->sectionsWarning);
    nlohmann::ordered_json sections = nlohmann::ordered_json::array();
    for (const api::SavedSection& s : m->sections) sections.push_back(s.json());
    if (st.savedSections) {
        std::vector<std::string> skipped;
        auto saved = st.savedSections->list(m->id, &skipped);
        if (!saved) return problem(res, saved.error(), req.path);
        for (const api::SavedSection& s : saved.value()) sections.push_back(s.json());
        for (const std::string& why : skipped) warnings.push_back("saved section " + why + ": skipped");
    }
    j["warnings"] = std::move(warnings);
    j["sections"] = std::move(sections);
    noStore(res);
    sendJson(res, j);
}

void save(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    if (!st.savedSections)
        return problem(
            res, 501,
            "this server keeps no saved sections: start it with --sections-dir DIR (GEOSLICE_SECTIONS_DIR; a "
            "directory shared by every replica)",
            req.path, "saving_off");
    if (!requireJsonBody(req, res)) return;
    nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
    if (body.is_discarded())
        return problem(res, 400, "the body is not valid JSON (UTF-8)", req.path, "invalid_argument");
    auto s = api::parseSavedSection(body, "the body", api::sectionTarget(*m), "saved");
    if (!s) return problem(res, s.error(), req.path);
    auto saved = st.savedSections->save(std::move(s.value()));
    if (!saved) {
        const Error& e = saved.error();
        // A full disk is a 507 (RFC 4918), too many a 409; other write failures a 500, named.
        if (e.code == ErrorCode::OutOfRange) return problem(res, 409, e.message, req.path, "too_many_saved_sections");
        if (e.code == ErrorCode::Unavailable)
            return problem(res, 507, "cannot save the section: " + e.message, req.path, "insufficient_storage");
        return problem(res, e, req.path);
    }
    const auto& [section, isNew] = saved.value();
    res.set_header("Location", sectionPath(m->id, section.id));
    noStore(res);
    sendJson(res, section.json(), isNew ? 201 : 200);
}

// The section `sid` names: the model's own first, then the saved ones; null after answering.
std::optional<api::SavedSection> findSection(ServerState& st, const HttpRequest& req, HttpResponse& res,
                                             const api::CatalogModel& m) {
    const std::string sid = req.matches[2];
    for (const api::SavedSection& s : m.sections)
        if (s.id == sid) return s;
    if (st.savedSections) {
        auto s = st.savedSections->find(m.id, sid);
        if (!s) {
            problem(res, s.error(), req.path);
            return std::nullopt;
        }
        if (s.value()) return s.value();
    }
    problem(res, 404, "model '" + m.id + "' has no saved section '" + text::escapeText(sid, 64) + "'", req.path,
            "not_found");
    return std::nullopt;
}

void one(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto params = queryParams(req);
    if (!params) return problem(res, params.error(), req.path);
    if (auto s = api::checkKnownParams(params.value(), {}); !s) return problem(res, s.error(), req.path);
    auto s = findSection(st, req, res, *m);
    if (!s) return;
    noStore(res);
    sendJson(res, s->json());
}

void remove(ServerState& st, const HttpRequest& req, HttpResponse& res) {
    auto m = findModel(st, req, req.matches[1], res);
    if (!m) return;
    auto s = findSection(st, req, res, *m);
    if (!s) return;
    if (s->source != "saved")
        return problem(res, 409,
                       "'" + s->name + "' is one of the model's own sections (its <id>.sections.json): edit that file",
                       req.path, "model_section");
    auto gone = st.savedSections->remove(m->id, s->id);
    if (!gone) return problem(res, gone.error(), req.path);
    noStore(res);
    res.status = 204;
}

}  // namespace

void addSavedSectionRoutes(Router& router, ServerState& st) {
    router.add("GET", "/v1/models/{id}/saved-sections", "/v1/models/([^/]+)/saved-sections",
               [&st](const HttpRequest& req, HttpResponse& res) { list(st, req, res); });
    router.add("POST", "/v1/models/{id}/saved-sections", "/v1/models/([^/]+)/saved-sections",
               [&st](const HttpRequest& req, HttpResponse& res) { save(st, req, res); });
    router.add("GET", "/v1/models/{id}/saved-sections/{sid}", "/v1/models/([^/]+)/saved-sections/([^/]+)",
               [&st](const HttpRequest& req, HttpResponse& res) { one(st, req, res); });
    router.add("DELETE", "/v1/models/{id}/saved-sections/{sid}", "/v1/models/([^/]+)/saved-sections/([^/]+)",
               [&st](const HttpRequest& req, HttpResponse& res) { remove(st, req, res); });
}

}  // namespace geoslice::server
