// geoslice: one executable, one subcommand per task (generate, info, coords, classify...).
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"
#include "model/version.hpp"

int main(int argc, char** argv) {
    CLI::App app{"geoslice: cut 3D geological models with planes and serve the sections"};
    app.require_subcommand(1);
    app.set_version_flag("--version", geoslice::kGeneratorName);
    int exitCode = 0;
    geoslice::cli::addGenerate(app, exitCode);
    geoslice::cli::addInfo(app, exitCode);
    geoslice::cli::addCoords(app, exitCode);
    geoslice::cli::addClassify(app, exitCode);
    geoslice::cli::addSection(app, exitCode);
    geoslice::cli::addRender(app, exitCode);
    geoslice::cli::addBorehole(app, exitCode);
    geoslice::cli::addReserves(app, exitCode);
    geoslice::cli::addBake(app, exitCode);
    geoslice::cli::addServe(app, exitCode);
    geoslice::cli::addQuery(app, exitCode);
    geoslice::cli::addHoles(app, exitCode);
    geoslice::cli::addTiles3d(app, exitCode);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "geoslice: error: %s\n", e.what());
        return 1;
    }
    return exitCode;
}
