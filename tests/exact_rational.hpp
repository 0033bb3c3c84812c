// exact_rational.hpp — the tests' name for the exact rational scalar
// (prover/include/warpmesh/exact_rational.hpp).
#pragma once

#include "../prover/include/warpmesh/exact_rational.hpp"

namespace warpmesh::testing {
using rational::Q;
}  // namespace warpmesh::testing
