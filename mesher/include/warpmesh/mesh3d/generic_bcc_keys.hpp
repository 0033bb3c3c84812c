// generic_bcc_keys.hpp — the keys of the BCC generic tetrahedron, written
// once: the local frame of a background tetrahedron, its symmetries, the
// canonical form of a configuration, and the key's code.  The 3D mesher
// computes with it the key of each background tetrahedron (to look up its
// certified bounds); the 3D prover enumerates and names its keys with it
// (prover/src/bcc/keys.cpp); the independent checker re-derives nothing of it
// (it reads codes only).  proofs/README.md, "The BCC space".
//
// THE LOCAL FRAME.  A background tetrahedron p = (k0, k1, c0, c1) in local
// order (generic_bcc.hpp, `background_tet`) is L(reference_tet) + k0 for one
// lattice isometry with linear part L, a signed permutation matrix of
// determinant +1: L (2,0,0) = k1 − k0, L (1,1,−1) = c0 − k0, L (1,1,1) =
// c1 − k0.  A vertex warped along the global direction d was warped along the
// local direction L⁻¹ d (`local_config`).
//
// THE SYMMETRIES.  The 8 permutations of the local vertices that keep the
// long-edge pairs {0,1} and {2,3}, each realised by a lattice isometry of
// the reference tetrahedron (perm[i] the image of vertex i, lin its linear
// part).  A configuration and its image have congruent outputs
// (tests/test_bcc_keys.cpp), so keys are taken up to them: the *canonical*
// key is the image whose encoding (sign, warp per vertex, then the parity
// bit) is lexicographically smallest.
#pragma once

#include <array>
#include <string>

#include "warpmesh/mesh3d/generic_bcc.hpp"

namespace warpmesh::bcc {

// A linear map of the lattice by its columns (the images of e_x, e_y, e_z).
using Linear = std::array<Ivec, 3>;

constexpr Ivec apply(const Linear& col, const Ivec& v) {
    Ivec r{};
    for (std::size_t k = 0; k < 3; ++k) r[k] = col[0][k] * v[0] + col[1][k] * v[1] + col[2][k] * v[2];
    return r;
}

// The linear part L taking the reference tetrahedron to the tetrahedron
// whose edge vectors from vertex 0 are a = p1 − p0, b = p2 − p0, c = p3 − p0
// (see "The local frame").
constexpr Linear frame_from_edges(const Ivec& a, const Ivec& b, const Ivec& c) {
    Linear col{};
    for (std::size_t k = 0; k < 3; ++k) {
        col[0][k] = a[k] / 2;
        col[1][k] = (b[k] + c[k] - a[k]) / 2;
        col[2][k] = (c[k] - b[k]) / 2;
    }
    return col;
}
constexpr Linear local_frame(const std::array<Ivec, 4>& p) {
    return frame_from_edges(sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0]));
}

// The direction index w with L neighbour_offsets[w] = neighbour_offsets[d]
// (L a signed permutation, so it exists); `stay` stays.
constexpr int pull_direction(const Linear& col, int d) {
    if (d == stay) return stay;
    for (int w = 0; w < direction_count; ++w)
        if (apply(col, neighbour_offsets[static_cast<std::size_t>(w)]) == neighbour_offsets[static_cast<std::size_t>(d)]) return w;
    return -1;
}

// The configuration of background tetrahedron p (local order) in its local
// frame, from its vertices' post-warp signs (-1, 0, +1) and *global* warp
// directions (index into neighbour_offsets, or `stay`), in local order.
// The parity bit is `tet_parity(p)` (not yet reduced: see `canonical`).
constexpr Config local_config(const std::array<Ivec, 4>& p, const std::array<int, 4>& sign,
                              const std::array<int, 4>& global_warp) {
    const Linear col = local_frame(p);
    Config c;
    c.parity = tet_parity(p);
    for (std::size_t i = 0; i < 4; ++i) {
        c.sign[i] = sign[i];
        c.warp[i] = pull_direction(col, global_warp[i]);
    }
    return c;
}

// ---------------------------------------------------------------------------
// The symmetries of the reference tetrahedron.
struct Symmetry {
    std::array<int, 4> perm;
    Linear lin;
};

constexpr std::array<Symmetry, 8> make_symmetries() {
    std::array<Symmetry, 8> out{};
    int n = 0;
    // The 8 permutations keeping {0,1} and {2,3}: swap within each pair or
    // not, exchange the pairs or not (m = 0: the identity).
    for (int m = 0; m < 8; ++m) {
        std::array<int, 4> p{m & 1, 1 - (m & 1), 2 + ((m >> 1) & 1), 3 - ((m >> 1) & 1)};
        if (m & 4) p = {p[2], p[3], p[0], p[1]};
        out[static_cast<std::size_t>(n++)] = Symmetry{p, {}};
    }
    for (Symmetry& s : out) {
        const auto img = [&](int i, int j) {
            return sub(reference_tet[static_cast<std::size_t>(s.perm[static_cast<std::size_t>(j)])],
                       reference_tet[static_cast<std::size_t>(s.perm[static_cast<std::size_t>(i)])]);
        };
        s.lin = frame_from_edges(img(0, 1), img(0, 2), img(0, 3));
    }
    return out;
}
inline constexpr std::array<Symmetry, 8> symmetries = make_symmetries();

// Whether the stencil of these signs has a quad on a long edge (the only
// place the parity bit matters).
constexpr bool has_parity_quad(const std::array<int, 4>& sign) {
    int pos = 0;
    for (int s : sign) pos += s > 0;
    if (pos == 0) return false;
    for (std::size_t e = 0; e < 2; ++e) {
        const auto& ed = tet_edges[e];
        if (sign[static_cast<std::size_t>(ed[0])] < 0 && sign[static_cast<std::size_t>(ed[1])] < 0) return true;
    }
    return false;
}

// The image of a configuration under a symmetry: signs and warps move with
// the vertices, warp directions with the linear part, and the parity bit so
// that the decision on each long-edge face maps to the decision on its image
// (the same for every face: tests/test_bcc_keys.cpp).  0 where unused.
constexpr Config transform(const Config& k, const Symmetry& s) {
    Config out;
    for (std::size_t i = 0; i < 4; ++i) {
        const auto j = static_cast<std::size_t>(s.perm[i]);
        out.sign[j] = k.sign[i];
        const int w = k.warp[i];
        out.warp[j] = w == stay ? stay : direction_of(apply(s.lin, neighbour_offsets[static_cast<std::size_t>(w)]));
    }
    const auto P = [&](int i) { return s.perm[static_cast<std::size_t>(i)]; };
    const bool before = face_takes_a(0, 1, 2, k.parity);
    out.parity = face_takes_a(P(0), P(1), P(2), 0) == before ? 0 : 1;
    if (!has_parity_quad(out.sign)) out.parity = 0;
    return out;
}

// The parameters of a configuration moved by a symmetry as `transform` moves
// the configuration: t with its vertex; u with its edge, measured from the
// image of the edge's first vertex (so 1 − u where the image edge is
// reversed).  The points of the image are the images of the points.
template <class T>
constexpr void transform_params(const Symmetry& s, const std::array<T, 4>& t, const std::array<T, 6>& u, std::array<T, 4>& t2,
                                std::array<T, 6>& u2) {
    for (std::size_t i = 0; i < 4; ++i) t2[static_cast<std::size_t>(s.perm[i])] = t[i];
    for (std::size_t e = 0; e < 6; ++e) {
        const int a = s.perm[static_cast<std::size_t>(tet_edges[e][0])];
        const int b = s.perm[static_cast<std::size_t>(tet_edges[e][1])];
        u2[static_cast<std::size_t>(edge_index(a, b))] = a < b ? u[e] : ScalarOps<T>::from_int(1) - u[e];
    }
}

constexpr std::array<int, 9> encode(const Config& k) {
    return {k.sign[0], k.warp[0], k.sign[1], k.warp[1], k.sign[2], k.warp[2], k.sign[3], k.warp[3], k.parity};
}

// The canonical key of a configuration: its smallest image under the 8
// symmetries (the identity is symmetry 0); `*which` gets the index of the
// symmetry that maps the configuration to it (the first, on ties).
// (Any key type with `transform` and `encode`: junction keys too,
// generic_bcc_materials.hpp.)
template <class K>
constexpr K smallest_image(const K& k, int* which) {
    K best = transform(k, symmetries[0]);
    int w = 0;
    for (int i = 1; i < 8; ++i) {
        const K t = transform(k, symmetries[static_cast<std::size_t>(i)]);
        if (encode(t) < encode(best)) best = t, w = i;
    }
    if (which) *which = w;
    return best;
}
constexpr Config canonical(const Config& k, int* which = nullptr) { return smallest_image(k, which); }

// The canonical key of background tetrahedron p (local order) from its
// vertices' signs and global warp directions: what the mesher looks up.
constexpr Config key_of(const std::array<Ivec, 4>& p, const std::array<int, 4>& sign, const std::array<int, 4>& global_warp) {
    return canonical(local_config(p, sign, global_warp));
}

// A key's code, e.g. "-,0g,+,0s/1": per vertex -, +, or 0 and its warp
// direction (a..n = neighbour_offsets 0..13, s = stay); the parity bit.  The
// certificate and the per-key table name keys by it.
inline std::string code_of(const Config& k) {
    std::string s;
    for (std::size_t i = 0; i < 4; ++i) {
        if (i) s += ',';
        const int v = k.sign[i];
        if (v < 0) s += '-';
        else if (v > 0) s += '+';
        else {
            s += '0';
            const int w = k.warp[i];
            s += w == stay ? 's' : static_cast<char>('a' + w);
        }
    }
    s += '/';
    s += static_cast<char>('0' + k.parity);
    return s;
}

}  // namespace warpmesh::bcc
