// write_plane_points.cpp — a slice mesh's vertices placed in 3D (--points-3d).
#include <cstdio>

#include "io/atomic_file.hpp"
#include "warpmesh/io/volume.hpp"

namespace warpmesh {

void write_points_3d(const Mesh& mesh, const SlicePlane& plane, const std::string& path) {
    AtomicFile file(path);
    std::ostream& out = file.stream();
    out << "x,y,z\n";
    char buf[96];
    for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
        const Vec3 p = plane.point(mesh.vertices[k].x, mesh.vertices[k].y);
        std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g\n", p[0], p[1], p[2]);
        out << buf;
    }
    file.commit();
}

}  // namespace warpmesh
