#include "api/view.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "api/json_writer.hpp"
#include "api/legend.hpp"
#include "section/contours.hpp"
#include "section/vector_export.hpp"

namespace geoslice::api {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Status requirePlanar(const SectionDef& def) {
    if (def.geometry == Geometry::Line)
        return makeError(ErrorCode::Unsupported,
                         "tiles of polyline sections are not served yet; use 'plane' or 'elevation'");
    if (!def.cutPlanes.empty())
        return makeError(ErrorCode::InvalidArgument,
                         "parameter 'planes': a section for tiles takes one plane; cut-outs of " +
                             std::to_string(def.cutPlanes.size()) + " planes are for perspective views");
    return {};
}

ViewImage fromSectionImage(SectionImage&& s) {
    ViewImage v;
    v.width = s.frame.width;
    v.height = s.frame.height;
    v.rgba = std::move(s.rgba);
    v.ids = std::move(s.ids);
    PixelMapping m;
    m.planar = s.frame;
    m.rect = s.frame.rect;
    m.width = v.width;
    m.height = v.height;
    v.mapping = m;
    return v;
}

}  // namespace

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

void colourByBlocks(const CatalogModel& model, const PropertyClasses& classes, const PixelMapping& mapping,
                    ViewImage& image) {
    const std::size_t pixels = std::size_t(image.width) * std::size_t(image.height);
    image.cells.assign(pixels, 0);
    if (!model.model.blocks || image.ids.size() != pixels) return;
    colourPixelsByBlocks(
        *model.model.blocks, classes, model.blockRecords, [&](int i, int j) { return mapping.worldAt(i, j); },
        image.width, image.height, image.ids.data(), image.rgba.size() == 4 * pixels ? image.rgba.data() : nullptr,
        image.cells.data());
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
        auto plane = checkSectionPlane(*model.index, sectionPlane(plan.section));
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

Result<ViewImage> renderProfile(const CatalogModel& model, const ViewPlan& plan, const std::atomic<bool>* cancel) {
    if (plan.view != ViewKind::Profile)
        return makeError(ErrorCode::InvalidArgument, "renderProfile: the plan is not a profile view");
    const auto t0 = std::chrono::steady_clock::now();
    auto mapping = profileMapping(model, plan);
    if (!mapping) return mapping.error();
    auto classes = blockClasses(model, plan.section);
    if (!classes) return classes.error();
    RasterOptions ro;
    ro.background = plan.section.background;
    ro.cancel = cancel;
    ViewImage v;
    if (plan.section.geometry == Geometry::Line) {
        auto section = computePolylineSection(*model.index, plan.section.line);
        if (!section) return makeError(section.error().code, "parameter 'line': " + section.error().message);
        if (auto c = checkCancel(cancel); !c) return c.error();
        auto image =
            rasterizePolylineSection(*model.index, section.value(), mapping.value().rect, plan.width, plan.height, ro);
        if (!image) return image.error();
        v.width = plan.width;
        v.height = plan.height;
        v.rgba = std::move(image.value().rgba);
        v.ids = std::move(image.value().ids);
    } else {
        auto section = computeSection(*model.index, sectionPlane(plan.section));
        if (!section) return section.error();
        if (auto c = checkCancel(cancel); !c) return c.error();
        auto image = rasterizeSection(*model.index, section.value(), mapping.value().rect, plan.width, plan.height, ro);
        if (!image) return image.error();
        v.width = plan.width;
        v.height = plan.height;
        v.rgba = std::move(image.value().rgba);
        v.ids = std::move(image.value().ids);
    }
    v.mapping = std::move(mapping.value());
    if (classes.value()) colourByBlocks(model, *classes.value(), *v.mapping, v);
    v.renderMs = msSince(t0);
    return v;
}

Result<std::string> renderVector(const CatalogModel& model, const ViewPlan& plan, bool svg, bool world,
                                 const std::atomic<bool>* cancel) {
    if (plan.view != ViewKind::Profile)
        return makeError(ErrorCode::Unsupported, "vector output (GeoJSON, SVG) exists for profile views only");
    auto mapping = profileMapping(model, plan);
    if (!mapping) return mapping.error();
    auto classes = blockClasses(model, plan.section);
    if (!classes) return classes.error();
    RasterOptions ro;
    ro.background = plan.section.background;
    auto emit = [&](const VectorSource& source) -> Result<std::string> {
        if (auto c = checkCancel(cancel); !c) return c.error();
        if (svg) return toSvg(*model.index, source, mapping.value().rect, plan.width, plan.height, ro);
        return toGeoJson(*model.index, source, world ? VectorFrame::World : VectorFrame::Plane).dump();
    };
    // The cells' exact pieces inside the clipping bodies (plane u/v or line s/z), drawn over the
    // bodies' own fills.
    std::optional<PolylineSection> line;
    std::optional<Section> planar;
    VectorSource source;
    Result<std::vector<BlockPiece>> pieces = std::vector<BlockPiece>();
    if (plan.section.geometry == Geometry::Line) {
        auto section = computePolylineSection(*model.index, plan.section.line);
        if (!section) return makeError(section.error().code, "parameter 'line': " + section.error().message);
        line = std::move(section.value());
        source = vectorSource(*line);
        if (classes.value())
            pieces = blockPieces(*model.model.blocks, *line, model.index->origin, &mapping.value().rect);
    } else {
        auto section = computeSection(*model.index, sectionPlane(plan.section));
        if (!section) return section.error();
        planar = std::move(section.value());
        source = vectorSource(*planar);
        if (classes.value()) pieces = blockPieces(*model.model.blocks, *planar, &mapping.value().rect);
    }
    if (!classes.value()) return emit(source);
    const PropertyClasses& pc = *classes.value();
    const BlockModel& blocks = *model.model.blocks;
    if (!pieces) return makeError(pieces.error().code, "parameter 'colour': " + pieces.error().message);
    if (auto c = checkCancel(cancel); !c) return c.error();
    if (svg) {
        source.svgOverBodies =
            blockPiecesSvg(blocks, pc, pieces.value(), mapping.value().rect, plan.width, plan.height);
        return emit(source);
    }
    nlohmann::ordered_json doc = toGeoJson(*model.index, source, world ? VectorFrame::World : VectorFrame::Plane);
    auto features = blockPiecesGeoJson(blocks, pc, pieces.value(), world ? &source.toWorld : nullptr);
    for (auto& f : features) doc["features"].push_back(std::move(f));
    doc["blockLegend"] = blockLegendJson(blocks, pc);
    return doc.dump();
}

Result<FrameRect> TileGrid::tileRect(int z, long long x, long long y) const {
    if (z < 0 || z > maxZoom)
        return makeError(ErrorCode::NotFound,
                         "tile zoom " + std::to_string(z) + " is outside 0.." + std::to_string(maxZoom));
    const long long n = 1LL << z;
    if (x < 0 || y < 0 || x >= n || y >= n)
        return makeError(ErrorCode::NotFound, "tile " + std::to_string(z) + "/" + std::to_string(x) + "/" +
                                                  std::to_string(y) + " is outside the grid (0.." +
                                                  std::to_string(n - 1) + " at zoom " + std::to_string(z) + ")");
    const double s = size0 / double(n);
    const double sv = s / exaggeration;
    FrameRect r;
    r.u0 = extent.u0 + double(x) * s;
    r.u1 = r.u0 + s;
    r.v1 = extent.v1 - double(y) * sv;
    r.v0 = r.v1 - sv;
    return r;
}

nlohmann::ordered_json TileGrid::describe() const {
    nlohmann::ordered_json j;
    j["tileSize"] = tileSize;
    j["minZoom"] = 0;
    j["maxZoom"] = maxZoom;
    j["origin"] = {{"u", extent.u0}, {"v", extent.v1}};
    j["size0"] = size0;
    j["exaggeration"] = exaggeration;
    j["extent"] = {{"u0", extent.u0}, {"u1", extent.u1}, {"v0", extent.v0}, {"v1", extent.v1}};
    j["tileRect"] =
        "u in [u0 + x*s, u0 + (x+1)*s], v in [v1 - (y+1)*s/k, v1 - y*s/k], s = size0 / 2^z, k = exaggeration";
    const double scale = 256.0 / size0;
    j["leaflet"] = {
        {"crs", "L.CRS.Simple"},
        {"lngOfU", "lng = (u - origin.u) * 256 / size0"},
        {"latOfV", "lat = (v - origin.v) * exaggeration * 256 / size0"},
        {"bounds", {{(extent.v0 - extent.v1) * exaggeration * scale, 0.0}, {0.0, (extent.u1 - extent.u0) * scale}}}};
    return j;
}

Result<TileGrid> tileGrid(const CatalogModel& model, const SectionDef& def) {
    if (auto s = requirePlanar(def); !s) return s.error();
    auto plane = checkSectionPlane(*model.index, sectionPlane(def));
    if (!plane) return plane.error();
    TileGrid g;
    // The picture's stretch of plane v (model/exaggeration.hpp): def.exaggeration on a
    // vertical plane, 1 on a horizontal one.
    g.exaggeration = exaggerationOf(def, model.index->bounds).vStretch(plane.value().normal);
    // The model's bounds on the plane, no margin; the grid is anchored at its top-left corner.
    g.extent = projectedBounds(plane.value(), model.index->bounds, model.model.origin);
    const double extentU = g.extent.u1 - g.extent.u0;
    const double extentV = (g.extent.v1 - g.extent.v0) * g.exaggeration;
    g.size0 = std::exp2(std::ceil(std::log2(std::max({extentU, extentV, 1e-3}))));
    const double finest = 0.01 * g.tileSize;  // about 1 cm per pixel
    g.maxZoom = std::clamp(int(std::ceil(std::log2(g.size0 / finest))), 0, 24);
    return g;
}

Result<ViewImage> renderSectionTile(const CatalogModel& model, const SectionDef& def, const TileGrid& grid, int z,
                                    long long x, long long y, const std::atomic<bool>* cancel) {
    auto rect = grid.tileRect(z, x, y);
    if (!rect) return rect.error();
    auto classes = blockClasses(model, def);
    if (!classes) return classes.error();
    const auto t0 = std::chrono::steady_clock::now();
    RasterOptions ro;
    ro.background = def.background;
    ro.cancel = cancel;
    auto image = renderTile(*model.index, sectionPlane(def), rect.value(), grid.tileSize, grid.tileSize, ro);
    if (!image) return image.error();
    ViewImage v = fromSectionImage(std::move(image.value()));
    if (classes.value()) colourByBlocks(model, *classes.value(), *v.mapping, v);
    v.renderMs = msSince(t0);
    return v;
}

Status checkPerspectiveCut(const CatalogModel& model, const ViewPlan& plan) {
    const CutOut cut = sectionCut(plan.section);
    const char* name = cut.planes.size() > 1                          ? "planes"
                       : plan.section.geometry == Geometry::Elevation ? "elevation"
                                                                      : "plane";
    return checkCutKeepsSomething(name, cut, model.index->bounds);
}

namespace {

// What a perspective view shows along the ray through a pixel centre, by the renderer's
// rule (renderer/slice_renderer.hpp): the first body interval with a kept part, at the start
// of that part. Where the body's own entry (its front face) is kept, that is its exterior,
// and an open surface crossed on a kept part of the ray before it is seen instead; where
// the entry is removed, the kept part starts on a cut face (a cap), which open surfaces
// never cover. With one plane no open surface can lie in front of a cap; with a cut-out
// one can (kept, removed, kept again along the ray), and the image shows the cap there.
Result<QueryAnswer> answerPerspective(const CatalogModel& model, const ViewPlan& plan, long long px, long long py,
                                      const ViewImage* cached, const RayWait& wait) {
    if (auto s = checkPerspectiveCut(model, plan); !s) return s.error();
    const CutOut cut = sectionCut(plan.section);
    // The pixel's ray in display space, mapped to world (the exaggeration is affine: a line
    // stays a line). Distances along it are world metres.
    const VerticalExaggeration display = exaggerationOf(plan.section, model.index->bounds);
    const PerspectiveCamera cam = displayCamera(plan, model.index->bounds);
    const PixelRay displayRay = pixelRay(cam, plan.width, plan.height, double(px) + 0.5, double(py) + 0.5);
    PixelRay ray;
    ray.origin = display.toWorld(displayRay.origin);
    ray.direction = glm::normalize(display.toWorld(displayRay.origin + displayRay.direction) - ray.origin);
    const std::vector<RaySpan> kept = cut.keptSpans(ray.origin, ray.direction);
    auto isKept = [&](double t) {
        for (const RaySpan& k : kept)
            if (t >= k.from && t <= k.to) return true;
        return false;
    };
    QueryAnswer a;
    a.px = px;
    a.py = py;
    a.perspective = true;
    a.world = glm::dvec3(std::numeric_limits<double>::quiet_NaN());
    double hitT = std::numeric_limits<double>::infinity();
    if (!kept.empty()) {
        auto rays = model.rays->wait(wait.deadline, wait.cancel);
        if (!rays) return rays.error();
        auto hole = rays.value().tracer->traceRay(ray.origin, ray.direction);
        if (hole) {
            bool cap = false;
            // Body intervals are disjoint and in order: the first with a kept part holds the
            // nearest kept point of any body.
            for (const BoreholeInterval& iv : hole.value().intervals) {
                for (const RaySpan& k : kept) {
                    const double from = std::max(iv.from, k.from), to = std::min(iv.to, k.to);
                    if (from < to && from < hitT) {
                        hitT = from;
                        a.record = iv.record;
                        cap = from > iv.from;
                    }
                }
                if (std::isfinite(hitT)) break;
            }
            if (!cap)
                for (const BoreholeCrossing& c : hole.value().crossings)
                    if (c.depth < hitT && isKept(c.depth)) {
                        hitT = c.depth;
                        a.record = c.record;
                        break;
                    }
        }
    }
    if (std::isfinite(hitT)) a.world = ray.origin + hitT * ray.direction;
    if (std::isfinite(hitT)) a.cell = blockCellAt(model, a.record, a.world);
    a.distanceAlong =
        std::isfinite(hitT) ? glm::length(a.world - ray.origin) : std::numeric_limits<double>::quiet_NaN();
    if (cached && !cached->ids.empty()) {
        a.record = cached->ids[std::size_t(py) * std::size_t(cached->width) + std::size_t(px)];
        a.fromIdBuffer = true;
    }
    return a;
}

}  // namespace

Result<QueryAnswer> answerPixel(const CatalogModel& model, const ViewPlan& plan, long long px, long long py,
                                const ViewImage* cached, const RayWait& wait) {
    if (px < 0 || py < 0 || px >= plan.width || py >= plan.height)
        return makeError(ErrorCode::OutOfRange, "parameters 'px', 'py': pixel (" + std::to_string(px) + ", " +
                                                    std::to_string(py) + ") is outside the " +
                                                    std::to_string(plan.width) + "x" + std::to_string(plan.height) +
                                                    " image");
    if (plan.view == ViewKind::Perspective) return answerPerspective(model, plan, px, py, cached, wait);
    std::optional<PixelMapping> fresh;
    const PixelMapping* mapping = cached && cached->mapping ? &*cached->mapping : nullptr;
    if (!mapping) {
        auto m = profileMapping(model, plan);
        if (!m) return m.error();
        fresh = std::move(m.value());
        mapping = &*fresh;
    }
    QueryAnswer a;
    a.px = px;
    a.py = py;
    const int i = int(px), j = int(py);
    a.world = mapping->worldAt(i, j);
    a.section = mapping->sectionAt(i, j);
    a.line = mapping->geometry == Geometry::Line;
    a.distanceAlong = a.line ? a.section.x : a.section.x - mapping->rect.u0;
    if (cached && !cached->ids.empty()) {
        const std::size_t p = std::size_t(j) * std::size_t(cached->width) + std::size_t(i);
        a.record = cached->ids[p];
        a.fromIdBuffer = true;
        if (!cached->cells.empty()) {
            a.cell = cached->cells[p] == 0 ? BlockModel::kNoCell : std::size_t(cached->cells[p] - 1);
            return a;
        }
    } else if (a.line && !(a.section.x >= 0.0 && a.section.x < mapping->line.length())) {
        // Like the polyline fill: nothing before the first vertex or past the last one.
        a.record = kNoRecord;
    } else {
        auto rays = model.rays->wait(wait.deadline, wait.cancel);
        if (!rays) return rays.error();
        a.record = rays.value().classifier->classify(a.world);
    }
    a.cell = blockCellAt(model, a.record, a.world);
    return a;
}

// A world point in every coordinate system the model's CRS leads to (README "Query answer
// coordinates"): the world frame, the projected CRS, lon/lat on the CRS's own datum, and
// WGS 84 through the transformation chosen for the model at load (CatalogModel::toWgs84).
void writeWorldPoint(JsonWriter& w, const CatalogModel& model, const glm::dvec3& world) {
    const Crs& crs = model.model.crs;
    w.beginObject();
    w.key("x").value(world.x).key("y").value(world.y).key("z").value(world.z);
    w.key("crs").value(crs.id());
    if (crs.isGeographic())
        w.key("axes")
            .beginArray()
            .value("x: lon (degrees)")
            .value("y: lat (degrees)")
            .value("z: height (m)")
            .endArray();
    else
        w.key("axes")
            .beginArray()
            .value("x: easting (m)")
            .value("y: northing (m)")
            .value("z: elevation (m)")
            .endArray();
    if (crs.isProjected()) {
        w.key("projected").beginObject();
        w.key("crs").value(crs.id()).key("name").value(crs.name());
        w.key("easting").value(world.x).key("northing").value(world.y);
        if (crs.isGaussKruger()) {
            w.key("zone").value(crs.zone()).key("zoneWidthDeg").value(crs.zoneWidthDeg());
            w.key("centralMeridianDeg").value(crs.centralMeridianDeg());
            w.key("axisOrder").value("easting, northing (metres); EPSG lists northing first");
        } else {
            w.key("axisOrder").value("easting, northing (metres), whatever order EPSG lists");
        }
        w.endObject();
        if (auto ll = crs.toLonLat(world.x, world.y)) {
            w.key("geodetic").beginObject();
            w.key("crs").value(crs.geographicId()).key("name").value(crs.geographicName());
            w.key("lon").value(ll.value().x).key("lat").value(ll.value().y);
            w.key("height").value(world.z);
            w.key("axisOrder").value("lon, lat (degrees), height (m); EPSG lists lat first");
            w.key("heightNote")
                .value("the model's elevation, reported as ellipsoidal height: no geoid model is configured");
            w.endObject();
        }
    } else if (crs.isGeographic()) {
        w.key("geodetic").beginObject();
        w.key("crs").value(crs.id()).key("name").value(crs.name());
        w.key("lon").value(world.x).key("lat").value(world.y).key("height").value(world.z);
        w.endObject();
    } else {
        w.key("projectedNote").value("the model has a local CRS: no projected or geodetic coordinates");
    }
    if (!crs.isLocal()) {
        Result<glm::dvec3> g = makeError(ErrorCode::NotFound, model.wgs84Note);
        if (model.toWgs84) g = model.toWgs84->apply(world);
        if (g) {
            w.key("wgs84").beginObject();
            w.key("crs").value("EPSG:4326").key("lon").value(g.value().x).key("lat").value(g.value().y);
            w.key("height").value(world.z);
            w.key("operation").value(model.toWgs84->operationName());
            if (model.toWgs84->accuracyM() >= 0.0)
                w.key("accuracyM").value(model.toWgs84->accuracyM());
            else
                w.key("accuracyM").null().key("accuracyNote").value("PROJ states no accuracy for this operation");
            w.key("axisOrder").value("lon, lat (degrees), height (m)");
            w.key("heightNote").value("the model's elevation, not transformed");
            w.endObject();
        } else {
            w.key("wgs84Note").value(g.error().message);
        }
    }
    w.endObject();
}

// "block": the cell's index and every property there, or null with why.
void writeBlockAnswer(JsonWriter& w, const BlockModel& blocks, std::size_t cell) {
    if (cell == BlockModel::kNoCell) {
        w.key("block")
            .null()
            .key("blockNote")
            .value("no block cell here: outside the block model's grid or outside the bodies that clip it");
        return;
    }
    const auto ijk = blocks.ijk(cell);
    w.key("block").beginObject();
    w.key("cell").beginArray().value((long long)ijk[0]).value((long long)ijk[1]).value((long long)ijk[2]).endArray();
    w.key("properties").beginObject();
    for (const BlockProperty& p : blocks.properties) {
        w.key(p.name).value(p.values[cell]);  // NaN (no value) is written as null
    }
    w.endObject();
    w.key("units").beginObject();
    for (const BlockProperty& p : blocks.properties) w.key(p.name).value(p.unit);
    w.endObject();
    w.endObject();
}

void writeQueryAnswer(const CatalogModel& model, const QueryAnswer& a, std::string& out) {
    JsonWriter w(out);
    w.beginObject();
    w.key("model").value(model.id).key("version").value(model.version);
    w.key("pixel").beginObject().key("x").value(a.px).key("y").value(a.py);
    w.key("centre").beginArray().value(double(a.px) + 0.5).value(double(a.py) + 0.5).endArray().endObject();
    w.key("hit").value(a.record != kNoRecord);
    if (a.record != kNoRecord) {
        const auto it = model.recordJson.find(a.record);
        if (it != model.recordJson.end())
            w.key("record").raw(it->second);
        else
            w.key("record").beginObject().key("id").value(static_cast<long long>(a.record)).endObject();
        if (const auto b = model.bodyName.find(a.record); b != model.bodyName.end()) w.key("body").value(b->second);
    } else {
        w.key("record").null().key("message").value("no geology at this pixel");
    }
    if (model.model.blocks) writeBlockAnswer(w, *model.model.blocks, a.cell);
    if (a.perspective) {
        w.key("distanceFromEye").value(a.distanceAlong);
        if (std::isfinite(a.world.x)) {
            w.key("world");
            writeWorldPoint(w, model, a.world);
        } else {
            w.key("world").null();
        }
        w.key("source").value(a.fromIdBuffer ? "id-buffer" : "ray");
        w.endObject();
        return;
    }
    w.key("section").beginObject();
    if (a.line) {
        w.key("distanceAlong").value(a.section.x).key("elevation").value(a.section.y);
        w.key("note").value("distanceAlong: metres of chainage from the line's first vertex");
    } else {
        w.key("u").value(a.section.x).key("v").value(a.section.y).key("distanceAlong").value(a.distanceAlong);
        w.key("note").value("u, v: plane metres; distanceAlong: metres along u from the image's left edge");
    }
    w.endObject();
    w.key("world");
    writeWorldPoint(w, model, a.world);
    w.key("source").value(a.fromIdBuffer ? "id-buffer" : "ray");
    w.endObject();
}

Result<std::string> queryPixel(const CatalogModel& model, const ViewPlan& plan, long long px, long long py,
                               const ViewImage* cached, const RayWait& wait) {
    auto a = answerPixel(model, plan, px, py, cached, wait);
    if (!a) return a.error();
    std::string out;
    out.reserve(1536);
    writeQueryAnswer(model, a.value(), out);
    return out;
}

nlohmann::ordered_json worldPointJson(const CatalogModel& model, const glm::dvec3& world) {
    std::string s;
    JsonWriter w(s);
    writeWorldPoint(w, model, world);
    return nlohmann::ordered_json::parse(s);
}

Result<nlohmann::ordered_json> boreholeAt(const CatalogModel& model, const Params& params, const RayWait& wait) {
    double x = 0.0, y = 0.0;
    if (param(params, "lon") || param(params, "lat")) {
        const auto lon = param(params, "lon"), lat = param(params, "lat");
        if (!lon || !lat) return makeError(ErrorCode::InvalidArgument, "borehole: give both 'lon' and 'lat'");
        auto lo = parseNumber("lon", *lon);
        if (!lo) return lo.error();
        auto la = parseNumber("lat", *lat);
        if (!la) return la.error();
        if (!model.model.crs.isProjected())
            return makeError(ErrorCode::InvalidArgument,
                             "borehole: lon/lat needs a model in a projected CRS; "
                             "this model is " +
                                 model.model.crs.id());
        auto xy = model.model.crs.fromLonLat(lo.value(), la.value());
        if (!xy) return xy.error();
        x = xy.value().x;
        y = xy.value().y;
    } else {
        const auto xs = param(params, "x"), ys = param(params, "y");
        if (!xs || !ys) return makeError(ErrorCode::InvalidArgument, "borehole: give 'x' and 'y' (or 'lon' and 'lat')");
        auto xv = parseNumber("x", *xs);
        if (!xv) return xv.error();
        auto yv = parseNumber("y", *ys);
        if (!yv) return yv.error();
        x = xv.value();
        y = yv.value();
    }
    auto rays = model.rays->wait(wait.deadline, wait.cancel);
    if (!rays) return rays.error();
    auto hole = rays.value().tracer->traceVertical(x, y);
    if (!hole) return hole.error();
    const Borehole& b = hole.value();
    nlohmann::ordered_json out;
    out["model"] = model.id;
    out["version"] = model.version;
    out.update(boreholeJson(model.model, b));
    // The collar in every coordinate system too, like every point the API reports.
    out["collarCoordinates"] =
        std::isnan(b.collarDepth) ? nlohmann::ordered_json(nullptr) : worldPointJson(model, b.collar);
    return out;
}

}  // namespace geoslice::api
