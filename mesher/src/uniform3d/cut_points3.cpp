// cut_points3.cpp — stage 3: the cut lattice edges (endpoints of strictly
// opposite signs, step 2 of generic_bcc.hpp's contract) and their cut
// points, a zero of f found by the level set's cut_parameter (the bracketed
// root finder to convergence unless the level set knows better).  Each edge
// is stored once, at its lower endpoint (uniform3d.hpp: forward slots), with
// its parameter u from that endpoint.  Two passes over the z planes (count,
// then fill) so the order does not depend on the threads.
#include <stdexcept>

#include "uniform3d.hpp"

namespace warpmesh::uniform3d {

Point3 Window::cut_position(const bcc::Ivec& lower, int slot, double u) const {
    const bcc::Ivec upper = bcc::add(lower, bcc::neighbour_offsets[static_cast<std::size_t>(forward_direction[static_cast<std::size_t>(slot)])]);
    const Point3 a = lattice_position(lower), b = lattice_position(upper);
    return {a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), a.z + u * (b.z - a.z)};
}

namespace {

// Calls visit(point index, point) for each point of plane z.
template <class Visit>
void plane_points(const Grid& g, int z, Visit&& visit) {
    const int zz = g.lo[2] + z, odd = zz & 1;
    std::int64_t at = g.plane_start[static_cast<std::size_t>(z)];
    for (int y = g.lo[1] + odd; y <= g.hi[1] - odd; y += 2)
        for (int x = g.lo[0] + odd; x <= g.hi[0] - odd; x += 2, ++at) visit(at, bcc::Ivec{x, y, zz});
}

bcc::Ivec forward_neighbour(const bcc::Ivec& p, int slot) {
    return bcc::add(p, bcc::neighbour_offsets[static_cast<std::size_t>(forward_direction[static_cast<std::size_t>(slot)])]);
}

}  // namespace

void find_cuts(const LevelSet3& f, Window& w) {
    const Grid& g = w.grid;
    const std::size_t n = static_cast<std::size_t>(g.count());
    const int planes = g.hi[2] - g.lo[2] + 1;
    w.cut_mask.resize(n);
    w.cut_first.resize(n);
    std::vector<std::int64_t> per_plane(static_cast<std::size_t>(planes) + 1, 0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        const std::int64_t first = g.plane_start[static_cast<std::size_t>(z)], end = g.plane_start[static_cast<std::size_t>(z) + 1];
        for (std::int64_t p = first; p < end; ++p) w.cut_mask[static_cast<std::size_t>(p)] = 0;
        std::int64_t count = 0;
        plane_points(g, z, [&](std::int64_t p, const bcc::Ivec& pq) {
            for (int s = 0; s < 7; ++s) {
                const bcc::Ivec q = forward_neighbour(pq, s);
                if (g.contains(q) && w.sign[static_cast<std::size_t>(p)] * w.sign[static_cast<std::size_t>(g.index(q))] < 0) {
                    w.cut_mask[static_cast<std::size_t>(p)] |= static_cast<std::uint8_t>(1u << s);
                    ++count;
                }
            }
        });
        per_plane[static_cast<std::size_t>(z) + 1] = count;
    }
    for (int z = 0; z < planes; ++z) per_plane[static_cast<std::size_t>(z) + 1] += per_plane[static_cast<std::size_t>(z)];
    if (per_plane.back() >= std::int64_t{UINT32_MAX}) throw std::length_error("more than 2^32 cut edges in one window");
    w.cut_u.resize(static_cast<std::size_t>(per_plane.back()));
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        std::int64_t at = per_plane[static_cast<std::size_t>(z)];
        plane_points(g, z, [&](std::int64_t p, const bcc::Ivec& pq) {
            const unsigned mask = w.cut_mask[static_cast<std::size_t>(p)];
            w.cut_first[static_cast<std::size_t>(p)] = mask ? static_cast<std::uint32_t>(at) : 0;
            for (int s = 0; s < 7; ++s) {
                if (!(mask >> s & 1u)) continue;
                const bcc::Ivec q = forward_neighbour(pq, s);
                w.cut_u[static_cast<std::size_t>(at++)] =
                    f.cut_parameter(g.lattice.position(pq), g.lattice.position(q), w.value[static_cast<std::size_t>(p)],
                                    w.value[static_cast<std::size_t>(g.index(q))]);
            }
        });
    }
}

}  // namespace warpmesh::uniform3d
