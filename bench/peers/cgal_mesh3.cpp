// cgal_mesh3.cpp — the CGAL Mesh_3 peer of scripts/bench.sh's 3D section
// (built only by that script; warpmesh does not depend on CGAL).
//
// usage: cgal_mesh3 RAW NX NY NZ SX SY SZ H [u16] [optimise] [cell=C] [distance=D] [out=MESH]
//   RAW: NX*NY*NZ unsigned bytes (or, with u16, little-endian 16-bit
//   labels), x fastest, 0 = outside and any other value a label (the script
//   writes the SPL atlas binarised, the region warpmesh meshes with --label
//   nonzero, or every label renumbered 1..N for the multi-material
//   comparison); SX SY SZ the voxel size in mm.  `optimise`: perturb and
//   exude after the refinement (CGAL's sliver removal).  cell=C: the cell
//   size C instead of H (0: no cell size, the cells free to grow inside;
//   the graded comparison of issue 48); distance=D: the facet distance D
//   instead of SX / 2.  out=MESH: write the complex as a Medit .mesh file
//   (CGAL's own writer), for whole-process runs that read, mesh and write
//   (scripts/bench.sh --cgal3d-whole).
// Meshes the labelled image with Labeled_mesh_domain_3 and the criteria
//   facet_angle 25, facet_size H, facet_distance SX / 2,
//   cell_radius_edge_ratio 3, cell_size H
// (CGAL's image-meshing example's criteria with the size set to H), no
// optimisers (lloyd/odt/perturb/exude off: the refinement alone, the fastest
// CGAL configuration), one thread.  Prints one line of JSON: the meshing time
// in seconds (make_mesh_3 only, no I/O; wall and CPU: one thread, so the CPU
// seconds are the figure a loaded machine does not inflate), the tetrahedra in the complex, their
// minimum and maximum dihedral angles in degrees, and the number of labels
// (subdomains) that got a tetrahedron, and the facets in the complex (the
// boundary and interface triangles).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/IO/File_medit.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;
namespace params = CGAL::parameters;

// The six dihedral angles of a tetrahedron, in degrees.
std::array<double, 6> dihedrals(const std::array<K::Point_3, 4>& p) {
    std::array<double, 6> out{};
    int k = 0;
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
            int c = -1, d = -1;
            for (int i = 0; i < 4; ++i)
                if (i != a && i != b) (c < 0 ? c : d) = i;
            const K::Vector_3 e = p[b] - p[a];
            const K::Vector_3 nc = CGAL::cross_product(e, p[c] - p[a]), nd = CGAL::cross_product(e, p[d] - p[a]);
            const double cosv = (nc * nd) / std::sqrt(nc.squared_length() * nd.squared_length());
            out[k++] = std::acos(std::clamp(cosv, -1.0, 1.0)) * 180 / M_PI;
        }
    return out;
}

int main(int argc, char** argv) {
    const std::vector<std::string> flags(argv + std::min(argc, 9), argv + argc);
    const bool u16 = std::count(flags.begin(), flags.end(), "u16") > 0, optimise = std::count(flags.begin(), flags.end(), "optimise") > 0;
    double cell = -1, distance = -1;  // -1: H, SX / 2
    std::string out;
    std::size_t known = static_cast<std::size_t>(u16) + static_cast<std::size_t>(optimise);
    for (const std::string& f : flags) {
        if (f.rfind("cell=", 0) == 0) cell = std::stod(f.substr(5)), ++known;
        if (f.rfind("distance=", 0) == 0) distance = std::stod(f.substr(9)), ++known;
        if (f.rfind("out=", 0) == 0) out = f.substr(4), ++known;
    }
    if (argc < 9 || static_cast<std::size_t>(argc - 9) != known) {
        std::cerr << "usage: cgal_mesh3 RAW NX NY NZ SX SY SZ H [u16] [optimise] [cell=C] [distance=D] [out=MESH]\n";
        return 2;
    }
    const int nx = std::stoi(argv[2]), ny = std::stoi(argv[3]), nz = std::stoi(argv[4]);
    const double sx = std::stod(argv[5]), sy = std::stod(argv[6]), sz = std::stod(argv[7]), h = std::stod(argv[8]);
    const std::size_t bytes = static_cast<std::size_t>(nx) * ny * nz * (u16 ? 2 : 1);
    std::vector<unsigned char> raw(bytes);
    std::ifstream in(argv[1], std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size()))) {
        std::cerr << "cgal_mesh3: cannot read " << raw.size() << " bytes from " << argv[1] << "\n";
        return 1;
    }
    _image* img = ::_createImage(nx, ny, nz, 1, static_cast<float>(sx), static_cast<float>(sy), static_cast<float>(sz), u16 ? 2 : 1,
                                 WK_FIXED, SGN_UNSIGNED);
    std::memcpy(img->data, raw.data(), raw.size());
    const CGAL::Image_3 image(img);
    const Domain domain = Domain::create_labeled_image_mesh_domain(image);
    const double d = distance < 0 ? sx / 2 : distance;
    const Criteria criteria = cell == 0 ? Criteria(params::facet_angle = 25, params::facet_size = h, params::facet_distance = d,
                                                   params::cell_radius_edge_ratio = 3)
                                        : Criteria(params::facet_angle = 25, params::facet_size = h, params::facet_distance = d,
                                                   params::cell_radius_edge_ratio = 3, params::cell_size = cell < 0 ? h : cell);

    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const C3t3 c3t3 = optimise ? CGAL::make_mesh_3<C3t3>(domain, criteria, params::no_lloyd(), params::no_odt(), params::perturb(),
                                                         params::exude())
                               : CGAL::make_mesh_3<C3t3>(domain, criteria, params::no_lloyd(), params::no_odt(),
                                                         params::no_perturb(), params::no_exude());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;

    double lo = 180, hi = 0;
    std::size_t count = 0;
    std::set<int> labels;
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c, ++count) {
        std::array<K::Point_3, 4> p;
        for (int i = 0; i < 4; ++i) p[static_cast<std::size_t>(i)] = c3t3.triangulation().point(c->vertex(i)).point();
        for (const double d : dihedrals(p)) lo = std::min(lo, d), hi = std::max(hi, d);
        labels.insert(static_cast<int>(c3t3.subdomain_index(c)));
    }
    if (!out.empty()) {
        std::ofstream medit(out);
        CGAL::IO::output_to_medit(medit, c3t3);
        if (!medit) {
            std::cerr << "cgal_mesh3: cannot write " << out << "\n";
            return 1;
        }
    }
    std::printf("{\"seconds\": %.3f, \"cpu_seconds\": %.3f, \"tetrahedra\": %zu, \"min_dihedral_deg\": %.3f, \"max_dihedral_deg\": %.3f, \"labels\": %zu, "
                "\"facets\": %zu}\n",
                seconds, cpu_seconds, count, lo, hi, labels.size(), static_cast<std::size_t>(c3t3.number_of_facets_in_complex()));
    return 0;
}
