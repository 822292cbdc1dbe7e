// Geo3DML reading: the declared CRS (Metadata or a geometry's srsName) -> Model::crs, and
// for Gauss-Kruger CRSs the check that coordinates fit it, swapping a northing-first file.
// Part of the reader in model/io/geo3dml/geo3dml_reader.hpp.
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <utility>

#include "model/io/geo3dml/geo3dml_reader.hpp"

namespace geoslice::geo3dml {
namespace {

// Gauss-Kruger eastings lie within this distance of the false easting (metres): a 6-degree
// zone at 18 N (southern China) reaches about 318 km from its central meridian.
constexpr double kMaxOffsetFromFalseEastingM = 500000.0;
// Projected northings of CGCS2000 Gauss-Kruger coordinates (northern hemisphere), metres.
constexpr double kMaxNorthingM = 10002000.0;

// "EPSG:4526", "urn:ogc:def:crs:EPSG::4526", "urn:ogc:def:crs:EPSG:6.6:4526",
// "http://www.opengis.net/def/crs/EPSG/0/4526" -> "EPSG:4526"; anything else unchanged.
std::string normaliseCrsText(std::string_view text) {
    text = trimSpace(text);
    const std::string lower = text::lower(text);
    std::size_t codeStart = std::string::npos;
    if (lower.starts_with("urn:ogc:def:crs:epsg:"))
        codeStart = lower.rfind(':') + 1;
    else if (lower.starts_with("http") && contains(lower, "/def/crs/epsg/"))
        codeStart = lower.rfind('/') + 1;
    else if (lower.starts_with("epsg:"))
        codeStart = 5;
    if (codeStart != std::string::npos && isDigits(text.substr(codeStart)))
        return "EPSG:" + std::string(text.substr(codeStart));
    return std::string(text);
}

}  // namespace

// Declared CRS -> model.crs. A CRS geoslice does not support leaves the model local, with the
// declared text in the model's notes ("declared_crs", "declared_crs_note"), so it is
// not lost. For a projected CRS the coordinates are checked against it (fixAxisOrder inside).
void Reader::applyCrs(Model& model) const {
    const std::string declared = declaredCrs_.empty() ? srsName_ : declaredCrs_;
    if (trimSpace(declared).empty()) return;
    const auto note = [&](const char* key, const std::string& value) { model.notes.emplace(key, quoted(value, 400)); };
    const Result<Crs> crs = Crs::parse(normaliseCrsText(declared));
    if (!crs) {
        note("declared_crs", declared);
        note("declared_crs_note",
             "not a CRS geoslice supports (" + crs.error().message + "); the model is kept in local coordinates");
        return;
    }
    model.crs = crs.value();
    // The fit check below knows Gauss-Kruger false eastings only; PROJ CRSs are taken as declared.
    if (!model.crs.isGaussKruger()) return;

    // Gauss-Kruger: easting = false easting +- a few hundred km, northing 0..10,002 km. Chinese
    // surveying writes X = northing first; EPSG's axis order for these CRSs is northing first
    // too, while geoslice's world frame is x = easting. Swap when only the swapped order fits.
    Aabb box;
    for (const auto* parts : {&model.bodies, &model.surfaces})
        for (const Part& p : *parts)
            for (const glm::dvec3& q : p.mesh.positions) box.extend(q);
    if (!box.valid()) return;
    const double fe = model.crs.falseEastingM();
    const auto eastingFits = [&](double lo, double hi) {
        return lo >= fe - kMaxOffsetFromFalseEastingM && hi <= fe + kMaxOffsetFromFalseEastingM;
    };
    const auto northingFits = [&](double lo, double hi) { return lo >= 0.0 && hi <= kMaxNorthingM; };
    const bool asWritten = eastingFits(box.min.x, box.max.x) && northingFits(box.min.y, box.max.y);
    const bool swapped = eastingFits(box.min.y, box.max.y) && northingFits(box.min.x, box.max.x);
    if (asWritten) return;
    if (swapped) {
        for (auto* parts : {&model.bodies, &model.surfaces})
            for (Part& p : *parts) {
                for (glm::dvec3& q : p.mesh.positions) std::swap(q.x, q.y);
                // Swapping two axes mirrors the mesh; swapping two corners keeps outward normals.
                for (std::size_t t = 0; t + 2 < p.mesh.indices.size(); t += 3)
                    std::swap(p.mesh.indices[t + 1], p.mesh.indices[t + 2]);
            }
        note("axis_order", "coordinates were written northing first (X = north); swapped to x = east, y = north");
        return;
    }
    const auto metres = [](double v) {  // whole metres; any finite double, however large
        char buf[64];
        std::snprintf(buf, sizeof buf, std::fabs(v) < 1e15 ? "%.0f" : "%.6g", v);
        return std::string(buf);
    };
    const auto range = [&](double lo, double hi) { return metres(std::floor(lo)) + ".." + metres(std::ceil(hi)); };
    note("crs_warning", "coordinates (x " + range(box.min.x, box.max.x) + " m, y " + range(box.min.y, box.max.y) +
                            " m) do not fit " + model.crs.id() + " (eastings near " + metres(fe) +
                            " m): the declared CRS may not apply");
}

}  // namespace geoslice::geo3dml
