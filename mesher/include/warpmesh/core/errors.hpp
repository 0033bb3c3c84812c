// errors.hpp — the exception types of the library.
//
// Every function of the library reports a failure the caller can act on by
// one of these two types, whose message names the offending file, string or
// option and the problem, so that a command line can print it as is.  Nothing
// in the library calls exit() or prints.
//
//   InputError   bad user input: an unreadable or malformed image, a shape
//                string that does not parse, a label absent from the image, an
//                option out of range, a lattice over the size limits, an empty
//                region.  Nothing has been written.
//   OptionError  an InputError about options (pipeline/options.hpp): a value
//                out of range, options that contradict each other.  Its
//                message names every option it mentions in the library's
//                words, marked: {name} (e.g. {max_memory}) or {name=value}
//                for a setting (e.g. {graded=true}); what() reads the marks
//                as name and name=value, and a client spells them its own way
//                (the command line as flags, --max-memory, --graded; Python
//                as keywords, graded=True).
//   OutputError  an output file could not be produced (directory missing, disk
//                full, unknown extension).  No partial file is left under the
//                requested name (atomic writes).
//
// Anything else that escapes — std::bad_alloc, std::logic_error from a failed
// internal check such as a certificate violation under verification — is an
// internal failure, not the caller's fault.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace warpmesh {

struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// `text` with every mark {name} or {name=value} (name: a lower-case letter,
// then lower-case letters, digits and '_') replaced by spell(name, value), value empty for {name};
// other braces are kept.
std::string spell_marks(std::string_view text,
                        const std::function<std::string(std::string_view name, std::string_view value)>& spell);

class OptionError : public InputError {
public:
    // `option`: the option at fault, by name; `message`: with marks.
    OptionError(std::string option, std::string message);
    const std::string& option() const { return option_; }
    const std::string& message() const { return message_; }

private:
    std::string option_, message_;
};

struct OutputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace warpmesh
