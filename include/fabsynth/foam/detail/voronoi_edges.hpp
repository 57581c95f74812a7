// SPDX-License-Identifier: MIT
#pragma once
/// @file voronoi_edges.hpp  (internal, behind evaluator.hpp) The Voronoi edge pieces inside a box,
/// from the seeds gathered by certificate.hpp.
///
/// Each seed i of S whose cell can meet the box gets its Voronoi cell clipped to its cell box
/// (polytope.hpp), by bisector half-spaces of the seeds of S sorted by distance, stopping when the
/// next seed is farther than twice the cell's circumradius (voro++'s criterion). A face edge
/// between bisectors (i, j) and (i, k) with i < j < k is emitted once. The result is the exact set
/// of Voronoi edge pieces inside the box (floating-point rounding ~1e-13 mm aside);
/// tests/foam/evaluator.cpp compares it with an independent triple-enumeration construction.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/detail/canonical_piece.hpp"
#include "fabsynth/foam/detail/certificate.hpp"
#include "fabsynth/foam/detail/polytope.hpp"
#include "fabsynth/foam/detail/workspace.hpp"

namespace fabsynth::foam::detail {

/// Clips ws.poly to the Voronoi cell of S[i] inside ws.cell_box[i]; false if the cell is empty
/// there. S must be sorted by x (gather_certified_seeds), which bounds the candidate cutters.
inline bool clip_cell(int i, foam_workspace& ws) {
    const std::vector<vec3>& S = ws.S;
    const int n = static_cast<int>(S.size());
    const vec3 si = S[static_cast<std::size_t>(i)];
    ws.poly.set_box(ws.cell_box[static_cast<std::size_t>(i)]);
    double lim2 = 4 * ws.poly.max_dist2(si);
    // candidate cutters: seeds with |x_j - x_i| < 2 * cell radius, sorted by distance
    ws.order.clear();
    const double reach_x = std::sqrt(lim2);
    const int jlo = static_cast<int>(
        std::lower_bound(S.begin(), S.end(), si.x - reach_x, [](const vec3& p, double v) { return p.x < v; }) - S.begin());
    for (int j = jlo; j < n && S[static_cast<std::size_t>(j)].x <= si.x + reach_x; ++j) {
        if (j == i) continue;
        const vec3 d = S[static_cast<std::size_t>(j)] - si;
        const double d2 = glm::dot(d, d);
        if (d2 < lim2 && d2 > 0) ws.order.push_back({d2, j});
    }
    std::sort(ws.order.begin(), ws.order.end());
    for (const auto& [d2, j] : ws.order) {
        if (d2 >= lim2) break;  // farther than twice the cell's circumradius: cannot cut
        const vec3 sj = S[static_cast<std::size_t>(j)];
        const vec3 nrm = sj - si;
        if (ws.poly.clip(nrm, 0.5 * (glm::dot(sj, sj) - glm::dot(si, si)), j)) {
            if (ws.poly.empty()) return false;
            lim2 = 4 * ws.poly.max_dist2(si);
        }
    }
    return true;
}

/// Calls visit(v, next, j, k, before, after) for every edge of the clipped cell of seed i that seed
/// i emits: the edge from vertex v to vertex next between the bisector faces of seeds j and k with
/// i < j < k (box faces and unknown tags excluded); before / after: the tags of the planes that end
/// it at v / next. Returns false as soon as visit does.
template <class Visit>
bool walk_cell_edges(int i, const polytope& poly, Visit&& visit) {
    const auto& verts = poly.verts();
    for (const auto& fc : poly.faces()) {
        const int j = fc.tag;
        if (j <= i) continue;
        const std::uint32_t m = fc.end - fc.begin;
        for (std::uint32_t k = 0; k < m; ++k) {
            const auto& v = verts[fc.begin + k];
            if (v.edge_tag <= j) continue;  // also skips box faces (< 0) and unknown tags
            const auto& next = verts[fc.begin + (k + 1) % m];
            if (!visit(v.p, next.p, j, v.edge_tag, verts[fc.begin + (k + m - 1) % m].edge_tag, next.edge_tag)) return false;
        }
    }
    return true;
}

/// Calls f(a, b) for every edge that seed i emits (walk_cell_edges) until f returns false.
template <class F>
bool emit_cell_edges(int i, const polytope& poly, F& f) {
    return walk_cell_edges(i, poly, [&](const vec3& a, const vec3& b, int, int, int, int) { return f(a, b); });
}

/// As emit_cell_edges, with each piece as f(canonical_piece, a, b) (canonical_piece.hpp; a, b: its
/// endpoints as computed, in no particular order): the seeds of its three faces, and at each end
/// the fourth seed of the Voronoi vertex there (none where a box face or an unidentified plane
/// ends it; an unidentified one keeps the computed end as a vertex).
template <class F>
bool emit_cell_pieces(int i, const polytope& poly, const std::vector<vec3>& S, F& f) {
    const auto seed = [&](int t) -> const vec3& { return S[static_cast<std::size_t>(t)]; };
    const auto end = [&](int t) {  // t: the plane that ends the edge there
        if (t >= 0) return piece_end{&seed(t), true};
        return piece_end{nullptr, t == unknown_tag};  // box faces are < 0, unknown is a vertex
    };
    return walk_cell_edges(i, poly, [&](const vec3& a, const vec3& b, int j, int k, int before, int after) {
        return f(make_canonical_piece(a, b, seed(i), seed(j), seed(k), end(before), end(after)), a, b);
    });
}

/// Gathers the certified seeds of box b and calls emit(i) with ws.poly holding the clipped cell
/// of each seed i whose cell meets b, until emit returns false.
template <class Seeds, class Emit>
void for_each_cell_clipped(const box3& b, const Seeds& gen, double max_radius, std::uint64_t owner, foam_workspace& ws, Emit&& emit) {
    const double h = 0.5 * glm::length(b.size());
    if (!(h <= 64 * gen.options().cell)) throw invalid_input("foam: query box too large or not finite");
    gather_certified_seeds(b, gen, max_radius, owner, ws);
    const int n = static_cast<int>(ws.S.size());
    for (int i = 0; i < n; ++i) {
        if (!ws.is_cell[static_cast<std::size_t>(i)]) continue;
        if (ws.cell_box[static_cast<std::size_t>(i)].empty()) continue;
        if (!clip_cell(i, ws)) continue;
        if (!emit(i)) return;
    }
}

/// Calls f(a, b) for every Voronoi edge piece inside box b (clipped to b) until f returns false.
/// The box must be finite with circumradius <= 64 coarse cells (else invalid_input).
template <class Seeds, class F>
void for_each_voronoi_edge(const box3& b, const Seeds& gen, double max_radius, std::uint64_t owner, foam_workspace& ws,
                           F&& f) {
    for_each_cell_clipped(b, gen, max_radius, owner, ws, [&](int i) { return emit_cell_edges(i, ws.poly, f); });
}

/// As for_each_voronoi_edge, with every piece as f(canonical_piece, a, b) (emit_cell_pieces).
template <class Seeds, class F>
void for_each_voronoi_piece(const box3& b, const Seeds& gen, double max_radius, std::uint64_t owner, foam_workspace& ws, F&& f) {
    for_each_cell_clipped(b, gen, max_radius, owner, ws, [&](int i) { return emit_cell_pieces(i, ws.poly, ws.S, f); });
}

}  // namespace fabsynth::foam::detail
