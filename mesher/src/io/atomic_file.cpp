// atomic_file.cpp — temporary file in the target directory + rename(2).
#include "io/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

namespace warpmesh {

namespace {

constexpr std::size_t stream_buffer_size = std::size_t{1} << 20;

std::string errno_text(int e) { return std::strerror(e); }

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    namespace fs = std::filesystem;
    const fs::path target(path_);
    const std::string name = target.filename().string();
    if (path_.empty() || name.empty() || name == "." || name == "..")
        throw OutputError("cannot write '" + path_ + "': not a file name");
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");

    // mkstemp wants a writable, NUL-terminated template ending in XXXXXX.
    const std::string pattern = (dir / ("." + name + ".tmp.XXXXXX")).string();
    std::vector<char> templ(pattern.begin(), pattern.end());
    templ.push_back('\0');
    const int fd = ::mkstemp(templ.data());
    if (fd < 0) {
        const int e = errno;
        throw OutputError("cannot write '" + path_ + "': cannot create a temporary file in '" + dir.string() +
                          "': " + errno_text(e));
    }
    temp_.assign(templ.data());

    // mkstemp creates mode 0600; give the file the mode a plain open would.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(fd, static_cast<mode_t>(0666 & ~mask));
    ::close(fd);

    buffer_ = std::make_unique<char[]>(stream_buffer_size);
    out_.rdbuf()->pubsetbuf(buffer_.get(), static_cast<std::streamsize>(stream_buffer_size));  // before open
    out_.open(temp_, std::ios::binary | std::ios::trunc);
    if (!out_) {
        const int e = errno;
        fail("cannot open the temporary file '" + temp_ + "': " + errno_text(e));
    }
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::fail(const std::string& reason) {
    discard();
    throw OutputError("cannot write '" + path_ + "': " + reason);
}

void AtomicFile::close() {
    if (closed_) return;
    auto reason = [](const char* what, int e) { return std::string(what) + (e ? ": " + errno_text(e) : std::string()); };
    if (!out_) fail(reason("write error", errno));  // an earlier write failed (e.g. ENOSPC)
    errno = 0;
    out_.flush();
    if (!out_) fail(reason("write error on flush", errno));
    errno = 0;
    out_.close();
    if (!out_) fail(reason("write error on close", errno));
    closed_ = true;
}

void AtomicFile::commit() {
    if (committed_) return;
    close();
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
        const int e = errno;
        fail("cannot rename the temporary file '" + temp_ + "': " + errno_text(e));
    }
    committed_ = true;
}

void AtomicFile::discard() noexcept {
    if (committed_ || temp_.empty()) return;
    if (out_.is_open()) out_.close();
    ::unlink(temp_.c_str());
    temp_.clear();
    closed_ = true;
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& body) {
    AtomicFile file(path);
    try {
        body(file.stream());
    } catch (const OutputError&) {
        file.discard();
        throw;
    } catch (const std::exception& e) {
        file.discard();
        throw OutputError("cannot write '" + path + "': " + e.what());
    }
    file.commit();
}

}  // namespace warpmesh
