// The demo mine's drillholes: a deterministic drillhole database drilled through a synthetic
// model (model/synthetic/synthetic.hpp), logged with the model's own units, so that sections
// of the demo show holes whose logs can be checked against the model.
//
// Layout (world metres, from the model's bounds): 24 vertical holes on a jittered 6 x 4 grid
// over the inner 80 % of the map extent (its third row a fence within 20 m of the middle
// northing, on the default east-west section), and 8 deviated holes near the centre, collared at
// -60 degrees and curving (azimuth drifting 40 degrees and steepening to about -80 over
// their length; survey stations every 30 m). Each hole starts on the model's top surface
// (`topAt`) and ends 70 % of the way down to the model's base.
// Tables (as CSV text read back through buildDrillholes, so the demo exercises the reader):
//   collar   hole_id, x, y, z, total_depth
//   survey   hole_id, depth, azimuth, dip (negative down)
//   lith     hole_id, from, to, code, unit -- runs of one model record along the hole (sampled
//            every metre by `recordAt`), `unit` the record's name, `code` its age symbol
//            (e.g. "T3x"; "ORE" for the orebody). Deliberate disagreements with the model:
//            in holes DDH-04, DDH-12 and DDH-20 the second interval is logged as the unit of
//            the third (when the hole has three), the logging errors a check should find.
//   assay    hole_id, from, to, SiO2_pct -- 10 m samples, values drawn around a level per unit.
// Same seed, same database. Pure function; the callbacks are called from this thread only.
#pragma once

#include <cstdint>
#include <functional>

#include <glm/vec3.hpp>

#include "model/drillholes/drillholes.hpp"
#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

struct SyntheticHoleSources {
    DrillholeSources sources;
    std::vector<std::string> disagreements;  // "DDH-04 12-30 m: logged T1j, model T3x", ...
};

// `topAt(x, y)`: elevation of the model's top at a map point (NaN: none there);
// `recordAt(p)`: the record of the body at world point p (kNoRecord outside every body).
SyntheticHoleSources syntheticHoleSources(const Model& model, const std::function<double(double, double)>& topAt,
                                          const std::function<RecordId(const glm::dvec3&)>& recordAt,
                                          std::uint64_t seed = 1);

}  // namespace geoslice
