// SPDX-License-Identifier: MIT
#pragma once
/// @file beams.hpp  The explicit beam network of a foam inside a box: nodes (Voronoi vertices and
/// the points where edges leave the box), edges, and a radius per edge (tau at its midpoint).
///
/// Usage:
///   beam_network net = extract_beams(foam, {{0,0,0},{10,10,10}});
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/evaluator.hpp"

namespace fabsynth::foam {

/// Nodes (mm), edges (pairs of node indices) and per-edge radii (mm).
struct beam_network {
    std::vector<vec3> nodes;
    std::vector<std::array<std::uint32_t, 2>> edges;
    std::vector<double> radii;
};

/// Beam network of the foam's Voronoi edges clipped to box b. Node positions are merged by
/// rounding to a 1e-7 mm grid (edge pieces meeting at a vertex come from different cells; a
/// position straddling a rounding boundary can rarely leave a duplicate node). The box is
/// processed in chunks of at most 4 coarse cells a side; it may span at most 1e6 chunks.
template <class Foam>
[[nodiscard]] beam_network extract_beams(const Foam& f, const box3& b) {
    if (b.empty() || !all_finite(b.lo) || !all_finite(b.hi)) throw invalid_input("extract_beams: box is empty or not finite");
    const double chunk = 4 * f.options().cell;
    const ivec3 n = glm::max(ivec3(1), ivec3(glm::ceil(b.size() / chunk)));
    if (double(n.x) * n.y * n.z > 1e6) throw invalid_input("extract_beams: box too large");
    const vec3 step = b.size() / vec3(n);
    beam_network net;
    std::unordered_map<std::uint64_t, std::uint32_t> index;
    const double q = 1e-7;
    auto node = [&](const vec3& p) {
        const auto key = [&](const vec3& v) {
            const auto k = glm::i64vec3(glm::round(v / q));
            return hash64(0, k.x, k.y, k.z);
        };
        const std::uint64_t h = key(p);
        if (auto it = index.find(h); it != index.end()) return it->second;
        net.nodes.push_back(p);
        const auto id = static_cast<std::uint32_t>(net.nodes.size() - 1);
        index.emplace(h, id);
        return id;
    };
    std::vector<edge_segment> segs;
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                const box3 c(b.lo + step * vec3(x, y, z), b.lo + step * vec3(x + 1, y + 1, z + 1));
                segs.clear();
                f.edges_in_box(c, segs);
                for (const auto& s : segs) {
                    if (glm::length(s.b - s.a) < q) continue;
                    const std::uint32_t i = node(s.a), j = node(s.b);
                    if (i == j) continue;
                    net.edges.push_back({i, j});
                    net.radii.push_back(f.radius(0.5 * (s.a + s.b)));
                }
            }
    return net;
}

}  // namespace fabsynth::foam
