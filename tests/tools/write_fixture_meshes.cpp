// write_fixture_meshes — writes the hand-built two-region mesh with interfaces
// (fixture_meshes.hpp) through warpmesh's writers in every solver format, for
// the real-client round trips in tests/python/ (the CLI cannot produce a
// multi-material mesh by itself yet).
//
//   write_fixture_meshes DIR
//     → DIR/two.msh (4.1), DIR/two-22.msh (2.2), DIR/two-data.msh (4.1 with
//       cell data), DIR/two.vtu, DIR/two.xdmf (+ two_facets.xdmf),
//       DIR/two.inp and DIR/two.node/.ele/.poly (the reference).
#include <exception>
#include <iostream>
#include <string>

#include "fixture_meshes.hpp"
#include "warpmesh/writers.hpp"

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
    } catch (const std::exception& e) {
        std::cerr << "write_fixture_meshes: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
