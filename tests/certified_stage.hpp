// certified_stage.hpp — a 2D stage's result (uniform.hpp, graded.hpp,
// materials.hpp) certified as the pipeline certifies it
// (pipeline/mesh2d.hpp: certify), for the tests that call the stages.
//
//   const auto r = certified(mesh_uniform(f, l, rule, with_keys), l, rule);
//   r.mesh, r.certified.min_deg, ...
#pragma once

#include <utility>

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"

namespace warpmesh::testing {

// What the tests ask of a stage for its certification: its keys, and (graded
// meshers) the band invariant checked, as the pipeline does with --verify.
inline constexpr KeyOptions with_keys{true, true};

// The stage's result and its certification's summary.
template <class Result>
struct Certified : Result {
    CertifiedSummary certified;
};

// r certified with `options` (default: bounds, cell data "certified_min_angle"
// and every keyed triangle verified, as `warpmesh --verify`).
template <class Result>
Certified<Result> certified(Result r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options = {true, true, true}) {
    Certified<Result> c{std::move(r), {}};
    c.certified = certify(static_cast<Result&>(c), lattice, rule, options);
    return c;
}

}  // namespace warpmesh::testing
