#include "api/plan.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>

#include "section/blocks/block_section.hpp"

namespace geoslice::api {
namespace {

std::string join(const double* v, std::size_t n) {
    std::string out;
    for (std::size_t i = 0; i < n; ++i) {
        if (i) out += ',';
        out += formatNumber(v[i]);
    }
    return out;
}

std::string colourHex(Rgba8 c) {
    static const char* digits = "0123456789abcdef";
    std::string s;
    for (std::uint8_t b : {c.r, c.g, c.b, c.a}) {
        s += digits[b >> 4];
        s += digits[b & 15];
    }
    return s;
}

Result<glm::dvec3> parseVec3(const Params& params, std::string_view name, glm::dvec3 fallback) {
    const auto text = param(params, name);
    if (!text) return fallback;
    auto v = parseNumberList(name, *text, 3);
    if (!v) return v.error();
    return glm::dvec3(v.value()[0], v.value()[1], v.value()[2]);
}

}  // namespace

std::string SectionDef::canonical() const {
    std::string s = "model=" + model;
    switch (geometry) {
        case Geometry::Plane: {
            if (cutPlanes.empty()) {
                s += "&plane=" + planeText(plane);
                break;
            }
            s += "&planes=";
            for (std::size_t i = 0; i < cutPlanes.size(); ++i) s += (i ? ";" : "") + planeText(cutPlanes[i]);
            s += std::string("&cut=") + cutModeName(cut);
            break;
        }
        case Geometry::Line: {
            std::vector<double> v;
            for (const auto& p : line) {
                v.push_back(p.x);
                v.push_back(p.y);
            }
            s += "&line=" + join(v.data(), v.size());
            break;
        }
        case Geometry::Elevation:
            s += "&elevation=" + formatNumber(elevation);
            break;
    }
    s += "&vx=" + formatNumber(exaggeration);
    s += "&bg=" + colourHex(background);
    if (colour) {
        s += "&colour=" + colour->property + "&ramp=" + colour->ramp;
        if (colour->breaks) s += "&breaks=" + join(colour->breaks->data(), colour->breaks->size());
    }
    if (holes.window != kDefaultHoleWindow) s += "&holes=" + formatNumber(holes.window);
    if (!holes.column.empty()) {
        s += "&holecolour=" + holes.column + "&holeramp=" + holes.ramp;
        if (holes.breaks) s += "&holebreaks=" + join(holes.breaks->data(), holes.breaks->size());
    }
    return s;
}

std::string ViewPlan::canonical() const {
    std::string s = section.canonical();
    if (view == ViewKind::Profile) {
        s += "&view=profile";
        if (frame) {
            const double v[4] = {frame->u0, frame->u1, frame->v0, frame->v1};
            s += "&frame=" + join(v, 4);
        }
    } else {
        s += "&view=perspective";
        if (camera) {
            const double v[10] = {camera->eye.x,    camera->eye.y,      camera->eye.z, camera->target.x,
                                  camera->target.y, camera->target.z,   camera->up.x,  camera->up.y,
                                  camera->up.z,     camera->fovYDegrees};
            s += "&camera=" + join(v, 10);
        }
    }
    s += "&size=" + std::to_string(width) + "x" + std::to_string(height);
    if (!shown.records.empty()) {
        s += shown.isolate ? "&isolate=" : "&hide=";
        for (std::size_t i = 0; i < shown.records.size(); ++i) s += (i ? "," : "") + std::to_string(shown.records[i]);
    }
    if (labels) s += *labels ? "&labels=1" : "&labels=0";
    if (patterns) s += *patterns ? "&patterns=1" : "&patterns=0";
    return s;
}

const std::vector<std::string_view>& sectionParamNames() {
    static const std::vector<std::string_view> names{"plane",  "planes", "cut",        "line",       "elevation",
                                                     "coords", "vx",     "bg",         "colour",     "breaks",
                                                     "ramp",   "holes",  "holecolour", "holebreaks", "holeramp"};
    return names;
}

const std::vector<std::string_view>& viewParamNames() {
    static const std::vector<std::string_view> names = [] {
        std::vector<std::string_view> n = sectionParamNames();
        for (std::string_view v :
             {"view", "frame", "size", "eye", "target", "up", "fov", "labels", "patterns", "hide", "isolate"})
            n.push_back(v);
        return n;
    }();
    return names;
}

namespace {

Result<std::vector<double>> parseBreaks(std::string_view name, std::string_view text) {
    auto v = parseNumberList(name, text, 0, 64);
    if (!v) return v.error();
    if (v.value().empty())
        return makeError(ErrorCode::InvalidArgument, "parameter '" + std::string(name) + "': no numbers");
    for (std::size_t i = 1; i < v.value().size(); ++i)
        if (!(v.value()[i] > v.value()[i - 1]))
            return makeError(ErrorCode::InvalidArgument,
                             "parameter '" + std::string(name) + "': values must increase strictly");
    return v;
}

bool isColumnName(std::string_view s) {
    if (s.empty() || s.size() > 64) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) return false;
    return true;
}

}  // namespace

Result<HoleDrawing> parseHoleDrawing(const Params& params) {
    HoleDrawing h;
    if (const auto w = param(params, "holes")) {
        auto v = parseNumber("holes", *w);
        if (!v) return v.error();
        if (!(v.value() >= 0.0 && v.value() <= kMaxHoleWindow))
            return makeError(ErrorCode::OutOfRange, "parameter 'holes': " + std::string(w->substr(0, 64)) +
                                                        " is outside 0..100000 metres (0 draws no holes)");
        h.window = v.value();
    }
    // breaks= and ramp= belong to colour= when it is given, else to holecolour=.
    const bool shared = !param(params, "colour");
    const auto ramp = param(params, "holeramp") ? param(params, "holeramp")
                      : shared                  ? param(params, "ramp")
                                                : std::nullopt;
    const std::string_view rampName = param(params, "holeramp") ? "holeramp" : "ramp";
    const auto breaks = param(params, "holebreaks") ? param(params, "holebreaks")
                        : shared                    ? param(params, "breaks")
                                                    : std::nullopt;
    const std::string_view breaksName = param(params, "holebreaks") ? "holebreaks" : "breaks";
    if (const auto c = param(params, "holecolour")) {
        if (!isColumnName(*c))
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'holecolour': an interval column name of 1..64 characters A-Z a-z 0-9 _ . -");
        h.column = std::string(*c);
        if (ramp) {
            if (!isRampName(*ramp)) {
                std::string known;
                for (auto n : rampNames()) known += (known.empty() ? "" : ", ") + std::string(n);
                return makeError(ErrorCode::InvalidArgument, "parameter '" + std::string(rampName) + "': '" +
                                                                 std::string(ramp->substr(0, 64)) + "' is not one of " +
                                                                 known);
            }
            h.ramp = std::string(*ramp);
        }
        if (breaks) {
            auto v = parseBreaks(breaksName, *breaks);
            if (!v) return v.error();
            h.breaks = std::move(v.value());
        }
    } else if (param(params, "holebreaks") || param(params, "holeramp")) {
        return makeError(ErrorCode::InvalidArgument, "parameters 'holebreaks' and 'holeramp' need 'holecolour=COLUMN'");
    }
    return h;
}

Result<std::optional<BlockColouring>> parseBlockColouring(const Params& params) {
    if (const auto colour = param(params, "colour")) {
        BlockColouring bc;
        bc.property = std::string(*colour);
        const bool nameOk =
            !bc.property.empty() && bc.property.size() <= 64 &&
            std::all_of(bc.property.begin(), bc.property.end(), [](char ch) {
                return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-';
            });
        if (!nameOk)
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'colour': a block property name of 1..64 characters A-Z a-z 0-9 _ . -");
        if (const auto ramp = param(params, "ramp")) {
            if (!isRampName(*ramp)) {
                std::string known;
                for (auto n : rampNames()) known += (known.empty() ? "" : ", ") + std::string(n);
                return makeError(ErrorCode::InvalidArgument,
                                 "parameter 'ramp': '" + std::string(ramp->substr(0, 64)) + "' is not one of " + known);
            }
            bc.ramp = std::string(*ramp);
        }
        if (const auto breaks = param(params, "breaks")) {
            auto v = parseNumberList("breaks", *breaks, 0, 64);
            if (!v) return v.error();
            if (v.value().empty()) return makeError(ErrorCode::InvalidArgument, "parameter 'breaks': no numbers");
            for (std::size_t i = 1; i < v.value().size(); ++i)
                if (!(v.value()[i] > v.value()[i - 1]))
                    return makeError(ErrorCode::InvalidArgument, "parameter 'breaks': values must increase strictly");
            bc.breaks = std::move(v.value());
        }
        return std::optional<BlockColouring>(std::move(bc));
    }
    if ((param(params, "breaks") || param(params, "ramp")) && !param(params, "holecolour"))
        return makeError(ErrorCode::InvalidArgument,
                         "parameters 'breaks' and 'ramp' need 'colour=PROPERTY' (or 'holecolour=COLUMN')");
    return std::optional<BlockColouring>();
}

Result<SectionDef> parseSectionDef(const Params& params, const std::string& model, const Crs& crs) {
    SectionDef def;
    def.model = model;
    const auto plane = param(params, "plane") ? param(params, "plane") : param(params, "planes");
    const std::string_view planeName = param(params, "plane") ? "plane" : "planes";
    if (param(params, "plane") && param(params, "planes"))
        return makeError(ErrorCode::InvalidArgument,
                         "parameters 'plane' and 'planes': give the planes either as 'plane' (repeated) or as "
                         "'planes=a,b,c,d;a,b,c,d...', not both");
    const auto line = param(params, "line");
    const auto elevation = param(params, "elevation");
    const int given = int(bool(plane)) + int(bool(line)) + int(bool(elevation));
    if (given != 1)
        return makeError(ErrorCode::InvalidArgument,
                         given == 0 ? "no section geometry: give one of 'plane=a,b,c,d', 'line=x1,y1,x2,y2[,...]' or "
                                      "'elevation=z'"
                                    : "more than one section geometry: give only one of 'plane', 'line', 'elevation'");
    if (param(params, "cut") && !plane)
        return makeError(ErrorCode::InvalidArgument, "parameter 'cut': needs planes ('plane' or 'planes')");
    // 'coords' gives the units of 'line' only: checked here, whatever the geometry, so that a
    // request that cannot mean what it says is refused at once rather than ignored.
    const auto coords = param(params, "coords");
    if (coords && *coords != "world" && *coords != "lonlat")
        return makeError(ErrorCode::InvalidArgument,
                         "parameter 'coords': '" + std::string(coords->substr(0, 64)) + "' is not 'world' or 'lonlat'");
    if (coords && !line)
        return makeError(ErrorCode::InvalidArgument,
                         std::string("parameter 'coords': sets the units of 'line' only, and this request gives its "
                                     "section as '") +
                             (plane ? std::string(planeName) : std::string("elevation")) +
                             "' (always world coordinates, metres): leave 'coords' out");
    if (plane) {
        auto planes = parsePlaneList(planeName, *plane);
        if (!planes) return planes.error();
        def.geometry = Geometry::Plane;
        if (const auto cut = param(params, "cut")) {
            auto mode = parseCutMode("cut", *cut);
            if (!mode) return mode.error();
            def.cut = mode.value();
        } else if (planes.value().size() > 1) {
            const std::string n = std::to_string(planes.value().size());
            return makeError(
                ErrorCode::InvalidArgument,
                (planeName == "plane" ? "parameter 'plane' is given more than once (" + n + " planes) without 'cut'"
                                      : "parameter 'cut': required with " + n + " planes") +
                    ": several planes make a cut-out of a perspective view, with cut=union (keep what "
                    "is on the kept side of every plane) or cut=intersection (take out what is on the "
                    "removed side of every plane: a wedge, octant or box); other views take one plane");
        }
        if (planes.value().size() > 1) {
            def.cutPlanes = std::move(planes.value());
            sortPlanes(def.cutPlanes);
            def.plane = def.cutPlanes.front();
        } else {
            def.plane = planes.value().front();
            def.cut = CutMode::Union;  // one plane: both modes are the same cut
        }
    } else if (elevation) {
        auto z = parseNumber("elevation", *elevation);
        if (!z) return z.error();
        if (auto s = checkCoordinate("parameter 'elevation'", z.value()); !s) return s.error();
        def.geometry = Geometry::Elevation;
        def.elevation = z.value();
        def.plane = horizontalPlane(z.value());
    } else {
        auto v = parseNumberList("line", *line, 0, 2 * kMaxLineVertices);
        if (!v) return v.error();
        if (v.value().size() % 2 != 0 || v.value().size() < 4)
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'line': needs at least two x,y vertices (an even count of numbers), got " +
                                 std::to_string(v.value().size()) + " numbers");
        const bool lonlat = coords && *coords == "lonlat";
        def.geometry = Geometry::Line;
        for (std::size_t i = 0; i + 1 < v.value().size(); i += 2) {
            glm::dvec2 p{v.value()[i], v.value()[i + 1]};
            if (lonlat) {
                if (!crs.isProjected())
                    return makeError(ErrorCode::InvalidArgument,
                                     "parameter 'coords': lonlat needs a model in a projected CRS; this model "
                                     "is " +
                                         crs.id());
                auto xy = crs.fromLonLat(p.x, p.y);
                if (!xy) return makeError(xy.error().code, "parameter 'line': " + xy.error().message);
                p = xy.value();
            }
            for (int k = 0; k < 2; ++k)
                if (auto s = checkCoordinate(
                        "parameter 'line': vertex " + std::to_string(def.line.size()) + (k == 0 ? " x" : " y"), p[k]);
                    !s)
                    return s.error();
            if (!def.line.empty() && glm::length(p - def.line.back()) < 1e-6)
                return makeError(ErrorCode::InvalidArgument, "parameter 'line': vertices " +
                                                                 std::to_string(def.line.size() - 1) + " and " +
                                                                 std::to_string(def.line.size()) + " coincide");
            def.line.push_back(p);
        }
    }
    if (const auto vx = param(params, "vx")) {
        auto k = parseNumber("vx", *vx);
        if (!k) return k.error();
        if (auto s = checkExaggerationFactor("parameter 'vx'", k.value()); !s) return s.error();
        def.exaggeration = k.value();
    }
    if (const auto bg = param(params, "bg")) {
        auto c = parseBackground("bg", *bg);
        if (!c) return c.error();
        def.background = c.value();
    }
    auto colour = parseBlockColouring(params);
    if (!colour) return colour.error();
    def.colour = std::move(colour.value());
    auto holes = parseHoleDrawing(params);
    if (!holes) return holes.error();
    def.holes = std::move(holes.value());
    return def;
}

Result<ViewPlan> parseViewPlan(const Params& params, const std::string& model, const Crs& crs) {
    ViewPlan plan;
    auto def = parseSectionDef(params, model, crs);
    if (!def) return def.error();
    plan.section = std::move(def.value());
    if (const auto size = param(params, "size")) {
        auto s = parseSize("size", *size, kMaxImageSide, static_cast<long long>(kMaxImagePixels));
        if (!s) return s.error();
        plan.width = s.value().width;
        plan.height = s.value().height;
    }
    for (const char* name : {"labels", "patterns"})
        if (const auto v = param(params, name)) {
            auto b = parseBool(name, *v);
            if (!b) return b.error();
            (std::string_view(name) == "labels" ? plan.labels : plan.patterns) = b.value();
        }
    const auto view = param(params, "view");
    if (!view || *view == "profile") {
        plan.view = ViewKind::Profile;
        if (const auto frame = param(params, "frame")) {
            auto f = parseNumberList("frame", *frame, 4);
            if (!f) return f.error();
            FrameRect r{f.value()[0], f.value()[2], f.value()[1], f.value()[3]};
            // The pixel size too, before any work (view/view_limits.hpp).
            if (auto s = checkFrame(r, plan.width, plan.height); !s)
                return makeError(s.error().code, "parameter 'frame' (with 'size' " + std::to_string(plan.width) + "x" +
                                                     std::to_string(plan.height) + "): " + s.error().message);
            plan.frame = r;
        }
        if (!plan.section.cutPlanes.empty())
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'plane' (or 'planes'): " + std::to_string(plan.section.cutPlanes.size()) +
                                 " planes cut perspective views only (view=perspective); a profile view, vector "
                                 "section or tile grid takes one 'plane'");
    } else if (*view == "perspective") {
        if (plan.section.geometry == Geometry::Line)
            return makeError(
                ErrorCode::Unsupported,
                "parameter 'view': perspective views of a polyline section are not supported; use a plane");
        plan.view = ViewKind::Perspective;
        if (param(params, "eye") || param(params, "target")) {
            if (!param(params, "eye") || !param(params, "target"))
                return makeError(ErrorCode::InvalidArgument, "perspective view: give both 'eye' and 'target'");
            PerspectiveCamera cam;
            auto eye = parseVec3(params, "eye", {});
            if (!eye) return eye.error();
            auto target = parseVec3(params, "target", {});
            if (!target) return target.error();
            auto up = parseVec3(params, "up", {0.0, 0.0, 1.0});
            if (!up) return up.error();
            cam.eye = eye.value();
            cam.target = target.value();
            cam.up = up.value();
            for (int k = 0; k < 3; ++k) {
                const char* axis[3] = {" x", " y", " z"};
                if (auto s = checkCoordinate(std::string("parameter 'eye'") + axis[k], cam.eye[k]); !s)
                    return s.error();
                if (auto s = checkCoordinate(std::string("parameter 'target'") + axis[k], cam.target[k]); !s)
                    return s.error();
                if (auto s = checkCoordinate(std::string("parameter 'up'") + axis[k], cam.up[k]); !s) return s.error();
            }
            if (auto s = checkCameraDistance("perspective view: parameters 'eye' and 'target'", cam.eye, cam.target);
                !s)
                return s.error();
            if (!(glm::length(glm::cross(glm::normalize(cam.up), glm::normalize(cam.target - cam.eye))) >= 1e-6))
                return makeError(ErrorCode::InvalidArgument,
                                 "perspective view: parameter 'up' is zero or parallel to the view direction");
            if (const auto fov = param(params, "fov")) {
                auto f = parseNumber("fov", *fov);
                if (!f) return f.error();
                if (auto s = checkFov("parameter 'fov'", f.value()); !s) return s.error();
                cam.fovYDegrees = f.value();
            }
            plan.camera = cam;
        }
    } else {
        return makeError(ErrorCode::InvalidArgument,
                         "parameter 'view': '" + std::string(*view) + "' is not 'profile' or 'perspective'");
    }
    // Units left out of a perspective view: hide=r1,r2,.. or isolate=r1,r2,.. (record ids).
    for (const char* name : {"hide", "isolate"}) {
        const auto text = param(params, name);
        if (!text) continue;
        if (plan.view != ViewKind::Perspective)
            return makeError(ErrorCode::InvalidArgument, std::string("parameter '") + name +
                                                             "': applies to perspective views (view=perspective); "
                                                             "sections show every unit the plane cuts");
        if (!plan.shown.records.empty() || plan.shown.isolate)
            return makeError(ErrorCode::InvalidArgument, "give 'hide' or 'isolate', not both");
        auto ids = parseNumberList(name, *text, 0, kMaxShownRecords);
        if (!ids) return ids.error();
        for (double v : ids.value()) {
            if (!(v >= 1.0 && v <= 4294967295.0) || v != std::floor(v))
                return makeError(ErrorCode::InvalidArgument, std::string("parameter '") + name +
                                                                 "': " + formatNumber(v) +
                                                                 " is not a record id (1..4294967295)");
            plan.shown.records.push_back(RecordId(v));
        }
        std::sort(plan.shown.records.begin(), plan.shown.records.end());
        plan.shown.records.erase(std::unique(plan.shown.records.begin(), plan.shown.records.end()),
                                 plan.shown.records.end());
        plan.shown.isolate = std::string_view(name) == "isolate";
    }
    return plan;
}

std::vector<RecordId> ShownUnits::hiddenOf(const Model& model) const {
    if (!isolate) return records;
    std::vector<RecordId> hidden;
    for (const auto* parts : {&model.bodies, &model.surfaces})
        for (const Part& p : *parts)
            if (!std::binary_search(records.begin(), records.end(), p.record)) hidden.push_back(p.record);
    std::sort(hidden.begin(), hidden.end());
    hidden.erase(std::unique(hidden.begin(), hidden.end()), hidden.end());
    return hidden;
}

Plane sectionPlane(const SectionDef& def) {
    return def.geometry == Geometry::Elevation ? horizontalPlane(def.elevation) : def.plane;
}

CutOut sectionCut(const SectionDef& def) {
    if (def.cutPlanes.empty()) return CutOut{{sectionPlane(def)}, CutMode::Union};
    return CutOut{def.cutPlanes, def.cut};
}

VerticalExaggeration exaggerationOf(const SectionDef& def, const Aabb& bounds) {
    return VerticalExaggeration::aboutCentreOf(def.exaggeration, bounds);
}

PerspectiveCamera displayCamera(const ViewPlan& plan, const Aabb& bounds) {
    const VerticalExaggeration ds = exaggerationOf(plan.section, bounds);
    if (plan.camera) {
        PerspectiveCamera c = *plan.camera;
        c.eye = ds.toDisplay(c.eye);
        c.target = ds.toDisplay(c.target);
        return c;
    }
    return defaultCamera(ds.boundsToDisplay(bounds));
}

std::string encodeSectionId(const SectionDef& def) { return base64UrlEncode(def.canonical()); }

Result<SectionDef> decodeSectionId(std::string_view sid, const std::function<const Crs*(const std::string&)>& crsOf) {
    if (sid.size() > 16384) return makeError(ErrorCode::InvalidArgument, "section id is longer than 16384 characters");
    auto text = base64UrlDecode(sid);
    if (!text) return makeError(ErrorCode::InvalidArgument, "section id is not base64url: " + text.error().message);
    Params params;
    std::string_view rest = text.value();
    while (!rest.empty()) {
        const std::size_t amp = rest.find('&');
        const std::string_view item = rest.substr(0, amp);
        const std::size_t eq = item.find('=');
        if (eq == std::string_view::npos || eq == 0)
            return makeError(ErrorCode::InvalidArgument, "section id does not decode to a section definition");
        if (!params.emplace(std::string(item.substr(0, eq)), std::string(item.substr(eq + 1))).second)
            return makeError(ErrorCode::InvalidArgument,
                             "section id: parameter '" + std::string(item.substr(0, std::min<std::size_t>(eq, 64))) +
                                 "' is given more than once");
        if (amp == std::string_view::npos) break;
        rest.remove_prefix(amp + 1);
    }
    const auto model = param(params, "model");
    if (!model) return makeError(ErrorCode::InvalidArgument, "section id names no model");
    {
        std::vector<std::string_view> known = sectionParamNames();
        known.push_back("model");
        if (auto s = checkKnownParams(params, known); !s)
            return makeError(s.error().code, "section id: " + s.error().message);
    }
    const Crs* crs = crsOf(std::string(*model));
    if (!crs)
        return makeError(ErrorCode::NotFound,
                         "section id names model '" + std::string(*model) + "', which is not loaded");
    auto def = parseSectionDef(params, std::string(*model), *crs);
    if (!def) return makeError(def.error().code, "section id: " + def.error().message);
    return def;
}

std::string base64UrlEncode(std::string_view bytes) {
    static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const std::uint32_t v =
            (std::uint8_t(bytes[i]) << 16) | (std::uint8_t(bytes[i + 1]) << 8) | std::uint8_t(bytes[i + 2]);
        for (int k = 3; k >= 0; --k) out += alphabet[(v >> (6 * k)) & 63];
    }
    if (i + 1 == bytes.size()) {
        const std::uint32_t v = std::uint8_t(bytes[i]) << 16;
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
    } else if (i + 2 == bytes.size()) {
        const std::uint32_t v = (std::uint8_t(bytes[i]) << 16) | (std::uint8_t(bytes[i + 1]) << 8);
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
        out += alphabet[(v >> 6) & 63];
    }
    return out;
}

Result<std::string> base64UrlDecode(std::string_view text) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        if (c == '-') return 62;
        if (c == '_') return 63;
        return -1;
    };
    if (text.size() % 4 == 1) return makeError(ErrorCode::InvalidArgument, "bad length " + std::to_string(text.size()));
    std::string out;
    std::uint32_t acc = 0;
    int bits = 0;
    for (char c : text) {
        const int v = value(c);
        if (v < 0)
            return makeError(ErrorCode::InvalidArgument, "character '" + std::string(1, c) + "' is not base64url");
        acc = (acc << 6) | std::uint32_t(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out += char((acc >> bits) & 0xff);
        }
    }
    return out;
}

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed) {
    std::uint64_t h = seed;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ULL;
    }
    return h;
}

std::string hex64(std::uint64_t v) {
    static const char* digits = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, v >>= 4) s[std::size_t(i)] = digits[v & 15];
    return s;
}

}  // namespace geoslice::api
