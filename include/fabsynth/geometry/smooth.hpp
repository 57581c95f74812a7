// SPDX-License-Identifier: MIT
#pragma once
/// @file smooth.hpp  Taubin lambda|mu smoothing of triangle meshes (vertex positions only).
///
/// Usage:
///   fabsynth::taubin_smooth(mesh);                                   // 10 pairs, lambda 0.5, mu -0.53
///   fabsynth::taubin_smooth(mesh, {.iterations = 30, .lambda = 0.6307, .mu = -0.6732});
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

/// Taubin lambda|mu smoothing of m in place (see file comment). Throws invalid_input for an invalid
/// mesh (non-finite vertex, missing vertex index) or options (iterations < 0, lambda not in (0, 1],
/// mu not in [-1, -lambda), non-finite weights).
inline void taubin_smooth(triangle_mesh& m, const taubin_options& o = {}) {
    validate(m, "taubin_smooth: mesh");
    if (o.iterations < 0) throw invalid_input("taubin_smooth: iterations must be >= 0, got " + std::to_string(o.iterations));
    if (!(std::isfinite(o.lambda) && o.lambda > 0.0 && o.lambda <= 1.0))
        throw invalid_input("taubin_smooth: lambda must be in (0, 1], got " + std::to_string(o.lambda));
    if (!(std::isfinite(o.mu) && o.mu < -o.lambda && o.mu >= -1.0))
        throw invalid_input("taubin_smooth: mu must be in [-1, -lambda) = [-1, " + std::to_string(-o.lambda) + "), got " +
                            std::to_string(o.mu));
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
                next[v] = cur[v] + w * (s / static_cast<double>(e - b) - cur[v]);
            },
            {.grain = 4096});
        m.vertices.swap(next);
    };
    for (int it = 0; it < o.iterations; ++it) {
        step(o.lambda);
        step(o.mu);
    }
}

}  // namespace fabsynth
