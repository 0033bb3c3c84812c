// mesh_materials_graded.cpp — the multi-material graded mesher
// (materials.hpp): the uniform multi-material front (material_front), the
// graded mesher's balanced quadtree with its finest band along every
// interface, and the triangles of its leaves.
//
// The quadtree (graded/quadtree.hpp) is built unchanged, from signs that say
// what it needs to know of the materials.  A lattice point is *critical* when
// a 4-neighbour has another material, i.e. it is an endpoint of a cut edge
// (every warped point and every tie is one); its sign is then 0.  Any other
// point has sign -1 if its material is output and +1 if it is the dropped
// background.  A non-critical point's 4-neighbours have its material, so
// their signs are its own or 0, never the opposite: the quadtree's critical
// points (sign 0, or a 4-neighbour of the opposite sign) are exactly these.
// Its invariant then reads: every square with a corner on a cut edge between
// different materials is a finest leaf with no split side — a square of the
// uniform multi-material mesh, with the same diagonal and triangles
// (check_critical_squares_finest checks it under KeyOptions::check_invariant).  A
// coarse leaf holds only non-critical points, 4-connected inside it, so they
// all carry one material, the leaf's; a finest square across a side of a
// coarse leaf shares two of them, and its triangle along that side has two
// staying corners of the leaf's material.  Inside leaves on the lattice
// border are not coarsened (quadtree.hpp), so the border is meshed as in the
// uniform mesh.  Tiles whose points all share one sign are uniform
// (tile_signs), so the quadtree's work outside the band follows the band.
//
// Size control.  max_cell and the grading buffer are the single-region
// mesher's (graded.hpp).  A material m with its own largest cell K_m (a power
// of two below max_cell, or any with max_cell 0) gives its non-critical
// points the inside class of level log2 K_m (quadtree.hpp: code -2 - L)
// instead of -1: its coarse leaves are at most K_m squares wide, so their
// triangles' longest edges at most √2 K_m s; its finest squares' at most
// √5 s, as everywhere.  A class is still "inside, non-critical": the
// critical points, hence the band, its squares and the interfaces, do not
// change, and a coarse leaf still holds the points of one material.
//
// Triangles, in order: the finest leaves in canonical order (for_each_finest)
// as mesh_materials does a lattice square (no moved corner: the union-jack
// diagonal, the square's material; else the rule on the material corners,
// each triangle the common material of its staying corners, or the material
// at its centroid); then the coarse leaves, by the graded templates
// (triangulate_graded.cpp: the diagonal of coarse_tie_break, or the centre
// joined to the corners and the split sides' midpoints: 45-45-90
// triangles), all of the leaf's material.
// The background's triangles are made too and dropped at output
// (MaterialOptions::keep_background false).  Conformity is the graded mesh's
// (2:1 edge balance, midpoints of split sides are vertices on both sides).
//
// Edges.  Every triangle's vertices are lattice points (warped or not), so
// its edges are pairs of lattice points.  An edge whose ends lie on one side
// of the lattice border (both i = 0, both i = nx, both j = 0 or both j = ny)
// is a side of a square or leaf on the border, held by that triangle alone:
// a border edge (boundary_domain if the triangle is output).  Any other edge
// can separate different materials only if both its triangles come from
// warped squares (a square with a moved corner): an edge of a plain square
// (no moved corner) or of a coarse leaf joins two unwarped points of one
// material, and the triangle across it has those two staying corners, hence
// that material too.  So only the warped squares' half-edges are sorted by
// their endpoints and paired; one without a twin there has its twin in a
// plain square or coarse leaf and separates nothing.  A pair of different
// materials is an interface if both triangles are output, else a boundary
// edge (boundary_level_set) of the output one, and adds its length to both
// perimeters.  Since the finest band is the uniform mesh's, the interfaces
// and boundary edges are the uniform mesh's, as vertex pairs.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>

#include "mesh2d/graded/quadtree.hpp"
#include "mesh2d/graded/tiles.hpp"
#include "mesh2d/materials/material_front.hpp"
#include "mesh2d/square_code.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/materials.hpp"

namespace warpmesh {
namespace {

using clock = std::chrono::steady_clock;
using namespace square_code;  // rule_bit, bc_bit, triangle_of

// A triangle of the full tiling: its corners as lattice points (counter-
// clockwise), twice its area, its material, whether it is output, whether it
// comes from a warped square, whether its square or leaf touches the lattice
// border.
struct FullTriangle {
    std::array<std::int64_t, 3> p;
    double area2;
    std::uint16_t m;
    bool out, warped, border;
};

// Half-edge p[k] → p[k + 1] of triangle `tri`, keyed by its endpoints in
// increasing order.
struct HalfEdge {
    std::int64_t lo, hi;
    std::int32_t tri;
    std::int8_t k;
    bool operator<(const HalfEdge& o) const { return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : tri < o.tri; }
};

// The signs the quadtree is built from (see the head comment), per point:
// 0 at a critical point, else `code` of its material (+1 the dropped
// background, -1 or an inside class).
std::vector<std::int8_t> material_signs(const Lattice& lattice, const Buffer<std::uint16_t>& mat, std::span<const std::int8_t> code) {
    const std::int64_t nxp = lattice.points_x(), nyp = lattice.ny + 1;
    std::vector<std::int8_t> sg(static_cast<std::size_t>(nxp * nyp));
#pragma omp parallel for schedule(static)
    for (std::int64_t j = 0; j < nyp; ++j) {
        const std::uint16_t* row = mat.data() + j * nxp;
        for (std::int64_t i = 0; i < nxp; ++i) {
            const std::uint16_t m = row[i];
            const bool critical = (i > 0 && row[i - 1] != m) || (i + 1 < nxp && row[i + 1] != m) ||
                                  (j > 0 && row[i - nxp] != m) || (j + 1 < nyp && row[i + nxp] != m);
            sg[static_cast<std::size_t>(i + j * nxp)] = critical ? std::int8_t{0} : code[m];
        }
    }
    return sg;
}

// Each material's sign code (head comment) and whether some material has an
// inside class of its own (a largest cell K_m below max_cell).  Throws
// std::invalid_argument for a max_cell_of of the wrong size or an entry that
// is not 0 or a power of two.
struct MaterialCodes {
    std::vector<std::int8_t> code;
    bool classes = false;
};

MaterialCodes material_codes(int nmat, bool drop, std::int64_t max_cell, std::span<const std::int64_t> max_cell_of) {
    if (!max_cell_of.empty() && max_cell_of.size() != static_cast<std::size_t>(nmat))
        throw std::invalid_argument("max_cell_of needs one entry per material (" + std::to_string(nmat) + "), got " +
                                    std::to_string(max_cell_of.size()));
    MaterialCodes c{std::vector<std::int8_t>(static_cast<std::size_t>(nmat), -1), false};
    if (drop) c.code[0] = 1;
    for (std::size_t m = 0; m < max_cell_of.size(); ++m) {
        const std::int64_t K = max_cell_of[m];
        if (K < 0 || (K & (K - 1)) != 0)
            throw std::invalid_argument("a material's max cell size must be 0 or a power of two, got " + std::to_string(K));
        if (K == 0 || (max_cell != 0 && K >= max_cell) || c.code[m] > 0) continue;
        c.code[m] = inside_class(std::countr_zero(static_cast<std::uint64_t>(K)));
        c.classes = true;
    }
    return c;
}

// The balanced quadtree of the material signs and its leaves, background
// included; sets r.leaves_per_level, r.quadtree_seconds and, with `verify`,
// r.invariant_squares after checking the band invariant on the leaves
// (std::logic_error if violated).
Leaves material_leaves(const Lattice& lattice, const MaterialFront& front, const MaterialCodes& codes, std::int64_t max_cell,
                       int grading_buffer, bool verify, MaterialResult& r) {
    const auto t0 = clock::now();
    const TiledSigns signs =
        tile_signs(lattice, material_signs(lattice, front.mat, codes.code), default_tile_log, /*sample_every_tile=*/false);
    const Quadtree tree = build_quadtree(lattice, signs, front.warped, max_cell, grading_buffer, codes.classes);
    Leaves leaves = quadtree_leaves(tree, &r.leaves_per_level, /*drop_outside=*/false);
    if (verify) {  // the invariant the certificates rest on, from the leaf list
        const CriticalSquaresCheck inv = check_critical_squares_finest(leaves, signs, front.warped);
        if (!inv.ok()) throw std::logic_error(inv.first);
        r.invariant_squares = inv.squares;
    }
    r.quadtree_seconds = seconds_since(t0);
    return leaves;
}

// The full tiling (head comment: Triangles): every triangle of every leaf,
// the dropped background's too; the squares through the rule with their
// output triangles (for the certification); the count of output triangles.
struct Tiling {
    std::vector<FullTriangle> all;
    std::vector<KeyedSquare> keyed;
    std::int64_t nout = 0;
    bool drop = false;
    // The fan rule's centroid fans: centre k is point npoints + k of the
    // triangles (after every lattice point), at fan_pos[k], of square fan_square[k].
    std::int64_t npoints = 0;
    std::vector<Vec2> fan_pos;
    std::vector<std::int64_t> fan_square;

    void add(std::int64_t a, std::int64_t b, std::int64_t c, double area2, int m, bool warped, bool border) {
        const bool out = !(drop && m == 0);
        all.push_back({{a, b, c}, area2, static_cast<std::uint16_t>(m), out, warped, border});
        nout += out;
    }
};

// Whether the square or leaf of width w at (i, j) touches the lattice border.
bool touches_border(const Lattice& lattice, std::int64_t i, std::int64_t j, std::int64_t w) {
    return i == 0 || j == 0 || i + w == lattice.nx || j + w == lattice.ny;
}

// The finest leaves' triangles, in canonical order, as mesh_materials makes
// a lattice square's; counts r.warped_squares, .forced_diagonals,
// .mixed_triangles, .centroid_triangles.
void tile_finest(const Leaves& leaves, const Lattice& lattice, const MaterialFront& front, const MaterialField& field,
                 DiagonalRule rule, Tiling& tiling, MaterialResult& r) {
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx;
    const double s2 = lattice.s * lattice.s;
    const Buffer<std::uint16_t>& mat = front.mat;
    const Buffer<std::uint8_t>& moved = front.moved;
    for_each_finest(leaves, [&](std::int64_t i, std::int64_t j) {
        const std::int64_t pa = lattice.index(i, j);
        const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
        const bool border = touches_border(lattice, i, j, 1);
        if (!(moved[static_cast<std::size_t>(p[0])] | moved[static_cast<std::size_t>(p[1])] |
              moved[static_cast<std::size_t>(p[2])] | moved[static_cast<std::size_t>(p[3])])) {
            // No corner moved, so no side is cut: one material, the diagonal
            // of the union-jack pattern (generic_square.hpp).
            const int m = mat[static_cast<std::size_t>(pa)];
            const std::uint8_t diagonal = union_jack(i, j) == TieBreak::bc ? square_code::bc_bit : 0;
            for (int k = 0; k < 2; ++k) {
                const auto tri = triangle_of(diagonal, k);
                tiling.add(p[static_cast<std::size_t>(tri[0])], p[static_cast<std::size_t>(tri[1])], p[static_cast<std::size_t>(tri[2])],
                           s2, m, false, border);
            }
            return;
        }
        ++r.warped_squares;
        const WarpedSquare w = warped_square(front, lattice, field, rule, p, i, j);
        const std::uint8_t c = w.code;
        r.forced_diagonals += w.forced;
        r.mixed_triangles += w.mixed, r.centroid_triangles += w.by_centroid;
        const std::int64_t first = tiling.nout;
        if (c & fan_bit) {  // the centroid fan, one material (as mesh_materials)
            std::array<Vec2, 4> x{};
            for (std::size_t q = 0; q < 4; ++q) x[q] = front.position(lattice, p[q], i + static_cast<std::int64_t>(q & 1), j + static_cast<std::int64_t>(q >> 1));
            const Vec2 mc = fan_centre_position(x);
            const std::int64_t centre = tiling.npoints + static_cast<std::int64_t>(tiling.fan_pos.size());
            tiling.fan_pos.push_back(mc);
            tiling.fan_square.push_back(i + j * nx);
            for (const auto& tri : fan_triangles) {
                const Vec2 a = x[static_cast<std::size_t>(tri[0])], b = x[static_cast<std::size_t>(tri[1])];
                tiling.add(p[static_cast<std::size_t>(tri[0])], p[static_cast<std::size_t>(tri[1])], centre,
                           (b.x - a.x) * (mc.y - a.y) - (b.y - a.y) * (mc.x - a.x), w.material[0], true, border);
            }
            if (tiling.nout > first) tiling.keyed.push_back({i + j * nx, first, static_cast<std::int32_t>(tiling.nout - first)});
            return;
        }
        for (int k = 0; k < 2; ++k) {
            const auto tri = triangle_of(c, k);
            tiling.add(p[static_cast<std::size_t>(tri[0])], p[static_cast<std::size_t>(tri[1])], p[static_cast<std::size_t>(tri[2])],
                       w.area2[static_cast<std::size_t>(k)], w.material[static_cast<std::size_t>(k)], true, border);
        }
        if (tiling.nout > first) tiling.keyed.push_back({i + j * nx, first, static_cast<std::int32_t>(tiling.nout - first)});
    });
}

// The coarse leaves' triangles, by the graded templates, all of the leaf's
// material.
void tile_coarse(const Leaves& leaves, const Lattice& lattice, const MaterialFront& front, Tiling& tiling) {
    const double s2 = lattice.s * lattice.s;
    for (const Leaf& leaf : leaves.coarse) {
        const int m = front.mat[static_cast<std::size_t>(lattice.index(leaf.i, leaf.j))];
        std::array<std::array<std::int64_t, 2>, 8> ij{};
        std::array<std::int64_t, 2> mid{};
        const int n = coarse_ring(leaf, ij, mid);
        std::array<std::int64_t, 8> ring{};
        for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) ring[k] = lattice.index(ij[k][0], ij[k][1]);
        const std::int64_t w = std::int64_t{1} << leaf.level;
        const bool border = touches_border(lattice, leaf.i, leaf.j, w);
        // Twice the area of the lattice triangle (u, v, q), from the indices (exact integers, times s^2).
        const auto area2 = [&](const std::array<std::int64_t, 2>& u, const std::array<std::int64_t, 2>& v, const std::array<std::int64_t, 2>& q) {
            return static_cast<double>((v[0] - u[0]) * (q[1] - u[1]) - (v[1] - u[1]) * (q[0] - u[0])) * s2;
        };
        if (!leaf.split_sides) {  // ring = A, B, D, C; the diagonal of coarse_tie_break
            for (const auto& t : coarse_diagonal_ring[coarse_tie_break(leaf) == TieBreak::bc]) {
                const auto a = static_cast<std::size_t>(t[0]), b = static_cast<std::size_t>(t[1]), d = static_cast<std::size_t>(t[2]);
                tiling.add(ring[a], ring[b], ring[d], area2(ij[a], ij[b], ij[d]), m, false, border);
            }
            continue;
        }
        const std::int64_t centre = lattice.index(mid[0], mid[1]);
        for (int k = 0; k < n; ++k) {
            const std::size_t k0 = static_cast<std::size_t>(k), k1 = static_cast<std::size_t>((k + 1) % n);
            tiling.add(centre, ring[k0], ring[k1], area2(mid, ij[k0], ij[k1]), m, false, border);
        }
    }
}

// The vertices: the points of output triangles, in lattice-point order, then
// the fans' centres by square (the uniform mesher's order), into
// mesh.vertices.  Returns each point's vertex id (written at those points
// only, read only there).
Buffer<std::int32_t> place_vertices(const Lattice& lattice, const MaterialFront& front, const Tiling& tiling, Mesh& mesh) {
    const std::int64_t nxp = lattice.points_x();
    const std::size_t npoints = static_cast<std::size_t>(lattice.point_count()), nfans = tiling.fan_pos.size();
    std::vector<std::uint8_t> used(npoints + nfans, 0);
    for (const FullTriangle& ft : tiling.all)
        if (ft.out)
            for (const std::int64_t q : ft.p) used[static_cast<std::size_t>(q)] = 1;
    Buffer<std::int32_t> vid(npoints + nfans);
    for (std::int64_t j = 0, q = 0; j <= lattice.ny; ++j)
        for (std::int64_t i = 0; i < nxp; ++i, ++q)
            if (used[static_cast<std::size_t>(q)]) {
                if (mesh.vertices.size() == static_cast<std::size_t>(INT32_MAX))
                    throw std::length_error("mesh too large for 32-bit vertex indices");
                vid[static_cast<std::size_t>(q)] = static_cast<std::int32_t>(mesh.vertices.size());
                mesh.vertices.push_back(front.position(lattice, q, i, j));
            }
    std::vector<std::size_t> order(nfans);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tiling.fan_square[a] < tiling.fan_square[b]; });
    for (const std::size_t k : order)
        if (used[npoints + k]) {
            if (mesh.vertices.size() == static_cast<std::size_t>(INT32_MAX)) throw std::length_error("mesh too large for 32-bit vertex indices");
            vid[npoints + k] = static_cast<std::int32_t>(mesh.vertices.size());
            mesh.vertices.push_back(tiling.fan_pos[k]);
        }
    return vid;
}

// The output triangles and their region tags (tag[m] of material m), into
// mesh; per material, the count and twice the area of its triangles of the
// full tiling, added to count and area2.
void emit_triangles(const Tiling& tiling, const Buffer<std::int32_t>& vid, std::span<const std::int32_t> tag,
                    std::span<std::int64_t> count, std::span<double> area2, Mesh& mesh) {
    mesh.triangles.resize(static_cast<std::size_t>(tiling.nout));
    mesh.region.resize(static_cast<std::size_t>(tiling.nout));
    const auto id = [&](std::int64_t q) { return vid[static_cast<std::size_t>(q)]; };
    std::size_t next = 0;
    for (const FullTriangle& ft : tiling.all) {
        ++count[ft.m];
        area2[ft.m] += ft.area2;
        if (!ft.out) continue;
        mesh.triangles[next] = {id(ft.p[0]), id(ft.p[1]), id(ft.p[2])};
        mesh.region[next++] = tag[ft.m];
    }
}

// The border edges, then the warped squares' half-edges paired (head
// comment: Edges): interfaces and level-set boundary edges into mesh, each
// edge's length added to perim of the materials it bounds.  std::logic_error
// for an edge of more than two triangles.
void material_edges(const Lattice& lattice, const MaterialFront& front, std::span<const FullTriangle> all,
                    const Buffer<std::int32_t>& vid, std::span<const std::int32_t> tag, std::span<double> perim, Mesh& mesh) {
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx;
    const auto id = [&](std::int64_t q) { return vid[static_cast<std::size_t>(q)]; };
    const std::int64_t npoints = lattice.point_count();
    const auto on_border = [&](std::int64_t a, std::int64_t b) {
        if (a >= npoints || b >= npoints) return false;  // a fan's centre
        const std::int64_t ia = a % nxp, ja = a / nxp, ib = b % nxp, jb = b / nxp;
        return (ia == ib && (ia == 0 || ia == nx)) || (ja == jb && (ja == 0 || ja == lattice.ny));
    };
    const auto length = [&](std::int64_t a, std::int64_t b) {
        const Vec2 x = front.position(lattice, a), y = front.position(lattice, b);
        return std::hypot(y.x - x.x, y.y - x.y);
    };
    std::vector<HalfEdge> half;
    for (std::size_t t = 0; t < all.size(); ++t) {
        const FullTriangle& ft = all[t];
        for (int k = 0; k < 3; ++k) {
            const std::int64_t a = ft.p[static_cast<std::size_t>(k)], b = ft.p[static_cast<std::size_t>((k + 1) % 3)];
            if (ft.border && on_border(a, b)) {
                perim[ft.m] += length(a, b);
                if (ft.out) {
                    mesh.boundary.push_back({id(a), id(b)});
                    mesh.boundary_tag.push_back(boundary_domain);
                }
            } else if (ft.warped) {
                half.push_back({std::min(a, b), std::max(a, b), static_cast<std::int32_t>(t), static_cast<std::int8_t>(k)});
            }
        }
    }
    std::sort(half.begin(), half.end());
    const auto ends = [&](const HalfEdge& h) {
        const FullTriangle& ft = all[static_cast<std::size_t>(h.tri)];
        return std::array<std::int64_t, 2>{ft.p[static_cast<std::size_t>(h.k)], ft.p[static_cast<std::size_t>((h.k + 1) % 3)]};
    };
    for (std::size_t k = 0; k < half.size();) {
        const HalfEdge& h1 = half[k];
        const bool twin = k + 1 < half.size() && half[k + 1].lo == h1.lo && half[k + 1].hi == h1.hi;
        if (!twin) {  // its twin is in a plain square or a coarse leaf: one material
            k += 1;
            continue;
        }
        if (k + 2 < half.size() && half[k + 2].lo == h1.lo && half[k + 2].hi == h1.hi)
            throw std::logic_error("graded multi-material mesh: an edge of more than two triangles");
        const HalfEdge& h2 = half[k + 1];
        k += 2;
        const FullTriangle &t1 = all[static_cast<std::size_t>(h1.tri)], &t2 = all[static_cast<std::size_t>(h2.tri)];
        if (t1.m == t2.m) continue;  // then both output or both not
        const double len = length(h1.lo, h1.hi);
        perim[t1.m] += len;
        perim[t2.m] += len;
        const auto e1 = ends(h1), e2 = ends(h2);
        if (t1.out && t2.out) {
            mesh.interfaces.push_back({id(e1[0]), id(e1[1])});
            mesh.interface_regions.push_back({tag[t1.m], tag[t2.m]});
        } else if (t1.out) {
            mesh.boundary.push_back({id(e1[0]), id(e1[1])});
            mesh.boundary_tag.push_back(boundary_level_set);
        } else if (t2.out) {
            mesh.boundary.push_back({id(e2[0]), id(e2[1])});
            mesh.boundary_tag.push_back(boundary_level_set);
        }
    }
}

}  // namespace

MaterialResult mesh_materials_graded(const MaterialField& field, const Lattice& lattice, const MaterialOptions& options,
                                     std::int64_t max_cell, int grading_buffer, std::span<const std::int64_t> max_cell_of) {
    check_material_options(field, options);
    const int nmat = field.count();
    const bool drop = !options.keep_background;
    const MaterialCodes codes = material_codes(nmat, drop, max_cell, max_cell_of);
    MaterialResult r;
    r.graded = true;
    const MaterialFront front = material_front(field, lattice, r);
    const Leaves leaves = material_leaves(lattice, front, codes, max_cell, grading_buffer, options.keys.check_invariant, r);

    // ---- triangles of the leaves --------------------------------------------------
    const auto t0 = clock::now();
    Tiling tiling;
    tiling.drop = drop;
    tiling.npoints = lattice.point_count();
    tiling.all.reserve(static_cast<std::size_t>(2 * leaves.finest + 6 * static_cast<std::int64_t>(leaves.coarse.size())));
    tile_finest(leaves, lattice, front, field, options.rule, tiling, r);
    tile_coarse(leaves, lattice, front, tiling);
    if (tiling.all.size() > static_cast<std::size_t>(INT32_MAX)) throw std::length_error("mesh too large for 32-bit triangle indices");

    Mesh& mesh = r.mesh;
    const Buffer<std::int32_t> vid = place_vertices(lattice, front, tiling, mesh);
    std::vector<std::int32_t> tag(static_cast<std::size_t>(nmat));
    for (int m = 0; m < nmat; ++m) tag[static_cast<std::size_t>(m)] = field.tag(m);
    std::vector<std::int64_t> count(static_cast<std::size_t>(nmat), 0);
    std::vector<double> area2(static_cast<std::size_t>(nmat), 0.0), perim(static_cast<std::size_t>(nmat), 0.0);
    emit_triangles(tiling, vid, tag, count, area2, mesh);
    material_edges(lattice, front, tiling.all, vid, tag, perim, mesh);
    r.times.triangulate = seconds_since(t0);
    finish_materials(r, field, drop, count, area2, perim);

    if (options.keys.keys) record_material_keys(r, lattice, front, std::move(tiling.keyed), field);
    return r;
}

}  // namespace warpmesh
