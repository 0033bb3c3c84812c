// witness_image.hpp — the 16-bit PGM that realises the separating and
// max-min rules' 15° witness (-R+U-L-R): f = pixel - 30000, inside below;
// lattice square (2, 2) has t = (1/2, a/(a+d) ~ 0.13397, 1/2, 1/2), where
// both diagonals have a 15.0000° angle (test_certified_mesh.cpp explains the
// stencil).  Shared by test_certified_mesh (the 15° floor is real) and
// test_fan_rule (the fan rule lifts it above atan(1/3)).
#pragma once
#include <filesystem>
#include <fstream>
#include <vector>

namespace warpmesh::testing {

inline void write_witness_image(const std::filesystem::path& img) {
    constexpr int W = 8, H = 8, iso = 30000, a = 2680, d = 17324, c = 5000;
    std::vector<std::vector<int>> v(H, std::vector<int>(W, iso - 10000));  // v[y][x]
    auto put = [&](int x, int y, int f) { v[static_cast<std::size_t>(y)][static_cast<std::size_t>(x)] = iso + f; };
    put(2, 2, -a), put(3, 2, +a), put(2, 3, -c), put(3, 3, -d);
    put(1, 3, +c), put(4, 3, +d);
    put(1, 2, -a), put(2, 1, -a), put(2, 4, -c), put(3, 4, -d), put(4, 2, +a), put(3, 1, +a);
    for (auto& row : v)
        for (int x = 5; x < W; ++x) row[static_cast<std::size_t>(x)] = iso + 10000;
    std::ofstream out(img, std::ios::binary);
    out << "P5\n" << W << " " << H << "\n65535\n";
    for (int r = 0; r < H; ++r)
        for (int x = 0; x < W; ++x) {
            const int p = v[static_cast<std::size_t>(H - 1 - r)][static_cast<std::size_t>(x)];
            out.put(static_cast<char>(p >> 8)).put(static_cast<char>(p & 255));
        }
}

}  // namespace warpmesh::testing
