// buffer.hpp — std::vector without the serial zero-fill.
//
// Buffer<T> is a std::vector whose resize() default-initialises its elements:
// for the trivial types of the large arrays (lattice values, signs, vertex ids,
// vertices, triangles) that means not touching the memory at all.  The first
// write then happens in the parallel loop that fills the array, each thread
// faulting in its own pages.  Why it matters: on the 2-core build machine a
// first touch (page fault and kernel zeroing) runs at about 1.6 GB/s per core,
// twenty times slower than rewriting touched memory, and a 4096² lattice
// needs about 0.9 GB; zero-filled by std::vector in the calling thread, that
// was over half of the meshing time, and all of it serial.
//
// The price: an element that no loop writes is indeterminate.  Every use below
// writes each element exactly once before reading it (the comments at the
// resize() calls say which loop).
//
// Large Buffers ask for transparent huge pages (Linux: madvise
// MADV_HUGEPAGE, a hint honoured where the kernel's THP mode is "madvise" or
// "always"): they are written whole, so 2 MB pages cost no memory, and they
// take a 512th of the page faults and of the TLB misses (a 3D lattice's
// arrays are hundreds of MB, and on virtual machines a page fault costs
// microseconds).  ZeroBuffer does not: it is also used for sparse arrays,
// whose untouched pages must stay unbacked.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace warpmesh {

// Huge pages for the whole 2 MB pages inside [p, p + bytes) if bytes is
// large (at least 16 MB); a hint, nothing happens where it is not supported.
inline void advise_huge_pages([[maybe_unused]] void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t huge = std::uintptr_t{1} << 21;
    if (bytes < (std::size_t{1} << 24)) return;
    const std::uintptr_t lo = (reinterpret_cast<std::uintptr_t>(p) + huge - 1) & ~(huge - 1),
                         hi = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(huge - 1);
    if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
#endif
}

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
    using value_type = T;
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() noexcept = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        T* p = std::allocator<T>::allocate(n);
        advise_huge_pages(p, n * sizeof(T));
        return p;
    }

    // T() would value-initialise (zero) — `new (p) U` default-initialises.
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <class T, class U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
    return true;
}

template <class T>
using Buffer = std::vector<T, DefaultInitAllocator<T>>;

// An allocator whose memory comes zeroed from calloc, for trivial types whose
// all-zero bytes are the value 0.  Elements are never written on
// construction, so a ZeroBuffer is all zeros without being touched: a large
// calloc is fresh pages the kernel zeroes on first use, and a sparse array
// (the graded mesher's point bitsets, mostly empty away from the boundary)
// costs only the pages it writes.
//
// Its rebind member and converting constructor repeat DefaultInitAllocator's:
// the allocator requirements ask every allocator type for its own (rebind
// must name ZeroAllocator<U>, not the base), so the pair is intended.
template <class T>
struct ZeroAllocator : DefaultInitAllocator<T> {
    static_assert(std::is_trivial_v<T>);
    using value_type = T;
    template <class U>
    struct rebind {
        using other = ZeroAllocator<U>;
    };
    ZeroAllocator() noexcept = default;
    template <class U>
    ZeroAllocator(const ZeroAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        void* p = std::calloc(n, sizeof(T));
        if (!p) throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t) noexcept { std::free(p); }
};

template <class T, class U>
bool operator==(const ZeroAllocator<T>&, const ZeroAllocator<U>&) noexcept {
    return true;
}

template <class T>
using ZeroBuffer = std::vector<T, ZeroAllocator<T>>;

}  // namespace warpmesh
