// options.cpp — reading option values, spelling option names, help texts
// (options.hpp).
#include "warpmesh/pipeline/options.hpp"

#include <charconv>
#include <algorithm>
#include <cmath>

namespace warpmesh {

std::string cli_flag(const OptionDoc& doc) {
    if (!doc.flag.empty()) return std::string(doc.flag);
    std::string f = "--" + std::string(doc.name);
    for (char& c : f)
        if (c == '_') c = '-';
    return f;
}

namespace {

const OptionDoc* find_doc(std::span<const OptionDoc* const> docs, std::string_view name) {
    for (const OptionDoc* d : docs)
        if (d->name == name) return d;
    return nullptr;
}

std::string spell_cli(const OptionDoc& d, std::string_view value) {
    if (d.kind == OptionKind::flag)
        return value == "false" && !d.off_flag.empty() ? std::string(d.off_flag) : cli_flag(d);
    return value.empty() ? cli_flag(d) : cli_flag(d) + " " + std::string(value);
}

std::string spell_python(const OptionDoc& d, std::string_view value) {
    const std::string name(d.name);
    if (value.empty()) return name;
    if (d.kind == OptionKind::flag) return name + (value == "true" ? "=True" : "=False");
    if (d.kind == OptionKind::choice) return name + "='" + std::string(value) + "'";
    return name + "=" + std::string(value);
}

}  // namespace

std::string spell_options(std::string_view text, std::span<const OptionDoc* const> docs, Spelling spelling) {
    return spell_marks(text, [&](std::string_view name, std::string_view value) {
        const OptionDoc* d = spelling == Spelling::library ? nullptr : find_doc(docs, name);
        if (!d) return value.empty() ? std::string(name) : std::string(name) + "=" + std::string(value);
        return spelling == Spelling::cli ? spell_cli(*d, value) : spell_python(*d, value);
    });
}

namespace {

// The option's heading: "--flag METAVAR", "--verify / --no-verify"; Python: the name.
std::string heading(const OptionDoc& d, Spelling spelling) {
    if (spelling != Spelling::cli) return std::string(d.name);
    std::string h = cli_flag(d);
    if (d.kind == OptionKind::flag) return d.off_flag.empty() ? h : h + " / " + std::string(d.off_flag);
    if (!d.metavar.empty()) return h + " " + std::string(d.metavar);
    std::string words;
    for (std::string_view w : d.choices) words += (words.empty() ? "" : "|") + std::string(w);
    return h + " " + words;
}

// `head`, then `text` wrapped to lines of at most `width` columns from
// column `column` (on the next line when `head` reaches the column).
std::string wrap(const std::string& head, const std::string& text, std::size_t column, std::size_t width) {
    std::vector<std::string> lines(1);
    for (std::size_t k = 0; k < text.size();) {
        const std::size_t end = std::min(text.find(' ', k), text.size());
        const std::string word = text.substr(k, end - k);
        k = end + 1;
        if (word.empty()) continue;
        if (!lines.back().empty() && column + lines.back().size() + 1 + word.size() > width) lines.emplace_back();
        lines.back() += (lines.back().empty() ? "" : " ") + word;
    }
    std::string out = head;
    out += head.size() + 2 > column ? "\n" + std::string(column, ' ') : std::string(column - head.size(), ' ');
    for (std::size_t k = 0; k < lines.size(); ++k) out += (k ? std::string(column, ' ') : "") + lines[k] + "\n";
    return out;
}

}  // namespace

std::string options_help(std::span<const OptionDoc* const> docs, std::span<const std::string_view> groups,
                         Spelling spelling, std::size_t column, std::size_t width) {
    std::string out;
    for (std::string_view group : groups) {
        std::string section;
        for (const OptionDoc* d : docs)
            if (d->group == group)
                section += wrap("  " + heading(*d, spelling), spell_options(d->help, docs, spelling), column, width);
        if (section.empty()) continue;
        out += (out.empty() ? "" : "\n") + std::string(group) + ":\n" + section;
    }
    return out;
}

std::string number_text(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

double OptionValue::number() const {
    double v = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(v))
        fail("expects a finite number, got '" + std::string(text) + "'");
    return v;
}

std::int64_t OptionValue::integer() const {
    std::int64_t v = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || ptr != end) fail("expects an integer, got '" + std::string(text) + "'");
    return v;
}

std::uint64_t OptionValue::megabytes() const {
    const std::int64_t mb = integer();
    if (mb < 1 || mb > (std::int64_t{1} << 40)) fail("expects megabytes, 1 to 2^40, got " + std::to_string(mb));
    return static_cast<std::uint64_t>(mb) << 20;
}

bool OptionValue::flag() const {
    if (text == "true") return true;
    if (text == "false") return false;
    fail("expects true or false, got '" + std::string(text) + "'");
}

std::pair<std::int32_t, double> OptionValue::tag_and_number() const {
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos)
        fail("expects T=H (a material's tag and a size), got '" + std::string(text) + "'");
    const std::int64_t tag = OptionValue{name, text.substr(0, eq), " T"}.integer();
    if (tag < 0 || tag > 65535) fail("T=H: T must be a label or tag 0..65535, got " + std::to_string(tag));
    return {static_cast<std::int32_t>(tag), OptionValue{name, text.substr(eq + 1), " H"}.number()};
}

void OptionValue::fail(std::string_view why) const {
    throw OptionError(std::string(name), "{" + std::string(name) + "}" + std::string(part) + " " + std::string(why));
}

void OptionValue::fail_choice(std::span<const std::string_view> words) const {
    std::string list;
    for (std::size_t k = 0; k < words.size(); ++k)
        list += std::string(k == 0 ? "" : k + 1 == words.size() ? " or " : ", ") + "'" + std::string(words[k]) + "'";
    fail("expects " + list + ", got '" + std::string(text) + "'");
}

}  // namespace warpmesh
