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
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "model/attributes.hpp"
#include "model/blocks/block_model.hpp"
#include "model/crs/crs.hpp"

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
    // Whether the two boxes share a point (bounds inclusive).
    bool meets(const Aabb& b) const {
        return glm::all(glm::lessThanEqual(min, b.max)) && glm::all(glm::greaterThanEqual(max, b.min));
    }
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

// Validation findings for one part (see model/mesh/validate.hpp).
struct MeshReport {
    std::size_t triangles = 0, vertices = 0;
    std::size_t boundaryEdges = 0;        // edges used by one triangle
    std::size_t nonManifoldEdges = 0;     // edges used by more than two triangles that could not be paired
    std::size_t splitEdges = 0;           // edges used by 4, 6... triangles, paired by angle (pinch-outs)
    std::size_t splitVertices = 0;        // welded vertices that are several vertices of the 2-manifold
    std::size_t inconsistentEdges = 0;    // manifold edges whose two triangles disagree in orientation
    std::size_t degenerateTriangles = 0;  // repeated index or zero area
    std::size_t duplicateTriangles = 0;   // same three vertices as an earlier triangle
    std::size_t nonFiniteVertices = 0;    // NaN or Inf coordinates
    std::size_t components = 0;           // shells: triangles connected across (paired) edges
    // No boundary and no unpaired non-manifold edges. For a body (validate()) this also
    // means its mesh indices are that 2-manifold as they stand: vertices are welded by
    // position and split per shell and per fan at pinch-outs.
    bool closed = false;
    bool consistentlyOriented = false;
    double signedVolume = 0.0;             // m^3, after any flip; closed bodies only
    bool flipped = false;                  // orientation was inward and has been flipped
    int nestingDepth = 0;                  // number of other closed bodies that contain this one
    int parent = -1;                       // index into Model::bodies of the innermost container, or -1
    std::vector<glm::dvec3> problemEdges;  // world midpoints of a few boundary / non-manifold edges
};

// One finding of validate() (model/mesh/validate.hpp).
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
    // The file or format says what the part is (a TSolid region, a .vtu formation, glTF
    // geoslice extras): finishLoadedModel() never reclassifies it by closure, so a declared
    // volume that cannot be closed is a validation error, not a surface.
    bool kindDeclared = false;
    RecordId record = kNoRecord;
    Mesh mesh;
    MeshReport report;  // filled by validate()
};

// A line object (GOCAD PLine: well paths, fault traces, contours): connected chains of
// points in world coordinates, kept and described; sections do not use them yet.
struct Polyline {
    std::string name;
    RecordId record = kNoRecord;
    std::vector<glm::dvec3> points;       // world, metres
    std::vector<std::uint32_t> segments;  // 2 per segment, indices into points
    // Optional per-point properties (PVRTX columns): values[p * names.size() + k].
    std::vector<std::string> propertyNames;
    std::vector<float> propertyValues;
};

// One property of a Grid: a value per grid sample (i fastest, then j, then k).
struct GridProperty {
    std::string name;
    std::string unit;                   // as written, may be empty
    std::optional<double> noDataValue;  // samples equal to it were stored as NaN
    std::vector<float> values;          // NaN = no data
};

// A structured grid (GOCAD Voxet: regular; SGrid: curvilinear), kept and described;
// sections do not use grids yet. Sample (i, j, k) of a regular grid is at
// origin + i * step[0] + j * step[1] + k * step[2] (world, metres; steps need not be
// orthogonal). A curvilinear grid gives every sample's position in `points` instead.
struct Grid {
    std::string name;
    std::string type;                                                          // "Voxet" or "SGrid"
    std::size_t dims[3] = {0, 0, 0};                                           // samples along u, v, w
    glm::dvec3 origin{0.0};                                                    // sample (0,0,0), world
    glm::dvec3 step[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};  // regular grids
    std::vector<glm::dvec3> points;  // curvilinear grids: dims[0]*dims[1]*dims[2] points
    bool cellCentred = false;        // properties per cell (dims-1 per axis) instead of per point
    std::vector<GridProperty> properties;

    std::size_t sampleCount() const { return dims[0] * dims[1] * dims[2]; }
    Aabb bounds() const;
};

struct Model {
    std::string name;
    std::string source;           // file it came from, for messages
    std::vector<Part> bodies;     // closed shells
    std::vector<Part> surfaces;   // open sheets
    std::vector<Grid> grids;      // structured grids (Voxet, SGrid): kept, not sectioned yet
    std::vector<Polyline> lines;  // well paths and lines (PLine): kept, not sectioned yet
    // The block model attached to the model (model/blocks/block_model.hpp), or null.
    std::shared_ptr<const BlockModel> blocks;
    AttributeTable attributes;
    Crs crs;                      // Crs::local() when the model has no CRS
    glm::dvec3 origin{0.0};       // world point that local coordinates are relative to
    ValidationReport validation;  // from the last validate()
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
