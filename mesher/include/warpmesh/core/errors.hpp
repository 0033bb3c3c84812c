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
//   OutputError  an output file could not be produced (directory missing, disk
//                full, unknown extension).  No partial file is left under the
//                requested name (atomic writes).
//
// Anything else that escapes — std::bad_alloc, std::logic_error from a failed
// internal check such as a certificate violation under verification — is an
// internal failure, not the caller's fault.
#pragma once

#include <stdexcept>

namespace warpmesh {

struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct OutputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace warpmesh
