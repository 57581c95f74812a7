#pragma once
// Test shapes shared by several test modules.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include <cmath>
#include <numbers>

#include "fabsynth/core/rng.hpp"
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

/// An (n+1) x (n+1) grid of spacing h in the plane z = 0, vertices jittered in x and y by up to
/// jitter * h (0: a regular grid; jitter_border false: the border vertices stay on the square),
/// each quad split into two counter-clockwise triangles (normal +z), vertex (i, j) at index
/// j (n + 1) + i.
inline triangle_mesh plane_grid(int n, double h, std::uint64_t seed, double jitter = 0.2, bool jitter_border = true) {
    triangle_mesh m;
    counter_rng rng(seed);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double jy = rng.uniform(-jitter, jitter) * h;  // y first: the draws of the former argument order (GCC)
            const double jx = rng.uniform(-jitter, jitter) * h;
            const bool move = jitter_border || (i > 0 && j > 0 && i < n && j < n);
            m.vertices.emplace_back(i * h + (move ? jx : 0.0), j * h + (move ? jy : 0.0), 0.0);
        }
    auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

/// The open cylinder x^2 + y^2 = r^2, 0 <= z <= height: `around` segments, rings every dz,
/// outward normals.
inline triangle_mesh cylinder(double r, double height, int around, double dz) {
    triangle_mesh m;
    const int rings = static_cast<int>(std::round(height / dz));
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i < around; ++i) {
            const double a = 2 * std::numbers::pi * i / around;
            m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), j * dz);
        }
    auto id = [around](int i, int j) { return static_cast<std::uint32_t>(j * around + (i % around)); };
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < around; ++i) {
            m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

}  // namespace fabsynth::test
