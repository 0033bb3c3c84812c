// point_set.hpp — a set of lattice points with O(1) ranks, stored and
// touched only where it has members.  Private to mesher/src (graded path);
// tested in tests/test_graded.cpp.
#pragma once

#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <vector>

#include "mesh2d/graded/bits.hpp"
#include "warpmesh/core/buffer.hpp"

namespace warpmesh {

// A set of lattice points (i, j), one bit each, with ranks: after finish(),
// rank(p) of a member p is the number of members before p in point
// (row-major) order, in O(1) — so a sorted list indexed by members (the
// warped points, the compacted vertices) needs no lattice-sized index array.
//
// Storage is blocked: block_words words (block_words x 64 points) by
// block_rows rows make a block of one 4 KiB page, and each block has a flag
// "holds a member".  A set that follows a curve then touches only the pages
// the curve crosses (a row-major bitset would touch every row's), and the
// scans in point order visit flagged blocks only.  Within a block the words
// are row-major; blocks are row-major too.
struct PointSet {
    static constexpr int block_words = 4, block_rows = 128;
    static_assert(std::has_single_bit(unsigned{block_words}) && std::has_single_bit(unsigned{block_rows}),
                  "blocks are addressed by shifts and masks");
    static constexpr int words_log = std::countr_zero(unsigned{block_words});           // block_words = 2^words_log
    static constexpr int rows_log = std::countr_zero(unsigned{block_rows});             // block_rows = 2^rows_log
    static constexpr int points_log = bits::word_log + words_log;                       // points a block row: 2^points_log
    static constexpr std::int64_t block_size = std::int64_t{block_words} * block_rows;  // words a block
    static_assert(block_size * 8 == 4096, "a block is one 4 KiB page");

    std::int64_t words_per_row = 0, rows = 0, blocks_x = 0, blocks_y = 0;
    ZeroBuffer<std::uint64_t> words;    // zeroed, touched only where written (buffer.hpp)
    Buffer<std::uint32_t> prefix;       // per non-zero word, members before it (after finish; < 2^32)
    std::vector<std::uint8_t> flagged;  // per block: 1 if it may hold a member
    std::int64_t count = 0;             // members (after finish)

    PointSet() = default;
    PointSet(std::int64_t points_x, std::int64_t nrows)
        : words_per_row((points_x + bits::word_bits - 1) >> bits::word_log),
          rows(nrows),
          blocks_x((words_per_row + block_words - 1) >> words_log),
          blocks_y((nrows + block_rows - 1) >> rows_log),
          words(static_cast<std::size_t>(blocks_x * blocks_y * block_size)),
          flagged(static_cast<std::size_t>(blocks_x * blocks_y), 0) {}

    // Point (i, j): its block, its word, its bit — shifts and masks only, no
    // division on the hot paths.
    std::size_t block(std::int64_t i, std::int64_t j) const {
        return static_cast<std::size_t>((j >> rows_log) * blocks_x + (i >> points_log));
    }
    // The first word of row j in block (bx, j >> rows_log).
    std::size_t row_base(std::int64_t bx, std::int64_t j) const {
        return static_cast<std::size_t>(((j >> rows_log) * blocks_x + bx) * block_size + ((j & (block_rows - 1)) << words_log));
    }
    std::size_t word(std::int64_t i, std::int64_t j) const {
        return block(i, j) * block_size +
               static_cast<std::size_t>(((j & (block_rows - 1)) << words_log) + ((i >> bits::word_log) & (block_words - 1)));
    }
    static int bit_of(std::int64_t i) { return static_cast<int>(i & (bits::word_bits - 1)); }
    static std::uint64_t bit(std::int64_t i) { return std::uint64_t{1} << bit_of(i); }

    bool contains(std::int64_t i, std::int64_t j) const { return words[word(i, j)] & bit(i); }
    void insert(std::int64_t i, std::int64_t j) { insert_bits<false>(i, j, 1); }
    // Points (i + k, j) for the bits k of rel (non-zero): at most two words,
    // the one of i and the next, since k < 64.  `concurrent`: for threads
    // marking the same set at once (relaxed atomics).
    template <bool concurrent>
    void insert_bits(std::int64_t i, std::int64_t j, std::uint64_t rel) {
        const int b = bit_of(i);
        or_word<concurrent>(i, j, rel << b);
        if (b && (rel >> (bits::word_bits - b))) or_word<concurrent>(i - b + bits::word_bits, j, rel >> (bits::word_bits - b));
    }

    // Membership of (i + q, j), q < n <= 64, as bit q: the word of i and,
    // past its end, the next (the points must lie in the row).
    std::uint64_t members(std::int64_t i, std::int64_t j, int n) const {
        const int b = bit_of(i);
        std::uint64_t m = words[word(i, j)] >> b;
        if (b + n > bits::word_bits) m |= words[word(i - b + bits::word_bits, j)] << (bits::word_bits - b);
        return m & bits::low_bits(n);
    }

    // Prefix sums and count.  Throws std::length_error beyond 2^32 - 1
    // members (a mesh's vertex ids are 32-bit anyway).
    void finish();

    // Members before (i, j) in point order: its vertex id if a member.  A
    // word with no member has no prefix written, and is not read (0).
    std::int64_t rank(std::int64_t i, std::int64_t j) const {
        const std::size_t w = word(i, j);
        return words[w] ? rank_in_word(w, bit_of(i)) : 0;
    }
    // Members before bit b of word w, a word with a member (after finish).
    std::int64_t rank_in_word(std::size_t w, int b) const {
        return static_cast<std::int64_t>(prefix[w]) + bits::count_below(words[w], b);
    }
    // rank(i + q, j) for q < n <= 3 (the points must lie in the row), valid
    // for the members among them: one word's prefix and bits, unless the run
    // crosses into the next word.
    std::array<std::int64_t, 3> rank_run(std::int64_t i, std::int64_t j, int n) const {
        const int b = bit_of(i);
        std::array<std::int64_t, 3> r{};
        if (b + n > bits::word_bits) {
            for (int q = 0; q < n; ++q) r[static_cast<std::size_t>(q)] = rank(i + q, j);
            return r;
        }
        const std::size_t w = word(i, j);
        const std::uint64_t m = words[w] >> b;
        if (!m) return r;  // no member among them
        r[0] = rank_in_word(w, b);
        r[1] = r[0] + static_cast<std::int64_t>(m & 1);
        r[2] = r[1] + static_cast<std::int64_t>((m >> 1) & 1);
        return r;
    }
    // fn(w, i0, bits, rank0) for every non-zero word of row j, in increasing
    // i (after finish): its index w, its first point i0, its members and the
    // rank of its first member.  Point sets of the same dimensions share the
    // word layout, so w indexes theirs too.
    template <class Fn>
    void for_each_word_in_row(std::int64_t j, Fn&& fn) const {
        const std::int64_t by = j >> rows_log;
        for (std::int64_t bx = 0; bx < blocks_x; ++bx) {
            if (!flagged[static_cast<std::size_t>(by * blocks_x + bx)]) continue;
            const std::size_t base = row_base(bx, j);
            for (int q = 0; q < block_words; ++q)
                if (const std::uint64_t m = words[base + static_cast<std::size_t>(q)])
                    fn(base + static_cast<std::size_t>(q), ((bx << words_log) + q) << bits::word_log, m,
                       static_cast<std::int64_t>(prefix[base + static_cast<std::size_t>(q)]));
        }
    }

private:
    template <bool concurrent>
    void or_word(std::int64_t i, std::int64_t j, std::uint64_t m) {
        if constexpr (concurrent) {
            std::atomic_ref<std::uint64_t>(words[word(i, j)]).fetch_or(m, std::memory_order_relaxed);
            std::atomic_ref<std::uint8_t>(flagged[block(i, j)]).store(1, std::memory_order_relaxed);
        } else {
            words[word(i, j)] |= m;
            flagged[block(i, j)] = 1;
        }
    }
};

}  // namespace warpmesh
