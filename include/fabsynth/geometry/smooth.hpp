// SPDX-License-Identifier: MIT
#pragma once
/// @file smooth.hpp  Taubin lambda|mu smoothing of triangle meshes (vertex positions only), free or,
/// for meshes of binary fields, with every vertex held on its grid edge (taubin_smooth_on_grid_edges).
///
/// Usage:
///   fabsynth::taubin_smooth(mesh);                                   // 10 pairs, lambda 0.5, mu -0.53
///   fabsynth::taubin_smooth(mesh, {.iterations = 30, .lambda = 0.6307, .mu = -0.6732});
///   fabsynth::taubin_smooth_on_grid_edges(voxel_mesh, origin, spacing, {.iterations = 50});  // within half a voxel
///
/// Method: G. Taubin, "A signal processing approach to fair surface design", SIGGRAPH 1995. With
/// the umbrella operator L(x_i) = (1 / |N(i)|) sum_{j in N(i)} (x_j - x_i) over the edge
/// neighbours N(i) (uniform weights), one iteration is a shrinking step x <- x + lambda L(x)
/// followed by an inflating step x <- x + mu L(x), mu < -lambda < 0. This is a low-pass filter with
/// pass-band frequency k_PB = 1/lambda + 1/mu (0.113 for the defaults): the staircase of a voxel
/// surface and other high-frequency noise are damped while the shape does not shrink the way
/// plain Laplacian smoothing does.
///
/// Only positions move: faces are kept, so a watertight mesh stays watertight (topologically;
/// smoothing does not prevent geometric self-intersections of nearly touching sheets). Vertices on
/// a boundary edge (an edge of exactly one face) are held fixed, so open meshes keep their rims;
/// vertices no face uses are left alone.
///
/// Determinism: neighbours are sorted by index and summed in that order; each step reads the
/// previous positions and writes a second buffer, in parallel over vertices, so the result is
/// bit-identical for any thread count. Time O(iterations * (V + F)), memory O(V + F).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/mesh.hpp"

namespace fabsynth {

/// Parameters of taubin_smooth (dimensionless).
struct taubin_options {
    int iterations = 10;   ///< number of lambda|mu pairs, >= 0
    double lambda = 0.5;   ///< shrinking weight, in (0, 1]
    double mu = -0.53;     ///< inflating weight, < -lambda and >= -1
};

/// Vertex adjacency of a mesh: neighbours of v are nbr[off[v] .. off[v + 1]), sorted, unique;
/// boundary[v] = 1 for vertices on a boundary edge.
struct mesh_adjacency {
    std::vector<std::size_t> off;
    std::vector<std::uint32_t> nbr;
    std::vector<std::uint8_t> boundary;
};

/// Adjacency of m (see mesh_adjacency). Degenerate face edges (a repeated index) are ignored.
/// Expects a valid mesh (faces index existing vertices). Time O(V + F log(max degree)), memory
/// 6 F + 3 V 32-bit words at the peak (the neighbour list holds each edge twice until it is compacted).
[[nodiscard]] inline mesh_adjacency vertex_adjacency(const triangle_mesh& m) {
    const std::size_t nv = m.vertices.size();
    mesh_adjacency a;
    a.off.assign(nv + 1, 0);
    for (const auto& t : m.faces)
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t u = t[static_cast<std::size_t>(i)], w = t[static_cast<std::size_t>((i + 1) % 3)];
            if (u == w) continue;
            ++a.off[u + 1], ++a.off[w + 1];
        }
    for (std::size_t v = 0; v < nv; ++v) a.off[v + 1] += a.off[v];
    std::vector<std::uint32_t> raw(a.off[nv]);
    {
        std::vector<std::size_t> fill(a.off.begin(), a.off.end() - 1);
        for (const auto& t : m.faces)
            for (int i = 0; i < 3; ++i) {
                const std::uint32_t u = t[static_cast<std::size_t>(i)], w = t[static_cast<std::size_t>((i + 1) % 3)];
                if (u == w) continue;
                raw[fill[u]++] = w, raw[fill[w]++] = u;
            }
    }
    // per vertex: sort, detect edges of multiplicity 1 (one face), deduplicate; counts first
    a.boundary.assign(nv, 0);
    std::vector<std::uint32_t> unique_count(nv, 0);
    parallel_for(
        0, nv,
        [&](std::size_t v) {
            auto* b = raw.data() + a.off[v];
            auto* e = raw.data() + a.off[v + 1];
            std::sort(b, e);
            std::uint32_t n = 0;
            for (auto* p = b; p != e;) {
                auto* q = p;
                while (q != e && *q == *p) ++q;
                if (q - p == 1) a.boundary[v] = 1;
                b[n++] = *p;
                p = q;
            }
            unique_count[v] = n;
        },
        {.grain = 4096});
    // compact the deduplicated lists in place, left to right (a list never moves right)
    std::size_t next = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        const std::size_t b = a.off[v];
        a.off[v] = next;
        if (next != b)
            std::copy_n(raw.begin() + static_cast<std::ptrdiff_t>(b), unique_count[v], raw.begin() + static_cast<std::ptrdiff_t>(next));
        next += unique_count[v];
    }
    a.off[nv] = next;
    raw.resize(next);
    a.nbr = std::move(raw);
    return a;
}

namespace detail {

inline void check_taubin(const triangle_mesh& m, const taubin_options& o, const char* who) {
    validate(m, (std::string(who) + ": mesh").c_str());
    if (o.iterations < 0) throw invalid_input(std::string(who) + ": iterations must be >= 0, got " + std::to_string(o.iterations));
    if (!(std::isfinite(o.lambda) && o.lambda > 0.0 && o.lambda <= 1.0))
        throw invalid_input(std::string(who) + ": lambda must be in (0, 1], got " + std::to_string(o.lambda));
    if (!(std::isfinite(o.mu) && o.mu < -o.lambda && o.mu >= -1.0))
        throw invalid_input(std::string(who) + ": mu must be in [-1, -lambda) = [-1, " + std::to_string(-o.lambda) + "), got " +
                            std::to_string(o.mu));
}

// Taubin pairs; after each step, vertex v's new position p becomes project(v, p).
template <class Project>
void taubin_steps(triangle_mesh& m, const taubin_options& o, const Project& project) {
    if (o.iterations == 0 || m.faces.empty()) return;
    const mesh_adjacency a = vertex_adjacency(m);
    const std::size_t nv = m.vertices.size();
    std::vector<vec3> next(nv);
    auto step = [&](double w) {
        const std::vector<vec3>& cur = m.vertices;
        parallel_for(
            0, nv,
            [&](std::size_t v) {
                const std::size_t b = a.off[v], e = a.off[v + 1];
                if (b == e || a.boundary[v]) {
                    next[v] = cur[v];
                    return;
                }
                vec3 s(0.0);
                for (std::size_t k = b; k < e; ++k) s += cur[a.nbr[k]];
                next[v] = project(v, cur[v] + w * (s / static_cast<double>(e - b) - cur[v]));
            },
            {.grain = 4096});
        m.vertices.swap(next);
    };
    for (int it = 0; it < o.iterations; ++it) {
        step(o.lambda);
        step(o.mu);
    }
}

}  // namespace detail

/// Taubin lambda|mu smoothing of m in place (see file comment). Throws invalid_input for an invalid
/// mesh (non-finite vertex, missing vertex index) or options (iterations < 0, lambda not in (0, 1],
/// mu not in [-1, -lambda), non-finite weights).
inline void taubin_smooth(triangle_mesh& m, const taubin_options& o = {}) {
    detail::check_taubin(m, o, "taubin_smooth");
    detail::taubin_steps(m, o, [](std::size_t, const vec3& p) { return p; });
}

/// Taubin smoothing of a mesh extracted from a binary field on a grid (marching_cubes of
/// +-1 samples, every vertex at the midpoint of the grid edge between an inside and an outside
/// grid point), with each vertex held on its grid edge: after every step a vertex is projected
/// back onto the edge's line and clamped to within `reach` grid spacings (the smallest of the
/// three) of the midpoint, and never nearer than 0.05 of the edge to either grid point.
///
/// What this keeps, whatever the iterations: each vertex stays strictly between its inside and
/// outside grid point, so within every tetrahedron of the extraction the surface still separates
/// the inside corners from the outside ones, as the extracted one did. The mesh therefore stays
/// embedded (no self-intersection), with the same faces, topology and inside grid points, and
/// every point of it lies within `reach` spacings of the unsmoothed mesh (the midpoints lie on the
/// boundary of the voxel solid, so of that too). The staircase of the voxels is smoothed within
/// that band. (The same idea as the constrained elastic surface nets of S. Gibson, "Constrained
/// elastic surface nets", MICCAI 1998, which hold each vertex inside its voxel, applied to the
/// edge vertices of marching tetrahedra.)
///
/// `origin` and `spacing` (mm) are those the mesh was extracted with. Throws invalid_input for
/// the options (as taubin_smooth), a `reach` outside (0, 0.5], or a vertex that is not the
/// midpoint of a grid edge (naming it).
inline void taubin_smooth_on_grid_edges(triangle_mesh& m, vec3 origin, vec3 spacing, const taubin_options& o = {}, double reach = 0.5) {
    detail::check_taubin(m, o, "taubin_smooth_on_grid_edges");
    if (!(reach > 0 && reach <= 0.5)) throw invalid_input("taubin_smooth_on_grid_edges: reach must be in (0, 0.5] spacings, got " + std::to_string(reach));
    if (!all_finite(origin) || !(spacing.x > 0 && spacing.y > 0 && spacing.z > 0 && all_finite(spacing)))
        throw invalid_input("taubin_smooth_on_grid_edges: origin must be finite and spacing > 0");
    const std::size_t nv = m.vertices.size();
    const double h = std::min({spacing.x, spacing.y, spacing.z});
    std::vector<vec3> mid(m.vertices), dir(nv);  // each vertex's edge: midpoint and full edge vector
    std::vector<double> smax(nv);                // largest |s| in p = mid + s dir
    for (std::size_t v = 0; v < nv; ++v) {
        const vec3 g = (m.vertices[v] - origin) / spacing * 2.0;  // 2 * grid coordinates: odd where on an edge
        ivec3 d(0);
        for (int i = 0; i < 3; ++i) {
            const double r = std::round(g[i]);
            if (std::abs(g[i] - r) > 1e-6 * std::max(1.0, std::abs(g[i])))
                throw invalid_input("taubin_smooth_on_grid_edges: vertex " + std::to_string(v) + " is not at the midpoint of a grid edge");
            d[i] = static_cast<int>(std::fmod(std::abs(r), 2.0));
        }
        if (d == ivec3(0))
            throw invalid_input("taubin_smooth_on_grid_edges: vertex " + std::to_string(v) + " is at a grid point, not the midpoint of a grid edge");
        dir[v] = vec3(d) * spacing;
        smax[v] = std::min(0.45, reach * h / glm::length(dir[v]));
    }
    detail::taubin_steps(m, o, [&](std::size_t v, const vec3& p) {
        const double s = std::clamp(glm::dot(p - mid[v], dir[v]) / glm::dot(dir[v], dir[v]), -smax[v], smax[v]);
        return mid[v] + s * dir[v];
    });
}

}  // namespace fabsynth
