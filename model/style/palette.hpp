// The default colours of a model that names none: a categorical fill palette for bodies,
// stable by unit name, and dark line colours for faults and other surfaces. One place for
// every view (sections, tiles, 3D, legends, print): the colours are written into the
// attribute records, which all of them read.
//
// A unit's colour is the palette entry its normalised name hashes to (lower case, runs of
// anything but letters and digits made one space, trimmed: "Upper_Sandstone" and
// "upper sandstone" are one unit), so the same name gets the same colour in every model and
// session. Names of one model that hash to the same entry are resolved deterministically: in
// order of normalised name, each takes the next free entry after its own, so the units of a
// model of up to kFillPaletteSize names all differ. More names than that reuse entries,
// darkened or lightened per round.
//
// Fills are light (CIELAB L* 55..92) and coloured; lines are dark (L* < 35), so a fault trace
// never looks like a fill. The palette comes from scripts/make_palette.py (greedy max-min
// CIEDE2000 in normal vision and under protanopia and deuteranopia, Machado et al. 2009).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "model/attributes.hpp"

namespace geoslice {

struct Model;

constexpr std::size_t kFillPaletteSize = 16;
// The fill palette, in the order scripts/make_palette.py chose it.
const Rgba8* fillPalette();
// Line colours: faults, and other surfaces (horizons, boundaries, terrain).
constexpr Rgba8 kFaultLineColour{0x1a, 0x1a, 0x1a, 0xff};
constexpr Rgba8 kSurfaceLineColour{0x2c, 0x3e, 0x50, 0xff};

// "Upper_Sandstone (T3)" -> "upper sandstone t3". Bytes >= 0x80 (UTF-8) are kept as letters.
std::string normaliseUnitName(std::string_view name);
// FNV-1a of the normalised name: the palette entry a unit prefers is this mod kFillPaletteSize.
std::uint32_t unitNameHash(std::string_view name);
// Entry `slot` (any size_t): slot % kFillPaletteSize, changed per round slot / kFillPaletteSize.
Rgba8 fillColourOf(std::size_t slot);

// Whether a record with this kind and name is drawn as a line (a fault or other surface)
// when no part says otherwise.
bool isFaultRecord(const AttributeRecord& r);

// Gives every record whose colour nobody chose (colourSource empty or "palette") its default
// colour: fills for records of bodies (and of nothing, unless their kind is a surface kind),
// line colours for records only surfaces and lines use. Idempotent; loaders call it last
// (finishLoadedModel, and again after a sidecar is merged).
void applyDefaultColours(Model& model);

}  // namespace geoslice
