// keys.cpp — the configuration keys of the generic square: enumeration under
// the consistency rules, their variables, and flat compatibility.  See
// proofs/README.md ("Configuration space").  The key code and the flatness
// test are the mesher's (mesh2d/square_keys.hpp: key_code,
// stencil_admits_flat): one copy on the untrusted side; the independent
// checker has its own, on purpose.
#include "warpmesh/mesh2d/square_keys.hpp"
#include "warpmesh/prove.hpp"

namespace warpmesh::prover {
namespace {

CornerState state_of(int st) {
    if (st == 0) return {0, Warp::stay};
    return {static_cast<std::int8_t>(st <= 5 ? -1 : 1), static_cast<Warp>((st - 1) % 5)};
}

// Corner reached from corner c by the slide w, or -1 when the slide is outward.
int inward_target(int c, Warp w) {
    const int x = (c & 1) + warp_dx(w), y = (c >> 1) + warp_dy(w);
    if (w == Warp::stay || x < 0 || x > 1 || y < 0 || y > 1) return -1;
    return x + 2 * y;
}

bool consistent(const Key& k) {
    for (int c = 0; c < 4; ++c) {
        const CornerState s = k.s[c];
        if (s.sign == 0 && s.warp != Warp::stay) return false;  // zero corners stay
        if (s.warp == Warp::stay) continue;
        const int n = inward_target(c, s.warp);
        if (n >= 0) {
            if (k.s[n].sign != -s.sign) return false;             // slides only along a cut edge
            if (inward_target(n, k.s[n].warp) == c) return false;  // never towards each other
        }
    }
    // Every cut edge of the square has a warped endpoint.
    constexpr int edges[4][2] = {{A, B}, {B, D}, {D, C}, {C, A}};
    for (const auto& e : edges) {
        const CornerState a = k.s[e[0]], b = k.s[e[1]];
        if (a.sign != 0 && b.sign == -a.sign && a.warp == Warp::stay && b.warp == Warp::stay) return false;
    }
    return true;
}


// Stencil index (square_keys.hpp's stencil_offsets) of the lattice neighbour
// outside the square that corner c slides towards: 4 + 2c + axis (0 = x, 1 = y).
int outward_index(int c, Warp w) { return 4 + 2 * c + (warp_dy(w) != 0 ? 1 : 0); }

}  // namespace

std::vector<Key> consistent_keys() {
    std::vector<Key> out;
    for (int a = 0; a < 11; ++a)
        for (int b = 0; b < 11; ++b)
            for (int c = 0; c < 11; ++c)
                for (int d = 0; d < 11; ++d) {
                    Key k{{state_of(a), state_of(b), state_of(c), state_of(d)}};
                    if (consistent(k)) out.push_back(k);
                }
    return out;
}


// Some affine function has the key's corner signs and sign -s at the outside
// neighbour of every outward slide of a corner of sign s (proofs/README.md,
// "Flatness"); the other stencil points are free.
bool flat_compatible(const Key& k) {
    std::array<std::int8_t, 12> signs{};
    std::uint16_t known = 0;
    for (int c = 0; c < 4; ++c) {
        signs[static_cast<std::size_t>(c)] = k.s[c].sign;
        known = static_cast<std::uint16_t>(known | 1u << c);
        const Warp w = k.s[c].warp;
        if (w != Warp::stay && inward_target(c, w) < 0) {
            const int q = outward_index(c, w);
            signs[static_cast<std::size_t>(q)] = static_cast<std::int8_t>(-k.s[c].sign);
            known = static_cast<std::uint16_t>(known | 1u << q);
        }
    }
    return stencil_admits_flat(signs, known);
}

std::vector<int> key_vars(const Key& k) {
    std::vector<int> v;
    for (int c = 0; c < 4; ++c)
        if (k.s[c].warp != Warp::stay) v.push_back(c);
    return v;
}

}  // namespace warpmesh::prover
