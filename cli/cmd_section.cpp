// geoslice section MODEL (--plane a,b,c,d | --elevation z | --line x1,y1,x2,y2[,...])
// [--size WxH] [--frame u0,u1,v0,v1 | --exaggeration k] [--out F.png|F.jpg|F.webp|F.ppm|F.pgm]... [--geojson F]
// [--geojson-frame plane|world] [--svg F] [--labels] [--patterns] [--no-labels] [--no-patterns]
// [--areas]: the exact section engine from the
// command line. Colour images go through image/image_encode.hpp (PNG, JPEG, WebP) or
// binary PPM (composited over white); the ID buffer is written as 16-bit binary PGM
// (record ids, big-endian, 0 = none). --geojson / --svg write the polygons and traces
// (section/fill/vector_export.hpp). --areas prints JSON (plane or line, frame, pixel -> world
// transform, area of each body in m², trace count) on stdout. With --line the section is
// vertical along the map polyline: u = distance along the line (m), v = elevation (m).
// Without --frame the image has the default frame of HTTP plans (view/view_frame.hpp):
// the same request gives the same picture here and from GET section.png.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/catalog.hpp"
#include "api/holes.hpp"
#include "api/params.hpp"
#include "api/request.hpp"
#include "api/view.hpp"
#include "cli/commands.hpp"
#include "image/image_encode.hpp"
#include "model/drillholes/drillholes.hpp"
#include "model/io/loaders.hpp"
#include "model/json_text.hpp"
#include "print/cairo_output.hpp"
#include "print/map_scale.hpp"
#include "print/paper.hpp"
#include "print/pattern_cairo.hpp"
#include "print/section_sheet.hpp"
#include "print/sheet_date.hpp"
#include "print/svg_output.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"
#include "section/fill/dxf_export.hpp"
#include "section/fill/raster.hpp"
#include "section/fill/vector_export.hpp"
#include "section/index/section_index.hpp"

namespace geoslice::cli {
namespace {

using api::formatNumber;
using print::todayUtc;

using json = nlohmann::ordered_json;

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Status writePpm(const std::string& path, const std::vector<std::uint8_t>& rgba, int W, int H) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return makeError(ErrorCode::IoError, "cannot open " + path + " for writing");
    std::fprintf(f, "P6\n%d %d\n255\n", W, H);
    std::vector<std::uint8_t> rgb(std::size_t(W) * std::size_t(H) * 3);
    for (std::size_t i = 0; i < std::size_t(W) * std::size_t(H); ++i) {
        const std::uint8_t* p = &rgba[4 * i];
        const unsigned a = p[3];
        for (int c = 0; c < 3; ++c)
            rgb[3 * i + std::size_t(c)] = static_cast<std::uint8_t>((p[c] * a + 255 * (255 - a) + 127) / 255);
    }
    const bool ok = std::fwrite(rgb.data(), 1, rgb.size(), f) == rgb.size();
    if (std::fclose(f) != 0 || !ok) return makeError(ErrorCode::IoError, "cannot write " + path);
    return {};
}

Status writePgm16(const std::string& path, const std::vector<std::uint32_t>& ids, int W, int H) {
    std::vector<std::uint8_t> data(ids.size() * 2);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] > 65535)
            return makeError(ErrorCode::OutOfRange,
                             "record id " + std::to_string(ids[i]) + " does not fit a 16-bit PGM (" + path + ")");
        data[2 * i] = static_cast<std::uint8_t>(ids[i] >> 8);
        data[2 * i + 1] = static_cast<std::uint8_t>(ids[i] & 0xFF);
    }
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return makeError(ErrorCode::IoError, "cannot open " + path + " for writing");
    std::fprintf(f, "P5\n%d %d\n65535\n", W, H);
    const bool ok = std::fwrite(data.data(), 1, data.size(), f) == data.size();
    if (std::fclose(f) != 0 || !ok) return makeError(ErrorCode::IoError, "cannot write " + path);
    return {};
}

json vec3(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

Status writeText(const std::string& path, const std::string& text) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return makeError(ErrorCode::IoError, "cannot open " + path + " for writing");
    const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (std::fclose(f) != 0 || !ok) return makeError(ErrorCode::IoError, "cannot write " + path);
    return {};
}

bool isEncoded(const std::string& path) { return imageFormatFromPath(path).ok(); }

json bodiesJson(const Model& m, const std::vector<BodySection>& bodies) {
    json out = json::array();
    for (const BodySection& b : bodies) {
        std::size_t holes = 0;
        for (const auto& p : b.polygons) holes += p.holes.size();
        out.push_back({{"name", m.bodies[b.part].name},
                       {"record", b.record},
                       {"area_m2", b.area},
                       {"polygons", b.polygons.size()},
                       {"holes", holes},
                       {"open_chains", b.openChains}});
    }
    return out;
}

// The sheet's options from the flags, every value checked before the model loads.
template <class Opts>
Result<print::SheetOptions> sheetOptionsFromFlags(const Opts& o, const std::optional<FrameRect>& frame) {
    const std::string ext = o.sheet.substr(std::min(o.sheet.size(), o.sheet.rfind('.') + 1));
    if (ext != "pdf" && ext != "svg" && !isEncoded(o.sheet))
        return makeError(ErrorCode::InvalidArgument,
                         "--print \"" + o.sheet + "\": the extension must be .pdf, .svg, .png, .jpg or .webp");
    print::SheetOptions so;
    auto orientation = print::parseOrientation(o.orientation);
    if (!orientation) return makeError(orientation.error().code, "--orientation: " + orientation.error().message);
    auto paper = print::paperSize(o.paper, orientation.value());
    if (!paper) return makeError(paper.error().code, "--paper: " + paper.error().message);
    so.paper = paper.value();
    if (!std::isnan(o.scale)) {
        if (Status s = print::checkScale(o.scale); !s)
            return makeError(s.error().code, "--scale: " + s.error().message);
        so.scale = o.scale;
    }
    if (Status s = checkExaggerationFactor("--vx", o.exaggeration); !s) return s.error();
    so.exaggeration = o.exaggeration;
    if (!(o.dpi >= 50.0 && o.dpi <= 600.0)) return makeError(ErrorCode::OutOfRange, "--dpi must be within 50..600");
    so.dpi = o.dpi;
    so.rasterGeometry = ext != "pdf" && ext != "svg";
    so.frame = frame;
    so.scaleName = "--scale";
    so.labels = !o.noLabels;
    so.patterns = !o.noPatterns;
    if (!o.date.empty() && !print::isCalendarDate(o.date))
        return makeError(ErrorCode::InvalidArgument, "--date \"" + o.date + "\" is not YYYY-MM-DD");
    return so;
}

Status writeSheet(const std::string& path, const print::Sheet& sheet, double dpi) {
    if (endsWith(path, ".pdf") || endsWith(path, ".svg")) {
        auto doc = endsWith(path, ".pdf") ? print::renderPdf(sheet) : print::renderSvg(sheet);
        if (!doc) return doc.error();
        return writeText(path, doc.value());
    }
    auto raster = print::renderRaster(sheet, dpi);
    if (!raster) return raster.error();
    return writeImage(path, raster.value().rgba.data(), raster.value().width, raster.value().height);
}

}  // namespace

void addSection(CLI::App& app, int& exitCode) {
    struct Opts {
        std::string model, plane, line, size = "1024x1024", frame, geojson, geojsonFrame, svg, dxf, dxfFrame = "plane";
        std::string sheet, paper = "A3", orientation = "landscape", date;
        double scale = NAN, dpi = 150.0;
        ColourOptions colour;
        std::vector<std::string> outs;
        std::string holes, holeColour, holeBreaks, holeRamp, drillholes;
        double elevation = NAN, exaggeration = 1.0;
        bool areas = false;
        bool labels = false, patterns = false, noLabels = false, noPatterns = false;
        unsigned threads = 1;
        LoadOptions load;
    };
    auto o = std::make_shared<Opts>();
    CLI::App* cmd = app.add_subcommand(
        "section", "Exact section of a model by a plane or along a map polyline (CPU): images, vectors and areas");
    cmd->add_option("MODEL", o->model, "Model file")->required();
    addLoadOptions(cmd, o->load);
    auto* planeOpt = cmd->add_option("--plane", o->plane,
                                     "Plane a,b,c,d in world coordinates (x east, y north, z up, metres); "
                                     "points with a*x+b*y+c*z+d >= 0 are kept");
    auto* elevOpt =
        cmd->add_option("--elevation", o->elevation, "Horizontal slice at this elevation (m), seen from above");
    auto* lineOpt = cmd->add_option("--line", o->line,
                                    "Vertical section along the map polyline x1,y1,x2,y2[,...] (world metres): "
                                    "u = distance along the line, v = elevation");
    planeOpt->excludes(elevOpt);
    planeOpt->excludes(lineOpt);
    elevOpt->excludes(lineOpt);
    cmd->add_option("--size", o->size, "Image size WxH in pixels (default 1024x1024)");
    cmd->add_option("--frame", o->frame,
                    "Frame u0,u1,v0,v1 in plane metres (with --line: distance along the line and elevation; "
                    "default: the model's bounds on the plane, as HTTP); same meaning as in render and frame=");
    cmd->add_option("--exaggeration,--vx", o->exaggeration,
                    "Vertical exaggeration of the image's default frame and of the sheet, 0.1..100, as HTTP vx= "
                    "(default 1)");
    cmd->add_option("--out", o->outs,
                    "Output file, repeatable: .png/.jpg/.webp/.ppm = colour, .pgm = record ids (16-bit)");
    cmd->add_option("--geojson", o->geojson, "Write the polygons and traces as GeoJSON");
    cmd->add_option("--geojson-frame", o->geojsonFrame,
                    "GeoJSON coordinates: world ([lon, lat, z] on WGS 84, RFC 7946; default with a CRS), projected "
                    "([x, y, z] in the model's CRS) or plane ([u, v] metres; default without a CRS)");
    cmd->add_option("--svg", o->svg, "Write the polygons and traces as SVG (same frame and size as the image)");
    cmd->add_option("--dxf", o->dxf,
                    "Write the section as DXF for CAD (dxflib, R2000): a layer per unit, closed polylines, solid "
                    "hatches and name labels");
    cmd->add_option("--dxf-frame", o->dxfFrame,
                    "DXF coordinates: plane (u, v metres, as drawn; default) or projected (3D polylines in the "
                    "model's CRS, no hatches)");
    cmd->add_option("--print", o->sheet,
                    "Write a print-ready section sheet: .pdf, .svg (text as text), or .png/.jpg/.webp at --dpi; "
                    "axes, scale, ends, legend, title block (print/section_sheet.hpp)");
    cmd->add_option("--paper", o->paper, "Sheet paper: A0..A5, letter, tabloid (default A3)");
    cmd->add_option("--orientation", o->orientation, "Sheet orientation: landscape (default) or portrait");
    cmd->add_option("--scale", o->scale,
                    "Sheet scale denominator S (1:S); default: the smallest round scale that fits the paper");
    cmd->add_option("--dpi", o->dpi, "Resolution of a .png/.jpg/.webp sheet, 50..600 (default 150)");
    cmd->add_option("--date", o->date, "The title block's date, YYYY-MM-DD (default: today, UTC)");
    cmd->add_flag("--labels", o->labels,
                  "Images (--out) and --svg: unit codes inside their polygons (on by default in --print)");
    cmd->add_flag("--patterns", o->patterns,
                  "Images (--out): lithology patterns over the units' colours (on by default in --svg and --print)");
    cmd->add_flag("--no-labels", o->noLabels, "No unit codes in --print sheets");
    cmd->add_flag("--no-patterns", o->noPatterns, "No lithology patterns in --svg and --print (and not in images)");
    cmd->add_flag("--areas", o->areas, "Print JSON with the section frame and each body's area (m^2) on stdout");
    cmd->add_option("--holes", o->holes,
                    "Draw the drillholes within this many metres of the section (default 50; 0: none), as HTTP "
                    "holes=");
    cmd->add_option("--holecolour", o->holeColour,
                    "Colour hole intervals by this interval column (or TABLE.COLUMN), as HTTP holecolour=");
    cmd->add_option("--holebreaks", o->holeBreaks, "Class breaks of a number --holecolour column, comma-separated");
    cmd->add_option("--holeramp", o->holeRamp,
                    "Colour ramp of --holecolour: viridis (default), magma, greys, spectral");
    cmd->add_option("--drillholes", o->drillholes,
                    "Drillhole database: a sidecar JSON or a folder of CSV tables (default: the "
                    "<stem>.drillholes.json sidecar beside the model); docs/drillholes.md");
    cmd->add_option("--threads", o->threads, "Threads for the cut: 1 or 2 (default 1)");
    addColourOptions(cmd, o->colour,
                     "Colour the block model's clipping bodies by this block property (images; SVG and GeoJSON of "
                     "plane sections: each cell's exact piece); same as colour= over HTTP");
    cmd->callback([o, &exitCode] {
        auto fail = [&](const std::string& msg, int code) {
            std::fprintf(stderr, "geoslice section: %s\n", msg.c_str());
            exitCode = code;
        };
        Plane plane;
        std::vector<glm::dvec2> linePoints;
        if (!o->plane.empty()) {
            auto p = parsePlaneFlag(o->plane);
            if (!p) return fail(p.error().message, 2);
            plane = p.value();
        } else if (std::isfinite(o->elevation)) {
            plane = horizontalPlane(o->elevation);
        } else if (!o->line.empty()) {
            auto numbers = parseNumbersFlag("--line", o->line, 0);
            if (!numbers) return fail(numbers.error().message, 2);
            const std::vector<double>& v = numbers.value();
            if (v.size() < 4 || v.size() % 2 != 0)
                return fail("--line needs x1,y1,x2,y2[,...]: an even count of at least 4 numbers (got " +
                                std::to_string(v.size()) + ")",
                            2);
            for (std::size_t i = 0; i < v.size(); i += 2) linePoints.push_back({v[i], v[i + 1]});
            if (auto l = makeSectionLine(linePoints); !l) return fail("--line: " + l.error().message, 2);
        } else {
            return fail("give --plane a,b,c,d, --elevation z (a finite number) or --line x1,y1,x2,y2[,...]", 2);
        }
        const bool polyline = !linePoints.empty();
        // The size against the limits HTTP checks, by HTTP's reader (view/view_limits.hpp).
        auto size = api::parseSize("--size", o->size, kMaxImageSide, static_cast<long long>(kMaxImagePixels));
        if (!size) return fail(size.error().message, 2);
        const int width = size.value().width, height = size.value().height;
        std::optional<FrameRect> givenFrame;
        if (!o->frame.empty()) {
            auto f = parseNumbersFlag("--frame", o->frame, 4);
            if (!f) return fail(f.error().message + " (u0,u1,v0,v1 in plane metres)", 2);
            FrameRect r;  // given as u0,u1,v0,v1
            r.u0 = f.value()[0];
            r.u1 = f.value()[1];
            r.v0 = f.value()[2];
            r.v1 = f.value()[3];
            if (Status s = checkFrame(r, width, height); !s) return fail("--frame: " + s.error().message, 2);
            givenFrame = r;
        }
        for (const auto& out : o->outs)
            if (!endsWith(out, ".ppm") && !endsWith(out, ".pgm") && !isEncoded(out))
                return fail("--out \"" + out +
                                "\": the extension must be .png, .jpg, .jpeg, .webp or .ppm (colour) or .pgm "
                                "(record ids)",
                            2);
        if (o->dxfFrame != "plane" && o->dxfFrame != "projected")
            return fail("--dxf-frame must be plane or projected (got \"" + o->dxfFrame + "\")", 2);
        // --geojson-frame is the server's `space` (api::parseVectorSpace: the same words and default).
        api::Params frameParam;
        if (!o->geojsonFrame.empty()) frameParam.emplace("space", o->geojsonFrame);
        if (!api::parseVectorSpace(frameParam, true))
            return fail("--geojson-frame must be world, projected or plane (got \"" + o->geojsonFrame + "\")", 2);
        if (o->threads < 1 || o->threads > 2) return fail("--threads must be 1 or 2", 2);
        if (Status s = checkExaggerationFactor("--exaggeration (--vx)", o->exaggeration); !s)
            return fail(s.error().message, 2);
        std::optional<print::SheetOptions> sheetOptions;
        if (!o->sheet.empty()) {
            auto so = sheetOptionsFromFlags(*o, givenFrame);
            if (!so) return fail(so.error().message, 2);
            sheetOptions = std::move(so.value());
        }

        api::Params holeParams;
        if (!o->holes.empty()) holeParams["holes"] = o->holes;
        if (!o->holeColour.empty()) holeParams["holecolour"] = o->holeColour;
        if (!o->holeBreaks.empty()) holeParams["holebreaks"] = o->holeBreaks;
        if (!o->holeRamp.empty()) holeParams["holeramp"] = o->holeRamp;
        auto holeDrawing = api::parseHoleDrawing(holeParams);
        if (!holeDrawing) {
            std::string m = holeDrawing.error().message;
            for (const char* name : {"holes", "holecolour", "holebreaks", "holeramp"})
                if (auto at = m.find(std::string("parameter '") + name + "'"); at != std::string::npos)
                    m.replace(at, std::strlen(name) + 12, std::string("--") + name);
            return fail(m, 2);
        }

        auto model = loadModel(o->model, o->load);
        if (!model) return fail(model.error().message, 1);
        // The drillholes drawn over the outputs (api/holes.hpp), held as a catalog model of
        // their own: the database, its index and the model's attribute table (unit colours).
        api::CatalogModel holesModel;
        holesModel.id = std::filesystem::path(o->model).filename().string();
        if (const std::string dh = o->drillholes.empty() ? drillholeSidecarFor(o->model) : o->drillholes; !dh.empty()) {
            auto db = loadDrillholes(dh);
            if (!db) return fail("drillholes " + dh + ": " + db.error().message, 1);
            if (auto s = placeDrillholes(db.value(), model->crs, model->bounds()); !s)
                return fail("drillholes " + dh + ": " + s.error().message, 1);
            holesModel.model.attributes = model->attributes;
            api::attachDrillholes(holesModel, std::move(db.value()));
        }
        if (model->validation.hasErrors())
            std::fprintf(stderr, "geoslice section: warning: %s has validation errors; contours may stay open\n",
                         o->model.c_str());
        auto index = buildSectionIndex(model.value());
        if (!index) return fail(index.error().message, 1);
        const SectionIndex& idx = *index.value();
        // The one default frame and pivot rule of HTTP plans (view/view_frame.hpp).
        const VerticalExaggeration ve = VerticalExaggeration::aboutCentreOf(o->exaggeration, idx.bounds);
        SectionOptions so;
        so.threads = o->threads;
        RasterOptions ro;
        ro.background = Rgba8{0, 0, 0, 0};

        // Both shapes end in the same outputs: colour + ids, a vector source and a frame.
        std::optional<Section> section;
        std::optional<PolylineSection> lineSection;
        FrameRect rect;
        std::vector<std::uint8_t> rgba;
        std::vector<std::uint32_t> ids;
        json frameJson, imageJson;
        if (polyline) {
            auto s = computePolylineSection(idx, linePoints, so);
            if (!s) return fail(s.error().message, 1);
            lineSection = std::move(s).value();
            rect =
                givenFrame ? *givenFrame : defaultLineFrame(lineSection->line.length(), idx.bounds, width, height, ve);
            auto img = rasterizePolylineSection(idx, *lineSection, rect, width, height, ro);
            if (!img) return fail(img.error().message, 1);
            json pts = json::array(), chain = json::array();
            for (std::size_t i = 0; i < img->line.points.size(); ++i) {
                pts.push_back({img->line.points[i].x, img->line.points[i].y});
                chain.push_back(img->line.chainage[i]);
            }
            frameJson = {{"line", pts}, {"chainage_m", chain}};
            imageJson = {{"width", width},
                         {"height", height},
                         {"rect_uv", {rect.u0, rect.v0, rect.u1, rect.v1}},
                         {"pixel",
                          "centre of pixel (i, j): u = rect_uv[0] + (i + 0.5) * (u1 - u0) / width, v = rect_uv[3] - "
                          "(j + 0.5) * (v1 - v0) / height; world = the line's point at distance u, elevation v"}};
            rgba = std::move(img->rgba);
            ids = std::move(img->ids);
        } else {
            auto s = computeSection(idx, plane, so);
            if (!s) return fail(s.error().message, 1);
            section = std::move(s).value();
            rect = givenFrame ? *givenFrame : defaultFrame(plane, idx.bounds, model->origin, width, height, ve);
            auto img = rasterizeSection(idx, *section, rect, width, height, ro);
            if (!img) return fail(img.error().message, 1);
            const PixelFrame& f = img->frame;
            frameJson = {{"origin", vec3(section->frame.originWorld())},
                         {"u", vec3(section->frame.u)},
                         {"v", vec3(section->frame.v)}};
            imageJson = {{"width", width},
                         {"height", height},
                         {"rect_uv", {rect.u0, rect.v0, rect.u1, rect.v1}},
                         {"world_at_pixel_corner_0_0", vec3(f.worldAtCorner())},
                         {"world_per_pixel_x", vec3(f.worldPerPixelX())},
                         {"world_per_pixel_y", vec3(f.worldPerPixelY())}};
            rgba = std::move(img->rgba);
            ids = std::move(img->ids);
        }
        VectorSource source = polyline ? vectorSource(*lineSection) : vectorSource(*section);
        std::optional<PropertyClasses> classes;
        std::vector<BlockPiece> pieces;
        auto requested = colourClasses(model.value(), o->colour);
        if (!requested) return fail(requested.error().message, 2);
        if (requested.value()) {
            classes = std::move(requested.value());
            const double pu = (rect.u1 - rect.u0) / width, pv = (rect.v1 - rect.v0) / height;
            std::function<glm::dvec3(int, int)> worldAt;
            std::optional<SectionLine> line;
            if (polyline) {
                auto l = makeSectionLine(linePoints);
                if (!l) return fail(l.error().message, 1);
                line = std::move(l.value());
                worldAt = [&](int i, int j) {
                    return line->worldAt(rect.u0 + (i + 0.5) * pu, rect.v1 - (j + 0.5) * pv);
                };
            } else {
                worldAt = [&](int i, int j) {
                    return section->frame.toWorld({rect.u0 + (i + 0.5) * pu, rect.v1 - (j + 0.5) * pv});
                };
            }
            // Where rows are lines in the world (the walk of section/blocks/block_raster.cpp): a plane's
            // whole row, a polyline's columns on each leg.
            const std::vector<RowLine> rowLines =
                polyline ? polylineRowLines(
                               *line, [&](int i) { return rect.u0 + (i + 0.5) * pu; }, width, pu)
                         : std::vector<RowLine>{{0, width, section->frame.u * pu}};
            colourPixelsByBlocks(*model->blocks, *classes, blockClipRecords(model.value(), *model->blocks), worldAt,
                                 width, height, ids.data(), rgba.data(), nullptr, rowLines);
            if (!o->svg.empty() || !o->geojson.empty()) {
                auto p = polyline ? blockPieces(*model->blocks, *lineSection, idx.origin, &rect)
                                  : blockPieces(*model->blocks, *section, &rect);
                if (!p) return fail(p.error().message, 1);
                pieces = std::move(p.value());
                source.svgOverBodies = blockPiecesSvg(*model->blocks, *classes, pieces, rect, width, height);
            }
        }
        if ((o->labels && !o->noLabels) || (o->patterns && !o->noPatterns))
            print::decorateSectionImage(idx, polyline ? lineSection->bodies : section->bodies, rect, width, height,
                                        rgba.data(), ids.data(),
                                        {o->labels && !o->noLabels, o->patterns && !o->noPatterns},
                                        polyline ? &lineSection->traces : &section->traces);
        api::ViewHoles holes;
        api::PixelMapping mapping;
        mapping.geometry = polyline            ? api::Geometry::Line
                           : !o->plane.empty() ? api::Geometry::Plane
                                               : api::Geometry::Elevation;
        mapping.rect = rect;
        mapping.width = width;
        mapping.height = height;
        if (polyline) {
            mapping.line = lineSection->line;
        } else {
            mapping.planar.section = section->frame;
            mapping.planar.rect = rect;
            mapping.planar.width = width;
            mapping.planar.height = height;
        }
        {
            api::SectionDef def;
            def.holes = holeDrawing.value();
            auto vh = api::viewHoles(holesModel, def, mapping);
            if (!vh) {
                std::string m = vh.error().message;
                if (auto at = m.find("parameter 'holecolour'"); at != std::string::npos)
                    m.replace(at, 22, "--holecolour");
                return fail(m, 2);
            }
            holes = std::move(vh.value());
        }
        if (!holes.empty()) {
            api::ViewImage view;
            view.width = width;
            view.height = height;
            view.rgba = std::move(rgba);
            api::drawHoles(holesModel, holes, mapping, view);
            rgba = std::move(view.rgba);
        }
        for (const auto& out : o->outs) {
            Status s = endsWith(out, ".ppm")   ? writePpm(out, rgba, width, height)
                       : endsWith(out, ".pgm") ? writePgm16(out, ids, width, height)
                                               : writeImage(out, rgba.data(), width, height);
            if (!s) return fail(s.error().message, 1);
        }
        if (!o->geojson.empty()) {
            const VectorFrame frame = api::parseVectorSpace(frameParam, !model->crs.isLocal()).value();
            const api::Wgs84Choice wgs84 =
                frame == VectorFrame::LonLat ? api::chooseWgs84Transform(model->crs, idx.bounds) : api::Wgs84Choice{};
            auto space = geoJsonSpace(source, frame, model->crs, wgs84.lonLat.get(), wgs84.lonLatNote);
            if (!space) {
                std::string m = space.error().message;
                if (auto at = m.find("parameter 'space'"); at != std::string::npos)
                    m.replace(at, 17, "--geojson-frame");
                return fail(m, 2);
            }
            auto doc = toGeoJson(idx, source, space.value());
            if (!doc) return fail(doc.error().message, 1);
            json& g = doc.value();
            if (classes)
                for (auto& feature : blockPiecesGeoJson(*model->blocks, *classes, pieces, space.value()))
                    g["features"].push_back(std::move(feature));
            for (auto& feature :
                 api::holesGeoJson(holesModel, holes, space.value().threeD() ? &space.value().position : nullptr))
                g["features"].push_back(std::move(feature));
            if (Status s = space.value().checkPositions(); !s) return fail(s.error().message, 1);
            if (auto legend = api::holeLegendJson(holes.style); !legend.is_null()) g["holeLegend"] = std::move(legend);
            if (Status s = writeText(o->geojson, jsonText(g) + "\n"); !s) return fail(s.error().message, 1);
        }
        if (!o->dxf.empty()) {
            DxfOptions dxfOptions;
            dxfOptions.frame = o->dxfFrame == "projected" ? DxfFrame::Projected : DxfFrame::Plane;
            dxfOptions.labels = !o->noLabels;
            auto dxf = toDxf(idx, source, dxfOptions);
            if (!dxf) return fail(dxf.error().message, 1);
            if (Status s = writeText(o->dxf, dxf.value()); !s) return fail(s.error().message, 1);
        }
        if (!o->svg.empty()) {
            SvgOverlays overlays;
            overlays.labels = o->labels && !o->noLabels;
            overlays.patterns = !o->noPatterns;
            overlays.textWidth = print::labelTextWidth;
            auto svg = toSvg(idx, source, rect, width, height, ro, overlays);
            if (!svg) return fail(svg.error().message, 1);
            if (const auto end = svg.value().rfind("</svg>"); end != std::string::npos)
                svg.value().insert(end, api::holesSvg(holesModel, holes, mapping));
            if (Status s = writeText(o->svg, svg.value()); !s) return fail(s.error().message, 1);
        }
        if (sheetOptions) {
            print::SheetInfo info;
            info.model = std::filesystem::path(o->model).filename().string();
            info.crs = model->crs.isLocal() ? "local metres (no CRS)"
                                            : (model->crs.epsg() > 0 ? "EPSG:" + std::to_string(model->crs.epsg()) + " "
                                                                     : std::string()) +
                                                  model->crs.name();
            info.date = o->date.empty() ? todayUtc() : o->date;
            info.definition = !o->plane.empty()  ? "plane=" + o->plane
                              : !o->line.empty() ? "line=" + o->line
                                                 : "elevation=" + formatNumber(o->elevation);
            if (o->exaggeration != 1.0) info.definition += "&vx=" + formatNumber(o->exaggeration);
            if (classes) {
                info.definition += "&colour=" + o->colour.colour;
                sheetOptions->blocks =
                    print::SheetBlocks{model->blocks.get(), *classes, blockClipRecords(model.value(), *model->blocks)};
            }
            if (!holes.empty())
                sheetOptions->overlay = [&](const print::MapFrame& frame, print::Sheet& sheet) {
                    api::addHolesToSheet(holesModel, holes, frame, sheet);
                };
            auto sheet = polyline ? print::sectionSheet(idx, *lineSection, *sheetOptions, info)
                                  : print::sectionSheet(idx, *section, *sheetOptions, info);
            if (!sheet) return fail(sheet.error().message, sheet.error().code == ErrorCode::OutOfRange ? 2 : 1);
            if (Status s = writeSheet(o->sheet, sheet.value(), o->dpi); !s) return fail(s.error().message, 1);
        }
        if (o->areas) {
            const std::vector<BodySection>& bodies = polyline ? lineSection->bodies : section->bodies;
            const std::size_t traces = polyline ? lineSection->traces.size() : section->traces.size();
            json j = {{"model", o->model}};
            if (polyline) {
                j["axes"] =
                    "world: x easting, y northing, z elevation, metres; u = distance along the line (m), "
                    "v = elevation (m)";
            } else {
                j["plane"] = {section->plane.normal.x, section->plane.normal.y, section->plane.normal.z,
                              section->plane.d};
                j["axes"] = "world: x easting, y northing, z elevation, metres; plane u/v metres from frame.origin";
            }
            j["frame"] = frameJson;
            j["image"] = imageJson;
            j["bodies"] = bodiesJson(model.value(), bodies);
            j["traces"] = traces;
            std::printf("%s\n", jsonText(j, 2).c_str());
        }
    });
}

}  // namespace geoslice::cli
