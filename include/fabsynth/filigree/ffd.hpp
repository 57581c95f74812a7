// SPDX-License-Identifier: MIT
#pragma once
/// @file ffd.hpp  Non-rigid deformation of skeletons (planar graphs of points and edges) by a
/// bicubic Bezier free-form deformation (filigree-synthesis.md §8.2, eqs. 10-14), and the
/// distortion measure that accepts or rejects a deformation (§4.3.2 "Distortion Measurement").
/// Generic: it knows nothing of elements or neighbours; the contact planner of Fig. 6 that uses it
/// is contact.hpp.
///
/// Usage:
///   using namespace fabsynth::filigree;
///   std::vector<point_constraint> hard{{12, target}, {0, positions[0]}};  // move 12, keep 0 still
///   ffd_result r = ffd_deform(positions, edges, hard);   // r.positions: one per input vertex
///   if (r.distortion < default_sigma_d) accept(r.positions);
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

}  // namespace fabsynth::filigree
