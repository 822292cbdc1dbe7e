// A drillhole database as mining software exchanges it: a collar table, a survey table and
// any number of interval tables (lithology, assays), read from CSV, validated, and
// desurveyed into hole paths (docs/drillholes.md).
//
// Conventions (every function here):
//  - world coordinates: x easting, y northing, z elevation up; metres;
//  - depth: measured depth along the hole from the collar, metres, increasing downhole;
//  - azimuth: degrees clockwise from grid north (the CRS's y axis), [0, 360];
//  - dip: degrees from the horizontal, [-90, 90], NEGATIVE DOWN (-90 = straight down).
//    Files whose dip is positive down say so in the sidecar ("dip": "positive_down"); they
//    are converted on reading, so everything in memory is negative down.
//
// Desurvey (desurvey()): the minimum curvature method (the industry default; Sawaryn &
// Thorogood, "A compendium of directional calculations based on the minimum curvature
// method", SPE 84246, 2003). Between stations i and i+1 with unit directions t1, t2 the
// hole follows a circular arc: dogleg beta = acos(t1.t2), ratio factor
// RF = 2/beta * tan(beta/2) (1 when beta -> 0), and
//   P2 = P1 + (MD2 - MD1)/2 * (t1 + t2) * RF.
// Positions between stations lie on that arc (not on the chord). A hole with one station is
// straight along it (tangent method); a hole without survey is straight down, or along the
// collar's azimuth/dip when the collar table gives them. Above the first station the hole is
// straight along the first station's direction; below the last one along the last's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "model/crs/crs.hpp"
#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

enum class DipConvention { NegativeDown, PositiveDown };
const char* dipConventionName(DipConvention d);  // "negative_down" | "positive_down"

// Unit direction of azimuth/dip (degrees; dip negative down) in world axes.
glm::dvec3 drillDirection(double azimuthDeg, double dipDeg);

struct SurveyStation {
    double depth = 0.0;    // m along the hole
    double azimuth = 0.0;  // degrees clockwise from north
    double dip = -90.0;    // degrees, negative down
};

// A desurveyed hole: nodes at the collar (depth 0), at every station and at the total depth
// when it is below the last station. Between two nodes the hole is a circular arc (minimum
// curvature); direction[i] is the unit tangent at node i.
struct HolePath {
    std::vector<double> depth;  // increasing, depth[0] = 0
    std::vector<glm::dvec3> position;
    std::vector<glm::dvec3> direction;
    const char* method = "";  // "minimum curvature", "tangent (one station)", ...

    // World position at `depth` m: on the arc between the nodes around it; straight along the
    // first/last direction outside [depth.front(), depth.back()].
    glm::dvec3 at(double depth) const;
};

// Desurveys one hole from its collar. `stations` sorted by strictly increasing depth, dips
// negative down. Empty stations: straight along `collarDirection` (default straight down).
// `totalDepth` (NaN when unknown) adds a node at the end of the hole.
HolePath desurvey(const glm::dvec3& collar, const std::vector<SurveyStation>& stations,
                  double totalDepth = std::numeric_limits<double>::quiet_NaN(),
                  const glm::dvec3& collarDirection = glm::dvec3(0.0, 0.0, -1.0));

// One problem in the database, never a silent drop: the file, its row (the header is row 1;
// 0 = the file as a whole), the hole (empty when the row has none) and what was done.
struct DrillholeIssue {
    std::string file;
    std::size_t row = 0;
    std::string hole;
    std::string message;
    std::string text() const;  // "survey.csv row 12, hole 'DH-1': ..."
};

// How one column of a table was read: `role` is hole, x, y, z, total_depth, depth, azimuth,
// dip, from, to; "column" for an interval table's kept data column; "ignored" otherwise.
// `how`: "recognised" (a common spelling), "sidecar" (named in the sidecar), "" (ignored/kept).
struct ColumnUse {
    std::string header;  // as in the file (BOM removed)
    std::string role;
    std::string how;
};

struct DrillholeTableInfo {
    std::string kind;  // "collar", "survey", "interval"
    std::string name;  // the table's name (interval tables: the sidecar's name or the file stem)
    std::string file;
    std::size_t rows = 0;      // data rows in the file
    std::size_t rowsUsed = 0;  // rows that went into the database
    std::vector<ColumnUse> columns;
    std::optional<DipConvention> dip;  // collar and survey tables
};

// A data column of an interval table: numeric when every non-blank cell is a finite number.
struct IntervalColumn {
    std::string name;
    std::string unit;  // from the sidecar, or the name's suffix (_pct -> %, _ppm -> ppm)
    bool numeric = false;
    std::vector<double> numbers;     // numeric: NaN for a blank cell
    std::vector<std::string> texts;  // text: "" for a blank cell
};

// An interval table, rows sorted by hole (database order) then from.
struct IntervalTable {
    std::string name;
    std::string file;
    std::vector<std::uint32_t> hole;  // index into DrillholeDatabase::holes
    std::vector<double> from, to;     // m along the hole, from < to
    std::vector<std::uint32_t> row;   // the file row each interval came from
    std::vector<IntervalColumn> columns;
    std::size_t size() const { return from.size(); }
};

struct Drillhole {
    std::string id;
    glm::dvec3 collar{0.0};
    double totalDepth = std::numeric_limits<double>::quiet_NaN();  // NaN: not in the collar table
    std::optional<SurveyStation> collarSurvey;                     // the collar table's azimuth/dip, if any
    std::vector<SurveyStation> stations;                           // validated, strictly increasing depth
    HolePath path;
};

// The sidecar's "units": which interval column holds the codes that are compared with the
// model's units (the model checked against its holes, api/drillhole_check.hpp) and how codes
// map to units. {"table": "lithology", "column": "lith", "map": {"SST": "Sandstone"}}; every
// key optional. Without a map a code names a unit itself (case-insensitive).
struct DrillholeUnitMap {
    std::string table;   // an interval table's name; empty: the first table holding `column`
    std::string column;  // empty: the first text column named like a lithology code
    std::vector<std::pair<std::string, std::string>> map;  // code -> unit, sorted by code
};

struct DrillholeDatabase {
    std::string source;  // the sidecar or folder it was loaded from
    std::string crs;     // the sidecar's "crs"; empty when not stated
    // Set by placeDrillholes when the holes were converted to the model's CRS: from what, to
    // what, by which PROJ operation.
    std::string conversion;
    std::optional<DrillholeUnitMap> units;  // the sidecar's "units", when given
    std::vector<Drillhole> holes;           // collar table order
    std::vector<IntervalTable> intervals;
    std::vector<DrillholeTableInfo> tables;  // collar, survey (when any), interval tables
    std::vector<DrillholeIssue> warnings;
    std::unordered_map<std::string, std::uint32_t> index;  // hole id -> index into holes

    std::size_t stationCount() const;
    const Drillhole* find(std::string_view id) const;
};

// One table to read: CSV text (a UTF-8 BOM is allowed), the name used in messages, and the
// sidecar's explicit column mapping (role -> header, case-insensitive) and dip convention.
struct DrillholeTableSource {
    std::string name;
    std::string file;
    std::string text;
    std::vector<std::pair<std::string, std::string>> columns;  // role -> header
    std::vector<std::pair<std::string, std::string>> units;    // data column -> unit
    DipConvention dip = DipConvention::NegativeDown;
};

struct DrillholeSources {
    std::string source;
    std::string crs;
    std::optional<DrillholeUnitMap> units;
    DrillholeTableSource collar;
    std::optional<DrillholeTableSource> survey;
    std::vector<DrillholeTableSource> intervals;
};

// Reads, validates and desurveys. Rows that cannot be used are skipped with a warning that
// names file, row and hole; an error only when the collar table has no usable hole (or its
// hole/x/y/z columns cannot be found).
Result<DrillholeDatabase> buildDrillholes(DrillholeSources sources);

// From a sidecar JSON (docs/drillholes.md: "collar", "survey", "intervals", "crs", "dip",
// per-table "file", "columns", "units", "dip"; files relative to the sidecar) or from a
// folder (collar.csv, survey.csv, every other *.csv an interval table).
Result<DrillholeDatabase> loadDrillholes(const std::string& path);

// The holes in the model's CRS: when the sidecar states a "crs" other than the model's, every
// collar and desurveyed node is converted through PROJ (one operation for the model's area,
// model/crs/crs.hpp CrsTransform; elevations kept) and the directions turned with the grid
// (each node's direction is the converted step of 10 m along it); `conversion` says how. No
// "crs", or the model's own: nothing to do. A model without a CRS takes the holes' coordinates
// as its own (a warning says so). Errors: the "crs" PROJ does not know, or no operation between
// the two (named).
Status placeDrillholes(DrillholeDatabase& db, const Crs& modelCrs, const Aabb& modelBounds);

// "<folder>/<stem>.drillholes.json" beside a model file when that file exists, else "".
std::string drillholeSidecarFor(const std::string& modelPath);

}  // namespace geoslice
