// resolution.cpp — is the lattice fine enough (resolution.hpp): in 2D the
// boundary loops and their widths 4A/P, in 3D the closed boundary
// components and their widths 6V/A.
//
// 3D.  A closed boundary component (faces tagged boundary_level_set, joined
// by shared vertices) of area A enclosing the volume V has the width 6V/A (a
// sphere's diameter, twice a slab's thickness); it is resolved when that is
// at least 4 lattice spacings.  Parts smaller than a cube vanish and leave
// no component: the level set's feature_size() (when known) must be at least
// 2 spacings too.  Otherwise a warning names a spacing that resolves the
// input — never below the input's own resolution (a volume's voxel), and
// none at all at a spacing at or below it (as in 2D).
#include "warpmesh/post/resolution.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "warpmesh/mesh3d/generic_bcc.hpp"  // bcc::Vec, cross, dot

namespace warpmesh {
namespace {

// x rounded down to two significant digits.
double two_digits(double x) {
    const double e = std::pow(10.0, std::floor(std::log10(x)) - 1);
    return std::floor(x / e) * e;
}

constexpr double min_cubes_across = 4;

std::size_t find(std::vector<std::int32_t>& parent, std::size_t x) {
    while (static_cast<std::size_t>(parent[x]) != x) x = static_cast<std::size_t>(parent[x] = parent[static_cast<std::size_t>(parent[x])]);
    return x;
}

// The narrowest closed boundary component's width 6V/A (0 without one).
double narrowest_width(const TetMesh& m) {
    std::vector<std::int32_t> parent(m.vertices.size());
    std::iota(parent.begin(), parent.end(), 0);
    for (std::size_t i = 0; i < m.boundary.size(); ++i) {
        if (m.boundary_tag[i] != boundary_level_set) continue;
        const auto& b = m.boundary[i];
        for (int k = 1; k < 3; ++k) parent[find(parent, static_cast<std::size_t>(b[static_cast<std::size_t>(k)]))] = static_cast<std::int32_t>(find(parent, static_cast<std::size_t>(b[0])));
    }
    std::vector<double> area(m.vertices.size(), 0), volume(m.vertices.size(), 0);
    for (std::size_t i = 0; i < m.boundary.size(); ++i) {
        if (m.boundary_tag[i] != boundary_level_set) continue;
        const auto& b = m.boundary[i];
        const Point3 &p = m.vertices[static_cast<std::size_t>(b[0])], &q = m.vertices[static_cast<std::size_t>(b[1])], &r = m.vertices[static_cast<std::size_t>(b[2])];
        const bcc::Vec<double> a{p.x, p.y, p.z}, u{q.x - p.x, q.y - p.y, q.z - p.z}, v{r.x - p.x, r.y - p.y, r.z - p.z};
        const bcc::Vec<double> n = bcc::cross(u, v);
        const std::size_t c = find(parent, static_cast<std::size_t>(b[0]));
        area[c] += 0.5 * std::sqrt(bcc::dot(n, n));
        volume[c] += bcc::dot(a, bcc::cross(bcc::Vec<double>{q.x, q.y, q.z}, bcc::Vec<double>{r.x, r.y, r.z})) / 6;
    }
    double narrowest = 0;
    for (std::size_t c = 0; c < area.size(); ++c)
        if (area[c] > 0) {
            const double w = 6 * std::abs(volume[c]) / area[c];
            narrowest = narrowest == 0 ? w : std::min(narrowest, w);
        }
    return narrowest;
}

}  // namespace


ResolutionCheck check_resolution(const Mesh& mesh, double spacing, double finest, double min_squares) {
    ResolutionCheck r;
    const bool refinable = spacing > finest;
    // Outgoing boundary edges per vertex; a pinch vertex has several, and the
    // walk takes any unused one (the loop's area and length are sums over its
    // edges, so how loops touching at a pinch are split matters little).
    std::unordered_multimap<std::int32_t, std::size_t> out;
    out.reserve(mesh.boundary.size());
    for (std::size_t e = 0; e < mesh.boundary.size(); ++e) out.emplace(mesh.boundary[e][0], e);
    std::vector<char> used(mesh.boundary.size(), 0);
    double narrowest = std::numeric_limits<double>::infinity();
    for (std::size_t start = 0; start < mesh.boundary.size(); ++start) {
        if (used[start]) continue;
        double twice_area = 0, length = 0;
        std::size_t e = start;
        for (;;) {
            used[e] = 1;
            const Vec2 a = mesh.vertices[static_cast<std::size_t>(mesh.boundary[e][0])];
            const Vec2 b = mesh.vertices[static_cast<std::size_t>(mesh.boundary[e][1])];
            twice_area += a.x * b.y - a.y * b.x;
            length += std::hypot(b.x - a.x, b.y - a.y);
            std::size_t next = e;
            const auto [lo, hi] = out.equal_range(mesh.boundary[e][1]);
            for (auto it = lo; it != hi; ++it)
                if (!used[it->second]) next = it->second;
            if (next == e) break;  // back at the start (or an open chain: malformed input)
            e = next;
        }
        if (!(length > 0)) continue;
        ++r.loops;
        const double width = 2 * std::abs(twice_area) / length;  // 4A/P
        narrowest = std::min(narrowest, width);
        if (refinable && width < min_squares * spacing) ++r.unresolved;
    }
    r.narrowest = r.loops ? narrowest : 0;
    if (r.unresolved) {
        r.suggested_spacing = std::max(finest, two_digits(narrowest / min_squares));
    }
    return r;
}

ResolutionCheck3 check_resolution3(const TetMesh& mesh, const LevelSet3& f, double s) {
    return check_resolution3(mesh, f.feature_size(), f.resolution(), s);
}

ResolutionCheck3 check_resolution3(const TetMesh& mesh, double feature, double finest, double s) {
    ResolutionCheck3 r;
    r.narrowest_width = narrowest_width(mesh);
    double want = 0;
    if (r.narrowest_width > 0 && r.narrowest_width < min_cubes_across * s) want = r.narrowest_width / min_cubes_across;
    if (feature > 0 && feature < 2 * s) want = want > 0 ? std::min(want, feature / 2) : feature / 2;
    if (want <= 0 || s <= finest) return r;
    r.suggested_spacing = std::max(two_digits(want), finest);
    std::ostringstream w;
    w << "--spacing " << s << " is too coarse for this input: its narrowest part is about "
      << (r.narrowest_width > 0 ? r.narrowest_width : 2 * feature) << " across (resolved at " << min_cubes_across
      << " cubes across); ";
    // A part narrower than the input's own resolution (a voxel) is resolved
    // only as far as the voxels resolve it: say so rather than promise it.
    if (two_digits(want) < finest)
        w << "that is below the input's resolution, " << finest << " (its voxel size): --spacing " << r.suggested_spacing
          << ", the finest that means anything for it, resolves what the voxels resolve";
    else
        w << "--spacing " << r.suggested_spacing << " resolves it";
    r.warning = w.str();
    return r;
}

}  // namespace warpmesh
