#include "renderer/gpu_model.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace geoslice {
namespace {

glm::vec4 recordColour(const Model& model, RecordId id) {
    Rgba8 c;
    if (const AttributeRecord* r = model.attributes.find(id)) c = r->colour;
    return glm::vec4(c.r, c.g, c.b, c.a) / 255.0f;
}

// A regular grid over the local bounds with cells about as wide as they are tall.
struct CellGrid {
    glm::dvec3 min{0.0}, cellSize{1.0};
    glm::ivec3 dims{1};
    std::size_t count() const { return std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z); }
    std::uint32_t cellOf(const glm::dvec3& p) const {
        glm::ivec3 c;
        for (int k = 0; k < 3; ++k) c[k] = std::clamp(int(std::floor((p[k] - min[k]) / cellSize[k])), 0, dims[k] - 1);
        return std::uint32_t((c.z * dims.y + c.y) * dims.x + c.x);
    }
};

CellGrid makeGrid(const Aabb& local, std::size_t triangles, std::size_t perCell, std::size_t maxCells) {
    CellGrid g;
    if (!local.valid()) return g;
    const double target = double(std::clamp<std::size_t>(triangles / std::max<std::size_t>(perCell, 1), 1,
                                                         std::clamp<std::size_t>(maxCells, 1, GpuModel::kMaxCells)));
    const glm::dvec3 extent = glm::max(local.size(), glm::dvec3(1e-3));
    const double k = std::cbrt(target / (extent.x * extent.y * extent.z));
    for (int a = 0; a < 3; ++a) g.dims[a] = std::max(1, int(std::floor(extent[a] * k)));
    g.min = local.min;
    g.cellSize = extent / glm::dvec3(g.dims);
    return g;
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Result<std::unique_ptr<GpuModel>> GpuModel::upload(GlContext& context, const Model& model,
                                                   const UploadOptions& options) {
    if (options.lodLevels < 1 || options.lodLevels > kMaxLodLevels)
        return makeError(ErrorCode::InvalidArgument, "LOD levels " + std::to_string(options.lodLevels) +
                                                         " is outside 1.." + std::to_string(kMaxLodLevels));
    const GlFunctions& gl = context.gl();
    std::unique_ptr<GpuModel> g(new GpuModel(context));
    g->origin_ = model.origin;
    g->bounds_ = model.bounds();
    const bool lod = options.lodLevels > 1 && (options.lod == UploadOptions::Lod::On ||
                                               (options.lod == UploadOptions::Lod::Auto && context.info().software));
    g->hasLod_ = lod;
    std::size_t totalTriangles = 0;
    for (const Part& p : model.bodies) totalTriangles += p.mesh.triangleCount();
    for (const Part& p : model.surfaces) totalTriangles += p.mesh.triangleCount();
    Aabb localBounds;
    if (g->bounds_.valid()) {
        localBounds.extend(g->bounds_.min - model.origin);
        localBounds.extend(g->bounds_.max - model.origin);
    }
    const CellGrid grid = makeGrid(localBounds, totalTriangles, options.trianglesPerCell, options.maxCells);
    g->cellBounds_.assign(grid.count(), Aabb{});

    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    // Simplified levels go after every part's full-detail indices; offsets relative to
    // lodIndices until the fix-up below.
    std::vector<std::uint32_t> lodIndices;
    double lodMs = 0.0;
    // Scratch for clusters: part vertex -> compact vertex.
    std::vector<std::uint32_t> remap;
    auto add = [&](const Part& part, bool body) -> Status {
        const Mesh& mesh = part.mesh;
        if (mesh.indices.empty()) return {};
        if (positions.size() > std::size_t(std::numeric_limits<GLint>::max()) ||
            indices.size() + mesh.indices.size() > std::size_t(std::numeric_limits<GLsizei>::max()))
            return makeError(ErrorCode::OutOfRange, "model " + model.name + " is too large for one GL buffer");
        std::vector<glm::vec3> local = model.localPositions(mesh);
        for (std::uint32_t i : mesh.indices)
            if (i >= local.size())
                return makeError(ErrorCode::InvalidArgument,
                                 "model " + model.name + ": part " + part.name + " has vertex index " +
                                     std::to_string(i) + " past its " + std::to_string(local.size()) + " vertices");
        DrawPart d;
        d.baseVertex = GLint(positions.size());
        d.firstIndex = indices.size();
        d.indexCount = GLsizei(mesh.indices.size());
        d.body = body;
        d.record = part.record;
        d.colour = recordColour(model, part.record);
        if (body && part.report.parent >= 0 && std::size_t(part.report.parent) < model.bodies.size()) {
            d.containerRecord = model.bodies[std::size_t(part.report.parent)].record;
            d.containerColour = recordColour(model, d.containerRecord);
        }
        if (!body)
            for (std::uint32_t i : mesh.indices) g->surfaceTriangles_.push_back(local[i]);

        // Triangles by the cell of their centroid (counting sort keeps the input order
        // within a cell, so the output is deterministic).
        const std::size_t triCount = mesh.indices.size() / 3;
        std::vector<std::uint32_t> cellOf(triCount);
        std::vector<std::uint32_t> start(grid.count() + 1, 0);
        for (std::size_t t = 0; t < triCount; ++t) {
            const glm::dvec3 c = (glm::dvec3(local[mesh.indices[3 * t]]) + glm::dvec3(local[mesh.indices[3 * t + 1]]) +
                                  glm::dvec3(local[mesh.indices[3 * t + 2]])) /
                                 3.0;
            cellOf[t] = grid.cellOf(c);
            ++start[cellOf[t] + 1];
        }
        for (std::size_t c = 0; c < grid.count(); ++c) start[c + 1] += start[c];
        std::vector<std::uint32_t> sorted(mesh.indices.size());
        {
            std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
            for (std::size_t t = 0; t < triCount; ++t) {
                const std::uint32_t at = fill[cellOf[t]]++;
                for (int k = 0; k < 3; ++k)
                    sorted[3 * std::size_t(at) + std::size_t(k)] = mesh.indices[3 * t + std::size_t(k)];
            }
        }
        remap.assign(local.size(), std::numeric_limits<std::uint32_t>::max());
        std::vector<glm::vec3> compactPos;
        std::vector<std::uint32_t> compactIdx, back, prev, out;
        for (std::uint32_t cell = 0; cell < grid.count(); ++cell) {
            if (start[cell] == start[cell + 1]) continue;
            DrawPart::Cluster cl;
            cl.cell = cell;
            cl.first[0] = d.firstIndex + 3 * std::size_t(start[cell]);
            cl.count[0] = GLsizei(3 * std::size_t(start[cell + 1] - start[cell]));
            const std::uint32_t* tri = sorted.data() + 3 * std::size_t(start[cell]);
            for (GLsizei i = 0; i < cl.count[0]; ++i) g->cellBounds_[cell].extend(glm::dvec3(local[tri[i]]));
            // Tiny clusters are not worth a draw call per level.
            if (lod && cl.count[0] >= 3 * 64) {
                const auto t0 = std::chrono::steady_clock::now();
                compactPos.clear();
                compactIdx.clear();
                back.clear();
                for (GLsizei i = 0; i < cl.count[0]; ++i) {
                    std::uint32_t& r = remap[tri[i]];
                    if (r == std::numeric_limits<std::uint32_t>::max()) {
                        r = std::uint32_t(compactPos.size());
                        compactPos.push_back(local[tri[i]]);
                        back.push_back(tri[i]);
                    }
                    compactIdx.push_back(r);
                }
                for (std::uint32_t v : back) remap[v] = std::numeric_limits<std::uint32_t>::max();
                const float scale = meshopt_simplifyScale(&compactPos[0].x, compactPos.size(), sizeof(glm::vec3));
                prev = compactIdx;
                float cumulative = 0.0f;
                while (cl.levels < options.lodLevels) {
                    const std::size_t target = std::max<std::size_t>(prev.size() / 4 / 3 * 3, 3);
                    out.resize(prev.size());
                    float err = 0.0f;
                    const std::size_t n =
                        meshopt_simplify(out.data(), prev.data(), prev.size(), &compactPos[0].x, compactPos.size(),
                                         sizeof(glm::vec3), target, 1.0f, meshopt_SimplifyLockBorder, &err);
                    if (n == 0 || n * 10 > prev.size() * 8) break;  // locked borders: no real progress
                    cumulative += err * scale;
                    const int l = cl.levels++;
                    cl.first[l] = lodIndices.size();
                    cl.count[l] = GLsizei(n);
                    cl.error[l] = cumulative;
                    for (std::size_t i = 0; i < n; ++i) lodIndices.push_back(back[out[i]]);
                    prev.assign(out.begin(), out.begin() + std::ptrdiff_t(n));
                }
                lodMs += msSince(t0);
            }
            d.clusters.push_back(cl);
        }
        positions.insert(positions.end(), local.begin(), local.end());
        indices.insert(indices.end(), sorted.begin(), sorted.end());
        g->parts_.push_back(std::move(d));
        g->triangles_ += mesh.triangleCount();
        return {};
    };
    for (const Part& p : model.bodies)
        if (auto s = add(p, true); !s) return s.error();
    for (const Part& p : model.surfaces)
        if (auto s = add(p, false); !s) return s.error();
    if (positions.empty())
        return makeError(ErrorCode::InvalidArgument, "model " + model.name + " has no triangles to draw");
    if (indices.size() + lodIndices.size() > std::size_t(std::numeric_limits<GLsizei>::max()))
        return makeError(ErrorCode::OutOfRange, "model " + model.name + " with LOD is too large for one GL buffer");
    const std::size_t lodBase = indices.size();
    for (DrawPart& d : g->parts_)
        for (DrawPart::Cluster& c : d.clusters)
            for (int l = 1; l < c.levels; ++l) c.first[l] += lodBase;
    indices.insert(indices.end(), lodIndices.begin(), lodIndices.end());
    g->lodBuildMs_ = lodMs;

    gl.CreateBuffers(1, &g->vertexBuffer_);
    gl.NamedBufferStorage(g->vertexBuffer_, GLsizeiptr(positions.size() * sizeof(glm::vec3)), positions.data(), 0);
    gl.CreateBuffers(1, &g->indexBuffer_);
    gl.NamedBufferStorage(g->indexBuffer_, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), 0);
    gl.CreateVertexArrays(1, &g->vao_);
    gl.VertexArrayVertexBuffer(g->vao_, 0, g->vertexBuffer_, 0, sizeof(glm::vec3));
    gl.VertexArrayElementBuffer(g->vao_, g->indexBuffer_);
    gl.EnableVertexArrayAttrib(g->vao_, 0);
    gl.VertexArrayAttribFormat(g->vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(g->vao_, 0, 0);
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
        return makeError(
            e == GL_OUT_OF_MEMORY ? ErrorCode::OutOfRange : ErrorCode::Internal,
            "uploading model " + model.name + " (" + std::to_string(g->triangles_) + " triangles): " + glErrorName(e));
    return g;
}

GpuModel::~GpuModel() {
    const GlFunctions& gl = context_.gl();
    if (vao_) gl.DeleteVertexArrays(1, &vao_);
    if (vertexBuffer_) gl.DeleteBuffers(1, &vertexBuffer_);
    if (indexBuffer_) gl.DeleteBuffers(1, &indexBuffer_);
}

}  // namespace geoslice
