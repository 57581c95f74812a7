// SPDX-License-Identifier: MIT
#pragma once
/// @file certificate.hpp  (internal, behind evaluator.hpp) Which seeds the Voronoi edges inside a
/// box depend on: the seed-neighbourhood certificate and the gather that applies it.
///
/// Proof (replaces the paper's disputed "2-ring" argument of Fig. 4):
///   Let r(p) be the distance from p to its nearest seed; r is 1-Lipschitz. A point p lies on a
///   Voronoi edge iff at least three seeds are at distance exactly r(p) from p. Consider a region B
///   (a box) with centre c and circumradius h, and let d1 = r(c). For every p in B,
///   r(p) <= d1 + h, so every seed that is nearest to p satisfies |s - c| <= r(p) + |p - c| <= d1 + 2h.
///   Hence the Voronoi diagram of S = {seeds with |s - c| <= d1 + 2h} coincides with the full
///   diagram inside B: same cells, same edges. For a query q with radius tau take B = the cube
///   q +- tau (it contains the ball of radius tau, so every edge point within tau of q is in B).
///   Any upper bound d1' >= d1 keeps this true, so d1 itself is never computed (see "Gather" below).
///   Nothing here depends on the density being smooth, on the jitter, or on a neighbourhood size
///   chosen in advance: the certificate is computed per query.
///   The paper's Algorithm 1 also only tests edges of the cell of the seed nearest to q; the
///   union-of-tubes definition needs edges of every cell touching the ball (a beam of a neighbouring
///   cell can reach into q's cell), which is what is done here.
///   (The paper's Fig. 4 "2-ring" bound is not used: it reasons about the cell of one seed and
///   assumes a seed in every grid cell at the resolution of the ring, which the graded subdivision
///   does not guarantee for sub-cells; the bound above assumes neither.)
///
/// Tighter per sub-box: the same argument applied to sub-boxes B_k of B (side ~ 2 max radius) with
///   their own d1_k keeps S small: S = union_k {|s - c_k| <= d1_k + 2 h_k}; the cell of s can meet
///   B_k only if dist(s, B_k) <= d1_k + h_k, and a point p of B_k in the cell of s satisfies
///   |p - s| = r(p) <= d1_k + h_k, so the cell of s is built only inside the bounding box of
///   U_k (B_k & cube(s, d1_k + h_k)). The cell of s also lies in the bisector half-space of s
///   against t_k, the seed nearest to c_k, so B_k is dropped for s when it lies wholly outside it.
///
/// Gather (what the code does): every seed within a margin m of B is collected (S_m); d1'_k is the
///   distance from c_k to its nearest seed in S_m, an upper bound of d1_k; the bounds need every seed
///   within d1'_k + 2 h_k of c_k, which S_m holds once m >= max_k d1'_k + 2 h_k. m starts at a
///   fraction of the seed spacing at the local density and grows until that holds. The loop stops at
///   the latest one pass after the first pass that collects any seed: S_m grows with m, so each
///   d1'_k can only shrink, and the next margin max_k d1'_k + 2 h_k then passes the test. Until a
///   seed is found m doubles; a seed is found once m >= sqrt(3) L, because every coarse cell holds
///   at least one seed (seeds.hpp) and B meets some coarse cell.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/foam/detail/workspace.hpp"
#include "fabsynth/foam/seeds.hpp"

namespace fabsynth::foam::detail {

/// Calls fn(seed) for every seed of coarse cell k: from the slice's cache when it holds k, else from
/// the per-thread cache of recently generated cells (512 direct-mapped slots, owned by the foam
/// instance `owner`).
template <class Seeds, class Fn>
void for_cell_seeds(const Seeds& gen, std::uint64_t owner, const i64vec3& k, foam_workspace& ws, Fn&& fn) {
    if (ws.cache && ws.cache->has(k)) {
        const std::size_t ci = ws.cache->index(k);
        for (std::uint32_t i = ws.cache->start[ci]; i < ws.cache->start[ci + 1]; ++i) fn(ws.cache->seeds[i]);
        return;
    }
    if (ws.recent_owner != owner || ws.recent.empty()) {
        ws.recent.assign(512, {});
        ws.recent_owner = owner;
    }
    auto& slot = ws.recent[hash64(0, k.x, k.y, k.z) & 511];
    if (!slot.valid || slot.key != k) {
        slot.seeds.clear();
        gen.cell_seeds(k, slot.seeds);
        slot.key = k;
        slot.valid = true;
    }
    for (const vec3& q : slot.seeds) fn(q);
}

/// The sub-boxes B_k of a query box: a grid of n[0] x n[1] x n[2] boxes (side ~ 2 max radius, at
/// most 16 per axis), all of circumradius h.
struct sub_box_grid {
    int n[3];
    vec3 step;  ///< sub-box side per axis, mm
    double h;   ///< circumradius of a sub-box, mm
    [[nodiscard]] bool single() const noexcept { return n[0] * n[1] * n[2] == 1; }
};

[[nodiscard]] inline sub_box_grid make_sub_boxes(const box3& b, double max_radius) {
    sub_box_grid g;
    const vec3 size = b.size();
    const double side = 2 * max_radius;
    for (int a = 0; a < 3; ++a) g.n[a] = std::clamp(static_cast<int>(std::ceil(size[a] / side)), 1, 16);
    g.step = size / vec3(g.n[0], g.n[1], g.n[2]);
    g.h = 0.5 * glm::length(g.step);
    return g;
}

/// Phase 1: ws.S = every seed within margin m of box b (m slightly widened so no seed is lost to
/// rounding), in coarse-cell order.
template <class Seeds>
void collect_seeds_near(const box3& b, double m, const Seeds& gen, std::uint64_t owner, foam_workspace& ws) {
    const double L = gen.options().cell;
    const double mslack = m + 1e-12 * (m + 1);  // never drop a seed to rounding
    const double m2 = mslack * mslack;
    const i64vec3 lo = coarse_cell_of(b.lo - vec3(mslack), L), hi = coarse_cell_of(b.hi + vec3(mslack), L);
    ws.S.clear();
    for (std::int64_t z = lo.z; z <= hi.z; ++z)
        for (std::int64_t y = lo.y; y <= hi.y; ++y)
            for (std::int64_t x = lo.x; x <= hi.x; ++x)
                for_cell_seeds(gen, owner, {x, y, z}, ws, [&](const vec3& q) {
                    const vec3 d = glm::clamp(q, b.lo, b.hi) - q;
                    if (glm::dot(d, d) <= m2) ws.S.push_back(q);
                });
}

/// Phase 2: sorts ws.S by x and finds, for each sub-box centre c_k, its nearest seed t_k in ws.S
/// and the distance d1'_k (ws.sub_c, ws.sub_near, ws.sub_d1); returns max_k d1'_k (infinite when
/// ws.S is empty).
inline double nearest_seed_per_sub_box(const box3& b, const sub_box_grid& g, foam_workspace& ws) {
    ws.sub_c.clear();
    ws.sub_d1.clear();
    ws.sub_near.clear();
    // scan S sorted by x outwards from c_k.x, stop when |dx| >= the best distance so far
    std::sort(ws.S.begin(), ws.S.end(), [](const vec3& p, const vec3& q) { return p.x < q.x; });
    const std::ptrdiff_t ns = static_cast<std::ptrdiff_t>(ws.S.size());
    double dmax = 0;
    for (int z = 0; z < g.n[2]; ++z)
        for (int y = 0; y < g.n[1]; ++y)
            for (int x = 0; x < g.n[0]; ++x) {
                const vec3 sc = b.lo + g.step * (vec3(x, y, z) + 0.5);
                double best2 = std::numeric_limits<double>::infinity();
                vec3 near(0);
                const std::ptrdiff_t mid =
                    std::lower_bound(ws.S.begin(), ws.S.end(), sc.x, [](const vec3& p, double v) { return p.x < v; }) -
                    ws.S.begin();
                for (std::ptrdiff_t i = mid; i < ns; ++i) {
                    const vec3 d = ws.S[static_cast<std::size_t>(i)] - sc;
                    if (d.x * d.x >= best2) break;
                    const double e2 = glm::dot(d, d);
                    if (e2 < best2) best2 = e2, near = ws.S[static_cast<std::size_t>(i)];
                }
                for (std::ptrdiff_t i = mid - 1; i >= 0; --i) {
                    const vec3 d = ws.S[static_cast<std::size_t>(i)] - sc;
                    if (d.x * d.x >= best2) break;
                    const double e2 = glm::dot(d, d);
                    if (e2 < best2) best2 = e2, near = ws.S[static_cast<std::size_t>(i)];
                }
                ws.sub_c.push_back(sc);
                ws.sub_d1.push_back(std::sqrt(best2));
                ws.sub_near.push_back(near);
                dmax = std::max(dmax, std::sqrt(best2));
            }
    return dmax;
}

/// Phase 3: the bounds of every sub-box (ws.sub_b) from its d1'_k and nearest seed, each widened by
/// slack_all, which is >= the rounding of every bound.
inline void compute_sub_box_bounds(const sub_box_grid& g, double slack_all, foam_workspace& ws) {
    ws.sub_b.resize(ws.sub_c.size());
    for (std::size_t k = 0; k < ws.sub_c.size(); ++k) {
        const double need = ws.sub_d1[k] + 2 * g.h + slack_all;
        const vec3 t = ws.sub_near[k];
        ws.sub_b[k] = {need * need, ws.sub_d1[k] + g.h + slack_all, glm::length(ws.sub_c[k]) + g.h + 1, glm::dot(t, t),
                       glm::length(t)};
    }
}

/// Phase 4, one seed s: whether some sub-box needs it (returned) and, in cell_box, the bounding box
/// of U_k (B_k & cube(s, d1'_k + h)) over the sub-boxes its cell can meet (empty if none). Only
/// sub-boxes within need_all of s can need it (one index of margin).
inline bool seed_cell_box(const vec3& s, const box3& b, const sub_box_grid& g, double need_all, double slack_all,
                          const foam_workspace& ws, box3& cell_box) {
    const double ss2 = glm::dot(s, s), sl = std::sqrt(ss2);
    const vec3 half_step = 0.5 * g.step;
    bool need = false;
    int klo[3], khi[3];
    for (int a = 0; a < 3; ++a) {
        klo[a] = 0, khi[a] = g.n[a] - 1;
        if (!(g.step[a] > 0)) continue;  // flat box: one sub-box along a
        klo[a] = std::max(0, static_cast<int>(std::floor((s[a] - need_all - b.lo[a]) / g.step[a])) - 1);
        khi[a] = std::min(g.n[a] - 1, static_cast<int>(std::floor((s[a] + need_all - b.lo[a]) / g.step[a])) + 1);
    }
    for (int kz = klo[2]; kz <= khi[2]; ++kz)
        for (int ky = klo[1]; ky <= khi[1]; ++ky)
            for (int kx = klo[0]; kx <= khi[0]; ++kx) {
                const std::size_t k = static_cast<std::size_t>((kz * g.n[1] + ky) * g.n[0] + kx);
                const sub_box_bound& sb = ws.sub_b[k];
                const vec3 dv = s - ws.sub_c[k];
                if (glm::dot(dv, dv) > sb.need2) continue;
                need = true;
                const vec3 klo3 = ws.sub_c[k] - half_step, khi3 = ws.sub_c[k] + half_step;
                const vec3 cl = glm::clamp(s, klo3, khi3);
                if (glm::dot(cl - s, cl - s) > sb.cell_reach * sb.cell_reach) continue;
                // the cell of s also lies in its bisector half-space against the seed t nearest to
                // the sub-box centre, {p : (t - s).p <= (|t|^2 - |s|^2) / 2}: skip B_k if its lowest
                // corner is above the bound (+ a rounding slack, using |t - s| <= |t| + |s|)
                const vec3 nt = ws.sub_near[k] - s;
                const double lowest = glm::dot(nt, ws.sub_c[k]) - (std::abs(nt.x) * half_step.x +
                                                                    std::abs(nt.y) * half_step.y +
                                                                    std::abs(nt.z) * half_step.z);
                const double bound = 0.5 * (sb.near_len2 - ss2);
                const double hslack = 1e-9 * (1 + (sb.near_len + sl) * sb.centre_scale + sb.near_len2 + ss2);
                if (lowest > bound + hslack) continue;
                // widened by the slack so rounding never cuts a cell piece off
                const vec3 pad(slack_all);
                cell_box.extend(box3(glm::max(klo3 - pad, s - vec3(sb.cell_reach)),
                                     glm::min(khi3 + pad, s + vec3(sb.cell_reach))));
            }
    return need;
}

/// Phase 4: keeps in ws.S (order preserved) the seeds some sub-box needs, with ws.is_cell and
/// ws.cell_box (clipped to b) for each.
inline void keep_needed_seeds(const box3& b, const sub_box_grid& g, double dmax, foam_workspace& ws) {
    const double need_all = dmax + 2 * g.h;
    const double slack_all = 1e-12 * (need_all + 1);  // >= the rounding of every bound
    compute_sub_box_bounds(g, slack_all, ws);
    std::size_t kept = 0;
    ws.is_cell.clear();
    ws.cell_box.clear();
    for (std::size_t i = 0; i < ws.S.size(); ++i) {
        const vec3 s = ws.S[i];
        const vec3 cb = glm::clamp(s, b.lo, b.hi);
        const double db2 = glm::dot(cb - s, cb - s);
        if (db2 > (need_all + slack_all) * (need_all + slack_all)) continue;  // no sub-box can need it
        box3 cell_box;  // empty until a sub-box contributes
        if (!seed_cell_box(s, b, g, need_all, slack_all, ws, cell_box)) continue;
        ws.S[kept++] = s;
        const bool cell = !cell_box.empty();
        ws.is_cell.push_back(cell ? 1 : 0);
        ws.cell_box.push_back(cell ? box3(glm::max(cell_box.lo, b.lo), glm::min(cell_box.hi, b.hi)) : box3{});
    }
    ws.S.resize(kept);
}

/// Fills ws.S with every seed that can be nearest to a point of b (sorted by x), ws.is_cell with
/// whether its cell can meet b and ws.cell_box with where (see the file comment). The start margin
/// is 0.5 (point queries: one sub-box; a second pass is cheaper than a large first one) or 1.0
/// (tiles: the max over sub-boxes) times the seed spacing rho^(-1/3) at the centre of b, plus 2 h.
template <class Seeds>
void gather_certified_seeds(const box3& b, const Seeds& gen, double max_radius, std::uint64_t owner, foam_workspace& ws) {
    const sub_box_grid g = make_sub_boxes(b, max_radius);
    double m = 2 * g.h + (g.single() ? 0.5 : 1.0) / std::cbrt(gen.effective_density(b.center()));
    double dmax = 0;
    for (int pass = 0;; ++pass) {
        collect_seeds_near(b, m, gen, owner, ws);
        dmax = nearest_seed_per_sub_box(b, g, ws);
        if (dmax + 2 * g.h <= m) break;
        if (pass > 64) throw solver_error("foam: seed search did not terminate (internal error)");
        m = std::isfinite(dmax) ? dmax + 2 * g.h : 2 * m;
    }
    keep_needed_seeds(b, g, dmax, ws);
}

}  // namespace fabsynth::foam::detail
