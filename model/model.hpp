// The geological model: closed bodies (stratum volumes, orebodies, intrusions) and open
// surfaces (faults, horizons, terrain), each pointing at an attribute record.
//
// Frames: `world` is double, in the model's CRS: x = easting, y = northing, z = elevation
// up, metres. `local` is float32 world minus Model::origin; every GPU- or BVH-facing
// buffer is local (a float at easting 35,500,000 m has 4 m steps; near the origin, mm).
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "model/attributes.hpp"
#include "model/crs.hpp"

namespace geoslice {

struct Aabb {
    glm::dvec3 min{std::numeric_limits<double>::infinity()};
    glm::dvec3 max{-std::numeric_limits<double>::infinity()};
    void extend(const glm::dvec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Aabb& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool valid() const { return min.x <= max.x && min.y <= max.y && min.z <= max.z; }
    glm::dvec3 centre() const { return (min + max) * 0.5; }
    glm::dvec3 size() const { return max - min; }
    bool contains(const Aabb& b) const {
        return glm::all(glm::lessThanEqual(min, b.min)) && glm::all(glm::greaterThanEqual(max, b.max));
    }
};

// A triangle mesh in world coordinates. Triangles are counter-clockwise seen from
// outside (outward normals) once validation has run on a closed body.
struct Mesh {
    std::vector<glm::dvec3> positions;   // world, metres
    std::vector<std::uint32_t> indices;  // 3 per triangle
    // Optional per-vertex properties (e.g. TSurf PVRTX columns): values[v * names.size() + k].
    std::vector<std::string> propertyNames;
    std::vector<float> propertyValues;

    std::size_t triangleCount() const { return indices.size() / 3; }
    std::size_t vertexCount() const { return positions.size(); }
    Aabb bounds() const;
};

// Validation findings for one part (see model/validate.hpp).
struct MeshReport {
    std::size_t triangles = 0, vertices = 0;
    std::size_t boundaryEdges = 0;     // edges used by one triangle
    std::size_t nonManifoldEdges = 0;  // edges used by more than two triangles
    std::size_t inconsistentEdges = 0; // manifold edges whose two triangles disagree in orientation
    std::size_t degenerateTriangles = 0;  // repeated index or zero area
    std::size_t duplicateTriangles = 0;   // same three vertices as an earlier triangle
    std::size_t nonFiniteVertices = 0;    // NaN or Inf coordinates
    std::size_t components = 0;           // edge-connected shells
    bool closed = false;                  // no boundary and no non-manifold edges
    bool consistentlyOriented = false;
    double signedVolume = 0.0;  // m^3, after any flip; closed bodies only
    bool flipped = false;       // orientation was inward and has been flipped
    int nestingDepth = 0;       // number of other closed bodies that contain this one
    int parent = -1;            // index into Model::bodies of the innermost container, or -1
};

// One finding of validate() (model/validate.hpp).
struct ValidationIssue {
    enum class Severity { Note, Warning, Error };
    Severity severity = Severity::Warning;
    std::string part;  // part name, empty for model-wide issues
    std::string message;
};

struct ValidationReport {
    std::vector<ValidationIssue> issues;
    bool hasErrors() const;
};

enum class PartKind { Body, Surface };

struct Part {
    std::string name;
    PartKind kind = PartKind::Body;
    RecordId record = kNoRecord;
    Mesh mesh;
    MeshReport report;  // filled by validate()
};

struct Model {
    std::string name;
    std::string source;          // file it came from, for messages
    std::vector<Part> bodies;    // closed shells
    std::vector<Part> surfaces;  // open sheets
    AttributeTable attributes;
    Crs crs;                     // Crs::local() when the model has no CRS
    glm::dvec3 origin{0.0};      // world point that local coordinates are relative to
    ValidationReport validation; // from the last validate()
    // Loader notes about the whole model (provenance, declared CRS, axis order, warnings),
    // key -> text; kept out of the attribute records, which describe geology.
    std::map<std::string, std::string> notes;

    Aabb bounds() const;
    std::size_t triangleCount() const;
    // Sets origin to the bounds centre rounded to whole metres (stable, readable).
    void recentre();
    // Float32 copy of a mesh's positions relative to origin (the local frame).
    std::vector<glm::vec3> localPositions(const Mesh& mesh) const;
};

}  // namespace geoslice
