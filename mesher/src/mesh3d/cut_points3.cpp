// cut_points3.cpp — stage 3: the cut lattice edges (endpoints of strictly
// opposite signs, step 2 of generic_bcc.hpp's contract) and their cut
// points, a zero of f found by the level set's cut_parameter (the bracketed
// root finder to convergence unless the level set knows better).  Each edge
// is stored once, at its lower endpoint (uniform3d.hpp: forward slots), with
// its parameter u from that endpoint.  Two passes over the z planes (count,
// then fill) so the order does not depend on the threads.
#include <algorithm>
#include <stdexcept>

#include "uniform3d.hpp"

namespace warpmesh::uniform3d {

Point3 Window::cut_position(const bcc::Ivec& lower, int slot, double u) const {
    const bcc::Ivec upper = bcc::add(lower, bcc::neighbour_offsets[static_cast<std::size_t>(forward_direction[static_cast<std::size_t>(slot)])]);
    const Point3 a = lattice_position(lower), b = lattice_position(upper);
    return {a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), a.z + u * (b.z - a.z)};
}

namespace {

bcc::Ivec forward_neighbour(const bcc::Ivec& p, int slot) {
    return bcc::add(p, bcc::neighbour_offsets[static_cast<std::size_t>(forward_direction[static_cast<std::size_t>(slot)])]);
}

// The forward neighbours of the points of one row (r) of plane z as index
// steps, the same all along the row: point r·w + c of the plane (w its row
// width) has neighbour `slot` at its index + step[slot] when the row allows
// it (row_ok) and 0 <= c + dc[slot] < width[slot].  A neighbour is in the
// window iff Grid::contains says so: +x, +y and +z stay in the point's kind
// (corners or centres) with the same row width; a short edge (±1, ±1, +1)
// goes from corner (c, r) to the centres c − 1 or c, r − 1 or r of plane
// z + 1, and from a centre to the corners c or c + 1, r or r + 1.
struct RowSteps {
    std::array<std::int64_t, 7> step{}, width{};
    std::array<int, 7> dc{};
    std::array<bool, 7> row_ok{};
    bool exists(int s, std::int64_t c) const {
        const std::size_t k = static_cast<std::size_t>(s);
        return row_ok[k] && c + dc[k] >= 0 && c + dc[k] < width[k];
    }
};

RowSteps row_steps(const Grid& g, int z, std::int64_t r) {
    const bool centres = ((g.lo[2] + z) & 1) != 0;
    const std::int64_t w = centres ? g.centre_w : g.corner_w, h = centres ? g.centre_h : g.corner_h;
    const std::int64_t wn = centres ? g.corner_w : g.centre_w, hn = centres ? g.corner_h : g.centre_h;  // plane z + 1
    const int planes = g.hi[2] - g.lo[2] + 1;
    const auto start = [&](int k) { return g.plane_start[static_cast<std::size_t>(k)]; };
    const std::int64_t row = start(z) + r * w;  // the row's first point
    RowSteps rs;
    rs.step[0] = 1, rs.dc[0] = 1, rs.width[0] = w, rs.row_ok[0] = true;
    rs.step[1] = w, rs.width[1] = w, rs.row_ok[1] = r + 1 < h;
    rs.row_ok[2] = z + 2 < planes, rs.width[2] = w;
    if (rs.row_ok[2]) rs.step[2] = start(z + 2) - start(z);
    for (std::size_t s = 3; s < 7; ++s) {
        const bcc::Ivec& d = bcc::neighbour_offsets[static_cast<std::size_t>(forward_direction[s])];
        const int dc = centres ? (d[0] + 1) / 2 : (d[0] - 1) / 2, dr = centres ? (d[1] + 1) / 2 : (d[1] - 1) / 2;
        rs.row_ok[s] = z + 1 < planes && r + dr >= 0 && r + dr < hn;
        if (rs.row_ok[s]) rs.step[s] = start(z + 1) + (r + dr) * wn + dc - row;
        rs.dc[s] = dc, rs.width[s] = wn;
    }
    return rs;
}

// Pass 1 of find_cuts on plane z: each point's mask of cut forward edges
// (differs(p, q): endpoints of strictly opposite signs, or of different
// materials); returns their number.
template <class Differs>
std::int64_t mark_cut_edges(const Grid& g, int z, Window& w, const Differs& differs) {
    const bool centres = ((g.lo[2] + z) & 1) != 0;
    const std::int64_t width = centres ? g.centre_w : g.corner_w, rows = centres ? g.centre_h : g.corner_h;
    std::int64_t count = 0;
    for (std::int64_t r = 0; r < rows; ++r) {
        const RowSteps rs = row_steps(g, z, r);
        const std::int64_t row = g.plane_start[static_cast<std::size_t>(z)] + r * width;
        // The columns [c_lo, c_hi) where every neighbour exists (none if the row lacks one).
        std::int64_t c_lo = 0, c_hi = width;
        for (std::size_t s = 0; s < 7; ++s) c_lo = std::max<std::int64_t>(c_lo, -rs.dc[s]), c_hi = std::min(c_hi, rs.width[s] - rs.dc[s]);
        if (!std::all_of(rs.row_ok.begin(), rs.row_ok.end(), [](bool ok) { return ok; })) c_hi = c_lo;
        for (std::int64_t c = 0; c < width; ++c) {
            const std::int64_t p = row + c;
            const bool all = c >= c_lo && c < c_hi;
            unsigned mask = 0;
            for (int s = 0; s < 7; ++s)
                if ((all || rs.exists(s, c)) && differs(p, p + rs.step[static_cast<std::size_t>(s)])) mask |= 1u << s;
            w.cut_mask[static_cast<std::size_t>(p)] = static_cast<std::uint8_t>(mask);
            count += slot_count(mask);
        }
    }
    return count;
}

// Both passes of find_cuts: the masks (differs), then each cut edge's
// parameter from its lower endpoint (cut(p, q, lower position, upper position)).
template <class Differs, class Cut>
void find_cuts_by(Window& w, const Differs& differs, const Cut& cut) {
    const Grid& g = w.grid;
    const std::size_t n = static_cast<std::size_t>(g.count());
    const int planes = g.hi[2] - g.lo[2] + 1;
    w.cut_mask.resize(n);
    w.cut_first.resize(n);
    std::vector<std::int64_t> per_plane(static_cast<std::size_t>(planes) + 1, 0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        per_plane[static_cast<std::size_t>(z) + 1] = mark_cut_edges(g, z, w, differs);
    }
    for (int z = 0; z < planes; ++z) per_plane[static_cast<std::size_t>(z) + 1] += per_plane[static_cast<std::size_t>(z)];
    if (per_plane.back() >= std::int64_t{UINT32_MAX}) throw std::length_error("more than 2^32 cut edges in one window");
    w.cut_u.resize(static_cast<std::size_t>(per_plane.back()));
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        std::int64_t at = per_plane[static_cast<std::size_t>(z)];
        for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
            const unsigned mask = w.cut_mask[static_cast<std::size_t>(p)];
            w.cut_first[static_cast<std::size_t>(p)] = mask ? static_cast<std::uint32_t>(at) : 0;
            if (!mask) continue;
            const bcc::Ivec pq = g.point_in_plane(z, p);
            for (int s = 0; s < 7; ++s) {
                if (!(mask >> s & 1u)) continue;
                const bcc::Ivec q = forward_neighbour(pq, s);
                w.cut_u[static_cast<std::size_t>(at++)] = cut(p, g.index(q), g.lattice.position(pq), g.lattice.position(q));
            }
        }
    }
}

}  // namespace

void find_cuts(const LevelSet3& f, Window& w) {
    find_cuts_by(
        w, [&](std::int64_t p, std::int64_t q) { return w.sign[static_cast<std::size_t>(p)] * w.sign[static_cast<std::size_t>(q)] < 0; },
        [&](std::int64_t p, std::int64_t q, Point3 a, Point3 b) {
            return f.cut_parameter(a, b, w.value[static_cast<std::size_t>(p)], w.value[static_cast<std::size_t>(q)]);
        });
}

void find_material_cuts(const MaterialField3& field, std::span<const std::uint16_t> material, bool merge_outside, Window& w) {
    const auto field_material = [&](std::int64_t p) {
        const int m = material[static_cast<std::size_t>(p)];
        return m == outside_code ? outside_material : m;
    };
    find_cuts_by(
        w,
        [&](std::int64_t p, std::int64_t q) {
            const std::uint16_t a = material[static_cast<std::size_t>(p)], b = material[static_cast<std::size_t>(q)];
            return a != b && !(merge_outside && (a == 0 || a == outside_code) && (b == 0 || b == outside_code));
        },
        [&](std::int64_t p, std::int64_t q, Point3 a, Point3 b) { return field.cut_parameter(a, b, field_material(p), field_material(q)); });
}

}  // namespace warpmesh::uniform3d
