// geoslice reserves MODEL [--plane a,b,c,d] [--json]: volume (m³, gross and net of nested
// bodies), tonnage (t) and metal of every closed body, whole or on the kept side of a plane
// (section/reserves.hpp says how and in which units; api/reserves.hpp lays out the JSON,
// which GET /v1/models/{id}/reserves serves too).
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "api/reserves.hpp"
#include "cli/commands.hpp"
#include "model/json_text.hpp"
#include "model/loaders.hpp"
#include "section/block_reserves.hpp"
#include "section/reserves.hpp"

namespace geoslice::cli {

void addReserves(CLI::App& app, int& exitCode) {
    struct Opts {
        std::string model, plane, property;
        std::vector<double> cutoffs;
        bool json = false, csv = false;
        LoadOptions load;
    };
    auto o = std::make_shared<Opts>();
    CLI::App* cmd = app.add_subcommand(
        "reserves", "Volume, tonnage and metal of every closed body, whole or on the kept side of a plane");
    cmd->add_option("MODEL", o->model, "Model file")->required();
    addLoadOptions(cmd, o->load);
    cmd->add_option("--plane", o->plane, "Plane a,b,c,d (world metres): count only what lies where a*x+b*y+c*z+d >= 0");
    cmd->add_flag("--json", o->json, "Print JSON instead of a table");
    cmd->add_flag("--csv", o->csv, "Print CSV (the body table; with --cutoffs the grade-tonnage table)");
    cmd->add_option("--cutoffs", o->cutoffs,
                    "Grade-tonnage table of the block model's clipping bodies at these cut-offs (comma-separated, "
                    "increasing)")
        ->delimiter(',');
    cmd->add_option("--property", o->property,
                    "The block property of the grade-tonnage table (default: the first not named density)");
    cmd->callback([o, &exitCode] {
        auto fail = [&](const std::string& msg, int code) {
            std::fprintf(stderr, "geoslice reserves: %s\n", msg.c_str());
            exitCode = code;
        };
        std::optional<Plane> plane;
        if (!o->plane.empty()) {
            auto p = parsePlaneFlag(o->plane);
            if (!p) return fail(p.error().message, 2);
            plane = p.value();
        }
        auto model = loadModel(o->model, o->load);
        if (!model) return fail(model.error().message, 1);
        const Model& m = model.value();
        auto r = computeReserves(m, plane);
        if (!r) return fail(r.error().message, 1);
        if (r->skippedOpenBodies)
            std::fprintf(stderr, "geoslice reserves: warning: %zu bodies are not closed shells and have no volume\n",
                         r->skippedOpenBodies);
        if (o->json && o->csv) return fail("--json and --csv exclude each other", 2);
        std::optional<GradeTonnage> table;
        if (!o->cutoffs.empty() || !o->property.empty()) {
            if (o->cutoffs.empty()) return fail("--property needs --cutoffs", 2);
            auto property = api::gradeProperty(m, o->property);
            if (!property) return fail(property.error().message, 1);
            auto t = computeGradeTonnage(m, property.value(), o->cutoffs, plane);
            if (!t) return fail(t.error().message, 2);
            table = std::move(t.value());
        }
        if (o->json) {
            auto doc = api::reservesJson(m, r.value(), o->model);
            if (table) doc["grade_tonnage"] = api::gradeTonnageJson(m, *table);
            std::printf("%s\n", jsonText(doc, 2).c_str());
            return;
        }
        if (o->csv) {
            std::fputs((table ? api::gradeTonnageCsv(m, *table) : api::reservesCsv(m, r.value())).c_str(), stdout);
            return;
        }
        if (r->plane)
            std::printf("kept side of plane (%.9g, %.9g, %.9g, %.9g)\n", r->plane->normal.x, r->plane->normal.y,
                        r->plane->normal.z, r->plane->d);
        std::printf("%-44s %8s %16s %16s %14s %14s\n", "body", "record", "gross_m3", "net_m3", "tonnage_t", "metal");
        for (const BodyReserves& b : r->bodies) {
            char tonnage[32] = "-", metal[64] = "-";
            if (b.tonnage) std::snprintf(tonnage, sizeof tonnage, "%.6g", *b.tonnage);
            if (b.metal) std::snprintf(metal, sizeof metal, "%.6g %s", *b.metal, b.metalUnit.c_str());
            std::printf("%-44s %8u %16.6g %16.6g %14s %14s\n", m.bodies[b.body].name.c_str(), b.record, b.grossVolume,
                        b.netVolume, tonnage, metal);
        }
        if (!table) return;
        std::printf("\ngrade-tonnage of %s%s (cells >= cut-off; exact cell x body volumes%s)\n",
                    table->property.c_str(), table->unit.empty() ? "" : (" [" + table->unit + "]").c_str(),
                    table->plane ? "; kept side of the plane" : "");
        std::printf("%-32s %12s %10s %16s %14s %12s %16s\n", "body", "cutoff", "cells", "volume_m3", "tonnage_t",
                    "mean_grade", "metal");
        for (const BodyGradeTonnage& b : table->bodies)
            for (const GradeTonnageRow& row : b.rows) {
                char tonnage[32] = "-", grade[32] = "-", metal[64] = "-";
                if (row.tonnage) std::snprintf(tonnage, sizeof tonnage, "%.6g", *row.tonnage);
                if (row.meanGrade) std::snprintf(grade, sizeof grade, "%.6g", *row.meanGrade);
                if (row.metal) std::snprintf(metal, sizeof metal, "%.6g %s", *row.metal, row.metalUnit.c_str());
                std::printf("%-32s %12.6g %10zu %16.6g %14s %12s %16s\n", m.bodies[b.body].name.c_str(), row.cutoff,
                            row.cells, row.volume, tonnage, grade, metal);
            }
    });
}

}  // namespace geoslice::cli
