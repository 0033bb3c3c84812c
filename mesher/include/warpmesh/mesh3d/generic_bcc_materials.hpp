// generic_bcc_materials.hpp — the multi-material generic tetrahedron: how a
// background tetrahedron whose vertices carry several materials is split,
// written once (the multi-material 3D mesher, mesh3d/mesh3d.hpp:
// mesh_bcc_materials; the 3D prover's junction keys, prover/src/bcc/
// junctions.cpp, and their certificate proofs/bcc_junctions.cert, which the
// mesher looks up by junction_key_of below).
//
// THE MODEL.  After warping (generic_bcc.hpp, steps 1–5, with "a lattice
// edge is cut iff its endpoints' materials differ"), each vertex of a
// background tetrahedron is either unwarped, with a material, or warped
// (zero: it lies on an interface).  Materials enter only through *letters*:
// per vertex, -1 if warped, else the rank of its material in order of first
// appearance among the local vertices 0..3 (so renumbering the labels
// changes no letter).  Let k be the number of letters.
//   k = 0 (all zero): nothing is output (as for one region; the volume, in
//          the α-band of the interfaces, is left out).
//   k = 1: the whole tetrahedron, that material.
//   k = 2: letters X = 0 and Y = 1: the one-region stencil twice, `stencil(sign_X, parity)` for X and
//          `stencil(−sign_X, parity)` for Y, with sign_X = − on X, + on Y, 0
//          on warped vertices.  Both use the parity rule: a face quad (two
//          vertices of one material, one of the other) takes the parity
//          rule's diagonal, a function of the face alone, so both
//          tetrahedra sharing the face agree; and the (2,2) prism's inside
//          quad, which both sides share, is forced to the same diagonal on
//          both sides (checked for every sign pattern and parity bit by
//          tests/test_bcc_materials.cpp).  The Delaunay face rule does not
//          have this property (its face choices can force the two sides'
//          shared quad to different diagonals), so multi-material meshes
//          use the parity rule.  Each side is a one-region key of
//          proofs/bcc.cert.
//   k >= 3 (a *junction*: three or four materials meet): the cone stencil.
//          Every face of the tetrahedron is subdivided by a rule of the face
//          alone (below); each triangle of a face belongs to one material;
//          each is joined to the centre point C, and the tetrahedron
//          (triangle, C) takes the triangle's material.  Since the warped
//          tetrahedron is convex and C lies strictly inside it, the cone
//          tiles it; since the face subdivision is the face's own, the
//          neighbours agree on it (conformity), whatever their k.
//
// FACE SUBDIVISION (a face (x, y, z) of local vertices):
//   one letter among its unwarped vertices (or none): the whole face;
//   two letters, a warped vertex z: (x, cut(x,y), z) and (cut(x,y), y, z);
//   two letters, no warped vertex, x1 < x2 of letter X and y of letter Y:
//          the triangle (y, cut(x1,y), cut(x2,y)) for Y and the quad (x1, x2,
//          cut(x2,y), cut(x1,y)) for X, split by the parity rule's diagonal
//          (face_takes_a(x1, x2, y, parity): x1–cut(x2,y), else
//          x2–cut(x1,y)) — the two-material stencils' own faces;
//   three letters: the face point F, and for each vertex v and each of its
//          two face edges (v, w) the triangle (v, cut(v,w), F), v's material.
//
// POINTS.  0..3 the vertices, 4 + e the cut point on local edge e, 10 + f
// the face point of the face without vertex f, 14 the centre.  The mesher
// puts F at the average of the face's three cut points and C at the average
// of the tetrahedron's four (warped) vertices; the reference configuration
// (vertices at reference_tet, cut points at edge midpoints, F at the face's
// centroid, C at the tetrahedron's) orients the output.
#pragma once

#include <array>
#include <cstdint>

#include <string>

#include "warpmesh/mesh3d/generic_bcc.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"  // symmetries, Symmetry, local_frame

namespace warpmesh::bcc {

inline constexpr int face_point(int f) { return 10 + f; }
inline constexpr int centre_point = 14;

// The letters of four local vertex materials (-1: warped), by first appearance.
template <class M>
constexpr std::array<int, 4> letters_of(const std::array<M, 4>& material, const std::array<bool, 4>& warped) {
    std::array<int, 4> letter{-1, -1, -1, -1};
    std::array<M, 4> seen{};
    int n = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        if (warped[i]) continue;
        int k = 0;
        while (k < n && !(seen[static_cast<std::size_t>(k)] == material[i])) ++k;
        if (k == n) seen[static_cast<std::size_t>(n++)] = material[i];
        letter[i] = k;
    }
    return letter;
}
constexpr int letter_count(const std::array<int, 4>& letter) {
    int k = 0;
    for (const int l : letter) k = l + 1 > k ? l + 1 : k;
    return k;
}

// An output tetrahedron of a multi-material stencil and its letter.
struct LetterTet {
    OutTet tet{};
    int letter = 0;
};
struct MaterialStencil {
    int count = 0;
    std::array<LetterTet, 24> tet{};
};

// Reference positions of the 15 points, times 6 (exact integers): vertices
// 12 p, cut points 6 (p + q), face points 4 (p + q + r), the centre 3 Σ p.
constexpr Ivec reference_point15(int q) {
    const auto P = [](int i) { return reference_tet[static_cast<std::size_t>(i)]; };
    if (q < 4) return {12 * P(q)[0], 12 * P(q)[1], 12 * P(q)[2]};
    if (q < 10) {
        const auto& e = tet_edges[static_cast<std::size_t>(q - 4)];
        const Ivec s = add(P(e[0]), P(e[1]));
        return {6 * s[0], 6 * s[1], 6 * s[2]};
    }
    Ivec s{0, 0, 0};
    for (int i = 0; i < 4; ++i)
        if (q == centre_point || i != q - 10) s = add(s, P(i));
    const int k = q == centre_point ? 3 : 4;
    return {k * s[0], k * s[1], k * s[2]};
}

constexpr void push_letter(MaterialStencil& s, int p0, int p1, int p2, int p3, int letter) {
    OutTet t{static_cast<std::uint8_t>(p0), static_cast<std::uint8_t>(p1), static_cast<std::uint8_t>(p2), static_cast<std::uint8_t>(p3)};
    const long o = orientation({reference_point15(p0), reference_point15(p1), reference_point15(p2), reference_point15(p3)});
    if (o < 0) std::swap(t[2], t[3]);
    s.tet[static_cast<std::size_t>(s.count++)] = {t, letter};
}

// Whether point q (of the 15) lies on the face without local vertex f: a
// vertex other than f, a cut point of an edge without f, or f's own face
// point (the centre lies on no face).  A junction's output tetrahedron is
// (three points of one face, the centre): it belongs to the face all three lie on.
constexpr bool point_on_face(int q, int f) {
    if (q < 4) return q != f;
    if (q < 10) return tet_edges[static_cast<std::size_t>(q - 4)][0] != f && tet_edges[static_cast<std::size_t>(q - 4)][1] != f;
    return q == face_point(f);
}

// The 15 points of a junction in the reference frame, times 12 (doubled
// coordinates times 12): generic_points' ten times 12 (vertex i warped along
// c.warp[i] by t[i], cut point e at fraction u[e] of its edge), face point f
// four times the sum of the face's three cut points (12 times their average;
// meaningful only on a face of three letters) and the centre three times the
// sum of the four vertices (12 times their average) — the positions the
// mesher computes (materials3.cpp), scaled.  Only + − × on the scalar, so
// these are exact polynomials in (t, u) for every scalar, the prover's dual
// intervals included; the angle and orientation forms (generic_bcc.hpp,
// "Angle forms") are homogeneous, so their signs and every comparison
// d² <= C N are those of the unscaled points.
template <class T>
std::array<Vec<T>, 15> junction_points12(const Config& c, const std::array<T, 4>& t, const std::array<T, 6>& u) {
    using O = ScalarOps<T>;
    const std::array<Vec<T>, 10> g = generic_points(c, t, u);
    std::array<Vec<T>, 15> p{};
    for (std::size_t q = 0; q < 10; ++q)
        for (std::size_t k = 0; k < 3; ++k) p[q][k] = O::from_int(12) * g[q][k];
    for (int f = 0; f < 4; ++f) {
        std::array<int, 3> v{};
        for (int i = 0, n = 0; i < 4; ++i)
            if (i != f) v[static_cast<std::size_t>(n++)] = i;
        const std::array<int, 3> e{cut_point(v[0], v[1]), cut_point(v[1], v[2]), cut_point(v[2], v[0])};
        for (std::size_t k = 0; k < 3; ++k)
            p[static_cast<std::size_t>(face_point(f))][k] =
                O::from_int(4) * (g[static_cast<std::size_t>(e[0])][k] + g[static_cast<std::size_t>(e[1])][k] + g[static_cast<std::size_t>(e[2])][k]);
    }
    for (std::size_t k = 0; k < 3; ++k) p[centre_point][k] = O::from_int(3) * (g[0][k] + g[1][k] + g[2][k] + g[3][k]);
    return p;
}

// The 15 points of a junction in the reference frame (doubled coordinates):
// junction_points12 / 12 — vertices and cut points as generic_points, face
// point f the average of the face's three cut points, the centre the
// average of the four vertices.
template <class T>
std::array<Vec<T>, 15> junction_points(const Config& c, const std::array<T, 4>& t, const std::array<T, 6>& u) {
    const std::array<Vec<T>, 10> g = generic_points(c, t, u);
    std::array<Vec<T>, 15> p = junction_points12(c, t, u);
    for (std::size_t q = 0; q < 15; ++q)
        for (std::size_t k = 0; k < 3; ++k) p[q][k] = q < 10 ? g[q][k] : p[q][k] / ScalarOps<T>::from_int(12);
    return p;
}

// The cone stencil of a junction (k >= 3; see above).
constexpr MaterialStencil junction_stencil(const std::array<int, 4>& letter, int parity) {
    MaterialStencil s;
    for (int f = 0; f < 4; ++f) {
        std::array<int, 3> v{};
        for (int i = 0, n = 0; i < 4; ++i)
            if (i != f) v[static_cast<std::size_t>(n++)] = i;
        const auto L = [&](int i) { return letter[static_cast<std::size_t>(i)]; };
        const int a = v[0], b = v[1], c = v[2];
        const bool ab = L(a) >= 0 && L(b) >= 0 && L(a) != L(b), bc = L(b) >= 0 && L(c) >= 0 && L(b) != L(c),
                   ca = L(c) >= 0 && L(a) >= 0 && L(c) != L(a);
        const int cuts = ab + bc + ca;
        const auto cone = [&](int p, int q, int r, int l) { push_letter(s, p, q, r, centre_point, l); };
        if (cuts == 0) {  // one letter (the others warped)
            const int l = L(a) >= 0 ? L(a) : L(b) >= 0 ? L(b) : L(c);
            cone(a, b, c, l);
        } else if (cuts == 3) {  // three letters: the face point
            const int F = face_point(f);
            for (const int x : {a, b, c})
                for (const int y : {a, b, c})
                    if (x != y) cone(x, cut_point(x, y), F, L(x));
        } else if (cuts == 1) {  // two letters, one vertex warped
            const int x = ab ? a : bc ? b : c, y = ab ? b : bc ? c : a, z = a + b + c - x - y;
            cone(x, cut_point(x, y), z, L(x));
            cone(cut_point(x, y), y, z, L(y));
        } else {  // two letters, no warped vertex: x1 < x2 share a letter, y the odd one
            const int y = !ab ? c : !bc ? a : b;  // the end of both cut edges
            int x1 = -1, x2 = -1;
            for (const int x : {a, b, c})
                if (x != y) (x1 < 0 ? x1 : x2) = x;
            if (x1 > x2) std::swap(x1, x2);
            const int c1 = cut_point(x1, y), c2 = cut_point(x2, y);
            cone(y, c1, c2, L(y));
            if (face_takes_a(x1, x2, y, parity)) {
                cone(x1, x2, c2, L(x1));
                cone(x1, c2, c1, L(x1));
            } else {
                cone(x1, x2, c1, L(x1));
                cone(x2, c2, c1, L(x1));
            }
        }
    }
    return s;
}

// ---------------------------------------------------------------------------
// JUNCTION KEYS (proofs/README.md, "Junction keys (3D, bcc_junctions.cert)").
// A junction background tetrahedron's configuration in its local frame:
// per vertex its letter (-1: warped; else 0..3 by first appearance among the
// unwarped vertices in local order, as letters_of gives them) and, for the
// warped vertex, the lattice direction (local frame, 0..13) along which it
// moved (`stay` for the others); and the parity bit, kept only where the
// cone stencil splits a quad on a long edge (else 0).  Keys are taken up to
// the 8 symmetries of the reference tetrahedron (generic_bcc_keys.hpp), as
// one-region keys are: an image moves letters and warps with the vertices
// and warp directions with the linear part, *re-letters* by first
// appearance (renaming materials changes no geometry), and takes the parity
// bit that maps the decision on each long-edge face to the decision on its
// image (`transform`'s rule; tests/test_bcc_junction_keys.cpp checks that
// images have the same output, point for point).  The canonical key is the
// image with the smallest encoding (letter, warp per vertex, then the bit).
struct JunctionKey {
    std::array<int, 4> letter{};
    std::array<int, 4> warp{stay, stay, stay, stay};
    int parity = 0;
};

// Letters renamed by first appearance in local order (-1 stays -1).
constexpr std::array<int, 4> first_appearance(const std::array<int, 4>& letter) {
    std::array<int, 4> rename{-1, -1, -1, -1}, out{-1, -1, -1, -1};
    int n = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        const int l = letter[i];
        if (l < 0) continue;
        if (rename[static_cast<std::size_t>(l)] < 0) rename[static_cast<std::size_t>(l)] = n++;
        out[i] = rename[static_cast<std::size_t>(l)];
    }
    return out;
}

// Whether the cone stencil of these letters splits a quad on a long edge
// (a face of three unwarped vertices and two letters whose equal pair is a
// long edge: face_takes_a reads the parity bit there, and nowhere else).
constexpr bool has_junction_parity_quad(const std::array<int, 4>& letter) {
    for (std::size_t e = 0; e < 2; ++e) {
        const int a = tet_edges[e][0], b = tet_edges[e][1];
        const int la = letter[static_cast<std::size_t>(a)], lb = letter[static_cast<std::size_t>(b)];
        if (la < 0 || la != lb) continue;
        for (int r = 0; r < 4; ++r) {
            const int lr = letter[static_cast<std::size_t>(r)];
            if (r != a && r != b && lr >= 0 && lr != la) return true;
        }
    }
    return false;
}

// The image of a junction key under a symmetry (see above); the parity bit
// as `transform` maps it for one-region keys, 0 where unused.
constexpr JunctionKey transform(const JunctionKey& k, const Symmetry& s) {
    JunctionKey out;
    std::array<int, 4> letter{};
    for (std::size_t i = 0; i < 4; ++i) {
        const auto j = static_cast<std::size_t>(s.perm[i]);
        letter[j] = k.letter[i];
        const int w = k.warp[i];
        out.warp[j] = w == stay ? stay : direction_of(apply(s.lin, neighbour_offsets[static_cast<std::size_t>(w)]));
    }
    out.letter = first_appearance(letter);
    const auto P = [&](int i) { return s.perm[static_cast<std::size_t>(i)]; };
    out.parity = face_takes_a(P(0), P(1), P(2), 0) == face_takes_a(0, 1, 2, k.parity) ? 0 : 1;
    if (!has_junction_parity_quad(out.letter)) out.parity = 0;
    return out;
}

constexpr std::array<int, 9> encode(const JunctionKey& k) {
    return {k.letter[0], k.warp[0], k.letter[1], k.warp[1], k.letter[2], k.warp[2], k.letter[3], k.warp[3], k.parity};
}

// The canonical junction key: the smallest image under the 8 symmetries;
// `*which` gets the index of the symmetry that maps k to it (the first, on ties).
constexpr JunctionKey canonical(const JunctionKey& k, int* which = nullptr) { return smallest_image(k, which); }

// The canonical junction key of background tetrahedron p (local order) from
// its vertices' letters (letters_of, local order) and *global* warp
// directions (`stay` for unwarped vertices): what the mesher looks up
// (bcc_certified.hpp, bcc_junction_certified_bound).
constexpr JunctionKey junction_key_of(const std::array<Ivec, 4>& p, const std::array<int, 4>& letter,
                                      const std::array<int, 4>& global_warp) {
    const Linear col = local_frame(p);
    JunctionKey k;
    k.letter = first_appearance(letter);
    for (std::size_t i = 0; i < 4; ++i) k.warp[i] = k.letter[i] < 0 ? pull_direction(col, global_warp[i]) : stay;
    k.parity = tet_parity(p);
    return canonical(k);
}

// The configuration junction_points reads (the warps; signs: - unwarped, 0 warped).
constexpr Config junction_config(const JunctionKey& k) {
    Config c;
    for (std::size_t i = 0; i < 4; ++i) c.sign[i] = k.letter[i] < 0 ? 0 : -1, c.warp[i] = k.warp[i];
    c.parity = k.parity;
    return c;
}

// A junction key's code, e.g. "a,b,0h,c/0": per vertex its letter (a..d) or
// 0 and its warp direction (a..n = neighbour_offsets 0..13); the parity
// bit.  proofs/bcc_junctions.cert and the compiled table name keys by it.
inline std::string code_of(const JunctionKey& k) {
    std::string s;
    for (std::size_t i = 0; i < 4; ++i) {
        if (i) s += ',';
        if (k.letter[i] >= 0) s += static_cast<char>('a' + k.letter[i]);
        else s += '0', s += static_cast<char>('a' + k.warp[i]);
    }
    s += '/';
    s += static_cast<char>('0' + k.parity);
    return s;
}

}  // namespace warpmesh::bcc
