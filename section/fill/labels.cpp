#include "section/fill/labels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

#include "model/json_text.hpp"

namespace geoslice {
namespace {

double segmentDistanceSq(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 ab = b - a;
    const double len = glm::dot(ab, ab);
    double t = len > 0.0 ? glm::dot(p - a, ab) / len : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const glm::dvec2 d = p - (a + t * ab);
    return glm::dot(d, d);
}

// Signed distance from p to the rings' edges: positive inside (even-odd).
double signedDistance(const glm::dvec2& p, const std::vector<Ring>& rings) {
    bool inside = false;
    double best = std::numeric_limits<double>::infinity();
    for (const Ring& r : rings) {
        if (r.empty()) continue;
        if (pointInRing(p, r)) inside = !inside;
        for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
            best = std::min(best, segmentDistanceSq(p, r[j], r[i]));
    }
    return (inside ? 1.0 : -1.0) * std::sqrt(best);
}

// Liang-Barsky: does segment ab meet the closed box?
bool segmentMeetsBox(const glm::dvec2& a, const glm::dvec2& b, const LabelBox& box) {
    double t0 = 0.0, t1 = 1.0;
    const glm::dvec2 d = b - a;
    const double p[4] = {-d.x, d.x, -d.y, d.y};
    const double q[4] = {a.x - box.x0, box.x1 - a.x, a.y - box.y0, box.y1 - a.y};
    for (int k = 0; k < 4; ++k) {
        if (p[k] == 0.0) {
            if (q[k] < 0.0) return false;
        } else {
            const double t = q[k] / p[k];
            if (p[k] < 0.0)
                t0 = std::max(t0, t);
            else
                t1 = std::min(t1, t);
            if (t0 > t1) return false;
        }
    }
    return true;
}

// Sutherland-Hodgman clip of a ring to the box (a convex clip window).
Ring clipRing(const Ring& ring, const LabelBox& b) {
    Ring out = ring;
    for (int edge = 0; edge < 4 && !out.empty(); ++edge) {
        auto inside = [&](const glm::dvec2& p) {
            switch (edge) {
                case 0:
                    return p.x >= b.x0;
                case 1:
                    return p.x <= b.x1;
                case 2:
                    return p.y >= b.y0;
                default:
                    return p.y <= b.y1;
            }
        };
        auto cross = [&](const glm::dvec2& p, const glm::dvec2& q) {
            const double t = edge == 0   ? (b.x0 - p.x) / (q.x - p.x)
                             : edge == 1 ? (b.x1 - p.x) / (q.x - p.x)
                             : edge == 2 ? (b.y0 - p.y) / (q.y - p.y)
                                         : (b.y1 - p.y) / (q.y - p.y);
            return p + t * (q - p);
        };
        Ring in = std::move(out);
        out.clear();
        for (std::size_t i = 0; i < in.size(); ++i) {
            const glm::dvec2& cur = in[i];
            const glm::dvec2& prev = in[(i + in.size() - 1) % in.size()];
            const bool ci = inside(cur), pi = inside(prev);
            if (ci) {
                if (!pi) out.push_back(cross(prev, cur));
                out.push_back(cur);
            } else if (pi) {
                out.push_back(cross(prev, cur));
            }
        }
    }
    return out.size() >= 3 ? out : Ring{};
}

std::string lowerAscii(std::string s) {
    for (char& c : s)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return s;
}

}  // namespace

glm::dvec2 poleOfInaccessibility(const std::vector<Ring>& rings, double precision, double* distance) {
    glm::dvec2 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
    for (const Ring& r : rings)
        for (const glm::dvec2& p : r) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    if (!(lo.x <= hi.x)) {
        if (distance) *distance = -std::numeric_limits<double>::infinity();
        return glm::dvec2(0.0);
    }
    const glm::dvec2 size = hi - lo;
    const double cellSize = std::min(size.x, size.y);
    if (cellSize <= 0.0) {
        if (distance) *distance = 0.0;
        return lo;
    }
    precision = std::max(precision, 1e-9 * std::max(size.x, size.y));
    struct Cell {
        glm::dvec2 c;
        double h, d, max;
    };
    auto makeCell = [&](const glm::dvec2& c, double h) {
        const double d = signedDistance(c, rings);
        return Cell{c, h, d, d + h * std::numbers::sqrt2};
    };
    auto lower = [](const Cell& a, const Cell& b) { return a.max < b.max; };
    std::priority_queue<Cell, std::vector<Cell>, decltype(lower)> queue(lower);
    const double h = 0.5 * cellSize;
    for (double x = lo.x; x < hi.x; x += cellSize)
        for (double y = lo.y; y < hi.y; y += cellSize) queue.push(makeCell({x + h, y + h}, h));
    // First guesses: the outer ring's area centroid and the bounding box's centre.
    Cell best = makeCell(0.5 * (lo + hi), 0.0);
    if (!rings.empty() && rings[0].size() >= 3) {
        const Ring& r = rings[0];
        double a = 0.0;
        glm::dvec2 c(0.0);
        for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
            const double f = r[j].x * r[i].y - r[i].x * r[j].y;
            c += (r[j] + r[i]) * f;
            a += 3.0 * f;
        }
        if (a != 0.0) {
            const Cell centroid = makeCell(c / a, 0.0);
            if (centroid.d > best.d) best = centroid;
        }
    }
    constexpr std::size_t kMaxCells = 20000;  // a bound on work for pathological rings
    for (std::size_t n = 0; !queue.empty() && n < kMaxCells; ++n) {
        const Cell cell = queue.top();
        queue.pop();
        if (cell.d > best.d) best = cell;
        if (cell.max - best.d <= precision) continue;
        const double q = 0.5 * cell.h;
        queue.push(makeCell(cell.c + glm::dvec2(-q, -q), q));
        queue.push(makeCell(cell.c + glm::dvec2(q, -q), q));
        queue.push(makeCell(cell.c + glm::dvec2(-q, q), q));
        queue.push(makeCell(cell.c + glm::dvec2(q, q), q));
    }
    if (distance) *distance = best.d;
    return best.c;
}

bool boxInsidePolygon(const LabelBox& box, const std::vector<Ring>& rings) {
    const glm::dvec2 centre{0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1)};
    bool inside = false;
    for (const Ring& r : rings)
        if (!r.empty() && pointInRing(centre, r)) inside = !inside;
    if (!inside) return false;
    for (const Ring& r : rings)
        for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
            if (segmentMeetsBox(r[j], r[i], box)) return false;
    return true;
}

std::string unitCode(const AttributeRecord* record, const std::string& fallback) {
    if (!record) return fallback;
    for (const char* name : {"code", "unit_code", "symbol", "label", "abbrev"})
        for (const auto& [key, value] : record->extra.items())
            if (lowerAscii(key) == name) {
                if (value.is_string() && !value.get<std::string>().empty()) return value.get<std::string>();
                if (value.is_number()) return jsonText(value);
            }
    // "Late Triassic (T3x)": a bracketed code of up to 12 bytes with no spaces.
    const std::string& age = record->age;
    if (!age.empty() && age.back() == ')') {
        const std::size_t open = age.rfind('(');
        if (open != std::string::npos) {
            const std::string code = age.substr(open + 1, age.size() - open - 2);
            if (!code.empty() && code.size() <= 12 && code.find(' ') == std::string::npos) return code;
        }
    }
    return record->name.empty() ? fallback : record->name;
}

std::vector<PlacedLabel> placeLabels(const std::vector<LabelCandidate>& candidates, const LabelBox& view, double gap,
                                     const std::vector<std::vector<glm::dvec2>>& obstacles) {
    struct Order {
        double area;
        std::size_t index;
    };
    std::vector<Order> order;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const LabelCandidate& c = candidates[i];
        if (c.rings.empty() || c.text.empty() || !(c.width > 0.0) || !(c.height > 0.0)) continue;
        double area = std::abs(ringArea(c.rings[0]));
        for (std::size_t k = 1; k < c.rings.size(); ++k) area -= std::abs(ringArea(c.rings[k]));
        if (area < c.width * c.height) continue;  // cannot hold the box
        order.push_back({area, i});
    }
    std::stable_sort(order.begin(), order.end(), [](const Order& a, const Order& b) { return a.area > b.area; });
    std::vector<PlacedLabel> placed;
    for (const Order& o : order) {
        const LabelCandidate& c = candidates[o.index];
        double d = 0.0;
        const glm::dvec2 p = poleOfInaccessibility(c.rings, 0.05 * c.height, &d);
        if (d < 0.5 * c.height) continue;  // too thin for the text anywhere
        const LabelBox box{p.x - 0.5 * c.width, p.y - 0.5 * c.height, p.x + 0.5 * c.width, p.y + 0.5 * c.height};
        if (box.x0 < view.x0 || box.y0 < view.y0 || box.x1 > view.x1 || box.y1 > view.y1) continue;
        if (!boxInsidePolygon(box, c.rings)) continue;
        const LabelBox padded{box.x0 - gap, box.y0 - gap, box.x1 + gap, box.y1 + gap};
        const bool blocked = std::any_of(obstacles.begin(), obstacles.end(), [&](const std::vector<glm::dvec2>& line) {
            for (std::size_t i = 0; i + 1 < line.size(); ++i)
                if (segmentMeetsBox(line[i], line[i + 1], padded)) return true;
            return false;
        });
        if (blocked) continue;
        if (std::any_of(placed.begin(), placed.end(), [&](const PlacedLabel& q) { return q.box.overlaps(box, gap); }))
            continue;
        placed.push_back({c.text, p, box, c.record, c.part});
    }
    return placed;
}

double estimateTextWidth(const std::string& text, double size) {
    double em = 0.0;
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        const std::size_t n = c < 0x80 ? 1 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
        if (n == 1)
            em += (c >= 'A' && c <= 'Z') ? 0.8 : c == ' ' ? 0.35 : 0.62;
        else
            em += n >= 3 ? 1.0 : 0.7;
        i += n;
    }
    return em * size;
}

std::vector<LabelCandidate> sectionLabelCandidates(const SectionIndex& index, const std::vector<BodySection>& bodies,
                                                   const std::function<glm::dvec2(const glm::dvec2&)>& toOutput,
                                                   const LabelBox& view, const LabelStyle& style) {
    std::vector<LabelCandidate> out;
    for (const BodySection& b : bodies) {
        const SectionPart& part = index.parts[b.part];
        const AttributeRecord* record = index.model ? index.model->attributes.find(b.record) : nullptr;
        const std::string text = unitCode(record, part.part ? part.part->name : "");
        if (text.empty()) continue;
        const double width = style.textWidth ? style.textWidth(text, style.size) : estimateTextWidth(text, style.size);
        for (const SectionPolygon& poly : b.polygons) {
            LabelCandidate c;
            c.text = text;
            c.record = b.record;
            c.part = b.part;
            c.width = width + 2.0 * style.padding * style.size;
            c.height = (1.0 + 2.0 * style.padding) * style.size;
            auto map = [&](const Ring& r) {
                Ring m;
                m.reserve(r.size());
                for (const glm::dvec2& p : r) m.push_back(toOutput(p));
                return clipRing(m, view);
            };
            Ring outer = map(poly.outer);
            if (outer.empty()) continue;
            c.rings.push_back(std::move(outer));
            for (const Ring& h : poly.holes)
                if (Ring m = map(h); !m.empty()) c.rings.push_back(std::move(m));
            out.push_back(std::move(c));
        }
    }
    return out;
}

std::vector<PlacedLabel> sectionLabels(const SectionIndex& index, const std::vector<BodySection>& bodies,
                                       const std::function<glm::dvec2(const glm::dvec2&)>& toOutput,
                                       const LabelBox& view, const LabelStyle& style,
                                       const std::vector<SectionTrace>* traces) {
    std::vector<std::vector<glm::dvec2>> obstacles;
    if (traces)
        for (const SectionTrace& t : *traces) {
            std::vector<glm::dvec2> line;
            for (const glm::dvec2& p : t.points) line.push_back(toOutput(p));
            if (t.closed && !t.points.empty()) line.push_back(toOutput(t.points.front()));
            obstacles.push_back(std::move(line));
        }
    return placeLabels(sectionLabelCandidates(index, bodies, toOutput, view, style), view, 0.3 * style.size, obstacles);
}

}  // namespace geoslice
