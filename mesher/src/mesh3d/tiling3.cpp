// tiling3.cpp — whether blocks (mesh3d.hpp: TetBlock) tile one lattice
// exactly once: the check merge_bcc_blocks makes before it merges, so that
// a lost, repeated or shifted block, or a block of another mesh, is refused
// with its name instead of leaving a hole that looks like boundary.
//
// The cubes of block b are the box [lo_b, hi_b).  The blocks tile the
// lattice's cubes [0, cubes) iff every box lies in it, no two boxes share a
// cube, and their cube counts add up to the lattice's: with no overlap the
// sum counts every covered cube once, so it equals the total iff nothing is
// missed.  A gap is named by a box of missing cubes: the boxes' faces cut
// each axis into intervals (the compressed grid, one cell per product of
// intervals, each cell wholly in a block or wholly out), and the first
// uncovered cell in (z, y, x) order is grown along x, then y, then z while
// the cells it takes in are uncovered.
#include <algorithm>
#include <charconv>
#include <numeric>

#include "uniform3d.hpp"

namespace warpmesh {
namespace {

std::string text(const std::array<std::int64_t, 3>& a) {
    return "(" + std::to_string(a[0]) + ", " + std::to_string(a[1]) + ", " + std::to_string(a[2]) + ")";
}
std::string text(const CubeRange& r) { return "[" + text(r.lo) + ", " + text(r.hi) + ")"; }
std::string named(std::span<const TetBlock> blocks, std::size_t i) {
    return "block " + std::to_string(i) + " (cubes " + text(blocks[i].range) + ")";
}

std::int64_t cube_count(const CubeRange& r) { return (r.hi[0] - r.lo[0]) * (r.hi[1] - r.lo[1]) * (r.hi[2] - r.lo[2]); }

// The shortest text that reads back as x.
std::string shortest(double x) {
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

std::string lattice_text(const Lattice3& L) {
    return "spacing " + shortest(L.spacing) + ", origin (" + shortest(L.origin.x) + ", " + shortest(L.origin.y) + ", " +
           shortest(L.origin.z) + "), cubes " + text(L.cubes);
}

// The first block whose lattice, face rule or alphas differ from block 0's.
std::optional<std::string> mixed(std::span<const TetBlock> blocks) {
    const TetBlock& a = blocks.front();
    for (std::size_t i = 1; i < blocks.size(); ++i) {
        const TetBlock& b = blocks[i];
        const bool same_lattice = a.lattice.spacing == b.lattice.spacing && a.lattice.origin.x == b.lattice.origin.x &&
                                  a.lattice.origin.y == b.lattice.origin.y && a.lattice.origin.z == b.lattice.origin.z &&
                                  a.lattice.cubes == b.lattice.cubes;
        const std::string of = named(blocks, i) + " and " + named(blocks, 0) + " are of different meshes: ";
        if (!same_lattice) return of + "lattices " + lattice_text(b.lattice) + " and " + lattice_text(a.lattice);
        if (a.face_rule != b.face_rule)
            return of + "face rules " + std::string(face_rule_name(b.face_rule)) + " and " + std::string(face_rule_name(a.face_rule));
        const auto [ln, ld, sn, sd] = b.alphas;
        const auto [aln, ald, asn, asd] = a.alphas;
        if (ln * ald != aln * ld || sn * asd != asn * sd) return of + "different alphas";
    }
    return std::nullopt;
}

// Two blocks sharing a cube, found by a sweep along x.
std::optional<std::string> overlap(std::span<const TetBlock> blocks) {
    std::vector<std::size_t> order(blocks.size());
    std::iota(order.begin(), order.end(), 0);
    std::erase_if(order, [&](std::size_t i) { return cube_count(blocks[i].range) == 0; });
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return blocks[i].range.lo[0] < blocks[j].range.lo[0]; });
    for (std::size_t u = 0; u < order.size(); ++u) {
        const CubeRange& a = blocks[order[u]].range;
        for (std::size_t v = u + 1; v < order.size() && blocks[order[v]].range.lo[0] < a.hi[0]; ++v) {
            const CubeRange& b = blocks[order[v]].range;
            CubeRange both;
            bool meet = true;
            for (std::size_t k = 0; k < 3; ++k) {
                both.lo[k] = std::max(a.lo[k], b.lo[k]), both.hi[k] = std::min(a.hi[k], b.hi[k]);
                meet = meet && both.lo[k] < both.hi[k];
            }
            if (!meet) continue;
            const std::size_t i = std::min(order[u], order[v]), j = std::max(order[u], order[v]);
            if (a.lo == b.lo && a.hi == b.hi)
                return "the cubes " + text(a) + " are given twice (blocks " + std::to_string(i) + " and " + std::to_string(j) + ")";
            return named(blocks, i) + " and " + named(blocks, j) + " overlap in the cubes " + text(both);
        }
    }
    return std::nullopt;
}

// A box of cubes no block covers (the blocks do not overlap), or nothing
// when the compressed grid would be too large to search.
std::optional<CubeRange> missing_box(std::span<const TetBlock> blocks, const std::array<std::int64_t, 3>& cubes) {
    std::array<std::vector<std::int64_t>, 3> cut;
    for (std::size_t k = 0; k < 3; ++k) {
        cut[k] = {0, cubes[k]};
        for (const TetBlock& b : blocks) cut[k].push_back(b.range.lo[k]), cut[k].push_back(b.range.hi[k]);
        std::sort(cut[k].begin(), cut[k].end());
        cut[k].erase(std::unique(cut[k].begin(), cut[k].end()), cut[k].end());
    }
    const std::array<std::size_t, 3> n{cut[0].size() - 1, cut[1].size() - 1, cut[2].size() - 1};
    if (n[0] * n[1] * n[2] > (std::size_t{1} << 24)) return std::nullopt;
    const auto at = [&](std::size_t k, std::int64_t x) {
        return static_cast<std::size_t>(std::lower_bound(cut[k].begin(), cut[k].end(), x) - cut[k].begin());
    };
    std::vector<std::uint8_t> covered(n[0] * n[1] * n[2], 0);
    const auto cell = [&](std::size_t x, std::size_t y, std::size_t z) -> std::uint8_t& { return covered[x + n[0] * (y + n[1] * z)]; };
    for (const TetBlock& b : blocks)
        for (std::size_t z = at(2, b.range.lo[2]); z < at(2, b.range.hi[2]); ++z)
            for (std::size_t y = at(1, b.range.lo[1]); y < at(1, b.range.hi[1]); ++y)
                for (std::size_t x = at(0, b.range.lo[0]); x < at(0, b.range.hi[0]); ++x) cell(x, y, z) = 1;
    const auto first = std::find(covered.begin(), covered.end(), 0);
    if (first == covered.end()) return std::nullopt;
    const std::size_t f = static_cast<std::size_t>(first - covered.begin());
    std::array<std::size_t, 3> lo{f % n[0], f / n[0] % n[1], f / (n[0] * n[1])}, hi{lo[0] + 1, lo[1] + 1, lo[2] + 1};
    const auto free = [&](const std::array<std::size_t, 3>& a, const std::array<std::size_t, 3>& b) {
        for (std::size_t z = a[2]; z < b[2]; ++z)
            for (std::size_t y = a[1]; y < b[1]; ++y)
                for (std::size_t x = a[0]; x < b[0]; ++x)
                    if (cell(x, y, z)) return false;
        return true;
    };
    for (std::size_t k = 0; k < 3; ++k)
        while (hi[k] < n[k]) {
            std::array<std::size_t, 3> a = lo, b = hi;
            a[k] = hi[k], b[k] = hi[k] + 1;
            if (!free(a, b)) break;
            ++hi[k];
        }
    CubeRange r;
    for (std::size_t k = 0; k < 3; ++k) r.lo[k] = cut[k][lo[k]], r.hi[k] = cut[k][hi[k]];
    return r;
}

}  // namespace

std::optional<std::string> tiling_problem(std::span<const TetBlock> blocks) {
    if (blocks.empty()) return "no blocks to merge (an empty list)";
    if (auto m = mixed(blocks)) return m;
    const std::array<std::int64_t, 3>& cubes = blocks.front().lattice.cubes;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        const CubeRange& r = blocks[i].range;
        for (std::size_t k = 0; k < 3; ++k)
            if (!(0 <= r.lo[k] && r.lo[k] <= r.hi[k] && r.hi[k] <= cubes[k]))
                return named(blocks, i) + " is not a range of the lattice's cubes " + text(cubes);
    }
    if (auto o = overlap(blocks)) return o;
    std::int64_t covered = 0;
    for (const TetBlock& b : blocks) covered += cube_count(b.range);
    const std::int64_t total = cubes[0] * cubes[1] * cubes[2];
    if (covered == total) return std::nullopt;
    std::string what = std::to_string(total - covered) + " of the lattice's " + std::to_string(total) + " cubes are in no block";
    if (const auto box = missing_box(blocks, cubes)) what = "the cubes " + text(*box) + " are in no block (" + what + ")";
    return what + ": a block is missing";
}

}  // namespace warpmesh
