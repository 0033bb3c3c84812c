// keys.cpp — the keys of the BCC generic tetrahedron: consistency rules,
// enumeration, parameters (proofs/README.md, "The BCC space").  Symmetries
// and canonical forms are generic_bcc_keys.hpp's.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
int warp_target(int i, int w) {
    if (w == bcc::stay) return -1;
    const bcc::Ivec q = bcc::add(bcc::reference_tet[static_cast<std::size_t>(i)], bcc::neighbour_offsets[static_cast<std::size_t>(w)]);
    for (int j = 0; j < 4; ++j)
        if (bcc::reference_tet[static_cast<std::size_t>(j)] == q) return j;
    return -1;
}

bool consistent(const Key& k) {
    if (k.parity != 0 && !has_parity_quad(k.sign)) return false;
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[static_cast<std::size_t>(i)];
        if (k.sign[static_cast<std::size_t>(i)] != 0 && w != bcc::stay) return false;
        const int j = warp_target(i, w);
        if (j < 0) continue;
        if (warp_target(j, k.warp[static_cast<std::size_t>(j)]) == i) return false;  // towards each other
        if (k.sign[static_cast<std::size_t>(j)] == 0 && k.warp[static_cast<std::size_t>(j)] == bcc::stay) return false;
    }
    return true;
}

std::vector<Key> enumerate_keys(bool all_zero) {
    std::vector<Key> out;
    // per vertex: 0 '-', 1 '+', 2 + w zero with warp w (0..14)
    std::array<int, 4> st{};
    for (st[0] = 0; st[0] < 17; ++st[0])
        for (st[1] = 0; st[1] < 17; ++st[1])
            for (st[2] = 0; st[2] < 17; ++st[2])
                for (st[3] = 0; st[3] < 17; ++st[3])
                    for (int parity = 0; parity < 2; ++parity) {
                        Key k;
                        int neg = 0, zero = 0;
                        for (std::size_t i = 0; i < 4; ++i) {
                            k.sign[i] = st[i] == 0 ? -1 : st[i] == 1 ? 1 : 0;
                            k.warp[i] = st[i] >= 2 ? st[i] - 2 : bcc::stay;
                            neg += k.sign[i] < 0;
                            zero += k.sign[i] == 0;
                        }
                        k.parity = parity;
                        if ((all_zero ? zero != 4 : neg == 0) || !consistent(k)) continue;
                        if (bcc::encode(canonical(k)) != bcc::encode(k)) continue;
                        out.push_back(k);
                    }
    return out;
}

std::optional<Key> key_with_code(const std::string& code) {
    for (const Key& k : enumerate_keys())
        if (code_of(k) == code) return k;
    return std::nullopt;
}

namespace {
double dyadic_floor(double x) { return std::floor(std::ldexp(x, 20)) / 1048576.0; }
double dyadic_ceil(double x) { return std::ceil(std::ldexp(x, 20)) / 1048576.0; }
}  // namespace

// Root boxes: x = num/den rounded to nearest is within 2^-53 relative of the
// exact value, far below 2^-20, so flooring/ceiling x·2^20 with a margin of
// one unit is safe: lo = floor(x·2^20 − 1)/2^20 <= exact, hi likewise.
Param warp_param(int i, int w, const bcc::Alphas& al) {
    const double a = bcc::is_long_direction(w) ? static_cast<double>(al.long_num) / static_cast<double>(al.long_den)
                                               : static_cast<double>(al.short_num) / static_cast<double>(al.short_den);
    return {i, 0.0, a, 0.0, dyadic_ceil(a + 0x1p-20)};
}
Param cut_param(int e, const bcc::Alphas& al) {
    const double a = bcc::edge_is_long(e) ? static_cast<double>(al.long_num) / static_cast<double>(al.long_den)
                                          : static_cast<double>(al.short_num) / static_cast<double>(al.short_den);
    return {4 + e, a, 1 - a, dyadic_floor(a - 0x1p-20), dyadic_ceil(1 - a + 0x1p-20)};
}

std::vector<Param> key_params(const Key& k, const bcc::Alphas& al) {
    std::vector<Param> out;
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[static_cast<std::size_t>(i)];
        if (k.sign[static_cast<std::size_t>(i)] == 0 && w != bcc::stay) out.push_back(warp_param(i, w, al));
    }
    for (int e = 0; e < 6; ++e) {
        const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
        if (k.sign[static_cast<std::size_t>(ed[0])] * k.sign[static_cast<std::size_t>(ed[1])] < 0) out.push_back(cut_param(e, al));
    }
    return out;
}

bool parse_alpha(const std::string& s, std::int64_t& num) {
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0' || !(x > 0 && x < 0.5)) return false;
    num = std::llround(x * 100000);
    return std::fabs(static_cast<double>(num) - x * 100000) < 1e-6;
}

}  // namespace warpmesh::bcc_prover
