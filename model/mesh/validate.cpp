#include "model/mesh/validate.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "model/mesh/closed_mesh.hpp"

namespace geoslice {
namespace {

// ", e.g. at (x, y, z), (x, y, z)" for the first few problem edges (world, mm).
std::string whereText(const std::vector<glm::dvec3>& points) {
    if (points.empty()) return {};
    std::string s = ", e.g. at";
    char buf[96];
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%s (%.3f, %.3f, %.3f)", i ? "," : "", points[i].x, points[i].y, points[i].z);
        s += buf;
    }
    return s;
}

}  // namespace

bool ValidationReport::hasErrors() const {
    return std::any_of(issues.begin(), issues.end(),
                       [](const auto& i) { return i.severity == ValidationIssue::Severity::Error; });
}

ValidationReport validate(Model& model) {
    ValidationReport report;
    using Sev = ValidationIssue::Severity;

    // Bodies in parallel: each analysis touches only its own part.
    std::vector<Part*> parts;
    for (auto& p : model.bodies) parts.push_back(&p);
    for (auto& p : model.surfaces) parts.push_back(&p);
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t i = next++; i < parts.size(); i = next++)
            parts[i]->report = analyseMesh(parts[i]->mesh, parts[i]->kind == PartKind::Body);
    };
    unsigned nThreads = std::max(1u, std::min<unsigned>(std::thread::hardware_concurrency(), 8));
    std::vector<std::thread> pool;
    for (unsigned i = 1; i < nThreads; ++i) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();

    for (const Part* p : parts) {
        const MeshReport& r = p->report;
        auto add = [&](Sev s, std::string msg) { report.issues.push_back({s, p->name, std::move(msg)}); };
        if (r.triangles == 0) add(Sev::Error, "has no triangles");
        if (r.nonFiniteVertices) add(Sev::Error, std::to_string(r.nonFiniteVertices) + " vertices are NaN or Inf");
        if (r.degenerateTriangles) add(Sev::Warning, std::to_string(r.degenerateTriangles) + " degenerate triangles");
        if (r.duplicateTriangles) add(Sev::Warning, std::to_string(r.duplicateTriangles) + " duplicate triangles");
        if (p->kind == PartKind::Body) {
            if (!r.closed)
                add(Sev::Error, "body is not a closed 2-manifold: " + std::to_string(r.boundaryEdges) +
                                    " open (boundary) edges, " + std::to_string(r.nonManifoldEdges) +
                                    " non-manifold edges" + whereText(r.problemEdges));
            else if (!r.consistentlyOriented)
                add(Sev::Error, std::to_string(r.inconsistentEdges) + " edges with inconsistent orientation");
            if (r.closed && (r.splitEdges || r.splitVertices))
                add(Sev::Note, "touches itself (pinch-outs): split into " + std::to_string(r.components) +
                                   " closed shells at " + std::to_string(r.splitEdges) + " edges and " +
                                   std::to_string(r.splitVertices) + " vertices");
            if (r.flipped) add(Sev::Note, "normals pointed inward; flipped to outward");
        } else if (r.nonManifoldEdges) {
            add(Sev::Warning, std::to_string(r.nonManifoldEdges) + " non-manifold edges");
        }
    }

    // Nesting of closed bodies: B is inside A when a point strictly inside B is inside A.
    const std::size_t nb = model.bodies.size();
    std::vector<Aabb> boxes(nb);
    for (std::size_t i = 0; i < nb; ++i) boxes[i] = model.bodies[i].mesh.bounds();
    for (std::size_t b = 0; b < nb; ++b) {
        Part& inner = model.bodies[b];
        inner.report.nestingDepth = 0;
        inner.report.parent = -1;
        if (!inner.report.closed || !inner.report.consistentlyOriented) continue;
        std::optional<glm::dvec3> probe;
        double parentVolume = std::numeric_limits<double>::infinity();
        for (std::size_t a = 0; a < nb; ++a) {
            const Part& outer = model.bodies[a];
            if (a == b || !outer.report.closed || !outer.report.consistentlyOriented || !boxes[a].contains(boxes[b]))
                continue;
            if (!probe) probe = closed_mesh::interiorPoint(inner.mesh);
            if (!probe) break;
            if (pointInClosedMesh(outer.mesh, *probe)) {
                ++inner.report.nestingDepth;
                if (std::abs(outer.report.signedVolume) < parentVolume) {
                    parentVolume = std::abs(outer.report.signedVolume);
                    inner.report.parent = static_cast<int>(a);
                }
            }
        }
        if (inner.report.parent >= 0)
            report.issues.push_back({Sev::Note, inner.name,
                                     "nested inside \"" +
                                         model.bodies[static_cast<std::size_t>(inner.report.parent)].name +
                                         "\" (depth " + std::to_string(inner.report.nestingDepth) + ")"});
    }
    model.validation = report;
    return report;
}

}  // namespace geoslice
