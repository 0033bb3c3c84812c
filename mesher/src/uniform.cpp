// uniform.cpp — the uniform mesher: the five stages in order, timed.
#include <chrono>

#include "warpmesh/uniform.hpp"

namespace warpmesh {

UniformResult mesh_uniform(const LevelSet& f, const Lattice& lattice, DiagonalRule rule,
                           const CertifyOptions& certify) {
    using clock = std::chrono::steady_clock;
    auto seconds = [](clock::time_point a) { return std::chrono::duration<double>(clock::now() - a).count(); };
    UniformResult r;
    auto t0 = clock::now();
    Buffer<double> values = sample_values(f, lattice);
    r.times.sample = seconds(t0);

    t0 = clock::now();
    const Buffer<std::int8_t> signs = compute_signs(values);
    r.times.signs = seconds(t0);

    t0 = clock::now();
    const std::vector<CutEdge> cuts = find_cut_edges(f, lattice, values, signs);
    Buffer<double>().swap(values);  // values are not needed past the cut points
    r.times.cut_points = seconds(t0);
    r.cut_edges = static_cast<std::int64_t>(cuts.size());

    t0 = clock::now();
    const std::vector<WarpedPoint> warped = warp_points(lattice, cuts, signs);
    r.times.warp = seconds(t0);
    r.warped_points = static_cast<std::int64_t>(warped.size());

    t0 = clock::now();
    std::vector<KeyedSquare> keyed;
    if (certify.enabled) r.stats.keyed_squares = &keyed;
    r.mesh = triangulate(f, lattice, signs, warped, rule, &r.stats);
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
