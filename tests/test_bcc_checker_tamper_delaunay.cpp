// The independent 3D checker (warpmesh-check-bcc) on the Delaunay face
// rule's certificate proofs/bcc_delaunay.cert (format 5: format 4 plus the
// header line `face-rule delaunay`) rejects (exit 1) every tampered copy,
// one test per new line or kind: the face-rule line removed, changed to
// another rule, repeated, or kept in a format 4 header; the certificate read
// as a parity (format 4) one, whose claims the parity stencils break; and a
// key line proved under the parity rule, whose claims the Delaunay rule's
// stencils break.  Each edit fails at the header or in the first pass (the
// witnesses), so the tests are fast; the untampered certificate is checked
// whole by scripts/test.sh (exit 0).
#define BOOST_TEST_MODULE bcc_checker_tamper_delaunay
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "checker_run.hpp"
#include "warpmesh/prove_bcc.hpp"

#ifndef WARPMESH_CHECK_BCC_EXE
#error "tests/CMakeLists.txt must define WARPMESH_CHECK_BCC_EXE"
#endif

namespace fs = std::filesystem;
using namespace warpmesh::testing;
namespace bp = warpmesh::bcc_prover;

namespace {

std::vector<std::string> cert() {
    auto l = read_lines(fs::path(WARPMESH_PROOFS_DIR) / "bcc_delaunay.cert");
    BOOST_REQUIRE(l.size() > 1000);
    BOOST_REQUIRE(l[0] == "warpmesh-bcc-certificate 5");
    return l;
}

// The certificate with key `code`'s line replaced by `line` and moved first.
std::vector<std::string> with_key_first(std::vector<std::string> l, const std::string& code, const std::string& line) {
    const std::size_t k = line_of(l, "key " + code + " ");
    l.erase(l.begin() + static_cast<long>(k));
    l.insert(l.begin() + static_cast<long>(line_of(l, "keys ")) + 1, line);
    return l;
}

}  // namespace

BOOST_AUTO_TEST_CASE(face_rule_line_removed) {
    auto l = cert();
    l.erase(l.begin() + static_cast<long>(line_of(l, "face-rule")));
    expect_bcc_rejected(l, "removed", "format 5 needs one face-rule line");
}

BOOST_AUTO_TEST_CASE(face_rule_changed) {
    for (const char* rule : {"face-rule parity", "face-rule voronoi", "face-rule delaunay extra"}) {
        auto l = cert();
        l[line_of(l, "face-rule")] = rule;
        expect_bcc_rejected(l, "changed", "unknown face rule");
    }
}

BOOST_AUTO_TEST_CASE(face_rule_line_repeated) {
    auto l = cert();
    const std::size_t f = line_of(l, "face-rule");
    auto a = l;
    a.insert(a.begin() + static_cast<long>(f), l[f]);  // twice after the header
    expect_bcc_rejected(a, "twice", "format 5 needs one face-rule line");
    auto b = l;
    b.push_back(l[f]);  // once more at the end
    expect_bcc_rejected(b, "atend", "format 5 needs one face-rule line");
}

BOOST_AUTO_TEST_CASE(format_4_with_a_face_rule_line) {
    auto l = cert();
    l[0] = "warpmesh-bcc-certificate 4";
    expect_bcc_rejected(l, "format4", "a face-rule line in a format 4 certificate");
}

// Read as a parity certificate (format 4, no face-rule line): the claims of
// the keys with quads, proved for the Delaunay rule's stencils, are broken
// by the parity rule's (the first, the prism -,-,-,+/0: its min witness,
// evaluated with the parity stencil, is below its claim).
BOOST_AUTO_TEST_CASE(delaunay_claims_read_with_the_parity_rule) {
    auto l = cert();
    l.erase(l.begin() + static_cast<long>(line_of(l, "face-rule")));
    l[0] = "warpmesh-bcc-certificate 4";
    expect_bcc_rejected(l, "asparity", "the witness of -,-,-,+/0 contradicts its claim");
}

// A key line proved under the parity rule at the certificate's alphas and
// caps, in the Delaunay certificate: its claims hold for the parity stencil
// and are within the theorem, but the Delaunay rule's admissible stencils
// break them (the prism -,-,+,+/0: its smallest dihedral angle is about
// 19.0 deg with the parity rule's diagonals, 13.6 deg with the Delaunay
// rule's, whose inside quad is free).
BOOST_AUTO_TEST_CASE(parity_claims_read_with_the_delaunay_rule) {
    const std::string code = "-,-,+,+/0";
    const warpmesh::bcc::Alphas al{26750, 100000, 39000, 100000};
    bp::Margins mg;
    mg.cap = bp::cap_claim(11.781, 161.253);
    for (const auto& key : bp::enumerate_keys()) {
        if (bp::code_of(key) != code) continue;
        const bp::KeyProof p = bp::prove_key_tight(key, al, mg);
        BOOST_REQUIRE(p.ok);
        const double c189 = std::cos(18.9 * M_PI / 180);
        BOOST_TEST(p.claim.cmin < c189 * c189);  // the parity rule's claim: above 18.9 deg
        const auto l = with_key_first(cert(), code, bp::certificate_line(key, p));
        expect_bcc_rejected(l, "paritykey", "the witness of -,-,+,+/0 contradicts its claim");
        return;
    }
    BOOST_FAIL("no key " + code);
}
