// gather_keys.hpp — the meshers' SquareKeys (mesh2d/lattice.hpp): what
// certification reads of each square through the rule.  Private to
// mesher/src.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

// The warp of lattice point p: its direction in `warped` (sorted by point),
// Warp::stay if p did not move.
inline Warp warp_at(std::span<const WarpedPoint> warped, std::int64_t p) {
    const auto it = std::lower_bound(warped.begin(), warped.end(), p, [](const WarpedPoint& w, std::int64_t q) { return w.p < q; });
    return it != warped.end() && it->p == p ? it->dir : Warp::stay;
}

// The stencil signs of square (i, j) from the signs of f at the lattice
// points, sign_at(x, y) (the one-region meshers); off_lattice outside.
template <class SignAt>
void stencil_signs(const Lattice& lattice, std::int64_t i, std::int64_t j, SignAt&& sign_at, std::array<std::int8_t, 12>& st) {
    for (std::size_t q = 0; q < 12; ++q) {
        const std::int64_t x = i + stencil_offsets[q][0], y = j + stencil_offsets[q][1];
        st[q] = (x < 0 || y < 0 || x > lattice.nx || y > lattice.ny) ? off_lattice : sign_at(x, y);
    }
}

// The SquareKeys of `squares` (the squares through the rule, moved in):
// stencil(i, j, signs) fills square (i, j)'s stencil signs and returns
// whether it is a junction square (then signs[0..3] are its corners'
// material classes); the corners' warps come from `warped` (sorted by
// point).  Parallel over the squares; `stencil` only reads.  Timed.
template <class Stencil>
SquareKeys gather_keys(const Lattice& lattice, std::vector<KeyedSquare> squares, std::span<const WarpedPoint> warped,
                       LatticeMetric metric, Stencil&& stencil) {
    const auto t0 = std::chrono::steady_clock::now();
    SquareKeys keys;
    keys.metric = metric;
    keys.stencils.resize(squares.size());
    const std::int64_t n = static_cast<std::int64_t>(squares.size()), nx = lattice.nx, nxp = lattice.points_x();
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < n; ++k) {
        const std::int64_t sq = squares[static_cast<std::size_t>(k)].square, i = sq % nx, j = sq / nx;
        KeyedStencil& ks = keys.stencils[static_cast<std::size_t>(k)];
        ks.junction = stencil(i, j, ks.signs);
        const std::int64_t pa = lattice.index(i, j);
        const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
        for (std::size_t c = 0; c < 4; ++c) ks.warps[c] = warp_at(warped, p[c]);
    }
    keys.squares = std::move(squares);
    keys.seconds = seconds_since(t0);
    return keys;
}

}  // namespace warpmesh
