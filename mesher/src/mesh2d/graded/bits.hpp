// bits.hpp — the word-level bit tools of the graded path: masks, counts,
// interleaving, and byte rows read as words.  Private to mesher/src; tested
// by tests/test_bits.cpp.
//
// Conventions: bit q of a 64-bit word stands for the element at offset q of a
// run (a point, a node, a byte); "byte q" of a word is the q-th byte of eight
// loaded from memory in order (little-endian, as on every target we build).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

namespace warpmesh::bits {

static_assert(std::endian::native == std::endian::little, "byte q of a loaded word must be bits 8q .. 8q + 7");

inline constexpr int word_bits = 64;
inline constexpr int word_log = 6;  // word_bits = 2^word_log
static_assert(word_bits == 1 << word_log);

// Bits 0 .. n - 1 set, 0 <= n <= 64 (a shift by 64 would be undefined).
constexpr std::uint64_t low_bits(std::int64_t n) { return n >= word_bits ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1; }

// The number of set bits of w below bit b, 0 <= b < 64: the rank of bit b
// among w's set bits.
constexpr int count_below(std::uint64_t w, int b) { return std::popcount(w & ((std::uint64_t{1} << b) - 1)); }

// Bit k of x < 2^32 to bits 2k and 2k + 1 (each bit doubled: a row of nodes
// seen as the row of their children).  Interleaving by halving masks.
constexpr std::uint64_t double_bits(std::uint64_t x) {
    x &= 0xffffffffull;
    x = (x | x << 16) & 0x0000ffff0000ffffull;
    x = (x | x << 8) & 0x00ff00ff00ff00ffull;
    x = (x | x << 4) & 0x0f0f0f0f0f0f0f0full;
    x = (x | x << 2) & 0x3333333333333333ull;
    x = (x | x << 1) & 0x5555555555555555ull;
    return x | x << 1;
}

// Bits 0, 2, 4, ... of x to bits 0, 1, 2, ... (odd bits ignored; a row of
// children seen as the row of their parents, one bit per pair).
constexpr std::uint64_t even_bits(std::uint64_t x) {
    x &= 0x5555555555555555ull;
    x = (x | x >> 1) & 0x3333333333333333ull;
    x = (x | x >> 2) & 0x0f0f0f0f0f0f0f0full;
    x = (x | x >> 4) & 0x00ff00ff00ff00ffull;
    x = (x | x >> 8) & 0x0000ffff0000ffffull;
    x = (x | x >> 16) & 0x00000000ffffffffull;
    return x;
}

// Bytes of a word: a byte's value repeated, and the high bit of every byte.
inline constexpr std::uint64_t byte_ones = 0x0101010101010101ull, byte_highs = 0x8080808080808080ull,
                               byte_low7 = 0x7f7f7f7f7f7f7f7full;

// Eight consecutive bytes as one word (byte q = p[q]).
template <class T>
inline std::uint64_t load8(const T* p) {
    static_assert(sizeof(T) == 1);
    std::uint64_t w;
    std::memcpy(&w, p, 8);
    return w;
}

// Bit q set iff byte q of w is non-zero.  Per byte, adding 0x7f to its low
// seven bits carries into the high bit iff they are non-zero (never beyond
// the byte), and or-ing the byte itself adds its own high bit; then the eight
// high bits, shifted to 8q, are gathered into bits 56 + q by one
// multiplication: the bit at 8q times the byte 2^(7 - m) at 8m lands at
// 8(q + m) + 7 - m, in the top byte iff q + m = 7, at 56 + q.  The products
// of one sum q + m fill distinct bits of byte q + m, so no two products share
// a bit and nothing carries.
constexpr std::uint64_t nonzero_bytes(std::uint64_t w) {
    constexpr std::uint64_t gather = 0x0102040810204080ull;  // byte m = 2^(7 - m)
    const std::uint64_t highs = (((w & byte_low7) + byte_low7) | w) & byte_highs;
    return (highs >> 7) * gather >> 56;
}

// Whether some byte of w is zero (the classic test: subtracting 1 from every
// byte borrows into a byte's high bit only past a zero byte, the lowest one
// exactly, and ~w drops bytes whose high bit was already set).
constexpr bool has_zero_byte(std::uint64_t w) { return ((w - byte_ones) & ~w & byte_highs) != 0; }

// fn(q) for every q < n with (row[q] == 0) == Zero, in increasing q: eight
// bytes at a time, skipping words with none of interest (the sparse scans of
// split flags and coarsening codes).
template <bool Zero, class T, class Fn>
inline void for_each_byte(const T* row, std::int64_t n, Fn&& fn) {
    static_assert(sizeof(T) == 1);
    std::int64_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const std::uint64_t w = load8(row + i);
        if (!(Zero ? has_zero_byte(w) : w != 0)) continue;
        for (std::int64_t q = i; q < i + 8; ++q)
            if ((row[q] == 0) == Zero) fn(q);
    }
    for (; i < n; ++i)
        if ((row[i] == 0) == Zero) fn(i);
}

// fn(q) for every set bit q of w, in increasing q.
template <class Fn>
inline void for_each_bit(std::uint64_t w, Fn&& fn) {
    for (; w; w &= w - 1) fn(std::countr_zero(w));
}

}  // namespace warpmesh::bits
