// names.hpp — the words of an enumeration: one table of (value, name) pairs
// per enum, beside the enum's definition, read both ways by name_of and
// value_of (e.g. DiagonalRule's diagonal_rule_names in generic_square.hpp).
// Reports, certificates, the command line and Python all spell a rule by its
// table, and parse it with it.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace warpmesh {

template <class E>
struct Named {
    E value;
    std::string_view name;
};

// The name of `value` ("" if the table lacks it).
template <class E, std::size_t N>
constexpr std::string_view name_of(const std::array<Named<E>, N>& names, E value) {
    for (const auto& n : names)
        if (n.value == value) return n.name;
    return {};
}

// The value named `name` exactly (case-sensitive), or nothing.
template <class E, std::size_t N>
constexpr std::optional<E> value_of(const std::array<Named<E>, N>& names, std::string_view name) {
    for (const auto& n : names)
        if (n.name == name) return n.value;
    return std::nullopt;
}

}  // namespace warpmesh
