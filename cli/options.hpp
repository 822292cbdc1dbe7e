// The flags and readers the subcommands share: load options, block-model colouring, and
// the one way the CLI reads numbers and planes from a flag.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "model/io/loaders.hpp"
#include "model/result.hpp"
#include "section/blocks/block_section.hpp"
#include "view/plane.hpp"

namespace geoslice::cli {

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

// Numbers given to a flag as "a,b,..." (`count` of them, 0 = any), read by the reader
// HTTP's parameters use (api/params.hpp), so the CLI refuses what HTTP refuses; errors name
// the flag and the text.
Result<std::vector<double>> parseNumbersFlag(const std::string& flag, const std::string& text, std::size_t count);
// A --plane value "a,b,c,d" (four finite numbers, (a, b, c) not zero) -> a unit plane.
// Errors name the flag and the text.
Result<Plane> parsePlaneFlag(const std::string& text);

}  // namespace geoslice::cli
