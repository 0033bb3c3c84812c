// point_set.cpp — the ranks of a PointSet (point_set.hpp).
#include "mesh2d/graded/point_set.hpp"

#include <stdexcept>

namespace warpmesh {

// Band by band of block_rows rows: the band's flagged blocks once, then each
// row across them, so the prefix runs in point (row-major) order.
void PointSet::finish() {
    prefix.resize(words.size());  // written for the non-zero words, the only ones rank() reads
    std::int64_t n = 0;
    std::vector<std::int64_t> band;  // the flagged blocks of the current band
    for (std::int64_t j = 0; j < rows; ++j) {
        if ((j & (block_rows - 1)) == 0) {
            band.clear();
            for (std::int64_t bx = 0; bx < blocks_x; ++bx)
                if (flagged[static_cast<std::size_t>((j >> rows_log) * blocks_x + bx)]) band.push_back(bx);
        }
        for (const std::int64_t bx : band) {
            const std::size_t base = row_base(bx, j);
            for (std::size_t q = 0; q < static_cast<std::size_t>(block_words); ++q)
                if (const std::uint64_t w = words[base + q]) {
                    if (n > static_cast<std::int64_t>(UINT32_MAX) - bits::word_bits)
                        throw std::length_error("more lattice points in a point set than 32-bit ranks allow");
                    prefix[base + q] = static_cast<std::uint32_t>(n);
                    n += std::popcount(w);
                }
        }
    }
    count = n;
}

}  // namespace warpmesh
