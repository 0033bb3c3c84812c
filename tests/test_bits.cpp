// The word-level bit tools of the graded path (mesher/src/mesh2d/graded/bits.hpp),
// each against a plain loop over bits or bytes.
#define BOOST_TEST_MODULE bits
#include <boost/test/unit_test.hpp>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "mesh2d/graded/bits.hpp"

using namespace warpmesh;

namespace {

// Words with few, many and patterned bits: random, sparse, dense, edges.
std::vector<std::uint64_t> sample_words() {
    std::vector<std::uint64_t> w{0, ~std::uint64_t{0}, 1, std::uint64_t{1} << 63, 0x8000000000000001ull, 0x0102040810204080ull,
                                 0x8080808080808080ull, 0x7f7f7f7f7f7f7f7full, 0x0100010001000100ull, 0xff00ff00ff00ff00ull};
    std::mt19937_64 rng(21);
    for (int k = 0; k < 300; ++k) {
        const std::uint64_t a = rng(), b = rng(), c = rng();
        w.push_back(a);
        w.push_back(a & b & c);  // sparse
        w.push_back(a | b | c);  // dense
    }
    return w;
}

std::uint8_t byte_of(std::uint64_t w, int q) { return static_cast<std::uint8_t>(w >> (8 * q)); }

}  // namespace

BOOST_AUTO_TEST_CASE(low_bits_has_no_shift_by_64) {
    for (int n = 0; n <= 64; ++n) {
        std::uint64_t want = 0;
        for (int q = 0; q < n; ++q) want |= std::uint64_t{1} << q;
        BOOST_TEST(bits::low_bits(n) == want);
    }
    BOOST_TEST(bits::low_bits(100) == ~std::uint64_t{0});
}

BOOST_AUTO_TEST_CASE(count_below_is_the_rank_of_a_bit) {
    for (const std::uint64_t w : sample_words())
        for (int b = 0; b < 64; ++b) {
            int want = 0;
            for (int q = 0; q < b; ++q) want += static_cast<int>((w >> q) & 1);
            BOOST_TEST_REQUIRE(bits::count_below(w, b) == want);
        }
}

BOOST_AUTO_TEST_CASE(double_bits_and_even_bits_are_parent_and_child_rows) {
    for (const std::uint64_t w : sample_words()) {
        const std::uint64_t x = w & 0xffffffffull;
        std::uint64_t doubled = 0, even = 0;
        for (int k = 0; k < 32; ++k) {
            if ((x >> k) & 1) doubled |= std::uint64_t{3} << (2 * k);
            if ((w >> (2 * k)) & 1) even |= std::uint64_t{1} << k;
        }
        BOOST_TEST_REQUIRE(bits::double_bits(w) == doubled);  // the high half of the input is ignored
        BOOST_TEST_REQUIRE(bits::even_bits(w) == even);       // odd bits are ignored
        BOOST_TEST_REQUIRE(bits::even_bits(bits::double_bits(x)) == x);
    }
}

BOOST_AUTO_TEST_CASE(nonzero_bytes_gathers_one_bit_per_byte) {
    for (const std::uint64_t w : sample_words()) {
        std::uint64_t want = 0;
        bool zero = false;
        for (int q = 0; q < 8; ++q) {
            want |= static_cast<std::uint64_t>(byte_of(w, q) != 0) << q;
            zero = zero || byte_of(w, q) == 0;
        }
        BOOST_TEST_REQUIRE(bits::nonzero_bytes(w) == want);
        BOOST_TEST_REQUIRE(bits::has_zero_byte(w) == zero);
    }
    // Every one of the 256 byte values in every position (carries must not
    // leave a byte).
    for (int q = 0; q < 8; ++q)
        for (unsigned v = 0; v < 256; ++v) {
            const std::uint64_t w = static_cast<std::uint64_t>(v) << (8 * q) | 0x0101010101010101ull * (v == 0x80);
            std::uint64_t want = 0;
            for (int r = 0; r < 8; ++r) want |= static_cast<std::uint64_t>(byte_of(w, r) != 0) << r;
            BOOST_TEST_REQUIRE(bits::nonzero_bytes(w) == want);
        }
}

BOOST_AUTO_TEST_CASE(load8_reads_bytes_in_memory_order) {
    const std::array<std::uint8_t, 9> b{1, 2, 3, 4, 5, 6, 7, 8, 9};
    BOOST_TEST(bits::load8(b.data()) == 0x0807060504030201ull);
    BOOST_TEST(bits::load8(b.data() + 1) == 0x0908070605040302ull);  // unaligned
}

BOOST_AUTO_TEST_CASE(for_each_byte_visits_zero_or_nonzero_bytes_in_order) {
    std::mt19937 rng(7);
    for (const int n : {0, 1, 7, 8, 9, 16, 63, 64, 65, 200}) {
        for (const int density : {0, 1, 4, 8}) {  // non-zero bytes: none, sparse, half, all
            std::vector<std::int8_t> row(static_cast<std::size_t>(n));
            for (auto& v : row) v = static_cast<std::int8_t>(density && static_cast<int>(rng() % 8) < density ? (rng() % 2 ? 1 : -1) : 0);
            std::vector<std::int64_t> zero, nonzero, want_zero, want_nonzero;
            for (int q = 0; q < n; ++q) (row[static_cast<std::size_t>(q)] == 0 ? want_zero : want_nonzero).push_back(q);
            bits::for_each_byte<true>(row.data(), n, [&](std::int64_t q) { zero.push_back(q); });
            bits::for_each_byte<false>(row.data(), n, [&](std::int64_t q) { nonzero.push_back(q); });
            BOOST_TEST_REQUIRE((zero == want_zero));
            BOOST_TEST_REQUIRE((nonzero == want_nonzero));
        }
    }
}

BOOST_AUTO_TEST_CASE(for_each_bit_visits_set_bits_in_order) {
    for (const std::uint64_t w : sample_words()) {
        std::vector<int> seen, want;
        for (int q = 0; q < 64; ++q)
            if ((w >> q) & 1) want.push_back(q);
        bits::for_each_bit(w, [&](int q) { seen.push_back(q); });
        BOOST_TEST_REQUIRE((seen == want));
    }
}
