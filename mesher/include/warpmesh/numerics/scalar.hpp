// scalar.hpp — the scalar interface of the generic models and the
// three-valued comparison (the numerics layer, warpmesh/numerics/).
//
// The generic models (mesh2d/generic_square.hpp, mesh3d/generic_bcc.hpp) are
// written once, templated on the scalar: the meshers instantiate them with
// `double` (and with exact or filtered scalars where a decision must be
// exact), the provers with outward-rounded intervals (interval.hpp) and dual
// numbers over them (dual.hpp).  A comparison is three-valued, `Truth`: an
// exact scalar always decides it; an enclosure (an interval, or a double
// with a bound on its rounding error) answers `maybe` where the enclosure
// does not decide it.  That is the one way "undecided" is signalled.
//
// This header needs nothing but the standard library; it is reachable from
// the umbrella warpmesh/warpmesh.hpp.  The checkers (checker/) never include
// it: they share no code with the prover.
#pragma once

#include <cstdint>
#include <optional>
#include <type_traits>

namespace warpmesh {

// ---------------------------------------------------------------------------
// Three-valued truth.  For exact scalars (double) every test is `yes` or `no`;
// for intervals a test that depends on the point of the box is `maybe`.
enum class Truth : std::uint8_t { no = 0, yes = 1, maybe = 2 };

constexpr Truth truth(bool b) { return b ? Truth::yes : Truth::no; }
// Kleene's strong three-valued logic.
constexpr Truth operator!(Truth a) {
    return a == Truth::maybe ? Truth::maybe : truth(a == Truth::no);
}
constexpr Truth operator&&(Truth a, Truth b) {
    if (a == Truth::no || b == Truth::no) return Truth::no;
    if (a == Truth::yes && b == Truth::yes) return Truth::yes;
    return Truth::maybe;
}
constexpr Truth operator||(Truth a, Truth b) { return !(!a && !b); }

// The operations the generic code needs from a scalar type.  The primary
// template serves the built-in floating types; other scalars specialise it
// (interval.hpp: outward rounding, and `maybe` when a comparison is not
// decided on the whole interval; dual.hpp; the mesher's exact and filtered
// scalars).  Only from_int is required of every scalar; `positive` and
// `less` of those whose comparisons a model asks for, `max` of those whose
// maximum it takes.
template <class T>
struct ScalarOps {
    static_assert(std::is_floating_point_v<T>, "specialise ScalarOps for this scalar");
    static T from_int(int v) { return static_cast<T>(v); }
    static Truth positive(const T& a) { return truth(a > 0); }
    static Truth less(const T& a, const T& b) { return truth(a < b); }
    static T max(const T& a, const T& b) { return a < b ? b : a; }
};

// The sign of a (-1, 0 or +1) where the scalar decides it, from the
// three-valued tests a > 0 and -a > 0 (ScalarOps<T>::positive of a and of
// 0 - a): +1 if the first is `yes`, -1 if the second is, 0 if both are `no`;
// std::nullopt otherwise (an enclosure that straddles or touches 0 on one
// side only).  Exact scalars always decide.
template <class T>
std::optional<int> decided_sign(const T& a) {
    using O = ScalarOps<T>;
    const Truth pos = O::positive(a);
    if (pos == Truth::yes) return 1;
    const Truth neg = O::positive(O::from_int(0) - a);
    if (neg == Truth::yes) return -1;
    if (pos == Truth::no && neg == Truth::no) return 0;
    return std::nullopt;
}

}  // namespace warpmesh
