// Progress of a proof over many keys, for a user at a terminal.
//
// Contract: when standard error is a terminal, KeyProgress keeps one line
// there, "<name>: <done> of <total> keys, <seconds> s", rewritten in place at
// most every half second as keys are finished (tick(), callable from any
// thread, e.g. inside an OpenMP loop) and erased when the object is
// destroyed, so that the summary line the tools print afterwards stands
// alone.  When standard error is not a terminal (logs, pipes, CTest, CI) it
// writes nothing: the output of a run is the same with or without it.
// Standard output is never touched.
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <utility>

namespace warpmesh::prover {

class KeyProgress {
public:
    KeyProgress(std::string name, long total) : name_(std::move(name)), total_(total), on_(::isatty(STDERR_FILENO) == 1) {}
    KeyProgress(const KeyProgress&) = delete;
    KeyProgress& operator=(const KeyProgress&) = delete;
    ~KeyProgress() {
        if (shown_) std::fprintf(stderr, "\r\033[K");  // carriage return, erase the line
    }
    void tick() {
        const long done = ++done_;
        if (!on_) return;
        const auto now = std::chrono::steady_clock::now();
        const std::lock_guard<std::mutex> lock(mutex_);
        if (shown_ && now - last_ < std::chrono::milliseconds(500)) return;
        last_ = now, shown_ = true;
        std::fprintf(stderr, "\r%s: %ld of %ld keys, %.0f s\033[K", name_.c_str(), done, total_,
                     std::chrono::duration<double>(now - start_).count());
        std::fflush(stderr);
    }

private:
    std::string name_;
    long total_;
    bool on_;
    bool shown_ = false;
    std::atomic<long> done_{0};
    std::mutex mutex_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_{};
};

}  // namespace warpmesh::prover
