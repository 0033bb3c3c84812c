// junctions.cpp — the junction keys of the BCC generic tetrahedron: where
// three or four materials meet (proofs/README.md, "Junction keys (3D,
// bcc_junctions.cert)").  Their consistency rules, enumeration and
// parameters, and the decomposition of a key's proof by the faces of its
// cone stencil (generic_bcc_materials.hpp): every output tetrahedron is a
// triangle of one face joined to the centre, so it depends only on that
// face's cut points and face point and on the centre — at most the face's
// three cut fractions and the warp — and each face is proved on its own box.
#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {

bool junction_consistent(const JunctionKey& k) {
    if (bcc::first_appearance(k.letter) != k.letter || bcc::letter_count(k.letter) < 3) return false;
    for (std::size_t i = 0; i < 4; ++i) {
        if (k.letter[i] < -1 || k.letter[i] > 3) return false;
        const bool warped = k.letter[i] < 0;
        if (warped != (k.warp[i] != bcc::stay) || k.warp[i] < 0 || k.warp[i] > bcc::stay) return false;
    }
    return k.parity == 0 || (k.parity == 1 && bcc::has_junction_parity_quad(k.letter));
}

std::vector<JunctionKey> enumerate_junction_keys() {
    std::vector<JunctionKey> out;
    // Per vertex: 0..3 a letter, 4 + w warped along direction w (0..13).
    std::array<int, 4> st{};
    for (st[0] = 0; st[0] < 18; ++st[0])
        for (st[1] = 0; st[1] < 18; ++st[1])
            for (st[2] = 0; st[2] < 18; ++st[2])
                for (st[3] = 0; st[3] < 18; ++st[3])
                    for (int parity = 0; parity < 2; ++parity) {
                        JunctionKey k;
                        for (std::size_t i = 0; i < 4; ++i) {
                            k.letter[i] = st[i] < 4 ? st[i] : -1;
                            k.warp[i] = st[i] < 4 ? bcc::stay : st[i] - 4;
                        }
                        k.parity = parity;
                        if (!junction_consistent(k) || bcc::encode(bcc::canonical(k)) != bcc::encode(k)) continue;
                        out.push_back(k);
                    }
    return out;
}

namespace {
// Whether local edge e is cut: both ends unwarped, different letters.
bool cut_edge(const JunctionKey& k, int e) {
    const int a = k.letter[static_cast<std::size_t>(bcc::tet_edges[static_cast<std::size_t>(e)][0])];
    const int b = k.letter[static_cast<std::size_t>(bcc::tet_edges[static_cast<std::size_t>(e)][1])];
    return a >= 0 && b >= 0 && a != b;
}
}  // namespace

// The root boxes as key_params makes them (warp_param, cut_param).
std::vector<Param> junction_params(const JunctionKey& k, const bcc::Alphas& al) {
    std::vector<Param> out;
    for (int i = 0; i < 4; ++i)
        if (k.warp[static_cast<std::size_t>(i)] != bcc::stay) out.push_back(warp_param(i, k.warp[static_cast<std::size_t>(i)], al));
    for (int e = 0; e < 6; ++e)
        if (cut_edge(k, e)) out.push_back(cut_param(e, al));
    return out;
}

std::vector<bcc::OutTet> junction_face_tets(const JunctionKey& k, int f) {
    const bcc::MaterialStencil st = bcc::junction_stencil(k.letter, k.parity);
    std::vector<bcc::OutTet> out;
    for (int j = 0; j < st.count; ++j) {
        const bcc::OutTet& t = st.tet[static_cast<std::size_t>(j)].tet;
        bool on = true;
        for (const std::uint8_t q : t) on = on && (q == bcc::centre_point || bcc::point_on_face(q, f));
        if (on) out.push_back(t);
    }
    return out;
}

std::vector<Param> junction_face_params(const JunctionKey& k, int f, const bcc::Alphas& al) {
    std::vector<Param> out;
    for (const Param& p : junction_params(k, al)) {
        const bool on_face = p.index >= 4 && bcc::tet_edges[static_cast<std::size_t>(p.index - 4)][0] != f &&
                             bcc::tet_edges[static_cast<std::size_t>(p.index - 4)][1] != f;
        if (p.index < 4 || on_face) out.push_back(p);
    }
    return out;
}

Subject region_subject(const Key& k, const bcc::Alphas& al, FaceRule rule) {
    Subject s;
    s.key = k, s.ps = key_params(k, al), s.rule = rule, s.seed = code_of(k);
    return s;
}

Subject junction_subject(const JunctionKey& k, int face, const bcc::Alphas& al) {
    Subject s;
    s.key = bcc::junction_config(k), s.ps = junction_face_params(k, face, al), s.rule = FaceRule::parity, s.junction = true;
    s.tets = junction_face_tets(k, face), s.seed = bcc::code_of(k) + " face " + std::to_string(face);
    return s;
}

}  // namespace warpmesh::bcc_prover
