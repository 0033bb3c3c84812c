// exact_rational.hpp — exact rationals as a scalar of the generic models
// (ScalarOps: from_int, positive), for tests that evaluate generic_a15.hpp's
// and the prover's forms exactly.
#pragma once

#include <boost/multiprecision/cpp_int.hpp>

#include "warpmesh/numerics/scalar.hpp"

namespace warpmesh::testing {

struct Q {
    boost::multiprecision::cpp_rational q;
};
inline Q operator+(const Q& a, const Q& b) { return {a.q + b.q}; }
inline Q operator-(const Q& a, const Q& b) { return {a.q - b.q}; }
inline Q operator*(const Q& a, const Q& b) { return {a.q * b.q}; }

}  // namespace warpmesh::testing

template <>
struct warpmesh::ScalarOps<warpmesh::testing::Q> {
    static warpmesh::testing::Q from_int(int v) { return {boost::multiprecision::cpp_rational(v)}; }
    static Truth positive(const warpmesh::testing::Q& a) { return truth(a.q > 0); }
};
