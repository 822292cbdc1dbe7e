// geoslice section MODEL (--plane a,b,c,d | --elevation z) [--size WxH] [--out F.ppm|F.pgm]...
// [--areas]: the exact section engine from the command line. Writes the colour image as
// binary PPM (composited over white) and the ID buffer as 16-bit binary PGM (record ids,
// big-endian, 0 = none); --areas prints JSON (plane, section frame, pixel -> world
// transform, area of each body in m², trace count) on stdout.
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "model/loaders.hpp"
#include "section/contours.hpp"
#include "section/raster.hpp"
#include "section/section_index.hpp"

namespace geoslice::cli {
namespace {

using json = nlohmann::ordered_json;

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Status writePpm(const std::string& path, const SectionImage& img) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return makeError(ErrorCode::IoError, "cannot open " + path + " for writing");
    const int W = img.frame.width, H = img.frame.height;
    std::fprintf(f, "P6\n%d %d\n255\n", W, H);
    std::vector<std::uint8_t> rgb(std::size_t(W) * std::size_t(H) * 3);
    for (std::size_t i = 0; i < std::size_t(W) * std::size_t(H); ++i) {
        const std::uint8_t* p = &img.rgba[4 * i];
        const unsigned a = p[3];
        for (int c = 0; c < 3; ++c)
            rgb[3 * i + std::size_t(c)] = static_cast<std::uint8_t>((p[c] * a + 255 * (255 - a) + 127) / 255);
    }
    const bool ok = std::fwrite(rgb.data(), 1, rgb.size(), f) == rgb.size();
    if (std::fclose(f) != 0 || !ok) return makeError(ErrorCode::IoError, "cannot write " + path);
    return {};
}

Status writePgm16(const std::string& path, const SectionImage& img) {
    std::vector<std::uint8_t> data(img.ids.size() * 2);
    for (std::size_t i = 0; i < img.ids.size(); ++i) {
        if (img.ids[i] > 65535)
            return makeError(ErrorCode::OutOfRange,
                             "record id " + std::to_string(img.ids[i]) + " does not fit a 16-bit PGM (" + path + ")");
        data[2 * i] = static_cast<std::uint8_t>(img.ids[i] >> 8);
        data[2 * i + 1] = static_cast<std::uint8_t>(img.ids[i] & 0xFF);
    }
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return makeError(ErrorCode::IoError, "cannot open " + path + " for writing");
    std::fprintf(f, "P5\n%d %d\n65535\n", img.frame.width, img.frame.height);
    const bool ok = std::fwrite(data.data(), 1, data.size(), f) == data.size();
    if (std::fclose(f) != 0 || !ok) return makeError(ErrorCode::IoError, "cannot write " + path);
    return {};
}

json vec3(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

}  // namespace

void addSection(CLI::App& app, int& exitCode) {
    struct Opts {
        std::string model, plane, size = "1024x1024", frame;
        std::vector<std::string> outs;
        double elevation = NAN;
        bool areas = false;
        unsigned threads = 1;
    };
    auto o = std::make_shared<Opts>();
    CLI::App* cmd = app.add_subcommand(
        "section", "Exact section of a model by a plane (CPU): colour image, record-id image and areas per body");
    cmd->add_option("MODEL", o->model, "Model file")->required();
    auto* planeOpt = cmd->add_option("--plane", o->plane,
                                     "Plane a,b,c,d in world coordinates (x east, y north, z up, metres); "
                                     "points with a*x+b*y+c*z+d >= 0 are kept");
    auto* elevOpt =
        cmd->add_option("--elevation", o->elevation, "Horizontal slice at this elevation (m), seen from above");
    planeOpt->excludes(elevOpt);
    cmd->add_option("--size", o->size, "Image size WxH in pixels (default 1024x1024)");
    cmd->add_option("--frame", o->frame,
                    "Frame u0,u1,v0,v1 in plane metres (default: the section's extent); same meaning as in render");
    cmd->add_option("--out", o->outs, "Output file, repeatable: .ppm = colour, .pgm = record ids (16-bit)");
    cmd->add_flag("--areas", o->areas, "Print JSON with the section frame and each body's area (m^2) on stdout");
    cmd->add_option("--threads", o->threads, "Threads for the cut: 1 or 2 (default 1)");
    cmd->callback([o, &exitCode] {
        auto fail = [&](const std::string& msg, int code) {
            std::fprintf(stderr, "geoslice section: %s\n", msg.c_str());
            exitCode = code;
        };
        Plane plane;
        if (!o->plane.empty()) {
            double v[4];
            char extra = 0;
            if (std::sscanf(o->plane.c_str(), "%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &extra) != 4)
                return fail("--plane \"" + o->plane + "\" is not a,b,c,d (four numbers)", 2);
            auto p = makePlane(v[0], v[1], v[2], v[3]);
            if (!p) return fail("--plane: " + p.error().message, 2);
            plane = p.value();
        } else if (std::isfinite(o->elevation)) {
            plane = horizontalPlane(o->elevation);
        } else {
            return fail("give --plane a,b,c,d or --elevation z (a finite number)", 2);
        }
        int width = 0, height = 0;
        char extra = 0;
        if (std::sscanf(o->size.c_str(), "%dx%d%c", &width, &height, &extra) != 2)
            return fail("--size \"" + o->size + "\" is not WxH", 2);
        if (Status s = checkFrame(FrameRect{}, width, height); !s) return fail("--size: " + s.error().message, 2);
        std::optional<FrameRect> givenFrame;
        if (!o->frame.empty()) {
            FrameRect r;
            if (std::sscanf(o->frame.c_str(), "%lf,%lf,%lf,%lf%c", &r.u0, &r.u1, &r.v0, &r.v1, &extra) != 4)
                return fail("--frame \"" + o->frame + "\" is not u0,u1,v0,v1 (four numbers, plane metres)", 2);
            if (Status s = checkFrame(r, width, height); !s) return fail("--frame: " + s.error().message, 2);
            givenFrame = r;
        }
        for (const auto& out : o->outs)
            if (!endsWith(out, ".ppm") && !endsWith(out, ".pgm"))
                return fail("--out \"" + out + "\": the extension must be .ppm (colour) or .pgm (record ids)", 2);
        if (o->threads < 1 || o->threads > 2) return fail("--threads must be 1 or 2", 2);

        auto model = loadModel(o->model);
        if (!model) return fail(model.error().message, 1);
        if (model->validation.hasErrors())
            std::fprintf(stderr, "geoslice section: warning: %s has validation errors; contours may stay open\n",
                         o->model.c_str());
        auto index = buildSectionIndex(model.value());
        if (!index) return fail(index.error().message, 1);
        SectionOptions so;
        so.threads = o->threads;
        auto section = computeSection(*index.value(), plane, so);
        if (!section) return fail(section.error().message, 1);
        const FrameRect rect = givenFrame ? *givenFrame : fitFrame(section.value(), width, height);
        RasterOptions ro;
        ro.background = Rgba8{0, 0, 0, 0};
        auto img = rasterizeSection(*index.value(), section.value(), rect, width, height, ro);
        if (!img) return fail(img.error().message, 1);
        for (const auto& out : o->outs) {
            Status s = endsWith(out, ".ppm") ? writePpm(out, img.value()) : writePgm16(out, img.value());
            if (!s) return fail(s.error().message, 1);
        }
        if (o->areas) {
            const Section& s = section.value();
            const PixelFrame& f = img->frame;
            json bodies = json::array();
            for (const BodySection& b : s.bodies) {
                std::size_t holes = 0;
                for (const auto& p : b.polygons) holes += p.holes.size();
                bodies.push_back({{"name", model->bodies[b.part].name},
                                  {"record", b.record},
                                  {"area_m2", b.area},
                                  {"polygons", b.polygons.size()},
                                  {"holes", holes},
                                  {"open_chains", b.openChains}});
            }
            json j = {
                {"model", o->model},
                {"plane", {s.plane.normal.x, s.plane.normal.y, s.plane.normal.z, s.plane.d}},
                {"axes", "world: x easting, y northing, z elevation, metres; plane u/v metres from frame.origin"},
                {"frame", {{"origin", vec3(s.frame.originWorld())}, {"u", vec3(s.frame.u)}, {"v", vec3(s.frame.v)}}},
                {"image",
                 {{"width", width},
                  {"height", height},
                  {"rect_uv", {rect.u0, rect.v0, rect.u1, rect.v1}},
                  {"world_at_pixel_corner_0_0", vec3(f.worldAtCorner())},
                  {"world_per_pixel_x", vec3(f.worldPerPixelX())},
                  {"world_per_pixel_y", vec3(f.worldPerPixelY())}}},
                {"bodies", bodies},
                {"traces", s.traces.size()},
            };
            std::printf("%s\n", j.dump(2).c_str());
        }
    });
}

}  // namespace geoslice::cli
