// errors.hpp — the exception type for bad user input.
//
// Everything that a user can get wrong — an unreadable or malformed image, a
// shape string that does not parse, a label that is not in the image — is
// reported as an InputError whose message names the offending file or string
// and the problem, so that the CLI can print it as is and exit with a
// "bad input" status, distinct from internal failures.
#pragma once

#include <stdexcept>

namespace warpmesh {

struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace warpmesh
