// generic_octree.hpp — the graded BCC lattice's transition rule, written
// once: the graded 3D mesher (src/mesh3d/graded/) emits its tetrahedra with
// it, the prover (warpmesh-prove-bcc --graded) enumerates and certifies its
// configurations; the checker (checker/checker3d.cpp) re-derives them on its
// own, on purpose.
//
// THE GRADED LATTICE.  A balanced octree of cubic cells (leaves) over the
// BCC lattice's cubes: a leaf of level l is an aligned block of 2^l × 2^l ×
// 2^l lattice cubes.  Balance: two leaves that share a face or a segment of
// an edge differ by at most one level (2:1 across faces and edges; corners
// are free).  Every leaf is split into six pyramids, its centre over each
// of its faces; the two pyramids over the same *face piece* — the square
// two face-adjacent leaves X and Y share, the face of the smaller one (or
// their common face) — form a bipyramid around the segment cX–cY of their
// centres, which crosses the piece's interior (equal leaves: at its centre;
// Y twice X's size: two thirds of the way from the corner of Y's face that
// the piece shares, towards the centre of Y's face).  The bipyramid is cut
// into the *fan*
//
//        (cX, cY, ring[i], ring[i + 1 mod n]),   i = 0 .. n − 1,
//
// ring the piece's boundary in cyclic order: its four corners and the
// midpoint of each side that is *split*, i.e. that a leaf of half the side's
// length also touches.  Each fan tetrahedron's faces (cX, ring[i], ring[i+1])
// and (cY, …) lie on the pyramids' sides, which the neighbouring pieces of
// the same leaf share with the same ring points on the shared side (a side is
// split or not by a property of the edge, not of the face), so the fans
// conform; they tile each leaf's pyramids, hence space.
//
// WHAT IS TRANSITION.  At the finest level (l = 0) an equal-size piece has
// no split side, and its fan is the four BCC background tetrahedra of the
// face (generic_bcc.hpp's background_tet): the uniform lattice, where the
// stencils and the certificates of the uniform mesher apply unchanged.  Every
// other fan tetrahedron — coarser equal leaves (the BCC tetrahedron scaled),
// a split side (a bisected one), leaves of two sizes — is a *template*: the
// mesher builds the octree so that its four vertices are lattice points that
// no warp moves, all inside or all outside (src/mesh3d/graded/octree3.hpp),
// so a template is a fixed polyhedron, output whole or not at all.
//
// CONFIGURATIONS.  Up to the lattice's symmetries (rotations and reflections
// of the cube; dihedral angles are invariant under both) and scaling by
// powers of two, a piece is one of 17: two equal leaves with any of the 16
// subsets of the four sides split, or a leaf against one twice its size
// (its face one quadrant of the bigger one's; no side can be split there:
// a leaf of half its size touching the side would touch the bigger leaf's
// edge, two levels apart).  `transition_config` lists them in doubled
// lattice coordinates: the smaller (or the equal) leaf X = [0, 4]³ above
// the piece z = 0, [0, 4]², and Y below it.
#pragma once

#include <array>
#include <cstdint>

#include "warpmesh/mesh3d/generic_bcc.hpp"  // Ivec, orientation

namespace warpmesh::bcc {

// A face piece: the two leaves' centres and the ring (doubled coordinates).
struct FacePiece {
    Ivec cx{}, cy{};
    std::array<Ivec, 8> ring{};
    int n = 0;
};
using LatticeTet = std::array<Ivec, 4>;

// The piece of the square face with lowest corner f0, normal to axis a, side
// d (doubled coordinates; d even where a side is split), between the leaf
// centres cx and cy.  Corner k of the face is f0 + d (0,0), (1,0), (1,1),
// (0,1) along the axes (b, c) = (a + 1, a + 2) mod 3; side k runs from
// corner k to corner k + 1, and bit k of `split` inserts its midpoint.
constexpr FacePiece face_piece(const Ivec& cx, const Ivec& cy, const Ivec& f0, int a, int d, unsigned split) {
    const std::size_t b = static_cast<std::size_t>((a + 1) % 3), c = static_cast<std::size_t>((a + 2) % 3);
    constexpr std::array<std::array<int, 2>, 5> corner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}};
    FacePiece p;
    p.cx = cx, p.cy = cy;
    for (std::size_t k = 0; k < 4; ++k) {
        Ivec q = f0;
        q[b] += d * corner[k][0], q[c] += d * corner[k][1];
        p.ring[static_cast<std::size_t>(p.n++)] = q;
        if (!(split >> k & 1u)) continue;
        Ivec m = f0;
        m[b] += d * (corner[k][0] + corner[k + 1][0]) / 2, m[c] += d * (corner[k][1] + corner[k + 1][1]) / 2;
        p.ring[static_cast<std::size_t>(p.n++)] = m;
    }
    return p;
}

// The fan of a piece, each tetrahedron (cx, cy, p, q) positively oriented (p
// and q swapped where (cx, cy, ring[i], ring[i+1]) is not); returns the count.
constexpr int piece_tets(const FacePiece& p, std::array<LatticeTet, 8>& out) {
    for (int i = 0; i < p.n; ++i) {
        LatticeTet t{p.cx, p.cy, p.ring[static_cast<std::size_t>(i)], p.ring[static_cast<std::size_t>((i + 1) % p.n)]};
        if (orientation(t) < 0) std::swap(t[2], t[3]);
        out[static_cast<std::size_t>(i)] = t;
    }
    return p.n;
}

// The 17 configurations (above): k = 0 .. 15 two equal leaves, sides split
// as the bits of k; k = 16 a leaf against one twice its size.
inline constexpr int transition_configs = 17;
constexpr FacePiece transition_config(int k) {
    if (k < 16) return face_piece({2, 2, 2}, {2, 2, -2}, {0, 0, 0}, 2, 4, static_cast<unsigned>(k));
    return face_piece({2, 2, 2}, {4, 4, -4}, {0, 0, 0}, 2, 4, 0);
}

}  // namespace warpmesh::bcc
