// exact_rational.hpp — exact rationals as a scalar of the generic models
// (ScalarOps: from_int, positive): for the A15 prover's witnesses at exact
// ends of a parameter box (a15.cpp) and for tests that evaluate
// generic_a15.hpp's and the prover's forms exactly.  Not on the proof path.
#pragma once

#include <boost/multiprecision/cpp_int.hpp>

#include "warpmesh/numerics/scalar.hpp"

namespace warpmesh::rational {

struct Q {
    boost::multiprecision::cpp_rational q;
};
inline Q operator+(const Q& a, const Q& b) { return {a.q + b.q}; }
inline Q operator-(const Q& a, const Q& b) { return {a.q - b.q}; }
inline Q operator*(const Q& a, const Q& b) { return {a.q * b.q}; }

}  // namespace warpmesh::rational

template <>
struct warpmesh::ScalarOps<warpmesh::rational::Q> {
    static warpmesh::rational::Q from_int(int v) { return {boost::multiprecision::cpp_rational(v)}; }
    static Truth positive(const warpmesh::rational::Q& a) { return truth(a.q > 0); }
};
