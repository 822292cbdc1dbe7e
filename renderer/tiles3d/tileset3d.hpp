// A model as an OGC 3D Tiles 1.1 tileset (docs.ogc.org/cs/22-025r4) for CesiumJS and other
// 3D Tiles clients: tileset.json plus one glTF 2.0 binary per tile.
//
// Placement. Every vertex goes through the model's CRS to WGS 84 geodetic coordinates (the
// caller's `toGeodetic`: PROJ's operation chosen for the model, api/catalog.hpp
// CatalogModel::lonLat), then to Earth-centred Earth-fixed (GeographicLib::Geocentric, WGS 84)
// and into the east-north-up frame at the model's centre, in double; tiles store those ENU
// positions as float32 (sub-millimetre within 10 km of the centre) and the root tile's
// `transform` is that ENU frame in ECEF. Each vertex is placed exactly where PROJ puts it
// (grid convergence, scale factor and the Earth's curvature included); only straight
// triangle edges between vertices remain straight. Model z is taken as the height above the
// ellipsoid, as PROJ does for a 2D CRS with a z (no geoid is applied: state that beside any
// figure that mixes with real heights).
//
// Levels of detail: the cluster hierarchy of renderer/lod/cluster_build.hpp, built over the
// ENU positions with about `trianglesPerTile` triangles per cell: per part and cell a cluster
// with up to lodLevels - 1 simplified copies (border locked), and groups of 2, 4 and 8 cells a
// side merged and simplified again (outer border locked). Tiles form an octree over the cell
// grid: a leaf is one cell at full detail; a tile at height h (a block of 2^h cells a side)
// draws, per cluster, the coarsest copy whose scope (its cell, or its group's block) lies in
// the tile's block and whose error is at most kErrorPerSize x the block's diagonal; all
// borders are locked, so tiles of different levels meet without cracks (refine REPLACE).
// geometricError is the largest error of what a tile draws (metres, monotone up the tree).
//
// Content: per tile one glTF node and primitive per part (flat normals, positions in glTF's
// y-up axes as 3D Tiles 1.1 expects), a material per record in the record's colour
// (pbrMetallicRoughness, metallic 0, double-sided: surfaces are open), EXT_mesh_features with
// a per-vertex feature id (_FEATURE_ID_0, the property-table row of the part's record) and
// EXT_structural_metadata with every attribute and the colour (bake/feature_table.hpp).
//
// Threads: build() on any thread; a built Tileset3d is immutable and may be read from any
// number of threads.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

struct Tiles3dOptions {
    std::size_t trianglesPerTile = 16384;  // about, per grid cell (all parts)
    std::size_t maxTiles = 4096;           // leaf cells at most
    int lodLevels = 5;                     // per cluster, full detail included
};

// A tile at height h draws copies whose error is at most this times its block's diagonal: at
// Cesium's default maximumScreenSpaceError (16 px) a tile filling a 1,000 px high view is
// refined once its error exceeds about 1/60 of its size.
constexpr double kErrorPerSize = 1.0 / 64.0;

// World (model CRS, metres) -> WGS 84 longitude, latitude (degrees) and ellipsoidal height (m).
using ToGeodetic = std::function<Result<glm::dvec3>(const glm::dvec3& world)>;

class Tileset3d {
public:
    // Errors: a model without triangles (InvalidArgument), a vertex `toGeodetic` refuses or
    // returns non-finite (the error names the vertex), DeadlineExceeded when *cancel turns true.
    static Result<std::shared_ptr<const Tileset3d>> build(const Model& model, const ToGeodetic& toGeodetic,
                                                          const Tiles3dOptions& options = {},
                                                          const std::atomic<bool>* cancel = nullptr);

    // tileset.json: asset 1.1, the root transform, one tile per octree node; content URIs are
    // `<contentPrefix><n>.glb<contentQuery>` relative to the tileset (n = 0 .. tileCount() - 1).
    nlohmann::ordered_json tilesetJson(const std::string& contentPrefix, const std::string& generator,
                                       const std::string& contentQuery = "") const;
    std::size_t tileCount() const { return tiles_.size(); }
    // The GLB of tile n (n < tileCount(), else OutOfRange).
    Result<std::vector<std::uint8_t>> tileGlb(std::size_t n) const;

    // The root transform (ENU at the centre -> ECEF), column-major like tileset.json.
    const glm::dmat4& enuToEcef() const { return enuToEcef_; }
    std::size_t triangleCount() const { return triangles_; }
    double buildMs() const { return buildMs_; }

    struct Piece {  // triangles of one part: indices into that part's vertices
        std::uint32_t part = 0;
        const std::uint32_t* indices = nullptr;
        std::size_t count = 0;  // indices
    };
    struct Tile {
        int height = 0;
        glm::dvec3 boxMin{0.0}, boxMax{0.0};  // ENU bounds of its content and its children's
        double geometricError = 0.0;
        std::vector<Piece> pieces;
        std::vector<std::uint32_t> children;
    };
    const std::vector<Tile>& tiles() const { return tiles_; }
    // Piece::part: the model's parts with triangles, bodies first, in model order.
    std::size_t partCount() const;
    PartKind partKind(std::uint32_t part) const;

private:
    struct PartData;
    Tileset3d();
    std::string name_;
    AttributeTable attributes_;
    std::vector<PartData> parts_;
    std::vector<Tile> tiles_;  // tiles_[0] is the root
    std::vector<RecordId> rows_;
    glm::dmat4 enuToEcef_{1.0};
    glm::dvec3 centreLonLatH_{0.0};
    std::string crsId_;
    std::size_t triangles_ = 0;
    double buildMs_ = 0.0;

public:
    ~Tileset3d();
    Tileset3d(const Tileset3d&) = delete;
    Tileset3d& operator=(const Tileset3d&) = delete;
};

}  // namespace geoslice
