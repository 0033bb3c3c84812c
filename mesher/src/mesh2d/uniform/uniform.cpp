// uniform.cpp — the uniform mesher: the five stages in order, timed.
#include <chrono>

#include "warpmesh/mesh2d/uniform.hpp"

#include "mesh2d/gather_keys.hpp"

namespace warpmesh {

namespace {
using clock = std::chrono::steady_clock;
}  // namespace

WarpedLattice warp_lattice(const LevelSet& f, const Lattice& lattice) {
    WarpedLattice w;
    auto t0 = clock::now();
    Buffer<double> values = sample_values(f, lattice);
    w.sample = seconds_since(t0);

    t0 = clock::now();
    w.signs = compute_signs(values);
    w.signs_seconds = seconds_since(t0);

    t0 = clock::now();
    const std::vector<CutEdge> cuts = find_cut_edges(f, lattice, values, w.signs);
    Buffer<double>().swap(values);  // values are not needed past the cut points
    w.cut_points = seconds_since(t0);
    w.cut_edges = static_cast<std::int64_t>(cuts.size());

    t0 = clock::now();
    w.warped = warp_points(lattice, cuts);
    w.warp = seconds_since(t0);
    return w;
}

UniformResult mesh_uniform(const LevelSet& f, const Lattice& lattice, DiagonalRule rule, KeyOptions keys, LatticeMetric metric) {
    UniformResult r;
    const WarpedLattice w = warp_lattice(f, lattice);
    r.times.sample = w.sample, r.times.signs = w.signs_seconds, r.times.cut_points = w.cut_points, r.times.warp = w.warp;
    r.cut_edges = w.cut_edges;
    r.warped_points = static_cast<std::int64_t>(w.warped.size());
    const auto& signs = w.signs;
    const auto& warped = w.warped;

    auto t0 = clock::now();
    std::vector<KeyedSquare> keyed;
    if (keys.keys) r.stats.keyed_squares = &keyed;
    r.mesh = triangulate(f, lattice, signs, warped, rule, &r.stats, metric);
    r.times.triangulate = seconds_since(t0);
    r.stats.keyed_squares = nullptr;
    if (keys.keys) {
        const auto sign_at = [&](std::int64_t i, std::int64_t j) { return signs[static_cast<std::size_t>(lattice.index(i, j))]; };
        r.keys = gather_keys(lattice, std::move(keyed), warped, metric, [&](std::int64_t i, std::int64_t j, std::array<std::int8_t, 12>& st) {
            stencil_signs(lattice, i, j, sign_at, st);
            return false;
        });
    }
    return r;
}

}  // namespace warpmesh
