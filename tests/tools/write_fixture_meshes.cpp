// write_fixture_meshes — writes the hand-built two-region mesh with interfaces
// (fixture_meshes.hpp) through warpmesh's writers in every solver format, for
// the real-client round trips in tests/python/ (the CLI cannot produce a
// multi-material mesh by itself yet).
//
//   write_fixture_meshes DIR
//     → DIR/two.msh (4.1), DIR/two-22.msh (2.2), DIR/two-data.msh (4.1 with
//       cell data), DIR/two.vtu, DIR/two.xdmf (+ two_facets.xdmf),
//       DIR/two.inp and DIR/two.node/.ele/.poly (the reference);
//     the tetrahedral fixture (fixture_meshes.hpp, cube_tet_mesh) in every
//     3D format: DIR/cubes.{vtu,msh,xdmf,inp,mesh}, cubes-22.msh,
//     cubes-data.msh, cubes-ascii.{vtu,msh,xdmf}, cubes-22-ascii.msh,
//     cubes-z.vtu, and its reference DIR/cubes.ref, written here directly
//     (not by a writer): "points N" then N "x y z" lines (17 significant
//     digits), "tets T" then "a b c d region" lines (0-based), "facets F"
//     then "a b c tag" lines: the boundary triangles with their tag, then the
//     interface triangles oriented out of region 3 with tag 3 (the facet
//     groups' rule, detail::facet_groups).
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>

#include "fixture_meshes.hpp"
#include "warpmesh/io/writers.hpp"

namespace {

void write_reference(const warpmesh::TetMesh& m, const std::string& path) {
    std::ofstream out(path);
    char buf[128];
    out << "points " << m.vertices.size() << '\n';
    for (const auto& p : m.vertices) {
        std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
        out << buf;
    }
    out << "tets " << m.tets.size() << '\n';
    for (std::size_t k = 0; k < m.tets.size(); ++k)
        out << m.tets[k][0] << ' ' << m.tets[k][1] << ' ' << m.tets[k][2] << ' ' << m.tets[k][3] << ' ' << m.region[k] << '\n';
    out << "facets " << m.boundary.size() + m.interfaces.size() << '\n';
    for (std::size_t k = 0; k < m.boundary.size(); ++k)
        out << m.boundary[k][0] << ' ' << m.boundary[k][1] << ' ' << m.boundary[k][2] << ' ' << m.boundary_tag[k] << '\n';
    for (std::size_t k = 0; k < m.interfaces.size(); ++k) {
        const auto& f = m.interfaces[k];
        if (m.interface_regions[k][0] == 3) out << f[0] << ' ' << f[1] << ' ' << f[2] << " 3\n";
        else out << f[2] << ' ' << f[1] << ' ' << f[0] << " 3\n";
    }
    if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace


int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: write_fixture_meshes DIR\n";
        return 2;
    }
    using namespace warpmesh;
    try {
        const Mesh m = testing::two_region_mesh();
        const std::string dir = std::string(argv[1]) + "/";
        WriteOptions v22, data;
        v22.msh.version = 22;
        data.msh.cell_data = true;
        write_mesh(m, dir + "two.msh");
        write_mesh(m, dir + "two-22.msh", v22);
        write_mesh(m, dir + "two-data.msh", data);
        for (const char* ext : {".vtu", ".xdmf", ".inp", ".node"}) write_mesh(m, dir + "two" + ext);
        // The text forms (--ascii), 2.2 binary and zlib .vtu (--compress).
        WriteOptions text, v22_text, zlib;
        text.ascii = v22_text.ascii = true;
        v22_text.msh.version = 22;
        zlib.vtu.encoding = VtuOptions::Encoding::zlib;
        for (const char* ext : {".vtu", ".msh", ".xdmf"}) write_mesh(m, dir + "two-ascii" + ext, text);
        write_mesh(m, dir + "two-22-ascii.msh", v22_text);
        write_mesh(m, dir + "two-z.vtu", zlib);

        const TetMesh c = testing::cube_tet_mesh();
        write_reference(c, dir + "cubes.ref");
        for (const char* ext : {".vtu", ".msh", ".xdmf", ".inp", ".mesh"}) write_mesh(c, dir + "cubes" + ext);
        write_mesh(c, dir + "cubes-22.msh", v22);
        write_mesh(c, dir + "cubes-data.msh", data);
        for (const char* ext : {".vtu", ".msh", ".xdmf"}) write_mesh(c, dir + "cubes-ascii" + ext, text);
        write_mesh(c, dir + "cubes-22-ascii.msh", v22_text);
        write_mesh(c, dir + "cubes-z.vtu", zlib);
    } catch (const std::exception& e) {
        std::cerr << "write_fixture_meshes: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
