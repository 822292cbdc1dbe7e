// Plans: the validated, canonical form of a request for a section view. A render or a
// query is a pure function of (model version, plan), so the canonical text of a plan is
// what cache keys, ETags and stateless section ids are made from (shared/DESIGN.md).
//
// Request parameters (HTTP query string or JSON fields; api/params.hpp):
//   geometry, exactly one of
//     plane=a,b,c,d             world plane; keeps a*x + b*y + c*z + d >= 0 (normalised here)
//     plane=.. repeated (up to 6) or planes=a,b,c,d;a,b,c,d;..  with cut=union|intersection:
//                               a cut-out of a perspective view (api/cut.hpp)
//     line=x1,y1,x2,y2[,...]    vertical section along a map polyline (2..256 vertices)
//     elevation=z               horizontal slice (plan map) at elevation z, metres
//   coords=world|lonlat         units of `line` (lonlat: degrees lon,lat in CGCS2000; default world);
//                               an error with 'plane' or 'elevation' (world coordinates, always)
//   view=profile|perspective    default profile
//   frame=u0,u1,v0,v1           profile: plane u/v metres shown (default: the model's
//                               bounds projected on the plane, 2 % margin, fitted to the size)
//   eye=x,y,z target=x,y,z up=x,y,z fov=deg   perspective camera (world; defaults around the model)
//   size=WxH                    pixels, each side 1..8192, at most 2^26 pixels (default 1024x1024)
//   vx=k                        vertical exaggeration 0.1..100 (default 1), view/exaggeration.hpp:
//                               elevation stretched k times about the bounds' centre elevation
//   bg=transparent|#rrggbb[aa]  background (default transparent)
//   colour=PROP breaks=b1,.. ramp=NAME   colour by a block property (BlockColouring)
//   labels=0|1 patterns=0|1     profile views: unit codes inside their polygons and lithology
//                               patterns (section/fill/labels.hpp, patterns.hpp); unset =
//                               the output's default (labels: on in print sheets only;
//                               patterns: on in SVG and print sheets, off in images)
//   holes=W holecolour=COL holebreaks=b1,.. holeramp=NAME   drillholes drawn on profile
//                               views (HoleDrawing, api/holes.hpp)
//   hide=r1,r2,.. | isolate=r1,r2,..   perspective views: records left out, or the only ones
//                               drawn (ShownUnits)
// Units: metres in the model's CRS (x easting, y northing, z elevation), degrees for lon/lat.
// Pure functions, any thread.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "api/cut.hpp"
#include "api/params.hpp"
#include "model/attributes.hpp"
#include "model/crs/crs.hpp"
#include "model/model.hpp"
#include "model/result.hpp"
#include "section/fill/raster.hpp"
#include "view/camera.hpp"
#include "view/exaggeration.hpp"
#include "view/plane.hpp"
#include "view/view_frame.hpp"
#include "view/view_limits.hpp"

namespace geoslice::api {

constexpr std::size_t kMaxLineVertices = 256;

enum class Geometry { Plane, Line, Elevation };
enum class ViewKind { Profile, Perspective };

// What a section is, independent of the view of it (a tile pyramid shares one).
// Colouring by a block property (model/blocks/block_model.hpp): colour=PROP [&breaks=b1,b2,...]
// [&ramp=viridis|magma|greys|spectral]. Without breaks: five equal classes over the
// property's range. PROP is [A-Za-z0-9_.-]{1,64}.
struct BlockColouring {
    std::string property;
    std::string ramp = "viridis";
    std::optional<std::vector<double>> breaks;
};

// Drillholes on profile views (api/holes.hpp): the holes within `window` metres of the section
// (holes=W, default kDefaultHoleWindow, 0 = none drawn), their intervals coloured by the
// interval column `column` (holecolour=COL: a text column by category, a number column by
// classes of `breaks` on `ramp`, as block properties are; holebreaks=, holeramp=, or breaks=
// and ramp= when no colour= is given). COL is [A-Za-z0-9_.-]{1,64}, or TABLE.COL to pick the
// interval table.
constexpr double kDefaultHoleWindow = 50.0;  // m
constexpr double kMaxHoleWindow = 100000.0;  // m
struct HoleDrawing {
    double window = kDefaultHoleWindow;
    std::string column;  // empty: holes in one colour
    std::string ramp = "viridis";
    std::optional<std::vector<double>> breaks;
};

struct SectionDef {
    std::string model;
    Geometry geometry = Geometry::Plane;
    Plane plane;  // Plane and Elevation: world, unit normal
    // Cut-outs (api/cut.hpp): with two or more planes all of them, sorted (`plane` is the
    // first), and how their removed sides combine; empty for one plane.
    std::vector<Plane> cutPlanes;
    CutMode cut = CutMode::Union;
    std::vector<glm::dvec2> line;  // Line: world easting, northing (metres)
    double elevation = 0.0;        // Elevation
    double exaggeration = 1.0;     // vertical exaggeration of profile frames
    Rgba8 background{0, 0, 0, 0};
    std::optional<BlockColouring> colour;  // colour the clipping bodies by a block property
    HoleDrawing holes;                     // drillholes drawn on profile views

    // "model=..&plane=..&vx=..&bg=..[&colour=..&ramp=..&breaks=..][&holes=..][&holecolour=..
    // &holeramp=..&holebreaks=..]" with every number in shortest round-trip form (holes= only
    // when not the default).
    std::string canonical() const;
};

// Units left out of a perspective view (hide=r1,r2,.. or isolate=r1,r2,..): the picture of
// the model without those records' bodies and surfaces (renderer/slice_renderer.hpp
// SliceRequest::hidden). At most kMaxShownRecords ids; each must be a record of the model
// (checked by the server against the model).
constexpr std::size_t kMaxShownRecords = 1024;
struct ShownUnits {
    std::vector<RecordId> records;  // sorted, unique
    bool isolate = false;           // records are the ones shown, not the ones hidden
    // The records not drawn: `records`, or with isolate every other record of `model`'s parts.
    std::vector<RecordId> hiddenOf(const Model& model) const;
};

struct ViewPlan {
    SectionDef section;
    ViewKind view = ViewKind::Profile;
    std::optional<FrameRect> frame;           // profile; nullopt = default frame
    std::optional<PerspectiveCamera> camera;  // perspective, world; nullopt = default camera
    int width = 1024, height = 1024;
    std::optional<bool> labels;    // labels=0|1; nullopt: the output's default
    std::optional<bool> patterns;  // patterns=0|1; nullopt: the output's default
    ShownUnits shown;              // perspective views: hide= / isolate=

    std::string canonical() const;  // the section's canonical text plus the view's fields
};

// The parameter names parseSectionDef and parseViewPlan read (routes add their own, e.g.
// px/py or quality, and reject the rest with checkKnownParams).
const std::vector<std::string_view>& sectionParamNames();
const std::vector<std::string_view>& viewParamNames();

// colour, breaks and ramp of `params` (nullopt when there is no 'colour').
Result<std::optional<BlockColouring>> parseBlockColouring(const Params& params);
// holes, holecolour, holebreaks/holeramp (or breaks/ramp without colour) of `params`.
Result<HoleDrawing> parseHoleDrawing(const Params& params);
// Parses the section fields of `params`. `crs` converts lon/lat lines (error when local).
Result<SectionDef> parseSectionDef(const Params& params, const std::string& model, const Crs& crs);
// Parses a whole view. Errors name the parameter (InvalidArgument / OutOfRange).
Result<ViewPlan> parseViewPlan(const Params& params, const std::string& model, const Crs& crs);

// The plane of a Plane or Elevation section (Elevation keeps what lies below z, seen from above).
Plane sectionPlane(const SectionDef& def);
// Every plane that cuts a perspective view of the section, with the cut mode: the section's
// plane alone, or the planes of a cut-out.
CutOut sectionCut(const SectionDef& def);

// Profile frames (FrameRect, defaultFrame, projectedBounds): view/view_frame.hpp.
// The perspective camera, its pixel rays and the default camera: view/camera.hpp.

// The section's vertical exaggeration: SectionDef::exaggeration about the centre elevation
// of the model's bounds (the one pivot rule, view/exaggeration.hpp). Perspective cameras
// given in a request are world points; they are mapped like the model.
VerticalExaggeration exaggerationOf(const SectionDef& def, const Aabb& bounds);
// The camera of a perspective plan in display space: the request's camera mapped, or the
// default camera around the display-space bounds.
PerspectiveCamera displayCamera(const ViewPlan& plan, const Aabb& bounds);

// Stateless section ids: base64url (no padding) of SectionDef::canonical(), and back.
std::string encodeSectionId(const SectionDef& def);
Result<SectionDef> decodeSectionId(std::string_view sid, const std::function<const Crs*(const std::string&)>& crsOf);

// base64url without padding (RFC 4648 section 5).
std::string base64UrlEncode(std::string_view bytes);
Result<std::string> base64UrlDecode(std::string_view text);

// 64-bit FNV-1a, for cache keys and ETags (not for security).
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed = 0xcbf29ce484222325ULL);
std::string hex64(std::uint64_t v);

}  // namespace geoslice::api
