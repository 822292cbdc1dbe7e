// bench_table1_cgal MODEL.ply PLANES.json OUT.json: CGAL's Polygon_mesh_slicer (AABB tree
// built once) on the mesh and planes bench_table1 exported, one thread. A benchmark peer:
// built only with -DGEOSLICE_BENCH_PEERS=ON, never linked into geoslice.
// Writes the time to read the mesh, to build the slicer (its AABB tree), per plane the
// slice time, segment count, total segment length and the sorted |area| of every closed
// polyline (computed in 3D about the plane normal), and the peak RSS.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <list>
#include <sstream>
#include <string>
#include <vector>

#include <CGAL/AABB_halfedge_graph_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>
#include <nlohmann/json.hpp>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using HGSP = CGAL::AABB_halfedge_graph_segment_primitive<Mesh>;
using AabbTraits = CGAL::AABB_traits<Kernel, HGSP>;
using AabbTree = CGAL::AABB_tree<AabbTraits>;
using Polyline = std::vector<Point>;
using Slicer = CGAL::Polygon_mesh_slicer<Mesh, Kernel>;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// Reads the PLY bench_table1 writes (binary little endian; double x y z; uchar 3 + int x3
// + int part per face). Faces that CGAL cannot add (non-manifold by index) are counted.
bool readPly(const std::string& path, Mesh& mesh, std::size_t& rejected) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    std::string line;
    std::size_t nv = 0, nf = 0;
    while (std::getline(f, line)) {
        if (line.rfind("element vertex ", 0) == 0) nv = std::stoul(line.substr(15));
        if (line.rfind("element face ", 0) == 0) nf = std::stoul(line.substr(13));
        if (line == "end_header") break;
    }
    std::vector<Mesh::Vertex_index> vs(nv);
    for (std::size_t i = 0; i < nv; ++i) {
        double p[3];
        f.read(reinterpret_cast<char*>(p), sizeof p);
        vs[i] = mesh.add_vertex(Point(p[0], p[1], p[2]));
    }
    rejected = 0;
    for (std::size_t i = 0; i < nf; ++i) {
        char rec[17];
        f.read(rec, sizeof rec);
        std::int32_t v[3];
        std::memcpy(v, rec + 1, 12);
        if (mesh.add_face(vs[std::size_t(v[0])], vs[std::size_t(v[1])], vs[std::size_t(v[2])]) == Mesh::null_face())
            ++rejected;
    }
    return bool(f);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: bench_table1_cgal MODEL.ply PLANES.json OUT.json\n");
        return 2;
    }
    nlohmann::json planes;
    std::ifstream(argv[2]) >> planes;
    Mesh mesh;
    std::size_t rejected = 0;
    double t = now();
    if (!readPly(argv[1], mesh, rejected)) {
        std::fprintf(stderr, "bench_table1_cgal: cannot read %s\n", argv[1]);
        return 1;
    }
    const double readMs = (now() - t) * 1e3;
    t = now();
    AabbTree tree(edges(mesh).first, edges(mesh).second, mesh);
    tree.build();
    Slicer slicer(mesh, tree);
    const double initMs = (now() - t) * 1e3;
    nlohmann::json out = nlohmann::json::array();
    std::vector<Polyline> polylines;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const auto& l = planes[k]["local"];
        const double a = l[0], b = l[1], c = l[2], d = l[3];
        polylines.clear();
        t = now();
        slicer(Kernel::Plane_3(a, b, c, d), std::back_inserter(polylines));
        const double ms = (now() - t) * 1e3;
        std::size_t segments = 0;
        double length = 0.0;
        std::vector<double> areas;
        for (const Polyline& pl : polylines) {
            if (pl.size() < 2) continue;
            segments += pl.size() - 1;
            for (std::size_t i = 0; i + 1 < pl.size(); ++i)
                length += std::sqrt(CGAL::squared_distance(pl[i], pl[i + 1]));
            if (pl.size() >= 4 && pl.front() == pl.back()) {
                // Shoelace about the normal, relative to the first point.
                double cx = 0.0, cy = 0.0, cz = 0.0;
                const Point& o = pl[0];
                for (std::size_t i = 1; i + 2 < pl.size(); ++i) {
                    const double px = pl[i].x() - o.x(), py = pl[i].y() - o.y(), pz = pl[i].z() - o.z();
                    const double qx = pl[i + 1].x() - o.x(), qy = pl[i + 1].y() - o.y(), qz = pl[i + 1].z() - o.z();
                    cx += py * qz - pz * qy;
                    cy += pz * qx - px * qz;
                    cz += px * qy - py * qx;
                }
                areas.push_back(0.5 * std::abs(cx * a + cy * b + cz * c));
            }
        }
        std::sort(areas.begin(), areas.end());
        out.push_back({{"plane", k}, {"ms", ms}, {"segments", segments}, {"length", length}, {"loop_areas", areas}});
    }
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    nlohmann::json doc = {
        {"peer", "cgal"},    {"version", CGAL_VERSION_STR}, {"read_ms", readMs},
        {"init_ms", initMs}, {"faces_rejected", rejected},  {"peak_rss_mib", double(u.ru_maxrss) / 1024.0},
        {"planes", out}};
    std::ofstream(argv[3]) << doc.dump(1);
    return 0;
}
