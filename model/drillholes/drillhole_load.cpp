// Reading and validating a drillhole database (model/drillholes/drillholes.hpp): CSV tables
// through text::csvRecord, columns recognised by their common spellings or named by the
// sidecar, every skipped or doubtful row reported as a DrillholeIssue.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>

#include <nlohmann/json.hpp>

#include "model/drillholes/drillholes.hpp"
#include "model/io/loaders.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

constexpr double kDepthTolerance = 1e-6;  // m: depths closer than this are equal

// Lower-case letters and digits only: "hole_ID" -> "holeid", "Depth From" -> "depthfrom".
std::string normaliseHeader(std::string_view h) {
    std::string out;
    for (char c : h)
        if ((c >= '0' && c <= '9') || (c >= 'a' && c <= 'z'))
            out += c;
        else if (c >= 'A' && c <= 'Z')
            out += char(c - 'A' + 'a');
    return out;
}

struct RoleSpelling {
    const char* role;
    std::vector<const char*> names;  // normalised (normaliseHeader)
};

// The common spellings of each role, per table kind; the first header matching a role wins.
const std::vector<RoleSpelling>& spellingsFor(std::string_view kind) {
    static const std::vector<const char*> hole = {"holeid",     "hole",       "bhid",      "dhid",        "holename",
                                                  "holeno",     "holenumber", "drillhole", "drillholeid", "borehole",
                                                  "boreholeid", "wellid",     "hid"};
    static const std::vector<const char*> azimuth = {"azimuth", "azi", "azim", "az", "brg", "bearing"};
    static const std::vector<const char*> dip = {"dip", "inclination", "incl", "inc"};
    static const std::vector<RoleSpelling> collar = {
        {"hole", hole},
        {"x", {"x", "east", "easting", "eastings", "xcollar", "collarx", "xcoord", "locationx"}},
        {"y", {"y", "north", "northing", "northings", "ycollar", "collary", "ycoord", "locationy"}},
        {"z", {"z", "rl", "elev", "elevation", "zcollar", "collarz", "zcoord", "collarrl", "locationz"}},
        {"total_depth",
         {"totaldepth", "maxdepth", "depth", "eoh", "eohdepth", "td", "length", "holelength", "finaldepth",
          "enddepth"}},
        {"azimuth", azimuth},
        {"dip", dip}};
    static const std::vector<RoleSpelling> survey = {
        {"hole", hole},
        {"depth", {"depth", "at", "md", "surveydepth", "measureddepth", "distance", "dist"}},
        {"azimuth", azimuth},
        {"dip", dip}};
    static const std::vector<RoleSpelling> interval = {
        {"hole", hole},
        {"from", {"from", "depthfrom", "fromdepth", "mfrom", "fromm", "samplefrom"}},
        {"to", {"to", "depthto", "todepth", "mto", "tom", "sampleto"}}};
    return kind == "collar" ? collar : kind == "survey" ? survey : interval;
}

std::vector<std::string> requiredRoles(std::string_view kind) {
    if (kind == "collar") return {"hole", "x", "y", "z"};
    if (kind == "survey") return {"hole", "depth", "azimuth", "dip"};
    return {"hole", "from", "to"};
}

// A unit from a column name's suffix: Cu_pct -> %, Au_ppm -> ppm.
std::string unitFromName(std::string_view name) {
    const std::string n = text::lower(name);
    auto ends = [&n](std::string_view s) { return n.size() > s.size() && n.ends_with(s); };
    if (ends("_pct")) return "%";
    if (ends("_ppm")) return "ppm";
    if (ends("_ppb")) return "ppb";
    if (ends("_gpt") || ends("_g/t")) return "g/t";
    return "";
}

std::string formatNumber(double v) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

enum class Cell { Blank, Number, Bad };

Cell readCell(const std::vector<std::string>& rec, int column, double& out) {
    out = std::numeric_limits<double>::quiet_NaN();
    if (column < 0 || std::size_t(column) >= rec.size()) return Cell::Blank;
    const std::string_view s = text::trim(rec[std::size_t(column)]);
    if (s.empty()) return Cell::Blank;
    auto v = text::parseDouble(s);
    if (!v || !std::isfinite(*v)) return Cell::Bad;
    out = *v;
    return Cell::Number;
}

std::string cellText(const std::vector<std::string>& rec, int column) {
    if (column < 0 || std::size_t(column) >= rec.size()) return "";
    return std::string(text::trim(rec[std::size_t(column)]));
}

// One CSV table being read: header, column roles, records one at a time with their row.
class TableReader {
public:
    TableReader(const DrillholeTableSource& src, std::string kind, std::vector<DrillholeIssue>& warnings)
        : src_(src), kind_(std::move(kind)), warnings_(warnings) {}

    // Reads the header and assigns roles; false (with a warning or `error`) when a required
    // role has no column.
    bool start(DrillholeTableInfo& info, std::string& error) {
        info.kind = kind_;
        info.name = src_.name;
        info.file = src_.file;
        std::string_view t = src_.text;
        if (t.starts_with("\xEF\xBB\xBF")) pos_ = 3;
        bool badQuote = false;
        header_ = text::csvRecord(t, pos_, badQuote);
        newlines_ = std::size_t(std::count(t.begin(), t.begin() + long(pos_), '\n'));
        for (auto& h : header_) h = std::string(text::trim(h));
        if (header_.size() == 1 && header_[0].empty()) header_.clear();
        info.columns.resize(header_.size());
        for (std::size_t i = 0; i < header_.size(); ++i) info.columns[i].header = header_[i];
        // Explicit mapping first, then the common spellings for roles still open.
        for (const auto& [role, name] : src_.columns) {
            int found = -1;
            for (std::size_t i = 0; i < header_.size() && found < 0; ++i)
                if (text::equalsNoCase(header_[i], name)) found = int(i);
            if (found < 0) {
                error = "the sidecar maps " + role + " to column '" + name + "', which the header does not have (" +
                        headerList() + ")";
                return false;
            }
            roles_[role] = found;
            info.columns[std::size_t(found)].role = role;
            info.columns[std::size_t(found)].how = "sidecar";
        }
        for (const RoleSpelling& r : spellingsFor(kind_)) {
            if (roles_.count(r.role)) continue;
            for (std::size_t i = 0; i < header_.size(); ++i) {
                if (!info.columns[i].role.empty()) continue;
                const std::string n = normaliseHeader(header_[i]);
                if (std::find(r.names.begin(), r.names.end(), n) != r.names.end()) {
                    roles_[r.role] = int(i);
                    info.columns[i].role = r.role;
                    info.columns[i].how = "recognised";
                    break;
                }
            }
        }
        for (auto& c : info.columns)
            if (c.role.empty()) c.role = kind_ == "interval" ? "column" : "ignored";
        for (const std::string& need : requiredRoles(kind_))
            if (!roles_.count(need)) {
                error =
                    "no column for " + need + " (header: " + headerList() + "; name it in the sidecar's \"columns\")";
                return false;
            }
        return true;
    }

    int column(const std::string& role) const {
        auto it = roles_.find(role);
        return it == roles_.end() ? -1 : it->second;
    }
    const std::vector<std::string>& header() const { return header_; }

    // The next data record (blank lines skipped); false at the end.
    bool next(std::vector<std::string>& rec, std::size_t& row) {
        const std::string_view t = src_.text;
        while (pos_ < t.size()) {
            const std::size_t start = pos_;
            bool badQuote = false;
            rec = text::csvRecord(t, pos_, badQuote);
            row = newlines_ + 1;  // the line the record starts on
            newlines_ += std::size_t(std::count(t.begin() + long(start), t.begin() + long(pos_), '\n'));
            if (badQuote) {
                warn(row, "", "a quoted cell is not closed: the rest of the file is skipped");
                pos_ = t.size();
                return false;
            }
            if (rec.size() == 1 && text::trim(rec[0]).empty()) continue;
            ++rows_;
            if (rec.size() > header_.size())
                warn(row, cellText(rec, column("hole")),
                     std::to_string(rec.size()) + " cells but the header has " + std::to_string(header_.size()) +
                         ": the extra cells are ignored");
            return true;
        }
        return false;
    }
    std::size_t rows() const { return rows_; }

    void warn(std::size_t row, std::string hole, std::string message) {
        warnings_.push_back({src_.file, row, std::move(hole), std::move(message)});
    }

private:
    std::string headerList() const {
        std::string s;
        for (const auto& h : header_) s += (s.empty() ? "" : ", ") + text::quoteToken(h);
        return s.empty() ? "empty" : s;
    }

    const DrillholeTableSource& src_;
    std::string kind_;
    std::vector<DrillholeIssue>& warnings_;
    std::vector<std::string> header_;
    std::map<std::string, int> roles_;
    std::size_t pos_ = 0, newlines_ = 0, rows_ = 0;
};

// Rows naming a hole that has no collar: one warning per hole, with its first row and count.
class UnknownHoles {
public:
    void add(const std::string& hole, std::size_t row) {
        auto [it, fresh] = seen_.try_emplace(hole, order_.size());
        if (fresh) order_.push_back({hole, row, 0});
        ++order_[it->second].count;
    }
    void report(TableReader& t, const std::string& collarFile) {
        for (const auto& u : order_)
            t.warn(u.row, u.hole,
                   "no collar for this hole in " + collarFile + ": its " + std::to_string(u.count) + " row" +
                       (u.count == 1 ? "" : "s") + " (first row " + std::to_string(u.row) + ") skipped");
    }

private:
    struct Unknown {
        std::string hole;
        std::size_t row, count;
    };
    std::unordered_map<std::string, std::size_t> seen_;
    std::vector<Unknown> order_;
};

// The hole a survey or interval row belongs to (its index in db.holes), or nullopt for a
// blank id (warned) or an id without a collar (noted in `unknown`, reported once per hole).
std::optional<std::uint32_t> rowHole(TableReader& t, const DrillholeDatabase& db, UnknownHoles& unknown,
                                     const std::string& id, std::size_t row) {
    if (id.empty()) {
        t.warn(row, "", "blank hole id: row skipped");
        return std::nullopt;
    }
    const auto it = db.index.find(id);
    if (it == db.index.end()) {
        unknown.add(id, row);
        return std::nullopt;
    }
    return it->second;
}

const char* cellProblem(Cell c) { return c == Cell::Blank ? "blank" : "not a finite number:"; }

std::string describe(const char* role, Cell c, const std::vector<std::string>& rec, int column,
                     const char* consequence = "row skipped") {
    std::string s = std::string(cellProblem(c));
    if (c == Cell::Bad) s += " " + text::quoteToken(cellText(rec, column));
    return std::string(role) + " cell " + s + ": " + consequence;
}

double signedDip(double dip, DipConvention d) { return d == DipConvention::PositiveDown ? -dip : dip; }

// Azimuth and dip of a row, checked; false with a warning naming the row.
bool readDirection(TableReader& t, const std::vector<std::string>& rec, std::size_t row, const std::string& hole,
                   DipConvention conv, double& azimuth, double& dip, const char* what, const char* consequence) {
    const Cell ca = readCell(rec, t.column("azimuth"), azimuth);
    const Cell cd = readCell(rec, t.column("dip"), dip);
    if (ca != Cell::Number) {
        t.warn(row, hole, std::string(what) + describe("azimuth", ca, rec, t.column("azimuth"), consequence));
        return false;
    }
    if (cd != Cell::Number) {
        t.warn(row, hole, std::string(what) + describe("dip", cd, rec, t.column("dip"), consequence));
        return false;
    }
    if (azimuth < 0.0 || azimuth > 360.0) {
        t.warn(row, hole, std::string(what) + "azimuth " + formatNumber(azimuth) + " outside [0, 360]: " + consequence);
        return false;
    }
    if (dip < -90.0 || dip > 90.0) {
        t.warn(row, hole, std::string(what) + "dip " + formatNumber(dip) + " outside [-90, 90]: " + consequence);
        return false;
    }
    dip = signedDip(dip, conv);
    return true;
}

Status readCollars(const DrillholeTableSource& src, DrillholeDatabase& db) {
    TableReader t(src, "collar", db.warnings);
    DrillholeTableInfo info;
    info.dip = src.dip;
    std::string error;
    if (!t.start(info, error)) return makeError(ErrorCode::ParseError, src.file + ": " + error);
    std::vector<std::size_t> collarRow;
    std::vector<std::string> rec;
    std::size_t row = 0;
    const int hc = t.column("hole");
    while (t.next(rec, row)) {
        const std::string id = cellText(rec, hc);
        if (id.empty()) {
            t.warn(row, "", "blank hole id: row skipped");
            continue;
        }
        glm::dvec3 p;
        bool ok = true;
        for (int k = 0; k < 3 && ok; ++k) {
            const char* role = k == 0 ? "x" : k == 1 ? "y" : "z";
            const Cell c = readCell(rec, t.column(role), p[k]);
            if (c != Cell::Number) {
                t.warn(row, id, describe(role, c, rec, t.column(role)));
                ok = false;
            }
        }
        if (!ok) continue;
        if (auto it = db.index.find(id); it != db.index.end()) {
            t.warn(row, id,
                   "duplicate collar (the first is row " + std::to_string(collarRow[it->second]) + "): row skipped");
            continue;
        }
        Drillhole h;
        h.id = id;
        h.collar = p;
        if (t.column("total_depth") >= 0) {
            double td;
            const Cell c = readCell(rec, t.column("total_depth"), td);
            if (c == Cell::Bad || (c == Cell::Number && td <= 0.0))
                t.warn(row, id,
                       "total depth " + text::quoteToken(cellText(rec, t.column("total_depth"))) +
                           " is not a positive number: the hole's end is unknown");
            else if (c == Cell::Number)
                h.totalDepth = td;
        }
        if (t.column("azimuth") >= 0 && t.column("dip") >= 0) {
            double az, dip;
            if (!cellText(rec, t.column("azimuth")).empty() || !cellText(rec, t.column("dip")).empty()) {
                if (readDirection(t, rec, row, id, src.dip, az, dip, "collar ", "the collar's direction is ignored"))
                    h.collarSurvey = SurveyStation{0.0, az, dip};
            }
        }
        db.index.emplace(id, std::uint32_t(db.holes.size()));
        db.holes.push_back(std::move(h));
        collarRow.push_back(row);
    }
    info.rows = t.rows();
    info.rowsUsed = db.holes.size();
    db.tables.push_back(std::move(info));
    if (db.holes.empty()) {
        std::string why = src.file + ": no usable collar";
        if (!db.warnings.empty())
            why +=
                " (" + std::to_string(db.warnings.size()) + " warnings; the first: " + db.warnings.front().text() + ")";
        return makeError(ErrorCode::ParseError, why);
    }
    return {};
}

void readSurveys(const DrillholeTableSource& src, DrillholeDatabase& db, const std::string& collarFile) {
    TableReader t(src, "survey", db.warnings);
    DrillholeTableInfo info;
    info.dip = src.dip;
    std::string error;
    if (!t.start(info, error)) {
        db.warnings.push_back({src.file, 0, "", error + ": the table is skipped, holes are straight"});
        db.tables.push_back(std::move(info));
        return;
    }
    UnknownHoles unknown;
    std::vector<std::size_t> lastRow(db.holes.size(), 0);
    std::vector<std::string> rec;
    std::size_t row = 0, used = 0;
    const int hc = t.column("hole");
    while (t.next(rec, row)) {
        const std::string id = cellText(rec, hc);
        const auto hole = rowHole(t, db, unknown, id, row);
        if (!hole) continue;
        Drillhole& h = db.holes[*hole];
        double depth;
        const Cell cd = readCell(rec, t.column("depth"), depth);
        if (cd != Cell::Number) {
            t.warn(row, id, describe("depth", cd, rec, t.column("depth")));
            continue;
        }
        if (depth < 0.0) {
            t.warn(row, id, "depth " + formatNumber(depth) + " m is negative: row skipped");
            continue;
        }
        double az, dip;
        if (!readDirection(t, rec, row, id, src.dip, az, dip, "", "row skipped")) continue;
        if (!h.stations.empty() && depth <= h.stations.back().depth + kDepthTolerance) {
            t.warn(row, id,
                   "survey depths not increasing: " + formatNumber(depth) + " m after " +
                       formatNumber(h.stations.back().depth) + " m (row " + std::to_string(lastRow[*hole]) +
                       "): row skipped");
            continue;
        }
        if (std::isfinite(h.totalDepth) && depth > h.totalDepth + kDepthTolerance)
            t.warn(row, id,
                   "station at " + formatNumber(depth) + " m is past the hole's total depth " +
                       formatNumber(h.totalDepth) + " m: kept");
        h.stations.push_back({depth, az, dip});
        lastRow[*hole] = row;
        ++used;
    }
    unknown.report(t, collarFile);
    info.rows = t.rows();
    info.rowsUsed = used;
    db.tables.push_back(std::move(info));
}

void readIntervals(const DrillholeTableSource& src, DrillholeDatabase& db, const std::string& collarFile) {
    TableReader t(src, "interval", db.warnings);
    DrillholeTableInfo info;
    std::string error;
    if (!t.start(info, error)) {
        db.warnings.push_back({src.file, 0, "", error + ": the table is skipped"});
        db.tables.push_back(std::move(info));
        return;
    }
    IntervalTable table;
    table.name = src.name;
    table.file = src.file;
    std::vector<int> dataColumn;
    for (std::size_t i = 0; i < info.columns.size(); ++i) {
        if (info.columns[i].role != "column") continue;
        dataColumn.push_back(int(i));
        IntervalColumn c;
        c.name = info.columns[i].header;
        c.numeric = true;
        c.unit = unitFromName(c.name);
        for (const auto& [col, unit] : src.units)
            if (text::equalsNoCase(col, c.name)) c.unit = unit;
        table.columns.push_back(std::move(c));
    }
    UnknownHoles unknown;
    std::vector<std::string> rec;
    std::size_t row = 0;
    const int hc = t.column("hole");
    while (t.next(rec, row)) {
        const std::string id = cellText(rec, hc);
        const auto hole = rowHole(t, db, unknown, id, row);
        if (!hole) continue;
        double from, to;
        const Cell cf = readCell(rec, t.column("from"), from);
        const Cell ct = readCell(rec, t.column("to"), to);
        if (cf != Cell::Number) {
            t.warn(row, id, describe("from", cf, rec, t.column("from")));
            continue;
        }
        if (ct != Cell::Number) {
            t.warn(row, id, describe("to", ct, rec, t.column("to")));
            continue;
        }
        if (from < 0.0) {
            t.warn(row, id, "from " + formatNumber(from) + " m is negative: row skipped");
            continue;
        }
        if (from >= to) {
            t.warn(row, id,
                   "interval " + formatNumber(from) + ".." + formatNumber(to) +
                       " m is reversed or empty (from >= to): row skipped");
            continue;
        }
        const double td = db.holes[*hole].totalDepth;
        if (std::isfinite(td) && to > td + kDepthTolerance)
            t.warn(row, id,
                   "interval " + formatNumber(from) + ".." + formatNumber(to) + " m ends past the hole's total depth " +
                       formatNumber(td) + " m: kept");
        table.hole.push_back(*hole);
        table.from.push_back(from);
        table.to.push_back(to);
        table.row.push_back(std::uint32_t(row));
        const std::size_t n = table.from.size();
        for (std::size_t k = 0; k < dataColumn.size(); ++k) {
            IntervalColumn& c = table.columns[k];
            const std::string cell = cellText(rec, dataColumn[k]);
            if (c.numeric) {
                double v = std::numeric_limits<double>::quiet_NaN();
                if (!cell.empty()) {
                    auto parsed = text::parseDouble(cell);
                    if (parsed && std::isfinite(*parsed)) {
                        v = *parsed;
                    } else {
                        // The first text cell: the column becomes text (the numbers so far in
                        // their shortest spelling).
                        c.numeric = false;
                        c.texts.reserve(n);
                        for (double x : c.numbers) c.texts.push_back(std::isnan(x) ? "" : formatNumber(x));
                        c.numbers.clear();
                        c.texts.push_back(cell);
                        continue;
                    }
                }
                c.numbers.push_back(v);
            } else {
                c.texts.push_back(cell);
            }
        }
    }
    unknown.report(t, collarFile);

    // Sort by hole then from, then look for overlaps within each hole.
    const std::size_t n = table.from.size();
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&table](std::uint32_t a, std::uint32_t b) {
        if (table.hole[a] != table.hole[b]) return table.hole[a] < table.hole[b];
        if (table.from[a] != table.from[b]) return table.from[a] < table.from[b];
        return table.row[a] < table.row[b];
    });
    auto permute = [&order](auto& v) {
        if (v.empty()) return;
        std::remove_reference_t<decltype(v)> out;
        out.reserve(v.size());
        for (std::uint32_t i : order) out.push_back(std::move(v[i]));
        v = std::move(out);
    };
    permute(table.hole);
    permute(table.from);
    permute(table.to);
    permute(table.row);
    for (auto& c : table.columns) {
        permute(c.numbers);
        permute(c.texts);
    }
    for (std::size_t i = 1, deepest = 0; i < n; ++i) {
        if (table.hole[i] != table.hole[i - 1]) {
            deepest = i;
            continue;
        }
        if (table.from[i] < table.to[deepest] - kDepthTolerance)
            t.warn(table.row[i], db.holes[table.hole[i]].id,
                   "interval " + formatNumber(table.from[i]) + ".." + formatNumber(table.to[i]) +
                       " m overlaps the interval " + formatNumber(table.from[deepest]) + ".." +
                       formatNumber(table.to[deepest]) + " m (row " + std::to_string(table.row[deepest]) + "): kept");
        if (table.to[i] > table.to[deepest]) deepest = i;
    }
    info.rows = t.rows();
    info.rowsUsed = n;
    db.tables.push_back(std::move(info));
    db.intervals.push_back(std::move(table));
}

Result<DipConvention> parseDip(const nlohmann::json& j, const std::string& where) {
    if (!j.is_string()) return makeError(ErrorCode::ParseError, where + ": \"dip\" must be a string");
    const std::string s = normaliseHeader(j.get<std::string>());
    if (s == "negativedown") return DipConvention::NegativeDown;
    if (s == "positivedown") return DipConvention::PositiveDown;
    return makeError(ErrorCode::ParseError, where + ": \"dip\" is " + text::quoteToken(j.get<std::string>()) +
                                                " (expected \"negative_down\" or \"positive_down\")");
}

Result<DrillholeTableSource> tableFromJson(const nlohmann::json& j, const std::filesystem::path& dir, DipConvention dip,
                                           const std::string& sidecar, const std::string& key) {
    DrillholeTableSource t;
    t.dip = dip;
    std::string file;
    if (j.is_string()) {
        file = j.get<std::string>();
    } else if (j.is_object()) {
        if (!j.contains("file") || !j["file"].is_string())
            return makeError(ErrorCode::ParseError, sidecar + ": " + key + " has no \"file\"");
        file = j["file"].get<std::string>();
        if (j.contains("name") && j["name"].is_string()) t.name = j["name"].get<std::string>();
        if (j.contains("dip")) {
            auto d = parseDip(j["dip"], sidecar + ": " + key);
            if (!d) return d.error();
            t.dip = d.value();
        }
        for (const char* what : {"columns", "units"}) {
            if (!j.contains(what)) continue;
            if (!j[what].is_object())
                return makeError(ErrorCode::ParseError, sidecar + ": " + key + "." + what + " must be an object");
            for (const auto& [k, v] : j[what].items()) {
                if (!v.is_string())
                    return makeError(ErrorCode::ParseError,
                                     sidecar + ": " + key + "." + what + "." + k + " must be a string");
                (what[0] == 'c' ? t.columns : t.units).emplace_back(k, v.get<std::string>());
            }
        }
    } else {
        return makeError(ErrorCode::ParseError, sidecar + ": " + key + " must be a file name or an object");
    }
    const std::filesystem::path p = dir / file;
    if (t.name.empty()) t.name = p.stem().string();
    t.file = p.filename().string();
    auto bytes = readFile(p.string());
    if (!bytes) return makeError(bytes.error().code, sidecar + ": " + key + ": " + bytes.error().message);
    t.text = std::move(bytes).value();
    return t;
}

}  // namespace

std::string DrillholeIssue::text() const {
    std::string s = file;
    if (row) s += " row " + std::to_string(row);
    if (!hole.empty()) s += ", hole " + text::quoteToken(hole);
    return s + ": " + message;
}

std::size_t DrillholeDatabase::stationCount() const {
    std::size_t n = 0;
    for (const auto& h : holes) n += h.stations.size();
    return n;
}

const Drillhole* DrillholeDatabase::find(std::string_view id) const {
    auto it = index.find(std::string(id));
    return it == index.end() ? nullptr : &holes[it->second];
}

Result<DrillholeDatabase> buildDrillholes(DrillholeSources sources) {
    DrillholeDatabase db;
    db.source = std::move(sources.source);
    db.crs = std::move(sources.crs);
    db.units = std::move(sources.units);
    if (auto s = readCollars(sources.collar, db); !s) return s.error();
    if (sources.survey) readSurveys(*sources.survey, db, sources.collar.file);
    for (const auto& t : sources.intervals) readIntervals(t, db, sources.collar.file);
    for (Drillhole& h : db.holes) {
        const glm::dvec3 dir =
            h.collarSurvey ? drillDirection(h.collarSurvey->azimuth, h.collarSurvey->dip) : glm::dvec3(0.0, 0.0, -1.0);
        h.path = desurvey(h.collar, h.stations, h.totalDepth, dir);
    }
    return db;
}

namespace {

// The sidecar's "units" object (DrillholeUnitMap).
Result<DrillholeUnitMap> unitMapFromJson(const nlohmann::json& j, const std::string& sidecar) {
    if (!j.is_object()) return makeError(ErrorCode::ParseError, sidecar + ": \"units\" must be an object");
    DrillholeUnitMap u;
    for (const char* key : {"table", "column"}) {
        if (!j.contains(key)) continue;
        if (!j[key].is_string())
            return makeError(ErrorCode::ParseError, sidecar + ": units." + key + " must be a string");
        (std::string(key) == "table" ? u.table : u.column) = j[key].get<std::string>();
    }
    if (j.contains("map")) {
        if (!j["map"].is_object())
            return makeError(ErrorCode::ParseError, sidecar + ": units.map must be an object (code -> unit)");
        for (const auto& [code, unit] : j["map"].items()) {
            if (!unit.is_string())
                return makeError(ErrorCode::ParseError, sidecar + ": units.map." + code + " must be a string");
            u.map.emplace_back(code, unit.get<std::string>());
        }
    }
    return u;
}

}  // namespace

Result<DrillholeDatabase> loadDrillholes(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    DrillholeSources src;
    src.source = path;
    if (fs::is_directory(path, ec)) {
        std::vector<fs::path> csvs;
        for (const auto& e : fs::directory_iterator(path, ec))
            if (e.is_regular_file() && text::equalsNoCase(e.path().extension().string(), ".csv"))
                csvs.push_back(e.path());
        std::sort(csvs.begin(), csvs.end());
        bool haveCollar = false;
        for (const fs::path& p : csvs) {
            const std::string stem = normaliseHeader(p.stem().string());
            auto bytes = readFile(p.string());
            if (!bytes) return bytes.error();
            DrillholeTableSource t;
            t.name = p.stem().string();
            t.file = p.filename().string();
            t.text = std::move(bytes).value();
            if ((stem == "collar" || stem == "collars") && !haveCollar) {
                src.collar = std::move(t);
                haveCollar = true;
            } else if ((stem == "survey" || stem == "surveys") && !src.survey) {
                src.survey = std::move(t);
            } else {
                src.intervals.push_back(std::move(t));
            }
        }
        if (!haveCollar) return makeError(ErrorCode::NotFound, path + ": no collar.csv in the folder");
        return buildDrillholes(std::move(src));
    }
    auto bytes = readFile(path, std::size_t(1) << 20);
    if (!bytes) return bytes.error();
    nlohmann::json j = nlohmann::json::parse(bytes.value(), nullptr, false);
    if (j.is_discarded() || !j.is_object())
        return makeError(ErrorCode::ParseError, path + ": not a JSON object (a drillholes sidecar)");
    const fs::path dir = fs::path(path).parent_path();
    DipConvention dip = DipConvention::NegativeDown;
    if (j.contains("dip")) {
        auto d = parseDip(j["dip"], path);
        if (!d) return d.error();
        dip = d.value();
    }
    if (j.contains("crs")) {
        if (!j["crs"].is_string()) return makeError(ErrorCode::ParseError, path + ": \"crs\" must be a string");
        src.crs = j["crs"].get<std::string>();
    }
    if (j.contains("units")) {
        auto units = unitMapFromJson(j["units"], path);
        if (!units) return units.error();
        src.units = std::move(units).value();
    }
    if (!j.contains("collar")) return makeError(ErrorCode::ParseError, path + ": no \"collar\" table");
    auto collar = tableFromJson(j["collar"], dir, dip, path, "collar");
    if (!collar) return collar.error();
    src.collar = std::move(collar).value();
    if (j.contains("survey")) {
        auto survey = tableFromJson(j["survey"], dir, dip, path, "survey");
        if (!survey) return survey.error();
        src.survey = std::move(survey).value();
    }
    if (j.contains("intervals")) {
        if (!j["intervals"].is_array())
            return makeError(ErrorCode::ParseError, path + ": \"intervals\" must be an array");
        for (std::size_t i = 0; i < j["intervals"].size(); ++i) {
            auto t = tableFromJson(j["intervals"][i], dir, dip, path, "intervals[" + std::to_string(i) + "]");
            if (!t) return t.error();
            src.intervals.push_back(std::move(t).value());
        }
    }
    return buildDrillholes(std::move(src));
}

std::string drillholeSidecarFor(const std::string& modelPath) {
    std::filesystem::path p(modelPath);
    p.replace_extension(".drillholes.json");
    std::error_code ec;
    return std::filesystem::is_regular_file(p, ec) ? p.string() : std::string();
}

}  // namespace geoslice
