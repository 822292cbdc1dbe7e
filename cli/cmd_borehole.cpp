// geoslice borehole MODEL (--x X --y Y | --from x,y,z --dir dx,dy,dz [--length L]) [--json]:
// a virtual borehole (section/borehole.hpp). Prints one line per interval (depths along
// the hole from the collar, elevations, record and its attributes) and per surface
// crossed, or with --json one JSON object. World coordinates: x easting, y northing,
// z elevation, metres, the model's CRS.
#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "model/json_text.hpp"
#include "model/loaders.hpp"
#include "section/borehole.hpp"

namespace geoslice::cli {
namespace {

using json = nlohmann::ordered_json;

bool parse3(const std::string& text, glm::dvec3& v) {
    char extra = 0;
    return std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &v.x, &v.y, &v.z, &extra) == 3;
}

std::string recordName(const Model& m, RecordId id) {
    const AttributeRecord* r = m.attributes.find(id);
    return r ? r->name : std::string("(no record)");
}

}  // namespace

void addBorehole(CLI::App& app, int& exitCode) {
    struct Opts {
        std::string model, from, dir;
        double x = NAN, y = NAN, length = INFINITY;
        bool json = false;
        LoadOptions load;
    };
    auto o = std::make_shared<Opts>();
    CLI::App* cmd = app.add_subcommand(
        "borehole",
        "Virtual borehole: the intervals (depth, elevation, record, attributes) along a vertical hole or a ray");
    cmd->add_option("MODEL", o->model, "Model file")->required();
    addLoadOptions(cmd, o->load);
    auto* xOpt = cmd->add_option("--x", o->x, "Easting of a vertical hole (world metres)");
    auto* yOpt = cmd->add_option("--y", o->y, "Northing of a vertical hole (world metres)");
    auto* fromOpt = cmd->add_option("--from", o->from, "Ray origin x,y,z (world metres) instead of --x/--y");
    auto* dirOpt = cmd->add_option("--dir", o->dir, "Ray direction dx,dy,dz (with --from; need not be unit)");
    cmd->add_option("--length", o->length, "Ray length in metres (with --from; default: through the model)");
    xOpt->excludes(fromOpt);
    yOpt->excludes(fromOpt);
    fromOpt->needs(dirOpt);
    cmd->add_flag("--json", o->json, "Print JSON instead of a table");
    cmd->callback([o, &exitCode] {
        auto fail = [&](const std::string& msg, int code) {
            std::fprintf(stderr, "geoslice borehole: %s\n", msg.c_str());
            exitCode = code;
        };
        glm::dvec3 from(0.0), dir(0.0);
        const bool vertical = o->from.empty();
        if (vertical) {
            if (!std::isfinite(o->x) || !std::isfinite(o->y))
                return fail("give --x X --y Y (finite easting and northing) or --from x,y,z --dir dx,dy,dz", 2);
        } else {
            if (!parse3(o->from, from)) return fail("--from \"" + o->from + "\" is not x,y,z (three numbers)", 2);
            if (!parse3(o->dir, dir)) return fail("--dir \"" + o->dir + "\" is not dx,dy,dz (three numbers)", 2);
        }
        auto model = loadModel(o->model, o->load);
        if (!model) return fail(model.error().message, 1);
        if (model->validation.hasErrors())
            std::fprintf(stderr, "geoslice borehole: warning: %s has validation errors; open bodies are skipped\n",
                         o->model.c_str());
        auto tracer = BoreholeTracer::build(model.value());
        if (!tracer) return fail(tracer.error().message, 1);
        auto bh = vertical ? (*tracer)->traceVertical(o->x, o->y) : (*tracer)->traceRay(from, dir, o->length);
        if (!bh) return fail(bh.error().message, bh.error().code == ErrorCode::InvalidArgument ? 2 : 1);
        const Model& m = model.value();
        const Borehole& b = bh.value();
        if (o->json) {
            json j = {{"model", o->model}};
            j.update(boreholeJson(m, b));
            std::printf("%s\n", jsonText(j, 2).c_str());
            return;
        }
        std::printf("hole from (%.3f, %.3f, %.3f) along (%.6f, %.6f, %.6f), %.3f m; collar ", b.origin.x, b.origin.y,
                    b.origin.z, b.direction.x, b.direction.y, b.direction.z, b.length);
        if (std::isfinite(b.collarDepth))
            std::printf("at %.3f m (elevation %.3f m)\n", b.collarDepth, b.collar.z);
        else
            std::printf("none (the hole meets no geology)\n");
        std::printf("%12s %12s %12s %12s  %-8s %s\n", "from_collar", "to_collar", "from_elev", "to_elev", "record",
                    "name / body");
        for (const auto& iv : b.intervals)
            std::printf("%12.3f %12.3f %12.3f %12.3f  %-8u %s / %s\n", iv.fromCollar, iv.toCollar, iv.fromElevation,
                        iv.toElevation, iv.record, recordName(m, iv.record).c_str(), m.bodies[iv.body].name.c_str());
        for (const auto& c : b.crossings)
            std::printf("crosses %s (record %u, %s) at %.3f m below the collar, elevation %.3f m\n",
                        m.surfaces[c.surface].name.c_str(), c.record, recordName(m, c.record).c_str(), c.depthCollar,
                        c.elevation);
        std::set<RecordId> records;
        for (const auto& iv : b.intervals) records.insert(iv.record);
        for (const auto& c : b.crossings) records.insert(c.record);
        for (RecordId id : records)
            if (const AttributeRecord* r = m.attributes.find(id))
                std::printf("record %u: %s\n", id, jsonText(r->toJson()).c_str());
    });
}

}  // namespace geoslice::cli
