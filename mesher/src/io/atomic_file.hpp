// atomic_file.hpp — write a file so that it either appears complete under its
// name or not at all.
//
// The body writes into a temporary file created (mkstemp) in the *target's
// directory* — `DIR/.NAME.tmp.XXXXXX` — so that the final rename(2) stays on
// one file system and is atomic.  The stream state is checked after the body,
// after flush and after close (a full disk or an NFS error may only surface
// there); on any failure the temporary is removed and an OutputError naming the
// requested path and the reason is thrown.  An existing file under the name is
// replaced only on success.  The new file gets mode 0666 & ~umask, as if
// opened normally.
#pragma once

#include <fstream>
#include <functional>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>

#include "warpmesh/core/errors.hpp"

namespace warpmesh {

// One file being written atomically.  Construction creates the temporary;
// stream() is where the content goes; commit() checks, closes and renames.
// Destroying an uncommitted AtomicFile removes the temporary.  Useful when
// several files must be complete before any of them is renamed (Triangle's
// .node/.ele); for one file prefer write_file_atomically.
class AtomicFile {
public:
    explicit AtomicFile(std::string path);  // throws OutputError
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ostream& stream() { return out_; }
    const std::string& path() const { return path_; }
    const std::string& temp_path() const { return temp_; }

    // Flush and close the temporary and check that every write succeeded;
    // throws OutputError (and removes the temporary) otherwise.  Idempotent.
    void close();
    // close(), then rename the temporary onto the path.  Throws OutputError.
    void commit();
    // Remove the temporary (no-op once committed).  Never throws.
    void discard() noexcept;

private:
    [[noreturn]] void fail(const std::string& reason);

    std::string path_, temp_;
    std::unique_ptr<char[]> buffer_;
    std::ofstream out_;
    bool closed_ = false, committed_ = false;
};

// Writes `path` atomically with `body`.  Exceptions thrown by the body are
// rethrown as OutputError("cannot write 'PATH': <what>") after the temporary is
// removed (an OutputError from the body is rethrown unchanged).
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& body);

namespace detail {
// Writes `f`'s content with body(f.stream()) and closes it (not yet renamed:
// for formats of several files, each f.commit() once all are complete).  Any
// exception from the body becomes OutputError("cannot write 'PATH': …").
void fill_atomic_file(AtomicFile& f, const std::function<void(std::ostream&)>& body);
}  // namespace detail

}  // namespace warpmesh
