// Conversions between CRSs: a projected CRS to and from lon/lat on its datum, one point
// from any CRS to any other (CGCS2000 pairs through GeographicLib, the rest through PROJ's
// proj_create_crs_to_crs), PROJ's candidate operations and one operation chosen for an area
// (CrsTransform). PROJ contexts come from model/crs/proj_pool.hpp.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <proj.h>

#include "model/crs/crs.hpp"
#include "model/crs/crs_proj.hpp"
#include "model/crs/proj_pool.hpp"

namespace geoslice {

using crs_detail::cstr;
using crs_detail::num;
using crs_detail::PjListPtr;
using crs_detail::PjPtr;
using crs_detail::shortId;

namespace {

Error notProjected(const Crs& crs, const char* what) {
    return makeError(ErrorCode::InvalidArgument, std::string(what) + " needs a projected CRS, got " + crs.id());
}

const std::string& defOf(const Crs& c) { return c.projInfo()->def; }
std::uint32_t defIdOf(const Crs& c) { return c.projInfo()->defId; }

// proj_create_crs_to_crs(a, b), normalised to easting/northing and lon/lat order, cached
// in the slot.
PJ* crsToCrs(proj::Slot& slot, const std::string& a, std::uint32_t aId, const std::string& b, std::uint32_t bId) {
    return slot.get(proj::key(proj::ObjectKind::CrsToCrs, aId, bId), [&](PJ_CONTEXT* ctx) -> PJ* {
        PjPtr raw(proj_create_crs_to_crs(ctx, a.c_str(), b.c_str(), nullptr));
        if (!raw) return nullptr;
        return proj_normalize_for_visualization(ctx, raw.get());
    });
}

Result<glm::dvec3> transformPoint(proj::Slot& slot, PJ* op, PJ_DIRECTION dir, const glm::dvec3& p,
                                  const std::function<std::string()>& where) {
    proj_errno_reset(op);
    const PJ_COORD r = proj_trans(op, dir, proj_coord(p.x, p.y, p.z, HUGE_VAL));
    if (!std::isfinite(r.xyz.x) || !std::isfinite(r.xyz.y) || std::fabs(r.xyz.x) >= HUGE_VAL / 2) {
        const int e = proj_errno(op);
        std::string why = e ? cstr(proj_context_errno_string(slot.ctx(), e)) : std::string("no result");
        proj_errno_reset(op);
        return makeError(ErrorCode::OutOfRange, where() + ": PROJ: " + why);
    }
    return glm::dvec3(r.xyz.x, r.xyz.y, r.xyz.z);
}

std::string pointText(const glm::dvec3& p) { return "(" + num(p.x) + ", " + num(p.y) + ")"; }

}  // namespace

namespace crs_detail {

std::string shortId(const Crs& c) {
    std::string s = c.id();
    return s.size() > 60 ? c.name() : s;
}

}  // namespace crs_detail

Result<glm::dvec2> Crs::toLonLat(double easting, double northing) const {
    if (!isProjected()) return notProjected(*this, "toLonLat");
    if (kind_ == Kind::GaussKruger) return crs_detail::gkToLonLat(*this, easting, northing);
    const glm::dvec3 p(easting, northing, 0.0);
    if (!std::isfinite(easting) || !std::isfinite(northing))
        return makeError(ErrorCode::InvalidArgument, shortId(*this) + " " + pointText(p) + ": not a finite number");
    proj::Lease slot;
    PJ* op = crsToCrs(*slot, proj_->def, proj_->defId, proj_->geoDef, proj_->geoDefId);
    if (!op) return makeError(ErrorCode::Internal, shortId(*this) + " to lon/lat: PROJ: " + slot->lastError());
    auto r = transformPoint(*slot, op, PJ_FWD, p, [&] { return shortId(*this) + " " + pointText(p) + " to lon/lat"; });
    if (!r) return r.error();
    return glm::dvec2(r->x, r->y);
}

Result<glm::dvec2> Crs::fromLonLat(double lonDeg, double latDeg) const {
    if (!isProjected()) return notProjected(*this, "fromLonLat");
    if (kind_ == Kind::GaussKruger) return crs_detail::gkFromLonLat(*this, lonDeg, latDeg);
    const glm::dvec3 p(lonDeg, latDeg, 0.0);
    if (!std::isfinite(lonDeg) || !std::isfinite(latDeg))
        return makeError(ErrorCode::InvalidArgument,
                         shortId(*this) + " from lon/lat " + pointText(p) + ": not a finite number");
    if (std::fabs(latDeg) > 90.0)
        return makeError(ErrorCode::OutOfRange,
                         shortId(*this) + " from lon/lat " + pointText(p) + ": latitude beyond +-90 degrees");
    proj::Lease slot;
    PJ* op = crsToCrs(*slot, proj_->def, proj_->defId, proj_->geoDef, proj_->geoDefId);
    if (!op) return makeError(ErrorCode::Internal, shortId(*this) + " from lon/lat: PROJ: " + slot->lastError());
    auto r = transformPoint(*slot, op, PJ_INV, p, [&] { return shortId(*this) + " from lon/lat " + pointText(p); });
    if (!r) return r.error();
    return glm::dvec2(r->x, r->y);
}

namespace {

// The CGCS2000-only path (GeographicLib), unchanged from before PROJ was added.
Result<glm::dvec3> convertCgcs2000(const Crs& from, const Crs& to, const glm::dvec3& p) {
    if (from == to) {
        if (from.isGeographic() && std::fabs(p.y) > 90.0) {
            return makeError(ErrorCode::OutOfRange, "convert " + from.id() + " -> " + to.id() + ": latitude " +
                                                        num(p.y) + " beyond +-90 degrees");
        }
        return p;
    }
    // Through geographic lon/lat (degrees); heights are ellipsoidal and unchanged.
    glm::dvec2 lonLat(p.x, p.y);
    if (from.isProjected()) {
        auto ll = from.toLonLat(p.x, p.y);
        if (!ll) return ll.error();
        lonLat = ll.value();
    } else if (std::fabs(p.y) > 90.0) {
        return makeError(ErrorCode::OutOfRange,
                         "convert " + from.id() + " -> " + to.id() + ": latitude " + num(p.y) + " beyond +-90 degrees");
    }
    if (to.isGeographic()) return glm::dvec3(lonLat, p.z);
    auto en = to.fromLonLat(lonLat.x, lonLat.y);
    if (!en) {
        Error e = en.error();
        if (from.isProjected()) e.message = "from " + from.id() + " (" + num(p.x) + ", " + num(p.y) + "): " + e.message;
        return e;
    }
    return glm::dvec3(en.value(), p.z);
}

std::string areaText(const LonLatBox& a) {
    return "lon " + num(a.west) + ".." + num(a.east) + ", lat " + num(a.south) + ".." + num(a.north);
}

// Where `p` (in `from`) lies outside either CRS's area of use: a sentence, else "".
std::string areaWarning(const Crs& from, const Crs& to, const glm::dvec3& p) {
    glm::dvec2 ll(p.x, p.y);
    if (from.isProjected()) {
        auto r = from.toLonLat(p.x, p.y);
        if (!r) return {};
        ll = r.value();
    }
    std::string out;
    for (const Crs* c : {&from, &to}) {
        const auto area = c->areaOfUse();
        if (!area || area->contains(ll.x, ll.y)) continue;
        if (c == &to && to == from) continue;
        if (!out.empty()) out += "; ";
        out += "lon/lat (" + num(ll.x) + ", " + num(ll.y) + ") lies outside the area of use of " + shortId(*c) + " (" +
               c->name() + ": " + areaText(*area) + ")";
    }
    return out;
}

}  // namespace

Result<glm::dvec3> convertPoint(const Crs& from, const Crs& to, const glm::dvec3& p, std::string* warning) {
    if (from.isLocal() || to.isLocal()) {
        if (from.isLocal() && to.isLocal()) return p;
        return makeError(ErrorCode::InvalidArgument, "cannot convert between " + shortId(from) + " and " + shortId(to) +
                                                         ": a local CRS has no georeference");
    }
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        return makeError(ErrorCode::InvalidArgument, "convert " + shortId(from) + " -> " + shortId(to) + ": point (" +
                                                         num(p.x) + ", " + num(p.y) + ", " + num(p.z) +
                                                         ") is not finite");
    }
    if (from.isGeographic() && std::fabs(p.y) > 90.0)
        return makeError(ErrorCode::OutOfRange, "convert " + shortId(from) + " -> " + shortId(to) + ": latitude " +
                                                    num(p.y) + " beyond +-90 degrees");
    Result<glm::dvec3> out = glm::dvec3(0.0);
    if (from.isCgcs2000() && to.isCgcs2000()) {
        out = convertCgcs2000(from, to, p);
    } else {
        proj::Lease slot;
        PJ* op = crsToCrs(*slot, defOf(from), defIdOf(from), defOf(to), defIdOf(to));
        if (!op)
            return makeError(ErrorCode::Unsupported, "no PROJ transformation from " + shortId(from) + " to " +
                                                         shortId(to) + ": " + slot->lastError());
        out = transformPoint(*slot, op, PJ_FWD, p,
                             [&] { return "convert " + shortId(from) + " -> " + shortId(to) + " " + pointText(p); });
    }
    if (warning) *warning = out ? areaWarning(from, to, p) : std::string();
    return out;
}

namespace {

struct FactoryDeleter {
    PJ_CONTEXT* ctx;
    void operator()(PJ_OPERATION_FACTORY_CONTEXT* f) const { proj_operation_factory_context_destroy(f); }
};

// PROJ's candidate operations from -> to (instantiable with the installed grids), best
// first, over `area` when given (strict containment) else over the CRSs' extents.
Result<std::vector<PjPtr>> candidateOperations(proj::Slot& slot, const Crs& from, const Crs& to,
                                               const std::optional<LonLatBox>& area) {
    PJ_CONTEXT* ctx = slot.ctx();
    PjPtr src(proj_create(ctx, defOf(from).c_str())), dst(proj_create(ctx, defOf(to).c_str()));
    if (!src || !dst) return makeError(ErrorCode::Internal, "PROJ: " + slot.lastError());
    std::unique_ptr<PJ_OPERATION_FACTORY_CONTEXT, FactoryDeleter> factory(
        proj_create_operation_factory_context(ctx, nullptr), FactoryDeleter{ctx});
    if (!factory) return makeError(ErrorCode::Internal, "PROJ: " + slot.lastError());
    if (area) {
        proj_operation_factory_context_set_area_of_interest(ctx, factory.get(), area->west, area->south, area->east,
                                                            area->north);
        proj_operation_factory_context_set_spatial_criterion(ctx, factory.get(),
                                                             PROJ_SPATIAL_CRITERION_STRICT_CONTAINMENT);
    } else {
        proj_operation_factory_context_set_spatial_criterion(ctx, factory.get(),
                                                             PROJ_SPATIAL_CRITERION_PARTIAL_INTERSECTION);
    }
    proj_operation_factory_context_set_grid_availability_use(ctx, factory.get(),
                                                             PROJ_GRID_AVAILABILITY_DISCARD_OPERATION_IF_MISSING_GRID);
    PjListPtr list(proj_create_operations(ctx, src.get(), dst.get(), factory.get()));
    std::vector<PjPtr> out;
    if (!list) return out;
    const int n = proj_list_get_count(list.get());
    for (int i = 0; i < n; ++i) {
        PjPtr op(proj_list_get(ctx, list.get(), i));
        if (op && proj_coordoperation_is_instantiable(ctx, op.get())) out.push_back(std::move(op));
    }
    return out;
}

// As proj_trans picks among proj_create_crs_to_crs's candidates for a point: the smallest
// stated accuracy wins, an unknown accuracy loses to any known one, ties keep PROJ's order.
std::size_t bestCandidate(proj::Slot& slot, const std::vector<PjPtr>& ops) {
    std::size_t best = 0;
    double bestAcc = -1.0;
    for (std::size_t i = 0; i < ops.size(); ++i) {
        const double acc = proj_coordoperation_get_accuracy(slot.ctx(), ops[i].get());
        if (acc >= 0.0 && (bestAcc < 0.0 || acc < bestAcc)) {
            best = i;
            bestAcc = acc;
        }
    }
    return best;
}

}  // namespace

Result<OperationSummary> summariseOperations(const Crs& from, const Crs& to) {
    OperationSummary s;
    if (from.isLocal() || to.isLocal())
        return makeError(ErrorCode::InvalidArgument, "no operations between a local CRS and another");
    s.identity = from.geographicId() == to.geographicId();
    proj::Lease slot;
    auto ops = candidateOperations(*slot, from, to, std::nullopt);
    if (!ops) return ops.error();
    if (ops->empty()) return s;
    const std::size_t best = bestCandidate(*slot, ops.value());
    s.bestName = cstr(proj_get_name(ops.value()[best].get()));
    s.bestAccuracyM = proj_coordoperation_get_accuracy(slot->ctx(), ops.value()[best].get());
    s.onlyBallpark = true;
    for (const auto& op : ops.value())
        if (!proj_coordoperation_has_ballpark_transformation(slot->ctx(), op.get())) s.onlyBallpark = false;
    if (s.identity) s.onlyBallpark = false;
    return s;
}

Result<CrsTransform> CrsTransform::forArea(const Crs& from, const Crs& to, const LonLatBox& area) {
    if (from.isLocal() || to.isLocal())
        return makeError(ErrorCode::InvalidArgument, "no transformation between a local CRS and another");
    proj::Lease slot;
    auto ops = candidateOperations(*slot, from, to, area);
    if (!ops) return ops.error();
    if (ops->empty())
        return makeError(ErrorCode::NotFound, "PROJ has no usable operation from " + shortId(from) + " to " +
                                                  shortId(to) + " over " + areaText(area));
    PJ* op = ops.value()[bestCandidate(*slot, ops.value())].get();
    CrsTransform t;
    t.from_ = from;
    t.to_ = to;
    t.name_ = cstr(proj_get_name(op));
    t.accuracyM_ = proj_coordoperation_get_accuracy(slot->ctx(), op);
    t.ballpark_ = proj_coordoperation_has_ballpark_transformation(slot->ctx(), op) != 0;
    PjPtr normalised(proj_normalize_for_visualization(slot->ctx(), op));
    if (!normalised) return makeError(ErrorCode::Internal, "PROJ: " + slot->lastError());
    t.pipeline_ = cstr(proj_as_proj_string(slot->ctx(), normalised.get(), PJ_PROJ_5, nullptr));
    if (t.pipeline_.empty()) t.pipeline_ = cstr(proj_as_projjson(slot->ctx(), normalised.get(), nullptr));
    if (t.pipeline_.empty()) return makeError(ErrorCode::Internal, "PROJ cannot write operation " + t.name_);
    t.pipelineId_ = proj::intern(t.pipeline_);
    return t;
}

Result<glm::dvec3> CrsTransform::apply(const glm::dvec3& p) const {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return makeError(ErrorCode::InvalidArgument, name_ + ": point " + pointText(p) + " is not finite");
    proj::Lease slot;
    PJ* op = slot->get(proj::key(proj::ObjectKind::Pipeline, pipelineId_),
                       [&](PJ_CONTEXT* ctx) { return proj_create(ctx, pipeline_.c_str()); });
    if (!op) return makeError(ErrorCode::Internal, name_ + ": PROJ: " + slot->lastError());
    return transformPoint(*slot, op, PJ_FWD, p, [&] { return name_ + " " + pointText(p); });
}

bool crsNetworkAccessEnabled() { return proj::networkEnabled(); }

Result<LonLatBox> lonLatBoxOf(const Crs& crs, const glm::dvec2& min, const glm::dvec2& max) {
    if (crs.isLocal()) return makeError(ErrorCode::InvalidArgument, "a local CRS has no lon/lat");
    LonLatBox box{1e9, 1e9, -1e9, -1e9};
    auto add = [&](const glm::dvec2& p) -> Status {
        glm::dvec2 ll = p;
        if (crs.isProjected()) {
            auto r = crs.toLonLat(p.x, p.y);
            if (!r) return r.error();
            ll = r.value();
        }
        box.west = std::min(box.west, ll.x);
        box.east = std::max(box.east, ll.x);
        box.south = std::min(box.south, ll.y);
        box.north = std::max(box.north, ll.y);
        return {};
    };
    // The extent's four edges, each densified: a projected grid's straight edge is curved in
    // lon/lat, and its extreme latitude or longitude can lie between the corners.
    const glm::dvec2 corners[4] = {min, {max.x, min.y}, max, {min.x, max.y}};
    for (int e = 0; e < 4; ++e) {
        const glm::dvec2 a = corners[e], b = corners[(e + 1) % 4];
        for (int k = 0; k < kLonLatEdgeSteps; ++k)
            if (Status s = add(a + (b - a) * (double(k) / kLonLatEdgeSteps)); !s) return s.error();
    }
    return box;
}

}  // namespace geoslice
