// The geoslice executable's subcommands. Each add* registers one subcommand on `app`;
// its callback stores the process exit code in `exitCode` (0 ok, 1 failure, 2 usage).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "model/loaders.hpp"
#include "model/plane.hpp"
#include "model/result.hpp"
#include "section/block_section.hpp"

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

// Options that reach the model readers, for every command that loads a model file:
// --region-array NAME (.vtu: the cell-data array that names each cell's formation).
void addLoadOptions(CLI::App* cmd, LoadOptions& options);

// --colour PROP, --breaks a,b,.. and --ramp NAME: a block-model colouring, as HTTP's colour=,
// breaks= and ramp= (section and render). `colourHelp` describes --colour for the command.
struct ColourOptions {
    std::string colour, ramp = "viridis";
    std::vector<double> breaks;  // empty: 5 equal classes
};
void addColourOptions(CLI::App* cmd, ColourOptions& options, const std::string& colourHelp);
// The classes `options` ask for on `model`'s block model; nullopt without --colour. Errors
// (InvalidArgument, starting "--colour: "): no block model, an unknown property (the known
// ones listed), bad breaks or ramp.
Result<std::optional<PropertyClasses>> colourClasses(const Model& model, const ColourOptions& options);

// A --plane value "a,b,c,d" (four finite numbers, (a, b, c) not zero) -> a unit plane.
// Errors name the flag and the text.
Result<Plane> parsePlaneFlag(const std::string& text);

}  // namespace geoslice::cli
