// SPDX-License-Identifier: MIT
#pragma once
/// @file neighbourhood.hpp  6-, 18- and 26-neighbourhoods of a voxel as compile-time offset tables.
///
/// Usage:
///   for (auto o : fabsynth::connectivity::c26::offsets) visit(p + ivec3(o[0], o[1], o[2]));
#include <array>
#include <concepts>
#include <cstddef>

#include "fabsynth/core/types.hpp"

namespace fabsynth {

namespace detail {
/// All offsets in {-1,0,1}^3 \ {0} with 1 <= |dx|+|dy|+|dz| <= max_l1, in x-fastest order.
template <int MaxL1, std::size_t N>
constexpr std::array<std::array<int, 3>, N> make_offsets() {
    std::array<std::array<int, 3>, N> out{};
    std::size_t n = 0;
    for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x) {
                const int l1 = (x != 0) + (y != 0) + (z != 0);
                if (l1 >= 1 && l1 <= MaxL1) out[n++] = {x, y, z};
            }
    return out;
}
}  // namespace detail

namespace connectivity {
/// Face neighbours (share a face).
struct c6 {
    static constexpr std::array<std::array<int, 3>, 6> offsets = detail::make_offsets<1, 6>();
};
/// Face and edge neighbours.
struct c18 {
    static constexpr std::array<std::array<int, 3>, 18> offsets = detail::make_offsets<2, 18>();
};
/// Face, edge and corner neighbours (touch by a corner).
struct c26 {
    static constexpr std::array<std::array<int, 3>, 26> offsets = detail::make_offsets<3, 26>();
};
}  // namespace connectivity

/// A neighbourhood policy: a static constexpr array `offsets` of {dx, dy, dz} triples, symmetric
/// (o in offsets implies -o in offsets).
template <class C>
concept neighbourhood = requires {
    { C::offsets.size() } -> std::convertible_to<std::size_t>;
    { C::offsets[0][0] } -> std::convertible_to<int>;
};

/// Offset as an ivec3.
[[nodiscard]] inline ivec3 as_ivec3(const std::array<int, 3>& o) noexcept { return {o[0], o[1], o[2]}; }

static_assert(neighbourhood<connectivity::c6> && neighbourhood<connectivity::c18> && neighbourhood<connectivity::c26>);

}  // namespace fabsynth
