#include "api/view.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "api/holes.hpp"
#include "api/legend.hpp"
#include "model/clock.hpp"
#include "model/json_text.hpp"
#include "print/pattern_cairo.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/dxf_export.hpp"
#include "section/fill/vector_export.hpp"

namespace geoslice::api {
Result<std::optional<PropertyClasses>> blockClasses(const CatalogModel& model, const SectionDef& def) {
    if (!def.colour) return std::optional<PropertyClasses>();
    if (!model.model.blocks)
        return makeError(ErrorCode::InvalidArgument, "parameter 'colour': model '" + model.id +
                                                         "' has no block model (attach one with a <stem>.blocks.json "
                                                         "or <stem>.blocks.csv sidecar)");
    auto classes = propertyClasses(*model.model.blocks, def.colour->property, def.colour->ramp, def.colour->breaks);
    if (!classes)
        return makeError(classes.error().code,
                         std::string(def.colour->breaks ? "parameters 'colour', 'breaks': " : "parameter 'colour': ") +
                             classes.error().message);
    return std::optional<PropertyClasses>(std::move(classes.value()));
}

std::size_t blockCellAt(const CatalogModel& model, RecordId record, const glm::dvec3& world) {
    if (!model.model.blocks || record == kNoRecord ||
        !std::binary_search(model.blockRecords.begin(), model.blockRecords.end(), record))
        return BlockModel::kNoCell;
    return model.model.blocks->cellAt(world);
}

Result<BlockCapTriangles> blockCapTriangles(const Model& model, const PropertyClasses& classes,
                                            const std::vector<Plane>& planes, std::size_t maxPieces) {
    const auto t0 = std::chrono::steady_clock::now();
    BlockCapTriangles out;
    if (!model.blocks) return out;
    const BlockModel& blocks = *model.blocks;
    const std::vector<double>& values = blocks.properties[std::size_t(classes.property)].values;
    Aabb clipBounds;
    for (std::uint32_t b : blocks.clipBodyIndex) clipBounds.extend(model.bodies[b].mesh.bounds());
    const glm::dvec3 origin = model.origin;
    for (const Plane& plane : planes) {
        const SectionFrame frame = makeSectionFrame(plane, origin);
        // Only the pieces whose bounds meet the clipping bodies' bounds' shadow on the plane
        // (the stencil keeps the rest off the image anyway).
        FrameRect limit;
        limit.u0 = limit.v0 = std::numeric_limits<double>::infinity();
        limit.u1 = limit.v1 = -std::numeric_limits<double>::infinity();
        for (int c = 0; c < 8 && clipBounds.valid(); ++c) {
            const glm::dvec3 corner{c & 1 ? clipBounds.max.x : clipBounds.min.x,
                                    c & 2 ? clipBounds.max.y : clipBounds.min.y,
                                    c & 4 ? clipBounds.max.z : clipBounds.min.z};
            const glm::dvec2 uv = frame.toPlane(corner - origin);
            limit.u0 = std::min(limit.u0, uv.x);
            limit.u1 = std::max(limit.u1, uv.x);
            limit.v0 = std::min(limit.v0, uv.y);
            limit.v1 = std::max(limit.v1, uv.y);
        }
        BlockCapTriangles::Range range;
        range.first = std::uint32_t(out.positions.size());
        if (clipBounds.valid()) {
            auto pieces = cellPolygons(blocks, frame, &limit, maxPieces);
            if (!pieces) return pieces.error();
            // Two passes: cells with a value, then those without (drawn into the cell buffer only).
            for (const bool valued : {true, false})
                for (const CellPolygon& piece : pieces.value()) {
                    const int k = classes.classOf(values[piece.cell]);
                    if ((k >= 0) != valued) continue;
                    const glm::uvec2 cc(std::uint32_t(piece.cell + 1), std::uint32_t(k + 1));
                    const glm::vec3 a(frame.toLocal(piece.ring[0]));
                    for (std::size_t v = 1; v + 1 < piece.ring.size(); ++v) {
                        out.positions.insert(out.positions.end(), {a, glm::vec3(frame.toLocal(piece.ring[v])),
                                                                   glm::vec3(frame.toLocal(piece.ring[v + 1]))});
                        out.cellClass.insert(out.cellClass.end(), {cc, cc, cc});
                    }
                    (valued ? range.valued : range.unvalued) += std::uint32_t(3 * (piece.ring.size() - 2));
                }
        }
        out.planes.push_back(range);
    }
    out.cutMs = msSince(t0);
    return out;
}

void colourByBlocks(const CatalogModel& model, const PropertyClasses& classes, const PixelMapping& mapping,
                    ViewImage& image) {
    const std::size_t pixels = std::size_t(image.width) * std::size_t(image.height);
    image.cells.assign(pixels, 0);
    if (!model.model.blocks || image.ids.size() != pixels) return;
    // Where pixel centres along a row lie on a line (the walk of section/blocks/block_raster.cpp): a
    // plane's whole row, a polyline's columns on each leg.
    const std::vector<RowLine> lines = mapping.geometry == Geometry::Line
                                           ? polylineRowLines(
                                                 mapping.line, [&](int i) { return mapping.sectionAt(i, 0).x; },
                                                 mapping.width, (mapping.rect.u1 - mapping.rect.u0) / mapping.width)
                                           : std::vector<RowLine>{{0, image.width, mapping.planar.worldPerPixelX()}};
    colourPixelsByBlocks(
        *model.model.blocks, classes, model.blockRecords, [&](int i, int j) { return mapping.worldAt(i, j); },
        image.width, image.height, image.ids.data(), image.rgba.size() == 4 * pixels ? image.rgba.data() : nullptr,
        image.cells.data(), lines);
}

glm::dvec2 PixelMapping::sectionAt(int i, int j) const {
    const double pu = (rect.u1 - rect.u0) / width, pv = (rect.v1 - rect.v0) / height;
    return {rect.u0 + (i + 0.5) * pu, rect.v1 - (j + 0.5) * pv};
}

glm::dvec3 PixelMapping::worldAt(int i, int j) const {
    if (geometry == Geometry::Line) {
        const glm::dvec2 sz = sectionAt(i, j);
        return line.worldAt(sz.x, sz.y);
    }
    return planar.pixelCentreWorld(i, j);
}

Result<PixelMapping> profileMapping(const CatalogModel& model, const ViewPlan& plan) {
    PixelMapping m;
    m.geometry = plan.section.geometry;
    m.width = plan.width;
    m.height = plan.height;
    if (plan.section.geometry == Geometry::Line) {
        auto line = makeSectionLine(plan.section.line);
        if (!line) return makeError(line.error().code, "parameter 'line': " + line.error().message);
        m.line = std::move(line.value());
        m.rect = plan.frame ? *plan.frame
                            : defaultLineFrame(m.line.length(), model.index->bounds, plan.width, plan.height,
                                               exaggerationOf(plan.section, model.index->bounds));
    } else {
        auto plane = checkPlaneMeetsBounds(sectionPlane(plan.section), model.index->bounds, model.index->origin);
        if (!plane)
            return makeError(plane.error().code,
                             std::string(plan.section.geometry == Geometry::Elevation ? "parameter 'elevation': "
                                                                                      : "parameter 'plane': ") +
                                 plane.error().message);
        m.rect = plan.frame ? *plan.frame
                            : defaultFrame(plane.value(), model.index->bounds, model.model.origin, plan.width,
                                           plan.height, exaggerationOf(plan.section, model.index->bounds));
        m.planar.section = makeSectionFrame(plane.value(), model.model.origin);
        m.planar.rect = m.rect;
        m.planar.width = plan.width;
        m.planar.height = plan.height;
    }
    if (auto s = checkFrame(m.rect, plan.width, plan.height); !s) return s.error();
    return m;
}

namespace {
constexpr double kLabelPx = 12.0;  // labels at print scale on a 96 dpi screen (9 pt)
}  // namespace

Result<ViewImage> renderProfile(const CatalogModel& model, const ViewPlan& plan, const std::atomic<bool>* cancel) {
    if (plan.view != ViewKind::Profile)
        return makeError(ErrorCode::InvalidArgument, "renderProfile: the plan is not a profile view");
    const auto t0 = std::chrono::steady_clock::now();
    auto mapping = profileMapping(model, plan);
    if (!mapping) return mapping.error();
    auto classes = blockClasses(model, plan.section);
    if (!classes) return classes.error();
    auto holes = viewHoles(model, plan.section, mapping.value());
    if (!holes) return holes.error();
    RasterOptions ro;
    ro.background = plan.section.background;
    ro.cancel = cancel;
    ViewImage v;
    std::optional<PolylineSection> lineSection;
    std::optional<Section> planeSection;
    if (plan.section.geometry == Geometry::Line) {
        auto section = computePolylineSection(*model.index, plan.section.line, besideOtherWork());
        if (!section) return makeError(section.error().code, "parameter 'line': " + section.error().message);
        if (auto c = checkCancel(cancel); !c) return c.error();
        auto image =
            rasterizePolylineSection(*model.index, section.value(), mapping.value().rect, plan.width, plan.height, ro);
        if (!image) return image.error();
        v.width = plan.width;
        v.height = plan.height;
        v.rgba = std::move(image.value().rgba);
        v.ids = std::move(image.value().ids);
        lineSection = std::move(section.value());
    } else {
        auto section = computeSection(*model.index, sectionPlane(plan.section), besideOtherWork());
        if (!section) return section.error();
        if (auto c = checkCancel(cancel); !c) return c.error();
        auto image = rasterizeSection(*model.index, section.value(), mapping.value().rect, plan.width, plan.height, ro);
        if (!image) return image.error();
        v.width = plan.width;
        v.height = plan.height;
        v.rgba = std::move(image.value().rgba);
        v.ids = std::move(image.value().ids);
        planeSection = std::move(section.value());
    }
    v.mapping = std::move(mapping.value());
    if (classes.value()) colourByBlocks(model, *classes.value(), *v.mapping, v);
    if (plan.labels.value_or(false) || plan.patterns.value_or(false))
        print::decorateSectionImage(*model.index, lineSection ? lineSection->bodies : planeSection->bodies,
                                    v.mapping->rect, v.width, v.height, v.rgba.data(),
                                    v.ids.size() == v.rgba.size() / 4 ? v.ids.data() : nullptr,
                                    {plan.labels.value_or(false), plan.patterns.value_or(false), kLabelPx},
                                    lineSection ? &lineSection->traces : &planeSection->traces);
    drawHoles(model, holes.value(), *v.mapping, v);
    v.renderMs = msSince(t0);
    return v;
}

Result<std::string> renderVector(const CatalogModel& model, const ViewPlan& plan, VectorFormat format,
                                 VectorFrame frame, const std::atomic<bool>* cancel) {
    if (plan.view != ViewKind::Profile)
        return makeError(ErrorCode::Unsupported, "vector output (GeoJSON, SVG, DXF) exists for profile views only");
    const bool svg = format == VectorFormat::Svg;
    auto mapping = profileMapping(model, plan);
    if (!mapping) return mapping.error();
    auto classes = blockClasses(model, plan.section);
    if (!classes) return classes.error();
    auto holes = viewHoles(model, plan.section, mapping.value());
    if (!holes) return holes.error();
    RasterOptions ro;
    ro.background = plan.section.background;
    SvgOverlays overlays;
    overlays.labels = plan.labels.value_or(false);
    overlays.patterns = plan.patterns.value_or(true);
    overlays.labelPx = kLabelPx;
    overlays.textWidth = print::labelTextWidth;
    // The drillholes go last: over everything in SVG, after the section's features in GeoJSON.
    auto withHoles = [&](std::string svgText) {
        const std::string g = holesSvg(model, holes.value(), mapping.value());
        const auto end = svgText.rfind("</svg>");
        if (!g.empty() && end != std::string::npos) svgText.insert(end, g);
        return svgText;
    };
    auto addHoles = [&](nlohmann::ordered_json& doc, const GeoJsonSpace& space) {
        if (holes.value().empty()) return;
        for (auto& f : holesGeoJson(model, holes.value(), space.threeD() ? &space.position : nullptr))
            doc["features"].push_back(std::move(f));
        if (auto legend = holeLegendJson(holes.value().style); !legend.is_null()) doc["holeLegend"] = std::move(legend);
    };
    auto spaceOf = [&](const VectorSource& source) {
        return geoJsonSpace(source, frame, model.model.crs, model.lonLat.get(), model.lonLatNote);
    };
    auto emit = [&](const VectorSource& source) -> Result<std::string> {
        if (auto c = checkCancel(cancel); !c) return c.error();
        if (format == VectorFormat::Dxf) {
            DxfOptions o;
            o.frame = frame == VectorFrame::Projected ? DxfFrame::Projected : DxfFrame::Plane;
            o.labels = plan.labels.value_or(true);
            return toDxf(*model.index, source, o);
        }
        if (svg) {
            auto text = toSvg(*model.index, source, mapping.value().rect, plan.width, plan.height, ro, overlays);
            if (!text) return text;
            return withHoles(std::move(text.value()));
        }
        auto space = spaceOf(source);
        if (!space) return space.error();
        auto doc = toGeoJson(*model.index, source, space.value());
        if (!doc) return doc.error();
        addHoles(doc.value(), space.value());
        if (Status s = space.value().checkPositions(); !s) return s.error();
        return jsonText(doc.value());
    };
    // The cells' exact pieces inside the clipping bodies (plane u/v or line s/z), drawn over the
    // bodies' own fills.
    std::optional<PolylineSection> line;
    std::optional<Section> planar;
    VectorSource source;
    Result<std::vector<BlockPiece>> pieces = std::vector<BlockPiece>();
    if (plan.section.geometry == Geometry::Line) {
        auto section = computePolylineSection(*model.index, plan.section.line, besideOtherWork());
        if (!section) return makeError(section.error().code, "parameter 'line': " + section.error().message);
        line = std::move(section.value());
        source = vectorSource(*line);
        if (classes.value())
            pieces = blockPieces(*model.model.blocks, *line, model.index->origin, &mapping.value().rect);
    } else {
        auto section = computeSection(*model.index, sectionPlane(plan.section), besideOtherWork());
        if (!section) return section.error();
        planar = std::move(section.value());
        source = vectorSource(*planar);
        if (classes.value()) pieces = blockPieces(*model.model.blocks, *planar, &mapping.value().rect);
    }
    if (!classes.value()) return emit(source);
    if (format == VectorFormat::Dxf)
        return makeError(ErrorCode::Unsupported,
                         "parameter 'colour': the DXF export draws the units, not block-model cells; leave colour out");
    const PropertyClasses& pc = *classes.value();
    const BlockModel& blocks = *model.model.blocks;
    if (!pieces) return makeError(pieces.error().code, "parameter 'colour': " + pieces.error().message);
    if (auto c = checkCancel(cancel); !c) return c.error();
    if (svg) {
        source.svgOverBodies =
            blockPiecesSvg(blocks, pc, pieces.value(), mapping.value().rect, plan.width, plan.height);
        return emit(source);
    }
    auto space = spaceOf(source);
    if (!space) return space.error();
    auto doc = toGeoJson(*model.index, source, space.value());
    if (!doc) return doc.error();
    for (auto& f : blockPiecesGeoJson(blocks, pc, pieces.value(), space.value()))
        doc.value()["features"].push_back(std::move(f));
    doc.value()["blockLegend"] = blockLegendJson(blocks, pc);
    addHoles(doc.value(), space.value());
    if (Status s = space.value().checkPositions(); !s) return s.error();
    return jsonText(doc.value());
}

}  // namespace geoslice::api
