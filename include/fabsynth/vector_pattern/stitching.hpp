// SPDX-License-Identifier: MIT
#pragma once
/// @file stitching.hpp  Gap stitching of placed pieces by linear rotation-invariant (LRI) deformation
/// of their boundaries (Zhou et al. 2014, §4.2, after Lipman, Sorkine, Levin & Cohen-Or 2005,
/// "Linear rotation-invariant coordinates for meshes", here for planar polylines).
///
/// After the sequence and the offsets are fixed, the portal endpoints of two neighbouring pieces do
/// not coincide and the total length l differs from the target L. The length difference is taken
/// up first by stretching every piece along u by L / l (piece_boundary's u_scale; the LRI rest shape
/// is the stretched boundary, rings with no portal included), so that junctions only have to close
/// the portal mismatch; a deformation that had to absorb L - l as well would compress or extend
/// chains that LRI keeps at their length, and compressed chains buckle. Each junction gets one target per
/// portal endpoint: the average of the two matching endpoints (and of their two tangents), placed at
/// the junction's u position (the junctions are spread so that the pattern spans [0, L] exactly).
/// Every piece boundary is then deformed to meet its targets.
///
/// What is deformed. A piece's ring (outer boundary or hole) that touches the piece's sides is split
/// at its portals into *chains*: polylines running from one portal endpoint to the next one off the
/// side lines. A portal itself becomes the straight segment between its two new endpoints, so the two
/// pieces meeting at a junction share exactly the same segment (intermediate vertices on a portal are
/// dropped). Each chain is deformed by LRI with four constraints: both end positions and both end
/// tangents (the first and last edge directions). Rings touching no side (holes, and the outlines of
/// islands, i.e. components enclosed in the piece) have no constraint; the paper leaves them open
/// (its Reeb slicing avoids islands). Here they are translated (after the u stretch, never rotated)
/// by the displacement of the piece's chain points interpolated at their centroid with inverse
/// squared distance weights, so they follow the boundary nearest to them and keep their clearance
/// to it (vine.svg has holes 0.04 mm from a chain; moved by the piece's average placement they were
/// cut by it). A piece with no chain at all uses its placement map (u stretched linearly over the
/// new extent, v shifted by the mean endpoint correction of each side, linear in u).
///
/// LRI for a chain q_0..q_m (m edges e_k = q_{k+1} - q_k, lengths l_k). Discrete frames live on the
/// edges: f_k = e_k / l_k as a complex number. The rotation-invariant coordinates are the relative
/// rotations r_k = f_{k+1} conj(f_k) between neighbouring frames and the edges in their own frame,
/// (l_k, 0). Step 1 solves min sum_k |f_{k+1} - r_k f_k|^2 for the free frames with f_0 and f_{m-1}
/// fixed to the target end directions, then normalises every frame. Step 2 solves
/// min sum_k (1/l_k) |p_{k+1} - p_k - l_k f_k|^2 for the free points with p_0 and p_m fixed; the 1/l_k
/// weights spread any length change along the chain in proportion to arc length. The end tangents
/// enter through the fixed end frames; the position solve is least squares over all edges, so the end
/// edges follow the averaged tangents closely but not exactly (positions are hard constraints,
/// tangents soft, as in Lipman et al.). Both normal
/// matrices depend only on the original chain, so they are factorised once per chain of an original
/// piece (sparse Cholesky, Eigen SimplicialLDLT) and every placed instance of the piece only solves
/// with new right-hand sides. If the targets are a rigid motion of the original chain, both systems
/// have the moved chain as an exact (zero-residual) solution: the deformation reproduces it.
///
/// Usage:
///   fabsynth::vector_pattern::lri_chain c(points);                        // factorises
///   auto moved = c.deform(a, b, dir_first, dir_last);               // new polyline, same size
///   fabsynth::vector_pattern::piece_boundary pb(piece);                    // all chains of a piece
///   auto rings = pb.deform(targets_left, targets_right, placement); // stitched rings
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/polygon.hpp"
#include "fabsynth/vector_pattern/pieces.hpp"

namespace fabsynth::vector_pattern {

/// LRI deformation of one open polyline with constrained end positions and end edge directions.
class lri_chain {
public:
    /// points: the original polyline, at least 2 points, no zero-length edge. Throws invalid_input
    /// otherwise, solver_error if a factorisation fails.
    explicit lri_chain(std::vector<vec2> points) : q_(std::move(points)) {
        if (q_.size() < 2) throw invalid_input("lri_chain: a chain needs at least 2 points");
        const std::size_t m = q_.size() - 1;
        len_.resize(m);
        frame_.resize(m);
        for (std::size_t k = 0; k < m; ++k) {
            if (!all_finite(q_[k + 1]) || !all_finite(q_[k])) throw invalid_input("lri_chain: non-finite point");
            const vec2 e = q_[k + 1] - q_[k];
            len_[k] = glm::length(e);
            if (!(len_[k] > 0.0)) throw invalid_input("lri_chain: zero-length edge " + std::to_string(k));
            frame_[k] = e / len_[k];
        }
        rot_.resize(m > 0 ? m - 1 : 0);
        for (std::size_t k = 0; k + 1 < m; ++k) rot_[k] = cmul(frame_[k + 1], conj(frame_[k]));
        factorise();
    }

    [[nodiscard]] std::size_t size() const noexcept { return q_.size(); }
    [[nodiscard]] const std::vector<vec2>& original() const noexcept { return q_; }

    /// Deformed polyline (same number of points) with first point a, last point b, first edge along
    /// dir_first and last edge along dir_last (any non-zero length; normalised).
    [[nodiscard]] std::vector<vec2> deform(vec2 a, vec2 b, vec2 dir_first, vec2 dir_last) const {
        const std::size_t m = q_.size() - 1;
        std::vector<vec2> out(q_.size());
        out.front() = a;
        out.back() = b;
        if (m == 1) return out;
        const vec2 d0 = normalised(dir_first), d1 = normalised(dir_last);
        // Step 1: frames.
        std::vector<vec2> f(m);
        f[0] = d0;
        f[m - 1] = d1;
        if (m > 2) {
            // Unknowns f_1..f_{m-2} as (x, y) pairs; equations f_{k+1} - r_k f_k = 0, k = 0..m-2.
            Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(2 * (m - 2)));
            // Only the first and last equations involve fixed frames: A^T b for those.
            // k = 0: f_1 - r_0 f_0 = 0  ->  row for f_1 gets + r_0 f_0.
            const vec2 t0 = cmul(rot_[0], f[0]);
            rhs[0] += t0.x;
            rhs[1] += t0.y;
            // k = m-2: f_{m-1} - r_{m-2} f_{m-2} = 0 -> residual -r f_{m-2} + f_{m-1}; A^T b adds
            // conj(r_{m-2}) f_{m-1} to the row of f_{m-2}.
            const vec2 t1 = cmul(conj(rot_[m - 2]), f[m - 1]);
            const std::size_t last = 2 * (m - 3);
            rhs[static_cast<Eigen::Index>(last)] += t1.x;
            rhs[static_cast<Eigen::Index>(last + 1)] += t1.y;
            const Eigen::VectorXd x = frames_->solve(rhs);
            for (std::size_t k = 1; k + 1 < m; ++k) {
                const vec2 v(x[static_cast<Eigen::Index>(2 * (k - 1))], x[static_cast<Eigen::Index>(2 * (k - 1) + 1)]);
                const double l = glm::length(v);
                f[k] = l > 1e-300 ? v / l : cmul(rot_[k - 1], f[k - 1]);
            }
        }
        // Step 2: positions p_1..p_{m-1}; residual sqrt(w_k)(p_{k+1} - p_k - l_k f_k).
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m - 1), 2);
        for (std::size_t k = 0; k < m; ++k) {
            const double w = 1.0 / len_[k];
            const vec2 d = len_[k] * f[k];
            // Point k+1 gets + w d, point k gets - w d (A^T b); fixed points move to the right side.
            if (k + 1 <= m - 1) {
                rhs(static_cast<Eigen::Index>(k), 0) += w * d.x;
                rhs(static_cast<Eigen::Index>(k), 1) += w * d.y;
                if (k == 0) {
                    rhs(0, 0) += w * a.x;
                    rhs(0, 1) += w * a.y;
                }
            }
            if (k >= 1) {
                rhs(static_cast<Eigen::Index>(k - 1), 0) -= w * d.x;
                rhs(static_cast<Eigen::Index>(k - 1), 1) -= w * d.y;
                if (k + 1 == m) {  // point k+1 = b is fixed
                    rhs(static_cast<Eigen::Index>(k - 1), 0) += w * b.x;
                    rhs(static_cast<Eigen::Index>(k - 1), 1) += w * b.y;
                }
            }
        }
        const Eigen::MatrixXd p = positions_->solve(rhs);
        for (std::size_t i = 1; i < m; ++i) out[i] = vec2(p(static_cast<Eigen::Index>(i - 1), 0), p(static_cast<Eigen::Index>(i - 1), 1));
        return out;
    }

private:
    using solver_t = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>;
    static vec2 cmul(vec2 a, vec2 b) noexcept { return {a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x}; }
    static vec2 conj(vec2 a) noexcept { return {a.x, -a.y}; }
    static vec2 normalised(vec2 d) {
        const double l = glm::length(d);
        if (!(l > 0.0) || !std::isfinite(l)) throw invalid_input("lri_chain: end direction is zero or not finite");
        return d / l;
    }

    void factorise() {
        const std::size_t m = q_.size() - 1;
        if (m > 2) {
            // Frame system: unknown frames 1..m-2, 2x2 blocks; equation k couples f_k and f_{k+1}.
            const auto nu = static_cast<Eigen::Index>(2 * (m - 2));
            std::vector<Eigen::Triplet<double>> t;
            auto add_block = [&](std::size_t i, std::size_t j, double a, double b) {  // block [[a,-b],[b,a]]
                const auto r = static_cast<Eigen::Index>(2 * i), c = static_cast<Eigen::Index>(2 * j);
                t.emplace_back(r, c, a), t.emplace_back(r, c + 1, -b), t.emplace_back(r + 1, c, b), t.emplace_back(r + 1, c + 1, a);
            };
            // A^T A: for equation k (f_{k+1} - r_k f_k): unknown u = k (if free) has block -r_k,
            // unknown u = k+1 (if free) identity. Products: I*I = I, conj(r) r = I, cross terms -r, -conj(r).
            for (std::size_t k = 0; k + 1 < m; ++k) {
                const bool a_free = k >= 1 && k <= m - 2, b_free = k + 1 <= m - 2;
                const vec2 r = rot_[k];
                if (a_free) add_block(k - 1, k - 1, 1.0, 0.0);
                if (b_free) add_block(k, k, 1.0, 0.0);
                if (a_free && b_free) {
                    // row of f_k (a), column of f_{k+1} (b): (-r)^H * I = -conj(r)
                    add_block(k - 1, k, -r.x, r.y);
                    // row of f_{k+1}, column of f_k: I^H * (-r) = -r
                    add_block(k, k - 1, -r.x, -r.y);
                }
            }
            Eigen::SparseMatrix<double> A(nu, nu);
            A.setFromTriplets(t.begin(), t.end());
            frames_ = std::make_shared<solver_t>(A);
            if (frames_->info() != Eigen::Success) throw solver_error("lri_chain: frame system factorisation failed");
        }
        // Position system: weighted path Laplacian on the free points 1..m-1.
        const auto np = static_cast<Eigen::Index>(m - 1);
        std::vector<Eigen::Triplet<double>> t;
        for (std::size_t k = 0; k < m; ++k) {
            const double w = 1.0 / len_[k];
            const bool a_free = k >= 1, b_free = k + 1 <= m - 1;
            if (a_free) t.emplace_back(static_cast<Eigen::Index>(k - 1), static_cast<Eigen::Index>(k - 1), w);
            if (b_free) t.emplace_back(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k), w);
            if (a_free && b_free) {
                t.emplace_back(static_cast<Eigen::Index>(k - 1), static_cast<Eigen::Index>(k), -w);
                t.emplace_back(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k - 1), -w);
            }
        }
        if (np > 0) {
            Eigen::SparseMatrix<double> A(np, np);
            A.setFromTriplets(t.begin(), t.end());
            positions_ = std::make_shared<solver_t>(A);
            if (positions_->info() != Eigen::Success) throw solver_error("lri_chain: position system factorisation failed");
        }
    }

    std::vector<vec2> q_;
    std::vector<double> len_;
    std::vector<vec2> frame_, rot_;
    std::shared_ptr<solver_t> frames_, positions_;  // shared: copies of a chain reuse one factorisation
};

/// Where a portal endpoint of a piece is: side, portal index (top to bottom), top or bottom end.
struct endpoint_ref {
    piece_side side = piece_side::left;
    std::uint32_t portal = 0;
    bool top = true;
    friend bool operator==(const endpoint_ref&, const endpoint_ref&) = default;
};

/// New position and outline tangent (x >= 0 convention of vector_pattern::portal) of a portal endpoint.
struct endpoint_target {
    vec2 position{0.0, 0.0};
    vec2 tangent{1.0, 0.0};
};

/// Placement of a piece instance: x in [x0, x1] maps to u in [u0, u1]; y maps to y + dv0 at the
/// left side and y + dv1 at the right side (linear in between). Used for rings with no portal.
struct piece_placement {
    double u0 = 0, u1 = 0;
    double dv0 = 0, dv1 = 0;
};

/// The boundary of one original piece, split into LRI chains (factorised once) and free rings.
class piece_boundary {
public:
    /// u_scale > 0 stretches the piece along x about its left side (x -> x0 + (x - x0) u_scale)
    /// before the chains are built, so the LRI rest shape already has the width the piece gets when
    /// a sequence of length l is spread over L (u_scale = L / l): the deformation then only carries
    /// the portal mismatch, not the length change (a uniformly compressed chain would otherwise
    /// buckle into its neighbours). Throws invalid_input if the piece's portals cannot be located on
    /// its rings (malformed piece) or u_scale is not finite and > 0.
    explicit piece_boundary(const piece& p, double u_scale = 1.0)
        : x0_(p.x0), x1_(p.x1), left_count_(p.left.size()), right_count_(p.right.size()) {
        if (!(std::isfinite(u_scale) && u_scale > 0.0)) throw invalid_input("piece_boundary: u_scale must be finite and > 0");
        scale_ = u_scale;
        x1_ = stretch(p.x1);
        for (std::size_t c = 0; c < p.polygons.size(); ++c) {
            add_ring(p, p.polygons[c].outer, true);
            for (const ring2& h : p.polygons[c].holes) add_ring(p, h, false);
        }
    }

    /// Stitched rings of one instance. left/right: targets of every endpoint of the left / right
    /// portals, two per portal (top, bottom), in portal order. Outer rings come out with positive
    /// area, holes negative (orientation kept from the piece).
    [[nodiscard]] std::vector<ring2> deform(const std::vector<endpoint_target>& left, const std::vector<endpoint_target>& right,
                                            const piece_placement& place) const {
        if (left.size() != 2 * left_count_ || right.size() != 2 * right_count_)
            throw invalid_input("piece_boundary: expected " + std::to_string(2 * left_count_) + " left and " +
                                std::to_string(2 * right_count_) + " right endpoint targets");
        auto target = [&](const endpoint_ref& e) -> const endpoint_target& {
            return (e.side == piece_side::left ? left : right)[2 * e.portal + (e.top ? 0 : 1)];
        };
        std::vector<ring2> out(rings_.size());
        std::vector<vec2> rest, moved;  // every chain point before and after the deformation
        for (std::size_t i = 0; i < rings_.size(); ++i) {
            for (const chain_part& ch : rings_[i].chains) {
                const endpoint_target &a = target(ch.from), &b = target(ch.to);
                const std::vector<vec2> d = ch.chain.deform(a.position, b.position, ch.sign_from * a.tangent, ch.sign_to * b.tangent);
                out[i].insert(out[i].end(), d.begin(), d.end());
                rest.insert(rest.end(), ch.chain.original().begin(), ch.chain.original().end());
                moved.insert(moved.end(), d.begin(), d.end());
            }
            // Chain k ends on one endpoint of a portal and chain k+1 starts on its other endpoint, so
            // the edges between consecutive chains are exactly the (straight) portal segments.
        }
        for (std::size_t i = 0; i < rings_.size(); ++i)
            if (rings_[i].chains.empty()) {
                const ring2& r = rings_[i].free_ring;
                vec2 c(0.0, 0.0);
                for (const vec2& q : r) c += q;
                c /= static_cast<double>(r.size());
                const vec2 d = free_ring_shift(c, rest, moved, place);
                for (const vec2& q : r) out[i].push_back(q + d);
            }
        return out;
    }

    [[nodiscard]] std::size_t chain_count() const noexcept {
        std::size_t n = 0;
        for (const auto& r : rings_) n += r.chains.size();
        return n;
    }

private:
    struct chain_part {
        lri_chain chain;
        endpoint_ref from, to;
        double sign_from = 1.0, sign_to = 1.0;  // chain edge direction = sign * portal tangent
    };
    struct ring_parts {
        bool outer = true;
        std::vector<chain_part> chains;  // empty: a free ring
        ring2 free_ring;
    };

    /// Translation of a ring with no portal whose centroid is c: the displacement of the piece's
    /// chain points interpolated at c with inverse squared distance weights (Shepard), so that a
    /// hole or island keeps its clearance to the boundary nearest to it (a hole 0.04 mm from a
    /// deformed chain, as in vine.svg, would otherwise be cut by it). A piece without chains uses
    /// the placement map.
    [[nodiscard]] vec2 free_ring_shift(vec2 c, const std::vector<vec2>& rest, const std::vector<vec2>& moved,
                                       const piece_placement& place) const {
        if (rest.empty()) return map(c, place) - c;
        vec2 sum(0.0, 0.0);
        double wsum = 0.0;
        for (std::size_t k = 0; k < rest.size(); ++k) {
            const vec2 e = rest[k] - c;
            const double w = 1.0 / std::max(glm::dot(e, e), 1e-24);
            sum += w * (moved[k] - rest[k]);
            wsum += w;
        }
        return sum / wsum;
    }

    [[nodiscard]] vec2 map(vec2 p, const piece_placement& pl) const {
        const double t = (p.x - x0_) / (x1_ - x0_);
        return {pl.u0 + t * (pl.u1 - pl.u0), p.y + (1.0 - t) * pl.dv0 + t * pl.dv1};
    }

    [[nodiscard]] double stretch(double x) const { return scale_ == 1.0 ? x : x0_ + (x - x0_) * scale_; }

    void add_ring(const piece& p, const ring2& original, bool outer) {
        ring2 r = original;  // stretched: points on x1 all land on x1_ (same expression)
        for (vec2& q : r) q.x = stretch(q.x);
        const std::size_t n = r.size();
        ring_parts parts;
        parts.outer = outer;
        // Runs of edges on a side line, as vector_pattern::detail::side_portals finds them.
        struct run {
            std::size_t first, last_point;  // points first..last_point (ring indices) lie on the line
            piece_side side;
        };
        std::vector<run> runs;
        for (const auto& line : {std::pair{p.x0, piece_side::left}, std::pair{x1_, piece_side::right}}) {
            const double xs = line.first;  // not a structured binding: clang 14 cannot capture one
            const piece_side side = line.second;
            auto on = [&](std::size_t i) { return r[i % n].x == xs && r[(i + 1) % n].x == xs; };
            std::size_t start = n;
            for (std::size_t i = 0; i < n && start == n; ++i)
                if (!on(i)) start = i;
            if (start == n) continue;
            for (std::size_t k = 1; k <= n; ++k) {
                const std::size_t i = (start + k) % n;
                if (!on(i) || on(i + n - 1)) continue;
                std::size_t e = i;
                while (on(e + 1)) ++e;
                if (r[i].y == r[(e + 1) % n].y) continue;
                runs.push_back({i, (e + 1) % n, side});
            }
        }
        if (runs.empty()) {
            parts.free_ring = r;
            rings_.push_back(std::move(parts));
            return;
        }
        std::sort(runs.begin(), runs.end(), [](const run& a, const run& b) { return a.first < b.first; });
        // A run is one portal: the one with both endpoint heights (portals of a side may touch at a
        // point, so one height alone can be ambiguous).
        auto portal_of = [&](const run& ru) -> std::uint32_t {
            const auto& ports = p.side(ru.side);
            const double a = r[ru.first].y, b = r[ru.last_point].y;
            const double top = std::min(a, b), bottom = std::max(a, b);
            for (std::size_t k = 0; k < ports.size(); ++k)
                if (ports[k].top == top && ports[k].bottom == bottom) return static_cast<std::uint32_t>(k);
            throw invalid_input("piece_boundary: a boundary run of the piece at x = " + std::to_string(r[ru.first].x) +
                                " is not among its portals");
        };
        auto ref_of = [&](const run& ru, bool at_first) {
            const std::uint32_t k = portal_of(ru);
            const portal& q = p.side(ru.side)[k];
            const double y = r[at_first ? ru.first : ru.last_point].y;
            const bool top = y == q.top && r[at_first ? ru.last_point : ru.first].y == q.bottom;
            return std::pair{endpoint_ref{ru.side, k, top}, top ? q.tangent_top : q.tangent_bottom};
        };
        for (std::size_t k = 0; k < runs.size(); ++k) {
            const run& a = runs[k];
            const run& b = runs[(k + 1) % runs.size()];
            std::vector<vec2> pts;
            for (std::size_t i = a.last_point;; i = (i + 1) % n) {
                pts.push_back(r[i]);
                if (i == b.first) break;
            }
            auto [from, g_from] = ref_of(a, false);
            auto [to, g_to] = ref_of(b, true);
            const vec2 e0 = pts[1] - pts[0], e1 = pts.back() - pts[pts.size() - 2];
            chain_part cp{lri_chain(std::move(pts)), from, to, glm::dot(e0, g_from) < 0.0 ? -1.0 : 1.0,
                          glm::dot(e1, g_to) < 0.0 ? -1.0 : 1.0};
            parts.chains.push_back(std::move(cp));
        }
        rings_.push_back(std::move(parts));
    }

    double x0_, x1_;  // x1_ stretched
    double scale_ = 1.0;
    std::size_t left_count_, right_count_;
    std::vector<ring_parts> rings_;
};

}  // namespace fabsynth::vector_pattern
