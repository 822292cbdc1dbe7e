#include "model/synthetic/synthetic.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace geoslice {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kWidth = 6000.0;   // param x' extent, m (east)
constexpr double kHeight = 4000.0;  // param y extent, m (north)
constexpr double kZRef = 700.0;     // elevation where the shear is zero, m
constexpr int kStrata = 7;
constexpr int kBlocks = 3;
constexpr std::array<double, kBlocks + 1> kBlockEdges = {0.0, 2000.0, 4100.0, kWidth};
constexpr std::array<double, kBlocks> kThrow = {0.0, -150.0, -60.0};  // graben: centre down
constexpr std::array<const char*, kBlocks> kBlockNames = {"west block", "graben", "east block"};
constexpr double kFaultCot = 0.36397023426620234;  // cot(70 deg)
constexpr double kMinThickness = 40.0;             // m, enforced between horizons
constexpr int kHostStratum = 5;                    // 1-based: Xujiahe Fm hosts the lens

struct StratumSpec {
    const char *name, *lithology, *age, *era, *colour;
    double density, thickness;
};
// Bottom to top, after the Sichuan Basin succession around silica sandstone mines.
constexpr std::array<StratumSpec, kStrata> kStrataSpecs = {{
    {"Maokou Formation", "limestone", "Middle Permian (P2m)", "Paleozoic", "#5b7fa6", 2.70, 250.0},
    {"Longtan Formation", "coal-bearing mudstone and shale", "Late Permian (P3l)", "Paleozoic", "#4a4a4a", 2.45, 150.0},
    {"Feixianguan Formation", "marl and oolitic limestone", "Early Triassic (T1f)", "Mesozoic", "#b07cc6", 2.65, 200.0},
    {"Jialingjiang Formation", "dolomite with gypsum", "Early Triassic (T1j)", "Mesozoic", "#8fb3d9", 2.80, 220.0},
    {"Xujiahe Formation", "quartz sandstone", "Late Triassic (T3x)", "Mesozoic", "#f2d16b", 2.55, 300.0},
    {"Ziliujing Formation", "purple-red mudstone", "Early Jurassic (J1z)", "Mesozoic", "#c96b5a", 2.50, 250.0},
    {"Shaximiao Formation", "siltstone and feldspathic sandstone", "Middle Jurassic (J2s)", "Mesozoic", "#d99a6c", 2.45,
     0.0},
}};

std::uint64_t splitmix(std::uint64_t& s) {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
double uniform(std::uint64_t& s) { return double(splitmix(s) >> 11) * (1.0 / 9007199254740992.0); }

// Smooth fields of the param frame (x' east, y north; metres).
struct Fields {
    double foldPhase, minorPhase, thickPhase, terrainPhase1, terrainPhase2;

    double fold(double x, double y) const {
        return 200.0 * std::sin(2.0 * kPi * x / 5200.0 + foldPhase) * (0.8 + 0.2 * std::cos(2.0 * kPi * y / 7000.0)) +
               25.0 * std::sin(2.0 * kPi * (x + y) / 1800.0 + minorPhase) + 0.02 * (y - 0.5 * kHeight);
    }
    double thicknessFactor(int k, double x, double y) const {
        return 1.0 +
               0.1 * std::sin(2.0 * kPi * x / 3700.0 + thickPhase + k) * std::cos(2.0 * kPi * y / 4300.0 + 0.7 * k);
    }
    double terrain(double x, double y) const {
        return 1800.0 + 160.0 * std::sin(2.0 * kPi * x / 3100.0 + terrainPhase1) * std::cos(2.0 * kPi * y / 2700.0) +
               70.0 * std::sin(2.0 * kPi * (x + 2.0 * y) / 1700.0 + terrainPhase2) + 0.03 * (x - 0.5 * kWidth);
    }
    int blockOf(double x) const {
        for (int b = 0; b < kBlocks; ++b)
            if (x <= kBlockEdges[static_cast<std::size_t>(b + 1)]) return b;
        return kBlocks - 1;
    }
    // Horizons h[0..kStrata] at (x, y) in block b: h[0] = zBottom, h[kStrata] = terrain.
    std::array<double, kStrata + 1> horizons(int b, double x, double y, double zBottom) const {
        std::array<double, kStrata + 1> h{};
        h[0] = zBottom;
        double z = -300.0 + fold(x, y) + kThrow[static_cast<std::size_t>(b)];
        for (int k = 1; k < kStrata; ++k) {
            z += kStrataSpecs[static_cast<std::size_t>(k - 1)].thickness * thicknessFactor(k, x, y);
            h[static_cast<std::size_t>(k)] = z;
        }
        h[kStrata] = terrain(x, y);
        for (int k = kStrata - 1; k >= 1; --k)  // keep every stratum at least kMinThickness thick
            h[static_cast<std::size_t>(k)] =
                std::min(h[static_cast<std::size_t>(k)], h[static_cast<std::size_t>(k + 1)] - kMinThickness);
        return h;
    }
};

// K(x'): 0 at the sides, -cot at fault 1 (dips east), +cot at fault 2 (dips west).
double shearSlope(double x) {
    const double x1 = kBlockEdges[1], x2 = kBlockEdges[2];
    if (x <= x1) return -kFaultCot * x / x1;
    if (x <= x2) return -kFaultCot + 2.0 * kFaultCot * (x - x1) / (x2 - x1);
    return kFaultCot * (kWidth - x) / (kWidth - x2);
}
glm::dvec3 shear(const glm::dvec3& p) { return {p.x + shearSlope(p.x) * (p.z - kZRef), p.y, p.z}; }

struct Plan {
    std::array<int, kBlocks> ncx{};  // cells per block along x'
    int ncy = 0;                     // cells along y
    int lensTheta = 0, lensPhi = 0;  // lens sphere resolution
    int faultNz = 0;                 // fault sheet cells along z
    std::size_t triangles(OreVariant ore) const {
        std::size_t t = 0;
        for (int n : ncx) t += kStrata * (4ull * n * ncy + 4ull * n + 4ull * ncy);
        std::size_t lens = 2ull * lensTheta * (lensPhi - 1);
        t += ore == OreVariant::Partition ? 2 * lens : lens;
        t += 2 * 2ull * ncy * faultNz;
        return t;
    }
};

Plan planFor(std::size_t target, OreVariant ore) {
    auto make = [&](int ncy) {
        Plan p;
        p.ncy = std::max(2, ncy);
        double dx = kHeight / p.ncy;
        for (int b = 0; b < kBlocks; ++b)
            p.ncx[static_cast<std::size_t>(b)] = std::max(
                2,
                static_cast<int>(std::lround(
                    (kBlockEdges[static_cast<std::size_t>(b + 1)] - kBlockEdges[static_cast<std::size_t>(b)]) / dx)));
        p.lensTheta = std::max(12, 4 * (p.ncy / 4));
        p.lensPhi = std::max(6, p.lensTheta / 2);
        p.faultNz = std::max(2, p.ncy / 2);
        return p;
    };
    // Strata dominate: ~ 4 * kStrata * 1.5 * ncy^2 triangles. Start there, then walk ncy.
    int ncy = std::max(2, static_cast<int>(std::sqrt(double(target) / (4.0 * kStrata * 1.5 * 1.06))));
    Plan best = make(ncy);
    auto err = [&](const Plan& p) { return std::abs(double(p.triangles(ore)) - double(target)); };
    for (int d = -3; d <= 3; ++d) {
        Plan p = make(ncy + d);
        if (err(p) < err(best)) best = p;
    }
    // Fine-tune: the lens takes up what is left, within sane limits.
    for (int i = 0; i < 64 && err(best) > 0.01 * double(target); ++i) {
        Plan p = best;
        std::size_t t = p.triangles(ore);
        int step = t < target ? 4 : -4;
        p.lensTheta = std::clamp(p.lensTheta + step, 12, 4096);
        p.lensPhi = std::max(6, p.lensTheta / 2);
        if (err(p) >= err(best)) break;
        best = p;
    }
    return best;
}

// Appends a grid of (nu+1) x (nv+1) vertices produced by f(i, j); returns the first index.
template <class F>
std::uint32_t addGrid(Mesh& m, int nu, int nv, F&& f) {
    auto first = static_cast<std::uint32_t>(m.positions.size());
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) m.positions.push_back(f(i, j));
    return first;
}
void quad(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {  // CCW a b c d
    m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
}

// Heightfield prism over [x0,x1] x [0,H] between horizon `lo` and `lo+1` (0-based index of
// the lower horizon) of block b. Top faces up, bottom down, walls outward.
void addStratumShell(Mesh& m, const Fields& f, int b, int lo, int ncx, int ncy, double zBottom) {
    const double x0 = kBlockEdges[static_cast<std::size_t>(b)], x1 = kBlockEdges[static_cast<std::size_t>(b + 1)];
    const double dx = (x1 - x0) / ncx, dy = kHeight / ncy;
    auto at = [&](int i, int j, int k) {
        double x = i == ncx ? x1 : x0 + i * dx, y = j == ncy ? kHeight : j * dy;
        return shear({x, y, f.horizons(b, x, y, zBottom)[static_cast<std::size_t>(k)]});
    };
    const std::uint32_t bot = addGrid(m, ncx, ncy, [&](int i, int j) { return at(i, j, lo); });
    const std::uint32_t top = addGrid(m, ncx, ncy, [&](int i, int j) { return at(i, j, lo + 1); });
    const auto row = static_cast<std::uint32_t>(ncx + 1);
    auto B = [&](int i, int j) { return bot + static_cast<std::uint32_t>(j) * row + static_cast<std::uint32_t>(i); };
    auto T = [&](int i, int j) { return top + static_cast<std::uint32_t>(j) * row + static_cast<std::uint32_t>(i); };
    for (int j = 0; j < ncy; ++j)
        for (int i = 0; i < ncx; ++i) {
            quad(m, T(i, j), T(i + 1, j), T(i + 1, j + 1), T(i, j + 1));  // up
            quad(m, B(i, j), B(i, j + 1), B(i + 1, j + 1), B(i + 1, j));  // down
        }
    for (int i = 0; i < ncx; ++i) {
        quad(m, B(i, 0), B(i + 1, 0), T(i + 1, 0), T(i, 0));          // south, -y
        quad(m, B(i + 1, ncy), B(i, ncy), T(i, ncy), T(i + 1, ncy));  // north, +y
    }
    for (int j = 0; j < ncy; ++j) {
        quad(m, B(ncx, j), B(ncx, j + 1), T(ncx, j + 1), T(ncx, j));  // east, +x
        quad(m, B(0, j + 1), B(0, j), T(0, j), T(0, j + 1));          // west, -x
    }
}

// The lens: an ellipsoid whose centre surface follows the host stratum's mid-surface.
void addLens(Mesh& m, const Fields& f, int nTheta, int nPhi, double zBottom, bool inward) {
    const double cx = 1000.0, cy = 2000.0, a = 450.0, b = 700.0, c = 90.0;
    const int block = f.blockOf(cx);
    auto point = [&](double theta, double phi) {
        double x = cx + a * std::sin(phi) * std::cos(theta), y = cy + b * std::sin(phi) * std::sin(theta);
        auto h = f.horizons(block, x, y, zBottom);
        double mid = 0.5 * (h[kHostStratum - 1] + h[kHostStratum]);
        return shear({x, y, mid + c * std::cos(phi)});
    };
    const auto first = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(point(0.0, 0.0));  // north pole
    for (int j = 1; j < nPhi; ++j)
        for (int i = 0; i < nTheta; ++i) m.positions.push_back(point(2.0 * kPi * i / nTheta, kPi * j / nPhi));
    m.positions.push_back(point(0.0, kPi));  // south pole
    const std::uint32_t south = static_cast<std::uint32_t>(m.positions.size() - 1);
    auto R = [&](int j, int i) { return first + 1 + static_cast<std::uint32_t>((j - 1) * nTheta + (i % nTheta)); };
    auto tri = [&](std::uint32_t p, std::uint32_t q, std::uint32_t r) {
        if (inward) std::swap(q, r);
        m.indices.insert(m.indices.end(), {p, q, r});
    };
    for (int i = 0; i < nTheta; ++i) tri(first, R(1, i), R(1, i + 1));
    for (int j = 1; j + 1 < nPhi; ++j)
        for (int i = 0; i < nTheta; ++i) {
            tri(R(j + 1, i), R(j + 1, i + 1), R(j, i + 1));
            tri(R(j + 1, i), R(j, i + 1), R(j, i));
        }
    for (int i = 0; i < nTheta; ++i) tri(south, R(nPhi - 1, i + 1), R(nPhi - 1, i));
}

// Fault sheet in the plane x' = xf from the base to the terrain, sheared to its dip.
void addFault(Mesh& m, const Fields& f, double xf, int ncy, int nz, double zBottom) {
    const std::uint32_t first = addGrid(m, ncy, nz, [&](int j, int k) {
        double y = j == ncy ? kHeight : j * kHeight / ncy;
        double top = f.terrain(xf, y);
        return shear({xf, y, zBottom + (top - zBottom) * k / nz});
    });
    const auto row = static_cast<std::uint32_t>(ncy + 1);
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ncy; ++j) {
            std::uint32_t a = first + static_cast<std::uint32_t>(k) * row + static_cast<std::uint32_t>(j);
            quad(m, a, a + 1, a + 1 + row, a + row);
        }
}

}  // namespace

std::optional<std::size_t> namedModelSize(const std::string& name) {
    if (name == "L1") return 500'000;
    if (name == "L2") return 2'000'000;
    if (name == "L3") return 5'000'000;
    if (name == "L4") return 10'000'000;
    return std::nullopt;
}

Result<Model> generateSynthetic(const SyntheticOptions& options) {
    if (options.triangles < 2000 || options.triangles > 200'000'000)
        return makeError(ErrorCode::OutOfRange,
                         "--triangles " + std::to_string(options.triangles) + " is outside 2000..200000000");
    std::uint64_t s = options.seed;
    Fields f{};
    f.foldPhase = 0.4 + 0.8 * uniform(s);
    f.minorPhase = 2.0 * kPi * uniform(s);
    f.thickPhase = 2.0 * kPi * uniform(s);
    f.terrainPhase1 = 2.0 * kPi * uniform(s);
    f.terrainPhase2 = 2.0 * kPi * uniform(s);

    // Flat base 150 m below the lowest first horizon (sampled densely; the clamp chain
    // only lowers horizons, so this bounds them).
    double lowest = 1e30;
    for (int j = 0; j <= 200; ++j)
        for (int i = 0; i <= 300; ++i) {
            double x = kWidth * i / 300.0, y = kHeight * j / 200.0;
            lowest = std::min(lowest, f.horizons(f.blockOf(x), x, y, 0.0)[1]);
        }
    const double zBottom = std::floor(lowest - 150.0);

    const Plan plan = planFor(options.triangles, options.ore);
    Model model;
    model.name = "geoslice synthetic mine (seed " + std::to_string(options.seed) + ")";
    model.source = "generate";
    for (int k = 1; k <= kStrata; ++k) {
        const auto& sp = kStrataSpecs[static_cast<std::size_t>(k - 1)];
        AttributeRecord r;
        r.id = static_cast<RecordId>(k);
        r.name = sp.name;
        r.kind = "stratum";
        r.lithology = sp.lithology;
        r.age = sp.age;
        r.era = sp.era;
        r.colour = *parseColour(sp.colour);
        r.colourSource = "generator";
        r.density = sp.density;
        model.attributes.put(r);
    }
    constexpr RecordId kOre = kStrata + 1, kF1 = kStrata + 2, kF2 = kStrata + 3;
    {
        AttributeRecord r;
        r.id = kOre;
        r.name = "Xujiahe silica sandstone orebody";
        r.kind = "orebody";
        r.lithology = "high-purity quartz sandstone";
        r.age = "Late Triassic (T3x)";
        r.era = "Mesozoic";
        r.colour = *parseColour("#e8322a");
        r.colourSource = "generator";
        r.density = 2.60;
        r.grade = 98.6;
        r.gradeUnit = "% SiO2";
        r.extra["host"] = "Xujiahe Formation";
        model.attributes.put(r);
        for (RecordId id : {kF1, kF2}) {
            AttributeRecord fr;
            fr.id = id;
            fr.name = id == kF1 ? "F1 normal fault" : "F2 normal fault";
            fr.kind = "fault";
            fr.lithology = "fault breccia";
            fr.colour = *parseColour("#111111");
            fr.colourSource = "generator";
            fr.extra["dip_deg"] = 70.0;
            fr.extra["dip_direction"] = id == kF1 ? "E" : "W";
            fr.extra["throw_m"] = id == kF1 ? 150.0 : 90.0;
            model.attributes.put(fr);
        }
    }

    for (int b = 0; b < kBlocks; ++b)
        for (int k = 1; k <= kStrata; ++k) {
            Part p;
            p.name = std::string(kStrataSpecs[static_cast<std::size_t>(k - 1)].name) + " (" +
                     kBlockNames[static_cast<std::size_t>(b)] + ")";
            p.kind = PartKind::Body;
            p.record = static_cast<RecordId>(k);
            addStratumShell(p.mesh, f, b, k - 1, plan.ncx[static_cast<std::size_t>(b)], plan.ncy, zBottom);
            if (options.ore == OreVariant::Partition && k == kHostStratum && b == f.blockOf(1000.0))
                addLens(p.mesh, f, plan.lensTheta, plan.lensPhi, zBottom, /*inward=*/true);  // the cavity
            model.bodies.push_back(std::move(p));
        }
    {
        Part p;
        p.name = "Xujiahe silica sandstone orebody";
        p.kind = PartKind::Body;
        p.record = kOre;
        addLens(p.mesh, f, plan.lensTheta, plan.lensPhi, zBottom, false);
        model.bodies.push_back(std::move(p));
    }
    for (int i = 0; i < 2; ++i) {
        Part p;
        p.name = i == 0 ? "F1 normal fault" : "F2 normal fault";
        p.kind = PartKind::Surface;
        p.record = i == 0 ? kF1 : kF2;
        addFault(p.mesh, f, kBlockEdges[static_cast<std::size_t>(i + 1)], plan.ncy, plan.faultNz, zBottom);
        model.surfaces.push_back(std::move(p));
    }

    // Placement: param centre -> requested world centre.
    glm::dvec3 centre(0.5 * kWidth, 0.5 * kHeight, 0.0);
    model.crs = options.crs;
    if (options.crs.isProjected()) {
        // Default place: 30.6 N on a Gauss-Kruger zone's central meridian; for other CRSs the
        // centre of their area of use.
        glm::dvec2 fallback(options.crs.centralMeridianDeg(), 30.6);
        if (!options.crs.isGaussKruger())
            if (const auto area = options.crs.areaOfUse(); area && area->west <= area->east)
                fallback = glm::dvec2(0.5 * (area->west + area->east), 0.5 * (area->south + area->north));
        glm::dvec2 at = options.atLonLat.value_or(fallback);
        auto en = options.crs.fromLonLat(at.x, at.y);
        if (!en) return en.error();
        centre = glm::dvec3(en->x, en->y, 0.0);
    } else if (options.atLonLat) {
        return makeError(ErrorCode::InvalidArgument, "--at needs a projected --crs (e.g. EPSG:4523)");
    }
    const glm::dvec3 shift = centre - glm::dvec3(0.5 * kWidth, 0.5 * kHeight, 0.0);
    for (auto* list : {&model.bodies, &model.surfaces})
        for (auto& p : *list)
            for (auto& v : p.mesh.positions) v += shift;
    model.recentre();
    return model;
}

}  // namespace geoslice
