// junction_keys.cpp — the junction keys: multi-material squares whose four
// corners carry 3 or 4 materials (proofs/README.md, "Junction keys").  The
// rules are those of the multi-material mesher (materials.hpp,
// mesh_materials.cpp, warp.cpp):
//
//   * every lattice point has one material (no zero-valued points);
//   * a lattice edge is cut iff its endpoints' materials differ; it has one
//     cut point, at u in (0, 1); its candidate is the closer endpoint (at
//     u = 1/2 the one the tie rule of materials.hpp picks — which one is not
//     constrained here), and only the candidate moves along it;
//   * a point that is the candidate of several cut edges takes the nearest cut
//     point; so a warped point has slid t in [0, 1/2] along a cut edge of its own.
//
// A key records which corners share a material (letters in order of first
// appearance, A..D) and each corner's warp.  Consistency:
//   1. the letters use >= 3 distinct values (1 or 2 materials: the sign keys,
//      with the larger material mapped to '-');
//   2. an inward slide (along a side of the square) runs along a cut side:
//      the corner it goes towards has a different letter;
//   3. two corners never slide towards each other along the same side;
//   4. every cut side (letters differ) has a warped endpoint (its candidate
//      warped, perhaps along another edge);
//   5. outward slides constrain only the outside neighbour (a different
//      material), which is not part of the key: free.
// Nothing else is imposed (superset, as for the sign keys).
#include <map>

#include "warpmesh/mesh2d/square_keys.hpp"
#include "warpmesh/prove.hpp"

namespace warpmesh::prover {
namespace {

// Corner reached from corner c by the slide w, or -1 (stay, or outward).
int inward_corner(int c, Warp w) {
    const int x = (c & 1) + warp_dx(w), y = (c >> 1) + warp_dy(w);
    if (w == Warp::stay || x < 0 || x > 1 || y < 0 || y > 1) return -1;
    return x + 2 * y;
}

bool canonical_letters(const std::array<MaterialCorner, 4>& m) {
    int next = 0;
    for (const auto& c : m) {
        if (c.material > next) return false;  // a new letter must be the next one
        if (c.material == next) ++next;
    }
    return next >= 3;  // rule 1
}

bool junction_consistent(const std::array<MaterialCorner, 4>& m) {
    if (!canonical_letters(m)) return false;
    for (int c = 0; c < 4; ++c) {
        const int n = inward_corner(c, m[c].warp);
        if (n < 0) continue;
        if (m[n].material == m[c].material) return false;        // rule 2
        if (inward_corner(n, m[n].warp) == c) return false;      // rule 3
    }
    constexpr int sides[4][2] = {{A, B}, {B, D}, {D, C}, {C, A}};
    for (const auto& e : sides) {
        const MaterialCorner a = m[e[0]], b = m[e[1]];
        if (a.material != b.material && a.warp == Warp::stay && b.warp == Warp::stay) return false;  // rule 4
    }
    return true;
}

}  // namespace

std::vector<Key> junction_keys() {
    std::vector<Key> out;
    for (int code = 0; code < 20 * 20 * 20 * 20; ++code) {
        Key k;
        k.junction = true;
        for (int c = 3, r = code; c >= 0; --c, r /= 20) {
            k.m[c] = {static_cast<std::uint16_t>(r % 20 / 5), static_cast<Warp>(r % 5)};
            k.s[c] = {0, k.m[c].warp};
        }
        if (junction_consistent(k.m)) out.push_back(k);
    }
    return out;
}

std::vector<int> junction_classes(DiagonalRule rule, const std::vector<Key>& keys, const std::vector<int>& ids) {
    std::map<int, int> first;  // (warps, forcing) → first index
    std::vector<int> rep(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const Key& k = keys[static_cast<std::size_t>(ids[i])];
        int cls = 0;
        for (const MaterialCorner& c : k.m) cls = cls * 5 + static_cast<int>(c.warp);
        Diagonal d{};
        // The separating and fan rules force; under the fan rule an unforced
        // junction key may take the fan (its staying corners share a letter:
        // two staying corners with different letters are opposite, hence
        // forcing), so the forcing also fixes the fan's availability.
        const int forcing =
            rule != DiagonalRule::maxmin && separating_diagonal(k.m, d) ? 1 + static_cast<int>(d) : 0;
        rep[i] = first.try_emplace(cls * 3 + forcing, static_cast<int>(i)).first->second;
    }
    return rep;
}

std::string code_of(const Key& k) { return k.junction ? junction_key_code(k.m) : key_code(k.s); }

}  // namespace warpmesh::prover
