// SPDX-License-Identifier: MIT
#pragma once
/// @file weld.hpp  Merges vertices with exactly equal positions (for STL's triangle soups).
#include <array>
#include <bit>
#include <cstdint>
#include <unordered_map>

#include "fabsynth/core/rng.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth::io::detail {

/// Builds an indexed mesh from corner positions, giving equal positions (== on doubles, so
/// -0 and +0 coincide) one vertex, numbered in order of first appearance.
class vertex_welder {
public:
    explicit vertex_welder(triangle_mesh& m) : mesh_(m) {}

    std::uint32_t add(const vec3& p) {
        const key k{bits(p.x), bits(p.y), bits(p.z)};
        const auto [it, inserted] = index_.try_emplace(k, static_cast<std::uint32_t>(mesh_.vertices.size()));
        if (inserted) mesh_.vertices.push_back(p);
        return it->second;
    }

private:
    using key = std::array<std::uint64_t, 3>;
    struct key_hash {
        std::size_t operator()(const key& k) const noexcept {
            return static_cast<std::size_t>(hash64(0, k[0], k[1], k[2]));
        }
    };
    static std::uint64_t bits(double x) noexcept { return std::bit_cast<std::uint64_t>(x + 0.0); }  // -0 -> +0

    triangle_mesh& mesh_;
    std::unordered_map<key, std::uint32_t, key_hash> index_;
};

}  // namespace fabsynth::io::detail
