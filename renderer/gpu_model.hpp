// A model uploaded to one GL context, in its local frame: float32 positions = world -
// Model::origin, computed in double on the CPU (Model::localPositions), so nothing reaches
// the GPU at a Gauss-Kruger magnitude. One vertex buffer and one index buffer for all parts;
// each part is a range drawn with glDrawElementsBaseVertex.
//
// Spatial clusters: the model's bounds are cut into a grid of cells (about
// UploadOptions::trianglesPerCell triangles each); every part's triangles are ordered by the
// cell of their centroid, so a part is one index range at full detail and each of its
// clusters (part x cell) a sub-range. The slicing pass skips clusters that are entirely on
// the removed side of the planes or outside the view (exact: they would give no fragment).
// Level of detail (UploadOptions::lod): each cluster also gets up to kMaxLodLevels - 1
// simplified copies (meshoptimizer, quadric edge collapse, Garland & Heckbert 1997) with the
// cluster's border vertices locked, so clusters at different levels still meet without
// cracks; each copy records its geometric error in metres (meshopt_simplify's error times
// meshopt_simplifyScale). A simplified copy lies in the convex hull of its cluster's
// vertices, hence inside the cell bounds (cellBounds()).
// Clusters, levels and groups are built on the CPU by renderer/lod/cluster_build.hpp.
//
// Baked record ids (paper section 2.2, issue 4 item 8): upload(context, model, baked) draws the
// bake's mesh instead of the model's (the same triangles in the same order, vertices split
// along chart borders) with a per-vertex UV (attribute 1, "page + u, v", bake/bake.hpp) and
// uploads the index texture T_ID as a GL_TEXTURE_2D_ARRAY (GL_R32UI, one layer per page,
// nearest, no mipmaps; the shader uses texelFetch, so no filtering ever mixes two ids) plus a
// record -> colour table (GL_TEXTURE_2D RGBA8, kColourTableWidth records per row, record id r
// at texel (r % width, r / width)), so that field records (grade classes) get their own colour.
// Limits: pages <= GL_MAX_ARRAY_TEXTURE_LAYERS, width and height <= GL_MAX_TEXTURE_SIZE, the
// largest record id < kColourTableWidth * GL_MAX_TEXTURE_SIZE; beyond them upload() returns
// OutOfRange naming the limit.
// Threads: create, use and destroy on the owning GlContext's thread. GL state: upload()
// creates buffers, textures and a vertex array with DSA and leaves no binding changed.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/gl_objects.hpp"

namespace geoslice {

namespace bake {
struct BakedModel;
struct Package;
}  // namespace bake

// How GpuModel::upload builds clusters and levels of detail.
struct GpuUploadOptions {
    enum class Lod { Off, On, Auto };  // Auto: on for software rasterisers (llvmpipe)
    Lod lod = Lod::Auto;
    // Grid resolution. Measured on L4 (10M triangles) at 1024x1024 on llvmpipe, perspective,
    // 1 px: 1024 per cell (16384 cells at most) drew 2.42M triangles with LOD (166-178 ms
    // draw + finish); 256 per cell (65536 cells) with groups (GpuModel::DrawPart::groups)
    // 1.73M (143 ms): smaller cells keep less at full detail around a cut, groups merge
    // their borders away from it.
    std::size_t trianglesPerCell = 256;
    std::size_t maxCells = 65536;  // 1..GpuModel::kMaxCells
    int lodLevels = 5;             // levels including full detail, 1..GpuModel::kMaxLodLevels
};

class GpuModel {
public:
    static constexpr int kMaxLodLevels = 8;
    static constexpr std::size_t kMaxCells = 1 << 16;
    using UploadOptions = GpuUploadOptions;
    struct DrawPart {
        GLint baseVertex = 0;
        GLsizei indexCount = 0;
        std::size_t firstIndex = 0;
        bool body = true;  // closed body (caps) or open surface
        RecordId record = kNoRecord;
        glm::vec4 colour{0.6f};                // attribute record colour, 0..1
        RecordId containerRecord = kNoRecord;  // innermost containing body (validation's parent)
        glm::vec4 containerColour{0.6f};
        // Bodies: the index of this body and of its container in Model::bodies (-1: none), so
        // that a view hiding bodies can find the nearest container it still shows.
        int bodyIndex = -1, containerBody = -1;
        // Open surfaces: their triangles in surfaceTriangles(), [surfaceFirst, + surfaceCount)
        // vertices.
        std::size_t surfaceFirst = 0, surfaceCount = 0;
        // Level l of a cluster: indices [first[l], first[l] + count[l]) of the index buffer
        // (part-local vertex numbers, baseVertex applies); level 0 is full detail and lies
        // inside [firstIndex, firstIndex + indexCount). error[l] in metres, error[0] = 0.
        struct Cluster {
            std::uint32_t cell = 0;
            int levels = 1;
            std::size_t first[kMaxLodLevels] = {};
            GLsizei count[kMaxLodLevels] = {};
            float error[kMaxLodLevels] = {};
        };
        std::vector<Cluster> clusters;  // in index-buffer order
        // Groups (LOD only; Nanite-style): the part's clusters in a block of 2, 4 or 8 cells
        // a side, their coarsest levels (or the coarsest group of the block size below)
        // merged and simplified again with the block's outer border locked, so the borders
        // between its cells collapse while it still meets its neighbours without cracks.
        // Up to three groups per block, each about half the one before, stored finest block
        // size first and finer before coarser. Drawn instead of all its members when every
        // member may have `error` (metres: the largest merged error plus the new one);
        // indices [first, first + count) like a cluster level.
        struct Group {
            std::size_t first = 0;
            GLsizei count = 0;
            float error = 0.0f;
            std::vector<std::uint32_t> members;  // indices into clusters
        };
        std::vector<Group> groups;
    };

    // Uploads every body and surface. Nesting comes from Part::report.parent, so the model
    // should have been validated (loaders do; generateSynthetic callers run validate()).
    static Result<std::unique_ptr<GpuModel>> upload(GlContext& context, const Model& model,
                                                    const UploadOptions& options = {});
    // The bake of `model` (bake::bakeModel(model), or a package loaded back into the same
    // model) with its id texture. baked.parts must match the model's non-empty parts one to
    // one (source index, kind, record, triangle count); errors: InvalidArgument naming the
    // first mismatch or a malformed bake (texel count, UV count, vertex index), OutOfRange
    // for the GL limits above or GL_OUT_OF_MEMORY. Colours: model.attributes, then
    // baked.fieldRecords (records not found: grey).
    static Result<std::unique_ptr<GpuModel>> upload(GlContext& context, const Model& model,
                                                    const bake::BakedModel& baked, const UploadOptions& options = {});
    // The same from a loaded package (bake/package.hpp): `model` is the package's mesh.glb
    // loaded as a model (what api/catalog.cpp serves) or the model it was baked from; package
    // part i is the model's i-th part with triangles (bodies, then surfaces). Positions are
    // taken from the package (glTF axes, its origin) into the model's local frame in double.
    // Colours: model.attributes, then package.attributes (field records). The package must
    // outlive the call only.
    static Result<std::unique_ptr<GpuModel>> upload(GlContext& context, const Model& model,
                                                    const bake::Package& package, const UploadOptions& options = {});
    static constexpr int kColourTableWidth = 1024;
    ~GpuModel();
    GpuModel(const GpuModel&) = delete;
    GpuModel& operator=(const GpuModel&) = delete;

    GLuint vertexArray() const { return vao_.id(); }
    const std::vector<DrawPart>& parts() const { return parts_; }
    const glm::dvec3& origin() const { return origin_; }
    const Aabb& worldBounds() const { return bounds_; }
    std::size_t triangleCount() const { return triangles_; }
    // Open surfaces (faults, terrain sheets) kept on the CPU for trace lines: local frame,
    // float32, three vertices per triangle.
    const std::vector<glm::vec3>& surfaceTriangles() const { return surfaceTriangles_; }
    // Bounds of the triangles of each cell, local frame (empty cells are invalid boxes).
    const std::vector<Aabb>& cellBounds() const { return cellBounds_; }
    bool hasLod() const { return hasLod_; }
    // Baked ids: 0 when uploaded without a bake.
    GLuint idTexture() const { return idTexture_.id(); }
    GLuint colourTable() const { return colourTable_.id(); }
    bool hasIdTexture() const { return bool(idTexture_); }
    // GPU bytes of the bake: the id texture (width * height * pages * 4), the UV attribute
    // (8 per vertex) and the colour table (4 per entry).
    std::size_t idTextureBytes() const { return idTextureBytes_; }
    std::size_t uvBytes() const { return uvBytes_; }
    std::size_t colourTableBytes() const { return colourTableBytes_; }
    double lodBuildMs() const { return lodBuildMs_; }

private:
    explicit GpuModel(GlContext& context) : context_(context) {}
    struct BakeSource;  // a BakedModel or a Package, viewed alike (gpu_model.cpp)
    static Result<std::unique_ptr<GpuModel>> build(GlContext& context, const Model& model, const BakeSource* baked,
                                                   const UploadOptions& options);
    Status uploadIdTexture(const Model& model, const BakeSource& baked);
    GlContext& context_;
    GlBuffer vertexBuffer_, indexBuffer_, uvBuffer_;
    GlTexture idTexture_, colourTable_;
    GlVertexArray vao_;  // last member: deleted first
    std::size_t idTextureBytes_ = 0, uvBytes_ = 0, colourTableBytes_ = 0;
    std::vector<DrawPart> parts_;
    glm::dvec3 origin_{0.0};
    Aabb bounds_;
    std::size_t triangles_ = 0;
    std::vector<glm::vec3> surfaceTriangles_;
    std::vector<Aabb> cellBounds_;
    bool hasLod_ = false;
    double lodBuildMs_ = 0.0;
};

}  // namespace geoslice
