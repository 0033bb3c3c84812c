// Random label images for the multi-material tests (test_materials,
// test_material_relabel,
// test_optimize_materials).
#pragma once

#include <array>
#include <random>
#include <vector>

#include "warpmesh/io/image.hpp"

namespace warpmesh::testing {

// Blobs: a few seeds with labels 0..labels, each pixel takes the nearest
// seed's label.
inline Image random_label_image(std::mt19937& rng, int w, int h, int labels) {
    Image img;
    img.width = w, img.height = h, img.maxval = 255, img.source = "random";
    img.pixels.resize(static_cast<std::size_t>(w * h));
    std::uniform_int_distribution<int> lab(0, labels), px(0, w - 1), py(0, h - 1);
    std::vector<std::array<int, 3>> seeds;
    for (int k = 0; k < 2 + labels; ++k) seeds.push_back({px(rng), py(rng), lab(rng)});
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            int best = 1 << 30, l = 0;
            for (const auto& s : seeds) {
                const int d = (s[0] - c) * (s[0] - c) + (s[1] - r) * (s[1] - r);
                if (d < best) best = d, l = s[2];
            }
            img.pixels[static_cast<std::size_t>(r * w + c)] = static_cast<std::uint16_t>(l);
        }
    return img;
}

}  // namespace warpmesh::testing
