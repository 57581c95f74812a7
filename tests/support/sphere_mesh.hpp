#pragma once
// Test shapes shared by several test modules.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth::test {

// Closed icosphere-like test mesh: an octahedron subdivided n times and projected to radius r.
inline triangle_mesh sphere_mesh(double r, int n) {
    triangle_mesh m;
    m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    m.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int it = 0; it < n; ++it) {
        triangle_mesh o;
        o.vertices = m.vertices;
        std::vector<std::pair<std::uint64_t, std::uint32_t>> mids;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            for (auto& [k, v] : mids)
                if (k == key) return v;
            o.vertices.push_back(glm::normalize(m.vertices[a] + m.vertices[b]));
            mids.push_back({key, static_cast<std::uint32_t>(o.vertices.size() - 1)});
            return mids.back().second;
        };
        for (const auto& t : m.faces) {
            const std::uint32_t a = mid(t[0], t[1]), b = mid(t[1], t[2]), c = mid(t[2], t[0]);
            o.faces.push_back({t[0], a, c});
            o.faces.push_back({a, t[1], b});
            o.faces.push_back({c, b, t[2]});
            o.faces.push_back({a, b, c});
        }
        m = std::move(o);
    }
    for (auto& v : m.vertices) v = glm::normalize(v) * r;
    return m;
}

}  // namespace fabsynth::test
