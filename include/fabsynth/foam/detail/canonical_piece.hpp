// SPDX-License-Identifier: MIT
#pragma once
/// @file canonical_piece.hpp  (internal, behind evaluator.hpp) A Voronoi edge piece whose distance
/// to a point does not depend on the box it was computed in.
///
/// A piece found in two boxes has two sets of endpoint coordinates: its cell was clipped by
/// different planes in a different order, and a box face may cut it. Its distance to q computed
/// from those endpoints differs in the last bits. Here the distance is computed from the seeds
/// instead: the edge of seeds (s_i, s_j, s_k) lies on the line through their circumcentre along
/// the normal of their plane, and a Voronoi vertex at an end is the circumcentre of its four seeds,
/// each computed from the seeds sorted by coordinates, so the same seeds give the same bits. The
/// endpoints only decide whether q's foot on the line lies within the piece: beyond an end that is
/// a Voronoi vertex the distance is to that vertex; beyond an end cut by the box the nearest point
/// of the edge lies outside the box, so (the box holding the ball of the query radius around q) the
/// piece is out of reach and reports +infinity. The answers of two boxes can then differ only where
/// q's true distance is exactly the query radius, up to rounding.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "fabsynth/core/types.hpp"

namespace fabsynth::foam::detail {

struct canonical_piece {
    vec3 c{0.0}, u{0.0};          ///< the edge's line: c + l u, |u| = 1
    double lo = 0.0, hi = 0.0;    ///< the piece's range of l
    vec3 v_lo{0.0}, v_hi{0.0};    ///< the Voronoi vertices at the ends, where vertex_lo / vertex_hi
    bool vertex_lo = false, vertex_hi = false;
};

namespace canonical {

[[nodiscard]] inline bool before(const vec3& p, const vec3& q) noexcept {
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
}

/// Circumcentre of the tetrahedron of four seeds (sorted first); false if they are coplanar.
[[nodiscard]] inline bool vertex_of(std::array<vec3, 4> s, vec3& out) noexcept {
    std::sort(s.begin(), s.end(), before);
    const vec3 a = s[1] - s[0], b = s[2] - s[0], c = s[3] - s[0];
    const double det = glm::dot(a, glm::cross(b, c));
    if (!(std::abs(det) > 0)) return false;
    out = s[0] + (glm::dot(a, a) * glm::cross(b, c) + glm::dot(b, b) * glm::cross(c, a) + glm::dot(c, c) * glm::cross(a, b)) / (2.0 * det);
    return true;
}

}  // namespace canonical

/// How a piece ends: at a cut of the box, at a Voronoi vertex of known fourth seed, or at a vertex
/// whose fourth plane the polytope could not name (its computed position is kept).
struct piece_end {
    const vec3* fourth_seed = nullptr;
    bool vertex = false;
};

/// The piece [a, b] of the edge of seeds si, sj, sk with ends ea (at a) and eb (at b). Falls back
/// to the endpoints as computed where the seeds are degenerate (collinear or coplanar).
[[nodiscard]] inline canonical_piece make_canonical_piece(const vec3& a, const vec3& b, const vec3& si, const vec3& sj, const vec3& sk,
                                                          piece_end ea, piece_end eb) {
    canonical_piece p;
    std::array<vec3, 3> s{si, sj, sk};
    std::sort(s.begin(), s.end(), canonical::before);
    const vec3 e1 = s[1] - s[0], e2 = s[2] - s[0], n = glm::cross(e1, e2);
    const double n2 = glm::dot(n, n);
    if (n2 > 0) {
        p.c = s[0] + (glm::dot(e1, e1) * glm::cross(e2, n) + glm::dot(e2, e2) * glm::cross(n, e1)) / (2.0 * n2);
        p.u = n / std::sqrt(n2);
    } else {  // degenerate seeds: the computed segment's own line
        p.c = a;
        const vec3 d = b - a;
        p.u = glm::dot(d, d) > 0 ? d / std::sqrt(glm::dot(d, d)) : vec3(1, 0, 0);
    }
    auto end_of = [&](const vec3& end, const piece_end& e, vec3& v) {
        v = end;
        if (e.fourth_seed && !canonical::vertex_of({si, sj, sk, *e.fourth_seed}, v)) v = end;
        return glm::dot(v - p.c, p.u);
    };
    vec3 va{0.0}, vb{0.0};
    const bool ia = ea.vertex || ea.fourth_seed, ib = eb.vertex || eb.fourth_seed;
    const double la = end_of(a, ea, va), lb = end_of(b, eb, vb);
    if (la <= lb) {
        p.lo = la, p.hi = lb, p.v_lo = va, p.v_hi = vb, p.vertex_lo = ia, p.vertex_hi = ib;
    } else {
        p.lo = lb, p.hi = la, p.v_lo = vb, p.v_hi = va, p.vertex_lo = ib, p.vertex_hi = ia;
    }
    return p;
}

/// The piece's end at its low (hi = false) or high end of l: the Voronoi vertex there, or the
/// line's point at the cut.
[[nodiscard]] inline vec3 end_point(const canonical_piece& p, bool hi) noexcept {
    if (hi) return p.vertex_hi ? p.v_hi : p.c + p.hi * p.u;
    return p.vertex_lo ? p.v_lo : p.c + p.lo * p.u;
}

/// Squared distance from q to the piece, or +infinity when its nearest edge point lies beyond an
/// end cut by the box (see the file comment).
[[nodiscard]] inline double distance2(const canonical_piece& p, const vec3& q) noexcept {
    const vec3 w = q - p.c;
    const double l = glm::dot(w, p.u);
    if (l < p.lo) {
        if (!p.vertex_lo) return std::numeric_limits<double>::infinity();
        const vec3 d = q - p.v_lo;
        return glm::dot(d, d);
    }
    if (l > p.hi) {
        if (!p.vertex_hi) return std::numeric_limits<double>::infinity();
        const vec3 d = q - p.v_hi;
        return glm::dot(d, d);
    }
    const vec3 d = w - l * p.u;
    return glm::dot(d, d);
}

}  // namespace fabsynth::foam::detail
