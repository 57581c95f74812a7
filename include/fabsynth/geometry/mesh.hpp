// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh.hpp  Indexed triangle meshes and their basic measures.
///
/// Usage:
///   fabsynth::triangle_mesh m = fabsynth::io::read_mesh("bunny.obj");
///   double v = fabsynth::signed_volume(m);   // > 0 for a closed, outward-oriented mesh
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/core/union_find.hpp"

namespace fabsynth {

/// Triangle soup with shared vertices. faces[i] holds three indices into vertices,
/// counter-clockwise seen from outside for closed meshes (outward normals).
struct triangle_mesh {
    std::vector<vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> faces;

    [[nodiscard]] std::size_t num_vertices() const noexcept { return vertices.size(); }
    [[nodiscard]] std::size_t num_faces() const noexcept { return faces.size(); }
    [[nodiscard]] bool empty() const noexcept { return faces.empty(); }
    friend bool operator==(const triangle_mesh&, const triangle_mesh&) = default;
};

/// Bounding box of the vertices (empty box for an empty mesh).
[[nodiscard]] inline box3 bounding_box(const triangle_mesh& m) {
    box3 b;
    for (const vec3& v : m.vertices) b.extend(v);
    return b;
}

/// Unnormalised face normal (length = 2 * area).
[[nodiscard]] inline vec3 face_normal_area2(const triangle_mesh& m, std::size_t f) {
    const auto& t = m.faces[f];
    return glm::cross(m.vertices[t[1]] - m.vertices[t[0]], m.vertices[t[2]] - m.vertices[t[0]]);
}

/// Area-weighted unit vertex normals (the sum of the unnormalised normals of the faces around a
/// vertex, normalised); (0, 0, 0) for a vertex no face with area uses.
[[nodiscard]] inline std::vector<vec3> vertex_normals(const triangle_mesh& m) {
    std::vector<vec3> n(m.num_vertices(), vec3(0.0));
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
        const vec3 a2 = face_normal_area2(m, f);
        for (const std::uint32_t v : m.faces[f]) n[v] += a2;
    }
    for (vec3& x : n) {
        const double l = glm::length(x);
        x = l > 0 ? x / l : vec3(0.0);
    }
    return n;
}

/// Barycentric coordinates over the triangle (a, b, c) of the point of its plane nearest to x
/// (x on or near the triangle); the centroid's (1/3 each) for a degenerate triangle.
[[nodiscard]] inline vec3 barycentric(vec3 x, vec3 a, vec3 b, vec3 c) {
    const vec3 v0 = b - a, v1 = c - a, v2 = x - a;
    const double d00 = glm::dot(v0, v0), d01 = glm::dot(v0, v1), d11 = glm::dot(v1, v1), d20 = glm::dot(v2, v0), d21 = glm::dot(v2, v1);
    const double den = d00 * d11 - d01 * d01;
    if (!(std::abs(den) > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    return {1 - v - w, v, w};
}

/// Total surface area.
[[nodiscard]] inline double surface_area(const triangle_mesh& m) {
    double a = 0;
    for (std::size_t f = 0; f < m.faces.size(); ++f) a += 0.5 * glm::length(face_normal_area2(m, f));
    return a;
}

/// Signed enclosed volume by the divergence theorem (exact for closed meshes; positive when
/// normals point outward).
[[nodiscard]] inline double signed_volume(const triangle_mesh& m) {
    double v = 0;
    for (const auto& t : m.faces)
        v += glm::dot(m.vertices[t[0]], glm::cross(m.vertices[t[1]], m.vertices[t[2]]));
    return v / 6.0;
}

/// Throws invalid_input unless every face indexes existing vertices and every vertex is finite.
inline void validate(const triangle_mesh& m, const char* what = "mesh") {
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
        if (!all_finite(m.vertices[i]))
            throw invalid_input(std::string(what) + ": vertex " + std::to_string(i) + " is not finite");
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (std::uint32_t v : m.faces[f])
            if (v >= m.vertices.size())
                throw invalid_input(std::string(what) + ": face " + std::to_string(f) + " indexes missing vertex " +
                                    std::to_string(v));
}

/// Mirrors the mesh in y (y -> -y) and reverses every face, so outward faces stay outward (an SVG
/// drawing is y-down; a print of it is y-up).
inline void mirror_y(triangle_mesh& m) noexcept {
    for (vec3& p : m.vertices) p.y = -p.y;
    for (auto& f : m.faces) std::swap(f[1], f[2]);
}

/// Turns a y-up mesh into a z-up one (the build direction of a printer): a rotation about x by
/// +90 degrees, (x, y, z) -> (x, -z, y), which keeps the faces' orientation.
inline void rotate_y_up_to_z_up(triangle_mesh& m) noexcept {
    for (vec3& v : m.vertices) v = vec3(v.x, -v.z, v.y);
}

/// The map p -> (p - origin) * scale that fit_to_size applied (for points given with the mesh).
struct size_fit {
    vec3 origin{0.0};
    double scale = 1.0;
    [[nodiscard]] vec3 operator()(const vec3& p) const noexcept { return (p - origin) * scale; }
};

/// Moves the mesh's bounding-box corner to the origin and scales it uniformly so that its longest
/// side is `size` mm; returns that map. Throws invalid_input for an empty or flat-in-every-direction
/// mesh or a size that is not finite and > 0.
inline size_fit fit_to_size(triangle_mesh& m, double size) {
    if (!(std::isfinite(size) && size > 0)) throw invalid_input("mesh size must be finite and > 0 mm, got " + std::to_string(size));
    const box3 bb = bounding_box(m);
    const double longest = bb.empty() ? 0.0 : std::max({bb.size().x, bb.size().y, bb.size().z});
    if (!(longest > 0)) throw invalid_input("cannot scale a mesh without extent to a size");
    const size_fit fit{bb.lo, size / longest};
    for (vec3& v : m.vertices) v = fit(v);
    return fit;
}

/// The faces f of m with keep[f] != 0, in order, with only the vertices they use (renumbered in
/// order of first use). keep has one entry per face.
[[nodiscard]] inline triangle_mesh faces_subset(const triangle_mesh& m, const std::vector<std::uint8_t>& keep) {
    if (keep.size() != m.faces.size())
        throw invalid_input("faces_subset: " + std::to_string(keep.size()) + " flags for " + std::to_string(m.faces.size()) + " faces");
    triangle_mesh out;
    std::vector<std::uint32_t> id(m.vertices.size(), UINT32_MAX);
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
        if (!keep[f]) continue;
        std::array<std::uint32_t, 3> o = m.faces[f];
        for (std::uint32_t& v : o) {
            if (id[v] == UINT32_MAX) id[v] = static_cast<std::uint32_t>(out.vertices.size()), out.vertices.push_back(m.vertices[v]);
            v = id[v];
        }
        out.faces.push_back(o);
    }
    return out;
}

/// Vertex clustering: vertices closer than `tolerance` mm are one (single linkage through a grid of
/// cell `tolerance`; a cluster takes the position of its lowest vertex id), faces are renumbered,
/// faces whose corners merged are dropped, unused vertices removed. For meshes whose booleans left
/// edges far shorter than any feature (a baked filigree before shell analysis). Deterministic.
[[nodiscard]] inline triangle_mesh cluster_vertices(const triangle_mesh& m, double tolerance) {
    if (!(std::isfinite(tolerance) && tolerance > 0)) throw invalid_input("cluster_vertices: tolerance must be finite and > 0 mm");
    union_find groups(m.vertices.size());
    std::map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>> cells;
    auto cell_of = [&](const vec3& p) {
        return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p.x / tolerance)), static_cast<std::int64_t>(std::floor(p.y / tolerance)),
                                           static_cast<std::int64_t>(std::floor(p.z / tolerance))};
    };
    for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
        const auto c = cell_of(m.vertices[v]);
        for (std::int64_t dz = -1; dz <= 1; ++dz)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dx = -1; dx <= 1; ++dx) {
                    const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == cells.end()) continue;
                    for (const std::uint32_t w : it->second)
                        if (glm::distance(m.vertices[v], m.vertices[w]) < tolerance) groups.unite(v, w);
                }
        cells[c].push_back(v);
    }
    triangle_mesh out;
    std::vector<std::uint32_t> id(m.vertices.size(), UINT32_MAX);
    for (const auto& f : m.faces) {
        std::array<std::uint32_t, 3> r{groups.find(f[0]), groups.find(f[1]), groups.find(f[2])};  // the lowest id of each cluster
        if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
        for (std::uint32_t& v : r) {
            if (id[v] == UINT32_MAX) id[v] = static_cast<std::uint32_t>(out.vertices.size()), out.vertices.push_back(m.vertices[v]);
            v = id[v];
        }
        out.faces.push_back(r);
    }
    return out;
}

}  // namespace fabsynth
