// shape_syntax.hpp — the syntax of shape strings, shared by the 2D and 3D
// parsers (shapes.cpp, shapes3.cpp): a term is a primitive `name:n,n,...` or
// an operation `name(S;S;...)` whose parts are split at the ';' outside
// nested parentheses.  Errors are InputError naming the offending text.
#pragma once

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "warpmesh/core/errors.hpp"

namespace warpmesh::shape_syntax {

inline std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

inline double parse_number(std::string_view s, std::string_view shape) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc{} || end != s.data() + s.size())
        throw InputError(std::string(shape) + ": '" + std::string(s) + "' is not a number");
    if (!std::isfinite(v)) throw InputError(std::string(shape) + ": parameters must be finite numbers");
    return v;
}

// The comma-separated numbers of a primitive's arguments.
inline std::vector<double> parse_numbers(std::string_view args, std::string_view shape) {
    std::vector<double> v;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = args.find(',', start);
        v.push_back(parse_number(args.substr(start, comma == std::string_view::npos ? comma : comma - start), shape));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return v;
}

// A term: an operation (name and the text inside its parentheses) or a
// primitive (name and the text after the colon).  `example` completes the
// message for text that is neither ("expected e.g. circle:0,0,1").
struct Term {
    bool operation = false;
    std::string_view name, body;
};
inline Term split_term(std::string_view s, const char* example) {
    s = trim(s);
    if (s.empty()) throw InputError("empty shape");
    const std::size_t paren = s.find('('), colon = s.find(':');
    if (paren != std::string_view::npos && (colon == std::string_view::npos || paren < colon)) {
        // The parentheses must balance, and the one opened after the name
        // must close at the very end.
        int depth = 0;
        for (std::size_t i = paren; i < s.size(); ++i) {
            if (s[i] == '(') ++depth;
            if (s[i] == ')' && --depth == 0 && i + 1 != s.size())
                throw InputError("unexpected text after ')' in '" + std::string(s) + "'");
            if (depth < 0) break;
        }
        if (depth != 0) throw InputError("unbalanced parentheses in '" + std::string(s) + "'");
        return {true, trim(s.substr(0, paren)), s.substr(paren + 1, s.size() - paren - 2)};
    }
    if (colon == std::string_view::npos)
        throw InputError("'" + std::string(s) + "' is not a shape (expected e.g. " + example + ")");
    return {false, trim(s.substr(0, colon)), s.substr(colon + 1)};
}

// An operation's parts (at least two, else InputError naming the operation).
inline std::vector<std::string_view> split_parts(std::string_view inner, std::string_view name) {
    std::vector<std::string_view> parts;
    int depth = 0;
    std::size_t start = 0;
    for (std::size_t i = 0; i < inner.size(); ++i) {
        if (inner[i] == '(') ++depth;
        if (inner[i] == ')') --depth;
        if (inner[i] == ';' && depth == 0) parts.push_back(inner.substr(start, i - start)), start = i + 1;
    }
    parts.push_back(inner.substr(start));
    if (parts.size() < 2) throw InputError(std::string(name) + " needs at least two shapes separated by ';'");
    return parts;
}

}  // namespace warpmesh::shape_syntax
