// SPDX-License-Identifier: MIT
#pragma once
/// @file deformation.hpp  Non-rigid deformation of filigree element skeletons by a bicubic Bezier
/// free-form deformation (filigree-synthesis.md §8.2, eqs. 10-14), the distortion measure that
/// accepts or rejects a deformation (§4.3.2 "Distortion Measurement"), and the planner of the two
/// tangential-contact cases of Fig. 6 (§4.3.2 "Smooth Connection via Non-rigid Deformation").
///
/// Usage:
///   using namespace fabsynth::filigree;
///   std::vector<point_constraint> hard{{12, target}, {0, positions[0]}};  // move 12, keep 0 still
///   ffd_result r = ffd_deform(positions, edges, hard);   // r.positions: one per input vertex
///   if (r.distortion < default_sigma_d) accept(r.positions);
///
///   // Fig. 6: bring element P into tangential contact with its neighbour Q.
///   if (auto plan = plan_tangent_contact(p_pos, p_edges, q_pos, q_edges, p_junctions, {}))
///       r = ffd_deform(p_pos, p_edges, plan->constraints);
///   auto accepted = smooth_connection(p_pos, p_edges, q_pos, q_edges, p_junctions);  // both steps
///
/// The deformation (§8.2). A 4 x 4 grid of control points p0_ij = lo + (i/3 W, j/3 H) is placed
/// regularly over the bounding rectangle of the skeleton, enlarged by `margin`; the bicubic Bezier
/// patch S0(u, v) = sum B_i(u) B_j(v) p0_ij over it is then the affine map (u, v) -> lo + (u W, v H)
/// (linear precision of the Bernstein basis), so every vertex has fixed parameters (u, v). The
/// unknowns are the 16 moved control points p_ij and one scale factor tau_e per skeleton edge; a
/// vertex goes to S(u, v) = sum B_i(u) B_j(v) p_ij. Minimised (eq. 14):
///   type 1 (eq. 10)  S(u_k, v_k) = q_k for every hard constraint k, via Lagrange multipliers;
///   type 2 (eq. 11)  lambda1 * sum |p_ij - (p_i'j' + p_i''j'') / 2|^2 over the 16 triples of
///                    consecutive control points along a row or a column;
///   type 3 (eq. 12)  lambda2 * sum |(v_a - v_b) - tau_e (v0_a - v0_b)|^2 over the edges e = (a, b);
///   type 4 (eq. 13)  lambda3 * sum (tau_e - mean of tau over the edges sharing an endpoint)^2.
/// Types 2 and 3 are in mm^2, type 4 is dimensionless, weighted as in the paper. The minimiser
/// is the solution of one linear KKT system, as the paper notes.
///
/// Regulariser (not in the paper, which leaves it unstated). Types 2-4 vanish for every
/// translation and every uniform scale of the control grid (with all tau equal to the scale), so
/// eq. 14 alone has no unique minimiser when fewer than two vertices are pinned (and more free
/// modes for a skeleton with too few edges to see every control point). We add
///   eps * (sum |p_ij - p0_ij|^2 / L^2 + sum (tau_e - 1)^2),  eps = 1e-8 * max(lambda1..3)
/// (1e-8 if all weights are 0), L the larger side of the control rectangle, so the term is
/// dimensionless and scale-free. The rest state still has zero cost, so without hard constraints
/// the output equals the input; otherwise, among motions of equal cost, the smallest is chosen.
/// Why so small: eq. 14 also has nearly free modes, e.g. tau growing linearly along a chain
/// (type 4 sees only its ends), which would let a larger regulariser trade the uniform stretch of
/// a pulled straight skeleton for an uneven one. The system is solved for the displacement from
/// the rest state, so that identity is exact and the conditioning costs no accuracy at rest.
///
/// Distortion (§4.3.2): the standard deviation of d'_ij / d_ij over the pairs of sample points
/// (dense samples along the skeleton, deformed by the same map S through their (u, v)).
///
/// Errors: invalid_input naming the input for non-finite coordinates, indices out of range, self
/// loops, two hard constraints on one vertex, bad weights, margins or spacings; solver_error naming
/// the constraint when the hard constraints are linearly dependent (more than 16, or constrained
/// vertices that coincide) or the KKT solve fails.
#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"
#include "fabsynth/geometry/segment.hpp"
#include "fabsynth/graph/skeleton_graph.hpp"

namespace fabsynth::filigree {

/// Penalty weights of eq. 14 (dimensionless; the paper's values are the defaults). Each >= 0.
struct ffd_weights {
    double lambda1 = 2.0;   ///< type 2: control points stay equally spaced along rows and columns
    double lambda2 = 60.0;  ///< type 3: each skeleton edge keeps its direction (up to its tau)
    double lambda3 = 0.5;   ///< type 4: the tau of neighbouring edges stay alike
};

/// A type 1 (hard) constraint: skeleton vertex `vertex` goes exactly to `target` (mm). A fixed
/// point is a constraint whose target is the vertex's own position.
struct point_constraint {
    std::uint32_t vertex = 0;
    vec2 target{0.0};
};

/// Result of ffd_deform.
struct ffd_result {
    std::vector<vec2> positions;        ///< deformed skeleton vertices, one per input vertex (mm)
    double distortion = 0.0;            ///< distortion() of the dense samples before vs after (dimensionless)
    double max_constraint_error = 0.0;  ///< max |S(u_k, v_k) - q_k| over the hard constraints (mm; 0 if none)
};

/// distortion() evaluates at most this many points: larger inputs are subsampled evenly (point
/// k of the subsample is input point floor(k (N - 1) / (cap - 1))), keeping the O(N^2) pair loop
/// bounded.
inline constexpr std::size_t distortion_sample_cap = 400;

/// Default enlargement of the bounding rectangle (fraction of its larger side, on every side).
inline constexpr double default_ffd_margin = 0.05;

/// Default distortion tolerance sigma_d (§8.1, Table 1 uses 0.13-0.17).
inline constexpr double default_sigma_d = 0.15;

namespace detail::ffd {

using sparse_matrix = Eigen::SparseMatrix<double>;
using triplet = Eigen::Triplet<double>;

inline constexpr std::size_t grid_points = 16;  // 4 x 4 control points
inline constexpr std::size_t control_unknowns = 2 * grid_points;  // x of each, then y of each

/// Control point (i, j) (i along x / u, j along y / v) as an index 0..15.
[[nodiscard]] constexpr std::size_t control(std::size_t i, std::size_t j) noexcept { return 4 * i + j; }

/// The cubic Bernstein basis at t.
[[nodiscard]] inline std::array<double, 4> bernstein3(double t) noexcept {
    const double s = 1.0 - t;
    return {s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t};
}

/// The 16 tensor-product weights B_i(u) B_j(v), indexed by control(i, j).
[[nodiscard]] inline std::array<double, grid_points> patch_basis(vec2 uv) noexcept {
    const auto bu = bernstein3(uv.x), bv = bernstein3(uv.y);
    std::array<double, grid_points> b{};
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = 0; j < 4; ++j) b[control(i, j)] = bu[i] * bv[j];
    return b;
}

/// The rectangle carrying the rest control grid: S0(u, v) = lo + (u, v) * size.
struct patch_frame {
    vec2 lo{0.0};
    vec2 size{1.0};
    [[nodiscard]] vec2 uv(vec2 p) const noexcept { return (p - lo) / size; }
};

/// Bounding rectangle of the points enlarged by margin * (its larger side) on every side (1 mm if
/// the points coincide), so that a straight skeleton still gets a rectangle of non-zero height.
/// Throws invalid_input if that rectangle overflows or underflows.
[[nodiscard]] inline patch_frame make_frame(std::span<const vec2> positions, double margin) {
    box2 b;
    for (const vec2& p : positions) b.extend(p);
    const vec2 s = b.size();
    const double side = std::max(s.x, s.y);
    const double pad = side > 0.0 ? margin * side : 1.0;
    const patch_frame f{b.lo - vec2(pad), s + vec2(2.0 * pad)};
    if (!(all_finite(f.lo) && all_finite(f.size) && f.size.x > 0.0 && f.size.y > 0.0))
        throw invalid_input("ffd_deform: the bounding rectangle of the positions, enlarged by margin " + std::to_string(margin) +
                            ", is not finite and non-degenerate");
    return f;
}

[[nodiscard]] inline std::string index_name(const char* what, std::size_t i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

inline void check_points(const char* fn, const char* what, std::span<const vec2> points) {
    for (std::size_t i = 0; i < points.size(); ++i)
        if (!all_finite(points[i])) throw invalid_input(std::string(fn) + ": " + index_name(what, i) + " is not finite");
}

inline void check_edges(const char* fn, const char* what, std::span<const std::array<std::uint32_t, 2>> edges, std::size_t n) {
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const auto [a, b] = edges[e];
        const std::string name = std::string(fn) + ": " + index_name(what, e) + " = (" + std::to_string(a) + ", " + std::to_string(b) + ")";
        for (const std::uint32_t v : {a, b})
            if (v >= n) throw invalid_input(name + " uses vertex " + std::to_string(v) + ", out of range for " + std::to_string(n) + " vertices");
        if (a == b) throw invalid_input(name + " is a self loop");
    }
}

inline void check_weights(const ffd_weights& w) {
    const std::pair<const char*, double> all[] = {{"lambda1", w.lambda1}, {"lambda2", w.lambda2}, {"lambda3", w.lambda3}};
    for (const auto& [name, value] : all)
        if (!(std::isfinite(value) && value >= 0.0))
            throw invalid_input(std::string("ffd_deform: weights.") + name + " must be finite and >= 0, got " + std::to_string(value));
}

/// Phase 1: every input in its domain; two constraints on one vertex are refused (even with equal
/// targets, since they make the KKT system singular).
inline void check_ffd_input(std::span<const vec2> positions, std::span<const std::array<std::uint32_t, 2>> edges,
                            std::span<const point_constraint> hard, const ffd_weights& w, double margin) {
    if (positions.empty()) throw invalid_input("ffd_deform: positions is empty");
    check_points("ffd_deform", "positions", positions);
    check_edges("ffd_deform", "edges", edges, positions.size());
    check_weights(w);
    require_positive(margin, "ffd_deform: margin");
    std::vector<std::size_t> by_vertex;
    for (std::size_t k = 0; k < hard.size(); ++k) {
        const std::string name = "ffd_deform: " + index_name("hard", k);
        if (hard[k].vertex >= positions.size())
            throw invalid_input(name + " constrains vertex " + std::to_string(hard[k].vertex) + ", out of range for " +
                                std::to_string(positions.size()) + " vertices");
        if (!all_finite(hard[k].target)) throw invalid_input(name + " (vertex " + std::to_string(hard[k].vertex) + ") has a non-finite target");
        by_vertex.push_back(k);
    }
    std::stable_sort(by_vertex.begin(), by_vertex.end(), [&](std::size_t a, std::size_t b) { return hard[a].vertex < hard[b].vertex; });
    for (std::size_t i = 1; i < by_vertex.size(); ++i) {
        const point_constraint &a = hard[by_vertex[i - 1]], &b = hard[by_vertex[i]];
        if (a.vertex != b.vertex) continue;
        throw invalid_input("ffd_deform: hard[" + std::to_string(by_vertex[i - 1]) + "] and hard[" + std::to_string(by_vertex[i]) +
                            "] both constrain vertex " + std::to_string(a.vertex) +
                            (a.target == b.target ? " (duplicate)" : " to different targets (contradictory)"));
    }
}

/// For every edge, the other edges sharing an endpoint with it (each listed once).
[[nodiscard]] inline std::vector<std::vector<std::uint32_t>> neighbour_edges(std::span<const std::array<std::uint32_t, 2>> edges,
                                                                             std::size_t num_vertices) {
    std::vector<std::vector<std::uint32_t>> incident(num_vertices);
    for (std::size_t e = 0; e < edges.size(); ++e)
        for (const std::uint32_t v : edges[e]) incident[v].push_back(static_cast<std::uint32_t>(e));
    std::vector<std::vector<std::uint32_t>> out(edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
        auto& n = out[e];
        for (const std::uint32_t v : edges[e])
            for (const std::uint32_t f : incident[v])
                if (f != e) n.push_back(f);
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());  // a parallel edge shares both endpoints
    }
    return out;
}

/// Phase 2: the Hessian H of the soft terms (types 2-4 and the regulariser) over the displacement
/// from the rest state, unknowns ordered [dx of the 16 control points, dy of them, dtau per edge].
/// Built as R^T R from the weighted residual rows R, every residual being zero at rest.
/// frame_side: L of the regulariser (mm); relative_eps: its weight relative to the largest lambda.
[[nodiscard]] inline sparse_matrix soft_hessian(std::span<const vec2> positions, std::span<const std::array<std::uint32_t, 2>> edges,
                                                const std::vector<vec2>& uv, const ffd_weights& w, double frame_side, double relative_eps = 1e-8) {
    const std::size_t n = control_unknowns + edges.size();
    std::vector<triplet> rows;
    Eigen::Index row = 0;
    auto coord = [](std::size_t c, int axis) { return static_cast<Eigen::Index>(c + (axis ? grid_points : 0)); };
    // Type 2 (eq. 11): the middle one of three consecutive control points stays at their midpoint.
    if (w.lambda1 > 0.0) {
        const double s = std::sqrt(w.lambda1);
        auto triple = [&](std::size_t before, std::size_t mid, std::size_t after) {
            for (int axis = 0; axis < 2; ++axis, ++row) {
                rows.emplace_back(row, coord(mid, axis), s);
                rows.emplace_back(row, coord(before, axis), -0.5 * s);
                rows.emplace_back(row, coord(after, axis), -0.5 * s);
            }
        };
        for (std::size_t a = 0; a < 4; ++a)
            for (std::size_t m = 1; m < 3; ++m) {
                triple(control(m - 1, a), control(m, a), control(m + 1, a));  // along u
                triple(control(a, m - 1), control(a, m), control(a, m + 1));  // along v
            }
    }
    // Type 3 (eq. 12): (v_a - v_b) - tau_e (v0_a - v0_b), with v - v0 = sum B_c(u, v) dp_c.
    if (w.lambda2 > 0.0) {
        const double s = std::sqrt(w.lambda2);
        for (std::size_t e = 0; e < edges.size(); ++e) {
            const auto [a, b] = edges[e];
            const auto ba = patch_basis(uv[a]), bb = patch_basis(uv[b]);
            const vec2 rest = positions[a] - positions[b];
            for (int axis = 0; axis < 2; ++axis, ++row) {
                for (std::size_t c = 0; c < grid_points; ++c)
                    if (ba[c] != bb[c]) rows.emplace_back(row, coord(c, axis), s * (ba[c] - bb[c]));
                rows.emplace_back(row, static_cast<Eigen::Index>(control_unknowns + e), -s * rest[axis]);
            }
        }
    }
    // Type 4 (eq. 13): tau_e minus the mean tau of its h neighbouring edges (no term when h = 0).
    if (w.lambda3 > 0.0) {
        const double s = std::sqrt(w.lambda3);
        const auto neighbours = neighbour_edges(edges, positions.size());
        for (std::size_t e = 0; e < edges.size(); ++e) {
            if (neighbours[e].empty()) continue;
            rows.emplace_back(row, static_cast<Eigen::Index>(control_unknowns + e), s);
            const double share = s / static_cast<double>(neighbours[e].size());
            for (const std::uint32_t f : neighbours[e]) rows.emplace_back(row, static_cast<Eigen::Index>(control_unknowns + f), -share);
            ++row;
        }
    }
    sparse_matrix r(row, static_cast<Eigen::Index>(n));
    r.setFromTriplets(rows.begin(), rows.end());
    sparse_matrix h = sparse_matrix(r.transpose()) * r;
    // Regulariser toward the rest state (see the file comment): makes H positive definite.
    const double max_weight = std::max({w.lambda1, w.lambda2, w.lambda3});
    const double eps = relative_eps * (max_weight > 0.0 ? max_weight : 1.0);
    std::vector<triplet> diagonal;
    for (std::size_t k = 0; k < n; ++k)
        diagonal.emplace_back(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k), k < control_unknowns ? eps / (frame_side * frame_side) : eps);
    sparse_matrix reg(h.rows(), h.cols());
    reg.setFromTriplets(diagonal.begin(), diagonal.end());
    return h + reg;
}

/// Phase 3: refuses hard constraints that are linearly dependent on earlier ones, naming the
/// first. The constraint rows (x and y alike) are the patch weights at the constrained vertices;
/// there are only 16 columns, so this is a handful of tiny dense LUs. Pivots below 1e-9 of the
/// largest count as zero: constrained vertices closer than ~1e-9 of the frame coincide.
inline void check_independent(std::span<const point_constraint> hard, const std::vector<vec2>& uv) {
    Eigen::MatrixXd rows(static_cast<Eigen::Index>(hard.size()), static_cast<Eigen::Index>(grid_points));
    for (std::size_t k = 0; k < hard.size(); ++k) {
        const auto b = patch_basis(uv[hard[k].vertex]);
        for (std::size_t c = 0; c < grid_points; ++c) rows(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)) = b[c];
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu;
    lu.setThreshold(1e-9);
    for (std::size_t k = 0; k < hard.size(); ++k) {
        lu.compute(rows.topRows(static_cast<Eigen::Index>(k + 1)));
        if (lu.rank() == static_cast<Eigen::Index>(k + 1)) continue;
        throw solver_error("ffd_deform: hard[" + std::to_string(k) + "] (vertex " + std::to_string(hard[k].vertex) +
                           ") is linearly dependent on the earlier hard constraints, so the KKT system is singular (a 4 x 4 "
                           "control grid meets at most 16 independent point constraints; coincident constrained vertices also do this)");
    }
}

/// Phase 4: the KKT system [H A^T; A 0] [d; mu] = [0; q - v0] and its solution, the displacement
/// d = [dp (32), dtau (#edges)]. The matrix is symmetric but indefinite (a saddle point: zero block
/// on the multipliers), so a Cholesky factor does not exist and an unpivoted LDLT can meet a zero
/// pivot; a sparse LU with partial pivoting is safe, and sparse because the tau unknowns couple
/// only to neighbouring edges. Two steps of iterative refinement recover the digits the
/// conditioning (eps against the weights) costs, for constraints met to round-off.
[[nodiscard]] inline Eigen::VectorXd solve_kkt(const sparse_matrix& h, std::span<const vec2> positions,
                                               std::span<const point_constraint> hard, const std::vector<vec2>& uv) {
    const Eigen::Index n = h.rows();
    const auto m = static_cast<Eigen::Index>(2 * hard.size());
    std::vector<triplet> entries;
    entries.reserve(static_cast<std::size_t>(h.nonZeros()) + 4 * grid_points * hard.size());
    for (Eigen::Index col = 0; col < h.outerSize(); ++col)
        for (sparse_matrix::InnerIterator it(h, col); it; ++it) entries.emplace_back(it.row(), it.col(), it.value());
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + m);
    for (std::size_t k = 0; k < hard.size(); ++k) {
        const auto b = patch_basis(uv[hard[k].vertex]);
        const vec2 move = hard[k].target - positions[hard[k].vertex];
        for (int axis = 0; axis < 2; ++axis) {
            const Eigen::Index row = n + static_cast<Eigen::Index>(2 * k) + axis;
            for (std::size_t c = 0; c < grid_points; ++c) {
                const auto col = static_cast<Eigen::Index>(c + (axis ? grid_points : 0));
                entries.emplace_back(row, col, b[c]);
                entries.emplace_back(col, row, b[c]);
            }
            rhs(row) = move[axis];
        }
    }
    sparse_matrix kkt(n + m, n + m);
    kkt.setFromTriplets(entries.begin(), entries.end());
    kkt.makeCompressed();
    Eigen::SparseLU<sparse_matrix, Eigen::COLAMDOrdering<int>> lu;
    lu.compute(kkt);
    if (lu.info() != Eigen::Success) throw solver_error("ffd_deform: the KKT system could not be factorised: " + lu.lastErrorMessage());
    Eigen::VectorXd x = lu.solve(rhs);
    for (int step = 0; step < 2; ++step) x += lu.solve(Eigen::VectorXd(rhs - kkt * x));
    if (lu.info() != Eigen::Success || !x.allFinite()) throw solver_error("ffd_deform: the KKT solve produced no finite solution");
    return x.head(n);
}

/// Phase 5: points moved by the deformed patch, p + sum B_c(uv(p)) dp_c (the exact S(u, v),
/// written as a displacement of the rest map S0, which reproduces p).
[[nodiscard]] inline std::vector<vec2> displace(std::span<const vec2> points, const patch_frame& frame, const Eigen::VectorXd& d) {
    std::vector<vec2> out(points.begin(), points.end());
    for (vec2& p : out) {
        const auto b = patch_basis(frame.uv(p));
        vec2 move(0.0);
        for (std::size_t c = 0; c < grid_points; ++c)
            move += b[c] * vec2(d(static_cast<Eigen::Index>(c)), d(static_cast<Eigen::Index>(c + grid_points)));
        p += move;
    }
    return out;
}

/// Indices of an even subsample of n points, at most cap of them (see distortion_sample_cap).
[[nodiscard]] inline std::vector<std::size_t> even_subsample(std::size_t n, std::size_t cap) {
    std::vector<std::size_t> idx;
    if (n <= cap) {
        for (std::size_t i = 0; i < n; ++i) idx.push_back(i);
        return idx;
    }
    for (std::size_t k = 0; k < cap; ++k) idx.push_back(k * (n - 1) / (cap - 1));
    return idx;
}

}  // namespace detail::ffd

/// Dense samples of a skeleton for distortion(): the vertices (first, in order), then for each
/// edge in order the points dividing it into ceil(length / spacing) equal parts (endpoints
/// excluded), so consecutive samples along an edge are at most `spacing` apart.
/// @param positions  #V vertex positions (mm), finite
/// @param edges      #E vertex index pairs, in range, no self loops
/// @param spacing    largest distance between samples along an edge (mm), finite and > 0
/// @return #V + (interior samples) points (mm). Throws invalid_input for bad input or more than
///         2^26 samples.
[[nodiscard]] inline std::vector<vec2> sample_edges(std::span<const vec2> positions, std::span<const std::array<std::uint32_t, 2>> edges,
                                                    double spacing) {
    detail::ffd::check_points("sample_edges", "positions", positions);
    detail::ffd::check_edges("sample_edges", "edges", edges, positions.size());
    require_positive(spacing, "sample_edges: spacing");
    constexpr double max_samples = 67108864.0;  // 2^26
    double count = static_cast<double>(positions.size());
    for (const auto& [a, b] : edges) count += std::ceil(glm::distance(positions[a], positions[b]) / spacing);
    if (count > max_samples)
        throw invalid_input("sample_edges: spacing " + std::to_string(spacing) + " mm gives more than 2^26 samples");
    std::vector<vec2> out(positions.begin(), positions.end());
    for (const auto& [a, b] : edges) {
        const auto parts = static_cast<std::size_t>(std::ceil(glm::distance(positions[a], positions[b]) / spacing));
        for (std::size_t q = 1; q < parts; ++q)
            out.push_back(positions[a] + (positions[b] - positions[a]) * (static_cast<double>(q) / static_cast<double>(parts)));
    }
    return out;
}

/// Distortion of `after` with regard to `before` (§4.3.2): the (population) standard deviation of
/// d'_ij / d_ij over all pairs i != j, d_ij = |before_i - before_j|, d'_ij = |after_i - after_j|.
/// Pairs with d_ij <= 1e-9 * (diagonal of the bounding box of `before`) are skipped (coincident
/// samples); 0 if no pair is left. The distance matrix, hence the value, is invariant to
/// translations and rotations of either set, and a uniform scale of `after` gives 0 (every ratio
/// equal). Inputs of more than distortion_sample_cap points are subsampled evenly first.
/// @param before  N points (mm), finite
/// @param after   the same N points after a deformation (mm), finite
/// Throws invalid_input if the sizes differ or a point is not finite. O(min(N, cap)^2).
[[nodiscard]] inline double distortion(std::span<const vec2> before, std::span<const vec2> after) {
    if (before.size() != after.size())
        throw invalid_input("distortion: before has " + std::to_string(before.size()) + " points, after " + std::to_string(after.size()));
    detail::ffd::check_points("distortion", "before", before);
    detail::ffd::check_points("distortion", "after", after);
    const std::vector<std::size_t> idx = detail::ffd::even_subsample(before.size(), distortion_sample_cap);
    box2 b;
    for (const vec2& p : before) b.extend(p);
    const double skip = 1e-9 * glm::length(b.size());
    // Two passes (mean, then squared deviations): no cancellation when the ratios are nearly equal.
    auto for_each_ratio = [&](auto&& f) {
        for (std::size_t i = 0; i < idx.size(); ++i)
            for (std::size_t j = i + 1; j < idx.size(); ++j) {
                const double d = glm::distance(before[idx[i]], before[idx[j]]);
                if (d > skip) f(glm::distance(after[idx[i]], after[idx[j]]) / d);
            }
    };
    double sum = 0.0;
    std::size_t count = 0;
    for_each_ratio([&](double r) { sum += r, ++count; });
    if (count == 0) return 0.0;
    const double mean = sum / static_cast<double>(count);
    double squares = 0.0;
    for_each_ratio([&](double r) { squares += (r - mean) * (r - mean); });
    return std::sqrt(squares / static_cast<double>(count));
}

/// Free-form deformation of a skeleton (§8.2, eqs. 10-14; see the file comment): minimises the
/// soft terms of types 2-4 subject to the hard constraints.
/// @param positions  #V skeleton vertex positions (mm), finite, not empty
/// @param edges      #E skeleton edges as vertex index pairs (in range, no self loops); they carry
///                   the type 3 and 4 terms and the distortion samples
/// @param hard       type 1 constraints, at most one per vertex, at most 16 independent ones
/// @param w          penalty weights lambda1..3 (finite, >= 0)
/// @param margin     enlargement of the bounding rectangle of `positions` on every side, as a
///                   fraction of its larger side (dimensionless, finite, > 0)
/// @return deformed positions (one per vertex, mm), the distortion of sample_edges(positions,
///         edges, total edge length / distortion_sample_cap) under the same map (the vertices
///         alone if the edges have no length), and the largest hard constraint error (mm).
/// Throws invalid_input or solver_error as described in the file comment.
[[nodiscard]] inline ffd_result ffd_deform(std::span<const vec2> positions, std::span<const std::array<std::uint32_t, 2>> edges,
                                           std::span<const point_constraint> hard, const ffd_weights& w = {},
                                           double margin = default_ffd_margin) {
    namespace d = detail::ffd;
    d::check_ffd_input(positions, edges, hard, w, margin);
    const d::patch_frame frame = d::make_frame(positions, margin);
    std::vector<vec2> uv;
    uv.reserve(positions.size());
    for (const vec2& p : positions) uv.push_back(frame.uv(p));
    d::check_independent(hard, uv);
    const d::sparse_matrix h = d::soft_hessian(positions, edges, uv, w, std::max(frame.size.x, frame.size.y));
    const Eigen::VectorXd displacement = d::solve_kkt(h, positions, hard, uv);

    ffd_result r;
    r.positions = d::displace(positions, frame, displacement);
    for (const point_constraint& c : hard)
        r.max_constraint_error = std::max(r.max_constraint_error, glm::distance(r.positions[c.vertex], c.target));
    double length = 0.0;
    for (const auto& [a, b] : edges) length += glm::distance(positions[a], positions[b]);
    const std::vector<vec2> samples = length > 0.0 ? sample_edges(positions, edges, length / static_cast<double>(distortion_sample_cap))
                                                   : std::vector<vec2>(positions.begin(), positions.end());
    r.distortion = distortion(samples, d::displace(samples, frame, displacement));
    return r;
}

// ---------------------------------------------------------------------------------------------
// Tangential contact planning (§4.3.2, Fig. 6)

/// The two cases of Fig. 6.
enum class contact_case : std::uint8_t {
    close_intersections,  ///< (1) a branch of P crosses a branch of Q twice, the crossings close together
    narrow_gap,           ///< (2) a branch of P passes a branch of Q at a narrow gap without crossing it
};

/// What counts as a contact to smooth. The paper gives no values; the defaults suit elements of
/// 10-50 mm drawn with strokes of about 1 mm.
struct contact_options {
    double max_intersection_gap = 2.0;  ///< case 1: largest distance between the two crossings (mm, > 0)
    double max_gap = 0.5;               ///< case 2: largest gap between the branches (mm, > 0)
    bool pin_far_end = true;            ///< also fix the vertex of P farthest from the contact point
    /// Also move the moving vertex's two branch neighbours by its displacement, so P is locally
    /// translated and keeps its tangent at the contact (not in the paper; off by default).
    bool keep_tangent = false;
};

/// The constraints that bring P into tangential contact with Q.
struct connection_plan {
    contact_case kind = contact_case::narrow_gap;
    /// [0] moves the moving vertex; then (keep_tangent) its branch neighbours by the same vector;
    /// then the fixed vertices, in increasing id.
    std::vector<point_constraint> constraints;
    vec2 contact{0.0};                          ///< where P will touch Q: the moving vertex's target (mm)
    std::uint32_t moving_vertex = 0;            ///< vertex of P that moves (= constraints[0].vertex)
    std::size_t p_branch = 0;                   ///< the branch of P, in skeleton_graph::branches() order
    std::size_t q_branch = 0;                   ///< the branch of Q, likewise
    double gap = 0.0;                           ///< case 1: distance between the two crossings; case 2: the gap (mm)
};

namespace detail::ffd {

/// A branch as positions along its walk and the vertex id of each (closed branches repeat the
/// first vertex at the end).
struct branch_path {
    std::vector<vec2> points;
    std::vector<std::uint32_t> vertices;
    bool closed = false;
    [[nodiscard]] std::size_t segments() const noexcept { return points.size() - 1; }
};

/// The branches of a skeleton (graph::skeleton_graph::branches(): runs between vertices of valence
/// != 2, then the cycles).
[[nodiscard]] inline std::vector<branch_path> branches_of(std::span<const vec2> positions, std::span<const std::array<std::uint32_t, 2>> edges) {
    graph::skeleton_graph<vec2> g;
    for (const vec2& p : positions) (void)g.add_vertex(p);
    for (const auto& [a, b] : edges) (void)g.add_edge(a, b);
    std::vector<branch_path> out;
    for (const graph::skeleton_branch& b : g.branches()) {
        branch_path p;
        p.closed = b.closed();
        for (const graph::vertex_id v : b.vertices) p.vertices.push_back(v), p.points.push_back(positions[v]);
        out.push_back(std::move(p));
    }
    return out;
}

[[nodiscard]] inline double cross(vec2 a, vec2 b) noexcept { return a.x * b.y - a.y * b.x; }

/// A point where a branch of P meets a branch of Q; `at` = segment index + parameter along P.
struct crossing {
    double at = 0.0;
    vec2 point{0.0};
};

/// Every point where branch p meets branch q, sorted along p. Segments are closed, with a
/// parameter slack of 1e-12 so that a crossing through a vertex is not lost to rounding; crossings
/// within `touch` (mm) of the previous one along p (or, on a closed branch, of the first) are one
/// point. Parallel (collinear) overlaps are not reported. O(segments(p) * segments(q)).
[[nodiscard]] inline std::vector<crossing> crossings(const branch_path& p, const branch_path& q, double touch) {
    std::vector<crossing> found;
    constexpr double slack = 1e-12;
    auto in_segment = [](double t) { return t >= -slack && t <= 1.0 + slack; };
    for (std::size_t i = 0; i < p.segments(); ++i) {
        const vec2 a = p.points[i], ab = p.points[i + 1] - a;
        for (std::size_t j = 0; j < q.segments(); ++j) {
            const vec2 c = q.points[j], cd = q.points[j + 1] - c;
            const double denom = cross(ab, cd);
            if (!(std::abs(denom) > 1e-14 * glm::length(ab) * glm::length(cd))) continue;  // parallel or degenerate
            const double t = cross(c - a, cd) / denom, u = cross(c - a, ab) / denom;
            if (in_segment(t) && in_segment(u)) found.push_back({static_cast<double>(i) + std::clamp(t, 0.0, 1.0), a + t * ab});
        }
    }
    std::stable_sort(found.begin(), found.end(), [](const crossing& x, const crossing& y) { return x.at < y.at; });
    std::vector<crossing> out;
    for (const crossing& x : found)
        if (out.empty() || glm::distance(x.point, out.back().point) > touch) out.push_back(x);
    if (p.closed && out.size() > 1 && glm::distance(out.back().point, out.front().point) <= touch) out.pop_back();
    return out;
}

/// Unit tangent of branch p at its walk position k (central difference; one-sided at open ends;
/// zero if the neighbours coincide).
[[nodiscard]] inline vec2 tangent(const branch_path& p, std::size_t k) {
    const std::size_t n = p.segments();
    const std::size_t prev = k > 0 ? k - 1 : (p.closed ? n - 1 : 0);
    const std::size_t next = k < n ? k + 1 : (p.closed ? 1 : n);
    const vec2 d = p.points[next] - p.points[prev];
    const double l = glm::length(d);
    return l > 0.0 ? d / l : vec2(0.0);
}

/// A candidate contact: the moving vertex, its target and the gap that ranks it.
struct contact_candidate {
    contact_case kind;
    std::size_t walk;  // position of the moving vertex along its branch of P
    std::uint32_t vertex;
    vec2 target;
    double gap;
    double span = 0.0;  // case 1: length of P between the two crossings (mm), breaks ties in gap
    std::size_t p_branch = 0, q_branch = 0;
};

/// Arc length along branch p from its start to walk position `at` (segment index + parameter).
[[nodiscard]] inline double arc_length(const branch_path& p, const std::vector<double>& cumulative, double at) {
    const auto seg = std::min(static_cast<std::size_t>(at), p.segments() - 1);
    return cumulative[seg] + (at - static_cast<double>(seg)) * glm::distance(p.points[seg], p.points[seg + 1]);
}

/// Case 1 on one pair of branches: over consecutive crossings x1, x2 along p (cyclically on a
/// closed branch) closer than max_gap, the non-fixed vertex of p strictly between them whose
/// tangent is most nearly parallel to the line x1 x2, moved to its projection onto that line.
/// The closest pair of crossings wins, then the shorter stretch of p between them (on a loop
/// crossed twice, both stretches join the same two crossings: the short one is the bulge).
[[nodiscard]] inline std::optional<contact_candidate> close_intersection_contact(const branch_path& p, const std::vector<crossing>& xs, double max_gap,
                                                                                 double touch, const std::vector<std::uint8_t>& fixed) {
    std::optional<contact_candidate> best;
    const std::size_t n = p.segments();
    std::vector<double> cumulative(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) cumulative[i + 1] = cumulative[i] + glm::distance(p.points[i], p.points[i + 1]);
    const std::size_t pairs = p.closed && xs.size() >= 2 ? xs.size() : (xs.size() >= 2 ? xs.size() - 1 : 0);
    for (std::size_t k = 0; k < pairs; ++k) {
        const crossing& x1 = xs[k];
        const crossing& x2 = xs[(k + 1) % xs.size()];
        const double gap = glm::distance(x1.point, x2.point);
        if (!(gap < max_gap) || gap <= touch || (best && gap > best->gap)) continue;
        double span = arc_length(p, cumulative, x2.at) - arc_length(p, cumulative, x1.at);
        if (span <= 0.0) span += cumulative[n];  // wraps on a closed branch
        if (best && gap == best->gap && !(span < best->span)) continue;
        const vec2 dir = (x2.point - x1.point) / gap;
        const double end = x2.at > x1.at ? x2.at : x2.at + static_cast<double>(n);
        std::optional<std::pair<double, std::size_t>> pick;                            // (1 - |cos|, walk position)
        for (double w = std::floor(x1.at) + 1.0; w < end; w += 1.0) {
            const auto pos = static_cast<std::size_t>(w) % n;
            if (fixed[p.vertices[pos]]) continue;
            const vec2 t = tangent(p, pos);
            if (t == vec2(0.0)) continue;
            const double misalign = 1.0 - std::abs(glm::dot(t, dir));
            if (!pick || misalign < pick->first) pick = std::pair{misalign, pos};
        }
        if (!pick) continue;
        const vec2 v = p.points[pick->second];
        best = contact_candidate{contact_case::close_intersections, pick->second, p.vertices[pick->second],
                                 x1.point + glm::dot(v - x1.point, dir) * dir, gap, span};
    }
    return best;
}

/// Case 2 on one pair of branches that do not meet: the non-fixed vertex of p nearest to q and
/// its closest point on q, if nearer than max_gap and farther than `touch` (already in contact).
[[nodiscard]] inline std::optional<contact_candidate> narrow_gap_contact(const branch_path& p, const branch_path& q, double max_gap,
                                                                         double touch, const std::vector<std::uint8_t>& fixed) {
    std::optional<contact_candidate> best;
    for (std::size_t k = 0; k < p.points.size(); ++k) {
        if (fixed[p.vertices[k]]) continue;
        const vec2 v = p.points[k];
        for (std::size_t j = 0; j < q.segments(); ++j) {
            const double gap = segment_distance(v, q.points[j], q.points[j + 1]);
            if (!(gap < max_gap) || gap <= touch || (best && !(gap < best->gap))) continue;
            const double t = segment_closest_parameter(v, q.points[j], q.points[j + 1]);
            best = contact_candidate{contact_case::narrow_gap, k, p.vertices[k], q.points[j] + t * (q.points[j + 1] - q.points[j]), gap};
        }
    }
    return best;
}

inline void check_contact_input(std::span<const vec2> p_positions, std::span<const std::array<std::uint32_t, 2>> p_edges,
                                std::span<const vec2> q_positions, std::span<const std::array<std::uint32_t, 2>> q_edges,
                                std::span<const std::uint32_t> fixed_vertices, const contact_options& opt) {
    constexpr const char* fn = "plan_tangent_contact";
    check_points(fn, "p_positions", p_positions);
    check_points(fn, "q_positions", q_positions);
    check_edges(fn, "p_edges", p_edges, p_positions.size());
    check_edges(fn, "q_edges", q_edges, q_positions.size());
    for (std::size_t i = 0; i < fixed_vertices.size(); ++i)
        if (fixed_vertices[i] >= p_positions.size())
            throw invalid_input(std::string(fn) + ": " + index_name("fixed_vertices", i) + " = " + std::to_string(fixed_vertices[i]) +
                                " is out of range for " + std::to_string(p_positions.size()) + " vertices of P");
    require_positive(opt.max_intersection_gap, "plan_tangent_contact: max_intersection_gap");
    require_positive(opt.max_gap, "plan_tangent_contact: max_gap");
}

/// The best contact over all branch pairs: case 1 before case 2 (an existing double crossing is
/// a connection to smooth), then the smaller gap, then the earlier (P branch, Q branch) pair.
[[nodiscard]] inline std::optional<contact_candidate> best_contact(const std::vector<branch_path>& pb, const std::vector<branch_path>& qb,
                                                                   const contact_options& opt, double touch, const std::vector<std::uint8_t>& fixed) {
    std::optional<contact_candidate> best;
    auto better = [&](const contact_candidate& c) {
        if (!best) return true;
        if (c.kind != best->kind) return c.kind == contact_case::close_intersections;
        return c.gap < best->gap || (c.gap == best->gap && c.span < best->span);
    };
    for (std::size_t i = 0; i < pb.size(); ++i)
        for (std::size_t j = 0; j < qb.size(); ++j) {
            const std::vector<crossing> xs = crossings(pb[i], qb[j], touch);
            auto c = xs.empty() ? narrow_gap_contact(pb[i], qb[j], opt.max_gap, touch, fixed)
                                : close_intersection_contact(pb[i], xs, opt.max_intersection_gap, touch, fixed);
            if (!c) continue;
            c->p_branch = i, c->q_branch = j;
            if (better(*c)) best = c;
        }
    return best;
}

/// The distance below which two points of P and Q touch (mm): 1e-9 of their largest coordinate
/// (plus 1e-9 mm), so rounding never turns a touching pair into a gap or two crossings.
[[nodiscard]] inline double touch_tolerance(std::span<const vec2> p_positions, std::span<const vec2> q_positions) {
    box2 b;
    for (const vec2& v : p_positions) b.extend(v);
    for (const vec2& v : q_positions) b.extend(v);
    return 1e-9 * (1.0 + std::max({std::abs(b.lo.x), std::abs(b.lo.y), std::abs(b.hi.x), std::abs(b.hi.y)}));
}

/// The plan: the moving constraint, (keep_tangent) its branch neighbours moved alike, then the
/// fixed vertices (the caller's, plus the far end).
[[nodiscard]] inline connection_plan make_plan(const contact_candidate& c, const branch_path& branch, std::span<const vec2> p_positions,
                                               std::vector<std::uint8_t> fixed, const contact_options& opt) {
    connection_plan plan;
    plan.kind = c.kind;
    plan.contact = c.target;
    plan.moving_vertex = c.vertex;
    plan.p_branch = c.p_branch, plan.q_branch = c.q_branch;
    plan.gap = c.gap;
    plan.constraints.push_back({c.vertex, c.target});
    std::vector<std::uint8_t> moving(p_positions.size(), 0);
    moving[c.vertex] = 1;
    if (opt.keep_tangent) {
        const std::size_t n = branch.segments();
        const std::size_t walks[] = {c.walk > 0 ? c.walk - 1 : (branch.closed ? n - 1 : c.walk), c.walk < n ? c.walk + 1 : (branch.closed ? 1 : c.walk)};
        for (const std::size_t w : walks) {
            const std::uint32_t v = branch.vertices[w];
            if (moving[v] || fixed[v]) continue;
            moving[v] = 1;
            plan.constraints.push_back({v, p_positions[v] + (c.target - p_positions[c.vertex])});
        }
    }
    if (opt.pin_far_end) {
        // The vertex of P farthest from the contact anchors the rest of the element, which would
        // otherwise translate as a whole (a translation costs nothing in eq. 14).
        std::size_t far = 0;
        for (std::size_t v = 1; v < p_positions.size(); ++v)
            if (glm::distance(p_positions[v], c.target) > glm::distance(p_positions[far], c.target)) far = v;
        if (!moving[far]) fixed[far] = 1;
    }
    for (std::size_t v = 0; v < fixed.size(); ++v)
        if (fixed[v]) plan.constraints.push_back({static_cast<std::uint32_t>(v), p_positions[v]});
    return plan;
}

}  // namespace detail::ffd

/// Plans the deformation of element P that brings it into tangential contact with its neighbour
/// Q (§4.3.2, Fig. 6). Branches are those of graph::skeleton_graph::branches().
///  - Case 1: a branch of P crosses a branch of Q at two points x1, x2, consecutive along P's
///    branch and closer than opt.max_intersection_gap. The moving vertex is the vertex of P
///    strictly between x1 and x2 along the branch (on a loop crossed twice: along the shorter
///    stretch) whose tangent is closest to the direction of the line x1 x2; its target is its
///    projection onto that line (the paper's rule). P then
///    touches the chord x1 x2, which lies off Q by Q's sagitta over it: that remaining sliver is
///    a case-2 gap, which a second call closes.
///  - Case 2: a branch of P does not meet a branch of Q, but one of its vertices is within
///    opt.max_gap of it. The moving vertex is the P vertex nearest to Q; its target is its
///    closest point on Q.
/// Case 1 is preferred to case 2, then the smaller gap. Points of P and Q closer than
/// 1e-9 * (1 + largest |coordinate|) mm touch: they are one crossing, not a gap. With
/// opt.keep_tangent the moving vertex's branch neighbours (unless fixed) get the same
/// displacement. Fixed points (targets = own positions): every vertex
/// of `fixed_vertices` (P's intersections with its other neighbours, which must not move), plus,
/// if opt.pin_far_end, the vertex of P farthest from the contact point (lowest id on ties).
/// Fixed vertices are never chosen to move.
/// @param p_positions, p_edges  skeleton of P (mm; index pairs, in range, no self loops)
/// @param q_positions, q_edges  skeleton of Q (mm), which does not move
/// @param fixed_vertices        vertices of P to keep still (in range; repeats allowed)
/// @param opt                   contact thresholds (mm)
/// @return the plan, or nullopt if no branch pair is in either case. Throws invalid_input for bad
///         input. O(segments(P) * segments(Q)).
[[nodiscard]] inline std::optional<connection_plan> plan_tangent_contact(std::span<const vec2> p_positions,
                                                                         std::span<const std::array<std::uint32_t, 2>> p_edges,
                                                                         std::span<const vec2> q_positions,
                                                                         std::span<const std::array<std::uint32_t, 2>> q_edges,
                                                                         std::span<const std::uint32_t> fixed_vertices,
                                                                         const contact_options& opt = {}) {
    namespace d = detail::ffd;
    d::check_contact_input(p_positions, p_edges, q_positions, q_edges, fixed_vertices, opt);
    std::vector<std::uint8_t> fixed(p_positions.size(), 0);
    for (const std::uint32_t v : fixed_vertices) fixed[v] = 1;
    const std::vector<d::branch_path> p_branches = d::branches_of(p_positions, p_edges);
    const double touch = d::touch_tolerance(p_positions, q_positions);
    const auto contact = d::best_contact(p_branches, d::branches_of(q_positions, q_edges), opt, touch, fixed);
    if (!contact) return std::nullopt;
    return d::make_plan(*contact, p_branches[contact->p_branch], p_positions, std::move(fixed), opt);
}

/// SMOOTHCONNECTION of Algorithm 1 (§4.3.2): plan_tangent_contact, then ffd_deform of P with the
/// plan's constraints; the result only if its distortion is below sigma_d (dimensionless, > 0;
/// Table 1: 0.13-0.17). nullopt if there is no contact to smooth or the deformation is rejected.
/// Throws as plan_tangent_contact and ffd_deform do (e.g. solver_error for more than 15 fixed
/// vertices).
[[nodiscard]] inline std::optional<ffd_result> smooth_connection(std::span<const vec2> p_positions,
                                                                 std::span<const std::array<std::uint32_t, 2>> p_edges,
                                                                 std::span<const vec2> q_positions,
                                                                 std::span<const std::array<std::uint32_t, 2>> q_edges,
                                                                 std::span<const std::uint32_t> fixed_vertices, const contact_options& opt = {},
                                                                 const ffd_weights& w = {}, double sigma_d = default_sigma_d) {
    require_positive(sigma_d, "smooth_connection: sigma_d");
    const std::optional<connection_plan> plan = plan_tangent_contact(p_positions, p_edges, q_positions, q_edges, fixed_vertices, opt);
    if (!plan) return std::nullopt;
    ffd_result r = ffd_deform(p_positions, p_edges, plan->constraints, w);
    if (!(r.distortion < sigma_d)) return std::nullopt;
    return r;
}

}  // namespace fabsynth::filigree
