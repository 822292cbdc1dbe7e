// Saved sections: a model's named sections, listed and opened by name ("Line 12").
//
// Two sources, one shape (SavedSection):
//  - the model's exploration lines, from the <stem>.sections.json sidecar beside the model
//    file (read at load, like the drillholes sidecar):
//        {"sections": [{"number": "12", "name": "Line 12", "vertices": [[x, y], ...], "vx": 2}, ...]}
//    (or the bare array). `vertices` are map points in the model's CRS (metres), 2..256 of
//    them; `number` (text or a whole number) and `name` are optional but one is needed (the
//    name defaults to "Line <number>"); `vx` defaults to 1 (true scale, as the API). A plane or an elevation may be
//    given instead of vertices ("plane": "a,b,c,d" | "elevation": z), as POST /sections takes.
//  - sections saved through the API (POST /v1/models/{id}/saved-sections with the same
//    fields, or "line": "x1,y1,x2,y2,..."), kept as one JSON file each in a directory shared
//    by every replica (SavedSectionStore; serve --sections-dir).
//
// A saved section's id is a hash of its model, source, definition, number and name
// (16 hex digits): the same section saved twice, or on two replicas, has one id, and ids
// survive restarts. `query` is the view parameters that draw it (line=..&vx=.. | plane=..&vx=..
// | elevation=..), ready for section.{png,pdf,...}, query and POST /sections.
//
// Thread-safety: parsing is pure; a SavedSectionStore may be used from any thread (each call
// works on the file system only; writes go to a unique temporary name and are renamed into
// place, so concurrent writers on one or many replicas never leave a torn file).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/crs/crs.hpp"
#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice::api {

constexpr std::size_t kMaxSavedSectionNameBytes = 200;
constexpr std::size_t kMaxSavedSectionNumberBytes = 32;
constexpr std::size_t kMaxSavedSectionsPerModel = 2000;  // sidecar entries, and files in the store per model
constexpr std::size_t kMaxSectionsSidecarBytes = std::size_t(8) << 20;

struct SavedSection {
    std::string id;       // 16 hex digits
    std::string model;    // model id
    std::string source;   // "model" (the sidecar's, or the demo's) or "saved"
    std::string number;   // exploration line number as written ("12", "3-1"); may be empty
    std::string name;     // what a user sees ("Line 12")
    std::string query;    // view parameters that draw it, canonical numbers
    std::string created;  // saved ones: UTC time of the first save, ISO 8601; empty for the sidecar's

    nlohmann::ordered_json json() const;
};

// The <stem>.sections.json beside a model file, or "" when there is none.
std::string sectionsSidecarFor(const std::string& modelPath);

// One section from its JSON object (a sidecar entry or a POST body): fields as in the header
// comment, checked as section requests are (api/plan.hpp parseSectionDef) and against the
// model's bounds (a section that misses the model is refused). `what` names the object in
// errors ("sections[3]", "the body"). Errors: InvalidArgument / OutOfRange naming the field.
// The model a section is checked against: its id, CRS and world bounds, and the local origin
// distances are taken from (api::CatalogModel's index has them).
struct SectionTarget {
    std::string model;
    Crs crs;
    Aabb bounds;
    glm::dvec3 origin{0.0};
};
Result<SavedSection> parseSavedSection(const nlohmann::json& j, const std::string& what, const SectionTarget& target,
                                       const std::string& source);

// The sidecar's sections, in file order. Errors name the file and the entry; two entries with
// the same number, or the same name, are an error too (a user opens them by name).
Result<std::vector<SavedSection>> loadSectionsSidecar(const std::string& path, const SectionTarget& target);

// Saved sections on disk: <dir>/<model id>/<id>.json. `dir` is created on first save.
class SavedSectionStore {
public:
    explicit SavedSectionStore(std::string dir) : dir_(std::move(dir)) {}
    const std::string& dir() const { return dir_; }

    // Saves `s` (its id already set). Returns the stored section and whether it was new: a
    // section saved before under the same id is returned as it was stored (its first
    // `created`). Errors: IoError naming the file and the system's reason; Unavailable for a
    // full disk, quota or file size limit (ENOSPC, EDQUOT, EFBIG; nothing is left behind); OutOfRange when the model
    // has kMaxSavedSectionsPerModel saved sections.
    Result<std::pair<SavedSection, bool>> save(SavedSection s) const;
    // The model's saved sections, oldest first (then by id). A file that cannot be read or
    // parsed is skipped and named in `skipped` ("<file>: why").
    Result<std::vector<SavedSection>> list(const std::string& modelId,
                                           std::vector<std::string>* skipped = nullptr) const;
    // One section, nullopt when there is none of that id (ids are 16 hex digits; anything
    // else is nullopt without touching the file system).
    Result<std::optional<SavedSection>> find(const std::string& modelId, std::string_view id) const;
    // Deletes one saved section; false when there was none.
    Result<bool> remove(const std::string& modelId, std::string_view id) const;

private:
    std::string dir_;
};

// True for 16 lower-case hex digits.
bool isSavedSectionId(std::string_view id);

}  // namespace geoslice::api
