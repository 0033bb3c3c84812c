// tets3.cpp — stage 5: every background tetrahedron of the cubes of a range
// split by its stencil (step 6 of generic_bcc.hpp's contract), in two passes
// over the cube layers (z) so that the output is written in place, in the
// same order for any number of threads:
//   A. count each layer's tetrahedra and mark the lattice points and cut
//      points they use (a byte per point: bit 7 the point, bit s the cut
//      point on its forward edge s; atomic, neighbouring layers share points);
//   B. number the used vertices in (z, y, x) order — lattice points, then
//      cut points by (lower endpoint, slot) — and write the tetrahedra.
// A background tetrahedron of cube m with index i (background_tet) exists iff
// the cube below m along axis i / 4 exists (its centre c1).  An all-zero one
// is output iff f < 0 at the centroid of its four vertices (summed in local
// order).
#include <atomic>
#include <stdexcept>

#include "uniform3d.hpp"
#include "warpmesh/errors.hpp"
#include "warpmesh/memory.hpp"

namespace warpmesh::uniform3d {
namespace {

constexpr std::uint8_t point_bit = 0x80;

struct Cube {
    const Window& w;
    const LevelSet3& f;
    // Local points, signs and the stencil of background tetrahedron `index` of
    // cube m; nullptr when it does not exist or outputs nothing.
    const Plan* split(const bcc::Ivec& m, int index, std::array<std::int64_t, 4>& at, bool& all_zero) const {
        const TetShape& s = tet_shapes()[static_cast<std::size_t>(index)];
        if (m[static_cast<std::size_t>(index / 4)] == 0) return nullptr;
        int code = 0, negative = 0, zero = 0;
        for (int k = 3; k >= 0; --k) {
            at[static_cast<std::size_t>(k)] = w.grid.index(bcc::add(m, s.offset[static_cast<std::size_t>(k)]));
            const int sg = w.sign[static_cast<std::size_t>(at[static_cast<std::size_t>(k)])];
            code = code * 3 + sg + 1;
            negative += sg < 0, zero += sg == 0;
        }
        all_zero = zero == 4;
        bool inside = false;
        if (negative == 0) {
            if (!all_zero) return nullptr;
            Point3 c{0, 0, 0};
            for (std::int64_t p : at) {
                const Point3 q = w.point_position(p);
                c = {c.x + q.x, c.y + q.y, c.z + q.z};
            }
            inside = f.value(0.25 * c.x, 0.25 * c.y, 0.25 * c.z) < 0;
            if (!inside) return nullptr;
        }
        return &plan(code, s.parity, inside);
    }
};

template <class Body>
void for_cubes_in_layer(const CubeRange& r, std::int64_t cz, Body&& body) {
    for (std::int64_t cy = r.lo[1]; cy < r.hi[1]; ++cy)
        for (std::int64_t cx = r.lo[0]; cx < r.hi[0]; ++cx) body(bcc::Ivec{static_cast<int>(2 * cx), static_cast<int>(2 * cy), static_cast<int>(2 * cz)}, cx, cy);
}

}  // namespace

Emitted emit_tets(const LevelSet3& f, const Window& w, const CubeRange& range, bool keys, std::uint64_t max_memory) {
    const Grid& g = w.grid;
    const Lattice3& L = g.lattice;
    const std::size_t n = static_cast<std::size_t>(g.count());
    const Cube cube{w, f};
    const std::int64_t layers = range.hi[2] - range.lo[2];
    std::vector<std::uint8_t> used(n, 0);
    std::vector<std::int64_t> layer_start(static_cast<std::size_t>(layers) + 1, 0);
    // Pass A.
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t l = 0; l < layers; ++l) {
        std::int64_t count = 0;
        for_cubes_in_layer(range, range.lo[2] + l, [&](const bcc::Ivec& m, std::int64_t, std::int64_t) {
            for (int index = 0; index < 12; ++index) {
                std::array<std::int64_t, 4> at{};
                bool all_zero = false;
                const Plan* p = cube.split(m, index, at, all_zero);
                if (!p) continue;
                count += p->stencil.count;
                const TetShape& s = tet_shapes()[static_cast<std::size_t>(index)];
                for (int q = 0; q < 10; ++q) {
                    if (!(p->uses >> q & 1u)) continue;
                    const bool vertex = q < 4;
                    const std::int64_t owner = at[static_cast<std::size_t>(vertex ? q : s.lower[static_cast<std::size_t>(q - 4)])];
                    const std::uint8_t bit = vertex ? point_bit : static_cast<std::uint8_t>(1u << s.slot[static_cast<std::size_t>(q - 4)]);
                    std::atomic_ref<std::uint8_t>(used[static_cast<std::size_t>(owner)]).fetch_or(bit, std::memory_order_relaxed);
                }
            }
        });
        layer_start[static_cast<std::size_t>(l) + 1] = count;
    }
    for (std::int64_t l = 0; l < layers; ++l) layer_start[static_cast<std::size_t>(l) + 1] += layer_start[static_cast<std::size_t>(l)];
    const std::int64_t tet_count = layer_start.back();

    // Numbering: per plane counts of used points and cut points, then prefix sums.
    const int planes = g.hi[2] - g.lo[2] + 1;
    std::vector<std::int64_t> plane_points(static_cast<std::size_t>(planes) + 1, 0), plane_cuts(static_cast<std::size_t>(planes) + 1, 0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        std::int64_t np = 0, nc = 0;
        for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            np += used[static_cast<std::size_t>(p)] >> 7;
            nc += __builtin_popcount(used[static_cast<std::size_t>(p)] & 0x7Fu);
        }
        plane_points[static_cast<std::size_t>(z) + 1] = np, plane_cuts[static_cast<std::size_t>(z) + 1] = nc;
    }
    for (int z = 0; z < planes; ++z) {
        plane_points[static_cast<std::size_t>(z) + 1] += plane_points[static_cast<std::size_t>(z)];
        plane_cuts[static_cast<std::size_t>(z) + 1] += plane_cuts[static_cast<std::size_t>(z)];
    }
    const std::int64_t points = plane_points.back(), cuts = plane_cuts.back(), vertex_count = points + cuts;
    if (vertex_count >= INT32_MAX || tet_count >= INT32_MAX)
        throw InputError("the 3D mesh would have more than 2^31 vertices or tetrahedra; choose a larger --spacing or mesh in blocks (mesh3d_block)");
    // The output: 16 bytes a tetrahedron (+4 for its region, written later),
    // 25 a vertex (+8 with keys), 8 a point for the numbering.
    check_memory(static_cast<std::uint64_t>(tet_count) * (20 + (keys ? 8 : 0)) + static_cast<std::uint64_t>(vertex_count) * 33 + n * 8,
                 max_memory, "the 3D mesh of " + std::to_string(tet_count) + " tetrahedra",
                 "about 24 bytes a tetrahedron", "choose a larger --spacing");

    Emitted out;
    out.cut_points = cuts;
    Buffer<std::int32_t> id(n);  // per point: its vertex id, or the first id of its cut points (written per plane below)
    Buffer<std::int32_t> cut_id(n);
    out.vertices.resize(static_cast<std::size_t>(vertex_count));
    out.on_level_set.resize(static_cast<std::size_t>(vertex_count));
    if (keys) out.vertex_key.resize(static_cast<std::size_t>(vertex_count));
    const Grid whole = Grid::whole(L);
    const std::int64_t lattice_points = L.point_count();
    std::int64_t warped_vertices = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : warped_vertices)
    for (int z = 0; z < planes; ++z) {
        std::int64_t vp = plane_points[static_cast<std::size_t>(z)], vc = points + plane_cuts[static_cast<std::size_t>(z)];
        for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            const std::uint8_t u = used[static_cast<std::size_t>(p)];
            id[static_cast<std::size_t>(p)] = static_cast<std::int32_t>(vp);
            cut_id[static_cast<std::size_t>(p)] = static_cast<std::int32_t>(vc);
            if (!u) continue;
            const bcc::Ivec q = g.point(p);
            const std::int64_t global = keys ? whole.index(q) : 0;
            if (u & point_bit) {
                const std::size_t v = static_cast<std::size_t>(vp++);
                out.vertices[v] = w.point_position(p);
                out.on_level_set[v] = w.sign[static_cast<std::size_t>(p)] == 0;
                warped_vertices += w.warp[static_cast<std::size_t>(p)] != bcc::stay;
                if (keys) out.vertex_key[v] = static_cast<std::uint64_t>(global);
            }
            for (int s = 0; s < 7; ++s) {
                if (!(u >> s & 1u)) continue;
                const std::size_t v = static_cast<std::size_t>(vc++);
                out.vertices[v] = w.cut_position(q, s, w.u(p, s));
                out.on_level_set[v] = 1;
                if (keys) out.vertex_key[v] = static_cast<std::uint64_t>(lattice_points + 7 * global + s);
            }
        }
    }
    out.warped_vertices = warped_vertices;

    // Pass B.
    out.tets.resize(static_cast<std::size_t>(tet_count));
    if (keys) out.tet_key.resize(static_cast<std::size_t>(tet_count));
    std::vector<std::vector<std::int64_t>> edge(static_cast<std::size_t>(layers)), zero(static_cast<std::size_t>(layers));
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t l = 0; l < layers; ++l) {
        std::int64_t t = layer_start[static_cast<std::size_t>(l)];
        const std::int64_t cz = range.lo[2] + l;
        for_cubes_in_layer(range, cz, [&](const bcc::Ivec& m, std::int64_t cx, std::int64_t cy) {
            const bool near_edge = cx < 2 || cy < 2 || cz < 2 || cx >= L.cubes[0] - 2 || cy >= L.cubes[1] - 2 || cz >= L.cubes[2] - 2;
            for (int index = 0; index < 12; ++index) {
                std::array<std::int64_t, 4> at{};
                bool all_zero = false;
                const Plan* p = cube.split(m, index, at, all_zero);
                if (!p) continue;
                const TetShape& s = tet_shapes()[static_cast<std::size_t>(index)];
                std::array<std::int32_t, 10> vid{};
                for (int q = 0; q < 10; ++q) {
                    if (!(p->uses >> q & 1u)) continue;
                    if (q < 4) {
                        vid[static_cast<std::size_t>(q)] = id[static_cast<std::size_t>(at[static_cast<std::size_t>(q)])];
                        continue;
                    }
                    const std::size_t owner = static_cast<std::size_t>(at[static_cast<std::size_t>(s.lower[static_cast<std::size_t>(q - 4)])]);
                    const int slot = s.slot[static_cast<std::size_t>(q - 4)];
                    vid[static_cast<std::size_t>(q)] = cut_id[owner] + __builtin_popcount(used[owner] & ((1u << slot) - 1));
                }
                bool faces_edge = false;
                if (near_edge)
                    for (const bcc::Ivec& a : s.across) faces_edge = faces_edge || !in_lattice(L, bcc::add(m, a));
                const std::uint64_t cube_key = static_cast<std::uint64_t>((cz * L.cubes[1] + cy) * L.cubes[0] + cx) * 48 + static_cast<std::uint64_t>(index) * 4;
                for (int k = 0; k < p->stencil.count; ++k, ++t) {
                    const bcc::OutTet& o = p->stencil.tet[static_cast<std::size_t>(k)];
                    out.tets[static_cast<std::size_t>(t)] = {vid[o[0]], vid[o[1]], vid[o[2]], vid[o[3]]};
                    if (keys) out.tet_key[static_cast<std::size_t>(t)] = cube_key + static_cast<std::uint64_t>(k);
                    if (faces_edge) edge[static_cast<std::size_t>(l)].push_back(t);
                    if (all_zero) zero[static_cast<std::size_t>(l)].push_back(t);
                }
            }
        });
    }
    for (const auto& e : edge) out.edge_tets.insert(out.edge_tets.end(), e.begin(), e.end());
    for (const auto& e : zero) out.all_zero.insert(out.all_zero.end(), e.begin(), e.end());
    return out;
}

}  // namespace warpmesh::uniform3d
