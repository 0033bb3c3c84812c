// flatness.cpp — is a 12-point stencil's sign pattern that of an affine function?
//
// Exact test: unknowns (a, b, c), constraints g_k = a x_k + b y_k + c with
// g_k = 0 where the sign is 0 and sign_k g_k >= 1 where it is not (the system
// is homogeneous, so strict signs scale to >= 1), one per constrained point.
// The four corners are always constrained and are not collinear, so the
// feasible polyhedron is pointed: if it is non-empty it has a vertex, where
// three linearly independent constraints are tight.  We solve every 3x3 system
// of constraints made tight (Cramer, integers) and test the solution against
// all constraints with exact integer arithmetic (the solution is
// (Da, Db, Dc) / det; multiply through by det).
// Full patterns (the mesher's question) are cached in a 3^12 table (atomic, so
// the OpenMP loops may share it).
//
// This is the one copy on the untrusted side: the prover asks it through
// stencil_admits_flat for its flat-compatible keys.  The independent checker
// (checker/checker.cpp) has its own copy of the same idea, on purpose.
#include <atomic>
#include <cstdlib>
#include <stdexcept>

#include "warpmesh/mesh2d/square_keys.hpp"

namespace warpmesh {

namespace {

bool decide(const std::array<std::int8_t, 12>& s, std::uint16_t known) {
    std::array<std::array<std::int64_t, 3>, 12> row{};
    std::array<std::int64_t, 12> rhs{};
    for (int k = 0; k < 12; ++k) {
        const std::int64_t x = stencil_offsets[static_cast<std::size_t>(k)][0],
                           y = stencil_offsets[static_cast<std::size_t>(k)][1];
        const std::int64_t sg = s[static_cast<std::size_t>(k)];
        // Constraint: sg * g_k >= 1 (sg != 0) or g_k = 0; tight form: row . (a,b,c) = rhs.
        const std::int64_t m = sg == 0 ? 1 : sg;
        row[static_cast<std::size_t>(k)] = {m * x, m * y, m};
        rhs[static_cast<std::size_t>(k)] = sg == 0 ? 0 : 1;
    }
    auto det3 = [](const std::array<std::int64_t, 3>& r0, const std::array<std::int64_t, 3>& r1,
                   const std::array<std::int64_t, 3>& r2) {
        return r0[0] * (r1[1] * r2[2] - r1[2] * r2[1]) - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0]) +
               r0[2] * (r1[0] * r2[1] - r1[1] * r2[0]);
    };
    auto on = [&](int k) { return (known >> k) & 1; };
    for (int p = 0; p < 12; ++p)
        for (int q = p + 1; q < 12; ++q)
            for (int r = q + 1; r < 12; ++r) {
                if (!on(p) || !on(q) || !on(r)) continue;
                const auto &r0 = row[static_cast<std::size_t>(p)], &r1 = row[static_cast<std::size_t>(q)],
                           &r2 = row[static_cast<std::size_t>(r)];
                const std::int64_t det = det3(r0, r1, r2);
                if (det == 0) continue;
                std::array<std::int64_t, 3> sol{};
                for (int v = 0; v < 3; ++v) {
                    auto c0 = r0, c1 = r1, c2 = r2;
                    c0[static_cast<std::size_t>(v)] = rhs[static_cast<std::size_t>(p)];
                    c1[static_cast<std::size_t>(v)] = rhs[static_cast<std::size_t>(q)];
                    c2[static_cast<std::size_t>(v)] = rhs[static_cast<std::size_t>(r)];
                    sol[static_cast<std::size_t>(v)] = det3(c0, c1, c2);  // value = sol / det
                }
                const std::int64_t sd = det > 0 ? 1 : -1;
                bool ok = true;
                for (int k = 0; k < 12 && ok; ++k) {
                    if (!on(k)) continue;
                    const auto& rk = row[static_cast<std::size_t>(k)];
                    // (rk . sol) / det  vs  rhs_k: compare rk.sol * sd with rhs_k * |det|
                    const std::int64_t lhs = (rk[0] * sol[0] + rk[1] * sol[1] + rk[2] * sol[2]) * sd;
                    const std::int64_t rr = rhs[static_cast<std::size_t>(k)] * std::llabs(det);
                    ok = s[static_cast<std::size_t>(k)] == 0 ? lhs == 0 : lhs >= rr;
                }
                if (ok) return true;
            }
    return false;
}

constexpr std::uint16_t all_points = 0xfff, corners = 0xf;
constexpr int table_size = 531441;  // 3^12
std::atomic<std::uint8_t> cache[table_size];  // 0 unknown, 1 flat, 2 not flat

}  // namespace

bool stencil_is_flat(const std::array<std::int8_t, 12>& s) {
    int code = 0;
    for (int k = 11; k >= 0; --k) code = code * 3 + (s[static_cast<std::size_t>(k)] + 1);
    const std::uint8_t c = cache[code].load(std::memory_order_relaxed);
    if (c) return c == 1;
    const bool flat = decide(s, all_points);
    cache[code].store(flat ? 1 : 2, std::memory_order_relaxed);
    return flat;
}

bool stencil_admits_flat(const std::array<std::int8_t, 12>& s, std::uint16_t known) {
    if ((known & corners) != corners || (known & ~all_points) != 0)
        throw std::invalid_argument("stencil_admits_flat: the four corners must be constrained");
    return known == all_points ? stencil_is_flat(s) : decide(s, known);
}

}  // namespace warpmesh
