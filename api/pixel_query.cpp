#include "api/pixel_query.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "api/json_writer.hpp"

namespace geoslice::api {

Status checkPerspectiveCut(const CatalogModel& model, const ViewPlan& plan) {
    const CutOut cut = sectionCut(plan.section);
    const char* name = cut.planes.size() > 1                          ? "planes"
                       : plan.section.geometry == Geometry::Elevation ? "elevation"
                                                                      : "plane";
    return checkCutKeepsSomething(name, cut, model.index->bounds);
}

Status checkShownUnits(const CatalogModel& model, const ViewPlan& plan) {
    if (plan.shown.records.empty()) return {};
    std::vector<RecordId> all;
    for (const auto* parts : {&model.model.bodies, &model.model.surfaces})
        for (const Part& p : *parts) all.push_back(p.record);
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    for (RecordId r : plan.shown.records)
        if (!std::binary_search(all.begin(), all.end(), r)) {
            std::string list;
            for (std::size_t i = 0; i < all.size() && i < 64; ++i) list += (i ? "," : "") + std::to_string(all[i]);
            return makeError(ErrorCode::InvalidArgument,
                             std::string("parameter '") + (plan.shown.isolate ? "isolate" : "hide") + "': record " +
                                 std::to_string(r) + " is not in the model (its records: " + list +
                                 (all.size() > 64 ? ",..." : "") + ")");
        }
    return {};
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
    if (auto s = checkShownUnits(model, plan); !s) return s.error();
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
    bool cap = false;  // the hit is on a cut face: the kept part starts inside the body
    // Units left out (hide= / isolate=): the picture of the model without them, as the
    // renderer draws it. A hidden body's interval is its nearest shown container's (the
    // container is whole without it) or nothing; a hidden surface is not crossed.
    const std::vector<RecordId> hidden = plan.shown.hiddenOf(model.model);
    auto isHidden = [&](RecordId r) { return std::binary_search(hidden.begin(), hidden.end(), r); };
    auto shownRecord = [&](const BoreholeInterval& iv) -> RecordId {
        if (!isHidden(iv.record)) return iv.record;
        for (int b = model.model.bodies[iv.body].report.parent; b >= 0;
             b = model.model.bodies[std::size_t(b)].report.parent)
            if (!isHidden(model.model.bodies[std::size_t(b)].record)) return model.model.bodies[std::size_t(b)].record;
        return kNoRecord;
    };
    if (!kept.empty()) {
        auto rays = model.rays->wait(wait.deadline, wait.cancel);
        if (!rays) return rays.error();
        auto hole = rays.value().tracer->traceRay(ray.origin, ray.direction);
        if (hole) {
            // Body intervals are disjoint and in order: the first with a kept part holds the
            // nearest kept point of any body.
            // With a body hidden, neighbouring intervals can become one unit: a shown interval
            // starts where the previous one of another record (or none) ended.
            RecordId before = kNoRecord;
            double beforeEnd = -std::numeric_limits<double>::infinity();
            for (const BoreholeInterval& iv : hole.value().intervals) {
                const RecordId r = shownRecord(iv);
                const bool continues = r != kNoRecord && r == before && iv.from <= beforeEnd + 1e-9;
                before = r;
                beforeEnd = iv.to;
                if (r == kNoRecord) continue;
                for (const RaySpan& k : kept) {
                    const double from = std::max(iv.from, k.from), to = std::min(iv.to, k.to);
                    if (from < to && from < hitT) {
                        hitT = from;
                        a.record = r;
                        cap = from > iv.from || continues;
                    }
                }
                if (std::isfinite(hitT)) break;
            }
            if (!cap)
                for (const BoreholeCrossing& c : hole.value().crossings)
                    if (c.depth < hitT && isKept(c.depth) && !isHidden(c.record)) {
                        hitT = c.depth;
                        a.record = c.record;
                        break;
                    }
        }
    }
    if (std::isfinite(hitT)) a.world = ray.origin + hitT * ray.direction;
    // The block cell on a cap only (the cut face, where the view colours by cell); an uncut
    // exterior face keeps the body's colour in the image and has no cell in the answer.
    if (std::isfinite(hitT) && cap) a.cell = blockCellAt(model, a.record, a.world);
    a.distanceAlong =
        std::isfinite(hitT) ? glm::length(a.world - ray.origin) : std::numeric_limits<double>::quiet_NaN();
    if (cached && !cached->ids.empty()) {
        const std::size_t p = std::size_t(py) * std::size_t(cached->width) + std::size_t(px);
        a.record = cached->ids[p];
        a.fromIdBuffer = true;
        // A coloured view's cells buffer (the GL cell attachment) is the cell the image used.
        if (!cached->cells.empty())
            a.cell = cached->cells[p] == 0 ? BlockModel::kNoCell : std::size_t(cached->cells[p] - 1);
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
    if (model.holeIndex && plan.section.holes.window > 0.0) {
        auto holes = viewHoles(model, plan.section, *mapping);
        if (!holes) return holes.error();
        a.hole = holeNearPixel(model, holes.value(), *mapping, double(i) + 0.5, double(j) + 0.5);
    }
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
void writeBlockAnswer(JsonWriter& w, const BlockModel& blocks, std::size_t cell, bool perspective) {
    if (cell == BlockModel::kNoCell) {
        w.key("block").null().key("blockNote");
        if (perspective)
            w.value(
                "no block cell here: not on a cut face (perspective views colour cut faces only), outside the block "
                "model's grid or outside the bodies that clip it");
        else
            w.value("no block cell here: outside the block model's grid or outside the bodies that clip it");
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
    if (model.model.blocks) writeBlockAnswer(w, *model.model.blocks, a.cell, a.perspective);
    if (a.hole) writeHoleHit(w, model, *a.hole);
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

Result<std::string> answerBatch(const CatalogModel& model, const ViewPlan& plan, const std::vector<PixelXY>& pixels,
                                const ViewImage* cached, const RayWait& wait, const std::atomic<bool>* cancel,
                                const std::string& batchName, const std::function<std::string(std::size_t)>& nameOf) {
    std::string out = "{\"results\":[";
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        if ((i & 63) == 0)
            if (auto c = checkCancel(cancel); !c) return c.error();
        auto a = answerPixel(model, plan, pixels[i].x, pixels[i].y, cached, wait);
        if (!a) return makeError(a.error().code, nameOf(i) + ": " + a.error().message);
        if (i) out += ',';
        writeQueryAnswer(model, a.value(), out);
        if (out.size() > kMaxBatchAnswerBytes)
            return makeError(ErrorCode::OutOfRange, batchName + ": the answer passed " +
                                                        std::to_string(kMaxBatchAnswerBytes >> 20) + " MiB after " +
                                                        std::to_string(i + 1) + " pixels; ask for fewer pixels");
    }
    out += "]}";
    return out;
}

nlohmann::ordered_json worldPointJson(const CatalogModel& model, const glm::dvec3& world) {
    std::string s;
    JsonWriter w(s);
    writeWorldPoint(w, model, world);
    return nlohmann::ordered_json::parse(s);
}

}  // namespace geoslice::api
