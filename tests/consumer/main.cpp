// A program that uses an installed warpmesh (tests/consumer/CMakeLists.txt).
#include <warpmesh/warpmesh.hpp>

#include <iostream>

int main() {
    const auto disc = warpmesh::parse_shape("circle:0,0,1");
    warpmesh::MeshOptions options;
    options.spacing = 0.05;
    const warpmesh::MeshResult r = warpmesh::mesh(*disc, options);
    std::cout << r.mesh.triangles.size() << " triangles, every angle in [" << r.certified.min_deg << ", "
              << r.certified.max_deg << "] deg\n";
    return r.mesh.triangles.empty() || !r.certified.available;
}
