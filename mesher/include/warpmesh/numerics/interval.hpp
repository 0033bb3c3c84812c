// interval.hpp — outward-rounded intervals for the provers (the numerics
// layer, warpmesh/numerics/): the interval type, its rounding guard, and its
// ScalarOps (scalar.hpp).
//
// NEEDS BOOST (Boost.Interval): never include it from a header reachable from
// the umbrella warpmesh/warpmesh.hpp (installed consumers must not need
// Boost).  Every translation unit that computes with these intervals is
// compiled with -frounding-math -fno-fast-math (prover/CMakeLists.txt): the
// compiler must not fold or move floating-point operations across the
// rounding-mode switches, and -ffast-math would void the enclosures.
#pragma once

#include <algorithm>
#include <cmath>

#include <boost/numeric/interval.hpp>

#include "warpmesh/numerics/scalar.hpp"

namespace warpmesh {

namespace interval_policies = boost::numeric::interval_lib;
// Outward rounding by the "opposite" trick: the FPU stays in upward mode and a
// lower bound is computed as -((-x) op y).  The operations do not switch the
// mode (switching it per operation cost ~80% of the run time); every entry
// point of interval code holds a `RoundUp` guard, which sets upward rounding
// for its scope and restores the caller's mode.  Without the guard the
// enclosures would not be outward: interval code must not run outside one.
using Interval = boost::numeric::interval<
    double, interval_policies::policies<interval_policies::save_state_nothing<interval_policies::rounded_arith_opp<double>>,
                                        interval_policies::checking_base<double>>>;
using RoundUp = interval_policies::save_state<interval_policies::rounded_arith_opp<double>>;

// `less` and `positive` answer yes/no only when decided on the whole interval.
// `less` further demands a relative margin of 1e-9: where it says "decided",
// the exact values differ by more than 1e-9 relative, so a double evaluation
// of the same expression (within a few ulps of the exact value) decides the
// same way (the 2D prover's agreement with the mesher's choice of diagonal).
// An empty interval (NaN ends, from a division by [0,0]) is never decided.
template <>
struct ScalarOps<Interval> {
    static Interval from_int(int v) { return Interval(static_cast<double>(v)); }
    static bool bad(const Interval& a) { return std::isnan(a.lower()) || std::isnan(a.upper()); }
    static Truth positive(const Interval& a) {
        if (bad(a)) return Truth::maybe;
        if (a.lower() > 0) return Truth::yes;
        if (a.upper() <= 0) return Truth::no;
        return Truth::maybe;
    }
    static Truth less(const Interval& a, const Interval& b) {
        if (bad(a) || bad(b)) return Truth::maybe;
        const double mag = std::max({std::fabs(a.lower()), std::fabs(a.upper()), std::fabs(b.lower()),
                                     std::fabs(b.upper())});
        const double m = 1e-9 * mag;  // >= 0; fl(x + m) >= x, so the tests below imply the exact ones
        if (a.upper() + m < b.lower()) return Truth::yes;
        if (a.lower() >= b.upper() + m) return Truth::no;
        return Truth::maybe;
    }
    static Interval max(const Interval& a, const Interval& b) {
        if (bad(a) || bad(b)) return Interval::whole();
        return boost::numeric::max(a, b);
    }
};

}  // namespace warpmesh
