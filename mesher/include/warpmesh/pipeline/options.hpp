// options.hpp — options by name: one table per dimension (mesh2d_option_table
// in mesh2d.hpp, mesh3d_option_table in mesh3d_options.hpp) from which the
// command line makes its help and its parser and Python its keywords and
// their docstrings, so that an option is added in one place plus its use.
//
// An entry is the option's name (the library's and Python's: max_memory),
// its command-line flag (derived: --max-memory, unless the entry says
// otherwise), its kind and metavar, its help (one paragraph in which other
// options are marked {name}, spelled by each client its way: errors.hpp's
// marks), its help group, and a setter that parses a value given as text into
// the options struct.  The table's validate checks the values and the
// contradictions between them, once, in the library, with OptionError
// messages in the library's words.
//
//   const auto& table = warpmesh::mesh2d_option_table();
//   warpmesh::MeshOptions o;
//   warpmesh::GivenOptions given;
//   table.set(o, given, "spacing", "0.5");    // OptionError: unknown name, bad text
//   table.validate(o, given);                 // OptionError: out of range, contradictions
#pragma once

#include <cstdint>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/names.hpp"

namespace warpmesh {

// How a value is given.
enum class OptionKind : std::uint8_t {
    flag,     // on or off: "true" / "false" (command line: the flag, or its off flag)
    number,   // a finite decimal number
    integer,  // a decimal integer
    choice,   // one of the entry's words
    pairs,    // T=H, repeatable: each value adds a pair (Python: a dict {T: H})
    text,     // any text (a file name, a list the option parses itself)
};

// What a help text or a docstring needs to know of an option.
struct OptionDoc {
    std::string_view name;     // library and Python name: "max_memory"
    OptionKind kind = OptionKind::flag;
    std::string_view metavar;  // "MB"; choices: their words joined by '|'; flags: ""
    std::string_view group;    // the help's section: "lattice and algorithm"
    std::string_view help;     // one paragraph; other options marked {name}
    std::vector<std::string_view> choices;  // OptionKind::choice: the words, in the help's order
    std::string_view flag;      // the command line's flag when it is not --name with '-' for '_'
    std::string_view off_flag;  // flags: the command line's flag that sets false ("--no-verify"), if any
};

// The command line's flag of an option: doc.flag, or "--" + name with '-'
// for '_' ("max_memory" -> "--max-memory").
std::string cli_flag(const OptionDoc& doc);

// How a client spells the options a text names ({name}, {name=value}):
//   library  name, name=value
//   cli      the flags: --max-memory, --graded (value true), --no-certify
//            (value false), --diagonal fan
//   python   keywords: max_memory, graded=True, rule='fan', spacing=0.5
// `docs`: the options the text may name (a name not among them is spelled as
// the library spells it).
enum class Spelling : std::uint8_t { library, cli, python };
std::string spell_options(std::string_view text, std::span<const OptionDoc* const> docs, Spelling spelling);

// The help of these options, in these groups (a section per group, the
// options in the order of `docs`; an option of another group is left out):
// "group:" then per option "  FLAG METAVAR" (cli) or "  name" (python) and its
// help spelled the same way, wrapped to `width` columns at column `column`.
std::string options_help(std::span<const OptionDoc* const> docs, std::span<const std::string_view> groups,
                         Spelling spelling, std::size_t column = 25, std::size_t width = 89);

// A number as options' texts and messages show it: the shortest text that
// reads back ("0.5", "1e+30", "nan").
std::string number_text(double x);

// One value given for an option (`name`, `text`), read as its kind; a bad
// text is an OptionError "{name} expects ..., got 'text'".  `part` names a
// part of a composite value in messages (max_size_of's " T", " H").
struct OptionValue {
    std::string_view name, text, part = {};
    double number() const;
    std::int64_t integer() const;
    bool flag() const;  // "true" or "false"
    // Megabytes, an integer in [1, 2^40], as bytes.
    std::uint64_t megabytes() const;
    template <class E, std::size_t N>
    E choice(const std::array<Named<E>, N>& names) const {
        if (const auto v = value_of(names, text)) return *v;
        std::vector<std::string_view> words;
        for (const auto& n : names) words.push_back(n.name);
        fail_choice(words);
    }
    // "T=H" -> (T, H) as given: T an integer in [0, 65535], H a number.
    std::pair<std::int32_t, double> tag_and_number() const;
    [[noreturn]] void fail(std::string_view why) const;  // OptionError "{name}<part> why"
    [[noreturn]] void fail_choice(std::span<const std::string_view> words) const;
};

// The names of the options a client set (the contradictions that a default
// cannot show: --grading 2 without --graded, --max-size 0).
using GivenOptions = std::set<std::string, std::less<>>;

template <class Options>
struct Option : OptionDoc {
    void (*set)(Options&, const OptionValue&) = nullptr;
};

template <class Options>
struct OptionTable {
    std::vector<Option<Options>> options;
    // Values and contradictions (OptionError); mesh() calls it with nothing given.
    void (*validate)(const Options&, const GivenOptions&) = nullptr;

    const Option<Options>* find(std::string_view name) const {
        for (const auto& o : options)
            if (o.name == name) return &o;
        return nullptr;
    }
    // Option `name` from `text` (OptionError for an unknown name or a bad
    // text), recorded in `given`.
    void set(Options& o, GivenOptions& given, std::string_view name, std::string_view text) const {
        const Option<Options>* option = find(name);
        if (!option) throw OptionError(std::string(name), "unknown option '" + std::string(name) + "'");
        option->set(o, OptionValue{option->name, text});
        given.emplace(name);
    }
    std::vector<const OptionDoc*> docs() const {
        std::vector<const OptionDoc*> d;
        for (const auto& o : options) d.push_back(&o);
        return d;
    }
};

// The words of a names table (names.hpp), for OptionDoc::choices.
template <class E, std::size_t N>
std::vector<std::string_view> words_of(const std::array<Named<E>, N>& names) {
    std::vector<std::string_view> w;
    for (const auto& n : names) w.push_back(n.name);
    return w;
}

}  // namespace warpmesh
