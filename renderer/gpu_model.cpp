#include "renderer/gpu_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "renderer/lod/cluster_build.hpp"

namespace geoslice {
namespace {

glm::vec4 recordColour(const Model& model, RecordId id) {
    Rgba8 c;
    if (const AttributeRecord* r = model.attributes.find(id)) c = r->colour;
    return glm::vec4(c.r, c.g, c.b, c.a) / 255.0f;
}

}  // namespace

Result<std::unique_ptr<GpuModel>> GpuModel::upload(GlContext& context, const Model& model,
                                                   const UploadOptions& options) {
    return build(context, model, nullptr, options);
}

struct GpuModel::BakeSource {
    struct PartView {
        std::string name;
        PartKind kind = PartKind::Body;
        RecordId record = kNoRecord;
        std::size_t source = 0;            // index into the model's bodies, then surfaces
        const float* positions = nullptr;  // 3 per vertex, relative to BakeSource::origin
        bool gltfAxes = false;             // (east, up, -north); else (east, north, up)
        const float* uvs = nullptr;        // 2 per vertex
        std::size_t vertexCount = 0;
        std::span<const std::uint32_t> indices;
    };
    std::vector<PartView> parts;
    glm::dvec3 origin{0.0};  // world, metres
    std::span<const std::uint32_t> texels;
    std::uint32_t width = 0, height = 0, pages = 0;
    std::vector<const AttributeRecord*> records;  // colours beyond the model's table
};

Result<std::unique_ptr<GpuModel>> GpuModel::upload(GlContext& context, const Model& model,
                                                   const bake::BakedModel& baked, const UploadOptions& options) {
    BakeSource src;
    src.origin = model.origin;  // BakedPart positions are world - Model::origin
    for (const bake::BakedPart& bp : baked.parts) {
        if (bp.uvs.size() != bp.positions.size())
            return makeError(ErrorCode::InvalidArgument, "bake of model " + model.name + ": part " + bp.name + " has " +
                                                             std::to_string(bp.uvs.size()) + " UVs for " +
                                                             std::to_string(bp.positions.size()) + " vertices");
        src.parts.push_back({bp.name, bp.kind, bp.record, bp.source,
                             bp.positions.empty() ? nullptr : &bp.positions[0].x, false,
                             bp.uvs.empty() ? nullptr : &bp.uvs[0].x, bp.positions.size(), bp.indices});
    }
    src.texels = baked.texels;
    src.width = baked.width, src.height = baked.height, src.pages = baked.pages;
    for (const AttributeRecord& r : baked.fieldRecords) src.records.push_back(&r);
    auto g = build(context, model, &src, options);
    if (!g) return g.error();
    if (auto s = (*g)->uploadIdTexture(model, src); !s) return s.error();
    return g;
}

Result<std::unique_ptr<GpuModel>> GpuModel::upload(GlContext& context, const Model& model, const bake::Package& package,
                                                   const UploadOptions& options) {
    BakeSource src;
    src.origin = package.origin;
    // Package part i: the model's i-th part with triangles.
    std::size_t next = 0;
    const std::size_t sourceCount = model.bodies.size() + model.surfaces.size();
    for (const bake::PackagePart& pp : package.parts) {
        auto partAt = [&](std::size_t i) -> const Part& {
            return i < model.bodies.size() ? model.bodies[i] : model.surfaces[i - model.bodies.size()];
        };
        while (next < sourceCount && partAt(next).mesh.indices.empty()) ++next;
        if (next == sourceCount)
            return makeError(ErrorCode::InvalidArgument, "package " + package.name + " has more parts than model " +
                                                             model.name + " (part " + pp.name + ")");
        src.parts.push_back({pp.name, pp.kind, pp.record, next++, pp.positions, true, pp.uvs, pp.vertexCount,
                             std::span<const std::uint32_t>(pp.indices, pp.indexCount)});
    }
    src.texels = package.texels;
    src.width = package.width, src.height = package.height, src.pages = package.pages;
    for (const auto& [id, r] : package.attributes.records()) src.records.push_back(&r);
    auto g = build(context, model, &src, options);
    if (!g) return g.error();
    if (auto s = (*g)->uploadIdTexture(model, src); !s) return s.error();
    return g;
}

Result<std::unique_ptr<GpuModel>> GpuModel::build(GlContext& context, const Model& model, const BakeSource* baked,
                                                  const UploadOptions& options) {
    // The baked part of each model part (bodies, then surfaces), checked one to one.
    const std::size_t sourceCount = model.bodies.size() + model.surfaces.size();
    std::vector<const BakeSource::PartView*> bakedOf(sourceCount, nullptr);
    if (baked) {
        for (std::size_t i = 0; i < baked->parts.size(); ++i) {
            const BakeSource::PartView& bp = baked->parts[i];
            const std::string where =
                "bake of model " + model.name + ": part " + std::to_string(i) + " (" + bp.name + ")";
            if (bp.source >= sourceCount)
                return makeError(ErrorCode::InvalidArgument, where + " names source part " + std::to_string(bp.source) +
                                                                 " of " + std::to_string(sourceCount));
            if (bakedOf[bp.source])
                return makeError(ErrorCode::InvalidArgument,
                                 where + " repeats source part " + std::to_string(bp.source));
            const bool body = bp.source < model.bodies.size();
            const Part& part = body ? model.bodies[bp.source] : model.surfaces[bp.source - model.bodies.size()];
            if (body != (bp.kind == PartKind::Body) || bp.record != part.record ||
                bp.indices.size() != part.mesh.indices.size())
                return makeError(ErrorCode::InvalidArgument,
                                 where + " does not match the model's part " + part.name + " (kind, record " +
                                     std::to_string(bp.record) + " vs " + std::to_string(part.record) + ", " +
                                     std::to_string(bp.indices.size() / 3) + " vs " +
                                     std::to_string(part.mesh.triangleCount()) + " triangles): bake this model again");
            if (bp.vertexCount && (!bp.positions || !bp.uvs))
                return makeError(ErrorCode::InvalidArgument, where + " has no positions or UVs");
            bakedOf[bp.source] = &bp;
        }
        for (std::size_t i = 0; i < sourceCount; ++i) {
            const Part& part = i < model.bodies.size() ? model.bodies[i] : model.surfaces[i - model.bodies.size()];
            if (!bakedOf[i] && !part.mesh.indices.empty())
                return makeError(ErrorCode::InvalidArgument, "bake of model " + model.name + " lacks part " +
                                                                 part.name + ": bake this model again");
        }
    }
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
    std::vector<glm::vec2> uvs;  // baked only: one per position
    std::vector<std::uint32_t> indices;
    // Simplified levels go after every part's full-detail indices; offsets relative to
    // lodIndices until the fix-up below.
    std::vector<std::uint32_t> lodIndices;
    double lodMs = 0.0;
    // Scratch for clusters: part vertex -> compact vertex.
    std::vector<std::uint32_t> remap;
    // `bp`: the part's bake (its own vertices, UVs and local positions), or none.
    auto add = [&](const Part& part, bool body, const BakeSource::PartView* bp) -> Status {
        const std::span<const std::uint32_t> partIndices = bp ? bp->indices : std::span(part.mesh.indices);
        if (partIndices.empty()) return {};
        if (positions.size() > std::size_t(std::numeric_limits<GLint>::max()) ||
            indices.size() + partIndices.size() > std::size_t(std::numeric_limits<GLsizei>::max()))
            return makeError(ErrorCode::OutOfRange, "model " + model.name + " is too large for one GL buffer");
        std::vector<glm::vec3> local;
        if (bp) {
            // The bake's frame -> the model's local frame, in double (exact when they agree).
            const glm::dvec3 shift = baked->origin - model.origin;
            local.resize(bp->vertexCount);
            for (std::size_t v = 0; v < bp->vertexCount; ++v) {
                const float* q = bp->positions + 3 * v;
                const glm::dvec3 p =
                    bp->gltfAxes ? glm::dvec3(q[0], -double(q[2]), q[1]) : glm::dvec3(q[0], q[1], q[2]);
                local[v] = glm::vec3(p + shift);
            }
        } else {
            local = model.localPositions(part.mesh);
        }
        for (std::uint32_t i : partIndices)
            if (i >= local.size())
                return makeError(ErrorCode::InvalidArgument,
                                 "model " + model.name + ": part " + part.name + " has vertex index " +
                                     std::to_string(i) + " past its " + std::to_string(local.size()) + " vertices");
        DrawPart d;
        d.baseVertex = GLint(positions.size());
        d.firstIndex = indices.size();
        d.indexCount = GLsizei(partIndices.size());
        d.body = body;
        d.record = part.record;
        d.colour = recordColour(model, part.record);
        if (body) d.bodyIndex = int(&part - model.bodies.data());
        if (body && part.report.parent >= 0 && std::size_t(part.report.parent) < model.bodies.size()) {
            d.containerRecord = model.bodies[std::size_t(part.report.parent)].record;
            d.containerColour = recordColour(model, d.containerRecord);
            d.containerBody = part.report.parent;
        }
        if (!body) {
            d.surfaceFirst = g->surfaceTriangles_.size();
            for (std::uint32_t i : partIndices) g->surfaceTriangles_.push_back(local[i]);
            d.surfaceCount = partIndices.size();
        }

        std::vector<std::uint32_t> sorted;
        lodMs += buildClusters(grid, local, partIndices, lod, options.lodLevels, d, sorted, lodIndices, g->cellBounds_,
                               remap);
        positions.insert(positions.end(), local.begin(), local.end());
        if (bp)
            for (std::size_t v = 0; v < bp->vertexCount; ++v) uvs.emplace_back(bp->uvs[2 * v], bp->uvs[2 * v + 1]);
        indices.insert(indices.end(), sorted.begin(), sorted.end());
        g->parts_.push_back(std::move(d));
        g->triangles_ += partIndices.size() / 3;
        return {};
    };
    for (std::size_t i = 0; i < model.bodies.size(); ++i)
        if (auto s = add(model.bodies[i], true, baked ? bakedOf[i] : nullptr); !s) return s.error();
    for (std::size_t i = 0; i < model.surfaces.size(); ++i)
        if (auto s = add(model.surfaces[i], false, baked ? bakedOf[model.bodies.size() + i] : nullptr); !s)
            return s.error();
    if (positions.empty())
        return makeError(ErrorCode::InvalidArgument, "model " + model.name + " has no triangles to draw");
    if (indices.size() + lodIndices.size() > std::size_t(std::numeric_limits<GLsizei>::max()))
        return makeError(ErrorCode::OutOfRange, "model " + model.name + " with LOD is too large for one GL buffer");
    const std::size_t lodBase = indices.size();
    for (DrawPart& d : g->parts_)
        for (DrawPart::Cluster& c : d.clusters)
            for (int l = 1; l < c.levels; ++l) c.first[l] += lodBase;
    for (DrawPart& d : g->parts_)
        for (DrawPart::Group& group : d.groups) group.first += lodBase;
    indices.insert(indices.end(), lodIndices.begin(), lodIndices.end());
    g->lodBuildMs_ = lodMs;

    g->vertexBuffer_ = GlBuffer::create(gl);
    gl.NamedBufferStorage(g->vertexBuffer_.id(), GLsizeiptr(positions.size() * sizeof(glm::vec3)), positions.data(), 0);
    g->indexBuffer_ = GlBuffer::create(gl);
    gl.NamedBufferStorage(g->indexBuffer_.id(), GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), 0);
    g->vao_ = GlVertexArray::create(gl);
    gl.VertexArrayVertexBuffer(g->vao_.id(), 0, g->vertexBuffer_.id(), 0, sizeof(glm::vec3));
    gl.VertexArrayElementBuffer(g->vao_.id(), g->indexBuffer_.id());
    gl.EnableVertexArrayAttrib(g->vao_.id(), 0);
    gl.VertexArrayAttribFormat(g->vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(g->vao_.id(), 0, 0);
    if (baked) {
        // Attribute 1: the bake's UV (page + u, v). Without a bake it stays disabled and reads
        // the constant (0, 0, 0, 1), which the shader ignores.
        g->uvBytes_ = uvs.size() * sizeof(glm::vec2);
        g->uvBuffer_ = GlBuffer::create(gl);
        gl.NamedBufferStorage(g->uvBuffer_.id(), GLsizeiptr(g->uvBytes_), uvs.data(), 0);
        gl.VertexArrayVertexBuffer(g->vao_.id(), 1, g->uvBuffer_.id(), 0, sizeof(glm::vec2));
        gl.EnableVertexArrayAttrib(g->vao_.id(), 1);
        gl.VertexArrayAttribFormat(g->vao_.id(), 1, 2, GL_FLOAT, GL_FALSE, 0);
        gl.VertexArrayAttribBinding(g->vao_.id(), 1, 1);
    }
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
        return makeError(
            e == GL_OUT_OF_MEMORY ? ErrorCode::OutOfRange : ErrorCode::Internal,
            "uploading model " + model.name + " (" + std::to_string(g->triangles_) + " triangles): " + glErrorName(e));
    return g;
}

Status GpuModel::uploadIdTexture(const Model& model, const BakeSource& baked) {
    const GlFunctions& gl = context_.gl();
    const std::string what = "id texture of model " + model.name + " (" + std::to_string(baked.width) + "x" +
                             std::to_string(baked.height) + "x" + std::to_string(baked.pages) + ")";
    if (baked.width == 0 || baked.height == 0 || baked.pages == 0 ||
        baked.texels.size() != std::size_t(baked.width) * baked.height * baked.pages)
        return makeError(ErrorCode::InvalidArgument,
                         what + " holds " + std::to_string(baked.texels.size()) + " texels, not width*height*pages");
    GLint maxSize = 0, maxLayers = 0;
    gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    gl.GetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    if (baked.width > std::uint32_t(maxSize) || baked.height > std::uint32_t(maxSize))
        return makeError(ErrorCode::OutOfRange, what + ": a side exceeds GL_MAX_TEXTURE_SIZE " +
                                                    std::to_string(maxSize) + " of this device; bake with --size " +
                                                    std::to_string(maxSize) + " or less");
    if (baked.pages > std::uint32_t(maxLayers))
        return makeError(ErrorCode::OutOfRange, what + ": pages exceed GL_MAX_ARRAY_TEXTURE_LAYERS " +
                                                    std::to_string(maxLayers) + " of this device");
    // Record -> colour: every record of the model's table and of the field.
    RecordId maxId = 0;
    for (const auto& [id, r] : model.attributes.records()) maxId = std::max(maxId, id);
    for (const AttributeRecord* r : baked.records) maxId = std::max(maxId, r->id);
    const std::size_t rows = std::size_t(maxId) / kColourTableWidth + 1;
    if (rows > std::size_t(maxSize))
        return makeError(ErrorCode::OutOfRange, "model " + model.name + ": record id " + std::to_string(maxId) +
                                                    " is beyond the colour table (" +
                                                    std::to_string(kColourTableWidth) + " x GL_MAX_TEXTURE_SIZE " +
                                                    std::to_string(maxSize) + " records)");
    const Rgba8 grey;  // what recordColour() gives a record that is not in the table
    std::vector<Rgba8> table(rows * kColourTableWidth, grey);
    for (const auto& [id, r] : model.attributes.records()) table[id] = r.colour;
    for (const AttributeRecord* r : baked.records) table[r->id] = r->colour;

    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    idTexture_ = GlTexture::create(gl, GL_TEXTURE_2D_ARRAY);
    gl.TextureParameteri(idTexture_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TextureParameteri(idTexture_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TextureParameteri(idTexture_.id(), GL_TEXTURE_MAX_LEVEL, 0);
    gl.TextureStorage3D(idTexture_.id(), 1, GL_R32UI, GLsizei(baked.width), GLsizei(baked.height),
                        GLsizei(baked.pages));
    // One page per call: a page is at most GL_MAX_TEXTURE_SIZE^2 * 4 bytes.
    for (std::uint32_t page = 0; page < baked.pages; ++page)
        gl.TextureSubImage3D(idTexture_.id(), 0, 0, 0, GLint(page), GLsizei(baked.width), GLsizei(baked.height), 1,
                             GL_RED_INTEGER, GL_UNSIGNED_INT,
                             baked.texels.data() + std::size_t(page) * baked.width * baked.height);
    idTextureBytes_ = baked.texels.size() * sizeof(std::uint32_t);

    colourTable_ = GlTexture::create(gl, GL_TEXTURE_2D);
    gl.TextureParameteri(colourTable_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TextureParameteri(colourTable_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TextureParameteri(colourTable_.id(), GL_TEXTURE_MAX_LEVEL, 0);
    gl.TextureStorage2D(colourTable_.id(), 1, GL_RGBA8, kColourTableWidth, GLsizei(rows));
    gl.TextureSubImage2D(colourTable_.id(), 0, 0, 0, kColourTableWidth, GLsizei(rows), GL_RGBA, GL_UNSIGNED_BYTE,
                         table.data());
    colourTableBytes_ = table.size() * sizeof(Rgba8);
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR)
        return makeError(e == GL_OUT_OF_MEMORY ? ErrorCode::OutOfRange : ErrorCode::Internal,
                         "uploading the " + what + ": " + glErrorName(e));
    return {};
}

GpuModel::~GpuModel() = default;

}  // namespace geoslice
