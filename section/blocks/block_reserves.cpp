#include "section/blocks/block_reserves.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>

#include "model/blocks/cell_locator.hpp"
#include "section/blocks/block_tet_volumes.hpp"
#include "section/cut/edge_crossing.hpp"
#include "section/volumes/reserves.hpp"

namespace geoslice {
namespace {

// The planes of one grid axis: plane p is at p * s; a coordinate equal to a plane counts as
// below it (see the header).
struct Axis {
    double s = 1.0;
    long n = 0;  // cells
    double plane(long p) const { return double(p) * s; }
    // The smallest p with plane(p) >= x.
    long firstAtOrAbove(double x) const {
        double t = std::ceil(x / s);
        t = std::clamp(t, -1e15, 1e15);
        long p = long(t);
        while (plane(p - 1) >= x) --p;
        while (plane(p) < x) ++p;
        return p;
    }
    // The cell (plane(c), plane(c + 1)] holding x (may be outside 0..n-1).
    long cellOf(double x) const { return firstAtOrAbove(x) - 1; }
};

using Poly = std::vector<glm::dvec3>;

// Keeps the part of `in` with g[a] > P (above) or g[a] <= P (!above); new points lie on P exactly.
void clipPoly(const Poly& in, int a, double P, bool above, Poly& out) {
    out.clear();
    const std::size_t n = in.size();
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3& p = in[i];
        const glm::dvec3& q = in[(i + 1) % n];
        const bool ip = above ? p[a] > P : p[a] <= P;
        const bool iq = above ? q[a] > P : q[a] <= P;
        if (ip) out.push_back(p);
        if (ip != iq) {
            const double t = (P - p[a]) / (q[a] - p[a]);
            glm::dvec3 r = p + t * (q - p);
            r[a] = P;
            out.push_back(r);
        }
    }
    if (out.size() < 3) out.clear();
}

// The point of segment ab at g[axis] = P, computed from the endpoints in a fixed order so that
// the two triangles of a shared edge give the same point.
glm::dvec3 crossAt(glm::dvec3 a, glm::dvec3 b, int axis, double P) {
    if (b.x < a.x || (b.x == a.x && (b.y < a.y || (b.y == a.y && b.z < a.z)))) std::swap(a, b);
    const double t = (P - a[axis]) / (b[axis] - a[axis]);
    glm::dvec3 r = a + t * (b - a);
    r[axis] = P;
    return r;
}

struct Crossing {
    long line = 0;  // index of the (plane, y line) pair
    double z = 0.0;
    int o = 0;  // +1 leaving upwards, -1 entering
    bool operator<(const Crossing& c) const { return line != c.line ? line < c.line : z < c.z; }
};

}  // namespace

Mesh keptSideShell(const Mesh& body, const Plane& plane) {
    Mesh out;
    struct Vertex {
        glm::dvec3 p;
        bool on;  // on the plane: a cut point or a vertex at distance 0
    };
    std::vector<std::pair<glm::dvec3, glm::dvec3>> capEdges;  // (p, q): kept piece edges on the plane
    glm::dvec3 cutSum(0.0);
    std::size_t cutCount = 0;
    auto emit = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        const auto base = std::uint32_t(out.positions.size());
        out.positions.insert(out.positions.end(), {a, b, c});
        out.indices.insert(out.indices.end(), {base, base + 1, base + 2});
    };
    for (std::size_t t = 0; t < body.triangleCount(); ++t) {
        glm::dvec3 p[3];
        double s[3];
        int kept = 0;
        for (int k = 0; k < 3; ++k) {
            p[k] = body.positions[body.indices[3 * t + std::size_t(k)]];
            s[k] = glm::dot(plane.normal, p[k]) + plane.d;
            kept += s[k] >= 0.0;
        }
        // A triangle on the plane and the cap over its edges are the same planar 2-chain with
        // opposite signs (volume 0): leave both out. (Kept, they would double the caps every
        // time a shell is clipped again on a plane it was capped on.)
        if (kept == 0 || (s[0] == 0.0 && s[1] == 0.0 && s[2] == 0.0)) continue;
        Vertex poly[4];
        int n = 0;
        for (int k = 0; k < 3; ++k) {
            const int k1 = (k + 1) % 3;
            if (s[k] >= 0.0) poly[n++] = {p[k], s[k] == 0.0};
            if ((s[k] >= 0.0) != (s[k1] >= 0.0)) {
                poly[n++] = {edgeCrossing(p[k], s[k], p[k1], s[k1]), true};
                cutSum += poly[n - 1].p;
                ++cutCount;
            }
        }
        for (int k = 1; k + 1 < n; ++k) emit(poly[0].p, poly[k].p, poly[k + 1].p);
        for (int k = 0; k < n; ++k)
            if (poly[k].on && poly[(k + 1) % n].on) {
                capEdges.emplace_back(poly[k].p, poly[(k + 1) % n].p);
                if (cutCount == 0) {
                    cutSum += poly[k].p;
                    ++cutCount;
                }
            }
    }
    if (capEdges.empty()) return out;
    glm::dvec3 o = cutSum / double(cutCount);
    o -= (glm::dot(plane.normal, o) + plane.d) * plane.normal;
    for (const auto& [a, b] : capEdges) emit(o, b, a);
    return out;
}

Mesh clipToConvex(const Mesh& closed, const std::vector<Plane>& planes) {
    Mesh m = closed;
    for (const Plane& p : planes) {
        if (m.indices.empty()) break;
        m = keptSideShell(m, p);
    }
    return m;
}

std::vector<CellVolume> cellBodyVolumes(const BlockModel& blocks, const Mesh& body, const Plane& plane) {
    std::vector<CellVolume> cells = cellBodyVolumes(blocks, keptSideShell(body, plane));
    std::erase_if(cells, [&](const CellVolume& c) { return std::abs(c.volume) <= 1e-9 * blocks.cellVolume(c.cell); });
    return cells;
}

namespace {

// A tetrahedron of a hexahedral cell, relative to the body's centre.
struct TetCell {
    std::size_t cell = 0;
    std::vector<Plane> planes;  // 4, inward unit normals
};

}  // namespace

std::vector<CellVolume> clippedCellBodyVolumes(const BlockModel& blocks, const Mesh& body) {
    std::vector<CellVolume> out;
    if (blocks.shape != CellShape::Hexahedron || blocks.cellCount() == 0 || body.indices.size() < 12) return out;
    const Aabb bb = body.bounds();
    if (!bb.valid()) return out;
    const glm::dvec3 o = bb.centre();
    Mesh shell = body;
    for (glm::dvec3& p : shell.positions) p -= o;
    std::vector<TetCell> tets;
    const auto meetsBody = [&](const Aabb& b) { return b.meets(bb); };
    blocks.locator->cellsMeeting(meetsBody, [&](std::size_t cell) {
        const auto k = blocks.cellCorners(cell);
        for (const auto& t : kCellTets) {
            TetCell tc;
            tc.cell = cell;
            glm::dvec3 v[4];
            for (int m = 0; m < 4; ++m) {
                v[m] = k[std::size_t(t[std::size_t(m)])] - o;
            }
            for (int m = 0; m < 4; ++m) {
                // The face opposite v[m], its normal towards v[m].
                const glm::dvec3 &a = v[(m + 1) % 4], &b = v[(m + 2) % 4], &c = v[(m + 3) % 4];
                glm::dvec3 nrm = glm::normalize(glm::cross(b - a, c - a));
                if (glm::dot(nrm, v[m] - a) < 0.0) nrm = -nrm;
                tc.planes.push_back({nrm, -glm::dot(nrm, a)});
            }
            tets.push_back(std::move(tc));
        }
    });
    std::vector<CellVolume> pieces;
    for (const TetCell& t : tets) {
        const double v = meshVolume(clipToConvex(shell, t.planes));
        if (v != 0.0) pieces.push_back({t.cell, v});
    }
    std::sort(pieces.begin(), pieces.end(), [](const CellVolume& x, const CellVolume& y) { return x.cell < y.cell; });
    for (const CellVolume& p : pieces) {
        if (!out.empty() && out.back().cell == p.cell)
            out.back().volume += p.volume;
        else
            out.push_back(p);
    }
    std::erase_if(out, [&](const CellVolume& c) { return std::abs(c.volume) <= 1e-9 * blocks.cellVolume(c.cell); });
    return out;
}

std::vector<CellVolume> cellBodyVolumes(const BlockModel& blocks, const Mesh& body) {
    std::vector<CellVolume> out;
    if (blocks.cellCount() == 0 || body.indices.size() < 12) return out;
    if (blocks.shape == CellShape::Hexahedron) return tetCellBodyVolumes(blocks, body);
    const Axis ax{blocks.size[0], long(blocks.dims[0])}, ay{blocks.size[1], long(blocks.dims[1])},
        az{blocks.size[2], long(blocks.dims[2])};
    std::vector<glm::dvec3> g(body.positions.size());
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < g.size(); ++v) {
        g[v] = blocks.toGrid(body.positions[v]);
        lo = glm::min(lo, g[v]);
        hi = glm::max(hi, g[v]);
    }
    // A left-handed grid frame mirrors the body: its outward triangles turn inward.
    const double handed = glm::dot(glm::cross(blocks.axis[0], blocks.axis[1]), blocks.axis[2]) < 0.0 ? -1.0 : 1.0;
    // Cells of the body's bounding box, inside the grid.
    const long i0 = std::max(0L, ax.cellOf(lo.x)), i1 = std::min(ax.n - 1, ax.cellOf(hi.x));
    const long j0 = std::max(0L, ay.cellOf(lo.y)), j1 = std::min(ay.n - 1, ay.cellOf(hi.y));
    const long k0 = std::max(0L, az.cellOf(lo.z)), k1 = std::min(az.n - 1, az.cellOf(hi.z));
    if (i0 > i1 || j0 > j1 || k0 > k1) return out;
    const long ni = i1 - i0 + 1, nj = j1 - j0 + 1, nk = k1 - k0 + 1;
    auto local = [&](long i, long j, long k) { return std::size_t((i - i0) + ni * ((j - j0) + nj * (k - k0))); };
    std::vector<double> vol(std::size_t(ni * nj * nk), 0.0);
    // C(p, j, k): the section area term of plane p = i + 1 for cell (i, j, k), stored at (i, j, k).
    std::vector<double> cap(vol.size(), 0.0);
    std::vector<Crossing> crossings;
    std::vector<double> many;  // a segment's parameters where it crosses y and z planes

    Poly tri(3), a, b, c, d, e, f;
    const std::size_t triangles = body.indices.size() / 3;
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::dvec3 v0 = g[body.indices[3 * t]], v1 = g[body.indices[3 * t + 1]], v2 = g[body.indices[3 * t + 2]];
        const glm::dvec3 tlo = glm::min(v0, glm::min(v1, v2)), thi = glm::max(v0, glm::max(v1, v2));
        // ---- 3D: the triangle's pieces in each cell: A_yz (x̄ - X_i).
        const long ti0 = std::max(i0, ax.cellOf(tlo.x)), ti1 = std::min(i1, ax.cellOf(thi.x));
        const long tj0 = std::max(j0, ay.cellOf(tlo.y)), tj1 = std::min(j1, ay.cellOf(thi.y));
        const long tk0 = std::max(k0, az.cellOf(tlo.z)), tk1 = std::min(k1, az.cellOf(thi.z));
        tri = {v0, v1, v2};
        for (long i = ti0; i <= ti1; ++i) {
            clipPoly(tri, 0, ax.plane(i), true, a);
            clipPoly(a, 0, ax.plane(i + 1), false, b);
            if (b.empty()) continue;
            for (long j = tj0; j <= tj1; ++j) {
                clipPoly(b, 1, ay.plane(j), true, c);
                clipPoly(c, 1, ay.plane(j + 1), false, d);
                if (d.empty()) continue;
                for (long k = tk0; k <= tk1; ++k) {
                    clipPoly(d, 2, az.plane(k), true, e);
                    clipPoly(e, 2, az.plane(k + 1), false, f);
                    if (f.empty()) continue;
                    const double x0 = ax.plane(i);
                    double sum = 0.0;
                    for (std::size_t m = 1; m + 1 < f.size(); ++m) {
                        const glm::dvec3 p = f[0], q = f[m], r = f[m + 1];
                        const double ayz = 0.5 * ((q.y - p.y) * (r.z - p.z) - (q.z - p.z) * (r.y - p.y));
                        sum += ayz * ((p.x + q.x + r.x) / 3.0 - x0);
                    }
                    vol[local(i, j, k)] += sum;
                }
            }
        }
        // ---- 2D: the triangle's segment on each plane x = X_p it crosses (p = i + 1).
        const long p0 = std::max(i0 + 1, ax.firstAtOrAbove(tlo.x)), p1 = std::min(i1 + 1, ax.firstAtOrAbove(thi.x) - 1);
        if (p0 > p1) continue;
        const glm::dvec3 n = glm::cross(v1 - v0, v2 - v0);
        const glm::dvec3 tv[3] = {v0, v1, v2};
        for (long p = p0; p <= p1; ++p) {
            const double X = ax.plane(p);
            glm::dvec3 pts[2];
            int np = 0;
            for (int ed = 0; ed < 3 && np < 2; ++ed) {
                const glm::dvec3 &u = tv[ed], &w = tv[(ed + 1) % 3];
                if ((u.x <= X) != (w.x <= X)) pts[np++] = crossAt(u, w, 0, X);
            }
            if (np != 2) continue;
            glm::dvec3 s0 = pts[0], s1 = pts[1];
            // Region on the left in (y, z): the outward normal (dz, -dy) agrees with (n_y, n_z).
            const double orient = (s1.z - s0.z) * n.y - (s1.y - s0.y) * n.z;
            if (orient == 0.0) continue;
            if (orient < 0.0) std::swap(s0, s1);
            const long i = p - 1;
            // Area term: pieces between the y and z planes the segment crosses, (ȳ - Y_j) dz.
            if (s0.z != s1.z) {
                const double ylo = std::min(s0.y, s1.y), yhi = std::max(s0.y, s1.y);
                const double zlo = std::min(s0.z, s1.z), zhi = std::max(s0.z, s1.z);
                many.clear();
                // Only the planes of the box's cells matter: pieces beyond them are skipped.
                auto addPlanes = [&](const Axis& A, double vlo, double vhi, double v0s, double v1s, long qlo,
                                     long qhi) {
                    if (v0s == v1s) return;
                    for (long q = std::max(qlo, A.firstAtOrAbove(vlo)); q <= qhi && A.plane(q) < vhi; ++q) {
                        const double tt = (A.plane(q) - v0s) / (v1s - v0s);
                        if (tt > 0.0 && tt < 1.0) many.push_back(tt);
                    }
                };
                addPlanes(ay, ylo, yhi, s0.y, s1.y, j0, j1 + 1);
                addPlanes(az, zlo, zhi, s0.z, s1.z, k0, k1 + 1);
                many.push_back(0.0);
                many.push_back(1.0);
                std::sort(many.begin(), many.end());
                for (std::size_t m = 0; m + 1 < many.size(); ++m) {
                    const double ta = many[m], tb = many[m + 1];
                    if (!(tb > ta)) continue;
                    const double ya = s0.y + ta * (s1.y - s0.y), yb = s0.y + tb * (s1.y - s0.y);
                    const double za = s0.z + ta * (s1.z - s0.z), zb = s0.z + tb * (s1.z - s0.z);
                    const double ym = s0.y == s1.y ? s0.y : 0.5 * (ya + yb);
                    const double zm = 0.5 * (za + zb);
                    const long j = ay.cellOf(ym), k = az.cellOf(zm);
                    if (j < j0 || j > j1 || k < k0 || k > k1) continue;
                    cap[local(i, j, k)] += (0.5 * (ya + yb) - ay.plane(j)) * (zb - za);
                }
            }
            // Crossings with the lines y = Y_q of this plane (q = j + 1 for the cells' faces).
            if (s0.y != s1.y) {
                const double ylo = std::min(s0.y, s1.y), yhi = std::max(s0.y, s1.y);
                const long q0 = std::max(j0 + 1, ay.firstAtOrAbove(ylo)),
                           q1 = std::min(j1 + 1, ay.firstAtOrAbove(yhi) - 1);
                for (long q = q0; q <= q1; ++q) {
                    const double Y = ay.plane(q);
                    if (!((ylo <= Y) && (Y < yhi))) continue;
                    glm::dvec3 ea = s0, eb = s1;
                    if (eb.y < ea.y || (eb.y == ea.y && eb.z < ea.z)) std::swap(ea, eb);
                    const double tt = (Y - ea.y) / (eb.y - ea.y);
                    const double z = ea.z + tt * (eb.z - ea.z);
                    const int o = -(s1.y - s0.y) > 0.0 ? 1 : -1;  // m_z = -dy of the oriented segment
                    crossings.push_back({(p - (i0 + 1)) * (nj + 1) + (q - j0), z, o});
                }
            }
        }
    }
    // ---- 1D: along each line (plane p, y = Y_q), L for the cells (p - 1, q - 1, k).
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t s = 0; s < crossings.size();) {
        std::size_t e2 = s;
        while (e2 < crossings.size() && crossings[e2].line == crossings[s].line) ++e2;
        const long line = crossings[s].line;
        const long p = line / (nj + 1) + i0 + 1, q = line % (nj + 1) + j0;
        const long i = p - 1, j = q - 1;
        if (j >= j0 && j <= j1) {
            // inside(Z) = entries minus exits at or below Z.
            int inside = 0;
            std::size_t m = s;
            // Crossings below Z_k0.
            while (m < e2 && crossings[m].z <= az.plane(k0)) inside -= crossings[m++].o;
            for (long k = k0; k <= k1; ++k) {
                const double Z0 = az.plane(k), Z1 = az.plane(k + 1);
                double L = 0.0;
                while (m < e2 && crossings[m].z <= Z1) {
                    L += (crossings[m].z - Z0) * crossings[m].o;
                    inside -= crossings[m].o;
                    ++m;
                }
                L += (Z1 - Z0) * inside;
                cap[local(i, j, k)] += ay.s * L;
            }
        }
        s = e2;
    }
    for (long k = k0; k <= k1; ++k)
        for (long j = j0; j <= j1; ++j)
            for (long i = i0; i <= i1; ++i) {
                const std::size_t l = local(i, j, k);
                const double v = handed * (vol[l] + ax.s * cap[l]);
                if (v != 0.0) out.push_back({blocks.linear(std::size_t(i), std::size_t(j), std::size_t(k)), v});
            }
    std::sort(out.begin(), out.end(), [](const CellVolume& x, const CellVolume& y) { return x.cell < y.cell; });
    return out;
}

Result<GradeTonnage> computeGradeTonnage(const Model& model, const std::string& property,
                                         const std::vector<double>& cutoffs, const std::optional<Plane>& plane) {
    std::optional<Plane> kept;
    if (plane) {
        auto p = makePlane(plane->normal.x, plane->normal.y, plane->normal.z, plane->d);
        if (!p) return makeError(p.error().code, "parameter 'plane': " + p.error().message);
        kept = p.value();
    }
    if (!model.blocks) return makeError(ErrorCode::InvalidArgument, "the model has no block model");
    const BlockModel& blocks = *model.blocks;
    auto volumes = [&](const Mesh& mesh) {
        return kept ? cellBodyVolumes(blocks, mesh, *kept) : cellBodyVolumes(blocks, mesh);
    };
    const int k = blocks.propertyIndex(property);
    if (k < 0)
        return makeError(ErrorCode::InvalidArgument, "parameter 'property': the block model has no property '" +
                                                         property + "' (properties: " + blocks.propertyList() + ")");
    if (cutoffs.size() > 64) return makeError(ErrorCode::OutOfRange, "parameter 'cutoffs': at most 64 cut-offs");
    for (std::size_t c = 0; c < cutoffs.size(); ++c)
        if (!std::isfinite(cutoffs[c]) || (c > 0 && !(cutoffs[c] > cutoffs[c - 1])))
            return makeError(ErrorCode::InvalidArgument, "parameter 'cutoffs': values must be finite and increase");
    const BlockProperty& grade = blocks.properties[std::size_t(k)];
    int densityIndex = -1;
    for (std::size_t p = 0; p < blocks.properties.size(); ++p) {
        std::string n = blocks.properties[p].name;
        std::transform(n.begin(), n.end(), n.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
        if (n == "density") densityIndex = int(p);
    }
    GradeTonnage out;
    out.property = grade.name;
    out.unit = grade.unit;
    out.cutoffs = cutoffs;
    out.plane = kept;
    for (std::uint32_t b : blocks.clipBodyIndex) {
        const Part& part = model.bodies[b];
        std::vector<CellVolume> cells = volumes(part.mesh);
        // Net: the bodies nested directly inside this one are not part of its region.
        for (std::uint32_t c = 0; c < model.bodies.size(); ++c) {
            if (model.bodies[c].report.parent != int(b) || !model.bodies[c].report.closed) continue;
            std::vector<CellVolume> inner = volumes(model.bodies[c].mesh);
            std::size_t m = 0;
            for (const CellVolume& cv : inner) {
                while (m < cells.size() && cells[m].cell < cv.cell) ++m;
                if (m < cells.size() && cells[m].cell == cv.cell) cells[m].volume -= cv.volume;
            }
        }
        BodyGradeTonnage bt;
        bt.body = b;
        bt.record = part.record;
        const AttributeRecord* rec = model.attributes.find(part.record);
        // NaN: the record has no density.
        double recordDensity = std::numeric_limits<double>::quiet_NaN();
        if (rec && rec->density) recordDensity = *rec->density;
        bt.densitySource = densityIndex >= 0 ? "block property '" + blocks.properties[std::size_t(densityIndex)].name +
                                                   "' (record density where a cell has none)"
                           : !std::isnan(recordDensity) ? "record"
                                                        : "none";
        bt.rows.resize(cutoffs.size());
        std::vector<double> tonnage(cutoffs.size(), 0.0), metalSum(cutoffs.size(), 0.0);
        bool allDensity = true;
        for (const CellVolume& cv : cells) {
            bt.volume += cv.volume;
            const double gv = grade.values[cv.cell];
            if (std::isnan(gv)) {
                bt.volumeNoGrade += cv.volume;
                continue;
            }
            double rho = std::numeric_limits<double>::quiet_NaN();
            if (densityIndex >= 0) rho = blocks.properties[std::size_t(densityIndex)].values[cv.cell];
            if (std::isnan(rho)) rho = recordDensity;
            for (std::size_t c = 0; c < cutoffs.size(); ++c) {
                if (!(gv >= cutoffs[c])) break;
                GradeTonnageRow& row = bt.rows[c];
                row.volume += cv.volume;
                ++row.cells;
                if (std::isnan(rho)) {
                    allDensity = false;
                    continue;
                }
                tonnage[c] += cv.volume * rho;
                metalSum[c] += cv.volume * rho * gv;
            }
        }
        for (std::size_t c = 0; c < cutoffs.size(); ++c) {
            GradeTonnageRow& row = bt.rows[c];
            row.cutoff = cutoffs[c];
            if (!allDensity || bt.densitySource == "none") continue;
            row.tonnage = tonnage[c];
            if (tonnage[c] > 0.0) {
                row.meanGrade = metalSum[c] / tonnage[c];
                auto [amount, unit] = metalContent(tonnage[c], *row.meanGrade, grade.unit);
                row.metal = amount;
                row.metalUnit = unit;
            }
        }
        out.bodies.push_back(std::move(bt));
    }
    return out;
}

}  // namespace geoslice
