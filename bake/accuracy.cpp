// The paper's "attribute mapping accuracy" (section 4): the fraction of random surface points
// whose record id, fetched through the point's interpolated UV and the nearest texel, is the
// record of the part they lie on. One sampler for the tests (tests/unit/bake_accuracy_test.cpp,
// bake_rebake_test.cpp) and the benchmark (bench/bake.cpp), over a fresh bake or a loaded
// package alike.
#include <algorithm>
#include <random>

#include "bake/bake.hpp"
#include "bake/package.hpp"

namespace geoslice::bake {

IdAccuracy sampleIdAccuracy(const UvPart* parts, std::size_t count, const std::uint32_t* texels, std::uint32_t width,
                            std::uint32_t height, std::uint32_t pages, std::size_t points, std::uint64_t seed) {
    std::size_t triangles = 0;
    for (std::size_t p = 0; p < count; ++p) triangles += parts[p].indexCount / 3;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    IdAccuracy out;
    for (std::size_t p = 0; p < count; ++p) {
        const UvPart& part = parts[p];
        const std::size_t tris = part.indexCount / 3;
        if (!tris) continue;
        const std::size_t n = std::max<std::size_t>(1, (points * tris + triangles - 1) / triangles);
        std::uniform_int_distribution<std::size_t> pick(0, tris - 1);
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t t = pick(rng);
            double r1 = unit(rng), r2 = unit(rng);
            if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
            // In float, as a GPU interpolates a varying.
            const float w[3] = {1.0f - float(r1) - float(r2), float(r1), float(r2)};
            glm::vec2 uv(0.0f);
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = part.indices[3 * t + std::size_t(k)];
                uv += w[k] * glm::vec2(part.uvs[2 * std::size_t(v)], part.uvs[2 * std::size_t(v) + 1]);
            }
            out.correct += fetchId(texels, width, height, pages, glm::dvec2(uv)) == part.record;
            ++out.points;
        }
    }
    return out;
}

namespace {

UvPart uvPart(const BakedPart& p) {
    return {p.uvs.empty() ? nullptr : &p.uvs[0].x, p.indices.data(), p.indices.size(), p.record};
}

}  // namespace

IdAccuracy sampleIdAccuracy(const BakedModel& baked, std::size_t points, std::uint64_t seed) {
    std::vector<UvPart> parts;
    for (const auto& p : baked.parts) parts.push_back(uvPart(p));
    return sampleIdAccuracy(parts.data(), parts.size(), baked.texels.data(), baked.width, baked.height, baked.pages,
                            points, seed);
}

IdAccuracy sampleIdAccuracy(const Package& pkg, std::size_t points, std::uint64_t seed) {
    std::vector<UvPart> parts;
    for (const auto& p : pkg.parts) parts.push_back({p.uvs, p.indices, p.indexCount, p.record});
    return sampleIdAccuracy(parts.data(), parts.size(), pkg.texels.data(), pkg.width, pkg.height, pkg.pages, points,
                            seed);
}

double partIdAccuracy(const BakedModel& b, std::size_t p, std::size_t samples, std::uint64_t seed) {
    const UvPart part = uvPart(b.parts[p]);
    return sampleIdAccuracy(&part, 1, b.texels.data(), b.width, b.height, b.pages, samples, seed).fraction();
}

}  // namespace geoslice::bake
