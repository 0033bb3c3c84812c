// A program that uses an installed warpmesh::io (tests/consumer/CMakeLists.txt):
// meshes a disc and writes it as XDMF with HDF5 heavy data into DIR.
#include <warpmesh/warpmesh.hpp>
#include <warpmesh/io/writers.hpp>

#include <iostream>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: consumer_io DIR\n";
        return 2;
    }
    const auto disc = warpmesh::parse_shape("circle:0,0,1");
    warpmesh::MeshOptions options;
    options.spacing = 0.1;
    const warpmesh::MeshResult r = warpmesh::mesh(*disc, options);
    try {
        warpmesh::write_mesh(r.mesh, std::string(argv[1]) + "/disc.xdmf");
    } catch (const std::exception& e) {
        std::cerr << "consumer_io: " << e.what() << '\n';
        return 1;
    }
    std::cout << "wrote " << argv[1] << "/disc.xdmf and its .h5 files\n";
    return 0;
}
