// geoslice holes check MODEL [--drillholes SIDECAR] [--json | --csv [--contacts]]: the model
// checked against its drillholes (api/drillhole_check.hpp): per hole and per unit the share of
// logged length where the model agrees, and each logged contact's distance to the model's
// nearest contact between the same units along the hole. The database is the
// <stem>.drillholes.json sidecar beside the model, or --drillholes (docs/drillholes.md).
// Exit 1 when the model, the database or the code column cannot be read.
#include <cmath>
#include <cstdio>
#include <string>

#include "api/drillhole_check.hpp"
#include "cli/commands.hpp"
#include "model/io/loaders.hpp"
#include "model/json_text.hpp"
#include "section/rays/borehole.hpp"

namespace geoslice::cli {

void addHoles(CLI::App& app, int& exitCode) {
    struct Opts {
        std::string model, drillholes;
        bool json = false, csv = false, contacts = false;
        LoadOptions load;
    };
    auto o = std::make_shared<Opts>();
    CLI::App* holes = app.add_subcommand("holes", "Drillholes against the model (docs/drillholes.md)");
    holes->require_subcommand(1);
    CLI::App* cmd = holes->add_subcommand(
        "check", "The model checked against its drillholes: agreement per hole and unit, contact distances");
    cmd->add_option("MODEL", o->model, "Model file")->required();
    addLoadOptions(cmd, o->load);
    cmd->add_option(
        "--drillholes", o->drillholes,
        "drillhole database: a sidecar JSON or a folder (default: <stem>.drillholes.json beside the model)");
    auto* jsonFlag = cmd->add_flag("--json", o->json, "Print the JSON document (as HTTP's drillholes/check)");
    auto* csvFlag = cmd->add_flag("--csv", o->csv, "Print CSV: one row per hole and unit");
    cmd->add_flag("--contacts", o->contacts, "With --csv: one row per logged contact instead")->needs(csvFlag);
    jsonFlag->excludes(csvFlag);
    cmd->callback([o, &exitCode] {
        auto fail = [&](const std::string& msg, int code) {
            std::fprintf(stderr, "geoslice holes check: %s\n", msg.c_str());
            exitCode = code;
        };
        const std::string dh = o->drillholes.empty() ? drillholeSidecarFor(o->model) : o->drillholes;
        if (dh.empty())
            return fail("no drillholes: " + o->model +
                            " has no <stem>.drillholes.json beside it; give --drillholes (docs/drillholes.md)",
                        1);
        auto db = loadDrillholes(dh);
        if (!db) return fail(db.error().message, 1);
        auto model = loadModel(o->model, o->load);
        if (!model) return fail(model.error().message, 1);
        if (auto s = placeDrillholes(db.value(), model.value().crs, model.value().bounds()); !s)
            return fail(s.error().message, 1);
        auto tracer = BoreholeTracer::build(model.value());
        if (!tracer) return fail(tracer.error().message, 1);
        auto c = api::checkDrillholes(model.value(), db.value(), *tracer.value());
        if (!c) return fail(c.error().message, 1);
        if (o->csv) {
            std::fputs(api::drillholeCheckCsv(c.value(), o->contacts).c_str(), stdout);
            return;
        }
        const auto j = api::drillholeCheckJson(c.value(), o->model, dh);
        if (o->json) {
            std::printf("%s\n", jsonText(j, 2).c_str());
            return;
        }
        const auto& s = j["summary"];
        auto pct = [](const nlohmann::ordered_json& v) {
            return v.is_null() ? std::string("-") : std::to_string(v.get<double>() * 100.0).substr(0, 6) + " %";
        };
        std::printf("%s against %s: table %s, column %s (%s)\n", o->model.c_str(), dh.c_str(), c->table.c_str(),
                    c->column.c_str(), j["mapping"].get<std::string>().c_str());
        std::printf(
            "holes %zu (traced %zu), logged %.3f m, agreeing %.3f m (%s); contacts %zu, with a model contact %zu",
            s["holes"].get<std::size_t>(), s["holes_traced"].get<std::size_t>(), s["logged_m"].get<double>(),
            s["agreed_m"].get<double>(), pct(s["share"]).c_str(), s["contacts"].get<std::size_t>(),
            s["contacts_found"].get<std::size_t>());
        if (!s["median_abs_distance_m"].is_null())
            std::printf(", median |distance| %.3f m, max %.3f m", s["median_abs_distance_m"].get<double>(),
                        s["max_abs_distance_m"].get<double>());
        std::printf("\n%-24s %12s %12s %9s\n", "unit", "logged_m", "agreed_m", "share");
        for (const auto& u : c->units)
            std::printf(
                "%-24s %12.3f %12.3f %9s%s\n", u.unit.c_str(), u.logged, u.agreed,
                pct(u.logged > 0.0 ? nlohmann::ordered_json(u.agreed / u.logged) : nlohmann::ordered_json()).c_str(),
                u.inModel ? "" : "  (not in the model)");
        for (const auto& w : c->warnings) std::printf("warning: %s\n", w.c_str());
    });
}

}  // namespace geoslice::cli
