// Least squares conformal maps: Levy, Petitjean, Ray, Maillot, "Least squares conformal maps
// for automatic texture atlas generation", SIGGRAPH 2002. Per triangle the Cauchy-Riemann
// residuals of the linear map (u, v) over the triangle's own orthonormal frame, weighted by
// the square root of its area, are minimised in the least squares sense with two vertices
// pinned; the normal equations are sparse symmetric positive definite (Eigen SimplicialLDLT).
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>

#include "bake/bake.hpp"

namespace geoslice::bake {
namespace {

// A triangle in its own plane: p0 = (0, 0), p1 = (x1, 0), p2 = (x2, y2), counter-clockwise
// (y2 >= 0) seen along the triangle's normal.
struct Flat {
    glm::dvec2 p[3];
    double area = 0.0;
};

Flat flatten(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    Flat f;
    glm::dvec3 e1 = b - a, e2 = c - a;
    const glm::dvec3 n = glm::cross(e1, e2);
    const double len1 = glm::length(e1), lenN = glm::length(n);
    f.p[0] = {0, 0};
    if (!(len1 > 0.0) || !std::isfinite(lenN)) {
        const double len2 = glm::length(e2);
        f.p[1] = {0, 0};
        f.p[2] = {std::isfinite(len2) ? len2 : 0.0, 0};
        return f;
    }
    const glm::dvec3 x = e1 / len1;
    f.p[1] = {len1, 0};
    f.p[2] = {glm::dot(e2, x), lenN / len1};
    f.area = 0.5 * lenN;
    return f;
}

double signedArea(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
}

}  // namespace

ChartUv lscmChart(const glm::dvec3* positions, const std::uint32_t* indices, const std::uint32_t* triangles,
                  std::size_t count) {
    ChartUv out;
    // Chart-local vertices, in ascending mesh index.
    out.vertices.reserve(count * 3);
    for (std::size_t k = 0; k < count; ++k)
        for (int e = 0; e < 3; ++e) out.vertices.push_back(indices[3 * std::size_t(triangles[k]) + e]);
    std::sort(out.vertices.begin(), out.vertices.end());
    out.vertices.erase(std::unique(out.vertices.begin(), out.vertices.end()), out.vertices.end());
    const std::size_t nv = out.vertices.size();
    auto local = [&](std::uint32_t v) {
        return static_cast<std::uint32_t>(std::lower_bound(out.vertices.begin(), out.vertices.end(), v) -
                                          out.vertices.begin());
    };
    out.corners.resize(count * 3);
    for (std::size_t k = 0; k < count * 3; ++k)
        out.corners[k] = local(indices[3 * std::size_t(triangles[k / 3]) + k % 3]);
    out.uv.assign(nv, glm::dvec2(0.0));

    std::vector<Flat> flat(count);
    glm::dvec3 normalSum(0.0);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t* t = indices + 3 * std::size_t(triangles[k]);
        flat[k] = flatten(positions[t[0]], positions[t[1]], positions[t[2]]);
        out.area3d += flat[k].area;
        const glm::dvec3 n = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
        if (std::isfinite(n.x + n.y + n.z)) normalSum += n;
    }
    if (count == 1 || out.area3d <= 0.0) {
        for (std::size_t k = 0; k < count; ++k)
            for (int e = 0; e < 3; ++e) out.uv[out.corners[3 * k + e]] = flat[k].p[e];
        return out;
    }

    // Projection onto the chart's mean plane: the initial layout, the choice of pins (extremes
    // along the principal axis) and a weak anchor for vertices no triangle constrains.
    const glm::dvec3 n = glm::normalize(normalSum);
    const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 ax = glm::normalize(glm::cross(helper, n)), ay = glm::cross(n, ax);
    std::vector<glm::dvec2> proj(nv);
    glm::dvec2 mean(0.0);
    for (std::size_t i = 0; i < nv; ++i) {
        const glm::dvec3 p = positions[out.vertices[i]];
        proj[i] = {glm::dot(p, ax), glm::dot(p, ay)};
        mean += proj[i];
    }
    mean /= double(nv);
    double sxx = 0, sxy = 0, syy = 0;
    for (auto& q : proj) {
        q -= mean;
        sxx += q.x * q.x;
        sxy += q.x * q.y;
        syy += q.y * q.y;
    }
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    const glm::dvec2 dir(std::cos(angle), std::sin(angle));
    std::size_t pin0 = 0, pin1 = 0;
    for (std::size_t i = 1; i < nv; ++i) {
        if (glm::dot(proj[i], dir) < glm::dot(proj[pin0], dir)) pin0 = i;
        if (glm::dot(proj[i], dir) > glm::dot(proj[pin1], dir)) pin1 = i;
    }
    if (pin0 == pin1) pin1 = (pin0 + 1) % nv;

    // Unknowns: (u_i, v_i) of free vertices; pinned ones move to the right-hand side.
    std::vector<int> column(nv, -1);
    int free = 0;
    for (std::size_t i = 0; i < nv; ++i)
        if (i != pin0 && i != pin1) column[i] = free++;
    using Triplet = Eigen::Triplet<double>;
    std::vector<Triplet> triplets;
    triplets.reserve(count * 12);
    Eigen::VectorXd rhsRows = Eigen::VectorXd::Zero(Eigen::Index(2 * count));
    for (std::size_t k = 0; k < count; ++k) {
        const Flat& f = flat[k];
        if (!(f.area > 0.0)) continue;
        const double w = 1.0 / (2.0 * std::sqrt(f.area));
        for (int j = 0; j < 3; ++j) {
            // Gradient of the hat function of vertex j: rot90(edge opposite j) / (2 area).
            const glm::dvec2 e = f.p[(j + 2) % 3] - f.p[(j + 1) % 3];
            // r1 = du/dx - dv/dy, r2 = du/dy + dv/dx (zero for a rotation + scale).
            const double cu1 = -e.y * w, cv1 = -e.x * w, cu2 = e.x * w, cv2 = -e.y * w;
            const std::size_t vi = out.corners[3 * k + j];
            const auto r1 = Eigen::Index(2 * k), r2 = Eigen::Index(2 * k + 1);
            if (column[vi] >= 0) {
                triplets.emplace_back(r1, 2 * column[vi], cu1);
                triplets.emplace_back(r1, 2 * column[vi] + 1, cv1);
                triplets.emplace_back(r2, 2 * column[vi], cu2);
                triplets.emplace_back(r2, 2 * column[vi] + 1, cv2);
            } else {
                rhsRows[r1] -= cu1 * proj[vi].x + cv1 * proj[vi].y;
                rhsRows[r2] -= cu2 * proj[vi].x + cv2 * proj[vi].y;
            }
        }
    }
    Eigen::SparseMatrix<double> a(Eigen::Index(2 * count), Eigen::Index(2 * free));
    a.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SparseMatrix<double> ata = Eigen::SparseMatrix<double>(a.transpose()) * a;
    Eigen::VectorXd rhs = a.transpose() * rhsRows;
    // Vertices that only zero-area triangles touch have no energy term: anchor them at their
    // projection (the others are left exactly to LSCM).
    std::vector<char> constrained(nv, 0);
    for (std::size_t k = 0; k < count; ++k)
        if (flat[k].area > 0.0)
            for (int j = 0; j < 3; ++j) constrained[out.corners[3 * k + j]] = 1;
    double diag = 0.0;
    for (Eigen::Index i = 0; i < ata.rows(); ++i) diag += ata.coeff(i, i);
    const double eps = ata.rows() && diag > 0.0 ? diag / double(ata.rows()) : 1.0;
    for (std::size_t i = 0; i < nv; ++i) {
        if (column[i] < 0 || constrained[i]) continue;
        ata.coeffRef(2 * column[i], 2 * column[i]) += eps;
        ata.coeffRef(2 * column[i] + 1, 2 * column[i] + 1) += eps;
        rhs[2 * column[i]] += eps * proj[i].x;
        rhs[2 * column[i] + 1] += eps * proj[i].y;
    }
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(ata);
    Eigen::VectorXd x;
    bool solved = solver.info() == Eigen::Success;
    if (solved) {
        x = solver.solve(rhs);
        solved = solver.info() == Eigen::Success && x.allFinite();
    }
    if (!solved) {
        out.badTriangles = count;
        return out;
    }
    for (std::size_t i = 0; i < nv; ++i)
        out.uv[i] = column[i] < 0 ? proj[i] : glm::dvec2(x[2 * column[i]], x[2 * column[i] + 1]);

    // Scale to the chart's 3D area; count flipped and collapsed triangles.
    double uvArea = 0.0;
    for (std::size_t k = 0; k < count; ++k)
        uvArea +=
            signedArea(out.uv[out.corners[3 * k]], out.uv[out.corners[3 * k + 1]], out.uv[out.corners[3 * k + 2]]);
    if (!(uvArea > 0.0) || !std::isfinite(uvArea)) {
        out.badTriangles = count;
        return out;
    }
    const double scale = std::sqrt(out.area3d / uvArea);
    for (auto& q : out.uv) q *= scale;
    for (std::size_t k = 0; k < count; ++k) {
        const double s =
            signedArea(out.uv[out.corners[3 * k]], out.uv[out.corners[3 * k + 1]], out.uv[out.corners[3 * k + 2]]);
        if (flat[k].area > 0.0 && !(s > 1e-6 * flat[k].area)) ++out.badTriangles;
    }
    return out;
}

}  // namespace geoslice::bake

namespace geoslice::bake {

void DistortionSums::add(const DistortionSums& o) {
    weight += o.weight;
    angle += o.angle;
    area += o.area;
    maxAngle = std::max(maxAngle, o.maxAngle);
    maxArea = std::max(maxArea, o.maxArea);
}

Distortion DistortionSums::result() const {
    Distortion d;
    if (weight > 0.0) {
        d.meanAngle = angle / weight;
        d.meanArea = area / weight;
    }
    d.maxAngle = maxAngle;
    d.maxArea = maxArea;
    return d;
}

DistortionSums measureDistortion(const glm::dvec3* positions, const std::uint32_t* indices,
                                 const std::uint32_t* triangles, std::size_t count, const ChartUv& chart) {
    constexpr double kCollapsed = 1e9;
    DistortionSums s;
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t* t = indices + 3 * std::size_t(triangles[k]);
        const Flat f = flatten(positions[t[0]], positions[t[1]], positions[t[2]]);
        if (!(f.area > 0.0)) continue;
        const glm::dvec2 q0 = chart.uv[chart.corners[3 * k]], q1 = chart.uv[chart.corners[3 * k + 1]],
                         q2 = chart.uv[chart.corners[3 * k + 2]];
        // J = Q P^-1 with P = [p1 - p0, p2 - p0] (p0 = 0), Q = [q1 - q0, q2 - q0].
        const glm::dmat2 p(f.p[1], f.p[2]);
        const glm::dmat2 j = glm::dmat2(q1 - q0, q2 - q0) * glm::inverse(p);
        const double a = j[0][0], b = j[1][0], c = j[0][1], d = j[1][1];
        const double e = 0.5 * (a * a + b * b + c * c + d * d), det = a * d - b * c;
        const double g = std::sqrt(std::max(0.0, e * e - det * det));
        const double s1 = std::sqrt(e + g), s2 = std::sqrt(std::max(0.0, e - g));
        const double angle = det > 0.0 && s2 > 0.0 ? std::min(kCollapsed, s1 / s2) : kCollapsed;
        const double area = det > 0.0 ? std::min(kCollapsed, std::max(det, 1.0 / det)) : kCollapsed;
        s.weight += f.area;
        s.angle += f.area * angle;
        s.area += f.area * area;
        s.maxAngle = std::max(s.maxAngle, angle);
        s.maxArea = std::max(s.maxArea, area);
    }
    return s;
}

}  // namespace geoslice::bake
