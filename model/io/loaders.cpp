#include "model/io/loaders.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <unordered_map>

#include "model/crs/model_crs.hpp"
#include "model/mesh/validate.hpp"
#include "model/style/palette.hpp"

namespace geoslice {
namespace {

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

// Merges an attributes sidecar (`<stem>.attributes.json|csv`) into a loaded model:
//  - every sidecar record is put into the table, replacing a record with the same id;
//  - a part whose name equals a sidecar record's name points at that record;
//  - otherwise a part whose record id is a sidecar record's id keeps pointing at it, and
//    when the part was named after its old record (a loader default such as "rock 3" in a
//    .vtu) it takes the sidecar record's name: that is how a sidecar names formations;
//  - sidecar rows that match no part by name or id are listed in a warning (a validation
//    issue, the model note "sidecar_unmatched", and a line on stderr), never dropped silently.
void mergeSidecar(Model& model, const AttributeTable& side, const std::string& sidePath) {
    const std::map<RecordId, AttributeRecord> old = model.attributes.records();
    for (const auto& [id, rec] : side.records()) {
        AttributeRecord r = rec;
        r.nameSource = "sidecar";
        if (!r.colourSource.empty()) r.colourSource = "sidecar";
        model.attributes.put(std::move(r));
    }
    // A sidecar row without a colour keeps the colour the file gave the part it names.
    auto keepFileColour = [&](RecordId sideId, RecordId oldId) {
        AttributeRecord* r = model.attributes.find(sideId);
        auto it = old.find(oldId);
        if (!r || !r->colourSource.empty() || it == old.end()) return;
        if (it->second.colourSource.empty() || it->second.colourSource == "palette") return;
        r->colour = it->second.colour;
        r->colourSource = it->second.colourSource;
    };
    std::set<RecordId> matched;
    for (auto* list : {&model.bodies, &model.surfaces}) {
        for (auto& part : *list) {
            if (const AttributeRecord* r = side.findByName(part.name)) {
                keepFileColour(r->id, part.record);
                part.record = r->id;
                matched.insert(r->id);
            } else if (const AttributeRecord* same = side.find(part.record)) {
                keepFileColour(same->id, part.record);
                if (auto it = old.find(part.record); it != old.end() && it->second.name == part.name)
                    part.name = same->name;
                matched.insert(same->id);
            }
        }
    }
    applyDefaultColours(model);
    std::string list;
    std::size_t unmatched = 0;
    for (const auto& [id, rec] : side.records()) {
        if (matched.count(id)) continue;
        if (unmatched++ < 20)
            list += (list.empty() ? "" : ", ") + ("'" + rec.name + "' (id " + std::to_string(id) + ")");
    }
    if (unmatched == 0) return;
    if (unmatched > 20) list += ", ... (" + std::to_string(unmatched - 20) + " more)";
    const std::string message = "attributes sidecar " + sidePath + ": " + std::to_string(unmatched) + " of " +
                                std::to_string(side.size()) + " rows match no part by name or id: " + list;
    model.notes["sidecar_unmatched"] = message;
    model.validation.issues.push_back({ValidationIssue::Severity::Warning, "", message});
    std::fprintf(stderr, "geoslice: warning: %s: %s\n", model.source.empty() ? sidePath.c_str() : model.source.c_str(),
                 message.c_str());
}

// `<stem>.crs` beside the model, then --crs; finally the model's CRS must suit a model.
Status applyCrsDeclarations(Model& model, const std::filesystem::path& p, std::string_view crsOverride) {
    const std::filesystem::path crsFile = p.parent_path() / (p.stem().string() + ".crs");
    std::error_code ec;
    if (std::filesystem::is_regular_file(crsFile, ec)) {
        auto text = readFile(crsFile.string(), std::size_t(1) << 20);
        if (!text) return text.error();
        if (auto s = declareModelCrs(model, text.value(), CrsDeclaration::CrsFile, crsFile.string()); !s) return s;
    }
    if (!crsOverride.empty())
        if (auto s = declareModelCrs(model, crsOverride, CrsDeclaration::Override, "--crs"); !s) return s;
    if (auto s = model.crs.checkModelCrs(); !s) return makeError(s.error().code, p.string() + ": " + s.error().message);
    if (auto w = model.notes.find("crs_warning"); w != model.notes.end())
        std::fprintf(stderr, "geoslice: warning: %s: %s\n", p.string().c_str(), w->second.c_str());
    return {};
}

// Content sniffing for files whose extension says nothing.
bool looksLikeAsciiStl(std::string_view data) {
    const std::string_view head = data.substr(0, 512);
    return head.substr(0, 6) == "solid " && head.find("facet") != std::string_view::npos;
}

bool looksLikeDxf(std::string_view data) {
    std::size_t i = 0;
    while (i < data.size() && i < 16 && (data[i] == ' ' || data[i] == '\t')) ++i;
    std::string_view head = data.substr(i, 64);
    return head.substr(0, 2) == "0\n" || head.substr(0, 3) == "0\r\n" ? head.find("SECTION") != std::string_view::npos
                                                                      : head.substr(0, 3) == "999";
}

// The string file of a Surpac DTM: the file its header record names (its first field, a
// bare file name: only the name is used, in the DTM's folder), else <stem>.str or <stem>.STR.
Result<std::string> surpacStringFileFor(const std::string& dtmPath, std::string_view dtm) {
    const std::filesystem::path p(dtmPath);
    std::vector<std::filesystem::path> candidates;
    const std::string_view firstLine = dtm.substr(0, std::min(dtm.find('\n'), std::size_t(1024)));
    std::string_view named = firstLine.substr(0, firstLine.find(','));
    while (!named.empty() && (named.back() == ' ' || named.back() == '\r')) named.remove_suffix(1);
    while (!named.empty() && named.front() == ' ') named.remove_prefix(1);
    if (!named.empty() && named.find('\0') == std::string_view::npos) {
        const std::filesystem::path name = std::filesystem::path(std::string(named)).filename();
        if (!name.empty() && name != "." && name != "..") candidates.push_back(p.parent_path() / name);
    }
    candidates.push_back(p.parent_path() / (p.stem().string() + ".str"));
    candidates.push_back(p.parent_path() / (p.stem().string() + ".STR"));
    for (const auto& c : candidates) {
        std::error_code ec;
        if (std::filesystem::is_regular_file(c, ec)) return c.string();
    }
    return makeError(ErrorCode::NotFound, dtmPath + ": the DTM's string file (" + candidates.front().string() +
                                              ") does not exist; a .dtm numbers the points of its .str");
}

}  // namespace

namespace {

// `path` opened for reading without blocking (a FIFO opened for reading would wait for a
// writer forever) and checked to be a regular file; -1 with `error` set otherwise.
int openRegularFile(const std::string& path, struct stat& st, Error& error) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int e = errno;
        if (e == ENOENT)
            error = makeError(ErrorCode::NotFound, path + ": does not exist (or is a dangling symlink)");
        else if (e == EACCES)
            error = makeError(ErrorCode::IoError, path + ": no read permission (" + std::strerror(e) + ")");
        else if (e == ELOOP)
            error = makeError(ErrorCode::IoError, path + ": a symlink loop (" + std::strerror(e) + ")");
        else
            error = makeError(ErrorCode::IoError, path + ": cannot open (" + std::string(std::strerror(e)) + ")");
        return -1;
    }
    if (::fstat(fd, &st) != 0) {
        error = makeError(ErrorCode::IoError, path + ": cannot stat (" + std::string(std::strerror(errno)) + ")");
        ::close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        error = makeError(ErrorCode::IoError, path + ": " + fileKindName(st.st_mode) + ", not a regular file");
        ::close(fd);
        return -1;
    }
    return fd;
}

// Reads up to `size` bytes at the file's current position (fewer only at its end).
Result<std::size_t> readSome(int fd, char* out, std::size_t size, const std::string& path) {
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::read(fd, out + done, std::min<std::size_t>(size - done, std::size_t(1) << 30));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return makeError(ErrorCode::IoError, path + ": read failed (" + std::strerror(errno) + ")");
        if (n == 0) break;
        done += std::size_t(n);
    }
    return done;
}

}  // namespace

std::string fileKindName(unsigned mode) {
    if (S_ISREG(mode)) return "a regular file";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISLNK(mode)) return "a symlink";
    return "a special file";
}

Result<std::string> readFile(const std::string& path, std::size_t maxBytes) {
    struct stat st {};
    Error error;
    const int fd = openRegularFile(path, st, error);
    if (fd < 0) return error;
    const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
    if (size > maxBytes) {
        ::close(fd);
        return makeError(ErrorCode::OutOfRange, path + ": " + std::to_string(size) + " bytes is over the limit of " +
                                                    std::to_string(maxBytes) + " bytes");
    }
    std::string data(static_cast<std::size_t>(size), '\0');
    auto got = readSome(fd, data.data(), data.size(), path);
    ::close(fd);
    if (!got) return got.error();
    if (got.value() != data.size())
        return makeError(ErrorCode::IoError, path + ": read " + std::to_string(got.value()) + " of " +
                                                 std::to_string(size) + " bytes (the file shrank while read)");
    return data;
}

Status probeModelFile(const std::string& path, std::uint64_t maxBytes) {
    struct stat st {};
    Error error;
    const int fd = openRegularFile(path, st, error);
    if (fd < 0) return error;
    const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
    auto refuse = [&](ErrorCode code, const std::string& why) {
        ::close(fd);
        return makeError(code, path + ": " + why);
    };
    if (size == 0) return refuse(ErrorCode::ParseError, "an empty file");
    if (size > maxBytes)
        return refuse(ErrorCode::OutOfRange, std::to_string(size) + " bytes is over the largest model file (" +
                                                 std::to_string(maxBytes) +
                                                 " bytes; the server's maxModelMiB setting)");
    char head[kModelProbeBytes];
    auto got = readSome(fd, head, std::min<std::uint64_t>(size, sizeof head), path);
    ::close(fd);
    if (!got) return got.error();
    const std::string_view h(head, got.value());
    if (h.empty())
        return makeError(ErrorCode::IoError, path + ": read nothing from a file of " + std::to_string(size) + " bytes");
    if (h.find_first_not_of('\0') == std::string_view::npos)
        return makeError(ErrorCode::ParseError, path + ": its first " + std::to_string(h.size()) +
                                                    " bytes are all zero (a sparse, truncated or preallocated "
                                                    "file?), not a model");
    const std::string ext = lowerExtension(path);
    if (ext == ".glb" || ext == ".gltf") {
        std::size_t i = h.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // a UTF-8 byte order mark
        while (i < h.size() && (h[i] == ' ' || h[i] == '\t' || h[i] == '\r' || h[i] == '\n')) ++i;
        if (h.compare(0, 4, "glTF") != 0 && (i == h.size() || h[i] != '{'))
            return makeError(ErrorCode::ParseError,
                             path + ": not glTF (its first bytes are neither the GLB magic 'glTF' nor a JSON object)");
    } else if (ext == ".dxf" && h.compare(0, 18, "AutoCAD Binary DXF") == 0) {
        return makeError(ErrorCode::Unsupported,
                         path + ": a binary DXF, which geoslice does not read: save it as ASCII DXF");
    } else if (ext == ".ply" && h.compare(0, 3, "ply") != 0) {
        return makeError(ErrorCode::ParseError, path + ": not PLY (its first line is not 'ply')");
    } else if (ext == ".str" || ext == ".dtm") {
        if (h.find('\0') != std::string_view::npos)
            return makeError(ErrorCode::Unsupported, path + ": a binary Surpac file (a NUL byte at offset " +
                                                         std::to_string(h.find('\0')) +
                                                         "), which geoslice does not read: save it as text");
    } else if (ext == ".obj" || ext == ".dxf" || ext == ".ts" || ext == ".tsurf" || ext == ".ml" || ext == ".so" ||
               ext == ".gp" || ext == ".vo" || ext == ".sg" || ext == ".pl") {
        if (const std::size_t nul = h.find('\0'); nul != std::string_view::npos)
            return makeError(ErrorCode::ParseError, path + ": a NUL byte at offset " + std::to_string(nul) +
                                                        " of a text format (binary data, not a model)");
    }
    return {};
}

void finishLoadedModel(Model& model, bool classifyByClosure, bool validateModel) {
    if (classifyByClosure) {
        std::vector<Part> all;
        for (auto* list : {&model.bodies, &model.surfaces})
            for (auto& p : *list) all.push_back(std::move(p));
        model.bodies.clear();
        model.surfaces.clear();
        for (auto& p : all) {
            if (p.kindDeclared) {
                (p.kind == PartKind::Body ? model.bodies : model.surfaces).push_back(std::move(p));
                continue;
            }
            MeshReport r = analyseMesh(p.mesh, /*fixOrientation=*/false);
            bool closed = r.closed && r.consistentlyOriented && r.triangles >= 4 && r.nonFiniteVertices == 0;
            p.kind = closed ? PartKind::Body : PartKind::Surface;
            (closed ? model.bodies : model.surfaces).push_back(std::move(p));
        }
    }
    std::unordered_map<std::string, RecordId> byName;  // first record of each name
    for (const auto& [id, r] : model.attributes.records()) byName.emplace(r.name, id);
    for (auto* list : {&model.bodies, &model.surfaces}) {
        for (auto& p : *list) {
            if (p.record != kNoRecord && model.attributes.find(p.record)) continue;
            if (auto it = byName.find(p.name); it != byName.end()) {
                p.record = it->second;
                continue;
            }
            AttributeRecord rec;
            rec.name = p.name;
            rec.kind = p.kind == PartKind::Body ? "body" : "surface";
            if (p.record != kNoRecord) {
                rec.id = p.record;
                model.attributes.put(std::move(rec));
            } else {
                p.record = model.attributes.add(std::move(rec));
            }
            byName.emplace(p.name, p.record);
        }
    }
    applyDefaultColours(model);
    model.recentre();
    if (validateModel) validate(model);
}

Result<Model> loadModel(const std::string& path, const LoadOptions& options) {
    auto bytes = readFile(path);
    if (!bytes) return bytes.error();
    const std::string& data = bytes.value();
    const std::string ext = lowerExtension(path);
    std::string baseDir = std::filesystem::path(path).parent_path().string();
    if (baseDir.empty()) baseDir = ".";  // a bare file name: its folder is the working directory

    Result<Model> model = makeError(ErrorCode::Unsupported, path + ": unknown model format");
    auto starts = [&](std::string_view magic) { return data.compare(0, magic.size(), magic) == 0; };
    if (ext == ".glb" || ext == ".gltf" || starts("glTF")) {
        model = parseGltf(reinterpret_cast<const std::uint8_t*>(data.data()), data.size(), path, baseDir);
    } else if (ext == ".ts" || ext == ".tsurf" || ext == ".ml" || ext == ".so" || ext == ".vo" || ext == ".sg" ||
               ext == ".pl" || ext == ".gp" || starts("GOCAD")) {
        model = parseGocad(data, path, baseDir);
    } else if (ext == ".vtu" || std::string_view(data).substr(0, 512).find("<VTKFile") != std::string_view::npos) {
        model = parseVtu(data, path, options.vtu);
    } else if (ext == ".obj") {
        model = parseObj(data, path, baseDir);
    } else if (ext == ".xml" || ext == ".geo3dml" || ext == ".gml") {
        model = parseGeo3dml(data, path, baseDir);
    } else if (ext == ".ply" || starts("ply\n") || starts("ply\r\n")) {
        model = parsePly(data, path);
    } else if (ext == ".dxf" || starts("AutoCAD Binary DXF") || looksLikeDxf(data)) {
        model = parseDxf(data, path);
    } else if (ext == ".str") {
        model = parseSurpacString(data, path);
    } else if (ext == ".dtm") {
        auto strPath = surpacStringFileFor(path, data);
        if (!strPath) return strPath.error();
        auto str = readFile(strPath.value());
        if (!str) return str.error();
        model = parseSurpacDtm(data, path, str.value(), strPath.value());
    } else if (ext == ".stl" || isBinaryStl(data) || looksLikeAsciiStl(data)) {
        model = parseStl(data, path);
    } else {
        return makeError(ErrorCode::Unsupported,
                         path +
                             ": unknown model format (expected .glb, .gltf, .obj, .vtu, .stl, .ply, .dxf, GOCAD .ts "
                             ".ml .so .vo .sg .pl .gp, Geo3DML .xml, or Surpac .str .dtm)");
    }
    if (!model) return model;

    std::filesystem::path p(path);
    for (const char* suffix : {".attributes.json", ".attributes.csv"}) {
        std::filesystem::path side = p.parent_path() / (p.stem().string() + suffix);
        std::error_code ec;
        if (!std::filesystem::exists(side, ec)) continue;
        auto table = AttributeTable::load(side.string());
        if (!table) return table.error();
        if (model->source.empty()) model->source = path;
        mergeSidecar(model.value(), table.value(), side.string());
        if (!table->declaredCrs().empty())
            if (auto s = declareModelCrs(*model, table->declaredCrs(), CrsDeclaration::Sidecar, side.string()); !s)
                return s.error();
        break;
    }
    if (auto s = applyCrsDeclarations(*model, p, options.crs); !s) return s.error();
    if (model->source.empty()) model->source = path;
    if (model->name.empty()) model->name = p.stem().string();
    if (auto s = attachBlockModel(*model, path, options.blocks); !s) return s.error();
    return model;
}

}  // namespace geoslice
