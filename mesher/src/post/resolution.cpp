// resolution.cpp — boundary loops and their widths (resolution.hpp).
#include "warpmesh/post/resolution.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

namespace warpmesh {

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
        const double s = narrowest / min_squares;
        const double unit = std::pow(10.0, std::floor(std::log10(s)) - 1);
        r.suggested_spacing = std::max(finest, std::floor(s / unit) * unit);
    }
    return r;
}

}  // namespace warpmesh
