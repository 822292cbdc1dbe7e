#include "api/saved_sections.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <set>
#include <thread>
#include <tuple>

#include <unistd.h>

#include "api/plan.hpp"
#include "api/request.hpp"
#include "bake/package.hpp"
#include "model/io/loaders.hpp"
#include "model/json_text.hpp"
#include "model/text_scan.hpp"

namespace geoslice::api {
namespace fs = std::filesystem;
namespace {

Error at(const std::string& what, const Error& e) { return makeError(e.code, what + ": " + e.message); }
Error bad(const std::string& what, const std::string& message) {
    return makeError(ErrorCode::InvalidArgument, what + ": " + message);
}

// A text field: a string of valid UTF-8 without control characters, at most `maxBytes`;
// `number` also takes a whole JSON number ("number": 12).
Result<std::string> textField(const nlohmann::json& j, const char* key, const std::string& what, std::size_t maxBytes,
                              bool wholeNumber) {
    const auto it = j.find(key);
    if (it == j.end() || it->is_null()) return std::string();
    std::string s;
    if (it->is_string()) {
        s = it->get<std::string>();
    } else if (wholeNumber && it->is_number_integer()) {
        s = it->is_number_unsigned() ? std::to_string(it->get<unsigned long long>())
                                     : std::to_string(it->get<long long>());
    } else {
        return bad(what, std::string("'") + key + "' is not " + (wholeNumber ? "a text or a whole number" : "a text"));
    }
    s = std::string(text::trim(s));
    if (s.size() > maxBytes)
        return bad(what, std::string("'") + key + "' has " + std::to_string(s.size()) + " bytes (at most " +
                             std::to_string(maxBytes) + ")");
    if (!text::isUtf8(s)) return bad(what, std::string("'") + key + "' is not valid UTF-8");
    for (unsigned char c : s)
        if (c < 0x20 || c == 0x7f) return bad(what, std::string("'") + key + "' holds a control character");
    return s;
}

// The view parameters that draw `def` (no model=, no defaults but vx).
std::string queryOf(const SectionDef& def) {
    std::string c = def.canonical();  // model=..&<geometry>&vx=..&bg=..
    const std::size_t a = c.find('&'), bg = c.find("&bg=");
    std::string q = c.substr(a + 1, bg - a - 1);
    if (def.geometry == Geometry::Elevation) q = q.substr(0, q.find("&vx="));
    return q;
}

std::string utcNow() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

Result<SavedSection> fromStoredJson(const std::string& text, const std::string& modelId) {
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (!j.is_object()) return makeError(ErrorCode::ParseError, "not a JSON object");
    SavedSection s;
    const std::pair<const char*, std::string*> fields[] = {
        {"id", &s.id}, {"number", &s.number}, {"name", &s.name}, {"query", &s.query}, {"created", &s.created}};
    for (const auto& [key, field] : fields) {
        const auto it = j.find(key);
        if (it == j.end() || !it->is_string()) {
            if (std::string_view(key) == "number" || std::string_view(key) == "created") continue;
            return makeError(ErrorCode::ParseError, std::string("no text '") + key + "'");
        }
        *field = it->get<std::string>();
    }
    if (!isSavedSectionId(s.id)) return makeError(ErrorCode::ParseError, "'id' is not 16 hex digits");
    s.model = modelId;
    s.source = "saved";
    return s;
}

std::string modelDir(const std::string& dir, const std::string& modelId) { return (fs::path(dir) / modelId).string(); }

}  // namespace

bool isSavedSectionId(std::string_view id) {
    return id.size() == 16 &&
           std::all_of(id.begin(), id.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

nlohmann::ordered_json SavedSection::json() const {
    nlohmann::ordered_json j;
    j["id"] = id;
    j["number"] = number.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(number);
    j["name"] = name;
    j["source"] = source;
    j["query"] = query;
    if (!created.empty()) j["created"] = created;
    return j;
}

std::string sectionsSidecarFor(const std::string& modelPath) {
    fs::path p(modelPath);
    p.replace_extension(".sections.json");
    std::error_code ec;
    return fs::is_regular_file(p, ec) ? p.string() : std::string();
}

Result<SavedSection> parseSavedSection(const nlohmann::json& j, const std::string& what, const SectionTarget& target,
                                       const std::string& source) {
    if (!j.is_object()) return bad(what, "is not a JSON object");
    static const std::set<std::string> known{"number", "name", "vertices", "line", "plane", "elevation", "vx"};
    for (const auto& [key, value] : j.items())
        if (!known.count(key))
            return bad(what, "unknown field '" + text::escapeText(key.substr(0, 64)) +
                                 "' (fields: number, name, vertices or line or plane or elevation, vx)");
    SavedSection s;
    s.model = target.model;
    s.source = source;
    auto number = textField(j, "number", what, kMaxSavedSectionNumberBytes, true);
    if (!number) return number.error();
    auto name = textField(j, "name", what, kMaxSavedSectionNameBytes, false);
    if (!name) return name.error();
    s.number = std::move(number.value());
    s.name = std::move(name.value());
    if (s.name.empty() && s.number.empty()) return bad(what, "needs a 'name' or a 'number'");
    if (s.name.empty()) s.name = "Line " + s.number;

    // The geometry, as section requests give it.
    int given = 0;
    for (const char* k : {"vertices", "line", "plane", "elevation"}) given += j.contains(k) ? 1 : 0;
    if (given != 1)
        return bad(what, given ? "give one of 'vertices', 'line', 'plane' and 'elevation'"
                               : "needs 'vertices' ([[x, y], ...] in the model's CRS), 'line', 'plane' or "
                                 "'elevation'");
    nlohmann::json view = nlohmann::json::object();
    if (const auto v = j.find("vertices"); v != j.end()) {
        if (!v->is_array()) return bad(what, "'vertices' is not an array of [x, y] points");
        if (v->size() < 2 || v->size() > kMaxLineVertices)
            return bad(what, "'vertices' has " + std::to_string(v->size()) + " points (2.." +
                                 std::to_string(kMaxLineVertices) + ")");
        std::string line;
        for (std::size_t i = 0; i < v->size(); ++i) {
            const auto& p = (*v)[i];
            if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
                return bad(what, "'vertices'[" + std::to_string(i) + "] is not an [x, y] pair of numbers");
            line += (i ? "," : "") + formatNumber(p[0].get<double>()) + "," + formatNumber(p[1].get<double>());
        }
        view["line"] = line;
    }
    for (const char* k : {"line", "plane", "elevation", "vx"})
        if (j.contains(k)) view[k] = j[k];
    auto params = paramsFromJson(view, what);
    if (!params) return params.error();
    auto def = parseSectionDef(params.value(), target.model, target.crs);
    if (!def) return at(what, def.error());
    if (!def.value().cutPlanes.empty()) return bad(what, "a saved section has one plane");
    // It must meet the model, as a section request would have to.
    const Aabb& b = target.bounds;
    if (def.value().geometry == Geometry::Line) {
        glm::dvec2 lo(INFINITY), hi(-INFINITY);
        for (const glm::dvec2& p : def.value().line) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        if (hi.x < b.min.x || lo.x > b.max.x || hi.y < b.min.y || lo.y > b.max.y)
            return makeError(ErrorCode::OutOfRange, what + ": the line (x " + formatNumber(lo.x) + ".." +
                                                        formatNumber(hi.x) + ", y " + formatNumber(lo.y) + ".." +
                                                        formatNumber(hi.y) + ") misses the model (x " +
                                                        formatNumber(b.min.x) + ".." + formatNumber(b.max.x) + ", y " +
                                                        formatNumber(b.min.y) + ".." + formatNumber(b.max.y) + ")");
    } else if (auto p = checkPlaneMeetsBounds(sectionPlane(def.value()), b, target.origin); !p) {
        return at(what, p.error());
    }
    s.query = queryOf(def.value());
    s.id = hex64(fnv1a64(target.model + "|" + source + "|" + s.query + "|" + s.number + "|" + s.name));
    return s;
}

Result<std::vector<SavedSection>> loadSectionsSidecar(const std::string& path, const SectionTarget& target) {
    auto bytes = readFile(path, kMaxSectionsSidecarBytes);
    if (!bytes) return bytes.error();
    std::string_view text = bytes.value();
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // a byte-order mark
    if (!text::isUtf8(text)) return makeError(ErrorCode::ParseError, path + ": not valid UTF-8");
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded()) return makeError(ErrorCode::ParseError, path + ": not valid JSON");
    if (j.is_object()) {
        for (const auto& [key, value] : j.items())
            if (key != "sections")
                return makeError(ErrorCode::ParseError, path + ": unknown member '" +
                                                            text::escapeText(key.substr(0, 64)) + "' (\"sections\")");
        j = j.contains("sections") ? j["sections"] : nlohmann::json::array();
    }
    if (!j.is_array()) return makeError(ErrorCode::ParseError, path + ": 'sections' is not an array");
    if (j.size() > kMaxSavedSectionsPerModel)
        return makeError(ErrorCode::OutOfRange, path + ": " + std::to_string(j.size()) + " sections (at most " +
                                                    std::to_string(kMaxSavedSectionsPerModel) + ")");
    std::vector<SavedSection> out;
    std::set<std::string> numbers, names;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string what = path + ": sections[" + std::to_string(i) + "]";
        auto s = parseSavedSection(j[i], what, target, "model");
        if (!s) return s.error();
        if (!s.value().number.empty() && !numbers.insert(s.value().number).second)
            return bad(what, "number '" + s.value().number + "' is given twice");
        if (!names.insert(s.value().name).second) return bad(what, "name '" + s.value().name + "' is given twice");
        out.push_back(std::move(s.value()));
    }
    return out;
}

Result<std::pair<SavedSection, bool>> SavedSectionStore::save(SavedSection s) const {
    if (!isSavedSectionId(s.id)) return makeError(ErrorCode::Internal, "a saved section without an id");
    const std::string dir = modelDir(dir_, s.model);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec)
        return makeError(ErrorCode::IoError, "cannot create the saved-sections directory " + dir + ": " + ec.message());
    const std::string path = dir + "/" + s.id + ".json";
    if (auto before = find(s.model, s.id); before && before.value()) return std::pair{*before.value(), false};
    std::size_t count = 0;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".json") ++count;
    if (count >= kMaxSavedSectionsPerModel)
        return makeError(ErrorCode::OutOfRange, "model '" + s.model + "' has " + std::to_string(count) +
                                                    " saved sections, the most kept (" +
                                                    std::to_string(kMaxSavedSectionsPerModel) + "): delete some first");
    s.source = "saved";
    s.created = utcNow();
    nlohmann::ordered_json j = s.json();
    j.erase("source");
    const std::string text = jsonText(j, 1) + "\n";
    // A name no other writer uses, renamed into place: two replicas saving the same section
    // at once each write their own file and the second rename replaces an identical section.
    static std::atomic<unsigned> serial{0};
    const std::string tmp = dir + "/." + s.id + ".tmp-" + std::to_string(::getpid()) + "-" +
                            std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()) % 1000000) + "-" +
                            std::to_string(serial++);
    if (auto w = bake::writeFileAtomically(tmp, text.data(), text.size()); !w) {
        // A full disk (or quota) is the store's state, not a fault: Unavailable, named.
        const std::string& why = w.error().message;
        for (int full : {ENOSPC, EDQUOT, EFBIG})
            if (why.find(std::strerror(full)) != std::string::npos) return makeError(ErrorCode::Unavailable, why);
        return w.error();
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        return makeError(ErrorCode::IoError, "cannot rename " + tmp + " to " + path + ": " + std::strerror(e));
    }
    return std::pair{std::move(s), true};
}

Result<std::vector<SavedSection>> SavedSectionStore::list(const std::string& modelId,
                                                          std::vector<std::string>* skipped) const {
    std::vector<SavedSection> out;
    const std::string dir = modelDir(dir_, modelId);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return out;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string file = e.path().filename().string();
        if (file.starts_with(".") || e.path().extension() != ".json") continue;
        auto bytes = readFile(e.path().string(), 64 * 1024);
        Result<SavedSection> s = bytes ? fromStoredJson(bytes.value(), modelId) : Result<SavedSection>(bytes.error());
        if (s && s.value().id + ".json" != file) s = makeError(ErrorCode::ParseError, "its id is not its file name");
        if (!s) {
            if (skipped) skipped->push_back(file + ": " + s.error().message);
            continue;
        }
        out.push_back(std::move(s.value()));
        if (out.size() >= kMaxSavedSectionsPerModel) break;
    }
    if (ec) return makeError(ErrorCode::IoError, "cannot list " + dir + ": " + ec.message());
    std::sort(out.begin(), out.end(), [](const SavedSection& a, const SavedSection& b) {
        return std::tie(a.created, a.id) < std::tie(b.created, b.id);
    });
    return out;
}

Result<std::optional<SavedSection>> SavedSectionStore::find(const std::string& modelId, std::string_view id) const {
    if (!isSavedSectionId(id)) return std::optional<SavedSection>();
    const std::string path = modelDir(dir_, modelId) + "/" + std::string(id) + ".json";
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return std::optional<SavedSection>();
    auto bytes = readFile(path, 64 * 1024);
    if (!bytes) return bytes.error();
    auto s = fromStoredJson(bytes.value(), modelId);
    if (!s) return makeError(ErrorCode::IoError, path + ": " + s.error().message);
    return std::optional<SavedSection>(std::move(s.value()));
}

Result<bool> SavedSectionStore::remove(const std::string& modelId, std::string_view id) const {
    if (!isSavedSectionId(id)) return false;
    const std::string path = modelDir(dir_, modelId) + "/" + std::string(id) + ".json";
    if (::unlink(path.c_str()) == 0) return true;
    if (errno == ENOENT) return false;
    const int e = errno;
    return makeError(ErrorCode::IoError, "cannot delete " + path + ": " + std::strerror(e));
}

}  // namespace geoslice::api
