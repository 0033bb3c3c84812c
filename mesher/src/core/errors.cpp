// errors.cpp — the marks of OptionError's messages (errors.hpp).
#include "warpmesh/core/errors.hpp"

namespace warpmesh {

namespace {

bool name_char(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; }

// The library's words: name, name=value.
std::string library_words(std::string_view name, std::string_view value) {
    return value.empty() ? std::string(name) : std::string(name) + "=" + std::string(value);
}

}  // namespace

std::string spell_marks(std::string_view text,
                        const std::function<std::string(std::string_view name, std::string_view value)>& spell) {
    std::string out;
    for (std::size_t k = 0; k < text.size();) {
        const std::size_t close = text[k] == '{' ? text.find('}', k) : std::string_view::npos;
        if (close != std::string_view::npos) {
            const std::string_view mark = text.substr(k + 1, close - k - 1);
            const std::size_t eq = mark.find('=');
            const std::string_view name = mark.substr(0, eq);
            bool ok = !name.empty() && name[0] >= 'a' && name[0] <= 'z' && (eq == std::string_view::npos || eq + 1 < mark.size());
            for (char c : name) ok = ok && name_char(c);
            if (ok) {
                out += spell(name, eq == std::string_view::npos ? std::string_view() : mark.substr(eq + 1));
                k = close + 1;
                continue;
            }
        }
        out += text[k++];
    }
    return out;
}

OptionError::OptionError(std::string option, std::string message)
    : InputError(spell_marks(message, library_words)), option_(std::move(option)), message_(std::move(message)) {}

}  // namespace warpmesh
