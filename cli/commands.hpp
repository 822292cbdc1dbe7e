// The geoslice executable's subcommands. Each add* registers one subcommand on `app`;
// its callback stores the process exit code in `exitCode` (0 ok, 1 failure, 2 usage).
#pragma once

#include <CLI/CLI.hpp>

#include "cli/options.hpp"

namespace geoslice::cli {

void addGenerate(CLI::App& app, int& exitCode);
void addInfo(CLI::App& app, int& exitCode);
void addCoords(CLI::App& app, int& exitCode);
void addClassify(CLI::App& app, int& exitCode);
void addSection(CLI::App& app, int& exitCode);
void addRender(CLI::App& app, int& exitCode);
void addBorehole(CLI::App& app, int& exitCode);
void addReserves(CLI::App& app, int& exitCode);
void addBake(CLI::App& app, int& exitCode);
void addServe(CLI::App& app, int& exitCode);
void addQuery(CLI::App& app, int& exitCode);
void addHoles(CLI::App& app, int& exitCode);
void addTiles3d(CLI::App& app, int& exitCode);

}  // namespace geoslice::cli
