// square_keys.cpp — the key codes of the generic square's configurations
// (square_keys.hpp).
#include "warpmesh/mesh2d/square_keys.hpp"

namespace warpmesh {

namespace {
constexpr char warp_chars[] = {'s', 'R', 'L', 'U', 'D'};  // Warp::stay, px, mx, py, my
}  // namespace

std::string key_code(const std::array<CornerState, 4>& cs) {
    std::string s;
    for (const auto& c : cs) {
        s += c.sign < 0 ? '-' : c.sign == 0 ? '0' : '+';
        s += warp_chars[static_cast<int>(c.warp)];
    }
    return s;
}

std::string junction_key_code(const std::array<MaterialCorner, 4>& cs) {
    std::string s;
    for (const auto& c : cs) {
        s += static_cast<char>('a' + c.material);
        s += warp_chars[static_cast<int>(c.warp)];
    }
    return s;
}

std::array<MaterialCorner, 4> junction_letters(const std::array<MaterialCorner, 4>& cs) {
    std::array<MaterialCorner, 4> out{};
    std::uint16_t next = 0;
    for (std::size_t q = 0; q < 4; ++q) {
        out[q] = {next, cs[q].warp};
        for (std::size_t e = 0; e < q; ++e)
            if (cs[e].material == cs[q].material) {
                out[q].material = out[e].material;
                break;
            }
        if (out[q].material == next) ++next;
    }
    return out;
}

}  // namespace warpmesh
