// keys.cpp — the keys of the BCC generic tetrahedron: consistency rules,
// symmetries, canonical forms, enumeration, parameters (proofs/README.md,
// "The BCC space").
#include <algorithm>
#include <cmath>

#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
namespace {

// The local vertex reached from vertex i along direction w, or -1.
int target(int i, int w) {
    if (w == bcc::stay) return -1;
    const bcc::Ivec q = bcc::add(bcc::reference_tet[static_cast<std::size_t>(i)], bcc::neighbour_offsets[static_cast<std::size_t>(w)]);
    for (int j = 0; j < 4; ++j)
        if (bcc::reference_tet[static_cast<std::size_t>(j)] == q) return j;
    return -1;
}

bcc::Ivec apply(const std::array<bcc::Ivec, 3>& col, const bcc::Ivec& v) {
    bcc::Ivec r{};
    for (std::size_t k = 0; k < 3; ++k) r[k] = col[0][k] * v[0] + col[1][k] * v[1] + col[2][k] * v[2];
    return r;
}

std::array<Symmetry, 8> make_symmetries() {
    std::array<Symmetry, 8> out{};
    int n = 0;
    std::array<int, 4> p{0, 1, 2, 3};
    do {
        const bool pairs = (p[0] / 2 == p[1] / 2) && (p[2] / 2 == p[3] / 2);
        if (!pairs) continue;
        // The linear part maps the reference edge vectors to their images:
        // (2,0,0) = k1 - k0, (1,1,-1) = c0 - k0, (1,1,1) = c1 - k0.
        const auto& r = bcc::reference_tet;
        const auto img = [&](int i, int j) { return bcc::sub(r[static_cast<std::size_t>(p[static_cast<std::size_t>(j)])], r[static_cast<std::size_t>(p[static_cast<std::size_t>(i)])]); };
        const bcc::Ivec a = img(0, 1), b = img(0, 2), c = img(0, 3);
        Symmetry s{p, {}};
        for (std::size_t k = 0; k < 3; ++k) {
            s.lin[0][k] = a[k] / 2;
            s.lin[1][k] = (b[k] + c[k] - a[k]) / 2;
            s.lin[2][k] = (c[k] - b[k]) / 2;
        }
        out[static_cast<std::size_t>(n++)] = s;
    } while (std::next_permutation(p.begin(), p.end()));
    return out;
}

std::array<int, 9> encode(const Key& k) {
    return {k.sign[0], k.warp[0], k.sign[1], k.warp[1], k.sign[2], k.warp[2], k.sign[3], k.warp[3], k.parity};
}

}  // namespace

const std::array<Symmetry, 8>& symmetries() {
    static const std::array<Symmetry, 8> s = make_symmetries();
    return s;
}

bool has_parity_quad(const std::array<int, 4>& sign) {
    int pos = 0;
    for (int s : sign) pos += s > 0;
    if (pos == 0) return false;
    for (int e = 0; e < 2; ++e) {
        const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
        if (sign[static_cast<std::size_t>(ed[0])] < 0 && sign[static_cast<std::size_t>(ed[1])] < 0) return true;
    }
    return false;
}

bool consistent(const Key& k) {
    if (k.parity != 0 && !has_parity_quad(k.sign)) return false;
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[static_cast<std::size_t>(i)];
        if (k.sign[static_cast<std::size_t>(i)] != 0 && w != bcc::stay) return false;
        const int j = target(i, w);
        if (j < 0) continue;
        if (target(j, k.warp[static_cast<std::size_t>(j)]) == i) return false;  // towards each other
        if (k.sign[static_cast<std::size_t>(j)] == 0 && k.warp[static_cast<std::size_t>(j)] == bcc::stay) return false;
    }
    return true;
}

Key transform(const Key& k, const Symmetry& s) {
    Key out;
    for (int i = 0; i < 4; ++i) {
        const auto j = static_cast<std::size_t>(s.perm[static_cast<std::size_t>(i)]);
        out.sign[j] = k.sign[static_cast<std::size_t>(i)];
        const int w = k.warp[static_cast<std::size_t>(i)];
        out.warp[j] = w == bcc::stay ? bcc::stay : bcc::direction_of(apply(s.lin, bcc::neighbour_offsets[static_cast<std::size_t>(w)]));
    }
    // The parity bit: the decision on a long-edge face maps to the decision on
    // its image (the same for every face: tests/test_bcc_keys.cpp).
    const auto P = [&](int i) { return s.perm[static_cast<std::size_t>(i)]; };
    const bool before = bcc::face_takes_a(0, 1, 2, k.parity);
    out.parity = bcc::face_takes_a(P(0), P(1), P(2), 0) == before ? 0 : 1;
    if (!has_parity_quad(out.sign)) out.parity = 0;
    return out;
}

Key canonical(const Key& k) {
    Key best = k;
    if (!has_parity_quad(best.sign)) best.parity = 0;
    for (const Symmetry& s : symmetries()) {
        const Key t = transform(k, s);
        if (encode(t) < encode(best)) best = t;
    }
    return best;
}

std::string code_of(const Key& k) {
    std::string s;
    for (int i = 0; i < 4; ++i) {
        if (i) s += ',';
        const int v = k.sign[static_cast<std::size_t>(i)];
        if (v < 0) s += '-';
        else if (v > 0) s += '+';
        else {
            s += '0';
            const int w = k.warp[static_cast<std::size_t>(i)];
            s += w == bcc::stay ? 's' : static_cast<char>('a' + w);
        }
    }
    s += '/';
    s += static_cast<char>('0' + k.parity);
    return s;
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
                        if (encode(canonical(k)) != encode(k)) continue;
                        out.push_back(k);
                    }
    return out;
}

namespace {
double dyadic_floor(double x) { return std::floor(std::ldexp(x, 20)) / 1048576.0; }
double dyadic_ceil(double x) { return std::ceil(std::ldexp(x, 20)) / 1048576.0; }
}  // namespace

// Root boxes: x = num/den rounded to nearest is within 2^-53 relative of the
// exact value, far below 2^-20, so flooring/ceiling x·2^20 with a margin of
// one unit is safe: lo = floor(x·2^20 − 1)/2^20 <= exact, hi likewise.
std::vector<Param> key_params(const Key& k, const bcc::Alphas& al) {
    const double along = static_cast<double>(al.long_num) / static_cast<double>(al.long_den);
    const double ashort = static_cast<double>(al.short_num) / static_cast<double>(al.short_den);
    std::vector<Param> out;
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[static_cast<std::size_t>(i)];
        if (k.sign[static_cast<std::size_t>(i)] == 0 && w != bcc::stay) {
            const double a = bcc::is_long_direction(w) ? along : ashort;
            out.push_back({i, 0.0, a, 0.0, dyadic_ceil(a + 0x1p-20)});
        }
    }
    for (int e = 0; e < 6; ++e) {
        const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
        if (k.sign[static_cast<std::size_t>(ed[0])] * k.sign[static_cast<std::size_t>(ed[1])] < 0) {
            const double a = bcc::edge_is_long(e) ? along : ashort;
            out.push_back({4 + e, a, 1 - a, dyadic_floor(a - 0x1p-20), dyadic_ceil(1 - a + 0x1p-20)});
        }
    }
    return out;
}

}  // namespace warpmesh::bcc_prover
