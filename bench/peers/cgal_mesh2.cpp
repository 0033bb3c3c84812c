// cgal_mesh2.cpp — the CGAL Mesh_2 peer of scripts/bench-peers.sh (built only
// by that script; warpmesh does not depend on CGAL).
//
// usage: cgal_mesh2 POLY H OUT.off
//   POLY: closed polylines ('loop N' then N lines 'x y') and hole seeds
//   ('hole x y'), as written by bench/peers/geometry.py.
// Meshes the domain with a constrained Delaunay triangulation refined by
// Delaunay_mesh_size_criteria_2(B = 0.125, size = sqrt(2) H) (B bounds
// shortest edge / circumradius; 0.125 is CGAL's default, ~20.7 degrees), one
// thread, and writes the in-domain triangles as OFF.  Prints the meshing time
// (constraint insertion and refinement, no I/O) in seconds on stdout.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
using Point = CDT::Point;

int main(int argc, char** argv) {
    if (argc != 4) {
        std::cerr << "usage: cgal_mesh2 POLY H OUT.off\n";
        return 2;
    }
    std::ifstream in(argv[1]);
    const double h = std::stod(argv[2]);
    std::vector<std::vector<Point>> loops;
    std::vector<Point> holes;
    for (std::string word; in >> word;) {
        if (word == "loop") {
            std::size_t n;
            in >> n;
            loops.emplace_back();
            for (std::size_t i = 0; i < n; ++i) {
                double x, y;
                in >> x >> y;
                loops.back().emplace_back(x, y);
            }
        } else if (word == "hole") {
            double x, y;
            in >> x >> y;
            holes.emplace_back(x, y);
        }
    }
    const auto start = std::chrono::steady_clock::now();
    CDT cdt;
    for (const auto& loop : loops) {
        std::vector<CDT::Vertex_handle> v;
        for (const Point& p : loop) v.push_back(cdt.insert(p));
        for (std::size_t i = 0; i < v.size(); ++i) cdt.insert_constraint(v[i], v[(i + 1) % v.size()]);
    }
    CGAL::refine_Delaunay_mesh_2(cdt, holes.begin(), holes.end(), Criteria(0.125, std::sqrt(2.0) * h));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::map<CDT::Vertex_handle, std::size_t> id;
    std::vector<Point> pts;
    std::vector<std::array<std::size_t, 3>> tris;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (!f->is_in_domain()) continue;
        std::array<std::size_t, 3> t;
        for (int k = 0; k < 3; ++k) {
            auto [it, fresh] = id.try_emplace(f->vertex(k), pts.size());
            if (fresh) pts.push_back(f->vertex(k)->point());
            t[k] = it->second;
        }
        tris.push_back(t);
    }
    std::ofstream out(argv[3]);
    out.precision(17);
    out << "OFF\n" << pts.size() << " " << tris.size() << " 0\n";
    for (const Point& p : pts) out << p.x() << " " << p.y() << " 0\n";
    for (const auto& t : tris) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
    std::cout << seconds << "\n";
    return out ? 0 : 1;
}
