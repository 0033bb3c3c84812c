// graded.cpp — the graded mesher: the uniform stages up to the warp, then the
// balanced quadtree and its triangulation, timed.
#include <chrono>

#include "warpmesh/graded.hpp"
#include "warpmesh/uniform.hpp"  // warp_lattice: the stages both meshers share

namespace warpmesh {

GradedResult mesh_graded(const LevelSet& f, const Lattice& lattice, DiagonalRule rule, std::int64_t max_cell,
                         const CertifyOptions& certify) {
    using clock = std::chrono::steady_clock;
    auto seconds = [](clock::time_point a) { return std::chrono::duration<double>(clock::now() - a).count(); };
    GradedResult r;
    const WarpedLattice w = warp_lattice(f, lattice);
    record_front_end(r, w);
    const auto& signs = w.signs;
    const auto& warped = w.warped;

    auto t0 = clock::now();
    const Quadtree tree = build_quadtree(lattice, signs, warped, max_cell);
    const std::vector<Leaf> leaves = quadtree_leaves(tree, &r.leaves_per_level);
    r.times.quadtree = seconds(t0);

    t0 = clock::now();
    std::vector<KeyedSquare> keyed;
    if (certify.enabled) r.stats.keyed_squares = &keyed;
    r.mesh = triangulate_graded(f, lattice, signs, tree, leaves, warped, rule, &r.stats);
    r.times.triangulate = seconds(t0);
    r.stats.keyed_squares = nullptr;
    if (certify.enabled) {
        t0 = clock::now();
        r.certified = certify_mesh(r.mesh, lattice, signs, warped, rule, keyed, certify);
        r.times.certify = seconds(t0);
    }
    return r;
}

}  // namespace warpmesh
