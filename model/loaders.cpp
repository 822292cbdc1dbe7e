#include "model/loaders.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unordered_map>

#include "model/validate.hpp"

namespace geoslice {
namespace {

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

// Re-points parts at sidecar records of the same name; sidecar records replace same ids.
void mergeSidecar(Model& model, const AttributeTable& side) {
    for (const auto& [id, rec] : side.records()) model.attributes.put(rec);
    for (auto* list : {&model.bodies, &model.surfaces})
        for (auto& part : *list)
            if (const AttributeRecord* r = side.findByName(part.name)) part.record = r->id;
}

}  // namespace

Result<std::string> readFile(const std::string& path, std::size_t maxBytes) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return makeError(ErrorCode::IoError, path + ": is a directory, not a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(ErrorCode::NotFound, path + ": cannot open (does it exist and is it readable?)");
    in.seekg(0, std::ios::end);
    std::streamoff size = in.tellg();
    if (size < 0) return makeError(ErrorCode::IoError, path + ": cannot determine the file size");
    if (static_cast<std::uint64_t>(size) > maxBytes)
        return makeError(ErrorCode::OutOfRange, path + ": " + std::to_string(size) + " bytes is over the limit of " +
                                                    std::to_string(maxBytes) + " bytes");
    in.seekg(0);
    std::string data(static_cast<std::size_t>(size), '\0');
    if (!in.read(data.data(), size)) return makeError(ErrorCode::IoError, path + ": read failed");
    return data;
}

void finishLoadedModel(Model& model, bool classifyByClosure) {
    if (classifyByClosure) {
        std::vector<Part> all;
        for (auto* list : {&model.bodies, &model.surfaces})
            for (auto& p : *list) all.push_back(std::move(p));
        model.bodies.clear();
        model.surfaces.clear();
        for (auto& p : all) {
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
    model.recentre();
    validate(model);
}

Result<Model> loadModel(const std::string& path) {
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
    } else if (ext == ".ts" || ext == ".tsurf" || starts("GOCAD")) {
        model = parseTsurf(data, path);
    } else if (ext == ".obj") {
        model = parseObj(data, path);
    } else if (ext == ".xml" || ext == ".geo3dml" || ext == ".gml") {
        model = parseGeo3dml(data, path);
    } else {
        return makeError(ErrorCode::Unsupported,
                         path + ": unknown model format (expected .glb, .gltf, .obj, .ts, or Geo3DML .xml)");
    }
    if (!model) return model;

    std::filesystem::path p(path);
    for (const char* suffix : {".attributes.json", ".attributes.csv"}) {
        std::filesystem::path side = p.parent_path() / (p.stem().string() + suffix);
        std::error_code ec;
        if (!std::filesystem::exists(side, ec)) continue;
        auto table = AttributeTable::load(side.string());
        if (!table) return table.error();
        mergeSidecar(model.value(), table.value());
        break;
    }
    if (model->source.empty()) model->source = path;
    if (model->name.empty()) model->name = p.stem().string();
    return model;
}

}  // namespace geoslice
