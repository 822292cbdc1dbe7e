// `geoslice coords`: convert points between any two CRSs (EPSG codes, names, WKT), line by
// line, like PROJ's cs2cs, in geoslice's axis order (easting northing / lon lat).
#include <charconv>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "cli/commands.hpp"
#include "model/crs/crs.hpp"

namespace geoslice::cli {
namespace {

struct CoordsOptions {
    std::string from;
    std::string to;
};

constexpr const char* kCoordsFooter =
    R"(CRSs: "EPSG:<code>" or "<code>" (any geographic or projected CRS in PROJ's EPSG
database), a CRS name PROJ knows ("CH1903 / LV03", "NAD27 / UTM zone 11N"), an OGC URN,
WKT, or "local". CGCS2000 (EPSG:4490) and its Gauss-Kruger CRSs (EPSG:4491-4554) go
through GeographicLib, everything else through PROJ (local database and grids only).
Input (stdin): one point per line, "x y [z]", separated by spaces or tabs, in geoslice's
API axis order, NOT EPSG's axis order:
  geographic CRSs   lon lat [h]            (degrees east, degrees north, metres)
  projected CRSs    easting northing [z]   (the CRS's unit: metres, or feet for a few)
(cs2cs takes EPSG's order, e.g. "lat lon" for EPSG:4326 and "northing easting" for
EPSG:4523; `cs2cs -r -s` would take and print ours for those.)
Heights pass through unchanged unless both CRSs are 3D.
Output (stdout): the converted point, tab separated; metres (or feet) with 6 decimals,
degrees with 10 decimals. Blank lines and lines starting with '#' are copied through. A
line that cannot be converted prints "*<TAB>*", its number and reason go to stderr,
conversion goes on, and the exit code is 1. A point outside either CRS's area of use is
converted with a warning on stderr. When PROJ knows only a "ballpark" transformation
between the two datums (no stated accuracy, errors of metres to hundreds of metres),
a warning says so before any output. An unknown --from/--to gives exit code 2.
Example: echo "2600000 1200000" | geoslice coords --from EPSG:2056 --to EPSG:4326
)";

std::string_view trimView(std::string_view s) {
    const char* ws = " \t\r\n\f\v";
    const auto b = s.find_first_not_of(ws);
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(ws) - b + 1);
}

// Splits on spaces and tabs.
std::vector<std::string_view> splitFields(std::string_view s) {
    std::vector<std::string_view> out;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
        size_t j = i;
        while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
        if (j > i) out.push_back(s.substr(i, j - i));
        i = j;
    }
    return out;
}

bool parseNumber(std::string_view s, double& v) {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars rejects a leading '+'
    const char* last = s.data() + s.size();
    auto [ptr, ec] = std::from_chars(s.data(), last, v);
    return !s.empty() && ec == std::errc() && ptr == last;
}

// Parses "x y [z]" and converts it; on failure `error` says why.
bool convertLine(std::string_view line, const Crs& from, const Crs& to, glm::dvec3& out, bool& hasZ, std::string& error,
                 std::string& warning) {
    const auto fields = splitFields(line);
    if (fields.size() != 2 && fields.size() != 3) {
        error = "expected 2 or 3 numbers (x y [z]), got " + std::to_string(fields.size()) + " fields";
        return false;
    }
    glm::dvec3 p(0.0);
    for (size_t i = 0; i < fields.size(); ++i) {
        if (!parseNumber(fields[i], p[static_cast<glm::length_t>(i)])) {
            error = "field " + std::to_string(i + 1) + " \"" + std::string(fields[i]) + "\" is not a number";
            return false;
        }
    }
    hasZ = fields.size() == 3;
    auto r = convertPoint(from, to, p, &warning);
    if (!r) {
        error = r.error().message;
        return false;
    }
    out = r.value();
    return true;
}

int runCoords(const CoordsOptions& opt) {
    auto from = Crs::parse(opt.from);
    if (!from) {
        std::fprintf(stderr, "geoslice coords: --from: %s\n", from.error().message.c_str());
        return 2;
    }
    auto to = Crs::parse(opt.to);
    if (!to) {
        std::fprintf(stderr, "geoslice coords: --to: %s\n", to.error().message.c_str());
        return 2;
    }
    if (from->isLocal() != to->isLocal()) {
        std::fprintf(stderr,
                     "geoslice coords: cannot convert between %s and %s: a local CRS has no "
                     "georeference\n",
                     from->id().c_str(), to->id().c_str());
        return 2;
    }
    if (!from->isLocal() && *from != *to) {
        auto ops = summariseOperations(*from, *to);
        if (ops && ops->onlyBallpark)
            std::fprintf(stderr,
                         "geoslice coords: warning: PROJ knows only a ballpark transformation from %s to %s (%s): "
                         "the datum shift is not applied, results can be off by metres to hundreds of metres\n",
                         from->name().c_str(), to->name().c_str(), ops->bestName.c_str());
    }
    // Degrees to 1e-10 (about 0.01 mm on the ground); metres to 1e-6 (1 um).
    const char* xyFormat = to->isGeographic() ? "%.10f\t%.10f" : "%.6f\t%.6f";
    int failures = 0;
    long lineNo = 0;
    std::string line;
    while (std::getline(std::cin, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const std::string_view body = trimView(line);
        if (body.empty() || body.front() == '#') {
            std::printf("%s\n", line.c_str());
            continue;
        }
        glm::dvec3 q(0.0);
        bool hasZ = false;
        std::string error, warning;
        if (!convertLine(body, *from, *to, q, hasZ, error, warning)) {
            std::fprintf(stderr, "geoslice coords: line %ld \"%s\": %s\n", lineNo, line.c_str(), error.c_str());
            std::printf("*\t*\n");
            ++failures;
            continue;
        }
        if (!warning.empty()) std::fprintf(stderr, "geoslice coords: line %ld: warning: %s\n", lineNo, warning.c_str());
        std::printf(xyFormat, q.x, q.y);
        if (hasZ) std::printf("\t%.6f", q.z);
        std::printf("\n");
    }
    std::fflush(stdout);
    if (failures > 0) {
        std::fprintf(stderr, "geoslice coords: %d of %ld lines failed\n", failures, lineNo);
        return 1;
    }
    return 0;
}

}  // namespace

void addCoords(CLI::App& app, int& exitCode) {
    auto opt = std::make_shared<CoordsOptions>();
    CLI::App* sub = app.add_subcommand(
        "coords",
        "Convert points between two CRSs (any EPSG code, a CRS name, WKT), stdin to stdout, like cs2cs "
        "but in easting/northing and lon/lat order");
    sub->add_option("--from", opt->from, "source CRS: EPSG:<code>, a CRS name, WKT, or local")->required();
    sub->add_option("--to", opt->to, "target CRS: EPSG:<code>, a CRS name, WKT, or local")->required();
    sub->footer(kCoordsFooter);
    sub->callback([opt, &exitCode] { exitCode = runCoords(*opt); });
}

}  // namespace geoslice::cli
