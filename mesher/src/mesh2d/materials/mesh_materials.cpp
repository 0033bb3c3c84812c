// mesh_materials.cpp — the multi-material uniform mesher (materials.hpp):
// materials per point → cut edges → warp → triangulate [→ the keys the
// certification reads].
//
// The triangulation is four passes, each parallel over rows and deterministic
// (as triangulate.cpp, whose square codes and side tables it shares):
//   1. per square: its diagonal, its two triangles' materials, which of them
//      are output (all but the dropped background's), per-material counts and
//      areas of the full tiling;
//   2. per point, whether an output triangle uses it → compact vertex ids;
//   3. the triangles and their region tags (and the keyed squares);
//   4. per square, its right and top sides and its diagonal (the left and
//      bottom sides on the lattice border): an edge between two output
//      triangles of different materials is an interface, an edge of exactly
//      one output triangle a boundary edge; every edge between different
//      materials adds its length to both materials' perimeters.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "mesh2d/gather_keys.hpp"
#include "mesh2d/square_code.hpp"
#include "warpmesh/core/errors.hpp"
#include "mesh2d/materials/material_front.hpp"
#include "warpmesh/mesh2d/materials.hpp"

namespace warpmesh {
namespace {

using clock = std::chrono::steady_clock;
using namespace square_code;  // tri0_bit, tri1_bit, bc_bit, rule_bit, triangle_of, uses_corner, sides

int thread_id() {
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}
int thread_count() {
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

}  // namespace

// The rule on a square's material corners, in the generic frame (the same
// choose_diagonal the prover certifies; generic_square.hpp).
[[gnu::flatten]] SquareSplit material_split(DiagonalRule rule, const std::array<MaterialCorner, 4>& cs,
                                            const std::array<double, 4>& t, bool& forced, TieBreak tie) {
    std::array<Warp, 4> w{};
    for (std::size_t k = 0; k < 4; ++k) w[k] = cs[k].warp;
    const Choice ch = choose_diagonal(rule, generic_positions(w, t), cs, tie);
    Diagonal d{};
    forced = false;
    if (separating_diagonal(cs, d)) forced = choose_diagonal(DiagonalRule::maxmin, generic_positions(w, t), cs, tie).bc != ch.bc;
    return ch.fan ? SquareSplit::fan : ch.bc ? SquareSplit::bc : SquareSplit::ad;
}

// The tie rule of materials.hpp, step 3: which endpoint of the cut edge from
// p = (i, j) to q = p + x (axis 0) or p + y (axis 1) moves when its cut point
// is exactly midway (u = 1/2).  It reads the materials only through "equal"
// and "is the background", never through their numbers, so renumbering the
// labels does not change it:
//   1. the background against another material: the other one moves (label
//      mode's rule, the inside point moves; for one label this is label mode);
//   2. else the endpoint with more lattice 4-neighbours of its own material
//      (deeper inside it) moves, so that the thinner side keeps its point —
//      a one-pixel label keeps its lattice point and its triangles;
//   3. else the lower end p (the edge's -x or -y end) moves.
// True when p moves.
static bool tie_mover_is_lower(const Buffer<std::uint16_t>& mat, std::int64_t nxp, std::int64_t ny, std::int64_t i, std::int64_t j,
                        int axis) {
    const std::int64_t qi = i + (axis == 0), qj = j + (axis == 1);
    const int mp = mat[static_cast<std::size_t>(i + j * nxp)], mq = mat[static_cast<std::size_t>(qi + qj * nxp)];
    if ((mp == 0) != (mq == 0)) return mq == 0;
    const auto own_neighbours = [&](std::int64_t a, std::int64_t b, int m) {
        int n = 0;
        if (a > 0) n += mat[static_cast<std::size_t>(a - 1 + b * nxp)] == m;
        if (a + 1 < nxp) n += mat[static_cast<std::size_t>(a + 1 + b * nxp)] == m;
        if (b > 0) n += mat[static_cast<std::size_t>(a + (b - 1) * nxp)] == m;
        if (b < ny) n += mat[static_cast<std::size_t>(a + (b + 1) * nxp)] == m;
        return n;
    };
    return own_neighbours(i, j, mp) >= own_neighbours(qi, qj, mq);
}

void check_material_options(const MaterialField& field, const MaterialOptions& options) {
    if (options.rule == DiagonalRule::maxmin)
        throw InputError("--diagonal maxmin cannot mesh several materials: it can join two unwarped corners of different "
                         "materials by its diagonal, leaving a triangle with no single material; use the fan rule (the "
                         "default) or the separating rule");
    const int nmat = field.count();
    if (nmat < 1 || nmat > 65536) throw InputError("between 1 and 65536 materials are needed, not " + std::to_string(nmat));
}

MaterialFront material_front(const MaterialField& field, const Lattice& lattice, MaterialResult& r) {
    PhaseTimes& times = r.times;
    MaterialFront front;
    const std::int64_t nxp = lattice.points_x(), ny = lattice.ny;
    const std::size_t npoints = static_cast<std::size_t>(lattice.point_count());
    front.nxp = nxp;

    // ---- 1. materials per point --------------------------------------------------
    auto t0 = clock::now();
    front.mat = Buffer<std::uint16_t>(npoints);  // every element written by sample_block
    Buffer<std::uint16_t>& mat = front.mat;
    field.sample_block(lattice, {0, 0, nxp, ny + 1}, mat);
    times.sample = seconds_since(t0);

    // ---- 2. cut edges --------------------------------------------------------------
    // sign: -1 when p is the edge's mover at a tie, u = 1/2 (tie_mover_is_lower).
    t0 = clock::now();
    std::vector<std::vector<CutEdge>> per_row(static_cast<std::size_t>(ny + 1));
    std::int64_t third = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(+ : third)
    for (std::int64_t j = 0; j <= ny; ++j) {
        auto& out = per_row[static_cast<std::size_t>(j)];
        const std::uint16_t* row = mat.data() + j * nxp;
        const std::uint16_t* up = j < ny ? row + nxp : nullptr;
        for (std::int64_t i = 0; i < nxp; ++i) {
            const int mp = row[i];
            for (int axis = 0; axis < 2; ++axis) {
                if (axis == 0 ? i + 1 >= nxp : !up) continue;
                const int mq = axis == 0 ? row[i + 1] : up[i];
                if (mq == mp) continue;
                const Vec2 a = lattice.position(i, j), b = lattice.position(i + (axis == 0), j + (axis == 1));
                const double u = field.cut_parameter(a, b, mp, mq);
                const bool p_moves = u == 0.5 && tie_mover_is_lower(mat, nxp, ny, i, j, axis);  // (u != 1/2: unused)
                out.push_back({lattice.index(i, j), static_cast<std::int8_t>(axis), static_cast<std::int8_t>(p_moves ? -1 : 1), u});
                const int mc = field.material_at(a.x + u * (b.x - a.x), a.y + u * (b.y - a.y));
                third += mc != mp && mc != mq;
            }
        }
    }
    std::vector<CutEdge> cuts;
    {
        std::size_t total = 0;
        for (const auto& v : per_row) total += v.size();
        cuts.reserve(total);
        for (auto& v : per_row) cuts.insert(cuts.end(), v.begin(), v.end()), std::vector<CutEdge>().swap(v);
    }
    front.cut_edges = static_cast<std::int64_t>(cuts.size());
    front.third_material_edges = third;
    times.cut_points = seconds_since(t0);

    // ---- 3. warp --------------------------------------------------------------------
    t0 = clock::now();
    front.warped = warp_points(lattice, cuts);
    const std::vector<WarpedPoint>& warped = front.warped;
    std::vector<CutEdge>().swap(cuts);
    front.moved = Buffer<std::uint8_t>(npoints);
    Buffer<std::uint8_t>& moved = front.moved;
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(npoints); ++k) moved[static_cast<std::size_t>(k)] = 0;
    for (const WarpedPoint& w : warped) moved[static_cast<std::size_t>(w.p)] = 1;
    times.warp = seconds_since(t0);
    r.cut_edges = front.cut_edges;
    r.third_material_edges = front.third_material_edges;
    r.warped_points = static_cast<std::int64_t>(front.warped.size());
    return front;
}

void finish_materials(MaterialResult& r, const MaterialField& field, bool drop, std::span<const std::int64_t> triangles,
                      std::span<const double> area2, std::span<const double> perimeter) {
    const int nmat = field.count();
    r.materials.resize(static_cast<std::size_t>(nmat));
    for (int m = 0; m < nmat; ++m) {
        const std::size_t k = static_cast<std::size_t>(m);
        MaterialStats& st = r.materials[k];
        st.tag = field.tag(m);
        st.name = field.name(m);
        st.output = !(drop && m == 0);
        st.reference_area = field.reference_area(m);
        st.triangles = triangles[k];
        st.area = 0.5 * area2[k];
        st.perimeter = perimeter[k];
        if (st.output && st.triangles > 0) r.mesh.region_names.emplace_back(st.tag, st.name);
    }
}

void measure_longest_edges(MaterialResult& r) {
    const Mesh& m = r.mesh;
    std::int32_t top = 0;  // region tags are material tags, 0 .. 65535
    for (const std::int32_t t : m.region) top = std::max(top, t);
    std::vector<double> longest2(static_cast<std::size_t>(top) + 1, 0.0);  // squared, per region tag
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        double& l2 = longest2[static_cast<std::size_t>(m.region[t])];
        for (int k = 0; k < 3; ++k) {
            const Vec2 a = m.vertices[static_cast<std::size_t>(m.triangles[t][k])];
            const Vec2 b = m.vertices[static_cast<std::size_t>(m.triangles[t][(k + 1) % 3])];
            l2 = std::max(l2, (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
        }
    }
    for (MaterialStats& s : r.materials)
        s.longest_edge = s.output && s.tag >= 0 && s.tag <= top ? std::sqrt(longest2[static_cast<std::size_t>(s.tag)]) : 0.0;
}

void record_material_keys(MaterialResult& r, const Lattice& lattice, const MaterialFront& front, std::vector<KeyedSquare> keyed,
                          const MaterialField& field) {
    const auto t0 = clock::now();
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx, ny = lattice.ny;
    const Buffer<std::uint16_t>& mat = front.mat;
    const Buffer<std::uint8_t>& moved = front.moved;
    // A square with one or two materials: the material of its first staying
    // corner (A, B, C, D; none stays: A's) is '-', every other point of the
    // stencil '+' (materials.hpp: why this is a key of the proof; the choice
    // reads no material number, and under the fan rule '-' is the staying
    // corners' common material, so "all inside" is the fan's condition).
    // A junction square (3 or 4 materials): its corners' material classes,
    // for its junction key.
    const auto stencil = [&](std::int64_t i, std::int64_t j, std::array<std::int8_t, 12>& st) {
        const std::int64_t pa = lattice.index(i, j);
        const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
        const std::array<std::uint16_t, 4> m{mat[static_cast<std::size_t>(p[0])], mat[static_cast<std::size_t>(p[1])],
                                             mat[static_cast<std::size_t>(p[2])], mat[static_cast<std::size_t>(p[3])]};
        std::uint16_t inside = m[0];
        for (std::size_t q = 4; q-- > 0;)
            if (!moved[static_cast<std::size_t>(p[q])]) inside = m[q];
        const std::uint16_t other = m[0] != inside ? m[0] : m[1] != inside ? m[1] : m[2] != inside ? m[2] : m[3];
        for (const std::uint16_t v : m)
            if (v != inside && v != other) {
                const auto letters = junction_letters({MaterialCorner{m[0], Warp::stay}, MaterialCorner{m[1], Warp::stay},
                                                       MaterialCorner{m[2], Warp::stay}, MaterialCorner{m[3], Warp::stay}});
                for (std::size_t q = 0; q < 4; ++q) st[q] = static_cast<std::int8_t>(letters[q].material);
                return true;
            }
        for (std::size_t q = 0; q < 12; ++q) {
            const std::int64_t x = i + stencil_offsets[q][0], y = j + stencil_offsets[q][1];
            st[q] = (x < 0 || y < 0 || x > nx || y > ny) ? off_lattice
                    : mat[static_cast<std::size_t>(lattice.index(x, y))] == inside ? std::int8_t{-1} : std::int8_t{1};
        }
        return false;
    };
    r.keys = gather_keys(lattice, std::move(keyed), front.warped, LatticeMetric::square, stencil);
    // The junction squares: their count, and the first 20 by square index
    // with their corners' tags and their junction keys.
    std::vector<std::int64_t> junctions;
    for (std::size_t k = 0; k < r.keys.squares.size(); ++k)
        if (r.keys.stencils[k].junction) junctions.push_back(r.keys.squares[k].square);
    r.junction_squares = static_cast<std::int64_t>(junctions.size());
    std::sort(junctions.begin(), junctions.end());
    if (junctions.size() > 20) junctions.resize(20);
    for (const std::int64_t sq : junctions) {
        JunctionSquare js{sq % nx, sq / nx, {}, {}, {}};
        const std::int64_t pa = lattice.index(js.i, js.j);
        const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
        std::array<MaterialCorner, 4> mc{};
        for (std::size_t q = 0; q < 4; ++q) {
            const std::uint16_t m = mat[static_cast<std::size_t>(p[q])];
            js.tags[q] = field.tag(m);
            mc[q] = {m, moved[static_cast<std::size_t>(p[q])] ? front.warp_of(p[q]).dir : Warp::stay};
        }
        js.key = junction_letters(mc);
        js.pattern = junction_key_code(js.key);
        r.junction_examples.push_back(std::move(js));
    }
    r.keys.seconds = seconds_since(t0);
}

namespace {

// Pass 1's results (head comment): per square its code (diagonal, rule bit;
// bit k: its triangle k is output) and its two triangles' materials; per
// row the output triangles, prefix-summed (row_tris[j]: row j's first
// triangle, row_tris[ny]: all); per thread, per material the triangles and
// twice their area over the full tiling.
struct SquarePass {
    Buffer<std::uint8_t> code;
    Buffer<std::array<std::uint16_t, 2>> tmat;  // materials of triangles 0, 1 (a fan: its material twice)
    std::vector<std::int64_t> row_tris;
    std::vector<std::int64_t> row_fans;         // output fans (their centres), prefix-summed as row_tris
    std::vector<std::vector<std::int64_t>> tri_count;
    std::vector<std::vector<double>> area2;
};

// Pass 1 over nthreads threads; also sets r.warped_squares,
// .forced_diagonals, .mixed_triangles, .centroid_triangles.
SquarePass classify_squares(const MaterialField& field, const Lattice& lattice, const MaterialFront& front,
                            const MaterialOptions& options, int nthreads, MaterialResult& r) {
    const int nmat = field.count();
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx, ny = lattice.ny;
    const Buffer<std::uint16_t>& mat = front.mat;
    const Buffer<std::uint8_t>& moved = front.moved;
    const bool drop = !options.keep_background;
    SquarePass pass{Buffer<std::uint8_t>(static_cast<std::size_t>(nx * ny)),
                    Buffer<std::array<std::uint16_t, 2>>(static_cast<std::size_t>(nx * ny)),
                    std::vector<std::int64_t>(static_cast<std::size_t>(ny) + 1, 0),
                    std::vector<std::int64_t>(static_cast<std::size_t>(ny) + 1, 0),
                    std::vector<std::vector<std::int64_t>>(static_cast<std::size_t>(nthreads), std::vector<std::int64_t>(static_cast<std::size_t>(nmat), 0)),
                    std::vector<std::vector<double>>(static_cast<std::size_t>(nthreads), std::vector<double>(static_cast<std::size_t>(nmat), 0.0))};
    Buffer<std::uint8_t>& code = pass.code;
    Buffer<std::array<std::uint16_t, 2>>& tmat = pass.tmat;
    std::vector<std::int64_t>& row_tris = pass.row_tris;
    std::int64_t warped_squares = 0, forced = 0, mixed = 0, centroid = 0;
    const double s2 = lattice.s * lattice.s;
#pragma omp parallel for schedule(dynamic, 8) reduction(+ : warped_squares, forced, mixed, centroid)
    for (std::int64_t j = 0; j < ny; ++j) {
        auto& count = pass.tri_count[static_cast<std::size_t>(thread_id())];
        auto& area = pass.area2[static_cast<std::size_t>(thread_id())];
        std::int64_t tris = 0, fans = 0;
        for (std::int64_t i = 0; i < nx; ++i) {
            const std::int64_t pa = lattice.index(i, j);
            const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
            const std::size_t sq = static_cast<std::size_t>(i + j * nx);
            std::uint8_t c = 0;
            std::array<std::uint16_t, 2> tm{};
            if (!(moved[static_cast<std::size_t>(p[0])] | moved[static_cast<std::size_t>(p[1])] |
                  moved[static_cast<std::size_t>(p[2])] | moved[static_cast<std::size_t>(p[3])])) {
                // No corner moved, so no side is cut: one material, the
                // diagonal of the union-jack pattern (generic_square.hpp).
                if (union_jack(i, j) == TieBreak::bc) c = square_code::bc_bit;
                const std::uint16_t m = mat[static_cast<std::size_t>(pa)];
                tm = {m, m};
                count[m] += 2;
                area[m] += 2 * s2;  // twice the areas of both halves
            } else {
                ++warped_squares;
                const WarpedSquare w = warped_square(front, lattice, field, options.rule, p, i, j);
                c = w.code;
                forced += w.forced, mixed += w.mixed, centroid += w.by_centroid;
                for (std::size_t k = 0; k < 2; ++k) {
                    const auto m = static_cast<std::size_t>(w.material[k]);
                    tm[k] = static_cast<std::uint16_t>(m);
                    count[m] += (c & fan_bit) ? 2 : 1;  // a fan: four triangles
                    area[m] += w.area2[k];
                }
            }
            for (int k = 0; k < 2; ++k)
                if (!drop || tm[static_cast<std::size_t>(k)] != 0) c |= static_cast<std::uint8_t>(1 << k), tris += (c & fan_bit) ? 2 : 1;
            fans += (c & fan_bit) && (c & tri0_bit);
            code[sq] = c;
            tmat[sq] = tm;
        }
        row_tris[static_cast<std::size_t>(j) + 1] = tris;
        pass.row_fans[static_cast<std::size_t>(j) + 1] = fans;
    }
    std::partial_sum(row_tris.begin(), row_tris.end(), row_tris.begin());
    std::partial_sum(pass.row_fans.begin(), pass.row_fans.end(), pass.row_fans.begin());
    r.warped_squares = warped_squares;
    r.forced_diagonals = forced;
    r.mixed_triangles = mixed;
    r.centroid_triangles = centroid;
    return pass;
}

// Pass 3: the triangles and their region tags (tag[m] of material m) at
// their rows' offsets, into mesh (its triangles sized by compact_vertices),
// the centroid fans' centres numbered from lattice_vertices on (as
// triangulate.cpp's); with want_keyed, per row the squares through the rule
// with their triangles.
std::vector<std::vector<KeyedSquare>> fill_triangles(const Lattice& lattice, const SquarePass& pass, const Buffer<std::int32_t>& vid,
                                                     std::int64_t lattice_vertices, std::span<const std::int32_t> tag, bool want_keyed,
                                                     Mesh& mesh) {
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx, ny = lattice.ny;
    const Buffer<std::uint8_t>& code = pass.code;
    std::vector<std::vector<KeyedSquare>> keyed_rows(want_keyed ? static_cast<std::size_t>(ny) : 0);
#pragma omp parallel for schedule(static)
    for (std::int64_t j = 0; j < ny; ++j) {
        std::int64_t next = pass.row_tris[static_cast<std::size_t>(j)];
        std::int64_t next_centre = lattice_vertices + pass.row_fans[static_cast<std::size_t>(j)];
        for (std::int64_t i = 0; i < nx; ++i) {
            const std::size_t sq = static_cast<std::size_t>(i + j * nx);
            const std::uint8_t c = code[sq];
            if (!(c & (tri0_bit | tri1_bit))) continue;
            const std::int64_t pa = lattice.index(i, j);
            const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
            if (c & fan_bit) {  // the centroid fan, one material
                if (want_keyed) keyed_rows[static_cast<std::size_t>(j)].push_back({static_cast<std::int64_t>(sq), next, 4});
                const auto m = static_cast<std::int32_t>(next_centre++);
                std::array<Vec2, 4> x{};
                for (std::size_t q = 0; q < 4; ++q) x[q] = mesh.vertices[static_cast<std::size_t>(vid[static_cast<std::size_t>(p[q])])];
                mesh.vertices[static_cast<std::size_t>(m)] = fan_centre_position(x);
                for (const auto& tri : fan_triangles) {
                    mesh.region[static_cast<std::size_t>(next)] = tag[pass.tmat[sq][0]];
                    mesh.triangles[static_cast<std::size_t>(next++)] = {vid[static_cast<std::size_t>(p[static_cast<std::size_t>(tri[0])])],
                                                                        vid[static_cast<std::size_t>(p[static_cast<std::size_t>(tri[1])])], m};
                }
                continue;
            }
            if (want_keyed && (c & rule_bit))
                keyed_rows[static_cast<std::size_t>(j)].push_back(
                    {static_cast<std::int64_t>(sq), next, static_cast<std::int32_t>((c & tri0_bit ? 1 : 0) + (c & tri1_bit ? 1 : 0))});
            for (int k = 0; k < 2; ++k) {
                if (!(c & (1 << k))) continue;
                const auto tri = triangle_of(c, k);
                mesh.region[static_cast<std::size_t>(next)] = tag[pass.tmat[sq][static_cast<std::size_t>(k)]];
                mesh.triangles[static_cast<std::size_t>(next++)] = {vid[static_cast<std::size_t>(p[tri[0]])],
                                                                    vid[static_cast<std::size_t>(p[tri[1]])],
                                                                    vid[static_cast<std::size_t>(p[tri[2]])]};
            }
        }
    }
    return keyed_rows;
}

// Pass 4: the boundary edges and interfaces, in square order, into mesh.
// Returns per thread (of nthreads), per material the length of its edges
// against other materials and the lattice border (its perimeter's parts).
std::vector<std::vector<double>> material_edges(const Lattice& lattice, const MaterialFront& front, const SquarePass& pass,
                                                const Buffer<std::int32_t>& vid, std::span<const std::int32_t> tag, int nthreads,
                                                Mesh& mesh) {
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx, ny = lattice.ny;
    const Buffer<std::uint8_t>& code = pass.code;
    const Buffer<std::array<std::uint16_t, 2>>& tmat = pass.tmat;
    const std::size_t nmat = tag.size();
    auto position = [&](std::int64_t p) { return front.position(lattice, p, p % nxp, p / nxp); };
    struct Edge {
        std::int32_t a, b;
        std::int32_t tag_or_left, right;  // boundary: tag, -1; interface: left, right region tags
    };
    std::vector<std::vector<Edge>> edge_rows(static_cast<std::size_t>(ny));
    std::vector<std::vector<double>> perim(static_cast<std::size_t>(nthreads), std::vector<double>(nmat, 0.0));
#pragma omp parallel for schedule(dynamic, 16)
    for (std::int64_t j = 0; j < ny; ++j) {
        auto& out = edge_rows[static_cast<std::size_t>(j)];
        auto& per = perim[static_cast<std::size_t>(thread_id())];
        for (std::int64_t i = 0; i < nx; ++i) {
            const std::size_t sq = static_cast<std::size_t>(i + j * nx);
            const std::uint8_t c = code[sq];
            const std::array<std::uint16_t, 2> tm = tmat[sq];
            const bool plain = !(c & rule_bit);
            // A plain square whose right and top neighbours are plain with its material has no edge to report.
            if (plain && i + 1 < nx && j + 1 < ny && !(code[sq + 1] & rule_bit) && !(code[sq + static_cast<std::size_t>(nx)] & rule_bit) &&
                tmat[sq + 1][0] == tm[0] && tmat[sq + static_cast<std::size_t>(nx)][0] == tm[0] && i > 0 && j > 0)
                continue;
            const std::int64_t pa = lattice.index(i, j);
            const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
            // The edge from corner `from` to `to` of this square, held by its triangle k (on the edge's left)
            // and by triangle k2 of square sq2 (on its right; sq2 < 0: the lattice border).
            auto edge = [&](int from, int to, int k, std::int64_t sq2, int k2) {
                const int m1 = tm[static_cast<std::size_t>(k)];
                const bool out1 = c & (1 << k);
                if (sq2 < 0) {
                    const Vec2 a = position(p[static_cast<std::size_t>(from)]), b = position(p[static_cast<std::size_t>(to)]);
                    per[static_cast<std::size_t>(m1)] += std::hypot(b.x - a.x, b.y - a.y);
                    if (out1) out.push_back({vid[static_cast<std::size_t>(p[static_cast<std::size_t>(from)])], vid[static_cast<std::size_t>(p[static_cast<std::size_t>(to)])], boundary_domain, -1});
                    return;
                }
                const int m2 = tmat[static_cast<std::size_t>(sq2)][static_cast<std::size_t>(k2)];
                const bool out2 = code[static_cast<std::size_t>(sq2)] & (1 << k2);
                if (m1 == m2 && out1 == out2) return;
                const std::int32_t va = vid[static_cast<std::size_t>(p[static_cast<std::size_t>(from)])], vb = vid[static_cast<std::size_t>(p[static_cast<std::size_t>(to)])];
                if (m1 != m2) {
                    const Vec2 a = position(p[static_cast<std::size_t>(from)]), b = position(p[static_cast<std::size_t>(to)]);
                    const double len = std::hypot(b.x - a.x, b.y - a.y);
                    per[static_cast<std::size_t>(m1)] += len;
                    per[static_cast<std::size_t>(m2)] += len;
                }
                if (out1 && out2) out.push_back({va, vb, tag[static_cast<std::size_t>(m1)], tag[static_cast<std::size_t>(m2)]});
                else if (out1) out.push_back({va, vb, boundary_level_set, -1});
                else if (out2) out.push_back({vb, va, boundary_level_set, -1});
            };
            const bool bc = c & bc_bit;
            const auto side_tri = [&](std::uint8_t code_, int sd) {
                const Side& s = sides[static_cast<std::size_t>(sd)];
                return (code_ & bc_bit) ? s.tri_bc : s.tri_ad;
            };
            // bottom (0) and left (3) only on the border; right (1) and top (2) always.
            if (j == 0) edge(sides[0].from, sides[0].to, side_tri(c, 0), -1, 0);
            if (i == 0) edge(sides[3].from, sides[3].to, side_tri(c, 3), -1, 0);
            if (i + 1 < nx) edge(sides[1].from, sides[1].to, side_tri(c, 1), static_cast<std::int64_t>(sq + 1), side_tri(code[sq + 1], 3));
            else edge(sides[1].from, sides[1].to, side_tri(c, 1), -1, 0);
            if (j + 1 < ny) edge(sides[2].from, sides[2].to, side_tri(c, 2), static_cast<std::int64_t>(sq) + nx, side_tri(code[sq + static_cast<std::size_t>(nx)], 0));
            else edge(sides[2].from, sides[2].to, side_tri(c, 2), -1, 0);
            // The diagonal, as it runs in triangle 0 (ABD: D→A, ABC: B→C), triangle 1 on its right
            // (a fan has no diagonal, and its edges to the centre join triangles of one material).
            if (!plain && !(c & fan_bit)) {
                if (bc) edge(B, C, 0, static_cast<std::int64_t>(sq), 1);
                else edge(D, A, 0, static_cast<std::int64_t>(sq), 1);
            }
        }
    }
    for (const auto& row : edge_rows)
        for (const Edge& e : row) {
            if (e.right < 0) {
                mesh.boundary.push_back({e.a, e.b});
                mesh.boundary_tag.push_back(e.tag_or_left);
            } else {
                mesh.interfaces.push_back({e.a, e.b});
                mesh.interface_regions.push_back({e.tag_or_left, e.right});
            }
        }
    return perim;
}

}  // namespace

MaterialResult mesh_materials(const MaterialField& field, const Lattice& lattice, const MaterialOptions& options) {
    check_material_options(field, options);
    const int nmat = field.count();
    MaterialResult r;
    const MaterialFront front = material_front(field, lattice, r);

    // ---- 4. triangulate ---------------------------------------------------------------
    const auto t0 = clock::now();
    const bool drop = !options.keep_background;
    const int nthreads = thread_count();
    const SquarePass pass = classify_squares(field, lattice, front, options, nthreads, r);

    // Pass 2: compact vertex ids (points used by an output triangle).
    Mesh& mesh = r.mesh;
    Buffer<std::int32_t> vid;
    const std::int64_t ntris = pass.row_tris.back();
    compact_vertices(
        lattice, pass.code, ntris, [](std::int64_t) { return true; },
        [&](std::int64_t p, std::int64_t i, std::int64_t j) { return front.position(lattice, p, i, j); }, vid, mesh);
    mesh.region.resize(static_cast<std::size_t>(ntris));

    std::vector<std::int32_t> tag(static_cast<std::size_t>(nmat));
    for (int m = 0; m < nmat; ++m) tag[static_cast<std::size_t>(m)] = field.tag(m);
    const auto lattice_vertices = static_cast<std::int64_t>(mesh.vertices.size());
    if (lattice_vertices + pass.row_fans.back() > INT32_MAX) throw std::length_error("mesh too large for 32-bit vertex indices");
    mesh.vertices.resize(static_cast<std::size_t>(lattice_vertices + pass.row_fans.back()));  // centres written in pass 3
    const std::vector<std::vector<KeyedSquare>> keyed_rows =
        fill_triangles(lattice, pass, vid, lattice_vertices, tag, options.keys.keys, mesh);
    const std::vector<std::vector<double>> perim = material_edges(lattice, front, pass, vid, tag, nthreads, mesh);
    r.times.triangulate = seconds_since(t0);

    // Per-material statistics and names.
    {
        std::vector<std::int64_t> count(static_cast<std::size_t>(nmat), 0);
        std::vector<double> area(static_cast<std::size_t>(nmat), 0.0), per(static_cast<std::size_t>(nmat), 0.0);
        for (int m = 0; m < nmat; ++m)
            for (int t = 0; t < nthreads; ++t) {
                count[static_cast<std::size_t>(m)] += pass.tri_count[static_cast<std::size_t>(t)][static_cast<std::size_t>(m)];
                area[static_cast<std::size_t>(m)] += pass.area2[static_cast<std::size_t>(t)][static_cast<std::size_t>(m)];
                per[static_cast<std::size_t>(m)] += perim[static_cast<std::size_t>(t)][static_cast<std::size_t>(m)];
            }
        finish_materials(r, field, drop, count, area, per);
    }

    // ---- 5. keys, for the certification ------------------------------------------------
    if (options.keys.keys) {
        std::vector<KeyedSquare> keyed;
        for (const auto& row : keyed_rows) keyed.insert(keyed.end(), row.begin(), row.end());
        record_material_keys(r, lattice, front, std::move(keyed), field);
    }
    return r;
}

}  // namespace warpmesh
