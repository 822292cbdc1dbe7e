// The RINGMesh oracle (issue 10): independent point-in-region oracles computed here, in
// plain double arithmetic, from the text of tests/data/ringmesh (BSD-3-Clause, RING
// Consortium; Pellerin et al. 2015), against what the loaded models answer through
// Classifier::classify (section/rays/classify.hpp) and the exact section engine's ID buffer.
//
//  - TSolid (geomodel3d.so): point in tetrahedron over the file's 13,510 TETRA lines.
//  - Model3d (geomodel3d.ml): vertical-ray parity over the triangles of each REGION's
//    TFACEs, read from the file's embedded TSurfs (unsigned: parity needs no orientation).
//
// The two files share the box but are not the same geology (their horizons lie hundreds of
// metres apart and only the Model3d has faults; see tests/data/ringmesh/README.md), so each
// model is checked against the oracle from its own file; the agreement between the two
// files is printed for the record.
//
// Tolerance: points within band = 1e-6 x (half-extent + diagonal) + 0.1 mm of any region
// boundary may fall either side (the classifier's stated bound for rays in the float32
// local frame, section/rays/classify.hpp, at the longest ray this model allows: ~3.0 cm here).
// Required: >= 99.99 % agreement over all points and pixel centres, 100 % beyond the band.
// Volumes: reserves (divergence theorem over the loaded shells) against the summed
// tetrahedron volumes, and against the Model3d regions' volumes from the file's triangles,
// to 1e-9 relative (double rounding over ~1e5 terms of ~1e9 m^3 each).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "model/io/loaders.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"
#include "section/rays/classify.hpp"
#include "section/volumes/reserves.hpp"
#include "tests/common/random_plane.hpp"
#include "tests/common/tolerances.hpp"

using geoslice::test::kShellVsCellSumRelTol;  // relative, a shell volume against its cells sum
                                              // (tests/common/tolerances.hpp)
// Relative: the regions tile the box: their summed tetrahedron volumes against its volume.
constexpr double kTilesBoxRelTol = 1e-9;

namespace geoslice {
namespace {

const std::string kDir = std::string(GEOSLICE_TEST_DATA_DIR) + "/ringmesh/";

using dvec3 = glm::dvec3;

double orient(const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a));
}

// Ericson, Real-Time Collision Detection, 5.1.5: closest point on triangle abc to p.
dvec3 closestOnTriangle(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c) {
    const dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// Uniform 3D bins over a box: items inserted by their (expanded) bounding boxes.
struct Bins {
    dvec3 lo{0.0}, size{1.0};
    int n = 32;
    std::vector<std::vector<std::uint32_t>> cells;
    Bins(const dvec3& l, const dvec3& h, int cellsPerAxis) : lo(l), size(h - l), n(cellsPerAxis) {
        cells.resize(static_cast<std::size_t>(n) * n * n);
    }
    int axis(double x, int a) const {
        int i = static_cast<int>(std::floor((x - lo[a]) / size[a] * n));
        return std::clamp(i, 0, n - 1);
    }
    void insert(std::uint32_t item, const dvec3& bmin, const dvec3& bmax) {
        for (int k = axis(bmin.z, 2); k <= axis(bmax.z, 2); ++k)
            for (int j = axis(bmin.y, 1); j <= axis(bmax.y, 1); ++j)
                for (int i = axis(bmin.x, 0); i <= axis(bmax.x, 0); ++i)
                    cells[(static_cast<std::size_t>(k) * n + j) * n + i].push_back(item);
    }
    const std::vector<std::uint32_t>& at(const dvec3& p) const {
        return cells[(static_cast<std::size_t>(axis(p.z, 2)) * n + axis(p.y, 1)) * n + axis(p.x, 0)];
    }
};

// Boundary triangles of a model and "is p within `band` of one?".
struct BoundaryBand {
    std::vector<std::array<dvec3, 3>> tris;
    std::unique_ptr<Bins> bins;
    double band = 0.0;
    void build(const dvec3& lo, const dvec3& hi, double b) {
        band = b;
        bins = std::make_unique<Bins>(lo, hi, 48);
        for (std::uint32_t t = 0; t < tris.size(); ++t) {
            dvec3 mn = glm::min(glm::min(tris[t][0], tris[t][1]), tris[t][2]) - dvec3(b);
            dvec3 mx = glm::max(glm::max(tris[t][0], tris[t][1]), tris[t][2]) + dvec3(b);
            bins->insert(t, mn, mx);
        }
    }
    bool near(const dvec3& p) const {
        for (std::uint32_t t : bins->at(p)) {
            const auto& tr = tris[t];
            if (glm::distance(p, closestOnTriangle(p, tr[0], tr[1], tr[2])) <= band) return true;
        }
        return false;
    }
};

// ---- TSolid oracle: the file's tetrahedra ----
struct TetOracle {
    std::vector<dvec3> v;  // by file id (index = id)
    std::vector<std::array<std::uint32_t, 4>> tets;
    std::vector<int> region;
    std::vector<std::string> names;
    std::unique_ptr<Bins> bins;

    void read(const std::string& path) {
        std::ifstream in(path);
        std::string line, kw;
        while (std::getline(in, line)) {
            std::istringstream ls(line);
            if (!(ls >> kw)) continue;
            if (kw == "TVOLUME") {
                std::string name;
                ls >> name;
                names.push_back(name);
            } else if (kw == "VRTX" || kw == "PVRTX") {
                std::size_t id;
                dvec3 p;
                ls >> id >> p.x >> p.y >> p.z;
                if (v.size() <= id) v.resize(id + 1, dvec3(NAN));
                v[id] = p;
            } else if (kw == "ATOM") {
                std::size_t id, ref;
                ls >> id >> ref;
                if (v.size() <= id) v.resize(id + 1, dvec3(NAN));
                v[id] = v[ref];
            } else if (kw == "TETRA") {
                std::array<std::uint32_t, 4> t{};
                ls >> t[0] >> t[1] >> t[2] >> t[3];
                tets.push_back(t);
                region.push_back(static_cast<int>(names.size()) - 1);
            }
        }
    }
    double volume(std::size_t t) const {
        return orient(v[tets[t][0]], v[tets[t][1]], v[tets[t][2]], v[tets[t][3]]) / 6.0;
    }
    void index(const dvec3& lo, const dvec3& hi) {
        bins = std::make_unique<Bins>(lo, hi, 32);
        for (std::uint32_t t = 0; t < tets.size(); ++t) {
            dvec3 mn(INFINITY), mx(-INFINITY);
            for (auto i : tets[t]) {
                mn = glm::min(mn, v[i]);
                mx = glm::max(mx, v[i]);
            }
            bins->insert(t, mn, mx);
        }
    }
    // Region index of the tetrahedron holding p (closed tetrahedra), or -1.
    int locate(const dvec3& p) const {
        for (std::uint32_t t : bins->at(p)) {
            const dvec3 &a = v[tets[t][0]], &b = v[tets[t][1]], &c = v[tets[t][2]], &d = v[tets[t][3]];
            const double s = orient(a, b, c, d);
            const double o[4] = {orient(p, b, c, d), orient(a, p, c, d), orient(a, b, p, d), orient(a, b, c, p)};
            bool in = true;
            for (double x : o) in = in && (s > 0 ? x >= 0 : x <= 0);
            if (in) return region[t];
        }
        return -1;
    }
    // Faces between different regions or on the outside.
    void boundary(BoundaryBand& out) const {
        std::map<std::array<std::uint32_t, 3>, std::vector<int>> faces;
        static const int kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
        for (std::size_t t = 0; t < tets.size(); ++t)
            for (const auto& f : kFace) {
                std::array<std::uint32_t, 3> key{tets[t][f[0]], tets[t][f[1]], tets[t][f[2]]};
                std::sort(key.begin(), key.end());
                faces[key].push_back(region[t]);
            }
        for (const auto& [key, regs] : faces)
            if (regs.size() != 2 || regs[0] != regs[1]) out.tris.push_back({v[key[0]], v[key[1]], v[key[2]]});
    }
};

// ---- Model3d oracle: the triangles of each REGION's TFACEs, by vertical-ray parity ----
struct RegionOracle {
    std::vector<std::string> names;              // non-Universe regions
    std::vector<std::array<dvec3, 3>> tris;      // every TSurf triangle
    std::vector<std::array<int, 2>> triRegions;  // regions each triangle bounds (-1: none)
    std::vector<double> volume;                  // per region, from oriented triangles
    std::unique_ptr<Bins> bins;                  // xy only (one z layer)

    void read(const std::string& path) {
        std::ifstream in(path);
        std::string line, kw;
        struct Tface {
            std::string surface;
            dvec3 key[3];
        };
        std::map<long, Tface> tfaces;
        std::vector<std::pair<std::string, std::vector<long>>> regions;
        // Header.
        while (std::getline(in, line)) {
            std::istringstream ls(line);
            if (!(ls >> kw)) continue;
            if (kw == "TFACE") {
                long id;
                std::string type, surface;
                ls >> id >> type >> surface;
                Tface f{surface, {}};
                for (auto& k : f.key) {
                    std::getline(in, line);
                    std::istringstream ks(line);
                    ks >> k.x >> k.y >> k.z;
                }
                tfaces[id] = f;
            } else if (kw == "REGION") {
                long id;
                std::string name;
                ls >> id >> name;
                std::vector<long> faces;
                long s = 1;
                while (s != 0 && in >> s)
                    if (s != 0) faces.push_back(s);
                regions.emplace_back(name, faces);
            } else if (kw == "END") {
                break;
            }
        }
        // Surfaces: patches in file order per surface name.
        std::map<std::string, std::vector<std::vector<std::array<dvec3, 3>>>> patches;
        std::map<long, dvec3> vtx;
        std::string name;
        std::vector<std::vector<std::array<dvec3, 3>>> cur;
        while (std::getline(in, line)) {
            std::istringstream ls(line);
            if (!(ls >> kw)) continue;
            if (kw == "GOCAD") {
                vtx.clear();
                cur.clear();
            } else if (kw.rfind("name:", 0) == 0) {
                name = kw.substr(5);
            } else if (kw == "TFACE") {
                cur.emplace_back();
            } else if (kw == "VRTX" || kw == "PVRTX") {
                long id;
                dvec3 p;
                ls >> id >> p.x >> p.y >> p.z;
                vtx[id] = p;
            } else if (kw == "ATOM" || kw == "PATOM") {
                long id, ref;
                ls >> id >> ref;
                vtx[id] = vtx[ref];
            } else if (kw == "TRGL") {
                long a, b, c;
                ls >> a >> b >> c;
                cur.back().push_back({vtx[a], vtx[b], vtx[c]});
            } else if (kw == "END") {
                patches[name] = cur;
            }
        }
        // Header TFACE ids -> patches (k-th TFACE of a surface = its k-th patch).
        std::map<long, const std::vector<std::array<dvec3, 3>>*> patchOf;
        std::map<std::string, std::size_t> next;
        for (const auto& [id, f] : tfaces) patchOf[id] = &patches[f.surface][next[f.surface]++];
        std::map<long, std::size_t> firstTri;
        for (const auto& [id, p] : patchOf) {
            firstTri[id] = tris.size();
            for (const auto& t : *p) {
                tris.push_back(t);
                triRegions.push_back({-1, -1});
            }
        }
        for (const auto& [rname, faces] : regions) {
            if (rname == "Universe") continue;
            const int r = static_cast<int>(names.size());
            names.push_back(rname);
            double vol = 0.0;
            for (long s : faces) {
                const long id = s < 0 ? -s : s;
                const Tface& f = tfaces[id];
                const auto& tl = *patchOf[id];
                // Orientation of the patch relative to its key triangle (found by positions).
                int same = 0;
                for (const auto& t : tl)
                    for (int q = 0; q < 3 && same == 0; ++q)
                        if (t[q] == f.key[0]) {
                            if (t[(q + 1) % 3] == f.key[1] && t[(q + 2) % 3] == f.key[2]) same = 1;
                            if (t[(q + 2) % 3] == f.key[1] && t[(q + 1) % 3] == f.key[2]) same = -1;
                        }
                EXPECT_NE(same, 0) << "key triangle of TFACE " << id << " not found";
                // The region lies on the key normal's side for +: outward is the other way.
                const double sign = (s > 0 ? -1.0 : 1.0) * (same < 0 ? -1.0 : 1.0);
                for (std::size_t t = 0; t < tl.size(); ++t) {
                    vol += sign * glm::dot(tl[t][0], glm::cross(tl[t][1], tl[t][2])) / 6.0;
                    auto& tr = triRegions[firstTri[id] + t];
                    (tr[0] < 0 ? tr[0] : tr[1]) = r;
                }
            }
            volume.push_back(vol);
        }
    }
    void index(const dvec3& lo, const dvec3& hi) {
        bins = std::make_unique<Bins>(dvec3(lo.x, lo.y, 0), dvec3(hi.x, hi.y, 1), 96);
        for (std::uint32_t t = 0; t < tris.size(); ++t) {
            dvec3 mn = glm::min(glm::min(tris[t][0], tris[t][1]), tris[t][2]);
            dvec3 mx = glm::max(glm::max(tris[t][0], tris[t][1]), tris[t][2]);
            bins->insert(t, dvec3(mn.x, mn.y, 0.5), dvec3(mx.x, mx.y, 0.5));
        }
    }
    // Region whose triangles a vertical ray up from p crosses an odd number of times; -1
    // for none, -2 for more than one (overlap).
    int locate(const dvec3& p) const {
        std::vector<int> parity(names.size(), 0);
        for (std::uint32_t t : bins->at(dvec3(p.x, p.y, 0.5))) {
            const auto& tr = tris[t];
            const glm::dvec2 a(tr[0]), b(tr[1]), c(tr[2]), q(p);
            const double d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
            if (d == 0.0) continue;  // vertical triangle: the ray runs along it
            const double l1 = ((q.x - a.x) * (c.y - a.y) - (q.y - a.y) * (c.x - a.x)) / d;
            const double l2 = ((b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x)) / d;
            if (l1 < 0 || l2 < 0 || l1 + l2 > 1) continue;
            const double z = tr[0].z + l1 * (tr[1].z - tr[0].z) + l2 * (tr[2].z - tr[0].z);
            if (z <= p.z) continue;
            for (int r : triRegions[t])
                if (r >= 0) parity[static_cast<std::size_t>(r)] ^= 1;
        }
        int found = -1;
        for (std::size_t r = 0; r < parity.size(); ++r)
            if (parity[r]) found = found == -1 ? static_cast<int>(r) : -2;
        return found;
    }
};

struct Agreement {
    std::size_t total = 0, agree = 0, far = 0, farAgree = 0;
    void add(bool same, bool isFar) {
        ++total;
        agree += same;
        far += isFar;
        farAgree += same && isFar;
    }
    double ratio() const { return double(agree) / double(total); }
};

// Record id of each oracle region (-1 / -2 -> 0), matched by name.
template <class Oracle>
std::vector<RecordId> recordsByName(const Model& m, const Oracle& o) {
    std::vector<RecordId> out;
    for (const std::string& n : o.names) {
        RecordId id = 0;
        for (const Part& b : m.bodies)
            if (b.name == n) id = b.record;
        EXPECT_NE(id, 0u) << "no body named " << n;
        out.push_back(id);
    }
    return out;
}

template <class Oracle>
void checkModel(const char* label, const Model& m, const Oracle& oracle, const BoundaryBand& band) {
    const std::vector<RecordId> rec = recordsByName(m, oracle);
    auto expected = [&](const dvec3& p) {
        const int r = oracle.locate(p);
        return r >= 0 ? rec[static_cast<std::size_t>(r)] : RecordId(0);
    };
    auto classifier = Classifier::build(m);
    ASSERT_TRUE(classifier.ok()) << classifier.error().message;
    const Aabb b = m.bounds();

    // Random points in the model's box.
    std::mt19937_64 rng(1234);
    std::uniform_real_distribution<double> ux(b.min.x, b.max.x), uy(b.min.y, b.max.y), uz(b.min.z, b.max.z);
    const std::size_t n = 100000;
    std::vector<dvec3> pts(n);
    for (auto& p : pts) p = {ux(rng), uy(rng), uz(rng)};
    std::vector<RecordId> got(n);
    (*classifier)->classifyBatch(pts.data(), n, got.data(), 2);
    Agreement points;
    std::size_t shown = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const RecordId want = expected(pts[i]);
        const bool isFar = !band.near(pts[i]);
        points.add(got[i] == want, isFar);
        if (got[i] != want && isFar && shown++ < 5)
            ADD_FAILURE() << label << ": classify(" << pts[i].x << ", " << pts[i].y << ", " << pts[i].z
                          << ") = " << got[i] << ", the oracle says " << want;
    }
    EXPECT_GE(points.ratio(), 0.9999) << points.agree << " / " << points.total;
    EXPECT_EQ(points.farAgree, points.far);

    // Pixel centres of the exact section's ID buffer on random planes.
    auto index = buildSectionIndex(m);
    ASSERT_TRUE(index.ok()) << index.error().message;
    RasterOptions opt;
    opt.colour = false;
    opt.traces = false;
    Agreement pixels;
    std::mt19937_64 prng(77);
    const int W = 160, H = 120;
    shown = 0;
    for (int k = 0; k < 24; ++k) {
        const Plane plane = test::randomPlane(b, prng, k);
        auto s = computeSection(*index.value(), plane);
        ASSERT_TRUE(s.ok()) << s.error().message;
        auto img = rasterizeSection(*index.value(), s.value(), fitFrame(s.value(), W, H), W, H, opt);
        ASSERT_TRUE(img.ok()) << img.error().message;
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const dvec3 p = img->frame.pixelCentreWorld(i, j);
                const RecordId want = expected(p);
                const RecordId have = img->ids[static_cast<std::size_t>(j) * W + static_cast<std::size_t>(i)];
                const bool isFar = !band.near(p);
                pixels.add(have == want, isFar);
                if (have != want && isFar && shown++ < 5)
                    ADD_FAILURE() << label << ": plane " << k << " pixel (" << i << ", " << j << ") at " << p.x << ", "
                                  << p.y << ", " << p.z << " has id " << have << ", the oracle says " << want;
            }
    }
    EXPECT_GE(pixels.ratio(), 0.9999) << pixels.agree << " / " << pixels.total;
    EXPECT_EQ(pixels.farAgree, pixels.far);
    std::printf(
        "[ oracle   ] %s: classify %zu/%zu points agree (%zu/%zu beyond %.4f m of a boundary); section ID "
        "buffer %zu/%zu pixel centres (%zu/%zu beyond)\n",
        label, points.agree, points.total, points.farAgree, points.far, band.band, pixels.agree, pixels.total,
        pixels.farAgree, pixels.far);
}

double bandFor(const Model& m) {
    const Aabb b = m.bounds();
    const double diag = glm::length(b.size());
    return 1e-6 * (0.5 * diag + diag) + 1e-4;
}

TEST(RingmeshOracle, TsolidAgreesWithItsTetrahedra) {
    auto r = loadModel(kDir + "geomodel3d.so");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();
    TetOracle oracle;
    oracle.read(kDir + "geomodel3d.so");
    ASSERT_EQ(oracle.tets.size(), 13510u);
    const Aabb b = m.bounds();
    oracle.index(b.min, b.max);
    BoundaryBand band;
    oracle.boundary(band);
    band.build(b.min, b.max, bandFor(m));

    // Volumes: reserves per body against the summed tetrahedra of its TVOLUME.
    auto reserves = computeReserves(m);
    ASSERT_TRUE(reserves.ok()) << reserves.error().message;
    std::vector<double> tetVolume(oracle.names.size(), 0.0);
    for (std::size_t t = 0; t < oracle.tets.size(); ++t)
        tetVolume[static_cast<std::size_t>(oracle.region[t])] += std::fabs(oracle.volume(t));
    ASSERT_EQ(reserves->bodies.size(), oracle.names.size());
    for (const BodyReserves& br : reserves->bodies) {
        const std::string& name = m.bodies[br.body].name;
        const auto it = std::find(oracle.names.begin(), oracle.names.end(), name);
        ASSERT_NE(it, oracle.names.end()) << name;
        const double want = tetVolume[static_cast<std::size_t>(it - oracle.names.begin())];
        EXPECT_NEAR(br.grossVolume, want, kShellVsCellSumRelTol * want) << name;
        std::printf("[ oracle   ] TSolid %-12s reserves %.6f m3, tetrahedra %.6f m3, relative difference %.2e\n",
                    name.c_str(), br.grossVolume, want, std::fabs(br.grossVolume - want) / want);
    }
    checkModel("TSolid", m, oracle, band);
}

TEST(RingmeshOracle, Model3dAgreesWithItsRegionTriangles) {
    auto r = loadModel(kDir + "geomodel3d.ml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();
    RegionOracle oracle;
    oracle.read(kDir + "geomodel3d.ml");
    ASSERT_EQ(oracle.names.size(), 14u);
    const Aabb b = m.bounds();
    oracle.index(b.min, b.max);
    BoundaryBand band;
    band.tris = oracle.tris;
    band.build(b.min, b.max, bandFor(m));

    // The regions partition the box: their volumes add up to the box's (its sides are the
    // planes of the bounds), and each equals what reserves computes on the loaded body.
    double sum = 0.0;
    for (double v : oracle.volume) sum += v;
    const double box = (b.max.x - b.min.x) * (b.max.y - b.min.y) * (b.max.z - b.min.z);
    EXPECT_NEAR(sum, box, kTilesBoxRelTol * box);
    auto reserves = computeReserves(m);
    ASSERT_TRUE(reserves.ok()) << reserves.error().message;
    ASSERT_EQ(reserves->bodies.size(), oracle.names.size());
    double worst = 0.0;
    for (const BodyReserves& br : reserves->bodies) {
        const std::string& name = m.bodies[br.body].name;
        const auto it = std::find(oracle.names.begin(), oracle.names.end(), name);
        ASSERT_NE(it, oracle.names.end()) << name;
        const double want = oracle.volume[static_cast<std::size_t>(it - oracle.names.begin())];
        EXPECT_GT(want, 0.0) << name;
        EXPECT_NEAR(br.grossVolume, want, kShellVsCellSumRelTol * want) << name;
        worst = std::max(worst, std::fabs(br.grossVolume - want) / want);
    }
    std::printf(
        "[ oracle   ] Model3d: 14 region volumes from the file's triangles vs reserves: worst relative "
        "difference %.2e; their sum vs the box: %.2e\n",
        worst, std::fabs(sum - box) / box);
    checkModel("Model3d", m, oracle, band);
}

TEST(RingmeshOracle, TheTwoFilesAreDifferentGeology) {
    // For the record (README of tests/data/ringmesh): after the best region-to-region
    // matching, how many random points the TSolid and the Model3d put in matching regions.
    TetOracle tets;
    tets.read(kDir + "geomodel3d.so");
    RegionOracle regions;
    regions.read(kDir + "geomodel3d.ml");
    dvec3 lo(INFINITY), hi(-INFINITY);
    for (const auto& t : regions.tris)
        for (const auto& p : t) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    tets.index(lo, hi);
    regions.index(lo, hi);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y), uz(lo.z, hi.z);
    std::map<std::pair<int, int>, std::size_t> joint;
    const std::size_t n = 20000;
    for (std::size_t i = 0; i < n; ++i) {
        const dvec3 p(ux(rng), uy(rng), uz(rng));
        ++joint[{regions.locate(p), tets.locate(p)}];
    }
    // Each Model3d region votes for the TSolid region it overlaps most.
    std::map<int, std::pair<int, std::size_t>> best;
    for (const auto& [key, count] : joint)
        if (count > best[key.first].second) best[key.first] = {key.second, count};
    std::size_t agree = 0;
    for (const auto& [r, b] : best) agree += b.second;
    const double ratio = double(agree) / double(n);
    std::printf("[ oracle   ] Model3d vs TSolid: %.1f %% of %zu points in matching regions at best\n", 100.0 * ratio,
                n);
    // Far from the 99.99 % the same geology would give: the files cannot be each other's oracle.
    EXPECT_LT(ratio, 0.99);
}

}  // namespace
}  // namespace geoslice
