#include "section/blocks/block_section.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "model/blocks/cell_locator.hpp"

namespace geoslice {
namespace {

struct Ramp {
    std::string_view name;
    std::vector<std::uint32_t> keys;  // 0xRRGGBB, low to high
};

const std::vector<Ramp>& ramps() {
    static const std::vector<Ramp> r{
        {"viridis",
         {0x440154, 0x482878, 0x3e4989, 0x31688e, 0x26828e, 0x1f9e89, 0x35b779, 0x6ece58, 0xb5de2b, 0xfde725}},
        {"magma", {0x000004, 0x1c1044, 0x4f127b, 0x812581, 0xb5367a, 0xe55064, 0xfb8761, 0xfec287, 0xfcfdbf}},
        {"greys", {0xf7f7f7, 0xd9d9d9, 0xbdbdbd, 0x969696, 0x737373, 0x525252, 0x252525}},
        {"spectral",
         {0x5e4fa2, 0x3288bd, 0x66c2a5, 0xabdda4, 0xe6f598, 0xffffbf, 0xfee08b, 0xfdae61, 0xf46d43, 0xd53e4f,
          0x9e0142}},
    };
    return r;
}

double cross(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

}  // namespace

const std::vector<std::string_view>& rampNames() {
    static const std::vector<std::string_view> names = [] {
        std::vector<std::string_view> n;
        for (const Ramp& r : ramps()) n.push_back(r.name);
        return n;
    }();
    return names;
}

bool isRampName(std::string_view name) {
    for (const Ramp& r : ramps())
        if (r.name == name) return true;
    return false;
}

Rgba8 rampColour(std::string_view name, double t) {
    const Ramp* ramp = &ramps()[0];
    for (const Ramp& r : ramps())
        if (r.name == name) ramp = &r;
    t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
    const double x = t * double(ramp->keys.size() - 1);
    const std::size_t k = std::min(std::size_t(x), ramp->keys.size() - 2);
    const double f = x - double(k);
    auto channel = [&](int shift) {
        const double a = double((ramp->keys[k] >> shift) & 255), b = double((ramp->keys[k + 1] >> shift) & 255);
        return std::uint8_t(std::lround(a + (b - a) * f));
    };
    return Rgba8{channel(16), channel(8), channel(0), 255};
}

std::string PropertyClasses::label(std::size_t k) const {
    auto number = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", v);
        return std::string(buf);
    };
    if (breaks.empty()) return "all values";
    if (k == 0) return "< " + number(breaks[0]);
    if (k == breaks.size()) return ">= " + number(breaks.back());
    return number(breaks[k - 1]) + " - " + number(breaks[k]);
}

int PropertyClasses::classOf(double value) const {
    if (std::isnan(value)) return -1;
    return int(std::upper_bound(breaks.begin(), breaks.end(), value) - breaks.begin());
}

Result<PropertyClasses> makePropertyClasses(int property, std::string ramp, std::vector<double> breaks) {
    if (!isRampName(ramp)) {
        std::string known;
        for (auto n : rampNames()) known += (known.empty() ? "" : ", ") + std::string(n);
        return makeError(ErrorCode::InvalidArgument, "colour ramp '" + ramp + "' is not one of " + known);
    }
    if (breaks.size() > 64)
        return makeError(ErrorCode::OutOfRange, "at most 64 class breaks (got " + std::to_string(breaks.size()) + ")");
    for (std::size_t i = 0; i < breaks.size(); ++i) {
        if (!std::isfinite(breaks[i])) return makeError(ErrorCode::InvalidArgument, "class breaks must be finite");
        if (i > 0 && !(breaks[i] > breaks[i - 1]))
            return makeError(ErrorCode::InvalidArgument, "class breaks must increase strictly");
    }
    PropertyClasses c;
    c.property = property;
    c.ramp = std::move(ramp);
    c.breaks = std::move(breaks);
    const std::size_t n = c.breaks.size() + 1;
    for (std::size_t k = 0; k < n; ++k)
        c.colours.push_back(rampColour(c.ramp, n == 1 ? 0.5 : double(k) / double(n - 1)));
    return c;
}

std::vector<double> defaultBreaks(const BlockProperty& property) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : property.values)
        if (std::isfinite(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    std::vector<double> b;
    if (!(hi > lo)) return b;
    for (int k = 1; k < 5; ++k) b.push_back(lo + (hi - lo) * k / 5.0);
    return b;
}

Result<PropertyClasses> propertyClasses(const BlockModel& blocks, const std::string& name, const std::string& ramp,
                                        const std::optional<std::vector<double>>& breaks) {
    const int k = blocks.propertyIndex(name);
    if (k < 0)
        return makeError(ErrorCode::InvalidArgument,
                         "the block model has no property '" + name + "' (properties: " + blocks.propertyList() + ")");
    return makePropertyClasses(k, ramp, breaks ? *breaks : defaultBreaks(blocks.properties[std::size_t(k)]));
}

std::vector<RecordId> blockClipRecords(const Model& model, const BlockModel& blocks) {
    std::vector<RecordId> r;
    for (std::uint32_t b : blocks.clipBodyIndex)
        if (b < model.bodies.size()) r.push_back(model.bodies[b].record);
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    return r;
}

std::vector<std::uint8_t> cellClassIndex(const BlockModel& blocks, const PropertyClasses& classes) {
    const std::vector<double>& values = blocks.properties[std::size_t(classes.property)].values;
    std::vector<std::uint8_t> out(values.size());
    for (std::size_t c = 0; c < values.size(); ++c) out[c] = std::uint8_t(classes.classOf(values[c]) + 1);
    return out;
}

namespace {

// Whether the polygon's bounding box misses `limit` (u/v).
bool outsideLimit(const Ring& ring, const FrameRect* limit) {
    if (!limit) return false;
    glm::dvec2 pl(std::numeric_limits<double>::infinity()), ph(-std::numeric_limits<double>::infinity());
    for (const auto& p : ring) {
        pl = glm::min(pl, p);
        ph = glm::max(ph, p);
    }
    return ph.x < limit->u0 || pl.x > limit->u1 || ph.y < limit->v0 || pl.y > limit->v1;
}

// The convex polygon of up to 4 crossing points (u/v), counter-clockwise, repeated points
// dropped; empty when it has no area.
Ring convexRing(glm::dvec2* pts, int n) {
    Ring ring;
    if (n < 3) return ring;
    glm::dvec2 mean(0.0);
    for (int i = 0; i < n; ++i) mean += pts[i];
    mean /= double(n);
    std::sort(pts, pts + n, [&](const glm::dvec2& p, const glm::dvec2& r) {
        return std::atan2(p.y - mean.y, p.x - mean.x) < std::atan2(r.y - mean.y, r.x - mean.x);
    });
    for (int i = 0; i < n; ++i)
        if (ring.empty() || pts[i] != ring.back()) ring.push_back(pts[i]);
    while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    if (ring.size() < 3 || !(ringArea(ring) > 0.0)) ring.clear();
    return ring;
}

// Hexahedral cells (model/blocks/block_model.hpp): every tetrahedron's cut, a triangle or a
// quadrilateral. Each crossing point is computed from its edge's two corners in the order
// of their lattice indices, so the tetrahedra sharing an edge (in one cell or in
// neighbours) get the same point and their polygons meet exactly.
Result<std::vector<CellPolygon>> tetCellPolygons(const BlockModel& blocks, const SectionFrame& frame,
                                                 const FrameRect* limit, std::size_t maxCells) {
    std::vector<CellPolygon> out;
    const glm::dvec3 o = frame.originWorld();
    auto signedDistance = [&](const glm::dvec3& p) { return glm::dot(frame.normal, p - o); };
    auto crosses = [&](const Aabb& box) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (int c = 0; c < 8; ++c) {
            const double s = signedDistance(
                {c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y, c & 4 ? box.max.z : box.min.z});
            lo = std::min(lo, s);
            hi = std::max(hi, s);
        }
        return lo < 0.0 && hi >= 0.0;
    };
    std::vector<std::size_t> cut;
    blocks.locator->cellsMeeting(crosses, [&](std::size_t cell) { cut.push_back(cell); });
    std::sort(cut.begin(), cut.end());
    for (const std::size_t cell : cut) {
        const auto k = blocks.cellCorners(cell);
        double sd[8];
        std::size_t id[8];
        for (int c = 0; c < 8; ++c) {
            sd[c] = signedDistance(k[std::size_t(c)]);
            id[c] = blocks.cornerIndex(cell, c);
        }
        for (const auto& tet : kCellTets) {
            glm::dvec2 pts[4];
            int n = 0;
            for (int e0 = 0; e0 < 4; ++e0)
                for (int e1 = e0 + 1; e1 < 4; ++e1) {
                    int a = tet[std::size_t(e0)], b = tet[std::size_t(e1)];
                    if ((sd[a] < 0.0) == (sd[b] < 0.0)) continue;
                    if (id[b] < id[a]) std::swap(a, b);
                    const double t = sd[a] / (sd[a] - sd[b]);
                    const glm::dvec3 p = k[std::size_t(a)] + t * (k[std::size_t(b)] - k[std::size_t(a)]) - o;
                    if (n < 4) pts[n++] = {glm::dot(p, frame.u), glm::dot(p, frame.v)};
                }
            CellPolygon cp{cell, convexRing(pts, n)};
            if (cp.ring.empty() || outsideLimit(cp.ring, limit)) continue;
            if (out.size() >= maxCells)
                return makeError(ErrorCode::OutOfRange, "the section crosses more than " + std::to_string(maxCells) +
                                                            " block cell pieces (tetrahedra)");
            out.push_back(std::move(cp));
        }
    }
    return out;
}

}  // namespace

Result<std::vector<CellPolygon>> cellPolygons(const BlockModel& blocks, const SectionFrame& frame,
                                              const FrameRect* limit, std::size_t maxCells) {
    std::vector<CellPolygon> out;
    if (blocks.cellCount() == 0) return out;
    if (blocks.shape == CellShape::Hexahedron) return tetCellPolygons(blocks, frame, limit, maxCells);
    // The plane in the grid frame: N . g + c = 0.
    const glm::dvec3 q = blocks.origin - frame.originWorld();  // grid origin relative to the u/v origin
    const glm::dvec3 N{glm::dot(frame.normal, blocks.axis[0]), glm::dot(frame.normal, blocks.axis[1]),
                       glm::dot(frame.normal, blocks.axis[2])};
    const double c = glm::dot(frame.normal, q);
    // u/v of a grid point: (q + sum g_a axis_a) . u
    const glm::dvec2 q2{glm::dot(q, frame.u), glm::dot(q, frame.v)};
    glm::dvec2 ax[3];
    for (int a = 0; a < 3; ++a)
        ax[a] = {glm::dot(blocks.axis[std::size_t(a)], frame.u), glm::dot(blocks.axis[std::size_t(a)], frame.v)};
    auto toUv = [&](const glm::dvec3& g) { return q2 + g.x * ax[0] + g.y * ax[1] + g.z * ax[2]; };

    int m = 0;
    for (int a = 1; a < 3; ++a)
        if (std::abs(N[a]) > std::abs(N[m])) m = a;
    if (!(std::abs(N[m]) > 0.0)) return out;
    const int a = (m + 1) % 3, b = (m + 2) % 3;
    // A plane parallel to a grid plane may lie on one (a cut through the lattice): its pieces
    // are then the faces between two layers, and which layer's side signs give them is the
    // rounding of the plane's offset. They go to the cell cellAt names at the piece's centre,
    // the one rule the images, the query and the GL caps share (none there: no piece).
    const bool gridParallel = std::abs(N[a]) + std::abs(N[b]) <= 1e-12 * std::abs(N[m]);
    const glm::dvec3 s{blocks.size[0], blocks.size[1], blocks.size[2]};
    static const int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                      {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (std::size_t ib = 0; ib < blocks.dims[std::size_t(b)]; ++ib) {
        for (std::size_t ia = 0; ia < blocks.dims[std::size_t(a)]; ++ia) {
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (int corner = 0; corner < 4; ++corner) {
                const double ga = double(ia + (corner & 1)) * s[a], gb = double(ib + (corner >> 1)) * s[b];
                const double gm = -(c + N[a] * ga + N[b] * gb) / N[m];
                lo = std::min(lo, gm);
                hi = std::max(hi, gm);
            }
            // The cells the column's crossing spans, and the neighbour too where it lies within
            // 1e-7 of a cell of a grid plane: the plane's offset c carries rounding of ~1e-8 m
            // at Gauss-Kruger eastings, so a plane on a grid plane (a cut through the lattice's
            // middle) would otherwise find its gm on one side and the corners' signs on the
            // other and give no polygon at all (the crossing test below decides).
            constexpr double kFaceSlack = 1e-7;  // cells
            const double k0 = std::max(0.0, std::floor(lo / s[m] - kFaceSlack));
            const double k1 = std::min(double(blocks.dims[std::size_t(m)]) - 1.0, std::floor(hi / s[m] + kFaceSlack));
            for (double kk = k0; kk <= k1; ++kk) {
                std::size_t idx[3];
                idx[a] = ia;
                idx[b] = ib;
                idx[m] = std::size_t(kk);
                glm::dvec3 corner[8];
                double sd[8];
                for (int v = 0; v < 8; ++v) {
                    glm::dvec3 g;
                    for (int axis = 0; axis < 3; ++axis)
                        g[axis] = double(idx[axis] + std::size_t((v >> axis) & 1)) * s[axis];
                    corner[v] = g;
                    sd[v] = glm::dot(N, g) + c;
                }
                std::array<glm::dvec2, 12> pts;
                int n = 0;
                for (const auto& e : kEdges) {
                    const double s0 = sd[e[0]], s1 = sd[e[1]];
                    if ((s0 < 0.0) == (s1 < 0.0)) continue;
                    const double t = s0 / (s0 - s1);
                    pts[std::size_t(n++)] = toUv(corner[e[0]] + t * (corner[e[1]] - corner[e[0]]));
                }
                CellPolygon cp{blocks.linear(idx[0], idx[1], idx[2]), convexRing(pts.data(), n)};
                if (cp.ring.empty() || outsideLimit(cp.ring, limit)) continue;
                if (gridParallel) {
                    glm::dvec2 centre(0.0);
                    for (const glm::dvec2& p : cp.ring) centre += p;
                    cp.cell = blocks.cellAt(frame.toWorld(centre / double(cp.ring.size())));
                    if (cp.cell == BlockModel::kNoCell) continue;
                }
                if (out.size() >= maxCells)
                    return makeError(ErrorCode::OutOfRange,
                                     "the section crosses more than " + std::to_string(maxCells) + " block cells");
                out.push_back(std::move(cp));
            }
        }
    }
    return out;
}

Ring clipRingToConvex(const Ring& subject, const Ring& clip) {
    Ring cur = subject, next;
    for (std::size_t e = 0; e < clip.size() && !cur.empty(); ++e) {
        const glm::dvec2 a = clip[e], b = clip[(e + 1) % clip.size()];
        const glm::dvec2 d = b - a;
        auto side = [&](const glm::dvec2& p) { return cross(d, p - a); };  // >= 0: inside (left of a->b)
        next.clear();
        for (std::size_t i = 0; i < cur.size(); ++i) {
            const glm::dvec2 p = cur[i], r = cur[(i + 1) % cur.size()];
            const double sp = side(p), sr = side(r);
            if (sp >= 0.0) next.push_back(p);
            if ((sp >= 0.0) != (sr >= 0.0)) {
                const double t = sp / (sp - sr);
                next.push_back(p + t * (r - p));
            }
        }
        std::swap(cur, next);
    }
    if (cur.size() < 3) cur.clear();
    return cur;
}

namespace {

// The pieces of `cells` (polygons in the bodies' 2D frame) inside every clipping body of `bodies`.
// A cell given by several polygons (its tetrahedra's cuts, consecutive) gives one piece per
// body: the union of their clipped rings.
void piecesOf(const BlockModel& blocks, const std::vector<CellPolygon>& cells, const std::vector<BodySection>& bodies,
              std::vector<BlockPiece>& out) {
    for (const BodySection& body : bodies) {
        if (!blocks.clips(body.part)) continue;
        const std::size_t firstOfBody = out.size();
        std::vector<const Ring*> rings;
        std::vector<std::array<glm::dvec2, 2>> boxes;
        for (const SectionPolygon& p : body.polygons) {
            rings.push_back(&p.outer);
            for (const Ring& h : p.holes) rings.push_back(&h);
        }
        for (const Ring* r : rings) {
            glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
            for (const auto& p : *r) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            boxes.push_back({lo, hi});
        }
        for (const CellPolygon& cp : cells) {
            glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
            for (const auto& p : cp.ring) {
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
            BlockPiece piece;
            piece.cell = cp.cell;
            piece.body = body.part;
            piece.record = body.record;
            for (std::size_t r = 0; r < rings.size(); ++r) {
                if (boxes[r][1].x < lo.x || boxes[r][0].x > hi.x || boxes[r][1].y < lo.y || boxes[r][0].y > hi.y)
                    continue;
                Ring clipped = clipRingToConvex(*rings[r], cp.ring);
                if (clipped.empty()) continue;
                const double area = ringArea(clipped);
                if (area == 0.0) continue;
                piece.area += area;
                piece.rings.push_back(std::move(clipped));
            }
            if (!(piece.area > 0.0)) continue;
            if (out.size() > firstOfBody && out.back().cell == piece.cell) {
                BlockPiece& last = out.back();
                last.area += piece.area;
                for (Ring& r : piece.rings) last.rings.push_back(std::move(r));
            } else {
                out.push_back(std::move(piece));
            }
        }
    }
}

}  // namespace

Result<std::vector<BlockPiece>> blockPieces(const BlockModel& blocks, const Section& section, const FrameRect* limit) {
    std::vector<BlockPiece> out;
    auto cells = cellPolygons(blocks, section.frame, limit);
    if (!cells) return cells.error();
    piecesOf(blocks, cells.value(), section.bodies, out);
    return out;
}

Result<std::vector<BlockPiece>> blockPieces(const BlockModel& blocks, const PolylineSection& section,
                                            const glm::dvec3& modelOrigin, const FrameRect* limit) {
    std::vector<BlockPiece> out;
    std::vector<CellPolygon> cells;
    for (const PolylineLeg& leg : section.legs) {
        if (!leg.cut) continue;
        // The leg's strip of the line frame (s, z), in its own plane's u/v (v = z).
        FrameRect strip{leg.s0, -std::numeric_limits<double>::max(), leg.s1, std::numeric_limits<double>::max()};
        if (limit) {
            strip.u0 = std::max(strip.u0, limit->u0);
            strip.u1 = std::min(strip.u1, limit->u1);
            strip.v0 = limit->v0;
            strip.v1 = limit->v1;
            if (!(strip.u0 < strip.u1)) continue;
        }
        FrameRect own = strip;
        own.u0 -= leg.uOffset;
        own.u1 -= leg.uOffset;
        auto legCells = cellPolygons(blocks, makeSectionFrame(leg.plane, modelOrigin), &own);
        if (!legCells) return legCells.error();
        for (CellPolygon& cp : legCells.value()) {
            for (glm::dvec2& p : cp.ring) p.x += leg.uOffset;
            cp.ring = clipRingToStrip(cp.ring, leg.s0, leg.s1);
            if (cp.ring.size() >= 3 && ringArea(cp.ring) > 0.0) cells.push_back(std::move(cp));
        }
        if (cells.size() > 4000000)
            return makeError(ErrorCode::OutOfRange, "the section line crosses more than 4,000,000 block cells");
    }
    piecesOf(blocks, cells, section.bodies, out);
    return out;
}

namespace {

std::string hexOf(Rgba8 c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

}  // namespace

std::string blockPiecesSvg(const BlockModel& blocks, const PropertyClasses& classes,
                           const std::vector<BlockPiece>& pieces, const FrameRect& rect, int width, int height) {
    const double sx = width / (rect.u1 - rect.u0), sy = height / (rect.v1 - rect.v0);
    const BlockProperty& prop = blocks.properties[std::size_t(classes.property)];
    std::string out;
    char buf[160];
    for (const BlockPiece& piece : pieces) {
        const double v = prop.values[piece.cell];
        if (std::isnan(v)) continue;
        const auto ijk = blocks.ijk(piece.cell);
        std::snprintf(buf, sizeof buf,
                      "<path fill=\"%s\" fill-rule=\"evenodd\" data-cell=\"%zu,%zu,%zu\" data-record=\"%u\" d=\"",
                      hexOf(classes.colourOf(v)).c_str(), ijk[0], ijk[1], ijk[2], piece.record);
        out += buf;
        bool first = true;
        for (const Ring& r : piece.rings) {
            for (std::size_t i = 0; i < r.size(); ++i) {
                std::snprintf(buf, sizeof buf, "%s%s%.3f,%.3f", first ? "" : " ", i == 0 ? "M" : "L",
                              (r[i].x - rect.u0) * sx, (rect.v1 - r[i].y) * sy);
                out += buf;
                first = false;
            }
            out += " Z";
        }
        std::snprintf(buf, sizeof buf, "\"><title>cell %zu,%zu,%zu: %s = %.6g</title></path>\n", ijk[0], ijk[1], ijk[2],
                      prop.name.c_str(), v);
        out += buf;
    }
    return out;
}

nlohmann::ordered_json blockPiecesGeoJson(const BlockModel& blocks, const PropertyClasses& classes,
                                          const std::vector<BlockPiece>& pieces, const GeoJsonSpace& space) {
    nlohmann::ordered_json features = nlohmann::ordered_json::array();
    const BlockProperty& prop = blocks.properties[std::size_t(classes.property)];
    for (const BlockPiece& piece : pieces) {
        // Group: each clockwise ring (a hole) goes with the first counter-clockwise ring that
        // holds its mean point, else with the first outer ring.
        std::vector<const Ring*> outers, holes;
        for (const Ring& r : piece.rings) (ringArea(r) > 0.0 ? outers : holes).push_back(&r);
        if (outers.empty()) continue;
        std::vector<std::vector<const Ring*>> polys;
        for (const Ring* o : outers) polys.push_back({o});
        for (const Ring* h : holes) {
            glm::dvec2 mean(0.0);
            for (const auto& p : *h) mean += p;
            mean /= double(h->size());
            std::size_t k = 0;
            for (std::size_t o = 0; o < outers.size(); ++o)
                if (pointInRing(mean, *outers[o])) {
                    k = o;
                    break;
                }
            polys[k].push_back(h);
        }
        nlohmann::ordered_json coords = nlohmann::ordered_json::array();
        for (const auto& poly : polys) {
            nlohmann::ordered_json rings = nlohmann::ordered_json::array();
            for (const Ring* r : poly) rings.push_back(geoJsonRing(*r, r == poly.front(), space));
            coords.push_back(std::move(rings));
        }
        const auto ijk = blocks.ijk(piece.cell);
        nlohmann::ordered_json props;
        props["kind"] = "block";
        props["cell"] = {ijk[0], ijk[1], ijk[2]};
        props["part"] = piece.body;
        props["record"] = piece.record;
        props["area_m2"] = piece.area;
        nlohmann::ordered_json values;
        for (const BlockProperty& p : blocks.properties)
            values[p.name] = std::isnan(p.values[piece.cell]) ? nlohmann::ordered_json(nullptr)
                                                              : nlohmann::ordered_json(p.values[piece.cell]);
        props["properties"] = std::move(values);
        const double v = prop.values[piece.cell];
        props["class"] = std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(classes.classOf(v));
        props["colour"] =
            std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(hexOf(classes.colourOf(v)));
        features.push_back({{"type", "Feature"},
                            {"geometry", {{"type", "MultiPolygon"}, {"coordinates", std::move(coords)}}},
                            {"properties", std::move(props)}});
    }
    return features;
}

}  // namespace geoslice
