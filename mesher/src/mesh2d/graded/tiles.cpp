// tiles.cpp — the graded mesher's front end (tiles.hpp), in passes:
//   classify_tiles  a range bound per block of tiles, top-down;
//   sample_tiles    f, signs and owned cut edges of each sampled tile;
//   fill_rings      each sampled tile's ring of neighbouring signs;
//   order_cut_edges the cut edges in point order;
// then warp_points, as in the uniform mesher.
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "mesh2d/graded/tiles.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace {

// Tile (I, J)'s points: [i0, i0 + ni) x [j0, j0 + nj).
PointBlock tile_points(const TiledSigns& t, std::int64_t I, std::int64_t J) {
    const std::int64_t i0 = I << t.tile_log, j0 = J << t.tile_log;
    return {i0, j0, std::min(i0 + t.size(), t.nx) - i0 + 1, std::min(j0 + t.size(), t.ny) - j0 + 1};
}

TiledSigns empty_tiles(const Lattice& lattice, int tile_log) {
    // At least 4 x 4 squares: the quadtree reads levels 1 and 2 per tile.
    if (tile_log < 2 || tile_log > 12) throw std::invalid_argument("tile_log must be in 2..12");
    TiledSigns t;
    t.tile_log = tile_log;
    t.nx = lattice.nx, t.ny = lattice.ny;
    t.tx = std::max<std::int64_t>(1, (lattice.nx + t.size() - 1) >> tile_log);
    t.ty = std::max<std::int64_t>(1, (lattice.ny + t.size() - 1) >> tile_log);
    t.slot.assign(static_cast<std::size_t>(t.tx * t.ty), -1);
    t.uniform.assign(static_cast<std::size_t>(t.tx * t.ty), 0);
    return t;
}

// Number the tiles with uniform 0 as sampled (row-major) and allocate their blocks.
std::vector<std::int64_t> allocate_sampled(TiledSigns& t) {
    std::vector<std::int64_t> sampled;
    for (std::int64_t k = 0; k < t.tx * t.ty; ++k)
        if (t.uniform[static_cast<std::size_t>(k)] == 0) {
            t.slot[static_cast<std::size_t>(k)] = static_cast<std::int32_t>(sampled.size());
            sampled.push_back(k);
        }
    if (sampled.size() > static_cast<std::size_t>(INT32_MAX)) throw std::length_error("too many tiles");
    t.blocks.resize(sampled.size() * static_cast<std::size_t>(t.stride() * t.stride()));
    return sampled;
}

// fn(m0, m1, owner) for the points (i, j) + m (di, dj), 0 <= m < len, of the
// lattice, cut into runs [m0, m1) that belong to one tile (-1: outside the
// lattice).  A run ends where the owner's column or row does: ownership is
// min(i >> b, tx - 1) on each axis (tiles.hpp), monotone along the run.
template <class Fn>
void for_each_owner_run(const TiledSigns& t, std::int64_t i, std::int64_t j, std::int64_t di, std::int64_t dj,
                        std::int64_t len, Fn&& fn) {
    for (std::int64_t m0 = 0; m0 < len;) {
        const std::int64_t a = i + m0 * di, b = j + m0 * dj;
        const std::int64_t c = di ? a : b, n = di ? t.nx : t.ny, tiles = di ? t.tx : t.ty;  // the moving coordinate
        const std::int64_t f = di ? b : a, nf = di ? t.ny : t.nx;                             // the fixed one
        std::int64_t m1 = len;  // outside to the end, unless:
        if (f >= 0 && f <= nf && c < 0) {
            m1 = std::min(len, m0 - c);  // outside until the coordinate reaches 0
        } else if (f >= 0 && f <= nf && c <= n) {
            // Inside: up to the end of the owner's span, [T c' , T (c' + 1)) or
            // up to n for the last tile.
            const std::int64_t owner = std::min(c >> t.tile_log, tiles - 1);
            const std::int64_t end = owner + 1 == tiles ? n + 1 : (owner + 1) << t.tile_log;
            m1 = std::min(len, m0 + (end - c));
        }
        const bool in_lattice = a >= 0 && b >= 0 && a <= t.nx && b <= t.ny;
        fn(m0, m1, in_lattice ? t.tile_of_x(a) + t.tile_of_y(b) * t.tx : std::int64_t{-1});
        m0 = m1;
    }
}

// The ring of every sampled tile, from the tiles around it, once all tiles'
// own points are set (a ring point belongs to another tile, whose own points
// are only read).  Run by run (for_each_owner_run): copied from a sampled
// owner's block, the owner's sign if it is uniform, 0 outside the lattice.
// Also checks the range bounds where a sampled tile meets a uniform one: the
// points they share (the tile's last row and column may belong to the next
// tiles) must have the uniform tile's sign; returns false if not (a range()
// that is not conservative).
bool fill_rings(TiledSigns& t, std::span<const std::int64_t> sampled) {
    bool consistent = true;
    const std::int64_t n = static_cast<std::int64_t>(sampled.size()), S = t.stride();
#pragma omp parallel for schedule(static) reduction(&& : consistent) if (n >= 64)
    for (std::int64_t s = 0; s < n; ++s) {
        const std::int64_t k = sampled[static_cast<std::size_t>(s)], I = k % t.tx, J = k / t.tx;
        const PointBlock b = tile_points(t, I, J);
        std::int8_t* blk = t.block(static_cast<std::int32_t>(s));
        // Point (x, y) of the tile, -1 <= x <= ni, -1 <= y <= nj, in its block.
        auto cell = [&](std::int64_t x, std::int64_t y) { return blk + (y + 1) * S + x + 1; };
        auto fill = [&](std::int64_t x, std::int64_t y, std::int64_t dx, std::int64_t dy, std::int64_t len) {
            std::int8_t* dst = cell(x, y);
            const std::int64_t step = dx + dy * S;
            for_each_owner_run(t, b.i0 + x, b.j0 + y, dx, dy, len, [&](std::int64_t m0, std::int64_t m1, std::int64_t owner) {
                const std::int32_t os = owner < 0 ? -1 : t.slot[static_cast<std::size_t>(owner)];
                if (os < 0) {
                    const std::int8_t v = owner < 0 ? std::int8_t{0} : t.uniform[static_cast<std::size_t>(owner)];
                    for (std::int64_t m = m0; m < m1; ++m) dst[m * step] = v;
                    return;
                }
                const std::int8_t* src = t.at(os, owner % t.tx, owner / t.tx, b.i0 + x + m0 * dx, b.j0 + y + m0 * dy);
                for (std::int64_t m = 0; m < m1 - m0; ++m) dst[(m0 + m) * step] = src[m * step];
            });
        };
        fill(-1, -1, 1, 0, b.ni + 2);  // bottom ring row, corners included
        fill(-1, b.nj, 1, 0, b.ni + 2);  // top
        fill(-1, 0, 0, 1, b.nj);       // left column
        fill(b.ni, 0, 0, 1, b.nj);     // right column
        auto check = [&](std::int64_t x, std::int64_t y, std::int64_t dx, std::int64_t dy, std::int64_t len) {
            for_each_owner_run(t, b.i0 + x, b.j0 + y, dx, dy, len, [&](std::int64_t m0, std::int64_t m1, std::int64_t owner) {
                if (owner == k || t.slot[static_cast<std::size_t>(owner)] >= 0) return;
                for (std::int64_t m = m0; m < m1; ++m)
                    consistent = consistent && *cell(x + m * dx, y + m * dy) == t.uniform[static_cast<std::size_t>(owner)];
            });
        };
        check(0, b.nj - 1, 1, 0, b.ni);  // the tile's last row and column
        check(b.ni - 1, 0, 0, 1, b.nj);
    }
    return consistent;
}

using clock = std::chrono::steady_clock;

// ---- classify: a range bound on each tile's reach ---------------------------
// The sign a range bound gives the reach (the points grown by one spacing) of
// tiles [I0, I1) x [J0, J1): σ if the bound decides it, else 0 (NaN included).
std::int8_t reach_sign(const LevelSet& f, const Lattice& lattice, const TiledSigns& t, std::int64_t I0, std::int64_t J0,
                       std::int64_t I1, std::int64_t J1) {
    const Vec2 lo = lattice.position((I0 << t.tile_log) - 1, (J0 << t.tile_log) - 1);
    const Vec2 hi = lattice.position(std::min(I1 << t.tile_log, t.nx) + 1, std::min(J1 << t.tile_log, t.ny) + 1);
    const Range range = f.range({lo.x, lo.y, hi.x, hi.y});
    return static_cast<std::int8_t>(range.lo > 0 ? 1 : range.hi < 0 ? -1 : 0);
}

// A block of tiles whose reach the bound decides decides all its tiles at
// once; others split in four, down to single tiles (undecided: 0, sampled).
void classify_block(const LevelSet& f, const Lattice& lattice, TiledSigns& t, std::int64_t I0, std::int64_t J0, std::int64_t I1,
                    std::int64_t J1) {
    const std::int8_t sg = reach_sign(f, lattice, t, I0, J0, I1, J1);
    if (sg != 0 || (I1 - I0 == 1 && J1 - J0 == 1)) {
        for (std::int64_t J = J0; J < J1; ++J)
            for (std::int64_t I = I0; I < I1; ++I) t.uniform[static_cast<std::size_t>(I + J * t.tx)] = sg;
        return;
    }
    const std::int64_t Im = I1 - I0 > 1 ? (I0 + I1) / 2 : I1, Jm = J1 - J0 > 1 ? (J0 + J1) / 2 : J1;
    classify_block(f, lattice, t, I0, J0, Im, Jm);
    if (Im < I1) classify_block(f, lattice, t, Im, J0, I1, Jm);
    if (Jm < J1) classify_block(f, lattice, t, I0, Jm, Im, J1);
    if (Im < I1 && Jm < J1) classify_block(f, lattice, t, Im, Jm, I1, J1);
}

// Sets t.uniform of every tile: top-down from blocks of top_block x
// top_block tiles (the parallel grain).  Work: O(undecided tiles x log).
void classify_tiles(const LevelSet& f, const Lattice& lattice, TiledSigns& t) {
    constexpr std::int64_t top_block = 16;
    const std::int64_t bx = (t.tx + top_block - 1) / top_block, by = (t.ty + top_block - 1) / top_block;
#pragma omp parallel for schedule(dynamic, 1) if (bx * by >= 4)
    for (std::int64_t b = 0; b < bx * by; ++b) {
        const std::int64_t I0 = (b % bx) * top_block, J0 = (b / bx) * top_block;
        classify_block(f, lattice, t, I0, J0, std::min(I0 + top_block, t.tx), std::min(J0 + top_block, t.ty));
    }
}

// ---- sample, signs, cut edges of each sampled tile ----------------------------
// Each thread appends its tiles' cut edges to one list of its own (not a list
// per tile: thousands of small growing vectors cost more in the allocator
// than the edges themselves); sampled tile s's are span[s].
struct CutEdgeLists {
    struct Span {
        std::size_t list, begin, end;
    };
    std::vector<std::vector<CutEdge>> lists;  // per thread
    std::vector<Span> span;                   // per sampled tile
};

// The signs of tile block b's values v (row stride b.ni) into the tile's
// block; false if a value is not finite.
bool tile_signs_from_values(const TiledSigns& t, const PointBlock& b, const std::vector<double>& v, std::int8_t* blk) {
    const std::int64_t S = t.stride();
    bool finite = true;
    for (std::int64_t y = 0; y < b.nj; ++y) {
        const double* vr = v.data() + y * b.ni;
        std::int8_t* o = blk + (y + 1) * S + 1;
        for (std::int64_t x = 0; x < b.ni; ++x) {
            finite = finite & std::isfinite(vr[x]);
            o[x] = static_cast<std::int8_t>((vr[x] > 0) - (vr[x] < 0));
        }
    }
    return finite;
}

// The cut edges that start at the points tile (I, J) owns — all but its last
// column / row, unless it is the last of its row / column — appended to out
// in point order (+x before +y at a point).  Per row, 64 points at a time, a
// flag byte per point whose edge to the right (+x) or upward (+y) is cut —
// sp != 0 and the other end -sp — in a loop the compiler vectorises; only a
// run with a flag is walked, the cut edges being a few per row.
void owned_cut_edges(const LevelSet& f, const Lattice& lattice, const TiledSigns& t, std::int64_t I, std::int64_t J, const PointBlock& b,
                     const std::vector<double>& v, const std::int8_t* blk, std::vector<CutEdge>& out) {
    constexpr std::int64_t run = 64;
    const std::int64_t S = t.stride();
    const std::int64_t own_x = I + 1 == t.tx ? b.ni : b.ni - 1, own_y = J + 1 == t.ty ? b.nj : b.nj - 1;
    for (std::int64_t y = 0; y < own_y; ++y) {
        const std::int8_t* r = blk + (y + 1) * S + 1;  // row y; row y + 1 is r + S
        const std::int64_t with_right = std::min(own_x, b.ni - 1), with_up = y + 1 < b.nj ? own_x : 0;
        for (std::int64_t x0 = 0; x0 < own_x; x0 += run) {
            const std::int64_t nr = std::min(x0 + run, with_right) - x0, nu = std::min(x0 + run, with_up) - x0;
            std::array<std::uint8_t, run> cr, cu;  // written for x < nr, x < nu; only those read
            std::uint8_t any = 0;
            for (std::int64_t x = 0; x < nr; ++x) {
                const std::int8_t a = r[x0 + x];
                cr[static_cast<std::size_t>(x)] = static_cast<std::uint8_t>((a != 0) & (r[x0 + x + 1] == -a));
                any |= cr[static_cast<std::size_t>(x)];
            }
            for (std::int64_t x = 0; x < nu; ++x) {
                const std::int8_t a = r[x0 + x];
                cu[static_cast<std::size_t>(x)] = static_cast<std::uint8_t>((a != 0) & (r[x0 + x + S] == -a));
                any |= cu[static_cast<std::size_t>(x)];
            }
            if (!any) continue;
            for (std::int64_t q = 0; q < std::max(nr, nu); ++q) {
                const std::size_t Q = static_cast<std::size_t>(q);
                const std::int64_t x = x0 + q;
                const double fp = v[static_cast<std::size_t>(x + y * b.ni)];
                if (q < nr && cr[Q])
                    append_cut_edge(f, lattice, b.i0 + x, b.j0 + y, 0, r[x], r[x + 1], fp, v[static_cast<std::size_t>(x + 1 + y * b.ni)], out);
                if (q < nu && cu[Q])
                    append_cut_edge(f, lattice, b.i0 + x, b.j0 + y, 1, r[x], r[x + S], fp, v[static_cast<std::size_t>(x + (y + 1) * b.ni)],
                                    out);
            }
        }
    }
}

// f at the points of every sampled tile, their signs into the tile's block,
// and the tile's owned cut edges.  Throws InputError (throw_non_finite) at
// the largest index of a non-finite value, whatever the thread count.
CutEdgeLists sample_tiles(const LevelSet& f, const Lattice& lattice, TiledSigns& t, std::span<const std::int64_t> sampled,
                          std::int64_t& points) {
    const std::int64_t n = static_cast<std::int64_t>(sampled.size());
    int nthreads = 1;
#ifdef _OPENMP
    nthreads = omp_get_max_threads();
#endif
    CutEdgeLists r;
    r.lists.resize(static_cast<std::size_t>(nthreads));
    r.span.assign(sampled.size(), CutEdgeLists::Span{0, 0, 0});
    std::int64_t bad = -1, count = 0;  // the lattice index of a non-finite value
#pragma omp parallel reduction(max : bad) reduction(+ : count)
    {
        std::vector<double> v(static_cast<std::size_t>((t.size() + 1) * (t.size() + 1)));
        int me = 0;
#ifdef _OPENMP
        me = omp_get_thread_num();
#endif
        auto& out = r.lists[static_cast<std::size_t>(me)];
        // Room for a boundary crossing each of its tiles once (T cut edges);
        // reserved, so untouched beyond what is written.
        out.reserve(static_cast<std::size_t>(n / nthreads + 1) * static_cast<std::size_t>(t.size()));
#pragma omp for schedule(dynamic, 4)
        for (std::int64_t s = 0; s < n; ++s) {
            const std::int64_t k = sampled[static_cast<std::size_t>(s)], I = k % t.tx, J = k / t.tx;
            const PointBlock b = tile_points(t, I, J);
            f.sample_block(lattice, b, v);
            count += b.ni * b.nj;
            std::int8_t* blk = t.block(static_cast<std::int32_t>(s));
            if (!tile_signs_from_values(t, b, v, blk)) {  // the largest non-finite point's index, as for every tile
                for (std::int64_t y = 0; y < b.nj; ++y)
                    for (std::int64_t x = 0; x < b.ni; ++x)
                        if (!std::isfinite(v[static_cast<std::size_t>(x + y * b.ni)])) bad = std::max(bad, lattice.index(b.i0 + x, b.j0 + y));
                continue;
            }
            const std::size_t first = out.size();
            owned_cut_edges(f, lattice, t, I, J, b, v, blk, out);
            r.span[static_cast<std::size_t>(s)] = {static_cast<std::size_t>(me), first, out.size()};
        }
    }
    if (bad >= 0) throw_non_finite(lattice, bad);
    points = count;
    return r;
}

// ---- cut edges in point order -------------------------------------------------
// All cut edges, as `edges` (the one thread's list, or the threads' lists
// joined into `joined`) and a permutation of them into point order — not a
// sorted copy: 4 bytes an edge instead of 24, and with one thread no copy at
// all.  Tile rows own the same lattice rows, so per tile row the tiles' edges
// are merged row by row.
Buffer<std::uint32_t> order_cut_edges(const Lattice& lattice, const TiledSigns& t, std::span<const std::int64_t> sampled, CutEdgeLists& c,
                                      std::vector<CutEdge>& joined, std::span<const CutEdge>& edges) {
    std::vector<std::size_t> base(c.lists.size() + 1, 0);  // list q's edges at base[q] .. of the joined edges
    for (std::size_t q = 0; q < c.lists.size(); ++q) base[q + 1] = base[q] + c.lists[q].size();
    const std::size_t total = base.back();
    if (total >= UINT32_MAX) throw std::length_error("too many cut edges");
    if (c.lists.size() > 1) {
        joined.reserve(total);
        for (const auto& l : c.lists) joined.insert(joined.end(), l.begin(), l.end());
    }
    edges = c.lists.size() > 1 ? std::span<const CutEdge>(joined) : std::span<const CutEdge>(c.lists[0]);
    Buffer<std::uint32_t> order(total);  // every element written below
    const std::int64_t n = static_cast<std::int64_t>(sampled.size());
    std::size_t k = 0;
    for (std::int64_t s0 = 0; s0 < n;) {
        const std::int64_t J = sampled[static_cast<std::size_t>(s0)] / t.tx;
        std::int64_t s1 = s0;
        while (s1 < n && sampled[static_cast<std::size_t>(s1)] / t.tx == J) ++s1;
        const std::int64_t j_end = J + 1 == t.ty ? t.ny + 1 : (J + 1) << t.tile_log;
        for (std::int64_t j = J << t.tile_log; j < j_end; ++j)
            for (std::int64_t s = s0; s < s1; ++s) {
                CutEdgeLists::Span& q = c.span[static_cast<std::size_t>(s)];  // begin: the tile's first edge not yet taken
                const CutEdge* e = edges.data() + base[q.list];
                const std::int64_t row_end = (j + 1) * lattice.points_x();  // cuts of row j: p < row_end
                while (q.begin < q.end && e[q.begin].p < row_end) order[k++] = static_cast<std::uint32_t>(base[q.list] + q.begin++);
            }
        s0 = s1;
    }
    assert(k == total);
    return order;
}

}  // namespace

TiledFront warp_tiles(const LevelSet& f, const Lattice& lattice, int tile_log) {
    const auto t0 = clock::now();
    TiledFront r;
    TiledSigns& t = r.signs;
    t = empty_tiles(lattice, tile_log);
    classify_tiles(f, lattice, t);
    const std::vector<std::int64_t> sampled = allocate_sampled(t);
    CutEdgeLists cuts = sample_tiles(f, lattice, t, sampled, r.sampled_points);
    if (!fill_rings(t, sampled))
        throw std::logic_error("the range bound of " + f.describe() + " is not conservative (a sampled sign contradicts it)");
    std::vector<CutEdge> joined;
    std::span<const CutEdge> edges;
    const Buffer<std::uint32_t> order = order_cut_edges(lattice, t, sampled, cuts, joined, edges);
    r.cut_edges = static_cast<std::int64_t>(order.size());
    r.tiles_seconds = seconds_since(t0);

    const auto t1 = clock::now();
    r.warped = warp_points(lattice, edges, order);
    r.warp_seconds = seconds_since(t1);
    return r;
}

TiledSigns tile_signs(const Lattice& lattice, std::span<const std::int8_t> signs, int tile_log, bool sample_every_tile) {
    TiledSigns t = empty_tiles(lattice, tile_log);
    if (!sample_every_tile)  // a tile whose points all have one non-zero sign is uniform
        for (std::int64_t k = 0; k < t.tx * t.ty; ++k) {
            const PointBlock b = tile_points(t, k % t.tx, k / t.tx);
            const std::int8_t first = signs[static_cast<std::size_t>(lattice.index(b.i0, b.j0))];
            bool same = first != 0;
            for (std::int64_t y = 0; y < b.nj && same; ++y) {
                const std::int8_t* row = signs.data() + lattice.index(b.i0, b.j0 + y);
                for (std::int64_t x = 0; x < b.ni; ++x) same &= row[x] == first;
            }
            t.uniform[static_cast<std::size_t>(k)] = same ? first : std::int8_t{0};
        }
    const std::vector<std::int64_t> sampled = allocate_sampled(t);
    const std::int64_t S = t.stride();
    for (std::size_t s = 0; s < sampled.size(); ++s) {
        const PointBlock b = tile_points(t, sampled[s] % t.tx, sampled[s] / t.tx);
        std::int8_t* blk = t.block(static_cast<std::int32_t>(s));
        for (std::int64_t y = 0; y < b.nj; ++y)
            for (std::int64_t x = 0; x < b.ni; ++x)
                blk[(y + 1) * S + x + 1] = signs[static_cast<std::size_t>(lattice.index(b.i0 + x, b.j0 + y))];
    }
    fill_rings(t, sampled);
    return t;
}

}  // namespace warpmesh
