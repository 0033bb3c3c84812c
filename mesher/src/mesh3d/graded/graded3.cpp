// graded3.cpp — the graded 3D mesher (mesh3d/graded.hpp): the uniform
// stages on the whole lattice up to warping, the octree (octree3.hpp), then
// stage 5 over it (tets3.cpp with the tree) and the boundary.
#include "warpmesh/mesh3d/graded.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "mesh3d/graded/octree3.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/grading.hpp"

namespace warpmesh {

int max_level_for_size(double max_size, double spacing) {
    if (!(spacing > 0) || !std::isfinite(max_size) || !(max_size >= 2 * spacing))
        throw std::invalid_argument("max size must be finite and at least 2 * spacing");
    int l = 1;
    while (l < 30 && std::ldexp(spacing, l + 1) <= max_size) ++l;
    return l;
}

void graded3::check_graded_options(const GradedOptions3& g) {
    if (g.max_level < 0) throw std::invalid_argument("mesh_bcc_graded: max_level must be 0 or more");
    if (g.buffer < 0 || g.buffer > max_grading_buffer) throw std::invalid_argument("mesh_bcc_graded: buffer out of range");
}

GradedBccMesh mesh_bcc_graded(const LevelSet3& f, const Lattice3& lattice, const BccOptions& o, const GradedOptions3& g) {
    using namespace uniform3d;
    graded3::check_graded_options(g);
    check_options(o);
    const ThreadCount threads(o.threads);
    const auto start = std::chrono::steady_clock::now();
    Window w;
    w.grid = Grid::whole(lattice);
    prepare_window(f, o, w);
    GradedBccMesh r;
    Emitted e;
    {
        const graded3::Octree3 tree = graded3::build_octree3(w, g.max_level, g.buffer);
        e = emit_tets(w, {{0, 0, 0}, lattice.cubes}, false, o.max_memory, o.face_rule, o.verify, &tree);
        r.leaves_per_level = tree.leaves_per_level;
    }
    r.template_tets = e.template_tets;
    const std::int64_t warped = w.warp_count;
    w = Window{};
    r.bcc = finish_mesh(std::move(e), f, lattice, o, warped);
    r.bcc.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

}  // namespace warpmesh
